//! Tokens and blocks: nom parsers for blanks, comments and tokens, and one loop over blocks.

use super::{Values, values_of};
use crate::camera::CameraDef;
use crate::capacity::{is_delimiter, is_space};
use crate::decimal::{NumberError, parse_number};
use crate::error::{
    Attr, Entity, Error, ErrorKind, Feature, Position, Range, Snippet, TextureError,
};
use crate::light::{LightDef, SlideDef, SpotDef};
use crate::material::MaterialDef;
use crate::name::{NAME_CAPACITY, PATH_CAPACITY};
use crate::object::{
    ObjectDef, PlaneDef, RectDef, RevSurfDef, ShapeDef, SphereDef, Surfer, TextureMode,
};
use crate::range::Extent;
use crate::scalar::Scalar;
use crate::scene::Scene;
use nom::branch::alt;
use nom::bytes::complete::{tag, take_till, take_till1, take_while1};
use nom::character::complete::char;
use nom::combinator::recognize;
use nom::multi::many0_count;
use nom::sequence::pair;
use nom::{IResult, Parser};

/// One block of a scene file, as written.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Item<'i> {
    Camera(CameraDef<'i>),
    Material(MaterialDef<'i>),
    Light(LightDef<'i>),
    // Read by the parser's texture resolver.
    #[cfg_attr(not(feature = "parser"), allow(dead_code))]
    Texture {
        name: &'i str,
        filename: &'i str,
    },
    Object(ObjectDef<'i>),
    /// The `animation` block: its name and number of frames.
    #[cfg(feature = "animate")]
    Animation {
        name: &'i str,
        frames: u16,
    },
    /// A motion block and the name of what it moves.
    #[cfg(feature = "animate")]
    Motion {
        def: crate::animation::MotionDef<'i>,
        target: &'i str,
    },
}

impl Item<'_> {
    /// Takes the definition into a scene's extent.
    pub(crate) fn measure(&self, extent: &mut Extent) {
        match self {
            Item::Camera(c) => extent.camera(c),
            Item::Light(l) => extent.light(l),
            Item::Material(m) => extent.material(m),
            Item::Texture { .. } => {}
            Item::Object(o) => extent.object(o),
            #[cfg(feature = "animate")]
            Item::Animation { .. } | Item::Motion { .. } => {}
        }
    }
}

/// Whitespace and `#` comments (to the end of the line).
fn blank(input: &[u8]) -> IResult<&[u8], usize> {
    many0_count(alt((
        take_while1(is_space),
        recognize(pair(char('#'), take_till(|b| b == b'\n'))),
    )))
    .parse(input)
}

/// `{`, `}`, or a run of anything else up to whitespace or a brace.
fn token(input: &[u8]) -> IResult<&[u8], &[u8]> {
    alt((tag(&b"{"[..]), tag(&b"}"[..]), take_till1(is_delimiter))).parse(input)
}

/// A token and its byte offset in the text.
#[derive(Clone, Copy)]
struct Tok<'i> {
    bytes: &'i [u8],
    at: usize,
}

impl Tok<'_> {
    fn is(&self, text: &[u8]) -> bool {
        self.bytes == text
    }
    fn is_brace(&self) -> bool {
        self.is(b"{") || self.is(b"}")
    }
}

fn snippet(token: Option<Tok<'_>>) -> Snippet {
    token.map_or(Snippet::END, |t| Snippet::new(t.bytes))
}

struct Cursor<'i> {
    text: &'i [u8],
    rest: &'i [u8],
}

impl<'i> Cursor<'i> {
    fn offset(&self, at: &[u8]) -> usize {
        self.text.len().saturating_sub(at.len())
    }

    fn error(&self, kind: ErrorKind, at: usize) -> Error {
        Error::at(kind, Position::of_offset(self.text, at))
    }

    /// The next token without consuming it; control characters outside comments are errors.
    fn peek(&self) -> Result<Option<Tok<'i>>, Error> {
        let rest = blank(self.rest).map_or(self.rest, |(rest, _)| rest);
        let at = self.offset(rest);
        let Some(&first) = rest.first() else {
            return Ok(None);
        };
        let bytes = token(rest).map_or(&[][..], |(_, bytes)| bytes);
        let bad = bytes.iter().position(|&b| b < 0x20 || b == 0x7f);
        match (bad, bytes.is_empty()) {
            (None, false) => Ok(Some(Tok { bytes, at })),
            (Some(i), _) => {
                let byte = bytes.get(i).copied().unwrap_or(first);
                Err(self.error(ErrorKind::InvalidCharacter { byte }, at + i))
            }
            (None, true) => Err(self.error(ErrorKind::InvalidCharacter { byte: first }, at)),
        }
    }

    fn advance(&mut self, token: Tok<'i>) {
        self.rest = self.text.get(token.at + token.bytes.len()..).unwrap_or(&[]);
    }

    fn next(&mut self) -> Result<Option<Tok<'i>>, Error> {
        let token = self.peek()?;
        if let Some(t) = token {
            self.advance(t);
        }
        Ok(token)
    }

    /// A token as UTF-8 text of at most `max` bytes.
    fn text_of(&self, token: Tok<'i>, max: usize) -> Result<&'i str, Error> {
        let text = core::str::from_utf8(token.bytes)
            .map_err(|e| self.error(ErrorKind::NotUtf8, token.at + e.valid_up_to()))?;
        if text.len() > max {
            let max = u16::try_from(max).unwrap_or(u16::MAX);
            return Err(self.error(ErrorKind::NameTooLong { max }, token.at));
        }
        Ok(text)
    }
}

/// One attribute's values and where they were.
#[derive(Clone, Copy)]
struct Slot<'i> {
    at: usize,
    value_at: usize,
    value: Value<'i>,
}

#[derive(Clone, Copy)]
enum Value<'i> {
    Numbers([f64; 3]),
    Word(&'i str),
}

/// A parsed block, before it is checked and added to the scene.
struct Block<'i> {
    entity: Entity,
    keyword_at: usize,
    name: &'i str,
    name_at: usize,
    /// By the attribute's place in its entity's list: a block holds at most
    /// [`Entity::MAX_ATTRIBUTES`] (a slot per attribute of the language would be 26, over a
    /// kilobyte of a microcontroller's stack while it parses).
    slots: [Option<Slot<'i>>; Entity::MAX_ATTRIBUTES],
}

impl<'i> Block<'i> {
    fn slot(&self, attr: Attr) -> Option<&Slot<'i>> {
        let place = self.entity.attributes().iter().position(|&a| a == attr)?;
        self.slots.get(place).and_then(Option::as_ref)
    }

    fn missing(&self, attr: Attr) -> ErrorKind {
        ErrorKind::MissingAttribute {
            entity: self.entity,
            attr,
        }
    }

    /// Copies the numbers of a required attribute into `out`, in place: definitions are
    /// filled field by field rather than built from returned arrays, whose copies were
    /// most of `to_item`'s code on the Cortex-M0 (one `memcpy` call per array and move).
    #[inline(never)]
    fn fill(&self, attr: Attr, out: &mut [f64]) -> Result<(), ErrorKind> {
        match self.slot(attr).map(|s| &s.value) {
            Some(Value::Numbers(values)) => {
                out.iter_mut().zip(values).for_each(|(o, v)| *o = *v);
                Ok(())
            }
            _ => Err(self.missing(attr)),
        }
    }

    /// [`fill`](Self::fill) for an optional attribute: `out` stays as it is (zero) when the
    /// attribute is left out.
    fn fill_optional(&self, attr: Attr, out: &mut [f64]) {
        // Left out is not an error here.
        let _ = self.fill(attr, out);
    }

    /// The one number of a required attribute.
    fn number(&self, attr: Attr) -> Result<f64, ErrorKind> {
        let mut value = [0.0];
        self.fill(attr, &mut value)?;
        let [value] = value;
        Ok(value)
    }

    fn word(&self, attr: Attr) -> Result<&'i str, ErrorKind> {
        match self.slot(attr).map(|s| s.value) {
            Some(Value::Word(word)) => Ok(word),
            _ => Err(self.missing(attr)),
        }
    }

    /// Where an error about this block points: at the attribute it is about, at the value
    /// for undefined names and texture files, else at the name or the keyword.
    fn offset_of(&self, kind: &ErrorKind) -> usize {
        let value_of = |attr| self.slot(attr).map(|s| s.value_at);
        let found = match kind {
            ErrorKind::UndefinedMaterial { attr, .. } => value_of(*attr),
            ErrorKind::UndefinedTexture { .. } => value_of(Attr::Texname),
            ErrorKind::Texture { .. } => value_of(Attr::Filename).or(value_of(Attr::Texname)),
            ErrorKind::DuplicateName { .. } | ErrorKind::NameTooLong { .. } => Some(self.name_at),
            other => other.attribute().and_then(|a| self.slot(a)).map(|s| s.at),
        };
        found.unwrap_or(self.keyword_at)
    }
}

const fn is_object(entity: Entity) -> bool {
    matches!(
        entity,
        Entity::Plane
            | Entity::Sphere
            | Entity::FPlane
            | Entity::TiledPlane
            | Entity::TexPlane
            | Entity::RevSurf
    )
}

fn is_keyword(token: Tok<'_>) -> bool {
    let attributes = Entity::ALL.iter().flat_map(|&e| e.attributes().iter());
    attributes
        .map(|a| a.keyword())
        .chain(Entity::ALL.iter().map(|e| e.keyword()))
        .any(|k| token.is(k.as_bytes()))
}

/// Reads every block of `text` in order and hands its definition to `sink`; errors from
/// either are placed at the block's attribute they are about.
pub(crate) fn walk<'i>(
    text: &'i [u8],
    mut sink: impl FnMut(Item<'i>) -> Result<(), ErrorKind>,
) -> Result<(), Error> {
    let mut cursor = Cursor { text, rest: text };
    while let Some(keyword) = cursor.next()? {
        let entity = Entity::ALL
            .iter()
            .copied()
            .find(|e| keyword.is(e.keyword().as_bytes()))
            .ok_or_else(|| {
                cursor.error(
                    ErrorKind::UnknownEntity {
                        found: Snippet::new(keyword.bytes),
                    },
                    keyword.at,
                )
            })?;
        let block = parse_block(&mut cursor, entity, keyword)?;
        to_item(&block)
            .and_then(&mut sink)
            .map_err(|kind| cursor.error(kind, block.offset_of(&kind)))?;
    }
    Ok(())
}

/// Parses `text` into `scene` (emptied first), with every length multiplied by `scale`,
/// or by the scale the number type needs when `None`.
pub(super) fn parse_into<
    't,
    S: Scalar,
    const OBJECTS: usize,
    const MATERIALS: usize,
    const LIGHTS: usize,
    const TEXTURES: usize,
    const MAX_WIDTH: usize,
>(
    text: &[u8],
    mut textures: impl FnMut(&str) -> Result<&'t [u8], TextureError>,
    scale: Option<f64>,
    scene: &mut Scene<'t, S, OBJECTS, MATERIALS, LIGHTS, TEXTURES, MAX_WIDTH>,
) -> Result<(), Error> {
    // First pass: how large the scene is, so that it can be scaled into the type's range.
    let mut extent = Extent::EMPTY;
    walk(text, |item| {
        item.measure(&mut extent);
        Ok(())
    })?;
    // Second pass: the scene, built in place; its camera is set when the block is reached,
    // wherever it is in the file, and there must be exactly one.
    let scale = scale.unwrap_or_else(|| extent.scale_for::<S>());
    scene.clear(scale);
    let mut cameras = 0;
    walk(text, |item| {
        let loaded = match item {
            Item::Camera(_) if cameras > 0 => Err(ErrorKind::SecondCamera),
            Item::Camera(def) => {
                cameras += 1;
                scene.set_camera(&def)
            }
            Item::Material(def) => scene.add_material(&def),
            Item::Light(def) => {
                if cfg!(feature = "projector")
                    && let Some(slide) = &def.slide
                {
                    scene.add_texture_named(slide.texname, &mut textures)?;
                }
                scene.add_light(&def)
            }
            Item::Object(def) => {
                if let ShapeDef::TexPlane(_, texname, _) = def.shape {
                    scene.add_texture_named(texname, &mut textures)?;
                }
                scene.add_object(&def)
            }
            Item::Texture { name, filename } => {
                scene.add_texture_file(name, filename, &mut textures)
            }
            // Not part of the scene: `parse_animation` reads them.
            #[cfg(feature = "animate")]
            Item::Animation { .. } | Item::Motion { .. } => Ok(()),
        };
        loaded.map_err(|kind| extent.explain::<S>(kind, scale))
    })?;
    if cameras == 0 {
        return Err(Error::at(
            ErrorKind::NoCamera,
            Position::of_offset(text, text.len()),
        ));
    }
    Ok(())
}

fn parse_block<'i>(
    c: &mut Cursor<'i>,
    entity: Entity,
    keyword: Tok<'i>,
) -> Result<Block<'i>, Error> {
    let name = match c.next()? {
        Some(t) if !t.is_brace() => t,
        other => {
            let at = other.map_or(c.text.len(), |t| t.at);
            return Err(c.error(
                ErrorKind::ExpectedName {
                    entity,
                    found: snippet(other),
                },
                at,
            ));
        }
    };
    let name_text = c.text_of(name, NAME_CAPACITY)?;
    let open = match c.next()? {
        Some(t) if t.is(b"{") => t,
        other => {
            let at = other.map_or(c.text.len(), |t| t.at);
            return Err(c.error(
                ErrorKind::ExpectedOpenBrace {
                    entity,
                    found: snippet(other),
                },
                at,
            ));
        }
    };
    let mut block = Block {
        entity,
        keyword_at: keyword.at,
        name: name_text,
        name_at: name.at,
        slots: [None; Entity::MAX_ATTRIBUTES],
    };
    let mut first = true;
    loop {
        let Some(token) = c.next()? else {
            let opened = Position::of_offset(c.text, open.at);
            return Err(c.error(ErrorKind::UnclosedBlock { entity, opened }, c.text.len()));
        };
        if token.is(b"}") {
            return Ok(block);
        }
        let (place, attr) = entity
            .attributes()
            .iter()
            .copied()
            .enumerate()
            .find(|(_, a)| token.is(a.keyword().as_bytes()))
            .ok_or_else(|| {
                c.error(
                    ErrorKind::UnknownAttribute {
                        entity,
                        found: Snippet::new(token.bytes),
                    },
                    token.at,
                )
            })?;
        if first && is_object(entity) && attr != Attr::Material {
            return Err(c.error(ErrorKind::MaterialNotFirst { entity }, token.at));
        }
        first = false;
        let Some(slot) = block.slots.get_mut(place) else {
            continue; // Cannot happen: every entity's attributes fit (checked at compile time).
        };
        if slot.is_some() {
            return Err(c.error(ErrorKind::DuplicateAttribute { attr }, token.at));
        }
        let (value, value_at) = parse_values(c, attr)?;
        *slot = Some(Slot {
            at: token.at,
            value_at,
            value,
        });
    }
}

fn parse_values<'i>(c: &mut Cursor<'i>, attr: Attr) -> Result<(Value<'i>, usize), Error> {
    let (count, whole) = match values_of(attr) {
        Values::Word => {
            return match c.next()? {
                Some(t) if !t.is_brace() => {
                    let max = if attr == Attr::Filename {
                        PATH_CAPACITY
                    } else {
                        usize::MAX
                    };
                    Ok((Value::Word(c.text_of(t, max)?), t.at))
                }
                other => {
                    let at = other.map_or(c.text.len(), |t| t.at);
                    Err(c.error(
                        ErrorKind::ExpectedWord {
                            attr,
                            found: snippet(other),
                        },
                        at,
                    ))
                }
            };
        }
        Values::Numbers(n) => (n, false),
        Values::Integers(n) => (n, true),
        // Three when a second number follows the first.
        Values::Channels => {
            let second = c.peek()?.and_then(|t| {
                let mut ahead = Cursor {
                    text: c.text,
                    rest: c.rest,
                };
                ahead.advance(t);
                ahead.peek().ok().flatten()
            });
            let three = second.is_some_and(|t| parse_number(t.bytes).is_ok());
            (if three { 3 } else { 1 }, false)
        }
    };
    let mut values = [0.0; 3];
    let mut first_at = c.text.len();
    for (index, slot) in (0u8..).zip(values.iter_mut().take(usize::from(count))) {
        let token = c.peek()?;
        let Some(t) = token else {
            let kind = ErrorKind::MissingValues {
                attr,
                expected: count,
                found: index,
                next: Snippet::END,
            };
            return Err(c.error(kind, c.text.len()));
        };
        let kind = match parse_number(t.bytes) {
            Ok(v) if whole && v != libm::trunc(v) => ErrorKind::NotAnInteger {
                attr,
                found: Snippet::new(t.bytes),
            },
            Ok(v) => {
                *slot = v;
                if index == 0 {
                    first_at = t.at;
                }
                c.advance(t);
                continue;
            }
            Err(NumberError::NotFinite) => ErrorKind::NotFinite {
                found: Snippet::new(t.bytes),
            },
            Err(NumberError::TooLarge) => ErrorKind::NumberTooLarge {
                found: Snippet::new(t.bytes),
            },
            Err(NumberError::NotANumber) if t.is_brace() || is_keyword(t) => {
                ErrorKind::MissingValues {
                    attr,
                    expected: count,
                    found: index,
                    next: Snippet::new(t.bytes),
                }
            }
            Err(NumberError::NotANumber) => ErrorKind::NotANumber {
                attr,
                found: Snippet::new(t.bytes),
            },
        };
        return Err(c.error(kind, t.at));
    }
    if let Some(t) = c.peek()?
        && !matches!(parse_number(t.bytes), Err(NumberError::NotANumber))
    {
        return Err(c.error(
            ErrorKind::ExtraValue {
                attr,
                expected: count,
            },
            t.at,
        ));
    }
    if count == 1 && values_of(attr) == Values::Channels {
        // One number for every channel.
        values = [values[0]; 3];
    }
    Ok((Value::Numbers(values), first_at))
}

/// A whole number of pixels; negative is 0 and huge saturates (as `as` does), so the
/// camera's checks report them.
fn pixels(v: f64) -> u32 {
    v as u32
}

fn rect(block: &Block<'_>) -> Result<RectDef, ErrorKind> {
    let mut rect = RectDef::new([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 2]);
    block.fill(Attr::Normal, &mut rect.normal)?;
    block.fill(Attr::Point, &mut rect.point)?;
    block.fill(Attr::Xdir, &mut rect.xdir)?;
    block.fill(Attr::Dimensions, &mut rect.dimensions)?;
    Ok(rect)
}

/// A texture's `mode`: 0 or 1.
fn mode(block: &Block<'_>) -> Result<TextureMode, ErrorKind> {
    match block.number(Attr::Mode)? {
        0.0 => Ok(TextureMode::Fit),
        1.0 => Ok(TextureMode::Tile),
        _ => Err(ErrorKind::OutOfRange {
            attr: Attr::Mode,
            range: Range::ZeroOrOne,
        }),
    }
}

/// A block's definition, its attributes taken in a fixed order (the first one missing is
/// the one reported).
fn to_item<'i>(block: &Block<'i>) -> Result<Item<'i>, ErrorKind> {
    let name = block.name;
    let shape = match block.entity {
        Entity::Animation | Entity::Line | Entity::Orbit | Entity::Bounce => {
            return motion_item(block);
        }
        Entity::Camera => {
            let mut pixeldim = [0.0; 2];
            block.fill(Attr::Pixeldim, &mut pixeldim)?;
            let mut camera = CameraDef::new(name, pixeldim.map(pixels), [0.0; 2], [0.0; 3]);
            block.fill(Attr::Worlddim, &mut camera.worlddim)?;
            block.fill(Attr::Viewpoint, &mut camera.viewpoint)?;
            return Ok(Item::Camera(camera));
        }
        Entity::Material => {
            let mut material = MaterialDef {
                name,
                ambient: [0.0; 3],
                diffuse: [0.0; 3],
                specular: [0.0; 3],
                shininess: 0.0,
                transparency: 0.0,
            };
            block.fill_optional(Attr::Ambient, &mut material.ambient);
            block.fill_optional(Attr::Diffuse, &mut material.diffuse);
            block.fill_optional(Attr::Specular, &mut material.specular);
            block.fill_optional(
                Attr::Shininess,
                core::slice::from_mut(&mut material.shininess),
            );
            block.fill_optional(
                Attr::Transparency,
                core::slice::from_mut(&mut material.transparency),
            );
            return Ok(Item::Material(material));
        }
        Entity::Light | Entity::Spotlight | Entity::Projector => {
            if block.entity == Entity::Projector {
                // First: a build without projectors leaves the rest out.
                Feature::Projector.require(None)?;
            }
            let mut light = LightDef::point(name, [0.0; 3], [0.0; 3]);
            block.fill(Attr::Location, &mut light.location)?;
            block.fill(Attr::Emissivity, &mut light.emissivity)?;
            if block.entity == Entity::Spotlight {
                let mut spot = SpotDef {
                    point: [0.0; 3],
                    theta: 0.0,
                };
                block.fill(Attr::Point, &mut spot.point)?;
                spot.theta = block.number(Attr::Theta)?;
                light.spot = Some(spot);
            } else if block.entity == Entity::Projector {
                light.slide = Some(SlideDef {
                    rect: rect(block)?,
                    texname: block.word(Attr::Texname)?,
                    mode: mode(block)?,
                });
            }
            return Ok(Item::Light(light));
        }
        Entity::Texture => {
            return Ok(Item::Texture {
                name,
                filename: block.word(Attr::Filename)?,
            });
        }
        Entity::Plane => {
            let mut plane = PlaneDef {
                normal: [0.0; 3],
                point: [0.0; 3],
            };
            block.fill(Attr::Normal, &mut plane.normal)?;
            block.fill(Attr::Point, &mut plane.point)?;
            ShapeDef::Plane(plane)
        }
        Entity::Sphere => {
            let mut sphere = SphereDef {
                center: [0.0; 3],
                radius: 0.0,
            };
            block.fill(Attr::Center, &mut sphere.center)?;
            sphere.radius = block.number(Attr::Radius)?;
            ShapeDef::Sphere(sphere)
        }
        Entity::FPlane => ShapeDef::FPlane(rect(block)?),
        Entity::TiledPlane => ShapeDef::TiledPlane(rect(block)?, block.word(Attr::Altmaterial)?),
        Entity::TexPlane => {
            ShapeDef::TexPlane(rect(block)?, block.word(Attr::Texname)?, mode(block)?)
        }
        Entity::RevSurf => {
            Feature::RevSurf.require(None)?;
            let surfer = match block.number(Attr::Surfer)? {
                1.0 => Surfer::Cone,
                2.0 => Surfer::Waist,
                3.0 => Surfer::Vase,
                _ => {
                    return Err(ErrorKind::OutOfRange {
                        attr: Attr::Surfer,
                        range: Range::Surfer,
                    });
                }
            };
            let mut revsurf = RevSurfDef {
                surfer,
                base: [0.0; 3],
                direction: [0.0; 3],
                height: 0.0,
            };
            block.fill(Attr::Base, &mut revsurf.base)?;
            block.fill(Attr::Direction, &mut revsurf.direction)?;
            revsurf.height = block.number(Attr::Height)?;
            ShapeDef::RevSurf(revsurf)
        }
    };
    let material = block.word(Attr::Material)?;
    Ok(Item::Object(ObjectDef {
        name,
        material,
        shape,
    }))
}

/// An `animation` block or a motion block.
#[cfg(feature = "animate")]
fn motion_item<'i>(block: &Block<'i>) -> Result<Item<'i>, ErrorKind> {
    use crate::animation::{MotionDef, Path};
    let count = |attr: Attr| {
        let v = block.number(attr)?;
        if (1.0..=65535.0).contains(&v) {
            Ok(v as u16)
        } else {
            Err(ErrorKind::OutOfRange {
                attr,
                range: Range::Count,
            })
        }
    };
    if block.entity == Entity::Animation {
        return Ok(Item::Animation {
            name: block.name,
            frames: count(Attr::Frames)?,
        });
    }
    let target = block.word(Attr::Target)?;
    let path = match block.entity {
        Entity::Line => {
            let mut by = [0.0; 3];
            block.fill(Attr::By, &mut by)?;
            Path::Line { by }
        }
        Entity::Orbit => {
            let (mut center, mut axis) = ([0.0; 3], [0.0; 3]);
            block.fill(Attr::Center, &mut center)?;
            block.fill(Attr::Direction, &mut axis)?;
            if axis == [0.0; 3] {
                return Err(ErrorKind::ZeroVector {
                    attr: Attr::Direction,
                });
            }
            let turns = block.number(Attr::Turns)?;
            Path::Orbit {
                center,
                axis,
                turns,
            }
        }
        _ => Path::Bounce {
            height: block.number(Attr::Height)?,
            bounces: count(Attr::Bounces)?,
        },
    };
    let def = MotionDef {
        name: block.name,
        path,
    };
    Ok(Item::Motion { def, target })
}

/// Without the `animate` feature, motion blocks are refused by name.
#[cfg(not(feature = "animate"))]
fn motion_item<'i>(_: &Block<'i>) -> Result<Item<'i>, ErrorKind> {
    Err(ErrorKind::NotCompiledIn {
        feature: Feature::Animate,
        attr: None,
    })
}
