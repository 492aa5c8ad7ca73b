//! The surface of revolution (`revsurf`): a profile `r(h)` turned about an axis.
//!
//! `base` is the axis' foot, `direction` its way up, `height` its length; the surface is
//! every point at height `0 <= h <= height` along the axis whose distance from the axis is
//! `r(h)`. It is open at both ends (the vases of the course's scenes show their insides).
//!
//! # The profiles (`surfer`)
//!
//! The course gives no formulas; these were recovered from its reference images. For every
//! image row of `revsurfa` and `revsurfe` (where the surface stands against the black
//! background), the first and last lit columns give two rays that graze the surface; each
//! ray's closest approach to the axis gives a height `h` and a distance `d`, and the
//! silhouette is where `d = r(h)`. The samples, 20 rows apart (h, d):
//!
//! - `surfer 1`: (5.75, 0.17) (4.16, 1.22) (2.99, 2.00) (1.53, 2.97) (0.23, 3.84): a line,
//!   `r = 4 - 2h/3` (a cone of base radius 4 and apex at `h = 6`: revsurfa's height);
//! - `surfer 2`: 0.49 at 3.21, 1.49 at 6.23, 0.94 at 4.62, 1.32 at 5.42, 0.79 at 2.00:
//!   `r = 1 + cos(h)/2` (a waist at `h = pi`);
//! - `surfer 3`: 0.49 at 4.67, 1.50 at 1.70, 0.98 at 6.25, 1.03 at 3.07, 0.62 at 5.47:
//!   `r = 1 + sin(h)/2` (a vase: belly at `pi/2`, neck at `3pi/2`).
//!
//! `h` is in world units (radians for 2 and 3); `height` cuts the profile, it does not
//! stretch it (texplane5 cuts `surfer 2` at 4.28).
//!
//! The normals are the surface's, `unit(radial - r'(h) axis)`, for surfers 2 and 3 (their
//! diffuse shading in revsurfe matches with these and not with twice the slope: 99.6 % of
//! pixels identical against 80.7 %). The course's cone leans its normals twice as far as
//! its side, `r' = -4/3`: fitting the lean `k` of `unit(radial + k axis)` to revsurfa's
//! brightness down two columns gives an RMS error of 0.7 levels at `k = 4/3` against 23 at
//! the side's `2/3`. Rendered with these, the images match the course's as docs/conformance.md's
//! table says.
//!
//! # The intersection
//!
//! With `w = base - ray.base` split along the unit axis `a` (`h0 = w . a`, `w_perp`) and
//! the direction likewise (`hd`, `d_perp`), a ray's distance from the axis squared is
//! `rho^2(t) = |w_perp + t d_perp|^2` and its height `h(t) = h0 + t hd`, and it meets the
//! surface where `G(t) = rho^2(t) - r(h(t))^2` changes sign. Not a polynomial: the roots
//! are bracketed, then refined.
//!
//! 1. The interval: where `0 <= h(t) <= height` (the slab) and `rho(t)` is at most the
//!    profile's largest radius (the bounding cylinder, solved exactly with its
//!    discriminant in the perpendicular form `A R^2 - ((w x d) . a)^2`), ahead of the ray's
//!    base. Not cut at the caller's `limit`: the pieces searched, and so the crossing found,
//!    are the same whatever the limit (whichever object was tested first); the search stops
//!    at the first piece that begins beyond the limit. The cylinder is tested first and
//!    has no division: most rays that get here (shadow rays passing beside the surface)
//!    stop at it. Fixed point asks before the search's first steps (which divide its
//!    direction by its length): exact integer tests rule out a ray whose line passes an
//!    upright surface's cylinder, or whose way stays outside the bounding sphere, by a
//!    margin (`src/scalar/ball.rs`).
//! 2. Bracketing: the interval is split in halves, left first, until a piece shows a sign
//!    change or is proved free of roots: `|G'| <= L` on a piece (`L` from the line's
//!    `|d(rho^2)/dt| = 2 |A t + B|` at the ends and the profile's largest `|r r'|`), so a
//!    piece whose ends satisfy `|G(a)| + |G(b)| > L (b - a)` has no root; in the float
//!    types, neither has one that the ray passes clear of (its least distance from the
//!    axis there beyond the largest radius the profile can have there). A sign change
//!    brackets an odd number of roots, so a piece that shows one is split on until it
//!    provably holds only one: `G` is convex along the ray (`G''` bounded below, checked
//!    once a ray: rays more than 35 degrees off the axis), monotonic on the piece (the
//!    line's part of `G'` outweighs the profile's), or curved one way on the piece (the
//!    profile's curvature bounded from its values at the piece's ends). Rays far from the
//!    surface are dismissed in a few evaluations; a ray grazing a silhouette is followed
//!    down to [`DEPTH`] halvings (1/65536 of the interval): nothing is missed that the ray
//!    passes through for more than that.
//! 3. Refinement: the Illinois variant of regula falsi on the bracket, until it stops
//!    shrinking, its steps in the float types at the root of the secant plus the ray's
//!    own bend (`A`); the hit is the end on the ray's side (no acne: the point is never
//!    inside).
//!
//! Every step is bounded: at most [`MAX_BRACKETING`] evaluations of `G` a ray to bracket
//! (if they run out, the nearest bracket found so far is refined) and
//! [`MAX_EVALUATIONS`] in all, each one profile (a sine) and a few products.

use super::{
    Object, ObjectVTable, Palette, Shape, Surface, ahead, object_material, object_surface,
};
use crate::error::{Attr, Entity, ErrorKind};
use crate::material::MaterialId;
use crate::ray::Ray;
use crate::scalar::{Scalar, load, load_direction, load_length, load_position};
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use crate::write;
#[cfg(feature = "print")]
use core::fmt;

/// Halvings of the interval at most while bracketing (the depth of the search's stack).
pub const DEPTH: usize = 16;

/// Evaluations of `G` a ray at most while bracketing.
pub const MAX_BRACKETING: u32 = 96;

/// Refinement's first steps by [`Search::model_step`] (the float types): on vases, 2 of
/// them took 6.0 evaluations a root and every step by it 5.7, but each costs twice a
/// secant's step.
const MODEL_STEPS: u8 = 2;

/// Evaluations of `G` a ray at most: bracketing and refinement together.
pub const MAX_EVALUATIONS: u32 = 128;

/// A profile: the radius as a function of the height along the axis (`surfer` in the
/// scene; see the module's docs for how they were recovered).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Surfer {
    /// `surfer 1`: `r = 4 - 2h/3`, a cone (none above `h = 6`).
    Cone = 1,
    /// `surfer 2`: `r = 1 + cos(h)/2`, a waist at `h = pi`.
    Waist = 2,
    /// `surfer 3`: `r = 1 + sin(h)/2`, a vase.
    Vase = 3,
}

impl Surfer {
    /// The largest radius anywhere on the profile.
    const fn widest(self) -> f64 {
        match self {
            Surfer::Cone => 4.0,
            _ => 1.5,
        }
    }

    /// The largest `|r r'|` anywhere on the profile (`4 * 2/3`, `1.5 * 0.5`).
    const fn steepest(self) -> f64 {
        match self {
            Surfer::Cone => 8.0 / 3.0,
            _ => 0.75,
        }
    }
}

/// A surface of revolution as written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RevSurfDef {
    /// The profile.
    pub surfer: Surfer,
    /// The foot of the axis.
    pub base: [f64; 3],
    /// The axis' direction, any length but zero.
    pub direction: [f64; 3],
    /// The length of the axis, above zero.
    pub height: f64,
}

/// A surface of revolution with its unit axis and bounds worked out at load.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RevSurf<S> {
    /// The profile.
    pub surfer: Surfer,
    /// The foot of the axis.
    pub base: Vec3<S>,
    /// The direction as written.
    pub direction: Vec3<S>,
    /// The unit axis.
    pub axis: Vec3<S>,
    /// The length of the axis.
    pub height: S,
    /// The scene's scale, and its reciprocal: the profile is in world units.
    pub scale: S,
    /// `1 / scale`.
    pub unscale: S,
    /// The bounding cylinder's radius (the widest radius, a little more).
    pub reach: S,
    /// The largest `|r r'|`, in scene units.
    pub steepest: S,
    /// The centre of the bounding sphere (for the render plan and the tree).
    pub center: Vec3<S>,
    /// The radius of the bounding sphere.
    pub bound: S,
}

/// The constants of the cone's profile, `4` and `2/3`, in `S`.
fn cone_constants<S: Scalar>() -> (S, S) {
    let four = S::TWO + S::TWO;
    let two_thirds = S::TWO / (S::ONE + S::TWO);
    (four, two_thirds)
}

impl<S: Scalar> RevSurf<S> {
    /// Checks a definition: a direction that is not zero, a height above zero.
    pub(crate) fn build(def: &RevSurfDef, scale: f64) -> Result<Self, ErrorKind> {
        let base = load_position::<S>(def.base, scale, Attr::Base)?;
        let direction = load_direction::<S>(def.direction, Attr::Direction)?;
        let height = load_length::<S>(def.height, scale, Attr::Height)?;
        let axis = direction.to_f64().unit_f64().ok_or(ErrorKind::ZeroVector {
            attr: Attr::Direction,
        })?;
        let h = def.height * scale;
        // A little wider than the widest radius: the bracket must not cut off a root on
        // the cylinder through rounding.
        let reach = def.surfer.widest() * scale * (1.0 + 1.0 / 256.0);
        let center = base.to_f64() + axis * (h / 2.0);
        let bound = crate::scalar::sqrt_f64(h * h / 4.0 + reach * reach);
        Ok(Self {
            surfer: def.surfer,
            base,
            direction,
            axis: axis.cast(),
            height,
            scale: load(scale, Attr::Height)?,
            unscale: load(1.0 / scale, Attr::Height)?,
            reach: load(reach, Attr::Height)?,
            steepest: load(def.surfer.steepest() * scale, Attr::Height)?,
            center: Vec3::new(
                load(center.x, Attr::Base)?,
                load(center.y, Attr::Base)?,
                load(center.z, Attr::Base)?,
            ),
            bound: load(bound, Attr::Height)?,
        })
    }

    /// The radius at height `h` (scene units), and its slope `dr/dh`.
    #[inline]
    pub fn profile(&self, h: S) -> (S, S) {
        let x = h * self.unscale;
        let half = S::SINE[0];
        match self.surfer {
            Surfer::Cone => {
                let (four, two_thirds) = cone_constants::<S>();
                let r = four * self.scale - two_thirds * h;
                if r > S::ZERO {
                    // The course's cone leans its normals twice as far as its side: see
                    // the module's docs.
                    (r, -(two_thirds + two_thirds))
                } else {
                    (S::ZERO, S::ZERO)
                }
            }
            Surfer::Waist => {
                let (sin, cos) = sin_cos(x);
                ((S::ONE + half * cos) * self.scale, -half * sin)
            }
            Surfer::Vase => {
                let (sin, cos) = sin_cos(x);
                ((S::ONE + half * sin) * self.scale, half * cos)
            }
        }
    }

    /// The radius at height `h` (scene units), and the profile's wave there: `cos x` for
    /// the waist, `sin x` for the vase (`x = h / scale`), 0 for the cone.
    #[inline]
    fn radius(&self, h: S) -> (S, S) {
        let x = h * self.unscale;
        let half = S::SINE[0];
        match self.surfer {
            Surfer::Cone => {
                let (four, two_thirds) = cone_constants::<S>();
                ((four * self.scale - two_thirds * h).max(S::ZERO), S::ZERO)
            }
            Surfer::Waist => {
                let wave = cos(x);
                ((S::ONE + half * wave) * self.scale, wave)
            }
            Surfer::Vase => {
                let wave = x.sin();
                ((S::ONE + half * wave) * self.scale, wave)
            }
        }
    }

    /// The nearest hit with `0 < t < limit` (see the module's docs).
    ///
    /// Fixed point, which has no range for the products of a long direction, searches
    /// along the unit direction (one wide reciprocal) and converts `t` after, as the
    /// sphere does.
    pub fn nearest(&self, ray: &Ray<S>, limit: S) -> Option<S> {
        // Fixed point: a ray that stays outside the bounding sphere, or an upright
        // surface's bounding cylinder, by a margin meets nothing, and most rays that reach
        // the test do (vases on the micro:bit: 6.4 of 7.7 a pixel), while the search's
        // first steps (the unit direction, the line's four dot products) cost about 1,400
        // instructions a ray on the Cortex-M0. The margin, 2^8 steps of 2^-16 a unit of
        // the line's distance, is some fifty times the roundings that can put a point the
        // search tries off the line; `clearing_the_ball_finds_nothing` tests it. A shadow
        // ray's segment (`limit` at most 1) is first compared with a bounding box, on the
        // Cortex-M0 (`a_cleared_box_finds_nothing`).
        if !S::WIDE_RANGE && (limit <= S::ONE && self.box_cleared_by(ray) || self.cleared_by(ray)) {
            return None;
        }
        self.searched(ray, limit)
    }

    /// Whether the segment from the ray's base to `base + dir` (a shadow ray's, `limit` at
    /// most 1) clears a bounding box by the same margin, on some axis: for an upright axis
    /// the box about the cylinder and its mirror image below the foot (no halving of the
    /// height for the box's middle), else the bounding sphere's cube. Comparisons only,
    /// on the Cortex-M0 (`Scalar::segment_clears_box`).
    fn box_cleared_by(&self, ray: &Ray<S>) -> bool {
        let (f, half) = self.clearing_box(ray.base);
        S::segment_clears_box(f, ray.dir, half)
    }

    /// [`box_cleared_by`](Self::box_cleared_by)'s box: `base` less its middle, and its
    /// half-sides.
    fn clearing_box(&self, base: Vec3<S>) -> (Vec3<S>, Vec3<S>) {
        if self.stands_upright() {
            let half = Vec3::new(self.reach, self.height, self.reach);
            (base - self.base, half)
        } else {
            let bound = Vec3::new(self.bound, self.bound, self.bound);
            (base - self.center, bound)
        }
    }

    /// Whether fixed point's exact pre-tests rule the ray out: for an upright axis, the
    /// bounding cylinder's line test on the ray's `x` and `z` (two products), then the
    /// bounding sphere (which also rules out rays passing above or below the surface).
    /// A tall surface's sphere holds much room beside its cylinder.
    fn cleared_by(&self, ray: &Ray<S>) -> bool {
        self.stands_upright() && S::line_clears_upright(ray.base - self.base, ray.dir, self.reach)
            || S::ray_clears_ball(ray.base - self.center, ray.dir, self.bound)
    }

    /// Whether the axis is `(0, 1, 0)` (every scene's `direction 0 1 0`).
    #[inline]
    fn stands_upright(&self) -> bool {
        self.axis == Vec3::new(S::ZERO, S::ONE, S::ZERO)
    }

    /// [`nearest`](Self::nearest) by the search alone.
    fn searched(&self, ray: &Ray<S>, limit: S) -> Option<S> {
        if S::WIDE_RANGE || ray.len == S::ONE {
            return self.nearest_along(ray.base, ray.dir, limit);
        }
        let (unit, inv) = super::unit_direction(ray)?;
        let t = self.nearest_along(ray.base, unit, S::UNBOUNDED)?;
        ahead(t.scale(inv), limit)
    }

    /// [`nearest`](Self::nearest) from `base` along `dir`.
    ///
    /// The search runs over the whole interval where the ray is inside the bounds, not
    /// only up to `limit`: what it finds does not depend on the limit (and so on which
    /// object was tested first), only whether it is kept does.
    fn nearest_along(&self, base: Vec3<S>, dir: Vec3<S>, limit: S) -> Option<S> {
        let (line, span) = Line::within_reach(self, base, dir)?;
        let (low, high) = self.interval(&line, span)?;
        if !(low < limit) {
            return None;
        }
        let mut search = Search {
            surface: self,
            line: &line,
            evaluations: 0,
        };
        ahead(search.first_root(low, high, limit)?, limit)
    }

    /// Where the ray is within the slab `0 <= h <= height` and `span`, where it is within
    /// the bounding cylinder and ahead of its base.
    fn interval(&self, line: &Line<S>, (mut low, mut high): (S, S)) -> Option<(S, S)> {
        if line.hd == S::ZERO {
            if line.h0 < S::ZERO || line.h0 > self.height {
                return None;
            }
        } else {
            let (a, b) = (-line.h0 / line.hd, (self.height - line.h0) / line.hd);
            let (near, far) = if a < b { (a, b) } else { (b, a) };
            low = low.max(near);
            high = high.min(far);
        }
        (low < high).then_some((low, high))
    }

    /// The unit outward normal at a point of the surface: `unit(radial - rho r'(h) a)`.
    pub fn normal_at(&self, point: Vec3<S>) -> Vec3<S> {
        let w = point - self.base;
        let h = w.dot(self.axis);
        let radial = w - self.axis * h;
        let rho = radial.length();
        let (_, slope) = self.profile(h);
        (radial - self.axis * (rho * slope))
            .unit()
            .unwrap_or(self.axis)
    }

    /// The kind's function table.
    pub const VTABLE: ObjectVTable<S> = ObjectVTable {
        kind: Entity::RevSurf,
        hits: revsurf_hits,
        normal: revsurf_normal,
        row_test: super::object_row_test,
        #[cfg(feature = "print")]
        printer: revsurf_print,
        material: object_material,
        surface: revsurf_surface,
    };
}

/// Whether `g`, a value of `G`, is across the surface from a ray that starts `outside`
/// (`G > 0`) or inside an open end (`G < 0`): zero counts as across.
#[inline]
fn crossed<S: Scalar>(outside: bool, g: S) -> bool {
    if outside {
        !(g > S::ZERO)
    } else {
        !(g < S::ZERO)
    }
}

/// `sin(x)` and `cos(x)`.
#[inline]
fn sin_cos<S: Scalar>(x: S) -> (S, S) {
    (x.sin(), cos(x))
}

/// `cos(x) = sin(x + pi/2)`, but `f64`'s is `libm::cos` (the course's).
#[inline]
fn cos<S: Scalar>(x: S) -> S {
    if S::COURSE_ORDER {
        S::from_f64(libm::cos(x.to_f64()))
    } else {
        (x + S::SINE[4]).sin()
    }
}

/// A ray in the axis' frame.
struct Line<S> {
    /// `ray.base - base` off the axis.
    w: Vec3<S>,
    /// The direction off the axis.
    d: Vec3<S>,
    /// Height of the ray's base, and its rate along the ray.
    h0: S,
    hd: S,
    /// `|d_perp|^2` and `w_perp . d_perp`: `rho^2(t) = A t^2 + 2 B t + C`.
    a: S,
    b: S,
    /// The axis is `(0, 1, 0)` (every scene's `direction 0 1 0`) and the type a float:
    /// `w` and `d` have no `y`, and their products by it are left out.
    upright: bool,
}

impl<S: Scalar> Line<S> {
    /// The ray in the axis' frame and the span of `t >= 0` where it is within the
    /// bounding cylinder (`A t^2 + 2 B t + C <= R^2`), if it comes within it. Most rays
    /// that get here miss the cylinder (shadow rays towards a light beside the surface):
    /// they are turned away before the rest of the line is worked out, without a division.
    #[inline]
    fn within_reach(surface: &RevSurf<S>, base: Vec3<S>, dir: Vec3<S>) -> Option<(Self, (S, S))> {
        let axis = surface.axis;
        let offset = base - surface.base;
        // Upright, in a float type, the general formulas' products by the axis' zeros are
        // exactly zero and the sums they join unchanged: the same values, fewer steps.
        let upright = S::WIDE_RANGE && surface.stands_upright();
        let (h0, hd, w, d, a) = if upright {
            let (w, d) = (
                Vec3::new(offset.x, S::ZERO, offset.z),
                Vec3::new(dir.x, S::ZERO, dir.z),
            );
            (offset.y, dir.y, w, d, d.x * d.x + d.z * d.z)
        } else {
            let h0 = offset.dot(axis);
            let hd = dir.dot(axis);
            let w = offset - axis * h0;
            let d = dir - axis * hd;
            (h0, hd, w, d, d.dot(d))
        };
        let reach2 = surface.reach * surface.reach;
        let (mut low, mut high) = (S::ZERO, S::UNBOUNDED);
        let b = if a > S::ZERO {
            // `B^2 - A C = -q^2` with `q = (w x d) . axis`: no large squares cancel.
            let q = if upright {
                w.z * d.x - w.x * d.z
            } else {
                w.cross(d).dot(axis)
            };
            let discriminant = a * reach2 - q * q;
            if !(discriminant > S::ZERO) {
                return None;
            }
            let b = if upright {
                w.x * d.x + w.z * d.z
            } else {
                w.dot(d)
            };
            let root = discriminant.sqrt();
            let (near, far) = ((-b - root) / a, (-b + root) / a);
            low = low.max(near);
            high = high.min(far);
            b
        } else if w.dot(w) > reach2 {
            // Along the axis, outside the cylinder.
            return None;
        } else {
            w.dot(d)
        };
        let line = Self {
            w,
            d,
            h0,
            hd,
            a,
            b,
            upright,
        };
        Some((line, (low, high)))
    }

    /// The ray's squared distance from the axis at `t`.
    #[inline(always)]
    fn squared(&self, t: S) -> S {
        // `WIDE_RANGE` first: fixed point has no code for the upright case.
        if S::WIDE_RANGE && self.upright {
            let (x, z) = (self.w.x + self.d.x * t, self.w.z + self.d.z * t);
            x * x + z * z
        } else {
            let p = self.w + self.d * t;
            p.dot(p)
        }
    }
}

/// One ray's root search, counting its evaluations.
struct Search<'a, S> {
    surface: &'a RevSurf<S>,
    line: &'a Line<S>,
    evaluations: u32,
}

impl<S: Scalar> Search<'_, S> {
    /// `G(t) = rho^2(t) - r(h(t))^2`, `rho` from the perpendicular offset (no large
    /// squares cancel), and the profile's wave at `t` (see [`RevSurf::radius`]).
    fn g(&mut self, t: S) -> (S, S) {
        self.evaluations += 1;
        let line = self.line;
        let squared = line.squared(t);
        let (r, wave) = self.surface.radius(line.h0 + line.hd * t);
        (squared - r * r, wave)
    }

    /// A bound on `|G'|` over `[a, b]`.
    fn slope_bound(&self, a: S, b: S) -> S {
        let line = self.line;
        let ends = (line.a * a + line.b).abs().max((line.a * b + line.b).abs());
        S::TWO * (ends + self.surface.steepest * line.hd.abs())
    }

    /// Whether `G` has no root on `[a, b]`, from its values at the ends: `|G'| <= L`
    /// there, so a root would need `|G(a)| + |G(b)| <= L (b - a)`.
    fn root_free(&self, a: S, ga: S, b: S, gb: S) -> bool {
        ga.abs() + gb.abs() > self.slope_bound(a, b) * (b - a)
    }

    /// Bounds on the profile's wave (`sin x` or `cos x`) over `[a, b]`, from its values at
    /// the ends: a wave changes by at most its change in `x`, which is the piece's length
    /// in `x` (`(b - a) |hd| / scale`).
    #[inline(always)]
    fn wave_range(&self, a: S, wave_a: S, b: S, wave_b: S) -> (S, S) {
        let half = S::SINE[0];
        let reach = (b - a) * self.line.hd.abs() * self.surface.unscale;
        let sum = wave_a + wave_b;
        let lowest = ((sum - reach) * half).max(-S::ONE);
        let highest = ((sum + reach) * half).min(S::ONE);
        (lowest, highest)
    }

    /// Whether the ray keeps to its side of the surface all over `[a, b]`: outside, its
    /// least distance from the axis there beyond the profile's largest radius there;
    /// inside (an open end), its largest within the least radius. The radii are bounded
    /// from the waves at the ends as in [`curved_one_way`](Self::curved_one_way), the
    /// cone's from its heights at the ends. A sharper test than
    /// [`root_free`](Self::root_free)'s slope, whose bound holds for the whole profile.
    /// The float types only: in Q16.16 it took 1.8 KB of the Cortex-M0's flash for 0.1 %
    /// of vases' frame there.
    fn clear_of(&self, outside: bool, piece: &Piece<S>) -> bool {
        let line = self.line;
        let surface = self.surface;
        let Piece {
            a,
            wave_a,
            b,
            wave_b,
            ..
        } = *piece;
        let (least, most) = match surface.surfer {
            Surfer::Cone => {
                let (ra, _) = surface.radius(line.h0 + line.hd * a);
                let (rb, _) = surface.radius(line.h0 + line.hd * b);
                (ra.min(rb), ra.max(rb))
            }
            Surfer::Waist | Surfer::Vase => {
                let half = S::SINE[0];
                let (lowest, highest) = self.wave_range(a, wave_a, b, wave_b);
                let radius = |wave: S| (S::ONE + half * wave) * surface.scale;
                (radius(lowest), radius(highest))
            }
        };
        if outside {
            // The squared distance is least at the ray's closest approach, or at an end.
            let closest = if line.a > S::ZERO {
                -line.b / line.a
            } else {
                a
            };
            line.squared(closest.max(a).min(b)) > most * most
        } else {
            line.squared(a).max(line.squared(b)) < least * least
        }
    }

    /// Whether `G` is convex along the whole ray, so that a piece whose ends differ in sign
    /// holds one root: `G'' = 2 A - hd^2 (r^2)''`, and `(r^2)''` is at most 3/4 for the
    /// vase and the waist and 8/9 for the cone (`r = scale rho(h / scale)`: the scales
    /// cancel), so `2 A > hd^2` is enough (the exact bound per profile measured no faster).
    /// Rays more than 35 degrees off the axis: nearly every ray of a vase seen from the side.
    fn convex(&self) -> bool {
        let line = self.line;
        line.a * S::TWO > line.hd * line.hd
    }

    /// Whether `G` keeps the sign of its curvature on `[a, b]`, so that a piece whose ends
    /// differ in sign holds one root (a convex or concave function crosses a level once
    /// between points on either side of it). `G'' = 2 A - hd^2 P''(x)` with `P = rho^2`
    /// the profile's square: for the vase and the waist `P'' = 1/2 - w - w^2` in the wave
    /// `w` (`sin x`, `cos x`), whose range on the piece is bounded by its values at the ends
    /// and the piece's length in `x` (a wave changes by at most its change in `x`); for the
    /// cone `P''` is 8/9, or 0 past the apex.
    fn curved_one_way(&self, a: S, wave_a: S, b: S, wave_b: S) -> bool {
        let line = self.line;
        let half = S::SINE[0];
        let (low, high) = match self.surface.surfer {
            Surfer::Cone => {
                let three = S::ONE + S::TWO;
                (S::ZERO, (S::TWO * S::TWO * S::TWO) / (three * three))
            }
            Surfer::Waist | Surfer::Vase => {
                let (lowest, highest) = self.wave_range(a, wave_a, b, wave_b);
                let p = |w: S| half - w - w * w;
                // A parabola opening down, its top at w = -1/2.
                let top = (-half).max(lowest).min(highest);
                (p(lowest).min(p(highest)), p(top))
            }
        };
        let (bend, curve) = (line.a * S::TWO, line.hd * line.hd);
        bend > curve * high || bend < curve * low
    }

    /// Whether `G` is monotonic on `[a, b]`: `G' = 2 (A t + B) - 2 r r' hd`, whose line
    /// part (linear in `t`, so bounded by its ends) outweighs the profile's part there.
    fn monotonic(&self, a: S, b: S) -> bool {
        let line = self.line;
        let profile = self.surface.steepest * line.hd.abs();
        let (first, last) = (line.a * a + line.b, line.a * b + line.b);
        first > profile || last < -profile
    }

    /// The first `t` in `[low, high]` where `G` changes sign, if it is below `limit`. The
    /// pieces are those of the whole interval whatever the limit (so the crossing found is
    /// too); the search stops at the first piece that begins beyond the limit.
    fn first_root(&mut self, low: S, high: S, limit: S) -> Option<S> {
        let (ga, wave_a) = self.g(low);
        // The sign the ray starts with: outside (G > 0) or inside an open end (G < 0).
        let outside = ga > S::ZERO;
        // A limit inside the interval (a shadow ray's light, a nearer object): if no root
        // can lie before it, nothing below the limit will be found. Else the search goes on
        // over the whole interval, as without a limit.
        if limit < high {
            let (at_limit, _) = self.g(limit);
            if !crossed(outside, at_limit) && self.root_free(low, ga, limit, at_limit) {
                return None;
            }
        }
        let (gb, wave_b) = self.g(high);
        let pieces = Pieces {
            outside,
            convex: self.convex(),
            // Pieces narrower than this are not split: the interval times 2^-DEPTH, a
            // constant the compiler folds. One product instead of DEPTH halvings, and the
            // same value: fixed point's products floor (`floor(floor(x/2)/2) =
            // floor(x/4)`), the floats' are exact (but for a subnormal product, some
            // 2^-111 wide in `f32`, which no ray's interval comes near).
            narrowest: (high - low) * (0..DEPTH).fold(S::ONE, |scale, _| scale * S::SINE[0]),
            limit,
        };
        // The whole interval is judged before the stack of pieces exists: a third of the
        // rays that get here are settled on it, and the stack costs a fill.
        // (`low < limit`: the caller checked.)
        let first = Piece {
            a: low,
            ga,
            wave_a,
            b: high,
            gb,
            wave_b,
        };
        match pieces.judge(self, &first, 0) {
            Verdict::Root => Some(self.refine(low, ga, high, gb)),
            Verdict::Empty => None,
            Verdict::Split(m, known) => pieces.split(self, first, m, known),
        }
    }

    /// Narrows a bracket `[a, b]` (`G(a)` on the ray's side, `G(b)` not) by the Illinois
    /// method; the end on the ray's side when it stops shrinking. Each step goes to the
    /// root of a model of `G` through the bracket's ends (the value of an end kept twice
    /// running halved, so that both ends move): the secant in fixed point, the secant and
    /// the ray's bend in the float types ([`model_step`](Self::model_step)).
    fn refine(&mut self, mut a: S, mut ga: S, mut b: S, mut gb: S) -> S {
        // Which end was kept last time: halve its value if it is kept again.
        let mut kept = 0i8;
        // The model's steps left: it pays while the bracket is wide.
        let mut modelled = if S::WIDE_RANGE { MODEL_STEPS } else { 0 };
        while self.evaluations < MAX_EVALUATIONS {
            if gb == S::ZERO {
                return b;
            }
            let mut m = if modelled > 0 {
                modelled -= 1;
                a + self.model_step(b - a, ga, gb)
            } else {
                let step = ga / (ga - gb);
                a + (b - a) * step
            };
            if S::WIDE_RANGE && !(m > a) {
                // The step puts the root at `a`: the value next above tests that.
                m = a.next_up();
            }
            if !(m > a && m < b) {
                m = a + (b - a) * S::SINE[0];
                if !(m > a && m < b) {
                    break;
                }
            }
            let (gm, _) = self.g(m);
            if (gm > S::ZERO) == (ga > S::ZERO) && gm != S::ZERO {
                (a, ga) = (m, gm);
                if kept == 1 {
                    gb = gb * S::SINE[0];
                }
                kept = 1;
            } else {
                (b, gb) = (m, gm);
                if kept == -1 {
                    ga = ga * S::SINE[0];
                }
                kept = -1;
            }
        }
        a
    }

    /// Where in `(0, w)` the model `ga + (s - A w) u + A u^2` of `G` on a bracket `w` wide
    /// is zero: the secant (slope `s`) plus the bend of the ray's squared distance from the
    /// axis (`A t^2 + ...`), exact but for the profile's own bend along the ray. It meets
    /// `ga` and `gb` at the ends, so one root lies between; by the stable formula. Primary
    /// rays cross a vase's wall nearly square to its axis, where the profile bends little:
    /// with the secant alone the brackets narrowed by 8.7 evaluations a root in vases, with
    /// this by 5.7. Not in fixed point, whose squares of slopes lose what the model gains
    /// (Q16.16 took more evaluations and moved 2 % of revsurfe's pixels).
    fn model_step(&self, w: S, ga: S, gb: S) -> S {
        let bend = self.line.a;
        let p = (gb - ga) / w - bend * w;
        let root = (p * p - S::TWO * S::TWO * bend * ga).sqrt();
        // `q = -(p + sign(p) root) / 2`: the roots are `ga / q` and `q / A`.
        let q = if p < S::ZERO {
            (root - p) * S::SINE[0]
        } else {
            -(p + root) * S::SINE[0]
        };
        let near = ga / q;
        if near > S::ZERO && near < w {
            near
        } else {
            q / bend
        }
    }
}

/// A piece `[a, b]` of a ray's interval, with `G` and the profile's wave at its ends.
#[derive(Clone, Copy)]
struct Piece<S> {
    a: S,
    ga: S,
    wave_a: S,
    b: S,
    gb: S,
    wave_b: S,
}

/// What a piece holds, as far as its ends tell.
enum Verdict<S> {
    /// Exactly one crossing, or it cannot be split further: refine it.
    Root,
    /// No crossing.
    Empty,
    /// Split it at the point; `true` if it is crossed (a bracket to fall back on).
    Split(S, bool),
}

/// The rules of one ray's search over its pieces.
struct Pieces<S> {
    outside: bool,
    convex: bool,
    narrowest: S,
    limit: S,
}

impl<S: Scalar> Pieces<S> {
    /// Judges a piece at `depth` halvings.
    fn judge(&self, search: &Search<'_, S>, piece: &Piece<S>, depth: usize) -> Verdict<S> {
        let Piece {
            a,
            ga,
            wave_a,
            b,
            gb,
            wave_b,
        } = *piece;
        let crossed = crossed(self.outside, gb);
        if crossed && self.convex {
            return Verdict::Root;
        }
        // The first split is at the ray's closest approach to the axis, if it is inside:
        // where a ray grazing a silhouette touches the surface; then halves.
        let line = search.line;
        let closest = if depth == 0 && line.a > S::ZERO {
            -line.b / line.a
        } else {
            a
        };
        let m = if closest > a && closest < b {
            closest
        } else {
            a + (b - a) * S::SINE[0]
        };
        let splits = depth < DEPTH && b - a > self.narrowest && m > a && m < b;
        if crossed {
            // A sign change brackets a root, but not necessarily the first one: three
            // crossings have one too. Refined only where the piece provably holds one
            // (see the module's docs) or cannot be split further.
            if !splits || search.monotonic(a, b) || search.curved_one_way(a, wave_a, b, wave_b) {
                return Verdict::Root;
            }
            Verdict::Split(m, true)
        } else if !splits
            || search.root_free(a, ga, b, gb)
            || S::WIDE_RANGE && search.clear_of(self.outside, piece)
        {
            Verdict::Empty
        } else {
            Verdict::Split(m, false)
        }
    }

    /// Goes on from a piece to split at `m`: pieces left to right, the right halves left
    /// behind on a stack, until one holds the first crossing or every piece before the
    /// limit is empty.
    fn split(
        &self,
        search: &mut Search<'_, S>,
        mut piece: Piece<S>,
        mut m: S,
        crossed: bool,
    ) -> Option<S> {
        // The right halves left behind, nearest last (a `heapless::Vec`: an array would be
        // filled with zeros first, 2 % of vases' frame).
        let mut stack: heapless::Vec<(S, S, S), DEPTH> = heapless::Vec::new();
        // The nearest bracket found so far: refined if the budget runs out before every
        // piece to its left is settled.
        let mut known = crossed.then_some(piece);
        loop {
            let (gm, wave_m) = search.g(m);
            // Cannot fail: a piece is split only at depth < DEPTH.
            stack.push((piece.b, piece.gb, piece.wave_b)).ok()?;
            (piece.b, piece.gb, piece.wave_b) = (m, gm, wave_m);
            // The next piece to split, or the root.
            loop {
                // Every piece left of this one is settled: any crossing left is beyond the
                // limit.
                if !(piece.a < self.limit) {
                    return None;
                }
                if search.evaluations >= MAX_BRACKETING {
                    let k = known?;
                    return Some(search.refine(k.a, k.ga, k.b, k.gb));
                }
                match self.judge(search, &piece, stack.len()) {
                    Verdict::Root => {
                        return Some(search.refine(piece.a, piece.ga, piece.b, piece.gb));
                    }
                    Verdict::Split(at, crossed) => {
                        if crossed {
                            known = Some(piece);
                        }
                        m = at;
                        break;
                    }
                    Verdict::Empty => {
                        // No root in [a, b]: on to the right half left behind.
                        let next = stack.pop()?;
                        (piece.a, piece.ga, piece.wave_a) = (piece.b, piece.gb, piece.wave_b);
                        (piece.b, piece.gb, piece.wave_b) = next;
                    }
                }
            }
        }
    }
}

/// Builds a surface of revolution and installs its table.
pub fn revsurf_init<S: Scalar>(
    name: &str,
    material: MaterialId,
    def: &RevSurfDef,
    scale: f64,
) -> Result<Object<S>, ErrorKind> {
    Object::init(
        &RevSurf::VTABLE,
        name,
        material,
        Shape::RevSurf(RevSurf::build(def, scale)?),
    )
}

/// `hits` of a surface of revolution.
pub fn revsurf_hits<S: Scalar>(obj: &Object<S>, ray: &Ray<S>, limit: S) -> Option<S> {
    match obj.shape() {
        Shape::RevSurf(surface) => surface.nearest(ray, limit),
        _ => None,
    }
}

/// `normal` of a surface of revolution.
pub fn revsurf_normal<S: Scalar>(obj: &Object<S>, point: Vec3<S>) -> Vec3<S> {
    match obj.shape() {
        Shape::RevSurf(surface) => surface.normal_at(point),
        _ => Vec3::ZERO,
    }
}

/// `surface` of a surface of revolution: its normal, its material.
pub fn revsurf_surface<'s, S: Scalar>(
    obj: &Object<S>,
    palette: &Palette<'s, S>,
    ray: &Ray<S>,
    t: S,
    out: &mut Option<Surface<'s, S>>,
) {
    object_surface(obj, palette, ray, t, revsurf_normal, out);
}

/// `printer` of a surface of revolution.
#[cfg(feature = "print")]
pub fn revsurf_print<S: Scalar>(
    obj: &Object<S>,
    palette: &Palette<'_, S>,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    super::object_print(obj, palette, out)?;
    if let Shape::RevSurf(surface) = obj.shape() {
        writeln!(out, "  {} {}", Attr::Surfer, surface.surfer as u8)?;
        write::vector(out, Attr::Base, surface.base, palette.scale)?;
        write::vector(out, Attr::Direction, surface.direction, 1.0)?;
        write::numbers(out, Attr::Height, &[surface.height], palette.scale)?;
    }
    write::footer(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::test_support::stream;
    use crate::scalar::I16F16;

    fn surface<S: Scalar>(surfer: Surfer) -> RevSurf<S> {
        leaning::<S>(surfer, [0.3, 1.0, 0.2])
    }

    fn leaning<S: Scalar>(surfer: Surfer, direction: [f64; 3]) -> RevSurf<S> {
        let def = RevSurfDef {
            surfer,
            base: [1.0, -2.0, -5.0],
            direction,
            height: 6.0,
        };
        RevSurf::build(&def, 1.0).unwrap()
    }

    /// An upright surface's line (`Line::upright`) holds the values the general formulas
    /// give, and its squared distance from the axis too, in `f32` and `f64`.
    #[test]
    fn upright_lines_equal_the_general_formulas() {
        fn check<S: Scalar + core::fmt::Debug>(from_f64: impl Fn(f64) -> S) {
            let s = leaning::<S>(Surfer::Vase, [0.0, 1.0, 0.0]);
            let axis = s.axis;
            let mut next = stream(5);
            let mut checked = 0;
            for _ in 0..4_000 {
                let mut v = || from_f64(next() * 8.0 - 4.0);
                let (base, dir) = (Vec3::new(v(), v(), v()), Vec3::new(v(), v(), v()));
                let offset = base - s.base;
                let (h0, hd) = (offset.dot(axis), dir.dot(axis));
                let (w, d) = (offset - axis * h0, dir - axis * hd);
                let (a, b) = (d.dot(d), w.dot(d));
                // The cylinder's span as the general formulas find it.
                let q = w.cross(d).dot(axis);
                let discriminant = a * (s.reach * s.reach) - q * q;
                let found = Line::within_reach(&s, base, dir);
                assert_eq!(found.is_some(), discriminant > S::ZERO, "{base:?} {dir:?}");
                let Some((line, span)) = found else {
                    continue;
                };
                let root = discriminant.sqrt();
                let (near, far) = ((-b - root) / a, (-b + root) / a);
                assert_eq!(span, (near.max(S::ZERO), far.min(S::UNBOUNDED)));
                assert!(line.upright);
                assert_eq!((line.h0, line.hd, line.w, line.d), (h0, hd, w, d));
                assert_eq!((line.a, line.b), (a, b));
                let t = from_f64(next() * 10.0);
                let p = w + d * t;
                assert_eq!(line.squared(t), p.dot(p));
                checked += 1;
            }
            assert!(checked > 500, "{checked}");
        }
        check::<f32>(|x| x as f32);
        check::<f64>(|x| x);
    }

    /// Fixed point's pre-tests (`RevSurf::cleared_by`: `Scalar::line_clears_upright`,
    /// `Scalar::ray_clears_ball`) are sound: wherever they rule a ray out, the search alone
    /// finds nothing either, with a limit or without. Rays from
    /// near and far (up to 60 units), inside the bounding sphere too, of lengths from 2^-6
    /// to 2^5 and unit rays, over the three profiles on three axes at three scales: a
    /// quarter aimed to pass the bounding sphere within a few margins of its surface, a
    /// quarter the bounding cylinder, a quarter leaving from just outside the sphere at
    /// every angle to the way out (those that move away are ruled out though their lines
    /// cross it), a quarter from anywhere near.
    #[test]
    fn clearing_the_ball_finds_nothing() {
        let (mut ruled_out, mut tried, mut found) = (0u32, 0u32, 0u32);
        let (mut leaving, mut leaving_ruled_out) = (0u32, 0u32);
        for (k, (surfer, direction, s)) in test_surfaces().enumerate() {
            let (center, bound) = (s.center.to_f64(), s.bound.to_f64());
            let mut next = stream(101 + k as u64);
            let fixed = |v: Vec3<f64>| v.cast::<I16F16>();
            for i in 0..6_000 {
                // A point at `bound (1 + e)` from the centre, a way across it there.
                let n = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5);
                let Some(n) = n.unit_f64() else { continue };
                let across = n.cross(Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5));
                let Some(across) = across.unit_f64() else {
                    continue;
                };
                let (e, from_far) = (next() * next() * 1.5 - 0.05, (next() - 0.3) * 60.0);
                let mut moving_away = false;
                let (from, way) = if i % 4 == 0 {
                    // Anywhere near, any way.
                    let v = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5);
                    (center + v * (4.0 * bound), n)
                } else if i % 4 == 1 {
                    // From just outside (or in), at an angle to the way out: those under a
                    // right angle move away, and their lines cross the sphere.
                    let angle = next() * 1.8;
                    let way = n * libm::cos(angle) + across * libm::sin(angle);
                    let from = center + n * (bound * (1.0 + e * 0.2));
                    // Clearly outside (by 1 % of the radius and more) and away.
                    moving_away = angle < 1.5 && e > 0.05;
                    (from, way)
                } else if i % 4 == 2 {
                    (center + n * (bound * (1.0 + e)) - across * from_far, across)
                } else {
                    // Past the bounding cylinder at `reach (1 + e / 4)` from the axis, at a
                    // height from below its foot to above its top, a way square to the
                    // radius there but leaning along the axis.
                    let a = s.axis.to_f64();
                    let Some(radial) = (n - a * n.dot(a)).unit_f64() else {
                        continue;
                    };
                    let h = (next() * 1.4 - 0.2) * s.height.to_f64();
                    let point =
                        s.base.to_f64() + a * h + radial * (s.reach.to_f64() * (1.0 + e / 4.0));
                    let way = radial.cross(a) + a * (next() - 0.5);
                    (point - way * from_far, way)
                };
                let len = libm::exp2(next() * 11.0 - 6.0);
                let ray = if i % 3 == 0 {
                    Ray::with_length(fixed(from), fixed(way), I16F16::ONE)
                } else {
                    Ray::new(fixed(from), fixed(way * len))
                };
                tried += 1;
                let passes = s.cleared_by(&ray);
                let unlimited = s.searched(&ray, I16F16::UNBOUNDED);
                found += u32::from(unlimited.is_some());
                leaving += u32::from(moving_away);
                if passes {
                    ruled_out += 1;
                    leaving_ruled_out += u32::from(moving_away);
                    assert_eq!(unlimited, None, "{surfer:?} {direction:?} {ray:?}");
                    let limit = I16F16::from_f64(next() * 30.0);
                    assert_eq!(s.searched(&ray, limit), None, "{surfer:?} {ray:?}");
                }
            }
        }
        // Not vacuous: many rays are ruled out and many hit; nearly every ray that leaves
        // from clearly outside is ruled out.
        assert!(
            leaving_ruled_out * 10 > leaving * 9,
            "{leaving_ruled_out} of {leaving}"
        );
        assert!(ruled_out > tried / 2, "{ruled_out} of {tried}");
        assert!(found > tried / 100, "{found} of {tried}");
    }

    /// The pre-tests' surfaces: three profiles, each on three axes (one upright) at
    /// scales 0.05, 0.5 and 2, in Q16.16, with their profiles and axes.
    fn test_surfaces() -> impl Iterator<Item = (Surfer, [f64; 3], RevSurf<I16F16>)> {
        let axes = [[0.3, 1.0, 0.2], [0.0, 1.0, 0.0], [1.0, 0.2, -0.1]];
        [Surfer::Cone, Surfer::Waist, Surfer::Vase]
            .into_iter()
            .flat_map(move |surfer| axes.map(|axis| (surfer, axis)))
            .flat_map(|(surfer, axis)| [0.05, 0.5, 2.0].map(|scale| (surfer, axis, scale)))
            .map(|(surfer, direction, scale)| {
                let def = RevSurfDef {
                    surfer,
                    base: [1.0, -2.0, -5.0],
                    direction,
                    height: 6.0,
                };
                (surfer, direction, RevSurf::build(&def, scale).unwrap())
            })
    }

    /// Wherever a shadow ray's segment (`0 < t < 1`) clears the box of `box_cleared_by` by
    /// the margin (the box test itself, which only the Cortex-M0 runs), the search alone
    /// finds nothing on it, with a limit of 1 or less: 108,000 Q16.16 segments over three
    /// profiles, three axes (the upright one takes the cylinder's box) and scales 0.05-2,
    /// ending at points in and about the box (a fifth of the way beyond its sides) and
    /// leaving from anywhere near. A box an eighth or a thirty-second short fails it.
    #[test]
    fn a_cleared_box_finds_nothing() {
        use crate::scalar::segment_clears_box;
        let (mut cleared, mut tried, mut found) = (0u32, 0u32, 0u32);
        for (k, (surfer, direction, s)) in test_surfaces().enumerate() {
            let (middle, half) = s.clearing_box(Vec3::ZERO);
            let (middle, half) = (-middle.to_f64(), half.to_f64());
            let mut next = stream(301 + k as u64);
            let fixed = |v: Vec3<f64>| v.cast::<I16F16>();
            let around = |next: &mut dyn FnMut() -> f64, spread: f64| {
                let u = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * (2.0 * spread);
                middle + Vec3::new(u.x * half.x, u.y * half.y, u.z * half.z)
            };
            for _ in 0..4_000 {
                let light = around(&mut next, 1.2);
                let from = around(&mut next, 4.0);
                let ray = Ray::new(fixed(from), fixed(light - from));
                let (f, half) = s.clearing_box(ray.base);
                let bits = |v: Vec3<I16F16>| [v.x, v.y, v.z].map(I16F16::to_bits);
                let half = bits(half).map(i32::unsigned_abs);
                let clears = segment_clears_box(bits(f), bits(ray.dir), half);
                let hit = s.searched(&ray, I16F16::ONE);
                tried += 1;
                found += u32::from(hit.is_some());
                if clears {
                    cleared += 1;
                    assert_eq!(hit, None, "{surfer:?} {direction:?} {ray:?}");
                    let limit = I16F16::from_f64(next());
                    assert_eq!(s.searched(&ray, limit), None, "{surfer:?} {ray:?}");
                }
            }
        }
        // Not vacuous: many segments clear the box and many meet the surface.
        assert!(cleared > tried / 10, "{cleared} of {tried}");
        assert!(found > tried / 10, "{found} of {tried}");
    }

    /// The search's narrowest piece, one product by `2^-DEPTH`, equals `DEPTH` halvings in
    /// Q16.16 (whose products floor) and in `f32` and `f64` (exact), on widths from one
    /// step of each type to thousands of units.
    #[test]
    fn one_product_equals_the_halvings() {
        fn check<S: Scalar + core::fmt::Debug>(from_f64: impl Fn(f64) -> S, least: f64) {
            let scale = (0..DEPTH).fold(S::ONE, |scale, _| scale * S::SINE[0]);
            let mut next = stream(17);
            for _ in 0..20_000 {
                let width = from_f64(least * libm::exp2(next() * (12.0 - least.log2())));
                let halved = (0..DEPTH).fold(width, |w, _| w * S::SINE[0]);
                assert_eq!(width * scale, halved, "{width:?}");
            }
        }
        check::<I16F16>(I16F16::from_f64, 1.0 / 65536.0);
        check::<f32>(|x| x as f32, 1e-20);
        check::<f64>(|x| x, 1e-200);
    }

    #[test]
    fn sine_in_f32_and_fixed_point() {
        let mut worst = (0.0f64, 0.0f64);
        for i in -4000..=4000 {
            let x = f64::from(i) / 200.0;
            let exact = libm::sin(x);
            worst.0 = worst.0.max((f64::from((x as f32).sin()) - exact).abs());
            worst.1 = worst
                .1
                .max((I16F16::from_f64(x).sin().to_f64() - exact).abs());
        }
        assert!(worst.0 < 1e-6, "f32 {}", worst.0);
        assert!(worst.1 < 1e-4, "I16F16 {}", worst.1);
    }

    /// Rays from outside a point `p` of the surface towards it, from straight on down to
    /// within 1e-5 of the tangent plane: each meets the surface no later than `p`, on it.
    #[test]
    fn rays_towards_the_surface_meet_it_up_to_grazing() {
        for surfer in [Surfer::Cone, Surfer::Waist, Surfer::Vase] {
            let s = surface::<f64>(surfer);
            let mut next = stream(7 + surfer as u64);
            let mut worst = 0.0f64;
            for _ in 0..20_000 {
                let h = 0.01 + next() * 5.8;
                let angle = next() * core::f64::consts::TAU;
                let (r, _) = s.profile(h);
                let a = s.axis.to_f64();
                let u = a.cross(Vec3::new(1.0, 0.0, 0.0)).unit_f64().unwrap();
                let v = a.cross(u);
                let radial = u * libm::cos(angle) + v * libm::sin(angle);
                let p = s.base + a * h + radial * r;
                // The surface's own normal (the cone's shading normal leans further).
                let slope = (s.profile(h + 1e-6).0 - s.profile(h - 1e-6).0) / 2e-6;
                let n = (radial - a * slope).unit_f64().unwrap();
                // A tangent direction, and a lean towards the normal from 1 down to 1e-4.
                let tangent = n.cross(a).unit_f64().unwrap_or(u);
                let lean = libm::pow(10.0, -5.0 * next());
                let from = p + (n * lean + tangent * (next() - 0.5)) * (1.0 + 4.0 * next());
                let dir = (p - from).unit_f64().unwrap();
                let reach = (p - from).length();
                let ray = Ray::with_length(from, dir, 1.0);
                let t = s
                    .nearest(&ray, f64::INFINITY)
                    .unwrap_or_else(|| panic!("{surfer:?}: missed {p:?} from {from:?}"));
                assert!(t <= reach * (1.0 + 1e-9), "{surfer:?}: {t} beyond {reach}");
                let q = ray.at(t) - s.base;
                let hq = q.dot(a);
                let off = ((q - a * hq).length() - s.profile(hq).0).abs();
                worst = worst.max(off);
            }
            assert!(worst < 1e-9, "{surfer:?}: a hit {worst} off the surface");
        }
    }

    /// Pieces of random rays' intervals that `clear_of` passes keep `G`'s sign at their
    /// left end all along (2,000 samples each), from outside and from inside an open end.
    #[test]
    fn pieces_found_clear_hold_no_crossing() {
        let leanings = [[0.3, 1.0, 0.2], [0.0, 1.0, 0.0]];
        for (surfer, direction) in [Surfer::Cone, Surfer::Waist, Surfer::Vase]
            .into_iter()
            .flat_map(|surfer| leanings.map(|direction| (surfer, direction)))
        {
            let s = leaning::<f64>(surfer, direction);
            let mut next = stream(11 + surfer as u64);
            let (mut cleared, mut inside) = (0, 0);
            for _ in 0..4_000 {
                // From anywhere near the surface (inside its open ends too), any way.
                let from = s.center
                    + Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * (2.5 * s.bound);
                let dir = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5);
                let Some((line, span)) = Line::within_reach(&s, from, dir) else {
                    continue;
                };
                let Some((low, high)) = s.interval(&line, span) else {
                    continue;
                };
                let mut search = Search {
                    surface: &s,
                    line: &line,
                    evaluations: 0,
                };
                let (mut pa, mut pb) = (next(), next());
                if pb < pa {
                    (pa, pb) = (pb, pa);
                }
                let (ta, tb) = (low + (high - low) * pa, low + (high - low) * pb);
                let ((ga, wave_a), (gb, wave_b)) = (search.g(ta), search.g(tb));
                let piece = Piece {
                    a: ta,
                    ga,
                    wave_a,
                    b: tb,
                    gb,
                    wave_b,
                };
                let outside = ga > 0.0;
                if !search.clear_of(outside, &piece) {
                    continue;
                }
                cleared += 1;
                inside += usize::from(!outside);
                for k in 0..=2_000 {
                    let t = ta + (tb - ta) * f64::from(k) / 2_000.0;
                    let (g, _) = search.g(t);
                    assert!(
                        (g > 0.0) == outside,
                        "{surfer:?}: G({t}) = {g} across, in a piece [{ta}, {tb}] found clear"
                    );
                }
            }
            // The test is not vacuous: many pieces are found clear, some from inside.
            assert!(
                cleared > 200 && inside > 5,
                "{surfer:?}: {cleared} clear, {inside} inside"
            );
        }
    }

    #[test]
    fn rays_along_the_axis_pass_through_the_open_ends() {
        let s = surface::<f32>(Surfer::Waist);
        let down = -s.axis;
        let above = s.base + s.axis * 10.0;
        assert_eq!(s.nearest(&Ray::new(above, down), f32::INFINITY), None);
        // Off the axis by more than the waist: the ray meets the inside of the top.
        let off = above + s.axis.cross(Vec3::new(1.0, 0.0, 0.0)).unit().unwrap() * 1.2;
        let t = s.nearest(&Ray::new(off, down), f32::INFINITY).unwrap();
        let h = (off + down * t - s.base).dot(s.axis);
        assert!(h > 4.0 && h < 6.0, "{h}");
    }

    #[test]
    fn zero_direction_and_bad_height_are_errors() {
        let mut def = RevSurfDef {
            surfer: Surfer::Vase,
            base: [0.0; 3],
            direction: [0.0; 3],
            height: 1.0,
        };
        assert_eq!(
            RevSurf::<f32>::build(&def, 1.0),
            Err(ErrorKind::ZeroVector {
                attr: Attr::Direction
            })
        );
        def.direction = [0.0, 1.0, 0.0];
        def.height = 0.0;
        assert_eq!(
            RevSurf::<f32>::build(&def, 1.0),
            Err(ErrorKind::NotPositive { attr: Attr::Height })
        );
    }
}
