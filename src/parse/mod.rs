//! The scene language: a nom parser over bytes, no allocation.
//!
//! The whole language of the course (see `SCENE-FORMAT.md` in the project's shared notes) plus
//! `#` comments: `ENTITY NAME { ATTRIBUTE VALUES ... }` blocks of whitespace-separated
//! tokens. Every error names the line and column, and what was expected there. The parser
//! never recurses (blocks do not nest), so no input can exhaust the stack, and every loop
//! consumes input, so none can hang.
//!
//! Texture files are asked of a caller-supplied resolver by file name: firmware returns an
//! `include_bytes!` slice, the host tracer reads the file (see `microray::host`).

pub(crate) mod grammar;
pub use crate::decimal as number;

use crate::error::{Attr, Entity, Error, TextureError};
use crate::range::{Extent, NumberType, Target};
use crate::scalar::Scalar;
use crate::scene::Scene;

/// Parses scene text into a scene with the capacities of the scene type.
///
/// `textures` maps a texture's file name (as written) to the file's bytes.
pub fn parse_scene<
    't,
    S: Scalar,
    const OBJECTS: usize,
    const MATERIALS: usize,
    const LIGHTS: usize,
    const TEXTURES: usize,
    const MAX_WIDTH: usize,
>(
    text: &[u8],
    textures: impl FnMut(&str) -> Result<&'t [u8], TextureError>,
) -> Result<Scene<'t, S, OBJECTS, MATERIALS, LIGHTS, TEXTURES, MAX_WIDTH>, Error> {
    let mut scene = Scene::empty();
    grammar::parse_into(text, textures, None, &mut scene)?;
    Ok(scene)
}

/// Parses scene text into an existing scene, emptied first, without a second copy of the
/// scene anywhere: what a microcontroller with little stack wants. On error the scene is
/// left empty or partly filled; parse again before rendering it.
///
/// ```
/// use microray::{parse::{no_textures, parse_scene_into}, Scene};
///
/// let mut scene: Scene<f32, 4, 4, 2, 0, 160> = Scene::empty();
/// parse_scene_into(b"camera c { pixeldim 8 6 worlddim 8 6 viewpoint 4 3 3 }", no_textures, &mut scene)?;
/// assert_eq!(scene.camera().width(), 8);
/// # Ok::<(), microray::Error>(())
/// ```
pub fn parse_scene_into<
    't,
    S: Scalar,
    const OBJECTS: usize,
    const MATERIALS: usize,
    const LIGHTS: usize,
    const TEXTURES: usize,
    const MAX_WIDTH: usize,
>(
    text: &[u8],
    textures: impl FnMut(&str) -> Result<&'t [u8], TextureError>,
    scene: &mut Scene<'t, S, OBJECTS, MATERIALS, LIGHTS, TEXTURES, MAX_WIDTH>,
) -> Result<(), Error> {
    grammar::parse_into(text, textures, None, scene)
}

/// Parses scene text with every length multiplied by `scale` (see [`crate::range`]), instead
/// of the scale [`parse_scene`] chooses for the number type. A power of two changes a
/// floating-point image not at all.
pub fn parse_scene_with_scale<
    't,
    S: Scalar,
    const OBJECTS: usize,
    const MATERIALS: usize,
    const LIGHTS: usize,
    const TEXTURES: usize,
    const MAX_WIDTH: usize,
>(
    text: &[u8],
    textures: impl FnMut(&str) -> Result<&'t [u8], TextureError>,
    scale: f64,
) -> Result<Scene<'t, S, OBJECTS, MATERIALS, LIGHTS, TEXTURES, MAX_WIDTH>, Error> {
    let mut scene = Scene::empty();
    grammar::parse_into(text, textures, Some(scale), &mut scene)?;
    Ok(scene)
}

pub use crate::texture::no_textures;

/// The attributes an entity takes, in the order the printer writes them.
pub const fn attributes_of(entity: Entity) -> &'static [Attr] {
    entity.attributes()
}

/// What values an attribute takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Values {
    /// This many decimal numbers.
    Numbers(u8),
    /// One decimal number for every channel, or three (r, g, b).
    Channels,
    /// This many whole numbers.
    Integers(u8),
    /// One name (of a material or texture) or file name.
    Word,
}

pub(crate) const fn values_of(attr: Attr) -> Values {
    use Attr::*;
    match attr {
        Pixeldim => Values::Integers(2),
        Mode | Surfer => Values::Integers(1),
        Worlddim | Dimensions => Values::Numbers(2),
        Specular => Values::Channels,
        Shininess | Transparency | Theta | Radius | Height => Values::Numbers(1),
        Viewpoint | Ambient | Diffuse | Location | Emissivity | Point | Normal | Center | Xdir
        | Base | Direction => Values::Numbers(3),
        Material | Altmaterial | Filename | Texname => Values::Word,
    }
}

/// Measures a scene file (without loading textures).
pub fn scene_extent(text: &[u8]) -> Result<Extent, Error> {
    let mut extent = Extent::EMPTY;
    grammar::walk(text, |item| {
        item.measure(&mut extent);
        Ok(())
    })?;
    Ok(extent)
}

/// The widest number type that fits the scene and is fast on the target: `f64` on a host,
/// `f32` with a single-precision FPU, and without one `I16F16` when the scene's smallest
/// features survive its resolution, else `f32` (soft float: slower, but it fits).
///
/// ```
/// use microray::parse::choose_number_type;
/// use microray::range::{NumberType, Target};
///
/// let scene = b"camera c { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 3 }
///               material m { diffuse 1 1 1 }
///               sphere s { material m center 4 3 -5 radius 1 }";
/// assert_eq!(choose_number_type(scene, Target::NoFpu)?, NumberType::I16F16);
/// let tiny = b"camera c { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 3 }
///              material m { diffuse 1 1 1 }
///              sphere s { material m center 4 3 -5 radius 0.001 }";
/// assert_eq!(choose_number_type(tiny, Target::NoFpu)?, NumberType::F32);
/// # Ok::<(), microray::Error>(())
/// ```
pub fn choose_number_type(text: &[u8], target: Target) -> Result<NumberType, Error> {
    let extent = scene_extent(text)?;
    Ok(match target {
        Target::Host => NumberType::F64,
        Target::SinglePrecisionFpu => NumberType::F32,
        Target::NoFpu if extent.fits::<crate::scalar::I16F16>() => NumberType::I16F16,
        Target::NoFpu => NumberType::F32,
    })
}
