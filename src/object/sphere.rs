//! The sphere.

use super::{
    Object, ObjectVTable, Palette, Shape, Surface, ahead, object_material, object_surface,
};
use crate::error::{Attr, Entity, ErrorKind};
use crate::material::MaterialId;
use crate::ray::Ray;
use crate::scalar::{Scalar, load, load_length, load_position};
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use crate::write;
#[cfg(feature = "print")]
use core::fmt;

/// A sphere as written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereDef {
    /// The centre.
    pub center: [f64; 3],
    /// The radius, above zero.
    pub radius: f64,
}

/// A sphere with its squared radius computed at load.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere<S> {
    /// The centre.
    pub center: Vec3<S>,
    /// The radius.
    pub radius: S,
    /// The radius squared.
    pub radius_squared: S,
}

impl<S: Scalar> Sphere<S> {
    /// Checks a definition: finite values, a radius above zero.
    pub(crate) fn build(def: &SphereDef, scale: f64) -> Result<Self, ErrorKind> {
        let center = load_position::<S>(def.center, scale, Attr::Center)?;
        let radius = load_length::<S>(def.radius, scale, Attr::Radius)?;
        let r = radius.to_f64();
        Ok(Self {
            center,
            radius,
            radius_squared: load(r * r, Attr::Radius)?,
        })
    }

    /// The near root of `|base + t dir - center|^2 = r^2`; a miss when the discriminant is
    /// not positive or the near root is not in `(0, limit)`.
    ///
    /// `f64` rays are unit rays (see [`nearest_unit`](Self::nearest_unit)). For `f32` rays
    /// of any length the quadratic is taken with the discriminant in the cross-product form
    /// `|dir|^2 r^2 - |f x dir|^2`, the same perpendicular distance scaled by `|dir|^2`:
    /// one square root and one division. Fixed point, which has no range for those products,
    /// multiplies the direction by its length's reciprocal first, and `t` by it after.
    #[inline]
    pub fn nearest(&self, ray: &Ray<S>, limit: S) -> Option<S> {
        if S::COURSE_ORDER || ray.len == S::ONE {
            return self.nearest_unit(ray.base, ray.dir, limit);
        }
        if S::WIDE_RANGE {
            let f = ray.base - self.center;
            let b = f.dot(ray.dir);
            if b > S::ZERO {
                return None;
            }
            let across = f.cross(ray.dir);
            let discriminant = ray.dir.dot(ray.dir) * self.radius_squared - across.dot(across);
            if !(discriminant > S::ZERO) {
                return None;
            }
            // b <= 0: q is the far root times |dir|^2, and the near root is c / q.
            let q = discriminant.sqrt() - b;
            let c = f.dot(f) - self.radius_squared;
            return ahead(c / q, limit);
        }
        // Most tests of such rays miss, and fixed point can tell most of them without the
        // length's square root and the quotients below (the same outcome, exactly): a
        // shadow ray's segment (`limit` at most 1) by comparisons with the ball's box,
        // else by exact sums.
        let f = ray.base - self.center;
        let half = Vec3::new(self.radius, self.radius, self.radius);
        if limit <= S::ONE && S::segment_clears_box(f, ray.dir, half)
            || S::misses_ball(f, ray.dir, ray.len, self.radius_squared)
        {
            return None;
        }
        // One wide reciprocal for the direction and for `t` (written out here, not through
        // `unit_direction`: inlined this way the minimal firmware is 300 B smaller).
        let len = ray.length();
        let inv = S::wide_recip(len.to_wide()?);
        let unit = Vec3::new(
            ray.dir.x.scale(inv),
            ray.dir.y.scale(inv),
            ray.dir.z.scale(inv),
        );
        // The limit applies to the converted `t`: ties must not depend on a rounded limit.
        let t = self.nearest_unit(ray.base, unit, S::UNBOUNDED)?;
        ahead(t.scale(inv), limit)
    }

    /// [`nearest`](Self::nearest) for a unit `dir`.
    ///
    /// With `f = base - center` and `b = f . dir`, the discriminant is taken in the
    /// perpendicular form `r^2 - |f - b dir|^2` (Haines et al., Ray Tracing Gems ch. 7), which
    /// does not subtract two large squares, and the near root in the stable form `c / q`,
    /// `q = -(b + sign(b) sqrt(disc))`, which does not subtract two close numbers. `c =
    /// |f|^2 - r^2` is evaluated as `(|f| - r)(|f| + r)` and divided by `q` before the second
    /// factor, so nothing is squared that could overflow a fixed-point type.
    #[inline]
    pub fn nearest_unit(&self, base: Vec3<S>, dir: Vec3<S>, limit: S) -> Option<S> {
        let f = base - self.center;
        let b = f.dot(dir);
        if b > S::ZERO {
            // Moving away from the centre: the near root is behind the base.
            return None;
        }
        let perpendicular = f - dir * b;
        let discriminant = self.radius_squared - perpendicular.dot(perpendicular);
        if !(discriminant > S::ZERO) {
            return None;
        }
        // b <= 0, so q = sqrt(disc) - b is the far root; the near root is c / q.
        let q = discriminant.sqrt() - b;
        let distance = f.length();
        let t = (distance - self.radius) * ((distance + self.radius) / q);
        ahead(t, limit)
    }

    /// The unit normal at a point of the sphere: `unit(point - center)` (the zero vector
    /// at the centre, which no hit reaches).
    #[inline]
    pub fn normal_at(&self, point: Vec3<S>) -> Vec3<S> {
        (point - self.center).unit().unwrap_or(Vec3::ZERO)
    }

    /// The sphere kind's function table.
    pub const VTABLE: ObjectVTable<S> = ObjectVTable {
        kind: Entity::Sphere,
        hits: sphere_hits,
        normal: sphere_normal,
        #[cfg(all(feature = "plan", feature = "batch"))]
        row_test: sphere_row_test,
        #[cfg(not(all(feature = "plan", feature = "batch")))]
        row_test: super::object_row_test,
        #[cfg(feature = "print")]
        printer: sphere_print,
        material: object_material,
        surface: sphere_surface,
    };
}

/// Builds a sphere object and installs its table.
pub fn sphere_init<S: Scalar>(
    name: &str,
    material: MaterialId,
    def: &SphereDef,
    scale: f64,
) -> Result<Object<S>, ErrorKind> {
    Object::init(
        &Sphere::VTABLE,
        name,
        material,
        Shape::Sphere(Sphere::build(def, scale)?),
    )
}

/// `hits` of a sphere.
pub fn sphere_hits<S: Scalar>(obj: &Object<S>, ray: &Ray<S>, limit: S) -> Option<S> {
    match obj.shape() {
        Shape::Sphere(sphere) => sphere.nearest(ray, limit),
        _ => None,
    }
}

/// `surface` of a sphere: its normal, its material.
pub fn sphere_surface<'s, S: Scalar>(
    obj: &Object<S>,
    palette: &Palette<'s, S>,
    ray: &Ray<S>,
    t: S,
    out: &mut Option<Surface<'s, S>>,
) {
    object_surface(obj, palette, ray, t, sphere_normal, out);
}

/// `normal` of a sphere.
pub fn sphere_normal<S: Scalar>(obj: &Object<S>, point: Vec3<S>) -> Vec3<S> {
    match obj.shape() {
        Shape::Sphere(sphere) => sphere.normal_at(point),
        _ => Vec3::ZERO,
    }
}

/// `row_test` of a sphere, on the host in `f64` (the rays are unit vectors there): the
/// rays of the row that can meet it, by their direction's `x`
/// ([`RowTest::Across`](super::RowTest::Across)).
///
/// The row's rays run from the eye `E` along `d = (a, dy, dz)`, `a` the pixel's `x` less
/// the eye's. The line meets a sphere about `C` (`w = C - E`) of radius `r` where
/// `(w . d)^2 >= (|w|^2 - r^2) |d|^2`, a quadratic in `a` that holds between its roots when
/// the eye is outside the sphere's slab along x (else every ray is tested). The radius is
/// widened as the render plan's bounds are (`2e-3` radians and more), far beyond the
/// roundings of the unit directions, and the unit direction's `x`, `a / |d|`, grows with
/// `a`: the rays outside the bounds miss, bit for bit as their test would.
#[cfg(all(feature = "plan", feature = "batch"))]
pub fn sphere_row_test<S: Scalar>(
    obj: &Object<S>,
    origin: &super::RowOrigin<S>,
) -> super::RowTest<S> {
    use super::RowTest;
    let Shape::Sphere(sphere) = obj.shape() else {
        return RowTest::Hits;
    };
    if !S::COURSE_ORDER {
        return RowTest::Hits;
    }
    let w = sphere.center.to_f64() - origin.eye.to_f64();
    let (dy, dz) = (origin.dy.to_f64(), origin.dz.to_f64());
    let distance = w.length();
    let radius = sphere.radius.to_f64();
    let r = radius + 2e-3 * (distance + radius) + 1e-9 * (distance + 1.0);
    let q = distance * distance - r * r;
    let k = w.y * dy + w.z * dz;
    let m = origin.dy_dz_squared();
    // A a^2 + B a + C >= 0.
    let (a2, b, c) = (w.x * w.x - q, 2.0 * w.x * k, k * k - q * m);
    let disc = b * b - 4.0 * a2 * c;
    if !(q > 0.0 && a2 < 0.0 && m > 0.0) {
        return RowTest::Hits;
    }
    if !(disc > 0.0) {
        // No ray of the row passes within the widened radius.
        return RowTest::Miss;
    }
    let root = crate::scalar::sqrt_f64(disc);
    // a2 < 0: the roots in increasing order.
    let (low, high) = ((-b + root) / (2.0 * a2), (-b - root) / (2.0 * a2));
    match (
        S::from_f64_checked(super::unit_x(low, m)),
        S::from_f64_checked(super::unit_x(high, m)),
    ) {
        (Some(lo), Some(hi)) => RowTest::Across { lo, hi },
        _ => RowTest::Hits,
    }
}

/// `printer` of a sphere.
#[cfg(feature = "print")]
pub fn sphere_print<S: Scalar>(
    obj: &Object<S>,
    palette: &super::Palette<'_, S>,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    super::object_print(obj, palette, out)?;
    if let Shape::Sphere(sphere) = obj.shape() {
        write::vector(out, Attr::Center, sphere.center, palette.scale)?;
        write::numbers(out, Attr::Radius, &[sphere.radius], palette.scale)?;
    }
    write::footer(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::test_support::ray;

    fn ball() -> Object<f64> {
        sphere_init(
            "s",
            0,
            &SphereDef {
                center: [0.0, 0.0, -10.0],
                radius: 2.0,
            },
            1.0,
        )
        .unwrap()
    }

    #[test]
    fn near_root_and_normal() {
        let hit = ball().hit(&ray([0.0, 0.0, 0.0], [0.0, 0.0, -1.0])).unwrap();
        assert_eq!(hit.t, 8.0);
        assert_eq!(hit.point, Vec3::new(0.0, 0.0, -8.0));
        assert_eq!(hit.normal, Vec3::new(0.0, 0.0, 1.0));
        // Off-axis: base (1,0,0) along -z meets the sphere at z = -10 + sqrt(3).
        let hit = ball().hit(&ray([1.0, 0.0, 0.0], [0.0, 0.0, -1.0])).unwrap();
        assert!((hit.t - (10.0 - 3f64.sqrt())).abs() < 1e-12);
        assert!((hit.normal.length() - 1.0).abs() < 1e-15);
    }

    /// Wherever a shadow ray's segment (`0 < t < 1`) clears the ball's box by the margin
    /// (the box test itself, which only the Cortex-M0 runs), the test finds nothing on
    /// it, with a limit of 1 or less: 60,000 Q16.16 segments over radii from 0.02 to 40,
    /// through points near the sphere's surface (from a tenth of the radius in to seven
    /// tenths out). A box an eighth or a thirty-second of the radius short, or half a
    /// segment's length taken, fails it.
    #[test]
    fn a_cleared_box_finds_nothing() {
        use crate::object::test_support::stream;
        use crate::scalar::{I16F16, segment_clears_box};
        let (mut cleared, mut tried, mut found) = (0u32, 0u32, 0u32);
        let mut next = stream(7);
        for radius in [0.02, 0.3, 1.0, 4.0, 40.0] {
            let def = SphereDef {
                center: [1.5, -2.0, -6.0],
                radius,
            };
            let sphere = Sphere::<I16F16>::build(&def, 1.0).unwrap();
            let center = sphere.center.to_f64();
            let fixed = |v: Vec3<f64>| v.cast::<I16F16>();
            for i in 0..12_000 {
                // A segment through a point near the surface, half of them square to an
                // axis (those graze the box's sides), of up to 4 radii each way.
                let unit = |v: Vec3<f64>| v.unit_f64();
                let Some(n) = unit(Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5)) else {
                    continue;
                };
                let point = center + n * (radius * (0.9 + 0.8 * next()));
                let mut way = [next() - 0.5, next() - 0.5, next() - 0.5];
                if i % 2 == 0 {
                    way[i / 2 % 3] = 0.0;
                }
                let Some(way) = unit(Vec3::from_array(way)) else {
                    continue;
                };
                let from = point - way * (4.0 * radius * next());
                let light = point + way * (4.0 * radius * next());
                let ray = Ray::new(fixed(from), fixed(light - from));
                let bits = |v: Vec3<I16F16>| [v.x, v.y, v.z].map(I16F16::to_bits);
                let half = [sphere.radius.to_bits().unsigned_abs(); 3];
                let clears =
                    segment_clears_box(bits(ray.base - sphere.center), bits(ray.dir), half);
                let hit = sphere.nearest(&ray, I16F16::ONE);
                tried += 1;
                found += u32::from(hit.is_some());
                if clears {
                    cleared += 1;
                    assert_eq!(hit, None, "{radius} {ray:?}");
                    let limit = I16F16::from_f64(next());
                    assert_eq!(sphere.nearest(&ray, limit), None, "{radius} {ray:?}");
                }
            }
        }
        // Not vacuous: many segments clear the box and many meet the sphere.
        assert!(cleared > tried / 10, "{cleared} of {tried}");
        assert!(found > tried / 10, "{found} of {tried}");
    }

    #[test]
    fn misses() {
        let s = ball();
        // Passes beside, grazes (discriminant 0), points away, starts inside.
        assert_eq!(s.hit(&ray([3.0, 0.0, 0.0], [0.0, 0.0, -1.0])), None);
        assert_eq!(s.hit(&ray([2.0, 0.0, 0.0], [0.0, 0.0, -1.0])), None);
        assert_eq!(s.hit(&ray([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])), None);
        assert_eq!(s.hit(&ray([0.0, 0.0, -10.0], [0.0, 0.0, -1.0])), None);
    }

    #[test]
    fn radius_must_be_positive() {
        let build = |radius| {
            let def = SphereDef {
                center: [0.0; 3],
                radius,
            };
            Sphere::<f32>::build(&def, 1.0)
        };
        for radius in [0.0, -1.0] {
            let result = build(radius);
            assert_eq!(
                result,
                Err(ErrorKind::NotPositive { attr: Attr::Radius }),
                "{radius}"
            );
        }
        // Positive, but zero in f32: too small for the type (issue 36: not "not positive").
        assert_eq!(
            build(1e-300),
            Err(ErrorKind::TooSmallForType {
                attr: Attr::Radius,
                number_type: "f32"
            })
        );
    }

    #[cfg(all(feature = "plan", feature = "batch"))]
    mod row_test {
        use super::*;
        use crate::object::{RowOrigin, RowTest};
        use proptest::prelude::*;

        proptest! {
            /// The rays of a row outside `RowTest::Across` miss the sphere, down to the
            /// pixels next to its outline.
            #[test]
            fn rays_outside_the_bounds_miss(
                center in prop::array::uniform3(-10.0f64..10.0),
                radius in 0.01f64..5.0,
                eye in prop::array::uniform3(-10.0f64..10.0),
                dy in -10.0f64..10.0,
                dz in -12.0f64..-0.1,
                xs in prop::collection::vec(-30.0f64..30.0, 32),
            ) {
                let Ok(obj) = sphere_init::<f64>("s", 0, &SphereDef { center, radius }, 1.0) else {
                    return Ok(());
                };
                let eye = Vec3::new(eye[0], eye[1], eye[2]);
                let origin = RowOrigin { eye, dy, dz, z_limit: f64::INFINITY, columns: crate::camera::RowColumns::none() };
                let Shape::Sphere(sphere) = obj.shape() else { unreachable!() };
                let test = sphere_row_test(&obj, &origin);
                // The row's rays through `xs`, and through points just beside the outline:
                // where the line from the eye grazes the sphere.
                for &a in &xs {
                    let d = Vec3::new(a, dy, dz);
                    let Some(dir) = d.unit() else { continue };
                    let ray = Ray::with_length(eye, dir, 1.0);
                    let hit = sphere.nearest(&ray, f64::INFINITY);
                    match test {
                        RowTest::Miss => prop_assert!(hit.is_none()),
                        RowTest::Across { lo, hi } if !(dir.x >= lo && dir.x <= hi) => {
                            prop_assert!(hit.is_none(), "{a} {lo} {hi}");
                        }
                        _ => {}
                    }
                }
            }
        }

        /// A ball in the middle of the view: the row through its centre tests the rays of
        /// its width (and the margin), not the others.
        #[test]
        fn the_bounds_hold_the_ball_and_little_more() {
            let obj = sphere_init::<f64>(
                "s",
                0,
                &SphereDef {
                    center: [4.0, 3.0, -6.0],
                    radius: 1.0,
                },
                1.0,
            )
            .unwrap();
            let origin = RowOrigin {
                eye: Vec3::new(4.0, 3.0, 4.0),
                dy: 0.0,
                dz: -4.0,
                z_limit: 0.01,
                columns: crate::camera::RowColumns::none(),
            };
            let RowTest::Across { lo, hi } = sphere_row_test(&obj, &origin) else {
                panic!("no bounds");
            };
            // The ball spans half-angle asin(1 / 10): dir.x within 0.1 of zero.
            assert!(lo < -0.1 && lo > -0.11, "{lo}");
            assert!(hi > 0.1 && hi < 0.11, "{hi}");
        }
    }
}
