//! The infinite plane: the seed's `plane_t`, `plane_init`, `plane_hits` and `plane_print`.

use super::{
    Hit, Object, ObjectVTable, Palette, RowOrigin, RowTest, Shape, Surface, object_material,
    object_surface,
};
use crate::error::{Attr, Entity, ErrorKind};
use crate::material::MaterialId;
use crate::ray::Ray;
use crate::scalar::{Scalar, load, load_direction, load_position};
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use crate::write;
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
    /// [`axis_table`](Self::axis_table), worked out at load (a byte: planes are in every
    /// object slot's data).
    pub axis: Option<u8>,
}

impl<S: Scalar> Plane<S> {
    /// Checks a definition: finite values, a normal that is not zero.
    pub(crate) fn build(def: &PlaneDef, scale: f64) -> Result<Self, ErrorKind> {
        let normal = load_direction::<S>(def.normal, Attr::Normal)?;
        let point = load_position::<S>(def.point, scale, Attr::Point)?;
        // Invariants in f64 from the stored values: every number type starts from the same
        // correctly rounded unit normal, and a re-read printed scene is equal.
        let unit = normal
            .to_f64()
            .unit_f64()
            .ok_or(ErrorKind::ZeroVector { attr: Attr::Normal })?;
        let n_dot_point = unit.dot(point.to_f64());
        let n_dot_point = load(n_dot_point, Attr::Point)?;
        let mut plane = Self {
            normal,
            point,
            unit_normal: unit.cast(),
            n_dot_point,
            axis: None,
        };
        plane.axis = plane.axis_table().and_then(|a| u8::try_from(a).ok());
        Ok(plane)
    }

    /// The seed's `plane_hits`: `t = (N.point - N.base) / N.dir`; no hit when the ray is
    /// parallel (`N.dir == 0`), when `t <= 0`, or when `t` is not below `limit`.
    #[inline]
    pub fn nearest(&self, ray: &Ray<S>, limit: S) -> Option<S> {
        // Mostly a shadow ray made a moment ago: see `LOAD_APART`.
        let ray = ray.read_apart();
        let n_dot_dir = S::dot_unit(ray.dir, self.unit_normal);
        let distance = self.n_dot_point - S::dot_unit(ray.base, self.unit_normal);
        // No division for planes behind the ray or beyond `limit`, nor when the ray is
        // parallel (`N.dir == 0`).
        S::parameter_within(distance, n_dot_dir, limit)
    }

    /// [`nearest`](Self::nearest), read off one coordinate when the normal is along an
    /// axis (exact, as [`axis_plane_hits`]): for the kinds built on a plane, whose own
    /// tables cannot be chosen by the plane's normal.
    #[cfg_attr(feature = "batch", inline(always))]
    #[cfg_attr(not(feature = "batch"), inline)]
    pub fn nearest_by_axis(&self, ray: &Ray<S>, limit: S) -> Option<S> {
        match self.read_axis() {
            Some(axis) => self.nearest_along(axis / 2, axis % 2 == 1, ray, limit),
            None => self.nearest(ray, limit),
        }
    }

    /// The axis [`nearest_by_axis`](Self::nearest_by_axis) reads one coordinate off, if
    /// it does (the normal lies along an axis and the type reads it exactly).
    #[inline]
    pub fn read_axis(&self) -> Option<u8> {
        self.axis.filter(|_| S::AXIS_READS)
    }

    /// `N.point - N.base`: the part of [`nearest_by_axis`](Self::nearest_by_axis) that
    /// rays from one point share (a row's primary rays, from the eye), computed as it does
    /// (see [`nearest_from`](Self::nearest_from)).
    #[cfg(feature = "plan")]
    #[inline]
    pub fn distance_from(&self, base: Vec3<S>) -> S {
        match self.read_axis() {
            Some(axis) => self.n_dot_point - coordinate(base, axis),
            None => self.n_dot_point - S::dot_unit(base, self.unit_normal),
        }
    }

    /// [`nearest_by_axis`](Self::nearest_by_axis) for a ray along `dir` from a base
    /// `distance` ([`distance_from`](Self::distance_from)) away: the same operations in
    /// the same order, so the same `t`, bit for bit (tests/plan.rs renders every scene
    /// both ways).
    #[cfg(feature = "plan")]
    #[inline]
    pub fn nearest_from(&self, distance: S, dir: Vec3<S>, limit: S) -> Option<S> {
        match self.read_axis() {
            Some(axis) => self.nearest_from_axis(axis, distance, dir, limit),
            None => self.nearest_from_leaning(distance, dir, limit),
        }
    }

    /// [`nearest_from`](Self::nearest_from) for a plane whose [`read_axis`](Self::read_axis)
    /// is `axis`.
    #[cfg(feature = "plan")]
    #[inline]
    pub(crate) fn nearest_from_axis(
        &self,
        axis: u8,
        distance: S,
        dir: Vec3<S>,
        limit: S,
    ) -> Option<S> {
        S::parameter_within(distance, coordinate(dir, axis), limit)
    }

    /// [`nearest_from`](Self::nearest_from) for a plane that reads no axis.
    #[cfg(feature = "plan")]
    #[inline]
    pub(crate) fn nearest_from_leaning(&self, distance: S, dir: Vec3<S>, limit: S) -> Option<S> {
        S::parameter_within(distance, S::dot_unit(dir, self.unit_normal), limit)
    }

    /// [`nearest`](Self::nearest) for a unit normal of `+1` (`-1` when `negative`) along
    /// `axis` (0 for x, 1 for y, 2 for z): the dot products read off one coordinate.
    #[inline]
    fn nearest_along(&self, axis: u8, negative: bool, ray: &Ray<S>, limit: S) -> Option<S> {
        let (dir, base) = match axis {
            0 => (ray.dir.x, ray.base.x),
            1 => (ray.dir.y, ray.base.y),
            _ => (ray.dir.z, ray.base.z),
        };
        let (dir, base) = if negative { (-dir, -base) } else { (dir, base) };
        S::parameter_within(self.n_dot_point - base, dir, limit)
    }

    /// The test of a row's primary rays: when the normal has no x part, `N . dir` is the
    /// same for every ray of the row (bit for bit: `0 * dir.x` adds nothing), so is `t`,
    /// and so is the hit point's `z`. Not in `f64`, whose primary rays are normalised
    /// (their `y` and `z` change along the row): each ray is tested there, with the part
    /// the rays share, `N.point - N.eye`, worked out once (with the plan; the other types
    /// leave that out for the Cortex-M0's flash).
    pub fn row_test(&self, origin: &RowOrigin<S>) -> RowTest<S> {
        let n = self.unit_normal;
        if S::COURSE_ORDER {
            // A floor or wall too: its `hits` reads one coordinate, but the batch then
            // tests the row's rays in a loop of their own instead of a call each.
            #[cfg(feature = "plan")]
            return RowTest::Plane(self.distance_from(origin.eye));
            #[cfg(not(feature = "plan"))]
            return RowTest::Hits;
        }
        if n.x != S::ZERO {
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
        write::vector(out, Attr::Normal, self.normal, 1.0)?;
        write::vector(out, Attr::Point, self.point, scale)
    }

    /// The plane kind's function table.
    pub const VTABLE: ObjectVTable<S> = Self::table(plane_hits);

    /// The tables of planes whose unit normal is `+x`, `-x`, `+y`, `-y`, `+z` or `-z`
    /// (floors and walls): their `hits` reads one coordinate where the general one takes
    /// two dot products. Exact: `N . v` with such an `N` is that coordinate or its negation
    /// in every number type (the other products are zeros, which add nothing).
    pub const AXIS_VTABLES: [ObjectVTable<S>; 6] = [
        Self::table(axis_plane_hits::<S, 0, false>),
        Self::table(axis_plane_hits::<S, 0, true>),
        Self::table(axis_plane_hits::<S, 1, false>),
        Self::table(axis_plane_hits::<S, 1, true>),
        Self::table(axis_plane_hits::<S, 2, false>),
        Self::table(axis_plane_hits::<S, 2, true>),
    ];

    const fn table(hits: fn(&Object<S>, &Ray<S>, S) -> Option<S>) -> ObjectVTable<S> {
        ObjectVTable {
            kind: Entity::Plane,
            hits,
            normal: plane_normal,
            row_test: plane_row_test,
            #[cfg(feature = "print")]
            printer: plane_print,
            material: object_material,
            surface: plane_surface,
        }
    }

    /// Which of [`AXIS_VTABLES`](Self::AXIS_VTABLES) fits this plane: `2 axis + 1` for a
    /// unit normal of `-1` along `axis`, `2 axis` for `+1`; `None` for other normals.
    pub fn axis_table(&self) -> Option<usize> {
        unit_axis(self.unit_normal)
    }
}

/// The axis code of a unit vector along an axis (twice the coordinate, plus one for the
/// negative direction): one component exactly `+-1`, the others zero.
pub(crate) fn unit_axis<S: Scalar>(n: Vec3<S>) -> Option<usize> {
    let (z, one) = (S::ZERO, S::ONE);
    let (axis, value) = match (n.x == z, n.y == z, n.z == z) {
        (false, true, true) => (0, n.x),
        (true, false, true) => (1, n.y),
        (true, true, false) => (2, n.z),
        _ => return None,
    };
    if value == one {
        Some(2 * axis)
    } else if value == -one {
        Some(2 * axis + 1)
    } else {
        None
    }
}

/// The seed's `plane_init`: the common part, then the plane's own table and data.
pub fn plane_init<S: Scalar>(
    name: &str,
    material: MaterialId,
    def: &PlaneDef,
    scale: f64,
) -> Result<Object<S>, ErrorKind> {
    plane_object(name, material, Plane::build(def, scale)?)
}

/// A plane object with the table that fits it (one of the axis tables, or the general one).
pub(crate) fn plane_object<S: Scalar>(
    name: &str,
    material: MaterialId,
    plane: Plane<S>,
) -> Result<Object<S>, ErrorKind> {
    let tables: &'static [ObjectVTable<S>; 6] = &Plane::AXIS_VTABLES;
    let vtable = plane
        .axis
        .and_then(|axis| tables.get(usize::from(axis)))
        .unwrap_or(&Plane::VTABLE);
    Object::init(vtable, name, material, Shape::Plane(plane))
}

/// `hits` of a plane.
pub fn plane_hits<S: Scalar>(obj: &Object<S>, ray: &Ray<S>, limit: S) -> Option<S> {
    match obj.shape() {
        Shape::Plane(plane) => plane.nearest(ray, limit),
        _ => None,
    }
}

/// `hits` of a plane whose unit normal is `+1` (or `-1` when `NEGATIVE`) along axis
/// `AXIS`: [`Plane::nearest`] with the dot products read off one coordinate.
pub fn axis_plane_hits<S: Scalar, const AXIS: u8, const NEGATIVE: bool>(
    obj: &Object<S>,
    ray: &Ray<S>,
    limit: S,
) -> Option<S> {
    match obj.shape() {
        Shape::Plane(plane) => plane.nearest_along(AXIS, NEGATIVE, ray, limit),
        _ => None,
    }
}

/// `surface` of the plane and the finite plane: the unit normal, the object's material.
pub fn plane_surface<'s, S: Scalar>(
    obj: &Object<S>,
    palette: &Palette<'s, S>,
    ray: &Ray<S>,
    t: S,
    out: &mut Option<Surface<'s, S>>,
) {
    object_surface(obj, palette, ray, t, plane_normal, out);
}

/// `row_test` of the infinite plane kinds (plane, tiled plane).
pub fn plane_row_test<S: Scalar>(obj: &Object<S>, origin: &RowOrigin<S>) -> RowTest<S> {
    match obj.shape() {
        Shape::Plane(plane) => plane.row_test(origin),
        Shape::TiledPlane(tiled) => tiled.rect.plane.row_test(origin),
        _ => RowTest::Hits,
    }
}

/// `row_test` of the finite plane kinds (finite plane, textured plane): in `f64` each ray
/// tested, with the plane's `N.point - N.eye` worked out once (their bounds depend on
/// `x`); in the other types, where the normal has no x part, the run of columns that meets
/// the rectangle ([`Rect::row_test`](super::fplane::Rect::row_test)), except when built for
/// size.
pub fn rect_row_test<S: Scalar>(obj: &Object<S>, origin: &RowOrigin<S>) -> RowTest<S> {
    let rect = match obj.shape() {
        Shape::FPlane(rect) => rect,
        Shape::TexPlane(textured) => &textured.rect,
        _ => return RowTest::Hits,
    };
    // Row tests come from the plan only.
    #[cfg(feature = "plan")]
    if S::COURSE_ORDER {
        return RowTest::Plane(rect.plane.distance_from(origin.eye));
    } else if !cfg!(microray_small) {
        return rect.row_test(origin);
    }
    let _ = (rect, origin);
    RowTest::Hits
}

/// `normal` of the plane kinds: the unit normal, everywhere.
pub fn plane_normal<S: Scalar>(obj: &Object<S>, _: Vec3<S>) -> Vec3<S> {
    match obj.shape() {
        Shape::Plane(plane) => plane.unit_normal,
        Shape::FPlane(rect) => rect.plane.unit_normal,
        Shape::TiledPlane(tiled) => tiled.rect.plane.unit_normal,
        Shape::TexPlane(textured) => textured.rect.plane.unit_normal,
        Shape::Sphere(_) | Shape::RevSurf(_) => Vec3::ZERO,
    }
}

/// The coordinate of `v` along an axis code (twice the coordinate, plus one for the
/// negative direction, which negates it): `n . v` for the unit vector `n` of that code.
#[cfg(feature = "plan")]
#[inline(always)]
pub(crate) fn coordinate<S: Scalar>(v: Vec3<S>, axis: u8) -> S {
    signed(pick(&v, axis / 2), axis)
}

/// Coordinate `i` of `v` (0 for x, 1 for y, 2 for z).
#[inline(always)]
pub(crate) fn pick<S: Scalar>(v: &Vec3<S>, i: u8) -> S {
    match i {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

/// `c`, negated for an odd axis code (a negative direction, as [`coordinate`] reads it).
#[inline(always)]
pub(crate) fn signed<S: Scalar>(c: S, code: u8) -> S {
    if code % 2 == 1 { -c } else { c }
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
    write::footer(out)
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

    /// The axis tables' `hits` against the general one, in one number type.
    fn axis_hits_equal_general<S: Scalar>(v: &[f64; 8], limit: f64) {
        for (axis, n) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
            .into_iter()
            .enumerate()
        {
            for sign in [1.0, -1.0] {
                let def = PlaneDef {
                    normal: n.map(|c| c * sign * 3.0),
                    point: [v[0], v[0], v[0]],
                };
                let obj = plane_init::<S>("p", 0, &def, 1.0).unwrap();
                let Shape::Plane(plane) = obj.shape() else {
                    panic!("not a plane")
                };
                let table = 2 * axis + usize::from(sign < 0.0);
                assert_eq!(plane.axis_table(), Some(table));
                let ray = Ray::new(
                    Vec3::new(v[1], v[2], v[3]).cast::<S>(),
                    Vec3::new(v[4], v[5], v[6]).cast::<S>(),
                );
                let limit = S::from_f64(limit);
                let axis_hits = Plane::AXIS_VTABLES[table].hits;
                assert_eq!(
                    axis_hits(&obj, &ray, limit),
                    plane.nearest(&ray, limit),
                    "{v:?}"
                );
                assert_eq!(obj.hits(&ray, limit), plane.nearest(&ray, limit), "{v:?}");
                assert_eq!(
                    plane.nearest_by_axis(&ray, limit),
                    plane.nearest(&ray, limit)
                );
                assert_eq!(
                    obj.hits(&ray, S::UNBOUNDED),
                    plane.nearest(&ray, S::UNBOUNDED)
                );
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn axis_tables_hit_where_the_general_plane_does(
            v in proptest::array::uniform8(-100.0f64..100.0),
            limit in 0.0f64..300.0,
        ) {
            // Zeros in the direction too: parallel rays.
            let mut w = v;
            w[5] = if w[7] > 50.0 { 0.0 } else { w[5] };
            axis_hits_equal_general::<f64>(&w, limit);
            axis_hits_equal_general::<f32>(&w, limit);
            axis_hits_equal_general::<crate::scalar::I16F16>(&w, limit);
        }
    }

    #[test]
    fn other_normals_keep_the_general_table() {
        let p = Plane::<f32>::build(
            &PlaneDef {
                normal: [0.0, 1.0, 1.0],
                point: [0.0; 3],
            },
            1.0,
        )
        .unwrap();
        assert_eq!(p.axis_table(), None);
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
