//! Where each object's shadows can fall on the screen: for each light and each object whose
//! test depends on `x` (a ball, a panel), a box of image rows and columns outside which no
//! primary ray meets a plain plane at a point that object shadows from that light.
//!
//! A point light `L` casts the shadow of a convex object `O` onto a plane `R` as the
//! central projection of `O` from `L` onto `R`: where every vertex `V` of a polytope holding
//! `O` lies nearer `R` than `L` does (`d(V) < d(L)`, distances along `R`'s normal on `L`'s
//! side), the projection `L + d(L) / (d(L) - d(V)) (V - L)` of each vertex lies on `R`, and
//! the shadow lies in their hull (vertices beyond `R` project between `L` and themselves:
//! the part of `O` on `R`'s far side casts nothing a ray from `R` to `L` could meet, and the
//! hull still holds the rest). The primary rays that meet `R` inside that hull are those of
//! the pixels of its outline on screen, worked out as the render plan works out an object's
//! rows and columns ([`View::outline`](super::View)). A plane whose normal has no `x` part is
//! the only kind a row's shading puts at one `t` ([`crate::shade::RowShading`]): such rows
//! test a light's shadow rays pixel by pixel only where one of these boxes holds the pixel,
//! and decide the rest once a row with the objects that ignore `x`.
//!
//! Every bound is conservative: the polytope is the object widened by 256 steps of the
//! type's resolution and 2e-3 of its distance from the light and from the origin (far above
//! the rounding of a shadow ray's test in any type), and the outline widens it again as the
//! plan does. A panel nearly in line with the light (its plane within 1/64 of the light's
//! distance from it), where a shadow ray's crossing of its plane is found with a large
//! error, and a light nearly as far from a receiver as the object is, get the whole screen.
//! `tests/plan.rs` renders random rooms with balls and panels both ways.

use super::{ANGLE_MARGIN, MILLIONTH, RowSpan, View};
use crate::camera::Camera;
use crate::light::Light;
use crate::object::{Object, Shape};
use crate::scalar::Scalar;
use crate::scalar::geometry::{self, Geo};
use crate::vec3::Vec3;
use heapless::Vec;

/// The most objects that depend on `x` a render with boxes may have.
pub const OCCLUDERS: usize = 4;

/// Widening in steps of the type's resolution.
const SHADOW_STEPS: Geo = 256.0;

/// A panel's plane must lie at least this far from the light, relative to the light's
/// distance from its corners.
const GRAZING: Geo = 1.0 / 64.0;

/// How much nearer a receiver than the light every vertex must be, relative to the light's
/// distance from it.
const NEARER: Geo = 1.0 / 1024.0;

/// A box of image rows (`y = 0` the bottom) and columns (`x = 0` the left).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScreenBox {
    /// The rows.
    pub rows: RowSpan,
    /// The columns.
    pub columns: RowSpan,
}

impl ScreenBox {
    /// The whole screen.
    pub const ALL: Self = Self {
        rows: RowSpan::ALL,
        columns: RowSpan::ALL,
    };
}

/// Shadow boxes of the objects that depend on `x`, per light and receiving plane (see the
/// module's docs): where one is missing, that light's shadow rays from that plane are
/// tested pixel by pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowBoxes {
    /// How many objects depend on `x`.
    occluders: u8,
    /// The lights (by their place in the scene's list) and receiving planes (by index)
    /// that have boxes, one for each occluder (all or none), in `boxes` in this order.
    pairs: Vec<Pair, PAIRS, u8>,
    /// The boxes, `occluders` for each pair. Held apart from the pairs (not a light and a
    /// plane beside every box), so that twice as many fit in about the RAM six took
    /// (spec0's on the Cortex-M0 within its limit; the showcase there -17 %).
    boxes: Vec<ScreenBox, BOXES, u8>,
}

/// The most boxes kept (a light's boxes for one plane come all or none).
pub const BOXES: usize = 12;

/// The most lights and planes with boxes.
const PAIRS: usize = 6;

/// A light and a receiving plane that have shadow boxes.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pair {
    light: u8,
    receiver: u8,
}

impl ShadowBoxes {
    /// Whether a scene's kept objects can have boxes: some depend on `x`, all of those are
    /// bounded, and there are at most [`OCCLUDERS`] (checked before [`new`](Self::new), whose
    /// frame is large: RAM on a Cortex-M0).
    pub fn possible<S: Scalar>(objects: &[Object<S>], kept: &[u16]) -> bool {
        let mut occluders = 0;
        for &index in kept {
            match objects.get(usize::from(index)) {
                Some(object) if object.hits_ignore_x() => {}
                Some(object) if bounded(object) => occluders += 1,
                _ => return false,
            }
        }
        occluders > 0 && occluders <= OCCLUDERS
    }

    /// The boxes for a scene's lights and kept objects; `None` where there are none (no
    /// object that depends on `x`, one that is not bounded, or no shadow that is). Out of
    /// line: its arrays of points stay out of the caller's frame (RAM on a Cortex-M0).
    #[inline(never)]
    pub fn new<S: Scalar>(
        camera: &Camera<S>,
        lights: &[Light<S>],
        objects: &[Object<S>],
        kept: &[u16],
    ) -> Option<Self> {
        let mut occluders = Vec::<u16, OCCLUDERS>::new();
        let mut receivers = Vec::<u8, 4>::new();
        for &index in kept {
            let object = objects.get(usize::from(index))?;
            if object.hits_ignore_x() {
                // More planes than that, or past 255: their rows test every pixel.
                if let Ok(index) = u8::try_from(index) {
                    let _ = receivers.push(index);
                }
            } else if bounded(object) {
                occluders.push(index).ok()?;
            } else {
                // An unbounded object that depends on `x` (a plane leaning along x) may
                // shadow any pixel: no box would leave one out.
                return None;
            }
        }
        if occluders.is_empty() {
            return None;
        }
        let rows = View::new(camera, false);
        let columns = View::new(camera, true);
        let resolution = super::resolution(camera);
        let mut pairs = Vec::new();
        let mut boxes = Vec::new();
        // One array of points for every call below, filled in place: returned by value
        // through the calls, its copies were the frame's largest part (RAM on a Cortex-M0).
        let mut points = [Vec3::ZERO; 8];
        // One occluder's shadow is bounded or not as its points are projected: no pass to
        // check it first (soft float).
        let single = occluders.len() == 1;
        for (number, light) in lights.iter().enumerate() {
            let number = u8::try_from(number).ok()?;
            'receivers: for &receiver in &receivers {
                // One shadow that is not bounded, and every pixel tests the light: the
                // others are not worth their outlines (soft float).
                let bounded = single
                    || occluders.iter().all(|&index| {
                        objects.get(usize::from(index)).is_some_and(|object| {
                            shadow_points(
                                light,
                                object,
                                receiver.into(),
                                objects,
                                (false, resolution),
                                &mut points,
                            )
                            .is_some()
                        })
                    });
                if !bounded || boxes.len() + occluders.len() > BOXES || pairs.is_full() {
                    continue;
                }
                for &index in &occluders {
                    let object = objects.get(usize::from(index))?;
                    let projected = shadow_points(
                        light,
                        object,
                        receiver.into(),
                        objects,
                        (true, resolution),
                        &mut points,
                    );
                    match projected {
                        Some(()) => {}
                        None if single => continue 'receivers,
                        None => return None,
                    }
                    let mut screen = ScreenBox {
                        rows: rows.span(rows.outline(&points, resolution)),
                        columns: columns.span(columns.outline(&points, resolution)),
                    };
                    // Every column: no row is cut for it.
                    if screen.columns.first == 0
                        && screen.columns.last >= camera.width().saturating_sub(1)
                    {
                        screen.columns = RowSpan::ALL;
                    }
                    boxes.push(screen).ok()?;
                }
                let pair = Pair {
                    light: number,
                    receiver,
                };
                pairs.push(pair).ok()?;
            }
        }
        let occluders = u8::try_from(occluders.len()).ok()?;
        (!pairs.is_empty()).then_some(Self {
            occluders,
            pairs,
            boxes,
        })
    }

    /// Each pair with its boxes.
    fn entries(&self) -> impl Iterator<Item = (&Pair, &[ScreenBox])> + '_ {
        let each = usize::from(self.occluders).max(1);
        self.pairs.iter().zip(self.boxes.chunks(each))
    }

    /// Light `light`'s boxes on the plane at `receiver`, one per occluder, if it has them
    /// (else none).
    fn boxes_of(&self, light: usize, receiver: usize) -> &[ScreenBox] {
        self.entries()
            .find(|(pair, _)| {
                usize::from(pair.light) == light && usize::from(pair.receiver) == receiver
            })
            .map_or(&[], |(_, boxes)| boxes)
    }

    /// Whether a shadow ray towards light `light` from a primary ray's hit on the plane at
    /// `own`, at row `y`, in columns `first..=last`, may be blocked by an object that
    /// depends on `x`.
    pub fn may_block(&self, light: usize, own: usize, y: u16, first: u16, last: u16) -> bool {
        let boxes = self.boxes_of(light, own);
        for b in boxes {
            if b.rows.contains(y) && b.columns.first <= last && first <= b.columns.last {
                return true;
            }
        }
        boxes.len() < usize::from(self.occluders)
    }

    /// Calls `cut` with the columns where the boxes of row `y` on the plane at `own` start
    /// and end (a box's last column plus one), of the lights whose boxes leave some of the
    /// row's columns out: where the row is cut into segments.
    pub fn cuts(&self, own: usize, y: u16, mut cut: impl FnMut(u16)) {
        for (pair, boxes) in self.entries() {
            if usize::from(pair.receiver) != own {
                continue;
            }
            let whole = boxes
                .iter()
                .any(|b| b.rows.contains(y) && b.columns == RowSpan::ALL);
            for b in boxes.iter().filter(|b| b.rows.contains(y)) {
                if !whole {
                    cut(b.columns.first);
                    cut(b.columns.last.saturating_add(1));
                }
            }
        }
    }
}

/// Into `points`, the projections from `light` onto the plane of `receiver` of the
/// vertices of a polytope holding `object`, widened (computed only when `project`); `None`
/// where the shadow is not bounded that way (see the module's docs); `resolution` as
/// [`super::resolution`] gives it.
fn shadow_points<S: Scalar>(
    light: &Light<S>,
    object: &Object<S>,
    receiver: u16,
    objects: &[Object<S>],
    (project, resolution): (bool, Geo),
    points: &mut [Vec3<Geo>; 8],
) -> Option<()> {
    let l = light.location.to_geo();
    widened_vertices(object, l, resolution, ANGLE_MARGIN, false, points)?;
    let plane = objects.get(usize::from(receiver))?.infinite_plane()?;
    let n = plane.unit_normal.to_geo();
    let offset = plane.n_dot_point.to_geo();
    let above = n.dot(l) - offset;
    let side = if above > 0.0 { 1.0 } else { -1.0 };
    let height = geometry::abs(above);
    for v in points.iter_mut() {
        let d = side * (n.dot(*v) - offset);
        if !(d < height * (1.0 - NEARER)) {
            return None;
        }
        if project {
            *v = l + (*v - l) * (height / (height - d));
        }
    }
    Some(())
}

/// Where on the infinite plane `plane` a shadow ray to a light at `l` can cross the
/// polytope of `vertices` (from [`widened_vertices`]).
#[cfg(feature = "animate")]
pub(crate) enum OnPlane {
    /// Nowhere: the polytope lies beyond the light or beyond the plane.
    Nowhere,
    /// Within the hull of the polytope's projection from the light (written to the
    /// caller's points), when it lies between them (see the module's docs).
    Within,
    /// Anywhere: it reaches past the light's height, or the light is on the plane.
    Anywhere,
}

/// Into `projected`, the projections of `vertices` from `l` onto `plane` where the
/// shadow is bounded that way (see [`OnPlane`]).
#[cfg(feature = "animate")]
pub(crate) fn shadow_on_plane<S: Scalar>(
    l: Vec3<Geo>,
    vertices: &[Vec3<Geo>; 8],
    plane: &crate::object::Plane<S>,
    projected: &mut [Vec3<Geo>; 8],
) -> OnPlane {
    let n = plane.unit_normal.to_geo();
    let offset = plane.n_dot_point.to_geo();
    let above = n.dot(l) - offset;
    let side = if above > 0.0 { 1.0 } else { -1.0 };
    let height = geometry::abs(above);
    if !(height > 0.0) {
        return OnPlane::Anywhere;
    }
    let (mut past_light, mut past_plane, mut between) = (true, true, true);
    for (v, p) in vertices.iter().zip(projected.iter_mut()) {
        let d = side * (n.dot(*v) - offset);
        past_light &= d > height * (1.0 + NEARER);
        past_plane &= d < 0.0;
        between &= d < height * (1.0 - NEARER);
        if between {
            *p = l + (*v - l) * (height / (height - d));
        }
    }
    if past_light || past_plane {
        OnPlane::Nowhere
    } else if between {
        OnPlane::Within
    } else {
        OnPlane::Anywhere
    }
}

/// Whether `object` is of a kind [`widened_vertices`] holds in a polytope.
fn bounded<S: Scalar>(object: &Object<S>) -> bool {
    match object.shape() {
        Shape::Sphere(_) | Shape::FPlane(_) | Shape::TexPlane(_) => true,
        Shape::RevSurf(_) => cfg!(feature = "revsurf"),
        Shape::Plane(_) | Shape::TiledPlane(_) => false,
    }
}

/// Into `vertices`, the vertices of a polytope holding `object` widened by the module's
/// margins, directions by `angle` radians (seen from a light at `l`): a cube about a ball
/// along the axes (or, with `facing_the_light`, an octagon about the cone of its shadow:
/// [`cone_octagon`]), a slab about a panel; `None` for other kinds and for a panel nearly
/// in line with the light.
///
/// `Some(true)` for the octagon (a flat polygon: the shadow is the pyramid beyond it).
pub(crate) fn widened_vertices<S: Scalar>(
    object: &Object<S>,
    l: Vec3<Geo>,
    resolution: Geo,
    angle: Geo,
    facing_the_light: bool,
    vertices: &mut [Vec3<Geo>; 8],
) -> Option<bool> {
    let margin = |points: &[Vec3<Geo>]| shadow_margin(points, l, resolution, angle);
    let (center, r) = match object.shape() {
        Shape::FPlane(rect) => return slab(rect, l, &margin, vertices).map(|()| false),
        Shape::TexPlane(textured) => {
            return slab(&textured.rect, l, &margin, vertices).map(|()| false);
        }
        _ => widened_ball(object, l, resolution, angle)?,
    };
    // With `facing_the_light`, the octagon about the cone of shadow rays that meet the
    // ball, where the cone begins (see `cone_octagon`): its shadow is the ball's within 6 %
    // of its area, where a cube's is up to 1.6 times it (the plan's boxes keep the axis
    // cube: no square roots in soft float on every render).
    if cfg!(feature = "animate") && facing_the_light && cone_octagon(center, r, l, vertices) {
        return Some(true);
    }
    for (i, v) in vertices.iter_mut().enumerate() {
        let sign = |bit: usize| if i & bit == 0 { -r } else { r };
        *v = center + Vec3::new(sign(4), sign(2), sign(1));
    }
    Some(false)
}

/// The ball holding `object` (a ball, or a surface of revolution's bounding ball) widened
/// by the margins of its shadow's bounds from a light at `l` (see the module's docs),
/// directions by `angle` radians: its centre and radius; `None` for other kinds.
pub(crate) fn widened_ball<S: Scalar>(
    object: &Object<S>,
    l: Vec3<Geo>,
    resolution: Geo,
    angle: Geo,
) -> Option<(Vec3<Geo>, Geo)> {
    let (center, radius) = match object.shape() {
        Shape::Sphere(s) => (s.center.to_geo(), s.radius.to_geo()),
        Shape::RevSurf(s) if cfg!(feature = "revsurf") => (s.center.to_geo(), s.bound.to_geo()),
        _ => return None,
    };
    let reach = Vec3::new(radius, radius, radius);
    let m = shadow_margin(&[center - reach, center + reach], l, resolution, angle);
    Some((center, radius + m))
}

/// The margin a shadow's bounds are widened by (narrowed by, for a certain umbra), for an
/// object reaching `points` and a light at `l`, directions by `angle` radians.
fn shadow_margin(points: &[Vec3<Geo>], l: Vec3<Geo>, resolution: Geo, angle: Geo) -> Geo {
    let reach = points
        .iter()
        .map(|&p| norm_1(p - l) + norm_1(p))
        .fold(0.0, Geo::max);
    SHADOW_STEPS * resolution + angle * reach
}

/// The corners of a certain umbra's polygon (see [`certain_umbra`]).
#[cfg(feature = "animate")]
pub(crate) const UMBRA_CORNERS: usize = 16;

/// Into `corners`, in order, a convex polygon on `plane` every point `P` of which is in the
/// ball `object`'s shadow from `l` for certain, as a number type of resolution `resolution`
/// traces it (directions within `angle` radians): the line from `P` to `l` passes within
/// the radius less the margin [`widened_vertices`] adds of the centre; the ball lies
/// between `P` and `l`, at least that margin from the plane (so a shadow ray's root is
/// clearly ahead of `P`) and that margin behind `z_limit` (the z rule drops hits in front
/// of it). The corners lie on the cone from `l` tangent to the shrunk ball, beyond where it
/// touches it, and so inside the shadow's ellipse. `false` where there is none: not a
/// ball, the ball near the plane or beyond it from `l`, or the cone not wholly meeting the
/// plane beyond the ball.
#[cfg(feature = "animate")]
pub(crate) fn certain_umbra<S: Scalar>(
    object: &Object<S>,
    l: Vec3<Geo>,
    (resolution, angle): (Geo, Geo),
    z_limit: Geo,
    plane: &crate::object::Plane<S>,
    corners: &mut [Vec3<Geo>; UMBRA_CORNERS],
) -> bool {
    /// Cosines of 22.5, 45 and 67.5 degrees.
    const C1: Geo = geometry::from_f64(0.923_879_532_511_286_7);
    const C2: Geo = geometry::FRAC_1_SQRT_2;
    const C3: Geo = geometry::from_f64(0.382_683_432_365_089_8);
    const AROUND: [(Geo, Geo); UMBRA_CORNERS] = [
        (1.0, 0.0),
        (C1, C3),
        (C2, C2),
        (C3, C1),
        (0.0, 1.0),
        (-C3, C1),
        (-C2, C2),
        (-C1, C3),
        (-1.0, 0.0),
        (-C1, -C3),
        (-C2, -C2),
        (-C3, -C1),
        (0.0, -1.0),
        (C3, -C1),
        (C2, -C2),
        (C1, -C3),
    ];
    let Shape::Sphere(ball) = object.shape() else {
        return false;
    };
    let (center, radius) = (ball.center.to_geo(), ball.radius.to_geo());
    let reach = Vec3::new(radius, radius, radius);
    let m = shadow_margin(&[center - reach, center + reach], l, resolution, angle);
    let r = radius - m;
    let (n, p0) = (plane.unit_normal.to_geo(), plane.point.to_geo());
    let (above, light_above) = (n.dot(center - p0), n.dot(l - p0));
    // The ball clear of the plane by the margin, on the light's side.
    let clear = radius + m;
    let sides = above > clear && light_above > 0.0 || above < -clear && light_above < 0.0;
    if !(r > 0.0 && sides && center.z + clear < z_limit) {
        return false;
    }
    let Some((distance, [a, u, w])) = cone_axes(l, center, r) else {
        return false;
    };
    // Where the cone touches the shrunk ball: `distance - r^2 / distance` along the axis,
    // a circle of radius `r sqrt(distance^2 - r^2) / distance` (a millionth inside it).
    let along = distance - r * r / distance;
    let across = r * geometry::sqrt(distance * distance - r * r) / distance * (1.0 - MILLIONTH);
    let middle = l + a * along;
    let toward_plane = n.dot(p0 - l);
    for (corner, (x, y)) in corners.iter_mut().zip(AROUND) {
        let q = middle + u * (across * x) + w * (across * y);
        let s = toward_plane / n.dot(q - l);
        // Beyond the touching circle (and so beyond where the line leaves the ball).
        if !(s > 1.0 + geometry::allowance(1e-9, 1e-5) && s.is_finite()) {
            return false;
        }
        *corner = l + (q - l) * s;
    }
    true
}

/// Into `vertices`, a regular octagon about the cross-section of the cone from `l` tangent
/// to the ball `(center, r)`, where the ball begins along the cone's axis: a shadow ray from
/// `P` to `l` meets the ball only if `P` lies in the cone and at least `D - r` along its
/// axis (`D` the centre's distance), where the cone's section is a disc of radius
/// `(D - r) tan a` (`sin a = r / D`). Every such `P` is `l + s (V - l)`, `s >= 1`, for a
/// `V` in the octagon (set a millionth nearer and wider than the rounded values). `false`
/// (nothing written) where `l` is within a thousandth of the ball's radius of it.
pub(crate) fn cone_octagon(
    center: Vec3<Geo>,
    r: Geo,
    l: Vec3<Geo>,
    vertices: &mut [Vec3<Geo>; 8],
) -> bool {
    /// `cos 22.5°` and `sin 22.5°`.
    const C: Geo = geometry::from_f64(0.923_879_532_511_286_7);
    const S: Geo = geometry::from_f64(0.382_683_432_365_089_8);
    let Some((distance, [a, u, w])) = cone_axes(l, center, r) else {
        return false;
    };
    let tan = r / geometry::sqrt(distance * distance - r * r);
    let near = (distance - r) * (1.0 - MILLIONTH);
    // The octagon's corners are `1 / cos 22.5°` out from its inscribed circle.
    let corner = near * tan * (1.0 + MILLIONTH) / C;
    let middle = l + a * near;
    let (c, s) = (corner * C, corner * S);
    let around = [
        (c, s),
        (s, c),
        (-s, c),
        (-c, s),
        (-c, -s),
        (-s, -c),
        (s, -c),
        (c, -s),
    ];
    for (v, (x, y)) in vertices.iter_mut().zip(around) {
        *v = middle + u * x + w * y;
    }
    true
}

/// The distance from `l` to the ball `(center, r)` and three orthogonal unit vectors, the
/// first from `l` towards the centre; `None` where `l` is within a thousandth of the
/// radius of the ball, or the axes fail.
fn cone_axes(l: Vec3<Geo>, center: Vec3<Geo>, r: Geo) -> Option<(Geo, [Vec3<Geo>; 3])> {
    let to = center - l;
    let distance = geometry::sqrt(to.dot(to));
    let axes = facing(to);
    // `facing` gives the axes where its roots fail: then the first may not point at the
    // ball.
    let pointed = axes[0].dot(to) >= distance * (1.0 - geometry::allowance(1e-9, 1e-5));
    (distance > r * 1.001 && pointed && distance.is_finite()).then_some((distance, axes))
}

/// Three orthogonal unit vectors, the first along `d` (the axes when `d` is zero or the
/// roots fail: a cube along them holds the ball as well).
fn facing(d: Vec3<Geo>) -> [Vec3<Geo>; 3] {
    let axes = [
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    ];
    let unit = |v: Vec3<Geo>| {
        let length = geometry::sqrt(v.dot(v));
        (length > 0.0 && length.is_finite()).then(|| v * (1.0 / length))
    };
    let Some(a) = unit(d) else {
        return axes;
    };
    // The axis least along `a` gives the second direction.
    let [ex, ey, ez] = axes;
    let (x, y, z) = (geometry::abs(a.x), geometry::abs(a.y), geometry::abs(a.z));
    let least = if x <= y && x <= z {
        ex
    } else if y <= z {
        ey
    } else {
        ez
    };
    match unit(a.cross(least)) {
        Some(u) => [a, u, a.cross(u)],
        None => axes,
    }
}

/// `|v|_1`, at least `|v|` (without a square root: soft float's are slow).
fn norm_1(v: Vec3<Geo>) -> Geo {
    geometry::abs(v.x) + geometry::abs(v.y) + geometry::abs(v.z)
}

/// Into `vertices`, a panel's corners moved out along its sides and off its plane both
/// ways by the margin.
fn slab<S: Scalar>(
    rect: &crate::object::Rect<S>,
    l: Vec3<Geo>,
    margin: &dyn Fn(&[Vec3<Geo>]) -> Geo,
    vertices: &mut [Vec3<Geo>; 8],
) -> Option<()> {
    let [p, across, up] = rect.corner_and_sides_geo();
    let corners = [p, p + across, p + across + up, p + up];
    let n = rect.plane.unit_normal.to_geo();
    let farthest = corners
        .iter()
        .map(|&c| rough_length(c - l))
        .fold(0.0, Geo::max);
    if !(geometry::abs(n.dot(l - p)) >= GRAZING * farthest) {
        return None;
    }
    let m = margin(&corners);
    let (a, b) = (along(across, m), along(up, m));
    for (i, v) in vertices.iter_mut().enumerate() {
        let corner = corners.get(i % 4).copied().unwrap_or(p);
        // Out of the panel at each corner: `-a - b`, `a - b`, `a + b`, `b - a`.
        let aside = match i % 4 {
            0 => -a - b,
            1 => a - b,
            2 => a + b,
            _ => b - a,
        };
        let off = if i < 4 { n * m } else { n * -m };
        *v = corner + aside + off;
    }
    Some(())
}

/// `|v|` within `2^-23` (see [`sqrt_f64_rough`](crate::scalar::sqrt_f64_rough)): a
/// panel's distances and sides only place margins of `2e-3` and more, and the exact root
/// in software `f64` was 5 of fplane3's instructions a pixel on the Cortex-M4F.
fn rough_length(v: Vec3<Geo>) -> Geo {
    geometry::sqrt_rough(v.dot(v))
}

/// `m` along `v`'s direction (zero for a zero or unbounded `v`).
fn along(v: Vec3<Geo>, m: Geo) -> Vec3<Geo> {
    let length = rough_length(v);
    if length > 0.0 && length.is_finite() {
        v * (m / length)
    } else {
        Vec3::ZERO
    }
}

#[cfg(all(test, feature = "animate"))]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A unit vector across `a`.
    fn across(a: Vec3<f64>) -> Vec3<f64> {
        let axis = if libm::fabs(a.x) < 0.5 {
            Vec3::new(1.0, 0.0, 0.0)
        } else {
            Vec3::new(0.0, 1.0, 0.0)
        };
        let u = a.cross(axis);
        u * (1.0 / u.length())
    }

    fn point() -> impl Strategy<Value = Vec3<f64>> {
        (-50.0..50.0f64, -50.0..50.0f64, -50.0..50.0f64).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    /// Whether `p` is `l + s (V - l)` for some `s >= 1` and `V` in the octagon `vertices`.
    fn in_pyramid(l: Vec3<f64>, vertices: &[Vec3<f64>; 8], p: Vec3<f64>) -> bool {
        let middle = vertices.iter().fold(Vec3::ZERO, |s, &v| s + v) * 0.125;
        let axis = middle - l;
        let (near, along) = (axis.dot(axis), (p - l).dot(axis));
        // Beyond the octagon's plane (a hair of slack for this test's own rounding).
        if along < near * (1.0 - 1e-12) {
            return false;
        }
        let x = l + (p - l) * (near / along);
        // Inside every edge: the crossing on the inner side of each.
        (0..8).all(|i| {
            let (a, b) = (vertices[i], vertices[(i + 1) % 8]);
            let inward = (b - a).cross(middle - a).cross(b - a);
            (x - a).dot(inward) >= -1e-9 * inward.length() * (b - a).length()
        })
    }

    proptest! {
        /// Every point whose segment to the light meets the ball lies in the pyramid the
        /// octagon spans from the light (the octagon's claim), and the octagon is no more
        /// than 9 % wider than the cone's section (it is 8.2 %: a regular octagon's
        /// corners).
        #[test]
        fn the_octagon_holds_every_shadow_ray_that_meets_the_ball(
            l in point(),
            center in point(),
            r in 0.01..10.0f64,
            on_ball in (0.0..1.0f64, 0.0..1.0f64, 0.0..1.0f64),
            s in prop_oneof![Just(1.0f64), 1.0..100.0f64],
        ) {
            let mut octagon = [Vec3::ZERO; 8];
            let (c, light) = (geometry::narrow(center), geometry::narrow(l));
            prop_assume!(cone_octagon(c, geometry::from_f64(r), light, &mut octagon));
            let vertices = octagon.map(geometry::widen);
            // The ball shrunk by `f32`'s rounding where the geometry is `f32` (every caller
            // widens it by at least 2.5e-4 of that reach).
            let full = r;
            let r = r - if geometry::SINGLE { 2e-5 * (center.length() + l.length() + r) } else { 0.0 };
            prop_assume!(r > 0.0);
            // A point of the ball seen beyond: on the circle where the cone touches it (the
            // shadow's edge), or at its nearest point (where the cone begins), or within.
            let (theta, pick, depth) = on_ball;
            let to = center - l;
            let d = to.length();
            let a = to * (1.0 / d);
            let u = across(a);
            let w = a.cross(u);
            let phi = theta * core::f64::consts::TAU;
            let around = u * libm::cos(phi) + w * libm::sin(phi);
            let touch = l + a * (d - r * r / d) + around * (r * libm::sqrt(d * d - r * r) / d);
            let q = if pick < 0.4 {
                touch
            } else if pick < 0.5 {
                center - a * r
            } else {
                center + (touch - center) * depth
            };
            let p = l + (q - l) * s;
            prop_assert!(in_pyramid(l, &vertices, p), "{p:?} outside");
            let middle = vertices.iter().fold(Vec3::ZERO, |s, &v| s + v) * 0.125;
            let (d, near) = ((center - l).length(), (middle - l).length());
            let section = near * full / libm::sqrt(d * d - full * full);
            let corner = (vertices[0] - middle).length();
            prop_assert!(corner <= section * 1.09, "{corner} for a section of {section}");
        }
    }
}
