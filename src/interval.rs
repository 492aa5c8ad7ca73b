//! Intervals of `f64` or `f32`: the render plan's sets of screen heights (in the
//! geometry's type, [`crate::scalar::geometry::Geo`]), and the coordinates where a plane
//! is clearly ahead of or behind the eye (`object::behind`, in `f64`). Worked out at
//! set-up, whatever the number type.

use core::ops::{Div, Neg};

/// A float an [`Interval`] can hold.
pub(crate) trait Bound: Copy + PartialOrd + Neg<Output = Self> + Div<Output = Self> {
    const ZERO: Self;
    const INFINITY: Self;
    const NEG_INFINITY: Self;

    /// The larger (a NaN loses, as in `f64::max`).
    #[inline]
    #[allow(clippy::eq_op)] // `self != self`: NaN
    fn larger(self, other: Self) -> Self {
        if other > self || self != self {
            other
        } else {
            self
        }
    }

    /// The smaller (a NaN loses, as in `f64::min`).
    #[inline]
    #[allow(clippy::eq_op)] // `self != self`: NaN
    fn smaller(self, other: Self) -> Self {
        if other < self || self != self {
            other
        } else {
            self
        }
    }
}

/// `f64` takes its own `max` and `min` (the same results; on a Cortex-M0 built for size,
/// 188 bytes less flash than the comparisons above).
impl Bound for f64 {
    const ZERO: Self = 0.0;
    const INFINITY: Self = f64::INFINITY;
    const NEG_INFINITY: Self = f64::NEG_INFINITY;
    #[inline]
    fn larger(self, other: Self) -> Self {
        self.max(other)
    }
    #[inline]
    fn smaller(self, other: Self) -> Self {
        self.min(other)
    }
}

impl Bound for f32 {
    const ZERO: Self = 0.0;
    const INFINITY: Self = f32::INFINITY;
    const NEG_INFINITY: Self = f32::NEG_INFINITY;
}

/// The numbers `lo <= x <= hi` (either end may be infinite; empty when `lo > hi`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Interval<F = f64> {
    pub(crate) lo: F,
    pub(crate) hi: F,
}

impl<F: Bound> Interval<F> {
    pub(crate) const ALL: Self = Self {
        lo: F::NEG_INFINITY,
        hi: F::INFINITY,
    };

    /// Keeps the numbers where `p + q x >= 0`.
    pub(crate) fn where_nonnegative(self, p: F, q: F) -> Self {
        if q > F::ZERO {
            Self {
                lo: self.lo.larger(-p / q),
                ..self
            }
        } else if q < F::ZERO {
            Self {
                hi: self.hi.smaller(-p / q),
                ..self
            }
        } else if p >= F::ZERO {
            self
        } else {
            Self {
                lo: F::INFINITY,
                hi: F::NEG_INFINITY,
            }
        }
    }

    /// The set in both.
    #[cfg(all(feature = "batch", feature = "plan"))]
    pub(crate) fn intersection(self, other: Self) -> Self {
        Self {
            lo: self.lo.larger(other.lo),
            hi: self.hi.smaller(other.hi),
        }
    }

    /// The smallest set holding both.
    pub(crate) fn hull(self, other: Self) -> Self {
        Self {
            lo: self.lo.smaller(other.lo),
            hi: self.hi.larger(other.hi),
        }
    }
}
