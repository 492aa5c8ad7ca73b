//! Bounded text: object, material, light and texture names, and texture file paths.
//!
//! The course kept names in fixed `char` buffers and overflowed them on long input; here a
//! name that does not fit is an [`ErrorKind::NameTooLong`] at load time.

use crate::error::ErrorKind;

/// The longest name, in bytes.
pub const NAME_CAPACITY: usize = 32;
/// The longest texture file path, in bytes.
pub const PATH_CAPACITY: usize = 128;

/// A name of an entity: at most [`NAME_CAPACITY`] bytes.
pub type Name = heapless::String<NAME_CAPACITY>;
/// A texture file path: at most [`PATH_CAPACITY`] bytes.
pub type FilePath = heapless::String<PATH_CAPACITY>;

/// Copies `text` into a bounded string, or says it is too long.
pub(crate) fn bounded<const N: usize>(text: &str) -> Result<heapless::String<N>, ErrorKind> {
    let mut out = heapless::String::new();
    out.push_str(text).map_err(|_| ErrorKind::NameTooLong {
        max: u16::try_from(N).unwrap_or(u16::MAX),
    })?;
    Ok(out)
}
