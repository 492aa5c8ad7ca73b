//! Shadow rays no object can block, found before they are cast (feature `batch`, `f64`).
//!
//! A plane blocks the way from a hit point `P` to a light `L` only if the two lie on
//! opposite sides of it. Where every object of a scene is a plane, and `P` and `L` lie
//! clearly on the same side of each but the one `P` is on, the shadow test would miss them
//! all, and the batch leaves it out (tplane4: every pixel, the tiled plane's test and the
//! walk around it, about 80 instructions, for a side test of about 40). The reasoning
//! holds for finite planes too (their test starts with their plane's; the tests below try
//! them), but [`worth_it`] keeps the side test to scenes of infinite planes, where it pays.
//!
//! "Clearly": farther from the plane than `2^-40 s`, where `s = |N.point| + |L|_1 +
//! |P|_1` is the size of the coordinates involved. With `u = 2^-53`, each value the shadow
//! test works out (the way `L - P`, its length, the unit direction `l`, `N . l`, and the
//! numerator `N.point - N.P`) is within `11 u s` of its exact value, and so is the side
//! test's own. The exact test puts the plane behind `P` or beyond `L` (both on one side);
//! with `L` and `P` at `2^-40 s` or more from the plane (as the side test works them out),
//! the rounded parameter stays behind `P` (a sign that differs) or at `L`'s distance or
//! beyond (`q >= limit`), with room 2^13 / 15 times what the roundings take. So it is the
//! same answer as the test's, bit for bit. The tests below try the test itself wherever the side test says
//! clear, with points and lights down to `2^-60` from the plane; with no margin they fail.

use crate::light::Light;
use crate::object::plane::Plane;
use crate::object::{Object, Shape};
use crate::scalar::Scalar;
use crate::vec3::Vec3;

/// The most planes a scene may have for the side test: a few dot products a pixel,
/// against the shadow test's call for each.
pub(crate) const MAX_PLANES: usize = 4;

/// `2^-40`: how far from a plane, relative to the coordinates' size, a point must be for
/// its side to be certain.
const MARGIN: f64 = 1.0 / 1_099_511_627_776.0;

/// Whether the side test can pay in a scene: its objects are all infinite planes (plain or
/// tiled; a finite plane lets light pass beside it, so hit points often lie beyond it), no
/// more than [`MAX_PLANES`], and one at least leans (a plane on an axis is tested by one
/// coordinate, about as fast as the side test).
pub(crate) fn worth_it<S: Scalar>(objects: &[Object<S>]) -> bool {
    objects.len() <= MAX_PLANES
        && objects.iter().all(|o| infinite_plane(o).is_some())
        && objects
            .iter()
            .any(|o| infinite_plane(o).is_some_and(|p| p.axis.is_none()))
}

/// The most lights the side test is prepared for.
pub(crate) const MAX_LIGHTS: usize = 4;

/// Each light's [`Sides`], worked out once a render.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightSides {
    sides: [Option<Sides>; MAX_LIGHTS],
}

impl LightSides {
    /// The side tests of `lights` among `objects`, where [`worth_it`] says so.
    pub(crate) fn new<S: Scalar>(objects: &[Object<S>], lights: &[Light<S>]) -> Option<Self> {
        if !(S::COURSE_ORDER && lights.len() <= MAX_LIGHTS && worth_it(objects)) {
            return None;
        }
        let mut sides = [None; MAX_LIGHTS];
        for (sides, light) in sides.iter_mut().zip(lights) {
            *sides = Some(Sides::new(objects, light.location)?);
        }
        Some(Self { sides })
    }

    /// The side test of light `n`.
    pub(crate) fn of(&self, n: usize) -> Option<&Sides> {
        self.sides.get(n)?.as_ref()
    }
}

/// A scene's planes seen from one light, in the objects' order (plane `k` is object `k`):
/// each one's normal and `N.point` turned so that the light's side is the positive one.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sides {
    count: usize,
    normal: [[f64; 3]; MAX_PLANES],
    n_dot_point: [f64; MAX_PLANES],
    /// The largest `|N.point| + |L|_1`.
    size: f64,
    /// The light's least distance from a plane, `|N.point - N.L|`.
    nearest: f64,
}

impl Sides {
    /// Every one of `objects` seen from a light at `light` (a shadow ray's set is some of
    /// them: a plane it leaves out is tested here all the same, which only clears fewer
    /// lanes); `None` where they are not all planes or more than [`MAX_PLANES`].
    pub(crate) fn new<S: Scalar>(objects: &[Object<S>], light: Vec3<S>) -> Option<Self> {
        let mut sides = Self {
            count: 0,
            normal: [[0.0; 3]; MAX_PLANES],
            n_dot_point: [0.0; MAX_PLANES],
            size: 0.0,
            nearest: f64::INFINITY,
        };
        let light = light.to_f64();
        let light_size = light.x.abs() + light.y.abs() + light.z.abs();
        for (index, object) in objects.iter().enumerate() {
            let plane = plane_of(object)?;
            let normal = plane.unit_normal.to_f64();
            let n_dot_point = plane.n_dot_point.to_f64();
            let light_side = n_dot_point - normal.dot(light);
            // Turned by a sign: the side test's values change sign only, not magnitude.
            let turn = if light_side < 0.0 { -1.0 } else { 1.0 };
            *sides.normal.get_mut(index)? = [normal.x * turn, normal.y * turn, normal.z * turn];
            *sides.n_dot_point.get_mut(index)? = n_dot_point * turn;
            sides.size = sides.size.max(n_dot_point.abs() + light_size);
            sides.nearest = sides.nearest.min(light_side.abs());
            sides.count += 1;
        }
        Some(sides)
    }

    /// Whether no plane of the set but `own` (the one the point lies on) can block the way
    /// from `point` to the light: each one's side of the point is the light's, clearly.
    #[inline(always)]
    pub(crate) fn clear<S: Scalar>(&self, point: Vec3<S>, own: usize) -> bool {
        let p = point.to_f64();
        let margin = (self.size + (p.x.abs() + p.y.abs() + p.z.abs())) * MARGIN;
        let planes = self.normal.iter().zip(&self.n_dot_point).take(self.count);
        self.nearest > margin
            && planes
                .enumerate()
                .all(|(index, (&[nx, ny, nz], &n_dot_point))| {
                    index == own || n_dot_point - (p.x * nx + p.y * ny + p.z * nz) > margin
                })
    }
}

/// The plane a kind's test starts with, for the kinds whose test misses where its plane's
/// does.
fn plane_of<S: Scalar>(object: &Object<S>) -> Option<&Plane<S>> {
    match object.shape() {
        Shape::FPlane(rect) => Some(&rect.plane),
        _ => infinite_plane(object),
    }
}

/// The plane of an infinite plane, plain or tiled.
fn infinite_plane<S: Scalar>(object: &Object<S>) -> Option<&Plane<S>> {
    match object.shape() {
        Shape::Plane(plane) => Some(plane),
        Shape::TiledPlane(tiled) => Some(&tiled.rect.plane),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::fplane::RectDef;
    use crate::object::plane::{PlaneDef, plane_init};
    use crate::object::{fplane::fplane_init, tiled_plane::tiled_plane_init};
    use crate::ray::Ray;
    use proptest::prelude::*;

    /// The course's shadow test from `point` to `light`, as `illuminate` casts it.
    fn blocked(object: &Object<f64>, point: Vec3<f64>, light: Vec3<f64>) -> bool {
        let to_light = light - point;
        let distance = to_light.length();
        if !(distance > 0.0) {
            return false;
        }
        let shadow = Ray::with_length(point, to_light / distance, 1.0);
        object.hits(&shadow, distance).is_some()
    }

    fn objects(normal: [f64; 3], point: [f64; 3], xdir: [f64; 3]) -> Option<[Object<f64>; 3]> {
        let rect = RectDef::new(normal, point, xdir, [50.0, 40.0]);
        Some([
            plane_init("p", 0, &PlaneDef { normal, point }, 1.0).ok()?,
            fplane_init("f", 0, &rect, 1.0).ok()?,
            tiled_plane_init("t", 0, &rect, 1, 1.0).ok()?,
        ])
    }

    /// Wherever the side test says clear, no plane kind's own test blocks the shadow ray.
    fn check(normal: [f64; 3], point: [f64; 3], xdir: [f64; 3], p: [f64; 3], light: [f64; 3]) {
        let Some(objects) = objects(normal, point, xdir) else {
            return;
        };
        let (p, light) = (
            Vec3::new(p[0], p[1], p[2]),
            Vec3::new(light[0], light[1], light[2]),
        );
        for object in &objects {
            let sides = Sides::new(core::slice::from_ref(object), light).unwrap();
            if sides.clear(p, usize::MAX) {
                assert!(
                    !blocked(object, p, light),
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
            let len = (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
            prop_assume!(len > 1e-3);
            let n = [normal[0] / len, normal[1] / len, normal[2] / len];
            let t1 = if n[0].abs() < 0.9 { [0.0, -n[2], n[1]] } else { [-n[2], 0.0, n[0]] };
            let t2 = [n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]];
            // The hit point and the light each at a distance from the plane from 2^-60 to
            // 2^4, anywhere along it: near the plane the side test's margin decides (the
            // test's own roundings could find a hit at a tiny `t`, or just short of the
            // light).
            let at = |a: f64, b: f64, d: f64| -> [f64; 3] {
                core::array::from_fn(|k| point[k] + a * t1[k] + b * t2[k] + d * n[k])
            };
            let dp = off[0] * 2f64.powi(exponent[0]);
            let dl = off[1] * 2f64.powi(exponent[1]);
            check(normal, point, t1, at(along[0], along[1], dp), at(along[2], along[3], dl));
            // The same side, the other far.
            check(normal, point, t1, at(along[0], along[1], dp), at(along[2], along[3], dp.signum() * 9.0));
            check(normal, point, t1, at(along[0], along[1], dl.signum() * 9.0), at(along[2], along[3], dl));
        }
    }
}
