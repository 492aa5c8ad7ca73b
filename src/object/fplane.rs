//! The finite plane (`fplane`): a rectangle on a plane, and the in-plane axes that the tiled
//! and textured planes share.

use super::plane::{pick, plane_normal, plane_surface, signed};
use super::{Hit, Object, ObjectVTable, Shape, object_material};
use crate::error::{Attr, Entity, ErrorKind};
use crate::material::MaterialId;
use crate::object::plane::{Plane, PlaneDef};
use crate::ray::Ray;
use crate::scalar::{Scalar, load_direction, load_length};
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use crate::write;
#[cfg(feature = "print")]
use core::fmt;

/// A rectangle as written: a plane, the direction of its x axis, and its size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RectDef {
    /// The normal.
    pub normal: [f64; 3],
    /// The rectangle's corner (local origin).
    pub point: [f64; 3],
    /// The x axis before projection onto the plane (must not be along the normal).
    pub xdir: [f64; 3],
    /// Width and height along the local x and y axes.
    pub dimensions: [f64; 2],
}

impl RectDef {
    /// A rectangle definition.
    pub const fn new(
        normal: [f64; 3],
        point: [f64; 3],
        xdir: [f64; 3],
        dimensions: [f64; 2],
    ) -> Self {
        Self {
            normal,
            point,
            xdir,
            dimensions,
        }
    }
}

/// A plane with in-plane axes: the rows `(u, v, n)` of the rotation `R` into plane
/// coordinates, `u = unit(xdir projected onto the plane)`, `v = n x u`, computed at load.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect<S> {
    /// The plane.
    pub plane: Plane<S>,
    /// `xdir` as written.
    pub xdir: Vec3<S>,
    /// Width and height.
    pub dimensions: [S; 2],
    /// Local x axis.
    pub u: Vec3<S>,
    /// Local y axis.
    pub v: Vec3<S>,
    /// Where the plane reads its normal off an axis and `u` and `v` lie along axes too
    /// ([`axes`](Self::axes)): the axis each of the normal, `u` and `v` reads (as
    /// [`Plane::read_axis`]'s code: twice the coordinate, plus one for the negative
    /// direction), and the pair of the normal's and `u`'s axes as `3 n + x` (the table's
    /// own, see [`fplane_axes_hits`]), so that a test checks one byte; else `NO_PAIR`.
    /// Four bytes, which fit where the object slot had room (firmware keeps arrays of them).
    codes: [u8; 3],
    pair: u8,
}

/// [`Rect`]'s `pair` of a rectangle off the axes.
const NO_PAIR: u8 = u8::MAX;

impl<S: Scalar> Rect<S> {
    /// The corner and the two sides from it (width along `u`, height along `v`), in `f64`:
    /// what bounds the rectangle (the tree's boxes, the shadows' cones).
    pub(crate) fn corner_and_sides(&self) -> [Vec3<f64>; 3] {
        [
            self.plane.point.to_f64(),
            self.u.to_f64() * self.dimensions[0].to_f64(),
            self.v.to_f64() * self.dimensions[1].to_f64(),
        ]
    }

    /// Checks a definition: a plane's checks, `xdir` not along the normal, positive size.
    pub(crate) fn build(def: &RectDef, scale: f64) -> Result<Self, ErrorKind> {
        let plane = Plane::build(
            &PlaneDef {
                normal: def.normal,
                point: def.point,
            },
            scale,
        )?;
        let xdir = load_direction::<S>(def.xdir, Attr::Xdir)?;
        let dimensions = [
            load_length::<S>(def.dimensions[0], scale, Attr::Dimensions)?,
            load_length::<S>(def.dimensions[1], scale, Attr::Dimensions)?,
        ];
        let n = plane.unit_normal.to_f64();
        let x = xdir.to_f64();
        if x.is_zero() {
            return Err(ErrorKind::ZeroVector { attr: Attr::Xdir });
        }
        // Parallel when the sine of the angle to the written normal is at rounding level:
        // the projection below would then be rounding noise, not a direction.
        let written = plane.normal.to_f64();
        let sine = crate::scalar::sqrt_f64(written.cross(x).dot(written.cross(x)))
            / crate::scalar::sqrt_f64(written.dot(written) * x.dot(x));
        if !(sine > 1e-12) {
            return Err(ErrorKind::XdirParallelToNormal);
        }
        let u = (x - n * x.dot(n))
            .unit_f64()
            .ok_or(ErrorKind::XdirParallelToNormal)?;
        let v = n.cross(u);
        Ok(Self::new(plane, xdir, dimensions, u.cast(), v.cast()))
    }

    /// A rectangle of checked parts (a compiled scene's).
    pub(crate) fn new(
        plane: Plane<S>,
        xdir: Vec3<S>,
        dimensions: [S; 2],
        u: Vec3<S>,
        v: Vec3<S>,
    ) -> Self {
        // Three different axes (so `d`'s third coordinate is the plane's own).
        let axis = |v| super::plane::unit_axis(v).and_then(|a| u8::try_from(a).ok());
        let axes = match (plane.read_axis(), axis(u), axis(v)) {
            (Some(n), Some(x), Some(y)) if n / 2 != x / 2 && n / 2 != y / 2 && x / 2 != y / 2 => {
                Some([x, y])
            }
            _ => None,
        };
        let (codes, pair) = match (plane.read_axis(), axes) {
            (Some(n), Some([x, y])) => ([n, x, y], 3 * (n / 2) + x / 2),
            _ => ([0; 3], NO_PAIR),
        };
        Self {
            plane,
            xdir,
            dimensions,
            u,
            v,
            codes,
            pair,
        }
    }

    /// The axes `u` and `v` lie along where the plane reads its normal off an axis too
    /// (codes as [`Plane::read_axis`]'s): the finite plane then gets a table whose `hits`
    /// reads them (see [`fplane_vtable`](Self::fplane_vtable)).
    pub fn axes(&self) -> Option<[u8; 2]> {
        let [_, x, y] = self.codes;
        (self.pair != NO_PAIR).then_some([x, y])
    }

    /// [`nearest`](Self::nearest) for a rectangle on [`axes`](Self::axes), with the axes'
    /// indices (`[normal, u, v]`, 0 for x to 2 for z) known where it is compiled and their
    /// codes (with the signs) given: the plane's test along its axis as
    /// `Plane::nearest_by_axis` makes it and the bounds as [`local`](Self::local)'s dot
    /// products find them (see [`within_on_known_axes`](Self::within_on_known_axes)), without
    /// choosing the coordinates at each call.
    #[inline(always)]
    fn nearest_on_known_axes(
        &self,
        index: [u8; 3],
        codes: [u8; 3],
        ray: &Ray<S>,
        limit: S,
    ) -> Option<S> {
        let [n, x, y] = index;
        let t = S::parameter_within(
            self.plane.n_dot_point - signed(pick(&ray.base, n), codes[0]),
            signed(pick(&ray.dir, n), codes[0]),
            limit,
        )?;
        self.within_on_known_axes([x, y], [codes[1], codes[2]], ray, t)
            .then_some(t)
    }

    /// [`nearest_from`](Self::nearest_from) for a rectangle on [`axes`](Self::axes), the
    /// axes known as in [`nearest_on_known_axes`](Self::nearest_on_known_axes): the plane's
    /// test as `Plane::nearest_from` makes it.
    #[cfg(all(feature = "plan", feature = "batch"))]
    #[inline(always)]
    pub(crate) fn nearest_from_on_known_axes(
        &self,
        index: [u8; 3],
        codes: [u8; 3],
        distance: S,
        ray: &Ray<S>,
        limit: S,
    ) -> Option<S> {
        let [n, x, y] = index;
        let t = S::parameter_within(distance, signed(pick(&ray.dir, n), codes[0]), limit)?;
        self.within_on_known_axes([x, y], [codes[1], codes[2]], ray, t)
            .then_some(t)
    }

    /// Whether the hit at `t` along `ray` lies within the rectangle, for a rectangle on
    /// [`axes`](Self::axes) (`[u, v]`'s indices and codes): `(+-1, 0, 0) . d` is `+-d.x`,
    /// and the other products are zeros (where `d` is not finite they make the sum NaN, but
    /// then a coordinate read here is not finite either: the plane's own coordinate of a
    /// hit on it is finite), so the same answer as [`local`](Self::local)'s dot products,
    /// with a shorter chain.
    #[inline(always)]
    fn within_on_known_axes(&self, [x, y]: [u8; 2], codes: [u8; 2], ray: &Ray<S>, t: S) -> bool {
        // The point's coordinate as `ray.at(t)` computes it, less the corner's.
        let along = |i: u8, code: u8| {
            let q = pick(&ray.base, i) + pick(&ray.dir, i) * t - pick(&self.plane.point, i);
            signed(q, code)
        };
        let (qx, qy) = (along(x, codes[0]), along(y, codes[1]));
        let [w, h] = self.dimensions;
        qx >= S::ZERO && qx <= w && qy >= S::ZERO && qy <= h
    }

    /// `(u, v) . (p - point)`: a point's coordinates within the rectangle.
    #[inline]
    pub fn local(&self, p: Vec3<S>) -> [S; 2] {
        let d = p - self.plane.point;
        [self.u.dot(d), self.v.dot(d)]
    }

    /// The plane's hit below `limit`, if it lies within `0 <= q <= dimensions`.
    #[cfg_attr(feature = "batch", inline(always))]
    #[cfg_attr(not(feature = "batch"), inline)]
    pub fn nearest(&self, ray: &Ray<S>, limit: S) -> Option<S> {
        let t = self.plane.nearest_by_axis(ray, limit)?;
        // The plane test read the ray one component a load (see `Ray::read_apart`) unless
        // it read one coordinate off an axis.
        let point = if self.plane.read_axis().is_some() {
            ray.read_apart().at(t)
        } else {
            ray.at(t)
        };
        let [qx, qy] = self.local(point);
        let [w, h] = self.dimensions;
        (qx >= S::ZERO && qx <= w && qy >= S::ZERO && qy <= h).then_some(t)
    }

    /// [`nearest`](Self::nearest) with the plane's `N.point - N.base` given (see
    /// [`Plane::nearest_from`]). (Written out, not shared with `nearest`: the shadow
    /// rays' `hits` is inlined better so.) Always inlined into the batch's row loop.
    #[cfg(feature = "plan")]
    #[cfg_attr(feature = "batch", inline(always))]
    #[cfg_attr(not(feature = "batch"), inline)]
    pub fn nearest_from(&self, distance: S, ray: &Ray<S>, limit: S) -> Option<S> {
        let t = self.plane.nearest_from(distance, ray.dir, limit)?;
        let [qx, qy] = self.local(ray.at(t));
        let [w, h] = self.dimensions;
        (qx >= S::ZERO && qx <= w && qy >= S::ZERO && qy <= h).then_some(t)
    }

    /// The nearest hit as a hit record.
    pub fn intersect(&self, ray: &Ray<S>) -> Option<Hit<S>> {
        self.nearest(ray, S::UNBOUNDED).map(|t| Hit {
            t,
            point: ray.at(t),
            normal: self.plane.unit_normal,
        })
    }

    /// Writes the plane's attributes, `xdir` and `dimensions`.
    #[cfg(feature = "print")]
    pub(crate) fn print_attributes(&self, out: &mut dyn fmt::Write, scale: f64) -> fmt::Result {
        self.plane.print_attributes(out, scale)?;
        write::vector(out, Attr::Xdir, self.xdir, 1.0)?;
        write::numbers(out, Attr::Dimensions, &self.dimensions, scale)
    }

    /// The fplane kind's function table.
    pub const VTABLE: ObjectVTable<S> = ObjectVTable {
        kind: Entity::FPlane,
        hits: fplane_hits,
        normal: plane_normal,
        row_test: super::plane::rect_row_test,
        #[cfg(feature = "print")]
        printer: fplane_print,
        material: object_material,
        surface: plane_surface,
    };

    /// The tables of finite planes on [`axes`](Self::axes), one for each pair of the
    /// normal's axis and `u`'s (`v`'s is the third): its `hits` reads the local coordinates
    /// off those axes, chosen when the function is compiled rather than by the codes at
    /// each call (host builds; the firmware keeps one table in flash). Installed by
    /// [`fplane_vtable`](Self::fplane_vtable) only; on another rectangle its `hits` misses.
    const AXES_VTABLES: [ObjectVTable<S>; 6] = [
        Self::axes_table::<0, 1>(),
        Self::axes_table::<0, 2>(),
        Self::axes_table::<1, 0>(),
        Self::axes_table::<1, 2>(),
        Self::axes_table::<2, 0>(),
        Self::axes_table::<2, 1>(),
    ];

    /// The table of [`AXES_VTABLES`](Self::AXES_VTABLES) for a normal along axis `N`
    /// and `u` along axis `X`.
    const fn axes_table<const N: u8, const X: u8>() -> ObjectVTable<S> {
        ObjectVTable {
            hits: fplane_axes_hits::<S, N, X>,
            ..Self::VTABLE
        }
    }

    /// The table that fits this rectangle as a finite plane.
    pub fn fplane_vtable(&self) -> &'static ObjectVTable<S> {
        // By the pair `3 n + x` the tables check, in the order of `AXES_VTABLES`.
        let table = match self.pair {
            _ if !cfg!(feature = "batch") => None,
            1 => Self::AXES_VTABLES.first(),
            2 => Self::AXES_VTABLES.get(1),
            3 => Self::AXES_VTABLES.get(2),
            5 => Self::AXES_VTABLES.get(3),
            6 => Self::AXES_VTABLES.get(4),
            7 => Self::AXES_VTABLES.get(5),
            _ => None,
        };
        table.unwrap_or(&Self::VTABLE)
    }
}

/// Builds a finite plane and installs its table.
pub fn fplane_init<S: Scalar>(
    name: &str,
    material: MaterialId,
    def: &RectDef,
    scale: f64,
) -> Result<Object<S>, ErrorKind> {
    let rect = Rect::build(def, scale)?;
    Object::init(rect.fplane_vtable(), name, material, Shape::FPlane(rect))
}

/// `hits` of a finite plane.
pub fn fplane_hits<S: Scalar>(obj: &Object<S>, ray: &Ray<S>, limit: S) -> Option<S> {
    match obj.shape() {
        Shape::FPlane(rect) => rect.nearest(ray, limit),
        _ => None,
    }
}

/// `hits` of a finite plane on axes (see [`Rect::axes`]) whose normal lies along axis `N`
/// and whose `u` along axis `X` (0 for x, 1 for y, 2 for z; `v` along the third).
pub fn fplane_axes_hits<S: Scalar, const N: u8, const X: u8>(
    obj: &Object<S>,
    ray: &Ray<S>,
    limit: S,
) -> Option<S> {
    match obj.shape() {
        // One byte says whether the table fits the rectangle; one it is not installed on
        // misses (so that a table chosen wrongly shows in the tests against the general
        // test, every pair of axes).
        Shape::FPlane(rect) if rect.pair == 3 * N + X => {
            rect.nearest_on_known_axes([N, X, 3 - N - X], rect.codes, ray, limit)
        }
        _ => None,
    }
}

/// `printer` of a finite plane.
#[cfg(feature = "print")]
pub fn fplane_print<S: Scalar>(
    obj: &Object<S>,
    palette: &super::Palette<'_, S>,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    super::object_print(obj, palette, out)?;
    if let Shape::FPlane(rect) = obj.shape() {
        rect.print_attributes(out, palette.scale)?;
    }
    write::footer(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::test_support::ray;

    fn tilted() -> RectDef {
        // fplane1's rectangle: 6 x 3 on the plane y + z = -3, corner (1, 0, -3).
        RectDef::new(
            [0.0, 1.0, 1.0],
            [1.0, 0.0, -3.0],
            [1.0, 0.0, 0.0],
            [6.0, 3.0],
        )
    }

    #[test]
    fn axes_are_orthonormal_rows() {
        let r = Rect::<f64>::build(&tilted(), 1.0).unwrap();
        assert_eq!(r.u, Vec3::new(1.0, 0.0, 0.0));
        let s = core::f64::consts::FRAC_1_SQRT_2;
        assert!((r.v - Vec3::new(0.0, s, -s)).length() < 1e-15);
        assert!(r.u.dot(r.v).abs() < 1e-15 && r.v.dot(r.plane.unit_normal).abs() < 1e-15);
    }

    #[test]
    fn hits_inside_only() {
        let obj: Object<f64> = fplane_init("f", 0, &tilted(), 1.0).unwrap();
        let Shape::FPlane(rect) = obj.shape() else {
            panic!("not an fplane")
        };
        // Local (1, sqrt 2) is the world point (2, 1, -4).
        let hit = obj.hit(&ray([2.0, 3.0, -2.0], [0.0, -1.0, -1.0])).unwrap();
        assert!((hit.point - Vec3::new(2.0, 1.0, -4.0)).length() < 1e-12);
        let [qx, qy] = rect.local(hit.point);
        assert!((qx - 1.0).abs() < 1e-12 && (qy - 2f64.sqrt()).abs() < 1e-12);
        // The same ray moved beyond the width (x = 7.5) or before the corner (x = 0.5).
        assert_eq!(obj.hit(&ray([7.5, 3.0, -2.0], [0.0, -1.0, -1.0])), None);
        assert_eq!(obj.hit(&ray([0.5, 3.0, -2.0], [0.0, -1.0, -1.0])), None);
        // Beyond the height: local y = 3.5 is the point (2, 2.47, -5.47).
        assert_eq!(obj.hit(&ray([2.0, 6.0, -2.0], [0.0, -1.0, -1.0])), None);
        // The infinite plane under it is hit there.
        assert!(
            rect.plane
                .intersect(&ray([2.0, 6.0, -2.0], [0.0, -1.0, -1.0]))
                .is_some()
        );
    }

    /// Every rectangle whose plane and axes lie along the coordinate axes (both signs of
    /// each, every pairing), against the general test's dot products, in every type.
    fn axes_hits_equal_general<S: Scalar>(v: &[f64; 9], limit: f64) {
        let e = |axis: usize, sign: f64| {
            let mut c = [0.0; 3];
            c[axis] = sign;
            c
        };
        for n_axis in 0..3 {
            for (n_sign, x_sign) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                let x_axis = (n_axis + 1 + usize::from(v[8] > 0.0)) % 3;
                let def = RectDef::new(
                    e(n_axis, n_sign * 2.0),
                    [v[0], v[1], v[0] - v[1]],
                    e(x_axis, x_sign * 3.0),
                    [2.5, 1.5],
                );
                let obj = fplane_init::<S>("f", 0, &def, 1.0).unwrap();
                let Shape::FPlane(rect) = obj.shape() else {
                    panic!("not an fplane")
                };
                // (`obj.hits` goes through the table installed for it.)
                assert_eq!(rect.axes().is_some(), S::AXIS_READS, "{def:?}");
                let ray = Ray::new(
                    Vec3::new(v[2], v[3], v[4]).cast::<S>(),
                    Vec3::new(v[5], v[6], v[7]).cast::<S>(),
                );
                let limit = S::from_f64(limit);
                assert_eq!(obj.hits(&ray, limit), rect.nearest(&ray, limit), "{v:?}");
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn axes_tables_hit_where_the_general_rectangle_does(
            v in proptest::array::uniform9(-4.0f64..4.0),
            limit in 0.0f64..30.0,
        ) {
            axes_hits_equal_general::<f64>(&v, limit);
            axes_hits_equal_general::<f32>(&v, limit);
            axes_hits_equal_general::<crate::scalar::I16F16>(&v, limit);
        }
    }

    #[test]
    fn leaning_rectangles_keep_the_general_table() {
        let obj: Object<f64> = fplane_init("f", 0, &tilted(), 1.0).unwrap();
        let Shape::FPlane(rect) = obj.shape() else {
            panic!("not an fplane")
        };
        assert_eq!(rect.axes(), None);
    }

    #[test]
    fn degenerate_axes_are_errors() {
        let mut def = tilted();
        def.xdir = [0.0, 2.0, 2.0];
        assert_eq!(
            Rect::<f64>::build(&def, 1.0),
            Err(ErrorKind::XdirParallelToNormal)
        );
        def.xdir = [0.0, 0.1, 0.1];
        assert_eq!(
            Rect::<f64>::build(&def, 1.0),
            Err(ErrorKind::XdirParallelToNormal)
        );
        def.xdir = [0.0; 3];
        assert_eq!(
            Rect::<f64>::build(&def, 1.0),
            Err(ErrorKind::ZeroVector { attr: Attr::Xdir })
        );
        def = tilted();
        def.dimensions = [6.0, 0.0];
        assert_eq!(
            Rect::<f64>::build(&def, 1.0),
            Err(ErrorKind::NotPositive {
                attr: Attr::Dimensions
            })
        );
    }
}
