//! The infinite plane: the seed's `plane_t`, `plane_init`, `plane_hits` and `plane_print`.

use super::{
    Hit, Object, ObjectVTable, Palette, RowOrigin, RowTest, Shape, Surface, object_material,
    object_surface,
};
use crate::error::{Attr, Entity, ErrorKind};
use crate::material::MaterialId;
#[cfg(feature = "print")]
use crate::print;
use crate::ray::Ray;
use crate::scalar::{Scalar, load, load_position, load3};
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use core::fmt;

/// A plane as written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneDef {
    /// The normal (any length but zero; normalised at load).
    pub normal: [f64; 3],
    /// A point on the plane.
    pub point: [f64; 3],
}

/// A plane with its invariants computed once, at load: the unit normal and `N.point`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane<S> {
    /// The normal as written (kept for the printer).
    pub normal: Vec3<S>,
    /// A point on the plane.
    pub point: Vec3<S>,
    /// The unit normal.
    pub unit_normal: Vec3<S>,
    /// `unit_normal . point`: the plane is `N.x = N.point`.
    pub n_dot_point: S,
}

impl<S: Scalar> Plane<S> {
    /// Checks a definition: finite values, a normal that is not zero.
    pub(crate) fn build(def: &PlaneDef, scale: f64) -> Result<Self, ErrorKind> {
        let normal = load3::<S>(def.normal, Attr::Normal)?;
        let point = load_position::<S>(def.point, scale, Attr::Point)?;
        // Invariants in f64 from the stored values: every number type starts from the same
        // correctly rounded unit normal, and a re-read printed scene is equal.
        let unit = normal
            .to_f64()
            .unit_f64()
            .ok_or(ErrorKind::ZeroVector { attr: Attr::Normal })?;
        let n_dot_point = unit.dot(point.to_f64());
        let n_dot_point = load(n_dot_point, Attr::Point)?;
        Ok(Self {
            normal,
            point,
            unit_normal: unit.cast(),
            n_dot_point,
        })
    }

    /// The seed's `plane_hits`: `t = (N.point - N.base) / N.dir`; no hit when the ray is
    /// parallel (`N.dir == 0`), when `t <= 0`, or when `t` is not below `limit`.
    #[inline]
    pub fn nearest(&self, ray: &Ray<S>, limit: S) -> Option<S> {
        let n_dot_dir = self.unit_normal.dot(ray.dir);
        let distance = self.n_dot_point - self.unit_normal.dot(ray.base);
        // No division for planes behind the ray or beyond `limit`, nor when the ray is
        // parallel (`N.dir == 0`).
        S::parameter_within(distance, n_dot_dir, limit)
    }

    /// The test of a row's primary rays: when the normal has no x part, `N . dir` is the
    /// same for every ray of the row (bit for bit: `0 * dir.x` adds nothing), so is `t`,
    /// and so is the hit point's `z`. (Not in `f64`, whose primary rays are normalised:
    /// their `y` and `z` change along the row.)
    pub fn row_test(&self, origin: &RowOrigin<S>) -> RowTest<S> {
        let n = self.unit_normal;
        if S::COURSE_ORDER || n.x != S::ZERO {
            return RowTest::Hits;
        }
        let ray = Ray::new(origin.eye, Vec3::new(S::ZERO, origin.dy, origin.dz));
        match self.nearest(&ray, S::UNBOUNDED) {
            Some(t) if origin.eye.z + origin.dz * t <= origin.z_limit => RowTest::At(t),
            _ => RowTest::Miss,
        }
    }

    /// The nearest hit as a hit record.
    pub fn intersect(&self, ray: &Ray<S>) -> Option<Hit<S>> {
        self.nearest(ray, S::UNBOUNDED).map(|t| Hit {
            t,
            point: ray.at(t),
            normal: self.unit_normal,
        })
    }

    /// Writes `normal` and `point`.
    #[cfg(feature = "print")]
    pub(crate) fn print_attributes(&self, out: &mut dyn fmt::Write, scale: f64) -> fmt::Result {
        print::vector(out, Attr::Normal, self.normal, 1.0)?;
        print::vector(out, Attr::Point, self.point, scale)
    }

    /// The plane kind's function table.
    pub const VTABLE: ObjectVTable<S> = ObjectVTable {
        kind: Entity::Plane,
        hits: plane_hits,
        normal: plane_normal,
        row_test: plane_row_test,
        #[cfg(feature = "print")]
        printer: plane_print,
        material: object_material,
        surface: plane_surface,
    };
}

/// The seed's `plane_init`: the common part, then the plane's own table and data.
pub fn plane_init<S: Scalar>(
    name: &str,
    material: MaterialId,
    def: &PlaneDef,
    scale: f64,
) -> Result<Object<S>, ErrorKind> {
    Object::init(
        &Plane::VTABLE,
        name,
        material,
        Shape::Plane(Plane::build(def, scale)?),
    )
}

/// `hits` of a plane.
pub fn plane_hits<S: Scalar>(obj: &Object<S>, ray: &Ray<S>, limit: S) -> Option<S> {
    match obj.shape() {
        Shape::Plane(plane) => plane.nearest(ray, limit),
        _ => None,
    }
}

/// `surface` of the plane and the finite plane: the unit normal, the object's material.
pub fn plane_surface<'s, S: Scalar>(
    obj: &Object<S>,
    palette: &Palette<'s, S>,
    ray: &Ray<S>,
    t: S,
) -> Option<Surface<'s, S>> {
    object_surface(obj, palette, ray, t, plane_normal)
}

/// `row_test` of the infinite plane kinds (plane, tiled plane).
pub fn plane_row_test<S: Scalar>(obj: &Object<S>, origin: &RowOrigin<S>) -> RowTest<S> {
    match obj.shape() {
        Shape::Plane(plane) => plane.row_test(origin),
        Shape::TiledPlane(tiled) => tiled.rect.plane.row_test(origin),
        _ => RowTest::Hits,
    }
}

/// `normal` of the plane kinds: the unit normal, everywhere.
pub fn plane_normal<S: Scalar>(obj: &Object<S>, _: Vec3<S>) -> Vec3<S> {
    match obj.shape() {
        Shape::Plane(plane) => plane.unit_normal,
        Shape::FPlane(rect) => rect.plane.unit_normal,
        Shape::TiledPlane(tiled) => tiled.rect.plane.unit_normal,
        Shape::TexPlane(textured) => textured.rect.plane.unit_normal,
        Shape::Sphere(_) => Vec3::ZERO,
    }
}

/// `printer` of a plane: the common object printer first, then the plane's attributes.
#[cfg(feature = "print")]
pub fn plane_print<S: Scalar>(
    obj: &Object<S>,
    palette: &super::Palette<'_, S>,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    super::object_print(obj, palette, out)?;
    if let Shape::Plane(plane) = obj.shape() {
        plane.print_attributes(out, palette.scale)?;
    }
    print::footer(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::test_support::ray;

    fn floor_at_minus_7() -> Object<f64> {
        plane_init(
            "p",
            0,
            &PlaneDef {
                normal: [0.0, 0.0, 1.0],
                point: [0.0, 0.0, -7.0],
            },
            1.0,
        )
        .unwrap()
    }

    #[test]
    fn seed_example() {
        // The seed's worked example: N = (0,0,1), point (0,0,-7), base (4,3,5), dir (0,0,-1).
        let hit = floor_at_minus_7()
            .hit(&ray([4.0, 3.0, 5.0], [0.0, 0.0, -1.0]))
            .unwrap();
        assert_eq!(hit.t, 12.0);
        assert_eq!(hit.point, Vec3::new(4.0, 3.0, -7.0));
        assert_eq!(hit.normal, Vec3::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn parallel_and_behind_miss() {
        let p = floor_at_minus_7();
        assert_eq!(p.hit(&ray([4.0, 3.0, 5.0], [1.0, 0.0, 0.0])), None);
        assert_eq!(p.hit(&ray([4.0, 3.0, 5.0], [0.0, 0.0, 1.0])), None);
    }

    #[test]
    fn normal_is_normalised_at_load_and_written_one_kept() {
        let p = Plane::<f64>::build(
            &PlaneDef {
                normal: [0.0, 3.0, 4.0],
                point: [0.0, 1.0, 0.0],
            },
            1.0,
        )
        .unwrap();
        assert_eq!(p.normal, Vec3::new(0.0, 3.0, 4.0));
        assert_eq!(p.unit_normal, Vec3::new(0.0, 0.6, 0.8));
        assert_eq!(p.n_dot_point, 0.6);
        assert_eq!(
            Plane::<f64>::build(
                &PlaneDef {
                    normal: [0.0; 3],
                    point: [0.0; 3]
                },
                1.0
            ),
            Err(ErrorKind::ZeroVector { attr: Attr::Normal })
        );
    }

    #[test]
    fn installs_the_plane_table() {
        let p = floor_at_minus_7();
        assert_eq!(p.vtable().kind, Entity::Plane);
        assert_eq!(p.kind(), Entity::Plane);
        // Dispatch goes through the installed table: the same answer as the plane itself.
        let Shape::Plane(plane) = p.shape() else {
            panic!("not a plane")
        };
        let r = ray([1.0, 2.0, 0.0], [0.1, -0.2, -1.0]);
        assert_eq!(p.hit(&r), plane.intersect(&r));
        // Below the limit only: the hit is at t = 7 |(0.1, -0.2, -1)| = 7.17.
        assert!(p.hits(&r, 7.2).is_some());
        assert_eq!(p.hits(&r, 7.1), None);
    }
}
