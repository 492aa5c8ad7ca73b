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

/// Writes a scene's `animation` block and its motions (after [`print_scene`], one blank
/// line before each block), as the parser reads them back.
///
/// ```
/// use microray::parse::parse_animation;
/// use microray::print::print_animation;
///
/// let text = b"sphere ball { material m center 0 1 0 radius 1 }
///     animation clip { frames 24 }
///     orbit round { target ball center 0 1 -2 direction 0 1 0 turns 0.5 }";
/// let animation = parse_animation::<2>(text)?.ok_or("none")?;
/// let mut out = String::new();
/// print_animation(&animation, &mut out)?;
/// assert_eq!(out, "\nanimation clip\n{\n  frames 24\n}\n\n\
///     orbit round\n{\n  target ball\n  center 0 1 -2\n  direction 0 1 0\n  turns 0.5\n}\n");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[cfg(feature = "animate")]
pub fn print_animation<const MOTIONS: usize>(
    animation: &crate::animation::Animation<'_, MOTIONS>,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    use crate::animation::{Path, Target};
    use crate::error::Attr;
    use crate::write;
    out.write_str("\n")?;
    write::header(out, "animation", animation.name())?;
    writeln!(out, "  {} {}", Attr::Frames, animation.frames())?;
    write::footer(out)?;
    for motion in animation.motions() {
        let keyword = match motion.path() {
            Path::Line { .. } => "line",
            Path::Orbit { .. } => "orbit",
            Path::Bounce { .. } => "bounce",
        };
        out.write_str("\n")?;
        write::header(out, keyword, motion.name())?;
        let target = match motion.target() {
            Target::Object { def, .. } => def.name,
            Target::Light { def, .. } => def.name,
        };
        write::word(out, Attr::Target, target)?;
        match *motion.path() {
            Path::Line { by } => write::numbers(out, Attr::By, &by, 1.0)?,
            Path::Orbit {
                center,
                axis,
                turns,
            } => {
                write::numbers(out, Attr::Center, &center, 1.0)?;
                write::numbers(out, Attr::Direction, &axis, 1.0)?;
                write::numbers(out, Attr::Turns, &[turns], 1.0)?;
            }
            Path::Bounce { height, bounces } => {
                write::numbers(out, Attr::Height, &[height], 1.0)?;
                writeln!(out, "  {} {bounces}", Attr::Bounces)?;
            }
        }
        write::footer(out)?;
    }
    Ok(())
}
