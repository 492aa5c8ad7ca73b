//! Scene text out: the whole scene, and the helpers every printer shares.
//!
//! What the printers write reads back as an equal scene, and printing that again gives the
//! same text: values are the ones written in the scene (not the normalised ones), each in the
//! shortest decimal that reads back exactly.

use crate::error::Attr;
use crate::material::MaterialId;
use crate::object::Palette;
use crate::scalar::Scalar;
use crate::scene::Scene;
use crate::vec3::Vec3;
use core::fmt;

/// Writes the whole scene: camera, materials, textures, lights, then objects, one blank line
/// between blocks.
pub fn print_scene<
    S: Scalar,
    const OBJECTS: usize,
    const MATERIALS: usize,
    const LIGHTS: usize,
    const TEXTURES: usize,
    const MAX_WIDTH: usize,
>(
    scene: &Scene<'_, S, OBJECTS, MATERIALS, LIGHTS, TEXTURES, MAX_WIDTH>,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    scene.camera().print(out)?;
    for material in scene.materials() {
        out.write_str("\n")?;
        material.print(out)?;
    }
    for texture in scene.textures() {
        out.write_str("\n")?;
        texture.print(out)?;
    }
    for light in scene.lights() {
        out.write_str("\n")?;
        light.print(out)?;
    }
    let palette = scene.palette();
    for object in scene.objects() {
        out.write_str("\n")?;
        object.print(&palette, out)?;
    }
    Ok(())
}

/// `KEYWORD NAME` and `{` on the next line.
pub fn header(out: &mut dyn fmt::Write, keyword: &str, name: &str) -> fmt::Result {
    writeln!(out, "{keyword} {name}\n{{")
}

/// The closing `}`.
pub fn footer(out: &mut dyn fmt::Write) -> fmt::Result {
    out.write_str("}\n")
}

/// `  ATTR v1 v2 ...`.
pub fn numbers<S: Scalar>(out: &mut dyn fmt::Write, attr: Attr, values: &[S]) -> fmt::Result {
    write!(out, "  {attr}")?;
    for value in values {
        out.write_str(" ")?;
        value.write_shortest(out)?;
    }
    out.write_str("\n")
}

/// `  ATTR x y z`.
pub fn vector<S: Scalar>(out: &mut dyn fmt::Write, attr: Attr, v: Vec3<S>) -> fmt::Result {
    numbers(out, attr, &[v.x, v.y, v.z])
}

/// `  ATTR WORD`.
pub fn word(out: &mut dyn fmt::Write, attr: Attr, word: &str) -> fmt::Result {
    writeln!(out, "  {attr} {word}")
}

/// `  ATTR MATERIAL-NAME`.
pub fn material_ref<S: Scalar>(
    out: &mut dyn fmt::Write,
    attr: Attr,
    palette: &Palette<'_, S>,
    id: MaterialId,
) -> fmt::Result {
    word(out, attr, palette.material(id).map_or("", |m| m.name()))
}
