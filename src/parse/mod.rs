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

#[cfg(feature = "animate")]
use crate::error::Snippet;
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

/// Reads a scene file's `animation` block and motions (see [`crate::animation`]); `None`
/// when it has neither. Each motion's target is the first object, else the first light,
/// of that name defined before the motion. Syntax errors anywhere in the file are
/// reported; the scene itself is [`parse_scene`]'s (which skips these blocks).
///
/// ```
/// use microray::parse::parse_animation;
///
/// let text = b"
///     camera c { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 6 }
///     material white { diffuse 3 3 3 }
///     sphere ball { material white center 4 1 -4 radius 1 }
///     animation clip { frames 24 }
///     bounce hop { target ball height 2 bounces 2 }
/// ";
/// let animation = parse_animation::<4>(text)?.ok_or("no animation")?;
/// assert_eq!(animation.frames(), 24);
/// assert_eq!(animation.offset(3, animation.motions()[0].target()), [0.0, 1.5, 0.0]);
///
/// let error = parse_animation::<4>(b"animation clip { frames 24 } line l { target nothing by 1 0 0 }")
///     .unwrap_err();
/// assert_eq!(error.to_string(),
///     "1:39: no object or light named `nothing` (a motion moves an object or light defined before it)");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[cfg(feature = "animate")]
pub fn parse_animation<const MOTIONS: usize>(
    text: &[u8],
) -> Result<Option<crate::animation::Animation<'_, MOTIONS>>, Error> {
    use crate::animation::{Animation, MotionDef, Target};
    use crate::error::{Collection, ErrorKind, Position};
    use grammar::Item;
    let mut animation: Option<Animation<'_, MOTIONS>> = None;
    let mut motions = heapless::Vec::<(MotionDef<'_>, Target<'_>), MOTIONS>::new();
    let mut items = 0usize;
    grammar::walk(text, |item| {
        items += 1;
        match item {
            Item::Animation { .. } if animation.is_some() => Err(ErrorKind::SecondAnimation),
            Item::Animation { name, frames } => {
                animation = Some(Animation::new(name, frames.into())?);
                Ok(())
            }
            Item::Motion { def, target } => {
                let target =
                    target_before(text, target, items).ok_or(ErrorKind::UndefinedTarget {
                        name: Snippet::new(target.as_bytes()),
                    })?;
                motions
                    .push((def, target))
                    .map_err(|_| ErrorKind::CapacityExceeded {
                        what: Collection::Motions,
                        capacity: u16::try_from(MOTIONS).unwrap_or(u16::MAX),
                    })
            }
            _ => Ok(()),
        }
    })?;
    let Some(mut animation) = animation else {
        if motions.is_empty() {
            return Ok(None);
        }
        return Err(Error::at(
            ErrorKind::NoAnimation,
            Position::of_offset(text, text.len()),
        ));
    };
    for (def, target) in motions {
        // Cannot fail: both lists hold `MOTIONS`, and the names were read as names.
        animation
            .add_motion(&def, target)
            .map_err(|kind| Error::at(kind, Position::of_offset(text, text.len())))?;
    }
    Ok(Some(animation))
}

/// The first object, else the first light, named `name` among the first `items` blocks.
#[cfg(feature = "animate")]
fn target_before<'i>(
    text: &'i [u8],
    name: &str,
    items: usize,
) -> Option<crate::animation::Target<'i>> {
    use crate::animation::Target;
    use grammar::Item;
    let (mut seen, mut objects, mut lights) = (0usize, 0u16, 0u16);
    let (mut object, mut light) = (None, None);
    // The blocks before were read without error: the walk cannot fail before `items`.
    let _ = grammar::walk(text, |item| {
        seen += 1;
        if seen >= items {
            // Stops the walk (the error is not reported).
            return Err(crate::error::ErrorKind::NoAnimation);
        }
        match item {
            Item::Object(def) => {
                if object.is_none() && def.name == name {
                    object = Some(Target::Object {
                        index: objects,
                        def,
                    });
                }
                objects = objects.saturating_add(1);
            }
            Item::Light(def) => {
                if light.is_none() && def.name == name {
                    light = Some(Target::Light { index: lights, def });
                }
                lights = lights.saturating_add(1);
            }
            _ => {}
        }
        Ok(())
    });
    object.or(light)
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
        Mode | Surfer | Frames | Bounces => Values::Integers(1),
        Worlddim | Dimensions => Values::Numbers(2),
        Specular => Values::Channels,
        Shininess | Transparency | Theta | Radius | Height | Turns => Values::Numbers(1),
        Viewpoint | Ambient | Diffuse | Location | Emissivity | Point | Normal | Center | Xdir
        | Base | Direction | By => Values::Numbers(3),
        Material | Altmaterial | Filename | Texname | Target => Values::Word,
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
