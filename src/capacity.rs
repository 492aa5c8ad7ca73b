//! How much room a scene needs: its capacities counted from the scene's text, at compile
//! time if need be, and named sizes for scenes written by hand.
//!
//! A [`Scene`](crate::Scene)'s five capacities are const generics, and every slot costs RAM
//! whether it is used or not. For a scene file that firmware embeds, [`Capacities::of_text`]
//! counts them in a `const`, so the type fits the file exactly and follows it when it
//! changes:
//!
//! ```
//! use microray::capacity::Capacities;
//! use microray::Scene;
//!
//! // In firmware: `include_bytes!("../scenes/minimal.txt")`.
//! const SCENE: &[u8] = b"
//!     camera eye { pixeldim 320 240 worlddim 8 6 viewpoint 4 3 3 }
//!     material white { diffuse 3 3 3 ambient 1 1 1 }
//!     material green { diffuse 1 6 1 }
//!     light top { location 4 10 0 emissivity 5 5 5 }
//!     plane floor { material white normal 0 1 0 point 0 0 0 }
//!     sphere ball { material green center 4 1 -3 radius 1 }
//! ";
//! const NEEDS: Capacities = Capacities::of_text(SCENE);
//! type MyScene = Scene<
//!     'static,
//!     f32,
//!     { NEEDS.objects },
//!     { NEEDS.materials },
//!     { NEEDS.lights },
//!     { NEEDS.textures },
//!     { NEEDS.max_width },
//! >;
//!
//! assert_eq!(NEEDS, Capacities { objects: 2, materials: 2, lights: 1, textures: 0, max_width: 320 });
//! let scene: MyScene = microray::parse::parse_scene(SCENE, microray::parse::no_textures)?;
//! assert_eq!(scene.objects().len(), 2);
//! # Ok::<(), microray::Error>(())
//! ```
//!
//! A firmware `build.rs` that picks its scenes at build time can call the same function
//! (and [`Capacities::max`] over several scenes) and write the type out.
//!
//! For scenes built in source, or read at run time, [`scene`](crate::scene)'s aliases give
//! common sizes a name: [`TinyScene`](crate::scene::TinyScene),
//! [`SmallScene`](crate::scene::SmallScene), [`LargeScene`](crate::scene::LargeScene) (and
//! the default [`Scene`](crate::Scene)).
//!
//! This module depends on no other: the parser shares its token rules.

/// The room a scene needs in each capacity of [`Scene`](crate::Scene): `Scene<'t, S, OBJECTS, MATERIALS,
/// LIGHTS, TEXTURES, MAX_WIDTH>`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Capacities {
    /// Objects (`plane`, `sphere`, `fplane`, `tiled_plane`, `texplane`, `revsurf`).
    pub objects: usize,
    /// Materials.
    pub materials: usize,
    /// Lights, spotlights and projectors.
    pub lights: usize,
    /// Textures: the `texture` blocks and the image files a `texname` names directly,
    /// each name once.
    pub textures: usize,
    /// The widest image: the camera's `pixeldim` width.
    pub max_width: usize,
}

impl Capacities {
    /// No room at all.
    pub const ZERO: Self = Self {
        objects: 0,
        materials: 0,
        lights: 0,
        textures: 0,
        max_width: 0,
    };

    /// What the scene in `text` defines, counted from its blocks without parsing their values
    /// (so without the `parser` feature, and in a `const`).
    ///
    /// For a scene the parser accepts, the counts are exact: a scene of this size loads, and
    /// one slot fewer in any list does not. For text the parser rejects they are only
    /// what the blocks it could make out ask for. `max_width` is read from a `pixeldim`
    /// written as digits (`320`, `320.0`); any other spelling counts as 0, and the scene
    /// then fails to load with an error naming the width.
    ///
    /// In a `const`, rustc allows a budget of evaluation steps: scene files of up to about
    /// 100 KB with up to 32 textures count within it (measured: 110 KB and 2,000 objects
    /// count, 167 KB does not). Past it rustc stops with "constant evaluation is taking a
    /// long time": count in a `build.rs` instead, or allow the `long_running_const_eval`
    /// lint where the `const` is.
    pub const fn of_text(text: &[u8]) -> Self {
        let mut needs = Self::ZERO;
        let mut events = Events::new(text);
        let mut names = TextureNames::new();
        while let Some(event) = events.next() {
            match event {
                Event::Block { keyword, name } => match keyword {
                    b"material" => needs.materials += 1,
                    b"light" | b"spotlight" | b"projector" => needs.lights += 1,
                    b"plane" | b"sphere" | b"fplane" | b"tiled_plane" | b"texplane"
                    | b"revsurf" => needs.objects += 1,
                    b"texture" => needs.textures += names.add(text, name) as usize,
                    _ => {}
                },
                Event::Texname(name) => needs.textures += names.add(text, name) as usize,
                Event::Width(width) => {
                    if width > needs.max_width {
                        needs.max_width = width;
                    }
                }
            }
        }
        needs
    }

    /// The larger of two in every capacity: room for either scene.
    pub const fn max(self, other: Self) -> Self {
        const fn larger(a: usize, b: usize) -> usize {
            if a > b { a } else { b }
        }
        Self {
            objects: larger(self.objects, other.objects),
            materials: larger(self.materials, other.materials),
            lights: larger(self.lights, other.lights),
            textures: larger(self.textures, other.textures),
            max_width: larger(self.max_width, other.max_width),
        }
    }
}

/// What the scan of a scene's text reports.
#[derive(Clone, Copy)]
enum Event<'a> {
    /// `KEYWORD NAME {` at the top level.
    Block { keyword: &'a [u8], name: &'a [u8] },
    /// The value of a `texname`.
    Texname(&'a [u8]),
    /// The first value of a `pixeldim`, read as a whole number.
    Width(usize),
}

/// The scene language's tokens, scanned in a `const fn`: blanks and `#` comments between
/// them, `{` and `}` tokens of their own (as the parser splits them).
struct Events<'a> {
    rest: &'a [u8],
    /// The two tokens before the current one, at the top level.
    before: [&'a [u8]; 2],
    /// Inside a block.
    inside: bool,
    /// The attribute whose first value comes next (`texname` or `pixeldim`), if any.
    pending: &'a [u8],
}

impl<'a> Events<'a> {
    const fn new(text: &'a [u8]) -> Self {
        Self {
            rest: text,
            before: [b"", b""],
            inside: false,
            pending: b"",
        }
    }

    const fn next(&mut self) -> Option<Event<'a>> {
        while let Some(token) = self.token() {
            if !self.inside {
                if is(token, b"{") {
                    self.inside = true;
                    let [keyword, name] = self.before;
                    self.before = [b"", b""];
                    return Some(Event::Block { keyword, name });
                }
                self.before = [self.before[1], token];
                continue;
            }
            if is(token, b"}") {
                self.inside = false;
                self.pending = b"";
                continue;
            }
            let pending = self.pending;
            self.pending = b"";
            if is(pending, b"texname") {
                return Some(Event::Texname(token));
            }
            if is(pending, b"pixeldim") {
                return Some(Event::Width(whole_number(token)));
            }
            if is(token, b"texname") || is(token, b"pixeldim") {
                self.pending = token;
            }
        }
        None
    }

    /// The next token, past blanks and comments.
    const fn token(&mut self) -> Option<&'a [u8]> {
        // Blanks and comments.
        let mut comment = false;
        while let Some((&b, rest)) = self.rest.split_first() {
            if comment {
                comment = b != b'\n';
            } else if b == b'#' {
                comment = true;
            } else if !is_space(b) {
                break;
            }
            self.rest = rest;
        }
        let start = self.rest;
        let Some((&first, after_first)) = start.split_first() else {
            return None;
        };
        if first == b'{' || first == b'}' {
            self.rest = after_first;
            return match start.split_at_checked(1) {
                Some((brace, _)) => Some(brace),
                None => None,
            };
        }
        let mut len = 0;
        let mut rest = start;
        while let Some((&b, after)) = rest.split_first() {
            if is_delimiter(b) {
                break;
            }
            len += 1;
            rest = after;
        }
        self.rest = rest;
        match start.split_at_checked(len) {
            Some((token, _)) => Some(token),
            None => None,
        }
    }
}

/// The texture names met so far (a `texture` block's name or a `texname`'s value), to count
/// each once as the parser makes one texture of each: the first [`TextureNames::KEPT`]
/// distinct ones kept to compare with, the rest looked for again in the text (slower: a
/// `const` has a budget of evaluation steps).
struct TextureNames<'a> {
    kept: [&'a [u8]; TextureNames::KEPT],
    distinct: usize,
    /// Texture names met, repeats included.
    met: usize,
}

impl<'a> TextureNames<'a> {
    const KEPT: usize = 32;

    const fn new() -> Self {
        Self {
            kept: [b""; Self::KEPT],
            distinct: 0,
            met: 0,
        }
    }

    /// Meets `name` in `text`: whether it is new.
    const fn add(&mut self, text: &[u8], name: &'a [u8]) -> bool {
        let earlier = self.met;
        self.met += 1;
        let stored = if self.distinct < Self::KEPT {
            self.distinct
        } else {
            Self::KEPT
        };
        // Always splits (`stored` is at most the length); else counting it is safe.
        let Some((kept, free)) = self.kept.split_at_mut_checked(stored) else {
            return true;
        };
        let mut rest: &[&[u8]] = kept;
        while let Some((first, tail)) = rest.split_first() {
            if is(first, name) {
                return false;
            }
            rest = tail;
        }
        match free.split_first_mut() {
            Some((slot, _)) => *slot = name,
            None => {
                if named_before(text, name, earlier) {
                    return false;
                }
            }
        }
        self.distinct += 1;
        true
    }
}

/// Whether a texture name came among the first `count` texture names of `text` (a
/// `texture` block's name or a `texname`'s value): the parser makes one texture of each.
const fn named_before(text: &[u8], name: &[u8], count: usize) -> bool {
    let mut events = Events::new(text);
    let mut seen = 0;
    while seen < count {
        let Some(event) = events.next() else {
            return false;
        };
        let earlier = match event {
            Event::Block {
                keyword: b"texture",
                name,
            } => name,
            Event::Texname(name) => name,
            _ => continue,
        };
        if is(earlier, name) {
            return true;
        }
        seen += 1;
    }
    false
}

/// White space between tokens (the parser's too).
pub(crate) const fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c)
}

/// What ends a token: white space or a brace (the parser's too).
pub(crate) const fn is_delimiter(b: u8) -> bool {
    is_space(b) || b == b'{' || b == b'}'
}

/// Byte-wise equality, in a `const fn`.
const fn is(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let (mut a, mut b) = (a, b);
    while let (Some((x, a_rest)), Some((y, b_rest))) = (a.split_first(), b.split_first()) {
        if *x != *y {
            return false;
        }
        a = a_rest;
        b = b_rest;
    }
    true
}

/// `digits` or `digits.000`, saturating; 0 for anything else.
const fn whole_number(token: &[u8]) -> usize {
    let mut value: usize = 0;
    let mut rest = token;
    let mut digits = 0;
    while let Some((&b, after)) = rest.split_first() {
        if !b.is_ascii_digit() {
            break;
        }
        value = value.saturating_mul(10).saturating_add((b - b'0') as usize);
        digits += 1;
        rest = after;
    }
    if let Some((b'.', mut fraction)) = rest.split_first() {
        while let Some((b'0', after)) = fraction.split_first() {
            fraction = after;
        }
        rest = fraction;
    }
    if digits == 0 || !rest.is_empty() {
        return 0;
    }
    value
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_split_at_braces_and_skip_comments() {
        let text = b"camera c{pixeldim 64.0 48 # pixeldim 999 9\n}texture t{filename a.ppm}";
        let needs = Capacities::of_text(text);
        assert_eq!(needs.max_width, 64);
        assert_eq!(needs.textures, 1);
    }

    #[test]
    fn a_texture_named_twice_takes_one_slot() {
        let text = b"texture wood { filename wood.ppm }
            texplane a { material m texname wood }
            texplane b { material m texname card.ppm }
            texplane c { material m texname card.ppm }
            projector p { texname card.ppm }";
        let needs = Capacities::of_text(text);
        assert_eq!((needs.textures, needs.objects, needs.lights), (2, 3, 1));
    }

    #[test]
    fn textures_past_the_kept_ones_count_once_too() {
        let mut text = std::string::String::new();
        for round in 0..2 {
            for k in 0..40 {
                if round == 0 {
                    text += &format!("texture t{k} {{ filename t{k}.ppm }}\n");
                }
                text += &format!("texplane p{round}x{k} {{ material m texname t{k} }}\n");
            }
        }
        text += "texplane file { material m texname other.ppm }\n";
        let needs = Capacities::of_text(text.as_bytes());
        assert_eq!((needs.textures, needs.objects), (41, 81));
    }

    #[test]
    fn widths_in_other_spellings_count_as_zero() {
        for width in ["6.4e2", "-640", "64x", "1.5"] {
            let text = format!("camera c {{ pixeldim {width} 48 }}");
            assert_eq!(Capacities::of_text(text.as_bytes()).max_width, 0, "{width}");
        }
    }
}
