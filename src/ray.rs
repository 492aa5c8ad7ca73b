//! Rays: a base point and a direction.

use crate::scalar::Scalar;
use crate::vec3::Vec3;

/// A ray `base + t * dir`, `t > 0`.
///
/// In `f64`, which follows the course's order of operations, every ray the tracer makes has
/// a unit direction. The other number types leave primary rays unnormalised (`dir` from
/// the eye to the pixel) and shadow rays end at the light (`t = 1`): `t` is then a
/// parameter, not a distance, and `len` says what one unit of it measures, when the maker
/// of the ray knows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray<S> {
    /// Where the ray starts.
    pub base: Vec3<S>,
    /// Where it goes.
    pub dir: Vec3<S>,
    /// `|dir|`, or zero when it was not computed (see [`length`](Self::length)).
    pub len: S,
}

impl<S: Scalar> Ray<S> {
    /// A ray whose direction's length is not known (or not needed).
    pub const fn new(base: Vec3<S>, dir: Vec3<S>) -> Self {
        Self {
            base,
            dir,
            len: S::ZERO,
        }
    }

    /// A ray whose direction has length `len` (`S::ONE` for unit directions).
    pub const fn with_length(base: Vec3<S>, dir: Vec3<S>, len: S) -> Self {
        Self { base, dir, len }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: S) -> Vec3<S> {
        self.base + self.dir * t
    }

    /// `|dir|`: the stored length, or computed when it was not stored.
    #[inline]
    pub fn length(&self) -> S {
        if self.len > S::ZERO {
            self.len
        } else {
            self.dir.length()
        }
    }
}
