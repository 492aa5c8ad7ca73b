//! The render plan: what a scene needs, worked out once before rendering.
//!
//! - [`Stages`]: which parts of the shading run at all. A scene without lights needs no
//!   illumination, one without mirror materials no reflection rays, one without transparent
//!   materials no transmission rays and no filter walk (its shadow rays stop at the first
//!   blocker), one without glints no Blinn-Phong term, one with a single object no shadow rays.
//! - Objects that no ray can ever count (wholly in front of the image plane, where the z rule
//!   discards every hit) are dropped for every ray.
//! - [`RowSpan`]: the image rows whose primary rays can reach each object. All rays of a row
//!   lie in one plane through the eye (it contains the eye and the row's line on the image
//!   plane, which runs along x), so seen along the x axis a row is a half-line from the eye,
//!   and an object can be hit only by the rows whose half-line meets its outline: a sphere's
//!   disc, a rectangle's corners' hull, an infinite plane's half of the view (its horizon).
//!
//! Every bound is conservative: it is computed in `f64` (or `f32`, see
//! [`crate::scalar::geometry`]) from the number type's own values, widened by an angle of
//! 2e-3 radians and 64 steps of the type's resolution, then by one row on each side, so the
//! rounding of the rays in `f32` or fixed point cannot reach an object its row's list left
//! out. A planned render is pixel for pixel the render without a
//! plan; the tests check that for every scene and number type.

use crate::camera::Camera;
use crate::interval::Interval;
use crate::light::Light;
use crate::material::Material;
use crate::object::{Object, Shape};
use crate::scalar::Scalar;
use crate::scalar::geometry::{self, Geo};
use crate::vec3::Vec3;
use heapless::Vec;

mod shadows;
#[cfg(all(test, feature = "animate"))]
pub(crate) use shadows::cone_octagon;
pub(crate) use shadows::widened_ball;
pub use shadows::{BOXES, OCCLUDERS, ScreenBox, ShadowBoxes};
#[cfg(feature = "animate")]
pub(crate) use shadows::{
    OnPlane, UMBRA_CORNERS, certain_umbra, shadow_on_plane, widened_vertices,
};

/// Angular widening of every bound, in radians: far above the direction error of any number
/// type microray has (about 1e-5 for Q16.16).
pub(crate) const ANGLE_MARGIN: Geo = 2e-3;

/// [`ANGLE_MARGIN`] for a moving picture's region (see [`crate::region`]): an eighth of
/// it, where each margin adds a ring of pixels to trace about every change. With the eye
/// 6 from the screen, as in the films, Q16.16's primary rays turn by about 3e-6 radians;
/// nearer, [`region_angle`] adds the type's rounding.
#[cfg(feature = "animate")]
const TIGHT_ANGLE: Geo = ANGLE_MARGIN / 8.0;

/// The angle a moving picture's region widens its hulls by, for `camera` in type `S`:
/// [`TIGHT_ANGLE`], and eight times the turn that a step of rounding in a point of the
/// screen gives a primary ray (one step of the type's resolution in fixed point; of its
/// precision at the screen's reach in floating point), which grows as the eye nears the
/// screen (one step of Q16.16 turns a ray 0.2 from the screen by 1e-4 radians).
#[cfg(feature = "animate")]
pub(crate) fn region_angle<S: Scalar>(camera: &Camera<S>) -> Geo {
    let eye = camera.viewpoint().to_geo();
    let [wx, wy] = camera.world().map(|w| geometry::abs(w.to_geo()));
    let step = if S::WIDE_RANGE {
        let reach = wx + wy + geometry::abs(eye.x) + geometry::abs(eye.y) + geometry::abs(eye.z);
        geometry::from_f64(S::UNIT_STEP) * reach
    } else {
        geometry::from_f64(S::MIN_NORMAL)
    };
    let angle = TIGHT_ANGLE + 8.0 * step / geometry::abs(eye.z);
    // The eye on the screen's plane, or nearly: every margin as wide as it gets.
    if angle < 1.0 { angle } else { 1.0 }
}

/// The step of the bounds' absolute margins (see [`RESOLUTION_STEPS`]) for `camera` in
/// type `S`: the type's resolution, and where the geometry is `f32`, that type's rounding at
/// the scene's reach (the eye's `|.|_1` and the screen's size: a point's position is off by
/// its rounding; farther points' by a share of their distance, which the angles cover).
pub(crate) fn resolution<S: Scalar>(camera: &Camera<S>) -> Geo {
    let own = geometry::from_f64(S::MIN_NORMAL);
    if !geometry::SINGLE {
        return own;
    }
    let [wx, wy] = camera.world().map(|w| geometry::abs(w.to_geo()));
    own + geometry::STEP * (wx + wy + norm_1(camera.viewpoint().to_geo()))
}

/// `|v|_1`.
fn norm_1(v: Vec3<Geo>) -> Geo {
    geometry::abs(v.x) + geometry::abs(v.y) + geometry::abs(v.z)
}

/// `cos` and `sin` of [`ANGLE_MARGIN`] (no trigonometry in the library).
const COS_MARGIN: Geo = geometry::from_f64(0.999_998_000_000_666_6);
const SIN_MARGIN: Geo = geometry::from_f64(0.001_999_998_666_666_933_3);

/// "A millionth more for the roundings": ten of `f32`'s steps where the geometry is `f32`.
const MILLIONTH: Geo = geometry::allowance(1e-6, 1e-5);

/// Widening in steps of the type's resolution (fixed point rounds every coordinate).
const RESOLUTION_STEPS: Geo = 64.0;

/// Which stages of the shading run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stages {
    /// Lights are summed (else only ambient light).
    pub illumination: bool,
    /// Shadow rays are cast (else every light reaches every lit surface).
    pub shadows: bool,
    /// Shadow rays walk through transparent objects, multiplying filters (else they stop at
    /// the first blocker: an any-hit test).
    pub filtered_shadows: bool,
    /// Mirror reflection rays.
    pub reflection: bool,
    /// Transmission rays through transparent objects.
    pub transparency: bool,
    /// Blinn-Phong glints.
    pub glints: bool,
}

impl Stages {
    /// Everything on: the render without a plan.
    pub const ALL: Self = Self {
        illumination: true,
        shadows: true,
        filtered_shadows: true,
        reflection: true,
        transparency: true,
        glints: true,
    };
}

/// The image rows (`y = 0` the bottom, as the camera counts) whose primary rays can hit an
/// object, both ends included; empty when `first > last`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowSpan {
    /// The lowest row.
    pub first: u16,
    /// The highest row.
    pub last: u16,
}

impl RowSpan {
    /// Every row.
    pub const ALL: Self = Self {
        first: 0,
        last: u16::MAX,
    };
    /// No row.
    pub const NONE: Self = Self { first: 1, last: 0 };

    /// Whether row `y` is in the span.
    #[inline]
    pub fn contains(&self, y: u16) -> bool {
        self.first <= y && y <= self.last
    }

    /// How many of the camera's rows the span covers.
    pub fn rows(&self, height: u16) -> u16 {
        let last = self.last.min(height.saturating_sub(1));
        if self.first > last {
            0
        } else {
            last - self.first + 1
        }
    }
}

/// A scene's render plan: the stages that run, the objects any ray can count (by index, in
/// definition order, which keeps the closest-hit tie rule) and each one's rows.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan<const OBJECTS: usize> {
    stages: Stages,
    kept: Vec<u16, OBJECTS>,
    spans: Vec<RowSpan, OBJECTS>,
    /// Each kept object's image columns (`x = 0` the left), as `spans` holds its rows.
    columns: Vec<RowSpan, OBJECTS>,
}

impl<const OBJECTS: usize> Plan<OBJECTS> {
    /// The plan for a scene's parts.
    #[inline(never)]
    pub fn new<S: Scalar>(
        camera: &Camera<S>,
        materials: &[Material<S>],
        lights: &[Light<S>],
        objects: &[Object<S>],
        z_limit: S,
    ) -> Self {
        let mut plan = Self {
            stages: Stages::ALL,
            kept: Vec::new(),
            spans: Vec::new(),
            columns: Vec::new(),
        };
        let view = View::new(camera, false);
        let across = View::new(camera, true);
        let resolution = resolution(camera);
        for (index, object) in objects.iter().enumerate() {
            if !wholly_in_front(object, z_limit.to_geo(), resolution) {
                let rows = view.rows_of(object, resolution);
                plan.keep(index, rows, across.rows_of(object, resolution));
            }
        }
        let used = |test: &dyn Fn(&Material<S>) -> bool| {
            plan.kept.iter().any(|&index| {
                objects.get(usize::from(index)).is_some_and(|object| {
                    materials_of(object)
                        .into_iter()
                        .flatten()
                        .filter_map(|id| materials.get(usize::from(id)))
                        .any(test)
                })
            })
        };
        let transparency = used(&|m| m.transparency != S::ZERO);
        plan.stages = Stages {
            illumination: !lights.is_empty(),
            // An object never shadows itself (shadow rays skip the object they leave).
            shadows: !lights.is_empty() && plan.kept.len() >= 2,
            filtered_shadows: transparency,
            reflection: used(&|m| m.reflects()),
            transparency,
            glints: !lights.is_empty() && used(&|m| m.shininess != S::ZERO),
        };
        plan
    }

    fn keep(&mut self, index: usize, span: RowSpan, columns: RowSpan) {
        // Indices that do not fit u16 cannot be planned: with more objects than that the
        // plan keeps only the first 65536, so scenes add them only below that (see
        // `Scene::add_object`). The three lists have the same capacity.
        if let Ok(index) = u16::try_from(index)
            && self.kept.push(index).is_ok()
            && (self.spans.push(span).is_err() || self.columns.push(columns).is_err())
        {
            self.kept.pop();
            self.spans.truncate(self.kept.len());
            self.columns.truncate(self.kept.len());
        }
    }

    /// No plan: every stage, no object listed (what a renderer holds without the `plan`
    /// feature).
    pub const fn empty() -> Self {
        Self {
            stages: Stages::ALL,
            kept: Vec::new(),
            spans: Vec::new(),
            columns: Vec::new(),
        }
    }

    /// The stages that run.
    pub fn stages(&self) -> Stages {
        self.stages
    }

    /// The objects any ray can count, by index.
    pub fn kept(&self) -> &[u16] {
        &self.kept
    }

    /// The row span of each kept object, in the order of [`kept`](Self::kept).
    pub fn spans(&self) -> &[RowSpan] {
        &self.spans
    }

    /// The column span of each kept object (`x = 0` the left: the image columns whose
    /// primary rays can reach it), in the order of [`kept`](Self::kept).
    pub fn columns(&self) -> &[RowSpan] {
        &self.columns
    }

    /// The objects whose span contains row `y` (`y = 0` the bottom), in definition order.
    pub fn objects_in_row(&self, y: u16) -> Vec<u16, OBJECTS> {
        let mut row = Vec::new();
        for index in self.in_row(y) {
            // Cannot fail: at most as many as `kept` holds.
            let _ = row.push(index);
        }
        row
    }

    /// [`objects_in_row`](Self::objects_in_row) one by one, with no list to move.
    pub fn in_row(&self, y: u16) -> impl Iterator<Item = u16> + '_ {
        self.kept
            .iter()
            .zip(&self.spans)
            .filter(move |(_, span)| span.contains(y))
            .map(|(&index, _)| index)
    }
}

/// The rows and columns whose primary rays can reach `object` (its spans in a plan).
#[cfg(feature = "animate")]
pub(crate) fn footprint<S: Scalar>(camera: &Camera<S>, object: &Object<S>) -> ScreenBox {
    let resolution = resolution(camera);
    ScreenBox {
        rows: View::new(camera, false).rows_of(object, resolution),
        columns: View::new(camera, true).rows_of(object, resolution),
    }
}

/// Into `octagon`, an octagon whose hull's outline holds a ball's (a sphere, or a
/// surface of revolution's bounding ball): about the cone from the eye tangent to the ball
/// widened as [`View::sphere`] widens it, by [`region_angle`]. `false` (nothing
/// written) for other kinds, and where the eye is in or near the ball.
#[cfg(feature = "animate")]
pub(crate) fn outline_octagon<S: Scalar>(
    camera: &Camera<S>,
    object: &Object<S>,
    octagon: &mut [Vec3<Geo>; 8],
) -> bool {
    let (center, radius) = match object.shape() {
        Shape::Sphere(s) => (s.center.to_geo(), s.radius.to_geo()),
        Shape::RevSurf(s) if cfg!(feature = "revsurf") => (s.center.to_geo(), s.bound.to_geo()),
        _ => return false,
    };
    let eye = camera.viewpoint().to_geo();
    let d = center - eye;
    let distance = geometry::abs(d.x) + geometry::abs(d.y) + geometry::abs(d.z);
    let angle = region_angle(camera);
    let r = radius + angle * (distance + radius) + RESOLUTION_STEPS * resolution(camera);
    shadows::cone_octagon(center, r, eye, octagon)
}

/// Weights `[a, b]` and bounds on `a x + b y` (low, high) and `a x - b y` (low, high).
#[cfg(feature = "animate")]
pub(crate) type CutBounds = ([i32; 2], [Geo; 4]);

/// The rows and columns whose primary rays can reach the hull of `points` (the whole
/// screen where the hull holds the eye or spans half a turn), and, where every point lies
/// before the eye and the box is bounded, bounds on `a x + b y` and `a x - b y` over the
/// pixels `(x, y)` (`y = 0` the top) whose primary rays can reach it, `[a, b]` from
/// `weights` of the box (none: no cut): the lines that cut its corners. A pixel can lie as
/// far from the points' own pixels along each axis as the box's margins (the larger
/// widening of its two ends, by [`region_angle`]: a turn by an angle moves a screen height
/// the more, the farther it is from the eye's, and the end farther from it is turned away
/// from it) and `spread` rows more: pixel `(x, y)`'s ray passes through its point, and the
/// samples of an anti-aliased pixel lie within half a row of it (`spread` 0.5; 0 for one
/// ray a pixel).
#[cfg(feature = "animate")]
pub(crate) fn outline_cut<S: Scalar>(
    camera: &Camera<S>,
    points: &[Vec3<Geo>],
    spread: Geo,
    weights: impl Fn(&ScreenBox) -> Option<[i32; 2]>,
) -> (ScreenBox, Option<CutBounds>) {
    let (rows, columns) = (View::new(camera, false), View::new(camera, true));
    let (angle, resolution) = (region_angle(camera), resolution(camera));
    if let Some(seen) = Seen::of(&rows, &columns, points, angle, resolution) {
        return seen.cut(&rows, &columns, points, spread, weights);
    }
    let (row_heights, column_heights) = (
        rows.outline_by(points, resolution, angle, at_least(angle)),
        columns.outline_by(points, resolution, angle, at_least(angle)),
    );
    let screen = ScreenBox {
        rows: rows.span_tight(row_heights, spread),
        columns: columns.span_tight(column_heights, spread),
    };
    // Rare: a hull whose points all lie before the eye takes the closed form above.
    let cut = (|| {
        let [a, b] = weights(&screen)?;
        let projection = Projection::new(&rows, &columns)?;
        let images = projection.images(points)?;
        let margin = |[lo, hi]: [Geo; 2], heights: Heights, per: Geo| {
            let (wide_lo, wide_hi) = (heights.lo * per, heights.hi * per);
            (lo - wide_lo).max(wide_hi - hi).max(0.0) + spread
        };
        let margins = [
            margin(images.columns, column_heights, projection.per_column),
            margin(images.rows, row_heights, projection.per_row),
        ];
        projection.cut(points, [a, b], margins)
    })();
    (screen, cut)
}

/// Points all clearly before the eye as the screen shows them: the columns and rows their
/// images span (pixels, rows from the bottom) and how far a pixel whose primary ray meets
/// their hull can lie from it along each (what [`View::outline_by`] widens by, in closed
/// form: one projection a point, where its two sweeps and the cut's projection took three
/// passes).
#[cfg(feature = "animate")]
struct Seen {
    projection: Projection,
    columns: [Geo; 2],
    rows: [Geo; 2],
    margins: [Geo; 2],
}

#[cfg(feature = "animate")]
impl Seen {
    /// `None` where a point is not clearly before the eye, or the widening is not small.
    fn of(
        rows: &View,
        columns: &View,
        points: &[Vec3<Geo>],
        angle: Geo,
        resolution: Geo,
    ) -> Option<Self> {
        let projection = Projection::new(rows, columns)?;
        let images = projection.images(points)?;
        let [near_columns, near_rows] = images.nearest;
        let margins = [
            projection.turned(images.columns, near_columns, angle, resolution, true)?,
            projection.turned(images.rows, near_rows, angle, resolution, false)?,
        ];
        Some(Self {
            projection,
            columns: images.columns,
            rows: images.rows,
            margins,
        })
    }

    /// [`outline_cut`] of the points seen: the pixels within the margins and `spread` of
    /// their images, and the cut's bounds (a second projection a point, for the weights
    /// that the box's size gives).
    fn cut(
        &self,
        rows: &View,
        columns: &View,
        points: &[Vec3<Geo>],
        spread: Geo,
        weights: impl Fn(&ScreenBox) -> Option<[i32; 2]>,
    ) -> (ScreenBox, Option<CutBounds>) {
        let [mx, my] = self.margins.map(|m| m + spread);
        let span = |view: &View, [lo, hi]: [Geo; 2], m: Geo| {
            view.rows_from(geometry::ceil(lo - m), geometry::floor(hi + m))
        };
        let screen = ScreenBox {
            rows: span(rows, self.rows, my),
            columns: span(columns, self.columns, mx),
        };
        let cut = weights(&screen).and_then(|ab| self.projection.cut(points, ab, [mx, my]));
        (screen, cut)
    }
}

/// The columns and rows (pixels, rows from the bottom) the images of some points span,
/// and each view's (columns', rows') nearest point's `|d|_1` from the eye.
#[cfg(feature = "animate")]
struct Images {
    columns: [Geo; 2],
    rows: [Geo; 2],
    nearest: [Geo; 2],
}

/// `[lo, hi]` widened to hold `v`.
#[cfg(feature = "animate")]
fn widen([lo, hi]: [Geo; 2], v: Geo) -> [Geo; 2] {
    [if v < lo { v } else { lo }, if v > hi { v } else { hi }]
}

/// Where the eye's rays through points meet the screen (`z = 0`), in pixels: `x` from the
/// left, rows from the bottom, pixel `(x, y)`'s ray passing through its point exactly.
#[cfg(feature = "animate")]
struct Projection {
    eye: Vec3<Geo>,
    /// Pixels a world unit along `x` and `y` (one quotient a view: soft float's are slow).
    per_column: Geo,
    per_row: Geo,
    /// The top row.
    top: Geo,
}

#[cfg(feature = "animate")]
impl Projection {
    fn new(rows: &View, columns: &View) -> Option<Self> {
        if !(rows.row_height > 0.0 && columns.row_height > 0.0) {
            return None;
        }
        let ([ex, ez], [ey, _]) = (columns.eye, rows.eye);
        Some(Self {
            eye: Vec3::new(ex, ey, ez),
            per_column: 1.0 / columns.row_height,
            per_row: 1.0 / rows.row_height,
            top: Geo::from(rows.height.saturating_sub(1)),
        })
    }

    /// `p`'s column and row (`0` the bottom); `None` unless `p` lies clearly before the
    /// eye.
    fn of(&self, p: &Vec3<Geo>) -> Option<[Geo; 2]> {
        let e = self.eye;
        let ahead = e.z - p.z;
        if !(ahead > geometry::allowance(1e-9, 1e-3) * (geometry::abs(e.z) + geometry::abs(p.z))) {
            return None;
        }
        let k = e.z / ahead;
        Some([
            (e.x + (p.x - e.x) * k) * self.per_column,
            (e.y + (p.y - e.y) * k) * self.per_row,
        ])
    }

    /// The columns and rows the images of `points` span, and each view's nearest point's
    /// `|d|_1` from the eye (as [`View::outline_by`] takes it); `None` unless every point
    /// lies clearly before the eye.
    fn images(&self, points: &[Vec3<Geo>]) -> Option<Images> {
        let e = self.eye;
        let mut columns = [Geo::INFINITY, Geo::NEG_INFINITY];
        let mut rows = columns;
        let mut nearest = [Geo::INFINITY; 2];
        for p in points {
            let [x, row] = self.of(p)?;
            columns = widen(columns, x);
            rows = widen(rows, row);
            let along = geometry::abs(p.z - e.z);
            nearest = [
                nearest[0].min(geometry::abs(p.x - e.x) + along),
                nearest[1].min(geometry::abs(p.y - e.y) + along),
            ];
        }
        Some(Images {
            columns,
            rows,
            nearest,
        })
    }

    /// The cut with weights `[a, b]` about the images of `points`, `margins` pixels (along
    /// `x` and `y`) out from them: bounds on `a x + b y` and `a x - b y`, `y = 0` the top.
    fn cut(&self, points: &[Vec3<Geo>], [a, b]: [i32; 2], [mx, my]: [Geo; 2]) -> Option<CutBounds> {
        let (af, bf) = (a as Geo, b as Geo);
        let mut sum = [Geo::INFINITY, Geo::NEG_INFINITY];
        let mut difference = sum;
        for p in points {
            let [x, row] = self.of(p)?;
            let y = self.top - row;
            sum = widen(sum, af * x + bf * y);
            difference = widen(difference, af * x - bf * y);
        }
        let m = af * mx + bf * my;
        let bounds = [sum[0] - m, sum[1] + m, difference[0] - m, difference[1] + m];
        (m.is_finite() && bounds.iter().all(|v| v.is_finite())).then_some(([a, b], bounds))
    }

    /// How far, in pixels along `x` (`columns`) or up the rows, a ray's crossing of the
    /// screen within `range` (pixels) moves when its direction turns by what
    /// [`View::outline_by`] widens a hull's directions by (`nearest` its points' least
    /// `|d|_1` from the eye in that view, `angle` and `resolution` as there): turned by
    /// `a` radians, a crossing `u` from the eye's foot moves at most `a h^2 / (e - a h)`,
    /// `h^2 = e^2 + u^2`, `e` the eye's height over the screen (the tangent's growth).
    /// `None` where that is not small (the eye near the screen, or the turn large).
    fn turned(
        &self,
        [lo, hi]: [Geo; 2],
        nearest: Geo,
        angle: Geo,
        resolution: Geo,
        columns: bool,
    ) -> Option<Geo> {
        let (per, foot) = if columns {
            (self.per_column, self.eye.x)
        } else {
            (self.per_row, self.eye.y)
        };
        let e = self.eye.z;
        let blur_sin = blur_sine(nearest, resolution, angle)?;
        if !(e > 0.0 && per > 0.0) {
            return None;
        }
        // The blur's angle (`asin x <= 1.05 x` for `x` below a half), then the turn by
        // `angle`, and a millionth more for the roundings here.
        let a = (blur_sin * 1.05 + angle) * (1.0 + MILLIONTH);
        let u = geometry::abs(lo / per - foot).max(geometry::abs(hi / per - foot));
        let h = geometry::sqrt(e * e + u * u) * (1.0 + MILLIONTH);
        let room = e - a * h;
        (room > 0.5 * e).then(|| a * h * h / room * per)
    }
}

/// Weights `[a, b]` and bounds on the pixels `(x, y)` (`y = 0` the top) of an octagon:
/// `x` low and high, `y` low and high, `a x + b y` low and high, `a x - b y` low and high.
#[cfg(feature = "animate")]
pub(crate) type OctagonBounds = ([i32; 2], [Geo; 8]);

/// An octagon of pixels whose primary rays, as any number type traces them, all meet the
/// convex polygon `corners` (in order, every one before the eye) on its plane, and so do
/// the samples of an anti-aliased pixel where `spread` is half a pixel: one inscribed in
/// its image (the octagon about the image, shrunk towards the corners' mean until each of
/// its corners lies within the image), then moved in by a ray's error (as [`outline_cut`]
/// moves out) and `spread`. `[a, b]` from `weights` of the image's width and height in
/// pixels. `None` when there is none.
#[cfg(feature = "animate")]
pub(crate) fn inscribed_cut<S: Scalar>(
    camera: &Camera<S>,
    corners: &[Vec3<Geo>; UMBRA_CORNERS],
    spread: Geo,
    weights: impl Fn(u16, u16) -> [i32; 2],
) -> Option<OctagonBounds> {
    let (rows, columns) = (View::new(camera, false), View::new(camera, true));
    let projection = Projection::new(&rows, &columns)?;
    let images = projection.images(corners)?;
    let mut image = [[0.0; 2]; UMBRA_CORNERS];
    let mut mean = [0.0; 2];
    for (to, p) in image.iter_mut().zip(corners) {
        let [x, row] = projection.of(p)?;
        *to = [x, projection.top - row];
        mean = [mean[0] + to[0], mean[1] + to[1]];
    }
    let (x_range, row_range) = (images.columns, images.rows);
    let y_range = [projection.top - row_range[1], projection.top - row_range[0]];
    let n = UMBRA_CORNERS as Geo;
    let c = [mean[0] / n, mean[1] / n];
    let side = |[lo, hi]: [Geo; 2]| (hi - lo).clamp(1.0, 2047.0) as u16;
    let [a, b] = weights(side(x_range), side(y_range));
    let (af, bf) = (a as Geo, b as Geo);
    if !(af > 0.0 && bf > 0.0) {
        return None;
    }
    let mut sum = [Geo::INFINITY, Geo::NEG_INFINITY];
    let mut difference = sum;
    for &[x, y] in &image {
        sum = widen(sum, af * x + bf * y);
        difference = widen(difference, af * x - bf * y);
    }
    let ([x0, x1], [y0, y1], [s0, s1], [d0, d1]) = (x_range, y_range, sum, difference);
    // The octagon's corners, in order round it.
    let octagon = [
        [x1, y1.min((s1 - af * x1) / bf)],
        [x1.min((s1 - bf * y1) / af), y1],
        [x0.max((d0 + bf * y1) / af), y1],
        [x0, y1.min((af * x0 - d0) / bf)],
        [x0, y0.max((s0 - af * x0) / bf)],
        [x0.max((s0 - bf * y0) / af), y0],
        [x1.min((d1 + bf * y0) / af), y0],
        [x1, y0.max((af * x1 - d1) / bf)],
    ];
    // The image's rightmost corner, where the octagon's first corner points.
    let rightmost = (0..UMBRA_CORNERS)
        .zip(&image)
        .fold((0, Geo::NEG_INFINITY), |(i, x), (j, p)| {
            if p[0] > x { (j, p[0]) } else { (i, x) }
        })
        .0;
    let f = inscribed_share(&image, c, &octagon, rightmost)?;
    // A ray's error, as the outlines widen directions, and the spread of a pixel's samples.
    let (angle, resolution) = (region_angle(camera), resolution(camera));
    let [near_columns, near_rows] = images.nearest;
    let [mx, my] = [
        projection.turned(x_range, near_columns, angle, resolution, true)?,
        projection.turned(row_range, near_rows, angle, resolution, false)?,
    ]
    .map(|m| m + spread);
    let m = af * mx + bf * my;
    let shrink = |lo: Geo, hi: Geo, at: Geo, margin: Geo| {
        [at + (lo - at) * f + margin, at + (hi - at) * f - margin]
    };
    let ([x0, x1], [y0, y1]) = (shrink(x0, x1, c[0], mx), shrink(y0, y1, c[1], my));
    let ([s0, s1], [d0, d1]) = (
        shrink(s0, s1, af * c[0] + bf * c[1], m),
        shrink(d0, d1, af * c[0] - bf * c[1], m),
    );
    let bounds = [x0, x1, y0, y1, s0, s1, d0, d1];
    bounds
        .iter()
        .all(|v| v.is_finite())
        .then_some(([a, b], bounds))
}

/// The largest share `f` (at most 1) such that the octagon shrunk towards `c` by `f` lies
/// within the convex polygon `image` (which holds `c`): for each of the octagon's corners,
/// where the ray from `c` through it leaves the polygon, through the edge between the
/// corners its direction lies between (found by walking round, both in order, from the
/// edges about corner `start`). `None` for a polygon that does not go round `c`.
#[cfg(feature = "animate")]
fn inscribed_share(
    image: &[[Geo; 2]; UMBRA_CORNERS],
    c: [Geo; 2],
    octagon: &[[Geo; 2]; 8],
    start: usize,
) -> Option<Geo> {
    let from_c = |p: [Geo; 2]| [p[0] - c[0], p[1] - c[1]];
    let turn = |points: &[[Geo; 2]]| {
        let next = points.iter().cycle().skip(1);
        let edges = points.iter().zip(next);
        edges
            .map(|(&p, &q)| cross(from_c(p), from_c(q)))
            .sum::<Geo>()
    };
    let (image_turn, octagon_turn) = (turn(image), turn(octagon));
    if !(image_turn.abs() > 0.0 && octagon_turn.abs() > 0.0) {
        return None;
    }
    let sign = if image_turn > 0.0 { 1.0 } else { -1.0 };
    let mut f: Geo = 1.0;
    // The edge before `start`: the octagon's first corner (rightmost) lies about there.
    let mut edge = start + UMBRA_CORNERS - 1;
    // The octagon's corners in the image's order round `c`.
    let mut in_order = *octagon;
    if (octagon_turn > 0.0) != (image_turn > 0.0) {
        in_order.reverse();
    }
    // Corner `i` of the image (round and round), from `c`.
    let at = |i: usize| from_c(image.get(i % UMBRA_CORNERS).copied().unwrap_or(c));
    for corner in in_order {
        let v = from_c(corner);
        // Walk to the edge whose ends `v` lies between (at most once round, and once more
        // for the first corner).
        let mut found = false;
        for _ in 0..2 * UMBRA_CORNERS {
            let (p, q) = (at(edge), at(edge + 1));
            if sign * cross(p, v) >= 0.0 && sign * cross(v, q) > 0.0 {
                // Where `t v` meets the edge `p + u (q - p)`.
                let e = [q[0] - p[0], q[1] - p[1]];
                let (inside, out) = (sign * cross(e, [-p[0], -p[1]]), sign * cross(e, v));
                // `c` inside the edge, `v` past it: `t = inside / -out` of the way.
                if out < 0.0 {
                    f = f.min(inside / -out);
                }
                found = true;
                break;
            }
            edge += 1;
        }
        if !found {
            return None;
        }
    }
    (f > 0.0).then_some(f)
}

/// The rows whose primary rays can reach an infinite plane, every column.
#[cfg(feature = "animate")]
pub(crate) fn plane_footprint<S: Scalar>(
    camera: &Camera<S>,
    plane: &crate::object::Plane<S>,
) -> ScreenBox {
    let rows = View::new(camera, false);
    ScreenBox {
        rows: rows.span(rows.plane(plane)),
        columns: RowSpan::ALL,
    }
}

/// The materials an object can show: its own, and a tiled plane's second one.
pub(crate) fn materials_of<S: Scalar>(object: &Object<S>) -> [Option<u16>; 2] {
    let alternate = match object.shape() {
        Shape::TiledPlane(tiles) => Some(tiles.altmaterial),
        _ => None,
    };
    [Some(object.material()), alternate]
}

/// Whether every point of the object has `z` clearly above the z limit, so the z rule
/// discards every hit of every ray on it.
fn wholly_in_front<S: Scalar>(object: &Object<S>, z_limit: Geo, resolution: Geo) -> bool {
    let clear_of = |z: Geo, size: Geo| {
        z > z_limit + ANGLE_MARGIN * (geometry::abs(z) + size) + RESOLUTION_STEPS * resolution
    };
    match object.shape() {
        Shape::Sphere(s) => {
            let r = s.radius.to_geo();
            clear_of(s.center.z.to_geo() - r, r)
        }
        // `cfg!`: without the feature there are none, and the sphere test keeps one caller.
        Shape::RevSurf(s) if cfg!(feature = "revsurf") => {
            let r = s.bound.to_geo();
            clear_of(s.center.z.to_geo() - r, r)
        }
        Shape::RevSurf(_) => false,
        Shape::FPlane(rect) => corners(rect).iter().all(|c| clear_of(c.z, 0.0)),
        Shape::TexPlane(t) => corners(&t.rect).iter().all(|c| clear_of(c.z, 0.0)),
        Shape::Plane(p) => plane_in_front(p, clear_of),
        Shape::TiledPlane(t) => plane_in_front(&t.rect.plane, clear_of),
    }
}

/// A plane facing along z (its normal has no x or y part) at a z clearly above the limit.
fn plane_in_front<S: Scalar>(
    plane: &crate::object::Plane<S>,
    clear_of: impl Fn(Geo, Geo) -> bool,
) -> bool {
    let n = plane.unit_normal;
    n.x == S::ZERO && n.y == S::ZERO && clear_of(plane.point.z.to_geo(), 0.0)
}

/// A rectangle's corners, in the geometry's type.
fn corners<S: Scalar>(rect: &crate::object::Rect<S>) -> [Vec3<Geo>; 4] {
    let p = rect.plane.point.to_geo();
    let across = rect.u.to_geo() * rect.dimensions[0].to_geo();
    let up = rect.v.to_geo() * rect.dimensions[1].to_geo();
    [p, p + across, p + across + up, p + up]
}

/// The 2-d cross product `a x b`: positive when `b` is anticlockwise of `a`.
fn cross(a: [Geo; 2], b: [Geo; 2]) -> Geo {
    a[0] * b[1] - a[1] * b[0]
}

fn length(a: [Geo; 2]) -> Geo {
    geometry::sqrt_rough(a[0] * a[0] + a[1] * a[1])
}

/// `a` turned by the angle whose cosine and sine are given (anticlockwise for `sin > 0`).
fn turn(a: [Geo; 2], cos: Geo, sin: Geo) -> [Geo; 2] {
    [a[0] * cos - a[1] * sin, a[0] * sin + a[1] * cos]
}

/// The sine of the angle by which a hull's directions are blurred, `nearest` its nearest
/// corner's `|d|_1` from the eye (see [`View::outline_by`]): the blur,
/// `steps + angle |d|_1`, over the bound `|d|_1 / sqrt 2` below the distance; `None`
/// unless that is below a half.
fn blur_sine(nearest: Geo, resolution: Geo, angle: Geo) -> Option<Geo> {
    let below = nearest * geometry::FRAC_1_SQRT_2;
    let blur = RESOLUTION_STEPS * resolution + angle * nearest;
    (below > 2.0 * blur).then(|| blur / below)
}

/// The sine and cosine of an angle widened by [`ANGLE_MARGIN`].
fn widened(sin: Geo, cos: Geo) -> (Geo, Geo) {
    widened_by(sin, cos, (SIN_MARGIN, COS_MARGIN))
}

/// The sine and cosine of an angle widened by the one whose sine and cosine are given.
fn widened_by(sin: Geo, cos: Geo, (by_sin, by_cos): (Geo, Geo)) -> (Geo, Geo) {
    (sin * by_cos + cos * by_sin, cos * by_cos - sin * by_sin)
}

/// The sine and cosine of an angle at least `angle` radians (small): `angle` and
/// `1 - angle^2`, below its true cosine (so the angle is larger).
#[cfg(feature = "animate")]
fn at_least(angle: Geo) -> (Geo, Geo) {
    (angle, 1.0 - angle * angle)
}

/// The camera seen along the x axis (rows: the eye `(y, z)`) or along the y axis (columns:
/// the eye `(x, z)`), and how a row or column maps to the image plane.
struct View {
    /// Columns: seen along y, coordinates `(x, z)`.
    columns: bool,
    eye: [Geo; 2],
    /// World units of the image plane per row.
    row_height: Geo,
    height: u16,
}

/// A set of screen heights `lo <= sy <= hi` on the image plane (either end may be
/// infinite).
type Heights = Interval<Geo>;

impl View {
    /// The camera seen along x (its rows) or, with `columns`, along y (its columns: all
    /// rays of an image column lie in one plane through the eye that holds the y axis).
    fn new<S: Scalar>(camera: &Camera<S>, columns: bool) -> Self {
        let eye = camera.viewpoint().to_geo();
        let (eye, world, count) = if columns {
            ([eye.x, eye.z], camera.world()[0], camera.width())
        } else {
            ([eye.y, eye.z], camera.world()[1], camera.height())
        };
        Self {
            columns,
            eye,
            row_height: world.to_geo() / Geo::from(count.saturating_sub(1).max(1)),
            height: count,
        }
    }

    /// A point's coordinates as this view sees them, and the one it looks along.
    fn seen(&self, v: Vec3<Geo>) -> ([Geo; 2], Geo) {
        if self.columns {
            ([v.x, v.z], v.y)
        } else {
            ([v.y, v.z], v.x)
        }
    }

    /// The rows whose primary rays can reach `object`.
    fn rows_of<S: Scalar>(&self, object: &Object<S>, resolution: Geo) -> RowSpan {
        let heights = match object.shape() {
            Shape::Sphere(s) => self.sphere(s.center.to_geo(), s.radius.to_geo(), resolution),
            Shape::RevSurf(s) if cfg!(feature = "revsurf") => {
                self.sphere(s.center.to_geo(), s.bound.to_geo(), resolution)
            }
            Shape::RevSurf(_) => Heights::ALL,
            Shape::FPlane(rect) => self.outline(&corners(rect), resolution),
            Shape::TexPlane(t) => self.outline(&corners(&t.rect), resolution),
            Shape::Plane(p) => self.plane(p),
            Shape::TiledPlane(t) => self.plane(&t.rect.plane),
        };
        self.span(heights)
    }

    /// The direction from the eye through screen height `sy` is `(sy - eye.y, -eye.z)`;
    /// it lies in the arc from direction `from` counter-clockwise to `to` (less than half a
    /// turn) when `from x d >= 0` and `d x to >= 0`, two conditions linear in `sy`.
    fn arc(&self, from: [Geo; 2], to: [Geo; 2]) -> Heights {
        if !(cross(from, to) > 0.0) {
            // Half a turn or more (or nothing to go by): every row.
            return Heights::ALL;
        }
        let [ey, ez] = self.eye;
        Heights::ALL
            .where_nonnegative(-from[0] * ez + from[1] * ey, -from[1])
            .where_nonnegative(ez * to[0] - to[1] * ey, to[1])
    }

    /// A sphere, seen along x, is a disc: the arc between the tangents from the eye.
    fn sphere(&self, center: Vec3<Geo>, radius: Geo, resolution: Geo) -> Heights {
        let (center, _) = self.seen(center);
        let c = [center[0] - self.eye[0], center[1] - self.eye[1]];
        let distance = length(c);
        let r = radius + ANGLE_MARGIN * (distance + radius) + RESOLUTION_STEPS * resolution;
        if !(distance > r) {
            return Heights::ALL;
        }
        // The tangents are c turned by the half angle a, sin a = r / distance, then widened.
        let sin = r / distance;
        let (sin, cos) = widened(sin, geometry::sqrt_rough(1.0 - sin * sin));
        if !(cos > 0.0) {
            return Heights::ALL;
        }
        self.arc(turn(c, cos, -sin), turn(c, cos, sin))
    }

    /// A rectangle, seen along x, is the hull of its corners: the arc their directions span.
    /// Any set of points: the arc of its hull.
    fn outline(&self, corners: &[Vec3<Geo>], resolution: Geo) -> Heights {
        self.outline_by(corners, resolution, ANGLE_MARGIN, (SIN_MARGIN, COS_MARGIN))
    }

    /// [`outline`](Self::outline) with a blur of `angle` radians a unit of distance, its
    /// directions then turned out by the angle whose sine and cosine are `widening` (the
    /// plan's [`ANGLE_MARGIN`]; a region's own angle).
    fn outline_by(
        &self,
        corners: &[Vec3<Geo>],
        resolution: Geo,
        angle: Geo,
        widening: (Geo, Geo),
    ) -> Heights {
        let direction = |corner: &Vec3<Geo>| {
            let (corner, _) = self.seen(*corner);
            [corner[0] - self.eye[0], corner[1] - self.eye[1]]
        };
        let Some(first) = corners.first() else {
            return Heights::ALL;
        };
        // Bounds on a corner's distance without a square root (soft float's are slow):
        // `|d|_1` above it, `|d|_1 / sqrt 2` below. Its blur, `steps + ANGLE_MARGIN |d|_1`,
        // over the bound below falls as `|d|_1` grows, and the blur is less than half the
        // bound below the more easily the larger `|d|_1`: the nearest corner decides both
        // (one quotient, where each corner took one).
        let mut nearest = Geo::INFINITY;
        // Whether every corner lies before the eye's plane, or every one behind it.
        let (mut before, mut behind) = (true, true);
        for corner in corners {
            let [dx, dy] = direction(corner);
            let above = geometry::abs(dx) + geometry::abs(dy);
            if !(above < Geo::INFINITY) {
                return Heights::ALL;
            }
            nearest = nearest.min(above);
            before &= dy < 0.0;
            behind &= dy > 0.0;
        }
        let Some(blur_sin) = blur_sine(nearest, resolution, angle) else {
            return Heights::ALL;
        };
        // Up by more than the few roundings by which a farther corner's quotient could
        // have come out above the nearest one's.
        let blur_sin = blur_sin * (1.0 + geometry::allowance(1e-14, 1e-6));
        // Sweep out the extremes from the first corner; within less than half a turn each
        // corner is clockwise of `low`, anticlockwise of `high`, or between them.
        let (mut low, mut high) = (direction(first), direction(first));
        for d in corners.iter().skip(1).map(direction) {
            if cross(high, d) > 0.0 {
                high = d;
            } else if cross(d, low) > 0.0 {
                low = d;
            }
        }
        // More than half a turn (the eye inside the outline) breaks the sweep: all rows.
        // Directions within a half plane (every corner on one side of the eye) span less,
        // and need no check.
        let spans_all = before
            || behind
            || corners
                .iter()
                .map(direction)
                .all(|d| cross(low, d) >= 0.0 && cross(d, high) >= 0.0);
        if !spans_all || cross(low, high) < 0.0 {
            return Heights::ALL;
        }
        let (sin, cos) = widened_by(
            blur_sin,
            geometry::sqrt_rough(1.0 - blur_sin * blur_sin),
            widening,
        );
        self.arc(turn(low, cos, -sin), turn(high, cos, sin))
    }

    /// An infinite plane: all of the view unless it runs along x; then the half of the view
    /// on its side of the horizon, widened by turning the normal both ways.
    fn plane<S: Scalar>(&self, plane: &crate::object::Plane<S>) -> Heights {
        let ([ny, nz], along) = self.seen(plane.unit_normal.to_geo());
        if along != 0.0 {
            return Heights::ALL;
        }
        let [ey, ez] = self.eye;
        let side = plane.n_dot_point.to_geo() - (ny * ey + nz * ez);
        // The eye near the plane sees it in every row.
        if !(geometry::abs(side) > ANGLE_MARGIN * (geometry::abs(ey) + geometry::abs(ez) + 1.0)) {
            return Heights::ALL;
        }
        // Hit when sign(side) (n . d) > 0, d = (sy - ey, -ez): linear in sy.
        let sign = if side > 0.0 { 1.0 } else { -1.0 };
        let facing = |sin: Geo| {
            let [ny, nz] = turn([ny, nz], COS_MARGIN, sin);
            Heights::ALL.where_nonnegative(sign * (-ny * ey - nz * ez), sign * ny)
        };
        facing(SIN_MARGIN).hull(facing(-SIN_MARGIN))
    }

    /// The rows whose screen height lies in `heights`, one more on each side.
    fn span(&self, heights: Heights) -> RowSpan {
        self.rows_from(
            geometry::floor(heights.lo / self.row_height) - 1.0,
            geometry::ceil(heights.hi / self.row_height) + 1.0,
        )
    }

    /// The rows whose screen height lies within `spread` rows of `heights` (half a row:
    /// those whose anti-aliased samples can lie in it; none: those whose one ray can).
    #[cfg(feature = "animate")]
    fn span_tight(&self, heights: Heights, spread: Geo) -> RowSpan {
        self.rows_from(
            geometry::ceil(heights.lo / self.row_height - spread),
            geometry::floor(heights.hi / self.row_height + spread),
        )
    }

    /// Rows `lo` to `hi` (whole numbers) on the screen: all of them where either is not a
    /// number.
    fn rows_from(&self, lo: Geo, hi: Geo) -> RowSpan {
        let top = Geo::from(self.height.saturating_sub(1));
        if lo.is_nan() || hi.is_nan() || !(self.row_height > 0.0) {
            return RowSpan::ALL;
        }
        if lo > hi || hi < 0.0 || lo > top {
            return RowSpan::NONE;
        }
        // Both clamped into 0..=top, which fits u16.
        let to_row = |v: Geo| v.clamp(0.0, top) as u16;
        RowSpan {
            first: to_row(lo),
            last: to_row(hi),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::CameraDef;
    use crate::light::LightDef;
    use crate::material::MaterialDef;
    use crate::object::ObjectDef;
    use crate::scene::Scene;

    const CAMERA: CameraDef<'static> = CameraDef::new("c", [80, 60], [8.0, 6.0], [4.0, 3.0, 6.0]);
    const LIGHT: LightDef<'static> = LightDef::point("l", [4.0, 8.0, 2.0], [5.0; 3]);
    const FLOOR: ObjectDef<'static> = ObjectDef::plane("f", "m", [0.0, 1.0, 0.0], [0.0; 3]);
    const BALL: ObjectDef<'static> = ObjectDef::sphere("b", "m", [4.0, 3.0, -4.0], 1.0);

    fn plan(
        materials: &[MaterialDef<'_>],
        lights: &[LightDef<'_>],
        objects: &[ObjectDef<'_>],
    ) -> Plan<4> {
        let scene: Scene<'_, f64, 4, 4, 2, 0, 80> =
            Scene::from_defs(&CAMERA, materials, &[], lights, objects).unwrap();
        Plan::new(
            scene.camera(),
            scene.materials(),
            scene.lights(),
            scene.objects(),
            scene.z_limit(),
        )
    }

    #[test]
    fn margin_constants_are_the_cosine_and_sine_of_the_margin() {
        // Within half a step of the geometry's type.
        let (cos, sin) = if geometry::SINGLE {
            (1e-7, 1e-9)
        } else {
            (1e-16, 1e-18)
        };
        let margin = geometry::to_f64(ANGLE_MARGIN);
        assert!((geometry::to_f64(COS_MARGIN) - libm::cos(margin)).abs() < cos);
        assert!((geometry::to_f64(SIN_MARGIN) - libm::sin(margin)).abs() < sin);
    }

    #[test]
    fn stages_follow_the_scene() {
        let matte = [MaterialDef::new("m").diffuse([1.0; 3])];
        let s = plan(&matte, &[], &[FLOOR, BALL]).stages();
        assert!(!s.illumination && !s.shadows && !s.reflection && !s.transparency && !s.glints);
        let s = plan(&matte, &[LIGHT], &[FLOOR, BALL]).stages();
        assert!(s.illumination && s.shadows && !s.filtered_shadows && !s.reflection);
        // One object cannot shadow itself.
        assert!(!plan(&matte, &[LIGHT], &[BALL]).stages().shadows);
        let glass = [MaterialDef::new("m")
            .diffuse([1.0; 3])
            .transparency(0.5)
            .specular(0.2)];
        let s = plan(&glass, &[LIGHT], &[FLOOR, BALL]).stages();
        assert!(
            s.transparency && s.filtered_shadows && s.reflection && !s.glints,
            "{s:?}"
        );
        let shiny = [MaterialDef::new("m").shininess(8.0)];
        assert!(plan(&shiny, &[LIGHT], &[BALL]).stages().glints);
        // A mirror material nobody uses needs no reflection rays.
        let unused = [
            MaterialDef::new("m"),
            MaterialDef::new("mirror").specular(1.0),
        ];
        assert!(!plan(&unused, &[LIGHT], &[BALL]).stages().reflection);
    }

    #[test]
    fn objects_wholly_in_front_of_the_image_plane_are_dropped() {
        let m = [MaterialDef::new("m")];
        let near = ObjectDef::sphere("n", "m", [4.0, 3.0, 2.0], 1.0);
        let poking = ObjectDef::sphere("p", "m", [4.0, 3.0, 0.5], 1.0);
        let front = ObjectDef::plane("w", "m", [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]);
        let p = plan(&m, &[], &[near, poking, front, BALL]);
        assert_eq!(p.kept(), &[1, 3]);
    }

    #[test]
    fn spans_are_tight_for_a_ball_and_the_horizon() {
        let m = [MaterialDef::new("m")];
        let p = plan(&m, &[], &[FLOOR, BALL]);
        let [floor, ball] = [p.spans()[0], p.spans()[1]];
        // The floor is below the eye (y = 3): the rows below the horizon at screen height 3
        // (row 29.5 of 0..59), one more for the margin.
        assert_eq!((floor.first, floor.last), (0, 31));
        // The ball (radius 1 at distance 10 from the eye, centred on the eye's height) spans
        // 2 * 6 / sqrt(99) = 1.206 world units on the screen: rows 23.5 to 35.5, widened.
        assert!(ball.first >= 21 && ball.first <= 23, "{ball:?}");
        assert!(ball.last >= 36 && ball.last <= 38, "{ball:?}");
        assert_eq!(p.objects_in_row(5).as_slice(), &[0]);
        assert_eq!(p.objects_in_row(30).as_slice(), &[0, 1]);
        assert_eq!(p.objects_in_row(50).as_slice(), &[] as &[u16]);
        assert_eq!(ball.rows(60), ball.last - ball.first + 1);
        assert_eq!(RowSpan::NONE.rows(60), 0);
        assert_eq!(RowSpan::ALL.rows(60), 60);
    }
    /// The angle between a primary ray of type `S` and the exact ray from the same (rounded)
    /// eye through its pixel's point, the largest over every pixel of a camera.
    #[cfg(feature = "animate")]
    fn largest_turn<S: Scalar>(camera: &CameraDef<'_>) -> f64 {
        let scene: Scene<'_, S, 1, 1, 1, 0, 1024> =
            Scene::from_defs(camera, &[], &[], &[], &[]).unwrap();
        let camera = scene.camera();
        let eye = camera.viewpoint().to_f64();
        let [wx, wy] = camera.world().map(|w| w.to_f64());
        let (w, h) = (camera.width(), camera.height());
        let mut largest: f64 = 0.0;
        for y in 0..h {
            for (x, ray) in camera.row_rays(y, 0).enumerate() {
                let Some(ray) = ray else { continue };
                let point = Vec3::new(
                    wx * x as f64 / f64::from(w - 1),
                    wy * f64::from(y) / f64::from(h - 1),
                    0.0,
                );
                let (exact, traced) = (point - eye, ray.dir.to_f64());
                let sin = exact.cross(traced).length() / (exact.length() * traced.length());
                largest = largest.max(sin);
            }
        }
        largest
    }

    /// The region's margin ([`region_angle`]) stays well above the direction error of every
    /// number type's primary rays: measured over whole screens of cameras near, far, wide
    /// and off-centre, up to 1024 pixels wide.
    #[cfg(feature = "animate")]
    #[test]
    fn primary_rays_turn_far_less_than_the_region_margin() {
        let cameras = [
            CameraDef::new("c", [160, 120], [8.0, 6.0], [4.0, 3.0, 6.0]),
            CameraDef::new("c", [320, 240], [8.0, 6.0], [-20.0, 40.0, 3.0]),
            CameraDef::new("c", [1024, 768], [8.0, 6.0], [4.0, 3.0, 0.2]),
            CameraDef::new("c", [241, 181], [400.0, 300.0], [200.0, 150.0, 900.0]),
            CameraDef::new("c", [640, 480], [8.0, 6.0], [4.0, 3.0, 30.0]),
            CameraDef::new("c", [320, 240], [8.0, 6.0], [4.0, 3.0, 0.02]),
        ];
        let angle = |def: &CameraDef<'_>, fixed: bool| {
            let scene: Scene<'_, f32, 1, 1, 1, 0, 1024> =
                Scene::from_defs(def, &[], &[], &[], &[]).unwrap();
            let fixed_scene: Scene<'_, crate::scalar::I16F16, 1, 1, 1, 0, 1024> =
                Scene::from_defs(def, &[], &[], &[], &[]).unwrap();
            if fixed {
                region_angle(fixed_scene.camera())
            } else {
                region_angle(scene.camera())
            }
        };
        for camera in &cameras {
            let (f32_turn, fixed_turn) = (
                largest_turn::<f32>(camera),
                largest_turn::<crate::scalar::I16F16>(camera),
            );
            // Q16.16's turn is one step of 2^-16 over the eye's distance from the screen
            // (1e-4 from 0.2 away); f32's its precision at the screen's reach over it.
            let (fixed_angle, f32_angle) = (angle(camera, true), angle(camera, false));
            assert!(
                fixed_turn < geometry::to_f64(fixed_angle) / 4.0,
                "{camera:?}: Q16.16 turns by {fixed_turn:e}"
            );
            assert!(
                f32_turn < geometry::to_f64(f32_angle) / 4.0,
                "{camera:?}: f32 turns by {f32_turn:e}"
            );
        }
    }
}
