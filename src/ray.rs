//! Rays: a base point and a direction.

use crate::scalar::Scalar;
use crate::vec3::Vec3;

/// Whether the plane test reads a ray's components one by one ([`Ray::read_apart`]): on
/// out-of-order processors. The tracer tests most shadow rays right after making them, and
/// the compiler writes a ray's vectors in pieces of its own choosing (`x` alone and `(y, z)`
/// together, say) and reads them back in others (`(x, y)` and `(z, dir.x)`). A load that
/// straddles two stores still on their way to the cache waits for both (the
/// store-forwarding stall: a fifth to a third of the plane test's time on the host); a load
/// of one component is forwarded from any store that holds it. An in-order Cortex-M has no
/// such stall and would only run the extra instructions.
pub(crate) const LOAD_APART: bool = cfg!(any(target_arch = "x86_64", target_arch = "aarch64"));

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
        if !LOAD_APART {
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
