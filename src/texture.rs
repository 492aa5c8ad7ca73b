//! Textures: binary PPM (P6) images, read in place from a byte slice.

use crate::error::{ErrorKind, Snippet, TextureError};
use crate::name::{FilePath, Name, bounded};
#[cfg(feature = "print")]
use crate::write;
#[cfg(feature = "print")]
use core::fmt;

/// A texture as written: its name, its file name, and the file's bytes.
///
/// `ppm` is borrowed for the scene's lifetime `'t`: a firmware scene uses `include_bytes!`,
/// the host tracer the bytes it read from the file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureDef<'a, 't> {
    /// The name texture planes refer to it by.
    pub name: &'a str,
    /// The file name, as written in the scene.
    pub filename: &'a str,
    /// The binary PPM file.
    pub ppm: &'t [u8],
}

/// A decoded texture: the pixels are the file's own bytes, not a copy.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture<'t> {
    name: Name,
    filename: FilePath,
    width: u16,
    height: u16,
    pixels: &'t [u8],
}

impl<'t> Texture<'t> {
    /// Decodes a definition's PPM bytes.
    pub(crate) fn build(def: &TextureDef<'_, 't>) -> Result<Self, ErrorKind> {
        let (width, height, pixels) = decode_ppm(def.ppm).map_err(|error| ErrorKind::Texture {
            file: Snippet::new(def.filename.as_bytes()),
            error,
        })?;
        Ok(Self {
            name: bounded(def.name)?,
            filename: bounded(def.filename)?,
            width,
            height,
            pixels,
        })
    }

    /// The texture's name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// The file name written in the scene.
    pub fn filename(&self) -> &str {
        &self.filename
    }
    /// Width in pixels.
    pub fn width(&self) -> u16 {
        self.width
    }
    /// Height in pixels.
    pub fn height(&self) -> u16 {
        self.height
    }

    /// The pixel at column `x` of row `y`, rows counted from the top of the file.
    /// Outside the image: black.
    pub fn texel(&self, x: usize, y: usize) -> [u8; 3] {
        if x >= usize::from(self.width) {
            return [0; 3];
        }
        let start = y
            .saturating_mul(usize::from(self.width))
            .saturating_add(x)
            .saturating_mul(3);
        match self.pixels.get(start..start.saturating_add(3)) {
            Some(&[r, g, b]) => [r, g, b],
            _ => [0; 3],
        }
    }

    /// Writes the texture block.
    #[cfg(feature = "print")]
    pub fn print(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        write::header(out, "texture", &self.name)?;
        write::word(out, crate::error::Attr::Filename, &self.filename)?;
        write::footer(out)
    }
}

/// A texture resolver for scenes without textures (for the parser and compiled scenes):
/// every file is "not found".
pub fn no_textures<'t>(_filename: &str) -> Result<&'t [u8], TextureError> {
    Err(TextureError::NotFound)
}

/// Reads a P6 header and returns width, height and the pixel bytes (borrowed).
pub fn decode_ppm(bytes: &[u8]) -> Result<(u16, u16, &[u8]), TextureError> {
    let rest = bytes
        .strip_prefix(b"P6")
        .ok_or(TextureError::NotBinaryPpm)?;
    let (width, rest) = header_number(rest)?;
    let (height, rest) = header_number(rest)?;
    let (max, rest) = header_number(rest)?;
    if max != 255 {
        return Err(TextureError::UnsupportedMaxValue);
    }
    // Exactly one whitespace byte separates the header from the pixels.
    let pixels = match rest.split_first() {
        Some((b, pixels)) if b.is_ascii_whitespace() => pixels,
        _ => return Err(TextureError::BadHeader),
    };
    let (width, height) = match (u16::try_from(width), u16::try_from(height)) {
        (Ok(w), Ok(h)) if w > 0 && h > 0 => (w, h),
        _ => return Err(TextureError::BadSize),
    };
    let size = usize::from(width) * usize::from(height) * 3;
    let pixels = pixels.get(..size).ok_or(TextureError::Truncated)?;
    Ok((width, height, pixels))
}

/// Skips whitespace and `#` comments, then reads a decimal number of up to 9 digits.
fn header_number(mut rest: &[u8]) -> Result<(u32, &[u8]), TextureError> {
    loop {
        match rest.split_first() {
            Some((b, tail)) if b.is_ascii_whitespace() => rest = tail,
            Some((b'#', _)) => {
                let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
                rest = rest.get(end..).unwrap_or(&[]);
            }
            _ => break,
        }
    }
    let digits = rest.iter().take_while(|b| b.is_ascii_digit()).count();
    if digits == 0 || digits > 9 {
        return Err(TextureError::BadHeader);
    }
    let value = rest
        .iter()
        .take(digits)
        .fold(0u32, |acc, d| acc * 10 + u32::from(d - b'0'));
    Ok((value, rest.get(digits..).unwrap_or(&[])))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decodes_header_with_comment_without_copying() {
        let file = b"P6\n# made by hand\n2 1\n255\n\x01\x02\x03\x04\x05\x06extra";
        let (w, h, pixels) = decode_ppm(file).unwrap();
        assert_eq!((w, h), (2, 1));
        assert_eq!(pixels, b"\x01\x02\x03\x04\x05\x06");
        assert!(core::ptr::eq(pixels.as_ptr(), file[26..].as_ptr()));
    }

    #[test]
    fn rejects_malformed_files() {
        assert_eq!(
            decode_ppm(b"P3 1 1 255 0 0 0"),
            Err(TextureError::NotBinaryPpm)
        );
        assert_eq!(decode_ppm(b"P6 1 255 "), Err(TextureError::BadHeader));
        assert_eq!(
            decode_ppm(b"P6 1 1 65535 \0\0\0\0\0\0"),
            Err(TextureError::UnsupportedMaxValue)
        );
        assert_eq!(decode_ppm(b"P6 0 1 255 "), Err(TextureError::BadSize));
        assert_eq!(
            decode_ppm(b"P6 2 2 255 \0\0\0"),
            Err(TextureError::Truncated)
        );
        assert_eq!(
            decode_ppm(b"P6 99999999999 1 255 "),
            Err(TextureError::BadHeader)
        );
    }

    #[test]
    fn texel_outside_is_black() {
        let file = b"P6 1 1 255 \x07\x08\x09";
        let t = Texture::build(&TextureDef {
            name: "t",
            filename: "t.ppm",
            ppm: file,
        })
        .unwrap();
        assert_eq!(t.texel(0, 0), [7, 8, 9]);
        assert_eq!(t.texel(1, 0), [0; 3]);
        assert_eq!(t.texel(0, usize::MAX), [0; 3]);
    }
}
