//! The float type the render plan's bounds and a moving picture's region are worked out in
//! ([`Geo`]): `f64` by default; `f32` with the `geometry-f32` feature, for targets whose
//! float unit is single precision only (the Cortex-M4F), where every `f64` operation is a
//! software routine of 70 to 120 instructions.
//!
//! Either type is safe because every bound carries margins far above its rounding: the
//! plan turns directions out by `2e-3` radians and a region by at least `2.5e-4`, both
//! thousands of `f32`'s steps (`1.2e-7`), and widens positions by a share of their distance
//! from the origin and the light, so an error in proportion to a coordinate stays inside
//! them. With `f32` the bounds' absolute margins (steps of the number type's resolution)
//! also take 64 or 256 of `f32`'s steps at the scene's reach (the eye and the screen: a
//! point near them is off by its rounding; a farther one by a share of its distance, which
//! the angles cover), and the few allowances written for `f64`'s own roundings (a
//! millionth, a billionth) take `f32`'s values from `allowance`: ten or more of its steps.
//! The region's and the plan's unit tests, `tests/plan.rs` and `tests/animate.rs` run with
//! either (CI runs both).

/// The geometry's float type (see the module's docs).
#[cfg(not(feature = "geometry-f32"))]
pub type Geo = f64;
/// The geometry's float type (see the module's docs).
#[cfg(feature = "geometry-f32")]
pub type Geo = f32;

/// Whether the geometry is worked out in `f32`.
pub const SINGLE: bool = cfg!(feature = "geometry-f32");

/// Whether the geometry's arithmetic is the target's float unit's (else software routines,
/// 70 to 120 instructions each: bounds worth working out once a render may not be worth it
/// once a row).
pub(crate) const IN_HARDWARE: bool = if SINGLE {
    super::HARD_FLOAT
} else {
    super::HARD_DOUBLE
};

/// `1 / sqrt 2`.
#[cfg(not(feature = "geometry-f32"))]
pub(crate) const FRAC_1_SQRT_2: Geo = core::f64::consts::FRAC_1_SQRT_2;
/// `1 / sqrt 2`.
#[cfg(feature = "geometry-f32")]
pub(crate) const FRAC_1_SQRT_2: Geo = core::f32::consts::FRAC_1_SQRT_2;

/// `f32`'s step just below 1 where the geometry is `f32`; zero where it is `f64` (whose
/// rounding the margins were first written for).
pub(crate) const STEP: Geo = allowance(0.0, f32::EPSILON);

/// An `f64` (a number type's constant) in the geometry's type.
#[inline]
pub(crate) const fn from_f64(value: f64) -> Geo {
    #[cfg(feature = "geometry-f32")]
    {
        value as f32
    }
    #[cfg(not(feature = "geometry-f32"))]
    {
        value
    }
}

/// An `f64` vector in the geometry's type.
#[inline]
pub(crate) fn narrow(v: crate::vec3::Vec3<f64>) -> crate::vec3::Vec3<Geo> {
    crate::vec3::Vec3::new(from_f64(v.x), from_f64(v.y), from_f64(v.z))
}

/// The geometry's value in `f64` (exact), for tests.
#[cfg(test)]
pub(crate) fn to_f64(value: Geo) -> f64 {
    #[cfg(feature = "geometry-f32")]
    {
        f64::from(value)
    }
    #[cfg(not(feature = "geometry-f32"))]
    {
        value
    }
}

/// The geometry's vector in `f64` (exact), for tests.
#[cfg(test)]
pub(crate) fn widen(v: crate::vec3::Vec3<Geo>) -> crate::vec3::Vec3<f64> {
    crate::vec3::Vec3::new(to_f64(v.x), to_f64(v.y), to_f64(v.z))
}

/// An allowance for rounding: `double` where the geometry is `f64`, `single` where it is
/// `f32` (whose steps are 2^29 times as coarse).
#[inline]
pub(crate) const fn allowance(double: f64, single: f32) -> Geo {
    #[cfg(feature = "geometry-f32")]
    {
        let _ = double;
        single
    }
    #[cfg(not(feature = "geometry-f32"))]
    {
        let _ = single;
        double
    }
}

pub(crate) use single_or_double::{abs, ceil, floor, sqrt, sqrt_rough};

#[cfg(not(feature = "geometry-f32"))]
mod single_or_double {
    /// `|x|`.
    #[inline]
    pub(crate) fn abs(x: f64) -> f64 {
        libm::fabs(x)
    }

    /// The square root (NaN below zero), correctly rounded.
    #[inline]
    pub(crate) fn sqrt(x: f64) -> f64 {
        libm::sqrt(x)
    }

    /// The square root to within `2^-23` of it, relative (see
    /// [`sqrt_f64_rough`](crate::scalar::sqrt_f64_rough)).
    #[inline]
    pub(crate) fn sqrt_rough(x: f64) -> f64 {
        crate::scalar::sqrt_f64_rough(x)
    }

    /// The largest whole number at most `x`.
    #[inline]
    pub(crate) fn floor(x: f64) -> f64 {
        libm::floor(x)
    }

    /// The smallest whole number at least `x`.
    #[inline]
    pub(crate) fn ceil(x: f64) -> f64 {
        libm::ceil(x)
    }
}

#[cfg(feature = "geometry-f32")]
mod single_or_double {
    /// `|x|`.
    #[inline]
    pub(crate) fn abs(x: f32) -> f32 {
        libm::fabsf(x)
    }

    /// The square root (NaN below zero), correctly rounded (the float unit's, where there
    /// is one).
    #[inline]
    pub(crate) fn sqrt(x: f32) -> f32 {
        if x >= 0.0 {
            crate::scalar::sqrtf(x)
        } else {
            f32::NAN
        }
    }

    /// The square root (the correctly rounded one: it costs no more in `f32`).
    #[inline]
    pub(crate) fn sqrt_rough(x: f32) -> f32 {
        sqrt(x)
    }

    /// The largest whole number at most `x`.
    #[inline]
    pub(crate) fn floor(x: f32) -> f32 {
        libm::floorf(x)
    }

    /// The smallest whole number at least `x`.
    #[inline]
    pub(crate) fn ceil(x: f32) -> f32 {
        libm::ceilf(x)
    }
}
