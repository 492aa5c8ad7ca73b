//! The tiled plane: an infinite checkerboard of two materials.

use super::plane::plane_normal;
use super::{Hit, Object, ObjectVTable, Palette, Shape, Surface, write_surface};
use crate::error::{Entity, ErrorKind};
use crate::material::MaterialId;
use crate::object::fplane::{Rect, RectDef};
use crate::ray::Ray;
use crate::scalar::Scalar;
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use crate::write;
#[cfg(feature = "print")]
use core::fmt;

/// The course's offset that keeps tile indices positive; it changes the parity for some tile
/// sizes, so it is kept.
pub const TILE_OFFSET: f64 = 100_000.0;

/// A checkerboard plane: the rectangle's axes and tile size, and the second material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TiledPlane<S> {
    /// The plane, its axes and the tile size (`dimensions`).
    pub rect: Rect<S>,
    /// The material of tiles where `ix + iy` is even.
    pub altmaterial: MaterialId,
    /// `100000 / dimensions`, split into its integer part's parity and its fraction, so that
    /// no type has to hold 100000 (Q16.16 cannot).
    pub offset: [(bool, S); 2],
    /// The tile size as written. The offset amplifies any rounding of the size 100000 times
    /// (Q16.16's rounding of 1.6 would shift the board by a quarter tile), so it is computed
    /// from this, and the printer writes this.
    pub written_dimensions: [f64; 2],
}

impl<S: Scalar> TiledPlane<S> {
    fn build(def: &RectDef, altmaterial: MaterialId, scale: f64) -> Result<Self, ErrorKind> {
        let rect = Rect::build(def, scale)?;
        // The offset scales with the sizes, so their ratio is the same in a scaled scene.
        let split = |size: f64| {
            let tiles = TILE_OFFSET / size;
            let whole = libm::floor(tiles);
            (libm::fmod(whole, 2.0) != 0.0, S::from_f64(tiles - whole))
        };
        let offset = [split(def.dimensions[0]), split(def.dimensions[1])];
        Ok(Self {
            rect,
            altmaterial,
            offset,
            written_dimensions: def.dimensions,
        })
    }
}

impl<S: Scalar> TiledPlane<S> {
    /// Whether the tile under `hit` uses `altmaterial`: with `q = R' hit` (the hit point
    /// itself, not relative to `point`), `ix = floor((q.x + 100000) / width)`, likewise `iy`;
    /// even `ix + iy` is the alternate material.
    #[inline]
    pub fn is_alternate(&self, point: Vec3<S>) -> bool {
        // floor((q + 100000) / w) = K + floor(q / w + f) where 100000 / w = K + f: only the
        // parity of K is kept.
        let [w, h] = self.rect.dimensions;
        let [(odd_x, fx), (odd_y, fy)] = self.offset;
        // The parity of ix + iy (wrapping) is that of ix xor that of iy.
        let odd_ix = (self.rect.u.dot(point) / w + fx).floor_is_odd();
        let odd_iy = (self.rect.v.dot(point) / h + fy).floor_is_odd();
        !(odd_ix ^ odd_iy ^ odd_x ^ odd_y)
    }

    /// The tiled plane kind's function table: the plane's `hits`, and a material look-up
    /// that the surface look-up follows.
    pub const VTABLE: ObjectVTable<S> = ObjectVTable {
        kind: Entity::TiledPlane,
        hits: tiled_plane_hits,
        normal: plane_normal,
        row_test: super::plane::plane_row_test,
        #[cfg(feature = "print")]
        printer: tiled_plane_print,
        material: tiled_plane_material,
        surface: tiled_plane_surface,
    };
}

/// Builds a tiled plane and installs its table.
pub fn tiled_plane_init<S: Scalar>(
    name: &str,
    material: MaterialId,
    def: &RectDef,
    altmaterial: MaterialId,
    scale: f64,
) -> Result<Object<S>, ErrorKind> {
    let tiled = TiledPlane::build(def, altmaterial, scale)?;
    Object::init(
        &TiledPlane::VTABLE,
        name,
        material,
        Shape::TiledPlane(tiled),
    )
}

/// `hits` of a tiled plane: the infinite plane's.
pub fn tiled_plane_hits<S: Scalar>(obj: &Object<S>, ray: &Ray<S>, limit: S) -> Option<S> {
    match obj.shape() {
        Shape::TiledPlane(tiled) => tiled.rect.plane.nearest_by_axis(ray, limit),
        _ => None,
    }
}

/// The material look-up of a tiled plane: the parity rule.
pub fn tiled_plane_material<S: Scalar>(obj: &Object<S>, point: Vec3<S>) -> MaterialId {
    match obj.shape() {
        Shape::TiledPlane(tiled) if tiled.is_alternate(point) => tiled.altmaterial,
        _ => obj.material(),
    }
}

/// `surface` of a tiled plane: the plane's normal, the material of the tile (the shape
/// matched once: the kind's table is installed only on tiled planes). Always inlined into
/// the batch, whose copies would otherwise call it.
#[inline(always)]
pub fn tiled_plane_surface<'s, S: Scalar>(
    obj: &Object<S>,
    palette: &Palette<'s, S>,
    ray: &Ray<S>,
    t: S,
    out: &mut Option<Surface<'s, S>>,
) {
    let Shape::TiledPlane(tiled) = obj.shape() else {
        *out = None;
        return;
    };
    let point = ray.at(t);
    let material = if tiled.is_alternate(point) {
        tiled.altmaterial
    } else {
        obj.material()
    };
    let hit = Hit {
        t,
        point,
        normal: tiled.rect.plane.unit_normal,
    };
    write_surface(out, hit, palette.material(material));
}

/// `printer` of a tiled plane.
#[cfg(feature = "print")]
pub fn tiled_plane_print<S: Scalar>(
    obj: &Object<S>,
    palette: &super::Palette<'_, S>,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    super::object_print(obj, palette, out)?;
    if let Shape::TiledPlane(tiled) = obj.shape() {
        tiled.rect.plane.print_attributes(out, palette.scale)?;
        write::vector(out, crate::error::Attr::Xdir, tiled.rect.xdir, 1.0)?;
        write::numbers(
            out,
            crate::error::Attr::Dimensions,
            &tiled.written_dimensions,
            1.0,
        )?;
        super::material_ref(
            out,
            crate::error::Attr::Altmaterial,
            palette,
            tiled.altmaterial,
        )?;
    }
    write::footer(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::test_support::{camera, materials, ray};
    use crate::vec3::Vec3;

    #[test]
    fn parity_picks_altmaterial() {
        // Floor y = -1, unit tiles, x axis along x. Material 0 is red, altmaterial 1 is gray.
        let def = RectDef::new(
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0],
        );
        let obj: Object<f64> = tiled_plane_init("t", 0, &def, 1, 1.0).unwrap();
        let mats = materials();
        let cam = camera();
        let palette = super::super::Palette {
            materials: &mats,
            textures: &[],
            camera: &cam,
            scale: 1.0,
            limits: crate::ray::Limits::at_scale(1.0),
        };
        // u = (1,0,0), v = n x u = (0,0,-1): q = (x, -z).
        let at = |x: f64, z: f64| {
            let r = ray([x, 1.0, z], [0.0, -1.0, 0.0]);
            let surface = obj
                .surface(&palette, &r, obj.hits(&r, f64::INFINITY).unwrap())
                .unwrap();
            (
                obj.material_at(surface.hit.point),
                surface.ambient,
                surface.material.specular,
            )
        };
        // x = 0.5, z = -0.5: ix = floor(100000.5) = 100000, iy = floor(100000.5): even → alt.
        assert_eq!(
            at(0.5, -0.5),
            (1, Vec3::new(0.5, 0.5, 0.5), Vec3::new(0.25, 0.25, 0.25))
        );
        // One tile over in x: odd → own material.
        assert_eq!(at(1.5, -0.5), (0, Vec3::new(1.0, 0.0, 0.0), Vec3::ZERO));
        // One tile over in z as well: even again.
        assert_eq!(at(1.5, -1.5).0, 1);
        // Negative coordinates floor, not truncate: x = -0.5 is tile 99999 (odd).
        assert_eq!(at(-0.5, -0.5).0, 0);
        // Far below -100000 the parity still alternates (the course's truncation broke here).
        assert_ne!(at(-200000.5, -0.5).0, at(-200001.5, -0.5).0);
    }
}
