//! The one error type: what went wrong, and where in the scene text.

use core::fmt;

/// What is wrong with a compiled scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompiledError {
    /// It does not start with [`MAGIC`](crate::compiled::MAGIC) and [`VERSION`](crate::compiled::VERSION).
    NotCompiled,
    /// It was compiled for another number type (its [`Scalar::CODE`](crate::scalar::Scalar::CODE)).
    OtherNumberType {
        /// The code in the bytes.
        found: u8,
    },
    /// It ends early.
    Truncated,
    /// An object kind, flag, axis or mode that does not exist, or a world window that is
    /// not positive.
    BadValue,
    /// A material or texture index past the end of its list.
    BadIndex,
    /// Bytes after the last object.
    Trailing,
}

/// A line and column in scene text, both counted from 1. Columns count characters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Position {
    /// Line, from 1.
    pub line: u32,
    /// Column in characters, from 1.
    pub column: u32,
}

impl Position {
    /// The position of byte `offset` in `text` (clamped to the end of the text).
    pub fn of_offset(text: &[u8], offset: usize) -> Self {
        let before = text.get(..offset).unwrap_or(text);
        let line_start = before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |i| i + 1);
        let lines = before.iter().filter(|&&b| b == b'\n').count();
        // Characters, not bytes: count every byte that does not continue a UTF-8 sequence.
        let columns = before
            .get(line_start..)
            .unwrap_or(&[])
            .iter()
            .filter(|&&b| b & 0xC0 != 0x80)
            .count();
        Self {
            line: u32::try_from(lines.saturating_add(1)).unwrap_or(u32::MAX),
            column: u32::try_from(columns.saturating_add(1)).unwrap_or(u32::MAX),
        }
    }
}

impl fmt::Display for Position {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

/// An error from loading a scene: its kind, and where it is when the scene came from text.
///
/// Scenes built in Rust source (without the parser) have no position.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Error {
    /// What went wrong.
    pub kind: ErrorKind,
    /// Where, for scenes read from text.
    pub position: Option<Position>,
}

impl Error {
    /// An error with no position (scene built in source).
    pub const fn new(kind: ErrorKind) -> Self {
        Self {
            kind,
            position: None,
        }
    }

    /// An error at a position.
    pub const fn at(kind: ErrorKind, position: Position) -> Self {
        Self {
            kind,
            position: Some(position),
        }
    }
}

impl From<ErrorKind> for Error {
    fn from(kind: ErrorKind) -> Self {
        Self::new(kind)
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.position {
            Some(p) => write!(f, "{p}: {}", self.kind),
            None => write!(f, "{}", self.kind),
        }
    }
}

impl core::error::Error for Error {}

/// The kinds of block in a scene file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Entity {
    Camera,
    Material,
    Light,
    Spotlight,
    Plane,
    Sphere,
    FPlane,
    TiledPlane,
    Texture,
    TexPlane,
    Projector,
    RevSurf,
    Animation,
    Line,
    Orbit,
    Bounce,
}

/// A cargo feature a scene can need: object kinds and shading stages beyond planes,
/// spheres, point lights, ambient and diffuse light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    /// `fplane` objects.
    FPlane,
    /// `tiled_plane` objects.
    TiledPlane,
    /// Textures and `texplane` objects.
    Texture,
    /// Spotlights.
    Spotlight,
    /// Projectors (`projector`).
    Projector,
    /// Surfaces of revolution (`revsurf`).
    RevSurf,
    /// Mirror reflection: a material's `specular`.
    Reflection,
    /// Transparency: a material's `transparency`.
    Transparency,
    /// Glints: a material's `shininess`.
    Glint,
    /// Moving pictures: `animation`, `line`, `orbit` and `bounce` blocks.
    Animate,
}

impl Feature {
    /// The cargo feature's name.
    pub const fn name(self) -> &'static str {
        match self {
            Feature::FPlane => "fplane",
            Feature::TiledPlane => "tiled-plane",
            Feature::Texture => "texture",
            Feature::Spotlight => "spotlight",
            Feature::Projector => "projector",
            Feature::RevSurf => "revsurf",
            Feature::Reflection => "reflection",
            Feature::Transparency => "transparency",
            Feature::Glint => "glint",
            Feature::Animate => "animate",
        }
    }

    /// What it provides, for error messages.
    pub const fn what(self) -> &'static str {
        match self {
            Feature::FPlane => "finite planes (`fplane`)",
            Feature::TiledPlane => "tiled planes (`tiled_plane`)",
            Feature::Texture => "textures (`texture`, `texplane`)",
            Feature::Spotlight => "spotlights",
            Feature::Projector => "projectors (`projector`)",
            Feature::RevSurf => "surfaces of revolution (`revsurf`)",
            Feature::Reflection => "mirror reflection (`specular`)",
            Feature::Transparency => "transparency (`transparency`)",
            Feature::Glint => "glints (`shininess`)",
            Feature::Animate => "moving pictures (`animation`, `line`, `orbit`, `bounce`)",
        }
    }

    /// Whether this build has it. The code a feature gates is behind this constant, so a
    /// build without the feature leaves that code out of the binary.
    pub const fn enabled(self) -> bool {
        match self {
            Feature::FPlane => cfg!(feature = "fplane"),
            Feature::TiledPlane => cfg!(feature = "tiled-plane"),
            Feature::Texture => cfg!(feature = "texture"),
            Feature::Spotlight => cfg!(feature = "spotlight"),
            Feature::Projector => cfg!(feature = "projector"),
            Feature::RevSurf => cfg!(feature = "revsurf"),
            Feature::Reflection => cfg!(feature = "reflection"),
            Feature::Transparency => cfg!(feature = "transparency"),
            Feature::Glint => cfg!(feature = "glint"),
            Feature::Animate => cfg!(feature = "animate"),
        }
    }

    /// `Ok` when this build has the feature, else the error that says so.
    pub const fn require(self, attr: Option<Attr>) -> Result<(), ErrorKind> {
        if self.enabled() {
            Ok(())
        } else {
            Err(ErrorKind::NotCompiledIn {
                feature: self,
                attr,
            })
        }
    }
}

impl Entity {
    /// The attributes the entity takes, in the order the printer writes them.
    pub const fn attributes(self) -> &'static [Attr] {
        use Attr::*;
        match self {
            Entity::Camera => &[Pixeldim, Worlddim, Viewpoint],
            Entity::Material => &[Ambient, Diffuse, Specular, Shininess, Transparency],
            Entity::Light => &[Location, Emissivity],
            Entity::Spotlight => &[Location, Emissivity, Point, Theta],
            Entity::Plane => &[Material, Normal, Point],
            Entity::Sphere => &[Material, Center, Radius],
            Entity::FPlane => &[Material, Normal, Point, Xdir, Dimensions],
            Entity::TiledPlane => &[Material, Normal, Point, Xdir, Dimensions, Altmaterial],
            Entity::Texture => &[Filename],
            Entity::TexPlane => &[Material, Normal, Point, Xdir, Dimensions, Texname, Mode],
            Entity::Projector => &[
                Location, Emissivity, Normal, Point, Xdir, Dimensions, Texname, Mode,
            ],
            Entity::RevSurf => &[Material, Surfer, Base, Direction, Height],
            Entity::Animation => &[Frames],
            Entity::Line => &[Target, By],
            Entity::Orbit => &[Target, Center, Direction, Turns],
            Entity::Bounce => &[Target, Height, Bounces],
        }
    }

    /// The most attributes an entity has (a projector's eight): a parsed block's slots.
    pub const MAX_ATTRIBUTES: usize = 8;

    /// Every entity, in the order the error messages list them.
    pub const ALL: [Entity; 16] = [
        Entity::Camera,
        Entity::Material,
        Entity::Light,
        Entity::Spotlight,
        Entity::Plane,
        Entity::Sphere,
        Entity::FPlane,
        Entity::TiledPlane,
        Entity::Texture,
        Entity::TexPlane,
        Entity::Projector,
        Entity::RevSurf,
        Entity::Animation,
        Entity::Line,
        Entity::Orbit,
        Entity::Bounce,
    ];

    /// The keyword that starts the block.
    pub const fn keyword(self) -> &'static str {
        match self {
            Entity::Camera => "camera",
            Entity::Material => "material",
            Entity::Light => "light",
            Entity::Spotlight => "spotlight",
            Entity::Plane => "plane",
            Entity::Sphere => "sphere",
            Entity::FPlane => "fplane",
            Entity::TiledPlane => "tiled_plane",
            Entity::Texture => "texture",
            Entity::TexPlane => "texplane",
            Entity::Projector => "projector",
            Entity::RevSurf => "revsurf",
            Entity::Animation => "animation",
            Entity::Line => "line",
            Entity::Orbit => "orbit",
            Entity::Bounce => "bounce",
        }
    }
}

impl fmt::Display for Entity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.keyword())
    }
}

/// The attributes inside blocks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Attr {
    Pixeldim,
    Worlddim,
    Viewpoint,
    Ambient,
    Diffuse,
    Specular,
    Shininess,
    Transparency,
    Location,
    Emissivity,
    Point,
    Theta,
    Material,
    Normal,
    Center,
    Radius,
    Xdir,
    Dimensions,
    Altmaterial,
    Filename,
    Texname,
    Mode,
    Surfer,
    Base,
    Direction,
    Height,
    Frames,
    Target,
    By,
    Turns,
    Bounces,
}

impl Attr {
    /// The number of attributes.
    pub const COUNT: usize = 31;

    /// The attribute's keyword.
    pub const fn keyword(self) -> &'static str {
        match self {
            Attr::Pixeldim => "pixeldim",
            Attr::Worlddim => "worlddim",
            Attr::Viewpoint => "viewpoint",
            Attr::Ambient => "ambient",
            Attr::Diffuse => "diffuse",
            Attr::Specular => "specular",
            Attr::Shininess => "shininess",
            Attr::Transparency => "transparency",
            Attr::Location => "location",
            Attr::Emissivity => "emissivity",
            Attr::Point => "point",
            Attr::Theta => "theta",
            Attr::Material => "material",
            Attr::Normal => "normal",
            Attr::Center => "center",
            Attr::Radius => "radius",
            Attr::Xdir => "xdir",
            Attr::Dimensions => "dimensions",
            Attr::Altmaterial => "altmaterial",
            Attr::Filename => "filename",
            Attr::Texname => "texname",
            Attr::Mode => "mode",
            Attr::Surfer => "surfer",
            Attr::Base => "base",
            Attr::Direction => "direction",
            Attr::Height => "height",
            Attr::Frames => "frames",
            Attr::Target => "target",
            Attr::By => "by",
            Attr::Turns => "turns",
            Attr::Bounces => "bounces",
        }
    }
}

impl fmt::Display for Attr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.keyword())
    }
}

/// The scene's bounded lists.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Collection {
    Objects,
    Materials,
    Lights,
    Textures,
    Motions,
}

impl fmt::Display for Collection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Collection::Objects => "objects",
            Collection::Materials => "materials",
            Collection::Lights => "lights",
            Collection::Textures => "textures",
            Collection::Motions => "motions",
        })
    }
}

/// The allowed range of a value, for [`ErrorKind::OutOfRange`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Range {
    /// `0 <= v <= 1`.
    ZeroToOne,
    /// `v >= 0`.
    NonNegative,
    /// `0 <= v <= 180` (degrees).
    HalfTurn,
    /// `0` or `1`.
    ZeroOrOne,
    /// `1`, `2` or `3` (the surfaces of revolution's profiles).
    Surfer,
    /// `1 <= v <= 65535` (frames, bounces).
    Count,
}

impl fmt::Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Range::ZeroToOne => "between 0 and 1",
            Range::NonNegative => "0 or more",
            Range::HalfTurn => "between 0 and 180 degrees",
            Range::ZeroOrOne => "0 or 1",
            Range::Surfer => "1, 2 or 3",
            Range::Count => "between 1 and 65535",
        })
    }
}

/// What is wrong with a texture's image file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextureError {
    /// The file could not be found.
    NotFound,
    /// The file exists but could not be read.
    Unreadable,
    /// The file does not start with `P6` (binary PPM).
    NotBinaryPpm,
    /// The header's width, height or maximum value is missing or not a number.
    BadHeader,
    /// Width or height is zero or above 65535.
    BadSize,
    /// The maximum sample value is not 255 (microray reads 8-bit PPM only).
    UnsupportedMaxValue,
    /// The file ends before all pixels.
    Truncated,
}

impl fmt::Display for TextureError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            TextureError::NotFound => "file not found",
            TextureError::Unreadable => "file cannot be read",
            TextureError::NotBinaryPpm => "not a binary PPM image (it must start with `P6`)",
            TextureError::BadHeader => "malformed PPM header (expected width, height and 255)",
            TextureError::BadSize => "image width and height must be 1 to 65535",
            TextureError::UnsupportedMaxValue => {
                "only 8-bit PPM images (maximum value 255) are supported"
            }
            TextureError::Truncated => "the file ends before the last pixel",
        })
    }
}

impl core::error::Error for TextureError {}

/// A short copy of the text an error is about (the found token, an undefined name).
///
/// Copied so that [`Error`] is `Copy` and needs no lifetime; long text is cut with `…`.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Snippet {
    bytes: [u8; Snippet::CAPACITY],
    len: u8,
    cut: bool,
    end_of_input: bool,
}

impl Snippet {
    const CAPACITY: usize = 32;

    /// The end of the input, shown as "end of file".
    pub const END: Snippet = Snippet {
        bytes: [0; Self::CAPACITY],
        len: 0,
        cut: false,
        end_of_input: true,
    };

    /// A copy of (the start of) `text`.
    pub fn new(text: &[u8]) -> Self {
        let len = text.len().min(Self::CAPACITY);
        let mut bytes = [0; Self::CAPACITY];
        for (to, from) in bytes.iter_mut().zip(text) {
            *to = *from;
        }
        // Never cut inside a UTF-8 sequence: back off to the start of the cut character.
        let mut keep = len;
        if text.len() > len {
            while keep > 0 && bytes.get(keep).is_some_and(|b| b & 0xC0 == 0x80) {
                keep -= 1;
            }
            if text.get(keep).is_some_and(|b| b & 0xC0 == 0x80) {
                keep = len;
            }
        }
        Self {
            bytes,
            len: u8::try_from(keep).unwrap_or(0),
            cut: text.len() > keep,
            end_of_input: false,
        }
    }

    /// The copied bytes.
    pub fn as_bytes(&self) -> &[u8] {
        self.bytes.get(..usize::from(self.len)).unwrap_or(&[])
    }

    /// Whether this stands for the end of the input.
    pub fn is_end(&self) -> bool {
        self.end_of_input
    }
}

impl fmt::Display for Snippet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.end_of_input {
            return f.write_str("end of file");
        }
        f.write_str("`")?;
        for chunk in self.as_bytes().utf8_chunks() {
            for c in chunk.valid().chars() {
                if c.is_control() {
                    write!(f, "{}", c.escape_default())?;
                } else {
                    write!(f, "{c}")?;
                }
            }
            for b in chunk.invalid() {
                write!(f, "\\x{b:02x}")?;
            }
        }
        if self.cut {
            f.write_str("…")?;
        }
        f.write_str("`")
    }
}

impl fmt::Debug for Snippet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

/// What went wrong. The `Display` text is the message after `LINE:COL: error: `.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// A block must start with an entity keyword.
    UnknownEntity {
        /// What was there instead.
        found: Snippet,
    },
    /// The entity keyword must be followed by a name.
    ExpectedName {
        /// The block's kind.
        entity: Entity,
        /// What was there instead.
        found: Snippet,
    },
    /// The name must be followed by `{`.
    ExpectedOpenBrace {
        /// The block's kind.
        entity: Entity,
        /// What was there instead.
        found: Snippet,
    },
    /// A word inside a block that is not one of its attributes.
    UnknownAttribute {
        /// The block's kind.
        entity: Entity,
        /// The word.
        found: Snippet,
    },
    /// An object's first attribute must be `material`, as in the course format.
    MaterialNotFirst {
        /// The block's kind.
        entity: Entity,
    },
    /// The same attribute twice in one block.
    DuplicateAttribute {
        /// The attribute.
        attr: Attr,
    },
    /// A required attribute is missing from a block.
    MissingAttribute {
        /// The block's kind.
        entity: Entity,
        /// The attribute.
        attr: Attr,
    },
    /// Fewer values than the attribute takes.
    MissingValues {
        /// The attribute.
        attr: Attr,
        /// How many it takes.
        expected: u8,
        /// How many were there.
        found: u8,
        /// What came instead of the next value.
        next: Snippet,
    },
    /// More values than the attribute takes.
    ExtraValue {
        /// The attribute.
        attr: Attr,
        /// How many it takes.
        expected: u8,
    },
    /// A value that should be a number is not one.
    NotANumber {
        /// The attribute.
        attr: Attr,
        /// The text.
        found: Snippet,
    },
    /// `nan`, `inf` and the like: microray reads finite decimals only.
    NotFinite {
        /// The text.
        found: Snippet,
    },
    /// A value in a scene built in source that is NaN or infinite.
    NonFiniteValue {
        /// The attribute.
        attr: Attr,
    },
    /// A value (or one computed from it at load) beyond the range of the scene's number type.
    BeyondRange {
        /// The attribute.
        attr: Attr,
        /// The number type's name.
        number_type: &'static str,
    },
    /// A length below the resolution of the scene's number type (after any scaling).
    TooSmallForType {
        /// The attribute.
        attr: Attr,
        /// The number type's name.
        number_type: &'static str,
    },
    /// A length that falls below the number type's resolution only because the scene had
    /// to be scaled down to bring a far coordinate within the type's range: the far value
    /// is the cause, and the error names it.
    ScaledBelowResolution {
        /// The attribute that became too small.
        attr: Attr,
        /// The number type's name.
        number_type: &'static str,
        /// The attribute holding the scene's largest coordinate.
        largest_at: Attr,
        /// That coordinate's size, rounded to a whole number (saturating).
        largest: u64,
        /// The type's range for coordinates: `2^range_log2`.
        range_log2: u16,
        /// The scene was scaled by `2^-scaled_log2`.
        scaled_log2: u16,
    },
    /// Neighbouring pixels' rays differ in direction by less than the number type can hold
    /// (a tiny `worlddim` spread over many pixels, seen from afar): rows or columns would
    /// merge.
    PixelsTooFine {
        /// The number type's name.
        number_type: &'static str,
        /// The steps of its resolution neighbouring pixels need at least.
        steps: u32,
    },
    /// A number beyond the range of `f64`.
    NumberTooLarge {
        /// The text.
        found: Snippet,
    },
    /// A value that must be a whole number is not one.
    NotAnInteger {
        /// The attribute.
        attr: Attr,
        /// The text.
        found: Snippet,
    },
    /// A name or path attribute without its word.
    ExpectedWord {
        /// The attribute.
        attr: Attr,
        /// What was there instead.
        found: Snippet,
    },
    /// The input ends inside a block.
    UnclosedBlock {
        /// The block's kind.
        entity: Entity,
        /// Where the block was opened.
        opened: Position,
    },
    /// A control character outside a comment.
    InvalidCharacter {
        /// The byte.
        byte: u8,
    },
    /// A name or path that is not valid UTF-8.
    NotUtf8,
    /// A name or path longer than its bounded buffer.
    NameTooLong {
        /// The most bytes it may have.
        max: u16,
    },
    /// An object names a material that was not defined before it.
    UndefinedMaterial {
        /// `material` or `altmaterial`.
        attr: Attr,
        /// The name.
        name: Snippet,
    },
    /// A textured plane names a texture that was not defined before it.
    UndefinedTexture {
        /// The name.
        name: Snippet,
    },
    /// Two materials (or two textures) with the same name: references would be ambiguous.
    DuplicateName {
        /// The block's kind.
        entity: Entity,
        /// The name.
        name: Snippet,
    },
    /// A scene has exactly one camera.
    SecondCamera,
    /// A scene has exactly one camera.
    NoCamera,
    /// A motion names an object or light that is not defined before it.
    UndefinedTarget {
        /// The name.
        name: Snippet,
    },
    /// A second `animation` block (a scene has at most one).
    SecondAnimation,
    /// Motions without an `animation` block, which gives the number of frames.
    NoAnimation,
    /// A change names an object, light or material by a number the scene does not have.
    NoSuchIndex {
        /// Which list.
        what: Collection,
        /// The number asked for (from 0, in definition order).
        index: u16,
    },
    /// A length that must be above zero (radius, world size, rectangle size).
    NotPositive {
        /// The attribute.
        attr: Attr,
    },
    /// `pixeldim` needs at least 2 by 2: the camera divides by `pixeldim - 1`.
    PixeldimTooSmall,
    /// The image is wider than the row buffer this build renders with.
    ImageTooWide {
        /// The width asked for.
        width: u32,
        /// The most this build takes.
        max: u32,
    },
    /// The image is taller than 65535 rows.
    ImageTooTall {
        /// The height asked for.
        height: u32,
    },
    /// A direction that is zero (a zero normal, or a spotlight aimed at its own location).
    ZeroVector {
        /// The attribute.
        attr: Attr,
    },
    /// `xdir` lies along the normal, so it gives no direction within the plane.
    XdirParallelToNormal,
    /// A value outside its allowed range.
    OutOfRange {
        /// The attribute.
        attr: Attr,
        /// The allowed range.
        range: Range,
    },
    /// A transparent material filters light by its diffuse colour, so it needs one.
    TransparentWithoutDiffuse,
    /// The scene needs something this build of microray left out (a cargo feature).
    NotCompiledIn {
        /// The feature that would provide it.
        feature: Feature,
        /// The attribute that asks for it; `None` when the whole block does.
        attr: Option<Attr>,
    },
    /// A bounded list is full.
    CapacityExceeded {
        /// Which list.
        what: Collection,
        /// Its capacity in this build.
        capacity: u16,
    },
    /// A texture's image file is missing or malformed.
    Texture {
        /// The file name.
        file: Snippet,
        /// What is wrong.
        error: TextureError,
    },
    /// A compiled scene ([`crate::compiled`]) is malformed.
    Compiled {
        /// The byte where the problem starts.
        offset: u32,
        /// What is wrong.
        problem: CompiledError,
    },
}

impl ErrorKind {
    /// The attribute the error is about, if any (the parser points at it).
    pub const fn attribute(&self) -> Option<Attr> {
        match *self {
            ErrorKind::NotPositive { attr }
            | ErrorKind::ZeroVector { attr }
            | ErrorKind::NonFiniteValue { attr }
            | ErrorKind::BeyondRange { attr, .. }
            | ErrorKind::TooSmallForType { attr, .. }
            | ErrorKind::ScaledBelowResolution { attr, .. }
            | ErrorKind::UndefinedMaterial { attr, .. }
            | ErrorKind::OutOfRange { attr, .. } => Some(attr),
            ErrorKind::PixeldimTooSmall
            | ErrorKind::PixelsTooFine { .. }
            | ErrorKind::ImageTooWide { .. }
            | ErrorKind::ImageTooTall { .. } => Some(Attr::Pixeldim),
            ErrorKind::XdirParallelToNormal => Some(Attr::Xdir),
            ErrorKind::UndefinedTexture { .. } => Some(Attr::Texname),
            ErrorKind::UndefinedTarget { .. } => Some(Attr::Target),
            ErrorKind::TransparentWithoutDiffuse => Some(Attr::Transparency),
            ErrorKind::Texture { .. } => Some(Attr::Filename),
            ErrorKind::NotCompiledIn { attr, .. } => attr,
            _ => None,
        }
    }
}

/// A size: whole below 10^15, else its power of ten.
fn write_size(f: &mut fmt::Formatter<'_>, size: u64) -> fmt::Result {
    if size < 1_000_000_000_000_000 {
        return write!(f, "{size}");
    }
    if size == u64::MAX {
        return f.write_str("over 10^19");
    }
    write!(f, "about 10^{}", size.ilog10())
}

fn write_list(
    f: &mut fmt::Formatter<'_>,
    words: impl Iterator<Item = &'static str>,
) -> fmt::Result {
    for (i, word) in words.enumerate() {
        if i > 0 {
            f.write_str(", ")?;
        }
        f.write_str(word)?;
    }
    Ok(())
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ErrorKind::UnknownEntity { found } => {
                write!(f, "expected an entity (")?;
                write_list(f, Entity::ALL.iter().map(|e| e.keyword()))?;
                write!(f, "), found {found}")
            }
            ErrorKind::ExpectedName { entity, found } => {
                write!(f, "expected a name after `{entity}`, found {found}")
            }
            ErrorKind::ExpectedOpenBrace { entity, found } => {
                write!(f, "expected `{{` to open the {entity} block, found {found}")
            }
            ErrorKind::UnknownAttribute { entity, found } => {
                write!(f, "unknown attribute {found} in {entity} (expected ")?;
                write_list(f, entity.attributes().iter().map(|a| a.keyword()))?;
                write!(f, " or `}}`)")
            }
            ErrorKind::MaterialNotFirst { entity } => {
                write!(f, "expected `material` as the first attribute of {entity}")
            }
            ErrorKind::DuplicateAttribute { attr } => {
                write!(f, "`{attr}` is given twice in this block")
            }
            ErrorKind::MissingAttribute { entity, attr } => {
                write!(f, "{entity} is missing `{attr}`")
            }
            ErrorKind::MissingValues {
                attr,
                expected,
                found,
                next,
            } => {
                let takes = Takes { attr, expected };
                write!(f, "`{attr}` takes {takes}, found {found} before {next}")
            }
            ErrorKind::ExtraValue { attr, expected } => {
                write!(
                    f,
                    "extra value: `{attr}` takes {}",
                    Takes { attr, expected }
                )
            }
            ErrorKind::NotANumber { attr, found } => {
                write!(f, "expected a number for `{attr}`, found {found}")
            }
            ErrorKind::NotFinite { found } => {
                write!(
                    f,
                    "{found} is not a finite number (scene files hold finite decimals)"
                )
            }
            ErrorKind::NonFiniteValue { attr } => {
                write!(f, "`{attr}` has a value that is not finite")
            }
            ErrorKind::BeyondRange { attr, number_type } => {
                write!(
                    f,
                    "`{attr}` is beyond the range of {number_type}, the number type of this build"
                )
            }
            ErrorKind::TooSmallForType { attr, number_type } => write!(
                f,
                "`{attr}` is too small for {number_type}, the number type of this build (below its resolution once the scene is scaled to its range)"
            ),
            ErrorKind::ScaledBelowResolution {
                attr,
                number_type,
                largest_at,
                largest,
                range_log2,
                scaled_log2,
            } => {
                f.write_str("the scene reaches ")?;
                write_size(f, largest)?;
                write!(
                    f,
                    " from the origin (its `{largest_at}`), beyond {number_type}'s range of 2^{range_log2}: scaled by 2^-{scaled_log2} to fit, its `{attr}` falls below {number_type}'s resolution (bring the scene nearer the origin, make it smaller, or use a wider number type)"
                )
            }
            ErrorKind::PixelsTooFine { number_type, steps } => write!(
                f,
                "neighbouring pixels are closer in direction than {number_type} can tell apart (at least {steps} steps of its resolution are needed: use fewer pixels or a larger `worlddim`)"
            ),
            ErrorKind::NumberTooLarge { found } => {
                write!(f, "{found} is out of range (beyond ±1.8e308)")
            }
            ErrorKind::NotAnInteger { attr, found } => {
                write!(f, "`{attr}` takes whole numbers, found {found}")
            }
            ErrorKind::ExpectedWord { attr, found } => {
                let what = if matches!(attr, Attr::Filename) {
                    "a file name"
                } else {
                    "a name"
                };
                write!(f, "expected {what} after `{attr}`, found {found}")
            }
            ErrorKind::UnclosedBlock { entity, opened } => {
                write!(
                    f,
                    "expected `}}` to close the {entity} block opened at {opened}, found end of file"
                )
            }
            ErrorKind::InvalidCharacter { byte } => {
                write!(
                    f,
                    "invalid character 0x{byte:02x} (control characters are allowed only in comments)"
                )
            }
            ErrorKind::NotUtf8 => write!(f, "names and file names must be valid UTF-8"),
            ErrorKind::NameTooLong { max } => write!(f, "name is longer than {max} bytes"),
            ErrorKind::UndefinedMaterial { name, .. } => {
                write!(
                    f,
                    "undefined material {name} (materials must be defined before the objects that use them)"
                )
            }
            ErrorKind::UndefinedTexture { name } => {
                write!(
                    f,
                    "undefined texture {name} (textures must be defined before the planes and projectors that use them)"
                )
            }
            ErrorKind::DuplicateName { entity, name } => {
                write!(f, "a {entity} named {name} is already defined")
            }
            ErrorKind::SecondCamera => write!(f, "second camera (a scene has exactly one)"),
            ErrorKind::UndefinedTarget { name } => {
                write!(
                    f,
                    "no object or light named {name} (a motion moves an object or light defined before it)"
                )
            }
            ErrorKind::SecondAnimation => {
                write!(f, "second `animation` block (a scene has at most one)")
            }
            ErrorKind::NoAnimation => write!(
                f,
                "motions but no `animation` block (it gives the number of frames: `animation clip {{ frames 48 }}`)"
            ),
            ErrorKind::NoSuchIndex { what, index } => {
                write!(
                    f,
                    "the scene's {what} have no number {index} (counted from 0)"
                )
            }
            ErrorKind::NoCamera => {
                write!(f, "no camera (a scene needs exactly one `camera` block)")
            }
            ErrorKind::NotPositive { attr } => write!(f, "`{attr}` must be greater than 0"),
            ErrorKind::PixeldimTooSmall => {
                write!(
                    f,
                    "`pixeldim` must be at least 2 by 2 (pixels map through pixeldim - 1)"
                )
            }
            ErrorKind::ImageTooWide { width, max } => {
                write!(
                    f,
                    "image is {width} pixels wide; this build's row buffer holds {max}"
                )
            }
            ErrorKind::ImageTooTall { height } => {
                write!(
                    f,
                    "image is {height} pixels tall; at most 65535 rows are supported"
                )
            }
            ErrorKind::ZeroVector { attr } => {
                if matches!(attr, Attr::Point) {
                    write!(
                        f,
                        "spotlight `point` equals its `location`, so it has no direction"
                    )
                } else {
                    write!(f, "`{attr}` must not be the zero vector")
                }
            }
            ErrorKind::XdirParallelToNormal => {
                write!(
                    f,
                    "`xdir` is parallel to the normal, so it gives no direction in the plane"
                )
            }
            ErrorKind::OutOfRange { attr, range } => write!(f, "`{attr}` must be {range}"),
            ErrorKind::NotCompiledIn { feature, .. } => write!(
                f,
                "this build of microray leaves out {} (cargo feature `{}`)",
                feature.what(),
                feature.name()
            ),
            ErrorKind::TransparentWithoutDiffuse => write!(
                f,
                "a transparent material needs a positive `diffuse` (it filters light by the diffuse colour)"
            ),
            ErrorKind::CapacityExceeded { what, capacity } => {
                write!(f, "too many {what}: this build holds {capacity}")
            }
            ErrorKind::Texture { file, error } => write!(f, "texture file {file}: {error}"),
            ErrorKind::Compiled { offset, problem } => {
                write!(f, "compiled scene, byte {offset}: {problem}")
            }
        }
    }
}

/// How many numbers an attribute takes: `specular` one for every channel or three.
struct Takes {
    attr: Attr,
    expected: u8,
}

impl fmt::Display for Takes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.attr, self.expected) {
            (Attr::Specular, _) => f.write_str("1 or 3 numbers"),
            (_, 1) => f.write_str("1 number"),
            (_, n) => write!(f, "{n} numbers"),
        }
    }
}

impl fmt::Display for CompiledError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            CompiledError::NotCompiled => {
                f.write_str("not a compiled scene of this version (`microray compile` writes one)")
            }
            CompiledError::OtherNumberType { found } => write!(
                f,
                "compiled for another number type (code {found}; 1 f64, 2 f32, 3 i16f16)"
            ),
            CompiledError::Truncated => f.write_str("ends early"),
            CompiledError::BadValue => {
                f.write_str("no such object kind, flag, axis or mode, or a window not above 0")
            }
            CompiledError::BadIndex => f.write_str("index past the end of its list"),
            CompiledError::Trailing => f.write_str("bytes after the last object"),
        }
    }
}

impl core::error::Error for CompiledError {}

// Every entity's attributes fit a block's slots (checked when the crate compiles).
#[allow(clippy::indexing_slicing)]
const _: () = {
    let mut i = 0;
    while i < Entity::ALL.len() {
        assert!(Entity::ALL[i].attributes().len() <= Entity::MAX_ATTRIBUTES);
        i += 1;
    }
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_count_lines_and_characters() {
        let text = "ab\ncé d\n".as_bytes();
        assert_eq!(
            Position::of_offset(text, 0),
            Position { line: 1, column: 1 }
        );
        assert_eq!(
            Position::of_offset(text, 3),
            Position { line: 2, column: 1 }
        );
        // `d` is byte 7 but character 4 of line 2 (é is two bytes).
        assert_eq!(
            Position::of_offset(text, 7),
            Position { line: 2, column: 4 }
        );
        assert_eq!(
            Position::of_offset(text, 99),
            Position { line: 3, column: 1 }
        );
    }

    #[test]
    fn snippets_cut_long_text_on_character_boundaries() {
        let long = "é".repeat(40);
        let s = Snippet::new(long.as_bytes());
        assert_eq!(s.as_bytes().len(), 32);
        assert_eq!(std::format!("{s}"), std::format!("`{}…`", "é".repeat(16)));
        assert_eq!(
            std::format!("{}", Snippet::new(b"a\x00\xff")),
            "`a\\u{0}\\xff`"
        );
        assert_eq!(std::format!("{}", Snippet::END), "end of file");
    }
}
