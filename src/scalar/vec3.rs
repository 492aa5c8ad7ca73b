//! Three-component vectors: points, directions and colours.

use crate::scalar::Scalar;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// Whether the plane test reads a ray's components one by one ([`Ray::read_apart`](crate::ray::Ray::read_apart)): on
/// out-of-order processors. The tracer tests most shadow rays right after making them, and
/// the compiler writes a ray's vectors in pieces of its own choosing (`x` alone and `(y, z)`
/// together, say) and reads them back in others (`(x, y)` and `(z, dir.x)`). A load that
/// straddles two stores still on their way to the cache waits for both (the
/// store-forwarding stall: a fifth to a third of the plane test's time on the host); a load
/// of one component is forwarded from any store that holds it. An in-order Cortex-M has no
/// such stall and would only run the extra instructions.
pub(crate) const LOAD_APART: bool = cfg!(any(target_arch = "x86_64", target_arch = "aarch64"));

/// A vector of three [`Scalar`]s. Colours use it too (red, green, blue), as the course did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vec3<S> {
    /// First component (x, or red).
    pub x: S,
    /// Second component (y, or green).
    pub y: S,
    /// Third component (z, or blue).
    pub z: S,
}

impl<S> Vec3<S> {
    /// A vector from its components.
    pub const fn new(x: S, y: S, z: S) -> Self {
        Self { x, y, z }
    }
}

impl<S: Scalar> Vec3<S> {
    /// The same vector with each component read by a load of its own where that pays (see
    /// [`LOAD_APART`](LOAD_APART)): for a vector written a moment ago.
    #[inline(always)]
    pub(crate) fn read_apart(&self) -> Self {
        if !LOAD_APART {
            return *self;
        }
        // `black_box` keeps the compiler from merging the loads (the values are the same).
        use core::hint::black_box;
        Self::new(black_box(self.x), black_box(self.y), black_box(self.z))
    }

    /// The zero vector (black, as a colour).
    pub const ZERO: Self = Self::new(S::ZERO, S::ZERO, S::ZERO);

    /// Converts each component from `f64` (see [`Scalar::from_f64`]).
    pub fn from_f64(v: [f64; 3]) -> Self {
        Self::new(S::from_f64(v[0]), S::from_f64(v[1]), S::from_f64(v[2]))
    }

    /// The components as `f64`.
    pub fn to_f64(self) -> Vec3<f64> {
        Vec3::new(self.x.to_f64(), self.y.to_f64(), self.z.to_f64())
    }

    /// The components in the geometry's type ([`crate::scalar::geometry::Geo`]).
    #[cfg(feature = "geometry-f32")]
    #[inline]
    pub fn to_geo(self) -> Vec3<crate::scalar::geometry::Geo> {
        Vec3::new(self.x.to_geo(), self.y.to_geo(), self.z.to_geo())
    }

    /// The components in the geometry's type ([`crate::scalar::geometry::Geo`]): `f64`,
    /// [`to_f64`](Self::to_f64) itself (one copy in flash).
    #[cfg(not(feature = "geometry-f32"))]
    #[inline(always)]
    pub fn to_geo(self) -> Vec3<f64> {
        self.to_f64()
    }

    /// The dot product (see [`Scalar::dot`]).
    #[inline]
    pub fn dot(self, other: Self) -> S {
        S::dot(self, other)
    }

    /// The cross product.
    #[inline]
    pub fn cross(self, other: Self) -> Self {
        Self::new(
            self.y * other.z - self.z * other.y,
            self.z * other.x - self.x * other.z,
            self.x * other.y - self.y * other.x,
        )
    }

    /// Component-wise product (colour filtering).
    #[inline]
    pub fn mul_each(self, other: Self) -> Self {
        Self::new(self.x * other.x, self.y * other.y, self.z * other.z)
    }

    /// The length (see [`Scalar::length`]).
    #[inline]
    pub fn length(self) -> S {
        S::length(self)
    }

    /// The vector divided by its length, or `None` for the zero vector (where the course
    /// produced NaN).
    #[inline(always)]
    pub fn unit(self) -> Option<Self> {
        let length = self.length();
        if length > S::ZERO {
            Some(self / length)
        } else {
            None
        }
    }

    /// The largest component.
    #[inline]
    pub fn max_component(self) -> S {
        self.x.max(self.y).max(self.z)
    }

    /// Whether every component is zero.
    #[inline]
    pub fn is_zero(self) -> bool {
        self.x == S::ZERO && self.y == S::ZERO && self.z == S::ZERO
    }
}

impl Vec3<f64> {
    /// A vector from an array of components.
    pub const fn from_array(v: [f64; 3]) -> Self {
        Self::new(v[0], v[1], v[2])
    }

    /// The vector divided by its length, or `None` when the length is zero or not finite.
    ///
    /// Load-time invariants (unit normals, plane axes) are computed with this in `f64` and only
    /// then converted to the scene's number type, so every type starts from the same rounding.
    pub fn unit_f64(self) -> Option<Self> {
        let length = crate::scalar::sqrt_f64(self.dot(self));
        if length > 0.0 && length.is_finite() {
            Some(Self::new(self.x / length, self.y / length, self.z / length))
        } else {
            None
        }
    }

    /// Converts each component into another number type.
    pub fn cast<S: Scalar>(self) -> Vec3<S> {
        Vec3::new(
            S::from_f64(self.x),
            S::from_f64(self.y),
            S::from_f64(self.z),
        )
    }
}

impl<S: Scalar> Add for Vec3<S> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<S: Scalar> Sub for Vec3<S> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<S: Scalar> Neg for Vec3<S> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl<S: Scalar> Div<S> for Vec3<S> {
    type Output = Self;
    #[inline]
    fn div(self, k: S) -> Self {
        S::div_vec(self, k)
    }
}

impl<S: Scalar> Mul<S> for Vec3<S> {
    type Output = Self;
    #[inline]
    fn mul(self, k: S) -> Self {
        Self::new(self.x * k, self.y * k, self.z * k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products() {
        let a = Vec3::new(1.0, 2.0, 3.0);
        let b = Vec3::new(4.0, -5.0, 6.0);
        assert_eq!(a.dot(b), 12.0);
        assert_eq!(a.cross(b), Vec3::new(27.0, 6.0, -13.0));
        assert_eq!(a.mul_each(b), Vec3::new(4.0, -10.0, 18.0));
        assert_eq!(b.max_component(), 6.0);
    }

    #[test]
    fn unit_of_zero_is_none() {
        assert_eq!(Vec3::<f32>::ZERO.unit(), None);
        assert_eq!(Vec3::new(0.0, 0.0, 0.0).unit_f64(), None);
        assert_eq!(Vec3::new(f64::INFINITY, 0.0, 0.0).unit_f64(), None);
        assert_eq!(
            Vec3::new(0.0, 3.0, 4.0).unit_f64(),
            Some(Vec3::new(0.0, 0.6, 0.8))
        );
    }
}
