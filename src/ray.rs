//! Rays: a base point and a direction.

use crate::scalar::Scalar;
use crate::vec3::Vec3;

/// A ray `base + t * dir`, `t > 0`. Directions are unit length wherever the tracer makes them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray<S> {
    /// Where the ray starts.
    pub base: Vec3<S>,
    /// Where it goes.
    pub dir: Vec3<S>,
}

impl<S: Scalar> Ray<S> {
    /// A ray from its base and direction.
    pub const fn new(base: Vec3<S>, dir: Vec3<S>) -> Self {
        Self { base, dir }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: S) -> Vec3<S> {
        self.base + self.dir * t
    }
}
