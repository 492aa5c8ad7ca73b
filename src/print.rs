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
    let scale = scene.scale();
    scene.camera().print(out, scale)?;
    for material in scene.materials() {
        out.write_str("\n")?;
        material.print(out, scale)?;
    }
    for texture in scene.textures() {
        out.write_str("\n")?;
        texture.print(out)?;
    }
    for light in scene.lights() {
        out.write_str("\n")?;
        light.print(out, scale, scene.textures())?;
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

/// `  ATTR v1 v2 ...`, each value divided by `scale` (the factor it was multiplied by at
/// load; 1 for values that do not scale). Unscaled values are written in the type's own
/// shortest text; scaled ones as the exact `f64` quotient.
pub fn numbers<S: Scalar>(
    out: &mut dyn fmt::Write,
    attr: Attr,
    values: &[S],
    scale: f64,
) -> fmt::Result {
    write!(out, "  {attr}")?;
    for value in values {
        out.write_str(" ")?;
        if scale == 1.0 {
            value.write_shortest(out)?;
        } else {
            (value.to_f64() / scale).write_shortest(out)?;
        }
    }
    out.write_str("\n")
}

/// `  ATTR x y z`, divided by `scale` (see [`numbers`]).
pub fn vector<S: Scalar>(
    out: &mut dyn fmt::Write,
    attr: Attr,
    v: Vec3<S>,
    scale: f64,
) -> fmt::Result {
    numbers(out, attr, &[v.x, v.y, v.z], scale)
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
