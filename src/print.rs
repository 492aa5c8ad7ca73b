//! Scene text out: the whole scene, each block by its own printer (the lines they write
//! with are [`crate::write`]'s).
//!
//! What the printers write reads back as an equal scene, and printing that again gives the
//! same text: values are the ones written in the scene (not the normalised ones), each in the
//! shortest decimal that reads back exactly.

use crate::scalar::Scalar;
use crate::scene::Scene;
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
