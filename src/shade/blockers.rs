//! The objects that can block each light, found once a render (feature `batch`, `f64`).
//!
//! A plane (plain, tiled or finite: their tests start with their plane's) blocks the way
//! from a hit point `P` to a light `L` only if the two lie on opposite sides of it. Every
//! shadow ray starts on an object a ray can meet (a render plan's kept objects), and the
//! filtered walk's later starts lie between `P` and `L`. So where the light and every
//! other kept object lie clearly on one side of a plane, the plane blocks none of that
//! light's shadow rays, and they leave it out (translucent3: the back wall, for both
//! lights; the filtered walk tests the green pane alone). A plane whose own points start a
//! ray is skipped by that ray anyway.
//!
//! "Clearly" is the side test's margin (see `sides`): farther from the plane than
//! `2^-40 s`, `s` the size of the coordinates involved, here taken over each object's
//! box. The shadow test's roundings cannot then find the plane between `P` and `L`.
//!
//! A sphere blocks the way from `P` to `L` only if `P` lies in the cone from `L` that
//! holds the sphere. Where a light's blockers are spheres and at most one other object,
//! a lane on that object (shiny3: the floor, under one ball) whose way to the light lies
//! outside every sphere's cone needs no shadow ray ([`Cones::clear`]; about 10
//! instructions for the sphere test's 40 and the walk to it).
//!
//! The cone is widened by `2^-20` in the sine of its half-angle: outside it, the line
//! from `P` to `L` passes the centre at `r + 2^-20 |C - L|` or more, while the sphere
//! test's perpendicular distance is off by a few units in the last place of `|P - C|`,
//! which the test keeps below `2^20 |C - L|` (`|P - C| <= |P - L| + |C - L|`). The
//! test's discriminant is then negative, as it is exactly: the same answer, bit for bit.

use crate::bvh::bounds;
use crate::light::Light;
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

/// `2^-20`: how much a sphere's cone is widened, in the sine of its half-angle.
const CONE_MARGIN: f64 = 1.0 / 1_048_576.0;

/// `2^20`: how far from the light, in units of its distance from a sphere's centre, a
/// cone's answer is trusted.
const CONE_REACH: f64 = 1_048_576.0;

/// Each light's list of the kept objects that can block it, in increasing index order,
/// and the cones of those that are spheres.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightBlockers {
    lists: [[u16; MAX_BLOCKERS]; MAX_LIGHTS],
    /// Each list's length; `None` for a light that tests every kept object.
    counts: [Option<u8>; MAX_LIGHTS],
    cones: [Option<Cones>; MAX_LIGHTS],
}

/// The cones of a light's blockers, where they are spheres and at most one other object.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cones {
    /// The blocker that is not a sphere: lanes on it skip it (their own shadow rays do);
    /// the others' need its side test, where it is a plane, or its shadow test.
    other: Option<usize>,
    /// The other blocker's side, where it is a plane.
    other_side: Option<Side>,
    count: usize,
    index: [usize; MAX_CONES],
    /// The unit way from the light to each sphere's centre.
    axis: [[f64; 3]; MAX_CONES],
    /// The cosine of each widened cone's half-angle.
    cos: [f64; MAX_CONES],
    /// The distance from the light within which the cones are trusted.
    reach: f64,
}

/// A plane seen from a light: its normal and `N.point` turned so that the light's side is
/// the positive one (as `sides` has them).
#[derive(Clone, Copy, Debug)]
struct Side {
    normal: [f64; 3],
    n_dot_point: f64,
    /// `|N.point| + |L|_1`.
    size: f64,
    /// The light's distance from the plane.
    light: f64,
}

impl Side {
    fn new(plane: (Vec3<f64>, f64), light: Vec3<f64>) -> Self {
        let (normal, n_dot_point) = plane;
        let light_side = n_dot_point - normal.dot(light);
        let turn = if light_side < 0.0 { -1.0 } else { 1.0 };
        Self {
            normal: [normal.x * turn, normal.y * turn, normal.z * turn],
            n_dot_point: n_dot_point * turn,
            size: n_dot_point.abs() + norm_1(light),
            light: light_side.abs(),
        }
    }

    /// Whether `point` and the light lie clearly on one side of the plane (`sides`).
    #[inline(always)]
    fn clear(&self, p: Vec3<f64>) -> bool {
        let margin = (self.size + norm_1(p)) * MARGIN;
        let [nx, ny, nz] = self.normal;
        self.light > margin && self.n_dot_point - (p.x * nx + p.y * ny + p.z * nz) > margin
    }
}

impl Cones {
    /// The cones of the spheres among `blockers` seen from a light at `light`; `None`
    /// where two blockers are not spheres or a sphere holds the light (or nearly).
    fn new<S: Scalar>(objects: &[Object<S>], blockers: &[u16], light: Vec3<f64>) -> Option<Self> {
        let mut cones = Self {
            other: None,
            other_side: None,
            count: 0,
            index: [0; MAX_CONES],
            axis: [[0.0; 3]; MAX_CONES],
            cos: [0.0; MAX_CONES],
            reach: f64::INFINITY,
        };
        for &index in blockers {
            let index = usize::from(index);
            let object = objects.get(index)?;
            let Shape::Sphere(sphere) = object.shape() else {
                if cones.other.replace(index).is_some() {
                    return None;
                }
                cones.other_side = plane_of(object).map(|plane| Side::new(plane, light));
                continue;
            };
            let to_center = sphere.center.to_f64() - light;
            let d = to_center.length();
            let sin = sphere.radius.to_f64() / d + CONE_MARGIN;
            if !(sin < 0.99) {
                return None;
            }
            let k = cones.count;
            *cones.index.get_mut(k)? = index;
            let axis = to_center / d;
            *cones.axis.get_mut(k)? = [axis.x, axis.y, axis.z];
            *cones.cos.get_mut(k)? = libm::sqrt(1.0 - sin * sin);
            cones.reach = cones.reach.min(d * CONE_REACH);
            cones.count = k + 1;
        }
        (cones.count > 0).then_some(cones)
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
        if let Some(other) = self.other {
            if other != own && !self.other_side.is_some_and(|side| side.clear(point)) {
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
            cones: [None; MAX_LIGHTS],
        };
        let mut any = false;
        let slots = blockers.lists.iter_mut().zip(&mut blockers.counts);
        for (((list, count), cones), light) in slots.zip(&mut blockers.cones).zip(lights) {
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
            *cones = Cones::new(objects, blocking, location);
            any |= cones.is_some();
        }
        any.then_some(blockers)
    }

    /// The objects that can block light `n`, if it has a list.
    #[inline(always)]
    pub(crate) fn of(&self, n: usize) -> Option<&[u16]> {
        let count = usize::from((*self.counts.get(n)?)?);
        self.lists.get(n)?.get(..count)
    }

    /// The cones of light `n`'s blockers, if it has them.
    #[inline(always)]
    pub(crate) fn cones(&self, n: usize) -> Option<&Cones> {
        self.cones.get(n)?.as_ref()
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

/// The unit normal and `N.point` of a kind whose test misses wherever its plane's does.
fn plane_of<S: Scalar>(object: &Object<S>) -> Option<(Vec3<f64>, f64)> {
    let plane = match object.shape() {
        Shape::Plane(plane) => plane,
        Shape::TiledPlane(tiled) => &tiled.rect.plane,
        Shape::FPlane(rect) => &rect.plane,
        _ => return None,
    };
    Some((plane.unit_normal.to_f64(), plane.n_dot_point.to_f64()))
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
        // The floor touches the ball: it stays a blocker, and so the cones clear only
        // the floor's lanes.
        assert!(!never_blocks(&objects, &[0, 1], 1, light));
        let cones = Cones::new(&objects, &[0, 1], light).unwrap();
        let lane = |p: [f64; 3], own| {
            let (ray, distance) = shadow(v(p), light).unwrap();
            cones.clear(v(p), ray.dir, distance, own)
        };
        // In front of the ball and behind it (in its shadow).
        assert!(lane([4.0, -1.0, 2.0], 1));
        assert!(!lane([0.0, -1.0, -14.0], 1));
        assert!(blocks(&objects[0], v([0.0, -1.0, -14.0]), light));
        // The ball's own lanes: clearly above the floor, or where it touches it.
        assert!(lane([4.0, 7.0, -6.0], 0));
        assert!(!lane([4.0, -1.0, -6.0], 0));
        assert!(!lane([4.0, -1.0 + 1e-14, -6.0], 0));
        // Two objects besides the spheres: no cones.
        let three = [
            objects[0].clone(),
            objects[1].clone(),
            plane([1.0, 0.0, 0.0], [-9.0, 0.0, 0.0]),
        ];
        assert!(Cones::new(&three, &[0, 1, 2], light).is_none());
    }

    proptest! {
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
            toward in prop::array::uniform3(-1.0f64..1.0),
            side in prop::array::uniform3(-1.0f64..1.0),
            distance in 1.1f64..40.0,
            beyond in 0.05f64..3.0,
            off in -1.0f64..1.0,
            exponent in -60i32..-1,
        ) {
            let toward = v(toward);
            prop_assume!(toward.length() > 1e-3);
            let axis = toward / toward.length();
            let light = v(center) - axis * (radius * distance);
            let objects = [ball(center, radius), plane([0.0, 1.0, 0.0], [0.0, -100.0, 0.0])];
            let Some(cones) = Cones::new(&objects, &[0, 1], light) else {
                return Ok(());
            };
            // A way from the light at the cone's half-angle, give or take `off 2^exponent`.
            let e = v(side) - axis * axis.dot(v(side));
            prop_assume!(e.length() > 1e-3);
            let e = e / e.length();
            let angle = libm::asin(1.0 / distance) + off * 2f64.powi(exponent);
            let way = axis * libm::cos(angle) + e * libm::sin(angle);
            let p = light + way * (radius * distance * beyond);
            let (ray, length) = shadow(p, light).unwrap();
            if cones.clear(p, ray.dir, length, 1) {
                prop_assert!(objects[0].hits(&ray, length).is_none());
            }
        }
    }
}
