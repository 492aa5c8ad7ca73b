//! The finite plane (`fplane`): a rectangle on a plane, and the in-plane axes that the tiled
//! and textured planes share.

use super::plane::{pick, plane_normal, plane_surface, signed};
use super::{Hit, Object, ObjectVTable, Shape, object_material};
#[cfg(feature = "plan")]
use super::{RowOrigin, RowTest};
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

    /// [`corner_and_sides`](Self::corner_and_sides) in the render plan's geometry type.
    pub(crate) fn corner_and_sides_geo(&self) -> [Vec3<crate::scalar::geometry::Geo>; 3] {
        use crate::scalar::geometry;
        if !geometry::SINGLE {
            // The same function where the geometry is `f64`: one copy in flash.
            return self.corner_and_sides().map(geometry::narrow);
        }
        [
            self.plane.point.to_geo(),
            self.u.to_geo() * self.dimensions[0].to_geo(),
            self.v.to_geo() * self.dimensions[1].to_geo(),
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

    /// Whether a point of the plane lies within `0 <= q <= dimensions`, as
    /// [`nearest`](Self::nearest) decides it for its hit.
    #[inline(always)]
    pub fn holds(&self, point: Vec3<S>) -> bool {
        let [qx, qy] = self.local(point);
        let [w, h] = self.dimensions;
        qx >= S::ZERO && qx <= w && qy >= S::ZERO && qy <= h
    }

    /// The plane's hit below `limit`, if it lies within `0 <= q <= dimensions`.
    #[cfg_attr(feature = "batch", inline(always))]
    #[cfg_attr(not(feature = "batch"), inline)]
    pub fn nearest(&self, ray: &Ray<S>, limit: S) -> Option<S> {
        self.nearest_in_line(ray, limit)
    }

    /// [`nearest`](Self::nearest), always in line but built for size: for the kinds'
    /// `hits`, where a test through the kind's table made two calls (the compiler keeps
    /// `nearest`, which has other callers, out of line).
    #[cfg_attr(not(microray_small), inline(always))]
    #[cfg_attr(microray_small, inline)]
    pub(crate) fn nearest_in_line(&self, ray: &Ray<S>, limit: S) -> Option<S> {
        let t = self.plane.nearest_by_axis(ray, limit)?;
        // The plane test read the ray one component a load (see `Ray::read_apart`) unless
        // it read one coordinate off an axis.
        let point = if self.plane.read_axis().is_some() {
            ray.read_apart().at(t)
        } else {
            ray.at(t)
        };
        self.holds(point).then_some(t)
    }

    /// The test of a row's primary rays when the plane's normal has no x part, in the
    /// types that leave primary rays unnormalised: every ray meets the plane at the same
    /// `t` (see [`Plane::row_test`]), and the rays that meet the rectangle are one run of
    /// columns, found by bisection with the test each ray would make.
    ///
    /// Why a run: along the row only the ray's `x` changes, and it grows with the column.
    /// The hit point's `x` (`eye.x + dir.x t`, `t > 0`), its offset from the corner and
    /// each local coordinate (`u . d`, `v . d`, whose other products are the same along
    /// the row) are then monotone in the column, since each rounded operation is monotone
    /// in each operand (saturation too). So each of `q >= 0` and `q <= size` holds on a
    /// prefix or a suffix of the row, which its values at the two ends tell, and their
    /// intersection is a run. Values beyond the type's range at either end (where an
    /// infinity could meet a zero or another infinity) leave each ray to its test.
    #[cfg(feature = "plan")]
    pub fn row_test(&self, origin: &RowOrigin<S>) -> RowTest<S> {
        let columns = &origin.columns;
        let count = columns.count();
        if S::COURSE_ORDER || self.plane.unit_normal.x != S::ZERO || count == 0 {
            return RowTest::Hits;
        }
        let ray = |column| {
            Ray::new(
                origin.eye,
                Vec3::new(columns.dir_x(column), origin.dy, origin.dz),
            )
        };
        // A finite limit, and no hit below it left to each ray's test: with an infinite
        // one, the RP2040's ROM float routines (the Pico's `f32` build) lost the
        // showcase's picture (a product with infinity is not IEEE's there).
        let t = match self.plane.nearest_by_axis(&ray(0), S::from_i32(1 << 20)) {
            Some(t) if origin.eye.z + origin.dz * t <= origin.z_limit => t,
            Some(_) => return RowTest::Miss,
            None => return RowTest::Hits,
        };
        let local = |column| self.local(ray(column).at(t));
        let last = count - 1;
        // At either end, the hit point and its coordinates within the range.
        let ends = [0, last].map(|column| {
            let p = ray(column).at(t);
            let [qx, qy] = self.local(p);
            let finite = ![p.x, p.y, p.z, qx, qy].into_iter().any(S::is_beyond_range);
            finite.then_some([qx, qy])
        });
        let [Some(at_first), Some(at_last)] = ends else {
            return RowTest::Hits;
        };
        if t.is_beyond_range() {
            return RowTest::Hits;
        }
        // The run `first..end` of columns whose rays meet the rectangle.
        let (mut first, mut end) = (0, count);
        for (axis, size) in [(0, self.dimensions[0]), (1, self.dimensions[1])] {
            let pick = |[qx, qy]: [S; 2]| if axis == 0 { qx } else { qy };
            let q = |column| pick(local(column));
            // Each bound holds on a prefix or a suffix of the row: its ends tell which (or
            // that it holds everywhere or nowhere); only a bound that changes is bisected.
            for lower in [true, false] {
                let holds = |q: S| if lower { q >= S::ZERO } else { q <= size };
                match (holds(pick(at_first)), holds(pick(at_last))) {
                    (true, true) => {}
                    (false, false) => return RowTest::Miss,
                    (false, true) => first = first.max(first_holding(last, |c| holds(q(c)))),
                    (true, false) => end = end.min(first_holding(last, |c| !holds(q(c)))),
                }
            }
        }
        if first >= end {
            return RowTest::Miss;
        }
        RowTest::AtAcross {
            t,
            lo: columns.dir_x(first),
            hi: columns.dir_x(end - 1),
            first,
            last: end - 1,
        }
    }

    /// [`nearest`](Self::nearest) with the plane's `N.point - N.base` given (see
    /// [`Plane::nearest_from`]). (Written out, not shared with `nearest`: the shadow
    /// rays' `hits` is inlined better so.) Always inlined into the batch's row loop.
    #[cfg(feature = "plan")]
    #[cfg_attr(feature = "batch", inline(always))]
    #[cfg_attr(not(feature = "batch"), inline)]
    pub fn nearest_from(&self, distance: S, ray: &Ray<S>, limit: S) -> Option<S> {
        let t = self.plane.nearest_from(distance, ray.dir, limit)?;
        self.holds(ray.at(t)).then_some(t)
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
        Shape::FPlane(rect) => rect.nearest_in_line(ray, limit),
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

/// The first column of `1..=last` where `holds` does, for a `holds` that stays true once
/// it is, false at column 0 and true at `last`: a bisection, about `log2(last)` calls.
#[cfg(feature = "plan")]
fn first_holding(last: u16, holds: impl Fn(u16) -> bool) -> u16 {
    let (mut lo, mut hi) = (1, last);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if holds(mid) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo
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

    /// A row's run of columns ([`Rect::row_test`]) against each ray's own test, for the
    /// rays as the row makes them (plain and shifted for anti-aliasing).
    #[cfg(feature = "plan")]
    mod row_run {
        use super::*;
        use crate::camera::{Camera, CameraDef};
        use crate::scalar::I16F16;
        use proptest::prelude::*;

        /// Checks every ray of row `y`: the row test's answer is `hits` with the z rule.
        /// Returns how many rays met the rectangle.
        fn check<S: Scalar>(
            def: &RectDef,
            camera: &CameraDef<'_>,
            y: u16,
            shift: [f64; 2],
        ) -> Result<usize, TestCaseError> {
            let (Ok(rect), Ok(camera)) = (
                Rect::<S>::build(def, 1.0),
                Camera::<S>::build(camera, 1024, 1.0),
            ) else {
                return Ok(0);
            };
            let z_limit = S::from_f64(0.01);
            #[cfg(feature = "antialias")]
            let rays = camera.shifted_row_rays(y, 0, shift.map(S::from_f64));
            #[cfg(not(feature = "antialias"))]
            let rays = {
                let _ = shift;
                camera.row_rays(y, 0)
            };
            let origin = rays.origin(z_limit);
            let test = rect.row_test(&origin);
            let mut met = 0;
            for (column, ray) in (0u16..).zip(rays) {
                let Some(ray) = ray else { continue };
                prop_assert_eq!(origin.columns.dir_x(column), ray.dir.x);
                let hit = rect
                    .nearest(&ray, S::UNBOUNDED)
                    .filter(|&t| ray.base.z + ray.dir.z * t <= z_limit);
                let row = match test {
                    RowTest::Miss => None,
                    RowTest::AtAcross {
                        t,
                        lo,
                        hi,
                        first,
                        last,
                    } => {
                        let inside = ray.dir.x >= lo && ray.dir.x <= hi;
                        prop_assert_eq!(inside, first <= column && column <= last);
                        inside.then_some(t)
                    }
                    RowTest::Hits => hit,
                    other => return Err(TestCaseError::fail(format!("{other:?}"))),
                };
                prop_assert_eq!(row, hit, "column {}", column);
                met += usize::from(hit.is_some());
            }
            Ok(met)
        }

        fn unit_in_yz() -> impl Strategy<Value = [f64; 3]> {
            prop_oneof![
                Just([0.0, 1.0, 0.0]),
                Just([0.0, 0.0, 1.0]),
                Just([0.0, -1.0, 1.0]),
                (-1.0f64..1.0, -1.0f64..1.0).prop_map(|(y, z)| [0.0, y, z]),
            ]
        }

        fn xdir() -> impl Strategy<Value = [f64; 3]> {
            prop_oneof![
                Just([1.0, 0.0, 0.0]),
                Just([-1.0, 0.0, 0.0]),
                Just([0.0, 1.0, 0.0]),
                prop::array::uniform3(-1.0f64..1.0),
            ]
        }

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(400))]
            #[test]
            fn runs_are_each_rays_test(
                normal in unit_in_yz(),
                xdir in xdir(),
                point in [-6.0f64..10.0, -4.0f64..8.0, -12.0f64..1.0],
                size in [0.05f64..9.0, 0.05f64..9.0],
                eye in [-4.0f64..12.0, -4.0f64..10.0, 0.5f64..10.0],
                width in 2u32..200,
                y in 0u16..60,
                shift in [-0.05f64..0.05, -0.05f64..0.05],
            ) {
                let def = RectDef::new(normal, point, xdir, size);
                let camera = CameraDef::new("c", [width, 60], [8.0, 6.0], eye);
                check::<f32>(&def, &camera, y, shift)?;
                check::<I16F16>(&def, &camera, y, shift)?;
            }
        }

        /// Rectangles cut by the row on both sides, on one side and not at all, with a
        /// pixel centre exactly on an edge (texplane1's wall, whose edges lie on columns).
        #[test]
        fn runs_end_where_the_rays_test_ends() {
            let camera = CameraDef::new("c", [640, 480], [8.0, 6.0], [4.0, 3.0, 8.0]);
            for (corner, width) in [(-1.0, 6.0), (2.0, 2.0), (-20.0, 40.0), (5.0, 1.0)] {
                let def = RectDef::new(
                    [0.0, 0.0, 1.0],
                    [corner, 0.0, -4.0],
                    [1.0, 0.0, 0.0],
                    [width, 6.0],
                );
                let mut met = 0;
                for y in [0, 100, 240, 479] {
                    met += check::<f32>(&def, &camera, y, [0.0; 2]).unwrap();
                    met += check::<I16F16>(&def, &camera, y, [0.0; 2]).unwrap();
                }
                assert!(met > 0);
            }
        }
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
