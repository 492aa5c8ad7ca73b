//! The scene language's lines, written: `KEYWORD NAME {`, `ATTR values`, `}`. Each kind
//! prints itself with these (the course's `printer` functions); [`crate::print`] writes a
//! whole scene with the kinds' printers.
//!
//! Values are written in the shortest decimal that reads back exactly.

use crate::error::Attr;
use crate::scalar::Scalar;
use crate::vec3::Vec3;
use core::fmt;

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
