//! Intervals of `f64`: the render plan's sets of screen heights, and the coordinates where
//! a plane is clearly ahead of or behind the eye (`object::behind`). Worked out at set-up,
//! in `f64` whatever the number type.

/// The numbers `lo <= x <= hi` (either end may be infinite; empty when `lo > hi`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Interval {
    pub(crate) lo: f64,
    pub(crate) hi: f64,
}

impl Interval {
    pub(crate) const ALL: Self = Self {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// Keeps the numbers where `p + q x >= 0`.
    pub(crate) fn where_nonnegative(self, p: f64, q: f64) -> Self {
        if q > 0.0 {
            Self {
                lo: self.lo.max(-p / q),
                ..self
            }
        } else if q < 0.0 {
            Self {
                hi: self.hi.min(-p / q),
                ..self
            }
        } else if p >= 0.0 {
            self
        } else {
            Self {
                lo: f64::INFINITY,
                hi: f64::NEG_INFINITY,
            }
        }
    }

    /// The set in both.
    #[cfg(all(feature = "batch", feature = "plan"))]
    pub(crate) fn intersection(self, other: Self) -> Self {
        Self {
            lo: self.lo.max(other.lo),
            hi: self.hi.min(other.hi),
        }
    }

    /// The smallest set holding both.
    pub(crate) fn hull(self, other: Self) -> Self {
        Self {
            lo: self.lo.min(other.lo),
            hi: self.hi.max(other.hi),
        }
    }
}
