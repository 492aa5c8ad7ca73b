//! What can block each light's shadow rays, worked out once a render (feature `batch`,
//! `f64`), so that the tests a shadow ray could not pass are not cast.
//!
//! **Planes.** A plane (plain, tiled or finite: their tests start with their plane's)
//! blocks the way from a hit point `P` to a light `L` only if the two lie on opposite sides
//! of it. "Clearly" on one side: farther from the plane than `2^-40 s`, where `s =
//! |N.point| + |L|_1 + |P|_1` is the size of the coordinates involved. With `u = 2^-53`,
//! each value the shadow test works out (the way `L - P`, its length, the unit direction
//! `l`, `N . l`, and the numerator `N.point - N.P`) is within `11 u s` of its exact value,
//! and so is the side test's own. The exact test puts the plane behind `P` or beyond `L`;
//! with both at `2^-40 s` or more from it, the rounded parameter stays behind `P` (a sign
//! that differs) or at `L`'s distance or beyond (`q >= limit`), with room 2^13 / 15 times
//! what the roundings take: the same answer as the test's, bit for bit.
//!
//! - **Lists.** Every shadow ray starts on an object a ray can meet (a render plan's kept
//!   objects), and the filtered walk's later starts lie between `P` and `L`. Where the
//!   light and every other kept object's box lie clearly on one side of a plane, the plane
//!   blocks none of that light's shadow rays, and its list leaves it out (translucent3: the
//!   back wall, for both lights; a walk over the one object left is one test).
//! - **Side tests.** Otherwise a plane is tested lane by lane: a hit point clearly on the
//!   light's side of it needs no test of it (tplane4, spec0; spec3's walls). A finite
//!   plane's side test is made only where another object can lie on the light's side of
//!   it (translucent3's wall lies wholly behind its pane).
//!
//! **Spheres.** A sphere blocks the way from `P` to `L` only if `P` lies in the cone from
//! `L` that holds the sphere. The cone is widened by `2^-20` in the sine of its half-angle:
//! outside it, the line from `P` to `L` passes the centre at `r + 2^-20 |C - L|` or more,
//! while the sphere test's perpendicular distance is off by a few units in the last place
//! of `|P - C|`, which the test keeps below `2^20 |C - L|` (`|P - C| <= |P - L| + |C -
//! L|`). The test's discriminant is then negative, as it is exactly (shiny3: the floor's
//! lanes outside the ball's shadow). The coordinates' size must stay within `2^20 |C - L|`
//! too (each difference the test takes rounds by `u` of it).
//!
//! **Finite planes** get the cone of the sphere that holds them (fplane3's panels,
//! translucent3's pane), where it is narrower than 45 degrees (a wider one clears few
//! lanes: spec3's walls), and trusted closer: the rectangle test finds the plane's crossing
//! `t = num / (N . l)` and reads its coordinates, which are off by about `u s / |N . l|`
//! (`s` the coordinates' size). With `|N . l| >= 2^-6` (else the lane is not cleared) and
//! `s` within a few `2^12 |C - L|`, that is a few `2^-35 |C - L|`, far inside the cone's
//! margin.
//!
//! Where a light's blockers are planes, spheres and at most one other object, a lane for
//! which every blocker but its own object is cleared casts no shadow ray and walks through
//! no transparent object ([`Clearing::clear`], in `illuminate`, where the way to the light
//! is already worked out). The tests below try the shadow test itself wherever a list
//! leaves a plane out or the clearing says clear, with points and lights down to `2^-60`
//! from the planes and the cones' edges; the side test and the sphere's cone fail without
//! their margins, the rectangle's with a bounding sphere 10 % short.

use crate::bvh::bounds;
use crate::light::Light;
use crate::object::fplane::Rect;
use crate::object::plane::Plane;
use crate::object::{Object, Shape};
use crate::scalar::Scalar;
use crate::vec3::Vec3;

/// The most lights with lists of their own (the others test every kept object).
pub(crate) const MAX_LIGHTS: usize = 4;

/// The longest list kept: a light whose blockers are more tests every kept object.
pub(crate) const MAX_BLOCKERS: usize = 8;

/// `2^-40`, the side test's relative margin.
const MARGIN: f64 = 1.0 / 1_099_511_627_776.0;

/// The most spheres a light's cones hold.
pub(crate) const MAX_CONES: usize = 4;

/// The most infinite planes, and the most finite planes, a light's clearing tests.
const MAX_SIDES: usize = 2;

/// `2^-20`: how much a sphere's cone is widened, in the sine of its half-angle.
const CONE_MARGIN: f64 = 1.0 / 1_048_576.0;

/// `2^20`: how far from the light, in units of its distance from a sphere's centre, a
/// cone's answer is trusted.
const CONE_REACH: f64 = 1_048_576.0;

/// `2^12`: as [`CONE_REACH`] for a rectangle's cone, whose test loses more to roundings.
const RECT_REACH: f64 = 4096.0;

/// `cos 45°`: a finite plane's cone must be narrower.
const NARROW_COS: f64 = core::f64::consts::FRAC_1_SQRT_2;

/// `2^-6`: the least `|N . l|` for which a rectangle's cone is trusted (a ray nearly
/// along the rectangle's plane finds the plane's crossing with a large error).
const GRAZING: f64 = 1.0 / 64.0;

/// Each light's list of the kept objects that can block it, in increasing index order,
/// and what clears its lanes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightBlockers {
    lists: [[u16; MAX_BLOCKERS]; MAX_LIGHTS],
    /// Each list's length; `None` for a light that tests every kept object.
    counts: [Option<u8>; MAX_LIGHTS],
    clearing: [Option<Clearing>; MAX_LIGHTS],
}

/// What clears a lane of a light's shadow test: its blockers' cones, where they are
/// spheres, and sides, where they are infinite planes; at most one blocker with neither.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Clearing {
    /// The blocker with neither: lanes on it skip it (their own shadow rays do), the
    /// others' need its shadow test.
    other: Option<usize>,
    /// The spheres: how many, and their indices.
    count: usize,
    index: [usize; MAX_CONES],
    /// The unit way from the light to each sphere's centre.
    axis: [[f64; 3]; MAX_CONES],
    /// The cosine of each widened cone's half-angle.
    cos: [f64; MAX_CONES],
    /// The distance from the light within which the cones and sides are trusted.
    reach: f64,
    /// The planes' indices and sides.
    planes: [Option<(usize, Side)>; MAX_SIDES],
    /// The finite planes' indices and cones, and whether there is one.
    rects: [Option<(usize, RectCone)>; MAX_SIDES],
    any_rects: bool,
    /// The one finite plane, where it is the only blocker (translucent3's pane): its
    /// light's loop copy tests it alone (`LightKind::PlainBehindOne`). A copy of the first
    /// of `rects`, read without a check of the others (as a flag beside `rects`,
    /// translucent3 +1.7 %).
    only_rect: Option<(usize, RectCone)>,
}

/// A finite plane seen from a light: the cone from the light that holds its bounding
/// sphere, widened as a sphere's, and its plane's side, where each can clear lanes.
#[derive(Clone, Copy, Debug)]
struct RectCone {
    axis: [f64; 3],
    /// The cosine of the cone's half-angle; -2 for no cone (no lane is outside it).
    cos: f64,
    /// The rectangle's unit normal.
    normal: [f64; 3],
    side: Option<Side>,
}

impl RectCone {
    /// Whether the way `l` from `point` to the light (`distance` long) lies clearly outside
    /// the cone and not along the plane, or `point` clearly on the light's side of the plane.
    #[inline(always)]
    fn clear(&self, point: Vec3<f64>, l: Vec3<f64>, distance: f64) -> bool {
        let [x, y, z] = self.axis;
        let [nx, ny, nz] = self.normal;
        let across = l.x * nx + l.y * ny + l.z * nz;
        (-(l.x * x + l.y * y + l.z * z) < self.cos && !(across.abs() < GRAZING))
            || self.side.is_some_and(|side| side.clear(point, distance))
    }
}

/// A plane seen from a light: its normal and `N.point` turned so that the light's side is
/// the positive one, and the margin as a function of the lane's distance to the light.
#[derive(Clone, Copy, Debug)]
struct Side {
    normal: [f64; 3],
    n_dot_point: f64,
    /// The margin `2^-40 s` bounded by `base + per_distance d`: with `d` the distance from
    /// the point to the light, `|P|_1 <= |L|_1 + sqrt 3 d` (one product for the three
    /// absolute values and sums).
    base: f64,
    per_distance: f64,
    /// The distance from the light within which the light itself is clearly off the plane.
    reach: f64,
}

impl Side {
    fn new(plane: (Vec3<f64>, f64), light: Vec3<f64>) -> Self {
        let (normal, n_dot_point) = plane;
        let light_side = n_dot_point - normal.dot(light);
        let turn = if light_side < 0.0 { -1.0 } else { 1.0 };
        let base = (n_dot_point.abs() + 2.0 * norm_1(light)) * MARGIN;
        // sqrt 3, rounded up.
        let per_distance = 1.732_051 * MARGIN;
        Self {
            normal: [normal.x * turn, normal.y * turn, normal.z * turn],
            n_dot_point: n_dot_point * turn,
            base,
            per_distance,
            // Where `|N.L - N.point| > base + per_distance d`.
            reach: (light_side.abs() - base) / per_distance,
        }
    }

    /// Whether `point`, `distance` from the light (within [`reach`](Self::reach)), and the
    /// light lie clearly on one side of the plane (see the module's documentation).
    #[inline(always)]
    fn clear(&self, p: Vec3<f64>, distance: f64) -> bool {
        let margin = self.base + self.per_distance * distance;
        let [nx, ny, nz] = self.normal;
        self.n_dot_point - (p.x * nx + p.y * ny + p.z * nz) > margin
    }
}

impl Clearing {
    /// The cones and sides of `blockers` seen from a light at `light`; `None` where two
    /// blockers have neither, there are more than the capacities, or a sphere holds the
    /// light (or nearly).
    fn new<S: Scalar>(
        objects: &[Object<S>],
        kept: &[u16],
        blockers: &[u16],
        light: Vec3<f64>,
    ) -> Option<Self> {
        let mut clearing = Self {
            other: None,
            count: 0,
            index: [0; MAX_CONES],
            axis: [[0.0; 3]; MAX_CONES],
            cos: [0.0; MAX_CONES],
            reach: f64::INFINITY,
            planes: [None; MAX_SIDES],
            rects: [None; MAX_SIDES],
            any_rects: false,
            only_rect: None,
        };
        for &number in blockers {
            let index = usize::from(number);
            let object = objects.get(index)?;
            // Infinite planes: their sides (a finite plane's follows).
            if let Some(plane) = object.infinite_plane().map(plane_f64) {
                let side = Side::new(plane, light);
                clearing.reach = clearing.reach.min(side.reach);
                *clearing.planes.iter_mut().find(|p| p.is_none())? = Some((index, side));
                continue;
            }
            // A finite plane's cone where it is narrow (a wide one clears few lanes: spec3's
            // walls); else it is the blocker with neither.
            if let Some((cone, reach)) = rect_cone(objects, kept, number, light) {
                *clearing.rects.iter_mut().find(|r| r.is_none())? = Some((index, cone));
                clearing.any_rects = true;
                clearing.reach = clearing.reach.min(reach);
                continue;
            }
            let Shape::Sphere(sphere) = object.shape() else {
                if clearing.other.replace(index).is_some() {
                    return None;
                }
                continue;
            };
            let center = sphere.center.to_f64();
            let (axis, cos, d) = cone(center, sphere.radius.to_f64(), light)?;
            if !(norm_1(center) + norm_1(light) < d * CONE_REACH) {
                return None;
            }
            let k = clearing.count;
            *clearing.index.get_mut(k)? = index;
            *clearing.axis.get_mut(k)? = axis;
            *clearing.cos.get_mut(k)? = cos;
            clearing.reach = clearing.reach.min(d * CONE_REACH);
            clearing.count = k + 1;
        }
        if let ([Some(rect), None], [None, None], 0, None) = (
            clearing.rects,
            clearing.planes,
            clearing.count,
            clearing.other,
        ) {
            clearing.only_rect = Some(rect);
        }
        Some(clearing)
    }

    /// Whether no blocker can stop the shadow ray from `point`, a lane's hit on object
    /// `own`, whose unit way to the light is `l`, `distance` long (as `illuminate` works
    /// them out; `l` is within a few units in the last place of the exact way, far inside
    /// the cones' margin).
    #[inline(always)]
    pub(crate) fn clear(&self, point: Vec3<f64>, l: Vec3<f64>, distance: f64, own: usize) -> bool {
        if !(distance < self.reach) {
            return false;
        }
        if self.other.is_some_and(|other| other != own) {
            return false;
        }
        // Each plane written out (as a loop, +3 % on shiny3).
        let [first, second] = &self.planes;
        if let Some((index, side)) = first
            && *index != own
            && !side.clear(point, distance)
        {
            return false;
        }
        if let Some((index, side)) = second
            && *index != own
            && !side.clear(point, distance)
        {
            return false;
        }
        // One test for the scenes without finite planes.
        if self.any_rects {
            let [first, second] = &self.rects;
            if let Some((index, cone)) = first
                && *index != own
                && !cone.clear(point, l, distance)
            {
                return false;
            }
            if let Some((index, cone)) = second
                && *index != own
                && !cone.clear(point, l, distance)
            {
                return false;
            }
        }
        // A plain loop: as iterator adapters the compiler left it out of line.
        for k in 0..MAX_CONES {
            if k >= self.count {
                break;
            }
            let (Some(&index), Some(&[x, y, z]), Some(&cos)) =
                (self.index.get(k), self.axis.get(k), self.cos.get(k))
            else {
                return false;
            };
            // The cosine of the angle between the way from the light and the axis.
            let along = -(l.x * x + l.y * y + l.z * z);
            if index != own && !(along < cos) {
                return false;
            }
        }
        true
    }
}

impl Clearing {
    /// Whether the clearing is one finite plane's alone.
    pub(crate) fn only_rect(&self) -> bool {
        self.only_rect.is_some()
    }

    /// [`clear`](Self::clear) for a clearing of one finite plane alone (see
    /// [`only_rect`](Self::only_rect)), without the other blockers' checks.
    #[inline(always)]
    pub(crate) fn clear_only_rect(
        &self,
        point: Vec3<f64>,
        l: Vec3<f64>,
        distance: f64,
        own: usize,
    ) -> bool {
        match &self.only_rect {
            Some((index, cone)) => {
                distance < self.reach && (*index == own || cone.clear(point, l, distance))
            }
            None => self.clear(point, l, distance, own),
        }
    }
}

impl LightBlockers {
    /// The lists of `lights` among the `kept` objects; `None` when no light leaves an
    /// object out (or the number type is not `f64`, whose margin this is).
    pub(crate) fn new<S: Scalar>(
        objects: &[Object<S>],
        kept: &[u16],
        lights: &[Light<S>],
    ) -> Option<Self> {
        if !S::COURSE_ORDER {
            return None;
        }
        let mut blockers = Self {
            lists: [[0; MAX_BLOCKERS]; MAX_LIGHTS],
            counts: [None; MAX_LIGHTS],
            clearing: [None; MAX_LIGHTS],
        };
        let mut any = false;
        let slots = blockers.lists.iter_mut().zip(&mut blockers.counts);
        for (((list, count), clearing), light) in slots.zip(&mut blockers.clearing).zip(lights) {
            let location = light.location.to_f64();
            let mut length = 0;
            for &index in kept {
                if never_blocks(objects, kept, index, location) {
                    continue;
                }
                // Too many: this light tests them all.
                let Some(slot) = list.get_mut(length) else {
                    length = usize::MAX;
                    break;
                };
                *slot = index;
                length += 1;
            }
            if length < kept.len() {
                *count = u8::try_from(length).ok();
                any = true;
            }
            let blocking = list.get(..length).unwrap_or(kept);
            *clearing = Clearing::new(objects, kept, blocking, location);
            any |= clearing.is_some();
        }
        any.then_some(blockers)
    }

    /// The objects that can block light `n`, if it has a list.
    #[inline(always)]
    pub(crate) fn of(&self, n: usize) -> Option<&[u16]> {
        let count = usize::from((*self.counts.get(n)?)?);
        self.lists.get(n)?.get(..count)
    }

    /// What clears light `n`'s lanes, if it has it.
    #[inline(always)]
    pub(crate) fn clearing(&self, n: usize) -> Option<&Clearing> {
        self.clearing.get(n)?.as_ref()
    }
}

/// Whether object `index`, a plane, blocks no shadow ray to a light at `light`: the light
/// and every other kept object lie clearly on one side of it.
fn never_blocks<S: Scalar>(
    objects: &[Object<S>],
    kept: &[u16],
    index: u16,
    light: Vec3<f64>,
) -> bool {
    let Some(plane) = objects.get(usize::from(index)).and_then(plane_of) else {
        return false;
    };
    let (normal, n_dot_point) = plane;
    let size = |p: Vec3<f64>| n_dot_point.abs() + norm_1(light) + norm_1(p);
    let light_side = n_dot_point - normal.dot(light);
    if !(light_side.abs() > size(light) * MARGIN) {
        return false;
    }
    kept.iter().filter(|&&other| other != index).all(|&other| {
        let Some((low, high)) = objects.get(usize::from(other)).and_then(bounds) else {
            return false;
        };
        corners(low, high).iter().all(|&corner| {
            let side = n_dot_point - normal.dot(corner);
            // The same sign as the light's, clearly.
            side * light_side.signum() > size(corner) * MARGIN
        })
    })
}

/// Whether the side test of plane `plane` (object `index`'s) can clear a lane: whether
/// another kept object may have points on the light's side of it (a choice of speed, not
/// of the answer: translucent3's back wall lies wholly behind its pane).
fn side_can_clear<S: Scalar>(
    objects: &[Object<S>],
    kept: &[u16],
    index: u16,
    (normal, n_dot_point): (Vec3<f64>, f64),
    light: Vec3<f64>,
) -> bool {
    let light_side = n_dot_point - normal.dot(light);
    let on_light_side = |p: Vec3<f64>| (n_dot_point - normal.dot(p)) * light_side > 0.0;
    kept.iter().filter(|&&other| other != index).any(|&other| {
        let Some(object) = objects.get(usize::from(other)) else {
            return false;
        };
        if let Some((low, high)) = bounds(object) {
            return corners(low, high).into_iter().any(on_light_side);
        }
        // An infinite plane parallel to this one lies on one side of it.
        match object.infinite_plane().map(plane_f64) {
            Some((m, m_dot_point)) => {
                let along = m.dot(normal);
                if along.abs() == 1.0 {
                    on_light_side(normal * (m_dot_point * along))
                } else {
                    true
                }
            }
            None => true,
        }
    })
}

/// The unit way from `light` to a sphere's centre, the cosine of the widened half-angle
/// of the cone from `light` that holds it, and the distance to the centre; `None` where
/// the cone is too wide (the light in the sphere or near it).
fn cone(center: Vec3<f64>, radius: f64, light: Vec3<f64>) -> Option<([f64; 3], f64, f64)> {
    let to_center = center - light;
    let d = to_center.length();
    let sin = radius / d + CONE_MARGIN;
    if !(sin < 0.99) {
        return None;
    }
    let axis = to_center / d;
    Some(([axis.x, axis.y, axis.z], libm::sqrt(1.0 - sin * sin), d))
}

/// A finite plane (object `index`) seen from a light at `light`, and the distance within
/// which its cone is trusted: its cone where the half-angle is below 45 degrees (a wider
/// one clears few lanes) and the coordinates' size within `2^12` times the distance to its
/// centre (see the module's documentation); its side where another kept object can lie on
/// the light's side. `None` where it has neither.
fn rect_cone<S: Scalar>(
    objects: &[Object<S>],
    kept: &[u16],
    index: u16,
    light: Vec3<f64>,
) -> Option<(RectCone, f64)> {
    let object = objects.get(usize::from(index))?;
    let Shape::FPlane(rect) = object.shape() else {
        return None;
    };
    let plane = plane_of(object)?;
    let side = side_can_clear(objects, kept, index, plane, light).then(|| Side::new(plane, light));
    let (center, radius) = bounding_sphere(rect);
    let n = rect.plane.unit_normal.to_f64();
    let mut rect_cone = RectCone {
        axis: [0.0; 3],
        cos: -2.0,
        normal: [n.x, n.y, n.z],
        side,
    };
    let mut reach = side.map_or(f64::INFINITY, |side| side.reach);
    if let Some((axis, cos, d)) = cone(center, radius, light)
        && cos > NARROW_COS
        && norm_1(center) + norm_1(light) < d * RECT_REACH
    {
        (rect_cone.axis, rect_cone.cos) = (axis, cos);
        reach = reach.min(d * RECT_REACH);
    }
    (rect_cone.cos > -2.0 || side.is_some()).then_some((rect_cone, reach))
}

/// The centre and radius of a sphere that holds a rectangle, in `f64`.
fn bounding_sphere<S: Scalar>(rect: &Rect<S>) -> (Vec3<f64>, f64) {
    let [corner, across, up] = rect.corner_and_sides();
    let center = corner + (across + up) * 0.5;
    // A hair wider than half the diagonal: the rounding of the centre.
    (center, (across + up).length() * 0.5 * (1.0 + 1e-12))
}

/// The unit normal and `N.point` of a kind whose test misses wherever its plane's does.
fn plane_of<S: Scalar>(object: &Object<S>) -> Option<(Vec3<f64>, f64)> {
    let plane = match object.shape() {
        Shape::FPlane(rect) => &rect.plane,
        _ => object.infinite_plane()?,
    };
    Some(plane_f64(plane))
}

/// A plane's unit normal and `N.point` in `f64`.
fn plane_f64<S: Scalar>(plane: &Plane<S>) -> (Vec3<f64>, f64) {
    (plane.unit_normal.to_f64(), plane.n_dot_point.to_f64())
}

fn norm_1(v: Vec3<f64>) -> f64 {
    v.x.abs() + v.y.abs() + v.z.abs()
}

/// The eight corners of a box.
fn corners(low: Vec3<f64>, high: Vec3<f64>) -> [Vec3<f64>; 8] {
    core::array::from_fn(|k| {
        Vec3::new(
            if k & 1 == 0 { low.x } else { high.x },
            if k & 2 == 0 { low.y } else { high.y },
            if k & 4 == 0 { low.z } else { high.z },
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::fplane::{RectDef, fplane_init};
    use crate::object::plane::{PlaneDef, plane_init};
    use crate::object::sphere::{SphereDef, sphere_init};
    use crate::object::tiled_plane::tiled_plane_init;
    use crate::ray::Ray;
    use proptest::prelude::*;

    fn v(a: [f64; 3]) -> Vec3<f64> {
        Vec3::new(a[0], a[1], a[2])
    }

    /// The course's shadow test from `point` to `light` against `object`, as `illuminate`
    /// casts it; with the unit way and distance it worked out.
    fn shadow(point: Vec3<f64>, light: Vec3<f64>) -> Option<(Ray<f64>, f64)> {
        let to_light = light - point;
        let distance = to_light.length();
        (distance > 0.0).then(|| (Ray::with_length(point, to_light / distance, 1.0), distance))
    }

    fn blocks(object: &Object<f64>, point: Vec3<f64>, light: Vec3<f64>) -> bool {
        shadow(point, light).is_some_and(|(ray, distance)| object.hits(&ray, distance).is_some())
    }

    fn plane(normal: [f64; 3], point: [f64; 3]) -> Object<f64> {
        plane_init("p", 0, &PlaneDef { normal, point }, 1.0).unwrap()
    }

    fn ball(center: [f64; 3], radius: f64) -> Object<f64> {
        sphere_init("s", 0, &SphereDef { center, radius }, 1.0).unwrap()
    }

    #[test]
    fn the_back_wall_never_blocks_and_the_pane_does() {
        // translucent3: a wall at z = -8, a pane at z = -5, lights in front.
        let objects = [
            plane([0.0, 0.0, 1.0], [0.0, 0.0, -8.0]),
            fplane_init(
                "f",
                0,
                &RectDef::new(
                    [0.0, 0.0, 1.0],
                    [2.0, 1.5, -5.0],
                    [1.0, 0.0, 0.0],
                    [4.0, 3.0],
                ),
                1.0,
            )
            .unwrap(),
        ];
        let light = v([0.0, 3.0, 3.0]);
        assert!(never_blocks(&objects, &[0, 1], 0, light));
        assert!(!never_blocks(&objects, &[0, 1], 1, light));
        // A light between the two: the wall still never blocks. The pane would not either
        // (the light is on the wall's side of it), but an infinite plane has no box to
        // show that, and the pane is kept.
        assert!(never_blocks(&objects, &[0, 1], 0, v([4.0, 3.0, -6.0])));
        assert!(!never_blocks(&objects, &[0, 1], 1, v([4.0, 3.0, -6.0])));
        // A light behind the wall: the wall blocks the pane's shadow rays.
        assert!(!never_blocks(&objects, &[0, 1], 0, v([0.0, 3.0, -9.0])));
    }

    #[test]
    fn a_ball_on_the_floor_clears_the_floor_outside_its_shadow() {
        // shiny3: a ball of radius 4 touching the floor y = -1.
        let objects = [
            ball([4.0, 3.0, -6.0], 4.0),
            plane([0.0, 1.0, 0.0], [0.0, -1.0, 0.0]),
        ];
        let light = v([10.0, 8.0, 4.0]);
        // The floor touches the ball: it stays a blocker, tested lane by lane.
        assert!(!never_blocks(&objects, &[0, 1], 1, light));
        let clearing = Clearing::new(&objects, &[0, 1], &[0, 1], light).unwrap();
        let lane = |p: [f64; 3], own| {
            let (ray, distance) = shadow(v(p), light).unwrap();
            clearing.clear(v(p), ray.dir, distance, own)
        };
        // In front of the ball and behind it (in its shadow).
        assert!(lane([4.0, -1.0, 2.0], 1));
        assert!(!lane([0.0, -1.0, -14.0], 1));
        assert!(blocks(&objects[0], v([0.0, -1.0, -14.0]), light));
        // The ball's own lanes: clearly above the floor, or where it touches it.
        assert!(lane([4.0, 7.0, -6.0], 0));
        assert!(!lane([4.0, -1.0, -6.0], 0));
        assert!(!lane([4.0, -1.0 + 1e-14, -6.0], 0));
        // More spheres than the cones hold: no clearing.
        let balls: Vec<_> = (0..=MAX_CONES)
            .map(|k| ball([k as f64, 3.0, -6.0], 0.1))
            .collect();
        let all: Vec<u16> = (0..=MAX_CONES as u16).collect();
        assert!(Clearing::new(&balls, &all, &all, light).is_none());
    }

    #[test]
    fn the_pane_clears_the_wall_outside_its_cone() {
        // translucent3's pane seen from its left light: the wall behind it keeps no side
        // test (none of its points is on the light's side), the cone clears.
        let wall = plane([0.0, 0.0, 1.0], [0.0, 0.0, -8.0]);
        let rect = RectDef::new(
            [0.0, 0.0, 1.0],
            [2.0, 1.5, -5.0],
            [1.0, 0.0, 0.0],
            [4.0, 3.0],
        );
        let objects = [wall, fplane_init("f", 0, &rect, 1.0).unwrap()];
        let light = v([0.0, 3.0, 3.0]);
        let (cone, _) = rect_cone(&objects, &[0, 1], 1, light).unwrap();
        assert!(cone.side.is_none());
        let clearing = Clearing::new(&objects, &[0, 1], &[1], light).unwrap();
        let lane = |p: [f64; 3]| {
            let (ray, distance) = shadow(v(p), light).unwrap();
            clearing.clear(v(p), ray.dir, distance, 0)
        };
        // Beside the pane's shadow, and in it.
        assert!(lane([-6.0, 3.0, -8.0]));
        assert!(!lane([4.0, 3.0, -8.0]));
        assert!(blocks(&objects[1], v([4.0, 3.0, -8.0]), light));
        // A ball in front of the pane: the side test is kept for its lanes.
        let objects = [
            objects[0].clone(),
            objects[1].clone(),
            ball([4.0, 3.0, -2.0], 0.5),
        ];
        let (cone, _) = rect_cone(&objects, &[0, 1, 2], 1, light).unwrap();
        assert!(cone.side.is_some());
    }

    /// A light and a point seen from it near the edge of the cone that holds a sphere:
    /// the light `distance` radii from the centre towards `toward`, the point `beyond`
    /// times as far from the light, at the cone's half-angle give or take `off 2^exponent`
    /// radians; or, given a plane's normal, on a way from the light nearly along the plane.
    type Way = ([f64; 3], [f64; 3], f64, f64, f64, i32);

    fn ways() -> impl Strategy<Value = Way> {
        (
            prop::array::uniform3(-1.0f64..1.0),
            prop::array::uniform3(-1.0f64..1.0),
            1.1f64..40.0,
            0.05f64..3.0,
            -1.0f64..1.0,
            -60i32..-1,
        )
    }

    fn near_the_edge(
        center: Vec3<f64>,
        radius: f64,
        &(toward, side, distance, beyond, off, exponent): &Way,
        along: Option<Vec3<f64>>,
    ) -> Option<(Vec3<f64>, Vec3<f64>)> {
        let axis = v(toward).unit()?;
        let light = center - axis * (radius * distance);
        let tilt = off * 2f64.powi(exponent);
        let way = match along {
            Some(n) => (v(side) - n * n.dot(v(side))).unit()? + n * tilt,
            None => {
                let e = (v(side) - axis * axis.dot(v(side))).unit()?;
                let angle = libm::asin(1.0 / distance) + tilt;
                axis * libm::cos(angle) + e * libm::sin(angle)
            }
        };
        Some((light, light + way.unit()? * (radius * distance * beyond)))
    }

    /// Wherever the side test says clear, no plane kind's own test blocks the shadow ray.
    fn check_side(normal: [f64; 3], point: [f64; 3], xdir: [f64; 3], p: [f64; 3], light: [f64; 3]) {
        let rect = RectDef::new(normal, point, xdir, [50.0, 40.0]);
        let (Ok(plain), Ok(finite), Ok(tiled)) = (
            plane_init("p", 0, &PlaneDef { normal, point }, 1.0),
            fplane_init("f", 0, &rect, 1.0),
            tiled_plane_init("t", 0, &rect, 1, 1.0),
        ) else {
            return;
        };
        let (p, light) = (v(p), v(light));
        for object in [plain, finite, tiled] {
            let side = Side::new(plane_of(&object).unwrap(), light);
            let distance = (light - p).length();
            if distance < side.reach && side.clear(p, distance) {
                assert!(
                    !blocks(&object, p, light),
                    "{normal:?} {point:?} {p:?} {light:?}"
                );
            }
        }
    }

    proptest! {
        #[test]
        fn clear_sides_are_never_blocked(
            normal in prop::array::uniform3(-3.0f64..3.0),
            axis in 0usize..4,
            point in prop::array::uniform3(-20.0f64..20.0),
            along in prop::array::uniform4(-30.0f64..30.0),
            off in prop::array::uniform2(-1.0f64..1.0),
            exponent in prop::array::uniform2(-60i32..4),
        ) {
            // Axis normals too (their tests read one coordinate).
            let mut normal = normal;
            if axis < 3 {
                normal = [0.0; 3];
                normal[axis] = if off[0] > 0.0 { 1.0 } else { -1.0 };
            }
            let len = v(normal).length();
            prop_assume!(len > 1e-3);
            let n = [normal[0] / len, normal[1] / len, normal[2] / len];
            let t1 = if n[0].abs() < 0.9 { [0.0, -n[2], n[1]] } else { [-n[2], 0.0, n[0]] };
            let t2 = [n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]];
            // The hit point and the light each at a distance from the plane from 2^-60 to
            // 2^4, anywhere along it: near the plane the margin decides (the test's own
            // roundings could find a hit at a tiny `t`, or just short of the light).
            let at = |a: f64, b: f64, d: f64| -> [f64; 3] {
                core::array::from_fn(|k| point[k] + a * t1[k] + b * t2[k] + d * n[k])
            };
            let dp = off[0] * 2f64.powi(exponent[0]);
            let dl = off[1] * 2f64.powi(exponent[1]);
            check_side(normal, point, t1, at(along[0], along[1], dp), at(along[2], along[3], dl));
            // The same side, the other far.
            check_side(normal, point, t1, at(along[0], along[1], dp), at(along[2], along[3], dp.signum() * 9.0));
            check_side(normal, point, t1, at(along[0], along[1], dl.signum() * 9.0), at(along[2], along[3], dl));
        }

        /// Wherever a finite plane's cone clears a lane, the plane's own test misses, down to
        /// `2^-60` radians from the cone's edge, and for ways nearly along the plane.
        #[test]
        fn cleared_lanes_miss_the_rectangle(
            normal in prop::array::uniform3(-1.0f64..1.0),
            corner in prop::array::uniform3(-20.0f64..20.0),
            xdir in prop::array::uniform3(-1.0f64..1.0),
            size in prop::array::uniform2(0.01f64..10.0),
            way in ways(),
            graze in any::<bool>(),
        ) {
            let rect = RectDef::new(normal, corner, xdir, size);
            let Ok(pane) = fplane_init::<f64>("f", 0, &rect, 1.0) else {
                return Ok(());
            };
            let objects = [pane];
            let Shape::FPlane(r) = objects[0].shape() else { unreachable!() };
            let (center, radius) = bounding_sphere(r);
            let n = r.plane.unit_normal;
            let Some((light, p)) = near_the_edge(center, radius, &way, graze.then_some(n)) else {
                return Ok(());
            };
            let Some((cone, reach)) = rect_cone(&objects, &[0], 0, light) else {
                return Ok(());
            };
            prop_assert!(cone.side.is_none());
            let (ray, length) = shadow(p, light).unwrap();
            if length < reach && cone.clear(p, ray.dir, length) {
                prop_assert!(objects[0].hits(&ray, length).is_none());
            }
        }

        /// Wherever a plane is left out of a light's list, it blocks no shadow ray from any
        /// point of the other objects' boxes, even those nearly touching it.
        #[test]
        fn planes_left_out_never_block(
            normal in prop::array::uniform3(-3.0f64..3.0),
            point in prop::array::uniform3(-20.0f64..20.0),
            along in prop::array::uniform3(-30.0f64..30.0),
            radius in 0.01f64..5.0,
            gap in -1.0f64..1.0,
            exponent in -60i32..4,
            light in prop::array::uniform3(-30.0f64..30.0),
            inside in prop::array::uniform3(0.0f64..=1.0),
        ) {
            let n = v(normal);
            prop_assume!(n.length() > 1e-3);
            let n = n / n.length();
            // The ball's box `gap 2^exponent` (either side) from the plane, nearest corner
            // first.
            let reach = radius * (n.x.abs() + n.y.abs() + n.z.abs());
            let off = reach + gap * 2f64.powi(exponent);
            let center = v(point) + v(along) - n * (n.dot(v(along))) + n * off;
            let objects = [plane(normal, point), ball([center.x, center.y, center.z], radius)];
            let light = v(light);
            if never_blocks(&objects, &[0, 1], 0, light) {
                let r = Vec3::new(radius, radius, radius);
                let (low, high) = (center - r, center + r);
                for corner in corners(low, high) {
                    prop_assert!(!blocks(&objects[0], corner, light));
                }
                let p = low + Vec3::new(
                    (high.x - low.x) * inside[0],
                    (high.y - low.y) * inside[1],
                    (high.z - low.z) * inside[2],
                );
                prop_assert!(!blocks(&objects[0], p, light));
            }
        }

        /// Wherever a cone clears a lane, the sphere's own test misses, down to `2^-60`
        /// radians from the cone's edge.
        #[test]
        fn cleared_lanes_miss_the_sphere(
            center in prop::array::uniform3(-20.0f64..20.0),
            radius in 0.001f64..8.0,
            way in ways(),
        ) {
            let Some((light, p)) = near_the_edge(v(center), radius, &way, None) else {
                return Ok(());
            };
            let objects = [ball(center, radius), plane([0.0, 1.0, 0.0], [0.0, -100.0, 0.0])];
            let Some(clearing) = Clearing::new(&objects, &[0, 1], &[0, 1], light) else {
                return Ok(());
            };
            let (ray, length) = shadow(p, light).unwrap();
            if clearing.clear(p, ray.dir, length, 1) {
                prop_assert!(objects[0].hits(&ray, length).is_none());
            }
        }
    }
}
