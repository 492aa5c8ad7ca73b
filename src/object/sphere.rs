//! The sphere.

use super::{
    Object, ObjectVTable, Palette, Shape, Surface, ahead, object_material, object_surface,
};
use crate::error::{Attr, Entity, ErrorKind};
use crate::material::MaterialId;
#[cfg(feature = "print")]
use crate::print;
use crate::ray::Ray;
use crate::scalar::{Scalar, load, load_length, load_position};
use crate::vec3::Vec3;
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

/// `printer` of a sphere.
#[cfg(feature = "print")]
pub fn sphere_print<S: Scalar>(
    obj: &Object<S>,
    palette: &super::Palette<'_, S>,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    super::object_print(obj, palette, out)?;
    if let Shape::Sphere(sphere) = obj.shape() {
        print::vector(out, Attr::Center, sphere.center, palette.scale)?;
        print::numbers(out, Attr::Radius, &[sphere.radius], palette.scale)?;
    }
    print::footer(out)
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
        for radius in [0.0, -1.0, 1e-300] {
            let def = SphereDef {
                center: [0.0; 3],
                radius,
            };
            let result = Sphere::<f32>::build(&def, 1.0);
            assert_eq!(
                result,
                Err(ErrorKind::NotPositive { attr: Attr::Radius }),
                "{radius}"
            );
        }
    }
}
