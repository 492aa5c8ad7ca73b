//! The textured plane: a rectangle whose ambient and diffuse colours are multiplied by an
//! image.

use super::plane::plane_normal;
use super::{Hit, Object, ObjectVTable, Palette, Shape, Surface, object_material, object_surface};
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

/// How a texture is laid on its rectangle (`mode` in the scene).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextureMode {
    /// `mode 0`: the image is stretched to fit the rectangle.
    Fit = 0,
    /// `mode 1`: the image repeats, one texel per camera pixel.
    Tile = 1,
}

/// A textured rectangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexPlane<S> {
    /// The rectangle.
    pub rect: Rect<S>,
    /// Index of the texture in the scene.
    pub texture: u16,
    /// How the texture is laid out.
    pub mode: TextureMode,
}

impl<S: Scalar> TexPlane<S> {
    /// The texel under a hit as a colour factor (value / 256); white without a texture.
    #[inline]
    pub fn texel(&self, palette: &Palette<'_, S>, hit: &Hit<S>) -> Vec3<S> {
        self.texel_at(palette, hit.point)
    }

    /// The texel at a point of the rectangle's plane as a colour factor (value / 256);
    /// white without a texture.
    pub fn texel_at(&self, palette: &Palette<'_, S>, point: Vec3<S>) -> Vec3<S> {
        let Some(texture) = palette.textures.get(usize::from(self.texture)) else {
            return Vec3::new(S::ONE, S::ONE, S::ONE);
        };
        let (width, height) = (i32::from(texture.width()), i32::from(texture.height()));
        let [qx, qy] = self.rect.local(point);
        // `q / size * texels` as the course writes it (f64); the other types multiply by
        // the ratio `texels / size` instead, whose rounding the texel count does not
        // multiply (in Q16.16, dividing first puts the texel edge 256 steps off).
        let texels = |q: S, size: S, count: i32| {
            let count = S::from_i32(count);
            if S::COURSE_ORDER {
                (q / size * count).floor_to_i32()
            } else {
                (q * (count / size)).floor_to_i32()
            }
        };
        let (column, row) = match self.mode {
            TextureMode::Fit => {
                let [w, h] = self.rect.dimensions;
                let x = texels(qx, w, width);
                let y = texels(qy, h, height);
                (x.clamp(0, width - 1), y.clamp(0, height - 1))
            }
            TextureMode::Tile => {
                let camera = palette.camera;
                let [world_w, world_h] = camera.world();
                let x = texels(qx, world_w, i32::from(camera.width()));
                let y = texels(qy, world_h, i32::from(camera.height()));
                (x.rem_euclid(width), y.rem_euclid(height))
            }
        };
        // Local y grows upwards; image rows are stored top first.
        let flipped = height - 1 - row;
        let [r, g, b] = texture.texel(
            usize::try_from(column).unwrap_or(0),
            usize::try_from(flipped).unwrap_or(0),
        );
        // `c / 256`, exact in every type (`STEP` is 2^-16), without `f64`: in software on
        // the boards, it was a third of texplane1's instructions on the Cortex-M4F.
        let unit = S::STEP * S::from_i32(256);
        let scale = |c: u8| S::from_i32(i32::from(c)) * unit;
        Vec3::new(scale(r), scale(g), scale(b))
    }

    /// The textured plane kind's function table: the rectangle's `hits`, and a surface
    /// look-up whose ambient and diffuse colours are multiplied by the texel.
    pub const VTABLE: ObjectVTable<S> = ObjectVTable {
        kind: Entity::TexPlane,
        hits: texplane_hits,
        normal: plane_normal,
        row_test: super::plane::rect_row_test,
        #[cfg(feature = "print")]
        printer: texplane_print,
        material: object_material,
        surface: texplane_surface,
    };
}

/// Builds a textured plane and installs its table.
pub fn texplane_init<S: Scalar>(
    name: &str,
    material: MaterialId,
    def: &RectDef,
    texture: u16,
    mode: TextureMode,
    scale: f64,
) -> Result<Object<S>, ErrorKind> {
    let textured = TexPlane {
        rect: Rect::build(def, scale)?,
        texture,
        mode,
    };
    Object::init(&TexPlane::VTABLE, name, material, Shape::TexPlane(textured))
}

/// `hits` of a textured plane: the rectangle's.
pub fn texplane_hits<S: Scalar>(obj: &Object<S>, ray: &Ray<S>, limit: S) -> Option<S> {
    match obj.shape() {
        Shape::TexPlane(textured) => textured.rect.nearest_in_line(ray, limit),
        _ => None,
    }
}

/// The surface look-up of a textured plane: the material's ambient and diffuse colours,
/// times the texel under the hit.
pub fn texplane_surface<'s, S: Scalar>(
    obj: &Object<S>,
    palette: &Palette<'s, S>,
    ray: &Ray<S>,
    t: S,
    out: &mut Option<Surface<'s, S>>,
) {
    object_surface(obj, palette, ray, t, plane_normal, out);
    if let (Some(surface), Shape::TexPlane(textured)) = (out, obj.shape()) {
        let texel = textured.texel(palette, &surface.hit);
        surface.ambient = surface.ambient.mul_each(texel);
        surface.diffuse = surface.diffuse.mul_each(texel);
    }
}

/// `printer` of a textured plane.
#[cfg(feature = "print")]
pub fn texplane_print<S: Scalar>(
    obj: &Object<S>,
    palette: &Palette<'_, S>,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    super::object_print(obj, palette, out)?;
    if let Shape::TexPlane(textured) = obj.shape() {
        textured.rect.print_attributes(out, palette.scale)?;
        let name = palette
            .textures
            .get(usize::from(textured.texture))
            .map_or("", |t| t.name());
        write::word(out, crate::error::Attr::Texname, name)?;
        writeln!(
            out,
            "  {} {}",
            crate::error::Attr::Mode,
            textured.mode as u8
        )?;
    }
    write::footer(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::test_support::{camera, materials, ray};
    use crate::texture::{Texture, TextureDef};

    #[test]
    fn fit_mode_scales_by_texel_with_rows_flipped() {
        // A 2 x 2 image: top row red, white; bottom row green, blue.
        let ppm = b"P6 2 2 255 \xff\x00\x00\xff\xff\xff\x00\xff\x00\x00\x00\xff";
        let textures = [Texture::build(&TextureDef {
            name: "t",
            filename: "t.ppm",
            ppm,
        })
        .unwrap()];
        let mats = materials();
        let cam = camera();
        let palette = Palette {
            materials: &mats,
            textures: &textures,
            camera: &cam,
            scale: 1.0,
            limits: crate::ray::Limits::at_scale(1.0),
        };
        // An 8 x 6 wall at z = -4, material gray (ambient 0.5, diffuse 3).
        let def = RectDef::new(
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -4.0],
            [1.0, 0.0, 0.0],
            [8.0, 6.0],
        );
        let obj: Object<f64> = texplane_init("w", 1, &def, 0, TextureMode::Fit, 1.0).unwrap();
        let look = |x: f64, y: f64| {
            let r = ray([x, y, 0.0], [0.0, 0.0, -1.0]);
            let surface = obj
                .surface(&palette, &r, obj.hits(&r, f64::INFINITY).unwrap())
                .unwrap();
            (surface.ambient, surface.diffuse)
        };
        let k = 255.0 / 256.0;
        // Lower left is the image's bottom-left texel (green).
        assert_eq!(look(1.0, 1.0).0, Vec3::new(0.0, 0.5 * k, 0.0));
        // Upper left is red, upper right white.
        assert_eq!(look(1.0, 5.0).1, Vec3::new(3.0 * k, 0.0, 0.0));
        assert_eq!(look(7.0, 5.0).1, Vec3::new(3.0 * k, 3.0 * k, 3.0 * k));
    }
}
