//! Rays: a base point and a direction.

use crate::scalar::Scalar;
use crate::vec3::Vec3;

/// Hit points with `z` above this are in front of the image plane (in scene units, before
/// any scaling of the scene).
pub const Z_LIMIT: f64 = 0.01;

/// Rays stop once the distance travelled from the eye exceeds this (the course's bound).
pub const MAX_DISTANCE: f64 = 32.0;

/// Lengths the tracer compares with, in the number type at the scene's scale (converted
/// once, when the scale is set: a compiled scene carries them, so firmware converts none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits<S> {
    /// Hit points with `z` above this are in front of the image plane (0.01, scaled).
    pub z: S,
    /// Rays stop once the distance travelled from the eye exceeds this ([`MAX_DISTANCE`],
    /// scaled).
    pub distance: S,
}

impl<S: Scalar> Limits<S> {
    pub(crate) fn at_scale(scale: f64) -> Self {
        Self {
            z: S::from_f64(Z_LIMIT * scale),
            distance: S::from_f64(MAX_DISTANCE * scale),
        }
    }

    /// [`at_scale(1.0)`](Self::at_scale) without `f64` (a scene whose scale was never set):
    /// 1/100 and 32 are the nearest values in every type (tested).
    pub(crate) fn unscaled() -> Self {
        Self {
            z: S::ONE.mul_ratio(1, 100),
            distance: S::from_i32(32),
        }
    }
}

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

    /// The same ray with each component read by a load of its own, where that pays (see
    /// [`LOAD_APART`]).
    #[inline(always)]
    pub(crate) fn read_apart(&self) -> Self {
        // Checked here as well as in `Vec3::read_apart`: without the early return the
        // Cortex-M0 build rebuilds the ray (32 B more flash, measured).
        if !crate::vec3::LOAD_APART {
            return *self;
        }
        Self {
            base: self.base.read_apart(),
            dir: self.dir.read_apart(),
            len: self.len,
        }
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
