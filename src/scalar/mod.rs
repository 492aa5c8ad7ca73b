//! The number type the tracer computes in.
//!
//! All geometry is generic over [`Scalar`] and monomorphised per type, so choosing a number
//! type costs nothing at run time. The trait asks only for what a fixed-point type can also
//! provide well: the four operations, negation, comparison, a square root, conversion from and
//! to `f64`, and a few constants.
//!
//! | type | range | error (per operation) |
//! |---|---|---|
//! | `f64` | ±1.8e308 | correctly rounded, 2^-53 relative |
//! | `f32` | ±3.4e38 | correctly rounded, 2^-24 relative |
//! | [`I16F16`] | ±32768 | 2^-16 absolute (truncating multiply and divide), see [`fixed`] |
//!
//! The vector operations ([`Scalar::dot`], [`Scalar::length`], [`Scalar::div_vec`]) are trait
//! methods so that a type can do them better than component by component: the fixed-point
//! type sums products in 64 bits before one shift (no intermediate overflow, one rounding).
//! The float types keep the plain left-to-right order the course's images need. So the
//! vectors live here too ([`vec3`], re-exported at the crate's root as `microray::vec3`):
//! the trait and the vector need each other.

mod ball;
// The Cortex-M0's box pre-test, for the objects' soundness tests on the host.
#[cfg(test)]
pub(crate) use ball::segment_clears_box;
pub mod fixed;
pub mod geometry;
pub mod vec3;
mod wide;

pub use fixed::I16F16;
pub use wide::RowRoots;

use crate::error::{Attr, ErrorKind};
use crate::vec3::Vec3;
use core::fmt;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// How a number type finds the camera's pixel positions `world * i / n` along a row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelSteps {
    /// Each as the course computes it: `world * i`, then the division by `n`.
    Course,
    /// `i` times the step `world / n`: one multiplication (within an ulp or two of the
    /// course's).
    Multiply,
    /// From one to the next by the step's integer and fractional parts, exactly as the
    /// course's formula gives them in a type with uniformly spaced values (fixed point,
    /// whose [`Scalar::to_raw`] is the value in steps of [`Scalar::MIN_NORMAL`], signed).
    Exact,
}

/// A real-number type the tracer can compute in.
///
/// Implementations must not panic for any input: division by zero, the square root of a
/// negative number and out-of-range conversions all give a defined value.
pub trait Scalar:
    Copy
    + Send
    + Sync
    + fmt::Debug
    + PartialEq
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + 'static
{
    /// The name used on the command line and in reports (`f64`, `f32`, ...).
    const NAME: &'static str;
    /// Zero.
    const ZERO: Self;
    /// One.
    const ONE: Self;
    /// Two.
    const TWO: Self;
    /// A limit above every ray parameter that counts: infinity for the float types, the
    /// largest value for fixed point (where a saturated value counts as no hit).
    const UNBOUNDED: Self;
    /// 2^-16, one step of I16F16: what a positive transparency or shininess the type would
    /// round to zero is kept at (zero shades otherwise: opaque, no glint).
    const STEP: Self;
    /// Scenes whose coordinates exceed this are scaled down at load (by a power of two, so
    /// that the image is unchanged in exact arithmetic).
    const MAX_EXTENT: f64;
    /// The largest a shading term (ambient, emissivity, diffuse times emissivity) or a squared
    /// radius may be after scaling, so that sums and squares stay within range.
    const MAX_TERM: f64;
    /// The smallest positive normal value (the type's resolution for fixed point); values
    /// below it are loaded as zero.
    const MIN_NORMAL: f64;
    /// The smallest length (radius, rectangle side, world window) the type resolves well;
    /// a scene with a smaller one, after scaling, is rejected for this type.
    const MIN_FEATURE: f64;
    /// The spacing of the type's values just below 1, where the components of unit vectors
    /// lie: the finest difference in direction the type can hold (`2^-52`, `2^-23`, `2^-16`).
    const UNIT_STEP: f64;
    /// Whether products of four coordinates stay within the type's range (the float types;
    /// not fixed point, whose range ends at 32768): the sphere test can then take the
    /// quadratic for a direction of any length instead of normalising it.
    const WIDE_RANGE: bool;
    /// Whether the type computes in the course's order of operations, so that its images
    /// are the course's bit for bit (`f64`). The other types take cheaper formulations of
    /// the same quantities where that order costs divisions and square roots (see
    /// [`crate::shade`]); the parity tests bound what that costs in accuracy.
    const COURSE_ORDER: bool;
    /// How the camera finds the pixel positions `world * i / n` along a row.
    const PIXEL_STEPS: PixelSteps;
    /// Whether reading a coordinate off a normal along an axis (a branch) is cheaper than
    /// the dot product (see [`crate::object::Plane::nearest_by_axis`]): not for `f32` on a
    /// hard-float Cortex-M, whose dot product is three multiply-adds (measured: 2-6 % more
    /// instructions on scenes of rectangles).
    const AXIS_READS: bool = true;

    /// Whether [`Sphere::nearest`](crate::object::sphere::Sphere::nearest)'s test of a ray
    /// that is not a unit ray certainly misses, `f` being the ray's base less the centre,
    /// `len` its stored length (zero: none): fixed point decides most misses from exact
    /// integer sums before it divides the direction by its length (`src/scalar/ball.rs`);
    /// the floats' tests are cheap enough as they are.
    #[inline(always)]
    fn misses_ball(f: Vec3<Self>, dir: Vec3<Self>, len: Self, r_squared: Self) -> bool {
        let _ = (f, dir, len, r_squared);
        false
    }
    /// Whether the segment from a ray's base to `base + dir` (`0 <= t <= 1`, a shadow ray's
    /// way to its light), `f` being the base less a box's centre, lies on some axis wholly
    /// beyond the box of half-sides `half`, by a margin (`src/scalar/ball.rs`'s
    /// `segment_clears_box`): six comparisons, where the Cortex-M0's exact pre-tests of a
    /// ball or a surface of revolution take library-sized products; elsewhere those, or
    /// the floats' tests, are cheap enough as they are.
    #[inline(always)]
    fn segment_clears_box(f: Vec3<Self>, dir: Vec3<Self>, half: Vec3<Self>) -> bool {
        let _ = (f, dir, half);
        false
    }
    /// Whether a ray from its base along `dir` (`t >= 0`), `f` being the base less a
    /// bounding sphere's centre, certainly stays outside the sphere, by a margin
    /// (`src/scalar/ball.rs`'s `ray_clears_wide_of`): fixed point rules out most rays
    /// that pass a surface of revolution from exact integer sums, before its search
    /// divides the direction by its length; the floats' cylinder test is cheap enough.
    #[inline(always)]
    fn ray_clears_ball(f: Vec3<Self>, dir: Vec3<Self>, radius: Self) -> bool {
        let _ = (f, dir, radius);
        false
    }
    /// Whether a ray's line, `f` being its base less a point of an upright axis, passes
    /// the axis farther than `radius`, by a margin (`src/scalar/ball.rs`'s
    /// `line_clears_disc`, on `x` and `z`): fixed point's cheapest pre-test of a surface of
    /// revolution standing upright.
    #[inline(always)]
    fn line_clears_upright(f: Vec3<Self>, dir: Vec3<Self>, radius: Self) -> bool {
        let _ = (f, dir, radius);
        false
    }
    /// What the lengths of a row's primary ray directions `(x, dy, dz)` share along the
    /// row, for [`row_length`](Self::row_length): fixed point's exact `dy^2 + dz^2`; the
    /// floats, whose sum is rounded in order, share nothing.
    #[inline(always)]
    fn row_squares(dy: Self, dz: Self) -> u64 {
        let _ = (dy, dz);
        0
    }
    /// The length of `(x, dy, dz)`, bit for bit [`length`](Self::length)'s, given
    /// `row_squares(dy, dz)` and the roots of the row's rays so far (fixed point finds its
    /// exact root from them; the floats need nothing of them).
    #[inline(always)]
    fn row_length(x: Self, dy: Self, dz: Self, squares: u64, roots: &mut RowRoots) -> Self {
        let _ = (squares, roots);
        Self::length(Vec3::new(x, dy, dz))
    }

    /// A wider positive number for the shading's quotients (distances squared times
    /// distances): the type itself for `f32` and `f64`, a 32-bit mantissa with an exponent
    /// for fixed point, whose range ends at 32768.
    type Wide: Copy + fmt::Debug + PartialEq;
    /// `a . b` as a wide number, when it is above zero.
    fn positive_dot(a: Vec3<Self>, b: Vec3<Self>) -> Option<Self::Wide>;
    /// [`positive_dot(v, v)`](Self::positive_dot), bit for bit, given
    /// [`row_squares(v.y, v.z)`](Self::row_squares) (the vectors to a light from a row's
    /// hits, which differ only in `x`).
    #[inline(always)]
    fn positive_row_square(v: Vec3<Self>, squares: u64) -> Option<Self::Wide> {
        let _ = squares;
        Self::positive_dot(v, v)
    }
    /// The value as a wide number, when it is above zero.
    fn to_wide(self) -> Option<Self::Wide>;
    /// `self` to the power `exponent` as a wide number (for glints: see
    /// [`pow_positive`](Self::pow_positive)); `None` when it is zero.
    #[inline]
    fn pow_wide(self, exponent: Self) -> Option<Self::Wide> {
        self.pow_positive(exponent).to_wide()
    }
    /// The product of two wide numbers.
    fn wide_mul(a: Self::Wide, b: Self::Wide) -> Self::Wide;
    /// The reciprocal of a wide number.
    fn wide_recip(a: Self::Wide) -> Self::Wide;
    /// `self` times a wide number (saturated where the type's range ends).
    fn scale(self, factor: Self::Wide) -> Self;
    /// Each component of `v` times a wide number (a colour times a shading quotient).
    #[inline]
    fn scale3(v: Vec3<Self>, factor: Self::Wide) -> Vec3<Self> {
        Vec3::new(v.x.scale(factor), v.y.scale(factor), v.z.scale(factor))
    }

    /// The type's code in a compiled scene ([`crate::compiled`]): 1 `f64`, 2 `f32`, 3 `I16F16`.
    const CODE: u8;
    /// How many bytes a value takes in a compiled scene.
    const RAW_BYTES: usize;
    /// The value's bits (`to_bits` of the float types, the fixed-point word), as a
    /// compiled scene stores them.
    fn to_raw(self) -> u64;
    /// The value with these bits (the low [`RAW_BYTES`](Self::RAW_BYTES) bytes count).
    fn from_raw(raw: u64) -> Self;

    /// The nearest value of this type (saturating where the type's range ends).
    fn from_f64(value: f64) -> Self;
    /// The value as an `f64` (exact for every type microray has).
    fn to_f64(self) -> f64;
    /// The value in the type the render plan's and a region's geometry is worked out in
    /// (`f64`, or `f32` with the `geometry-f32` feature: one rounding).
    #[inline]
    fn to_geo(self) -> geometry::Geo {
        self.to_f64() as geometry::Geo
    }
    /// The square root; the root of a negative number is defined as zero.
    fn sqrt(self) -> Self;
    /// `self` to the power `exponent`, for glints; defined as 0 when `self <= 0` (where the
    /// course took `pow` of a negative dot product).
    fn pow_positive(self, exponent: Self) -> Self;
    /// A value below which [`pow_wide`](Self::pow_wide) of any `self` with this exponent
    /// is certainly `None` (a glint of exactly nothing), so that a glint need not compute
    /// the power there; zero where the type does not say.
    #[inline]
    fn glint_floor(exponent: Self) -> Self {
        let _ = exponent;
        Self::ZERO
    }
    /// The channel byte of a colour value: `self * 255` computed exactly (in `f64` for the
    /// float types), clamped to 0..=255 and truncated, as the course's images need.
    #[inline]
    fn to_byte(self) -> u8 {
        let v = self.to_f64() * 255.0;
        if v >= 255.0 {
            255
        } else if v > 0.0 {
            v as u8
        } else {
            0
        }
    }
    /// The largest integer not above the value, saturated to the `i32` range.
    fn floor_to_i32(self) -> i32;
    /// Whether [`floor_to_i32`](Self::floor_to_i32) is odd (a tile's parity).
    #[inline]
    fn floor_is_odd(self) -> bool {
        self.floor_to_i32() & 1 == 1
    }
    /// A whole number.
    fn from_i32(value: i32) -> Self;
    /// `self * numerator / denominator`, for pixel coordinates: in this order for the float
    /// types (the course's), exactly in 64 bits for fixed point (where `self * numerator`
    /// could overflow).
    #[inline]
    fn mul_ratio(self, numerator: u16, denominator: u16) -> Self {
        self * Self::from_i32(i32::from(numerator)) / Self::from_i32(i32::from(denominator))
    }
    /// The nearest value of this type, or `None` when `value` is outside the type's range.
    #[inline]
    fn from_f64_checked(value: f64) -> Option<Self> {
        let converted = Self::from_f64(value);
        converted.to_f64().is_finite().then_some(converted)
    }
    /// Writes the shortest decimal text that reads back as exactly this value.
    #[cfg(feature = "print")]
    fn write_shortest(self, out: &mut dyn fmt::Write) -> fmt::Result;

    /// The dot product of two vectors.
    #[inline]
    fn dot(a: Vec3<Self>, b: Vec3<Self>) -> Self {
        a.x * b.x + a.y * b.y + a.z * b.z
    }
    /// `v . n` for a unit normal `n`: [`dot`](Self::dot), or what it gives read off one
    /// coordinate where a type gains by it (fixed point, for normals along an axis).
    #[inline]
    fn dot_unit(v: Vec3<Self>, n: Vec3<Self>) -> Self {
        Self::dot(v, n)
    }
    /// [`positive_dot`](Self::positive_dot) of `v` and a unit normal `n`, as
    /// [`dot_unit`](Self::dot_unit) is to [`dot`](Self::dot).
    #[inline]
    fn positive_dot_unit(v: Vec3<Self>, n: Vec3<Self>) -> Option<Self::Wide> {
        Self::positive_dot(v, n)
    }
    /// The mirror direction of `dir` about a unit normal `n`: `dir - 2 (dir . n) n`.
    #[inline]
    fn reflect(dir: Vec3<Self>, n: Vec3<Self>) -> Vec3<Self> {
        dir - n * (Self::TWO * Self::dot_unit(dir, n))
    }
    /// The length of a vector.
    #[inline]
    fn length(v: Vec3<Self>) -> Self {
        Self::dot(v, v).sqrt()
    }
    /// Each component divided by `d`.
    #[inline]
    fn div_vec(v: Vec3<Self>, d: Self) -> Vec3<Self> {
        Vec3::new(v.x / d, v.y / d, v.z / d)
    }
    /// `1 / self`.
    #[inline]
    fn recip(self) -> Self {
        Self::ONE / self
    }
    /// `num / den` when it lies in `(0, limit)`, a ray parameter that counts; `None` when
    /// it does not. Types tell without dividing where they can: a plane behind the ray or
    /// beyond the nearest hit so far costs no division. `f64` and fixed point decide
    /// exactly as the division does; `f32` compares `num` with `den limit`, which can differ
    /// from the rounded quotient by an ulp at a tie.
    #[inline]
    fn parameter_within(num: Self, den: Self, limit: Self) -> Option<Self> {
        let q = num / den;
        (q > Self::ZERO && q < limit).then_some(q)
    }

    /// The next value above a positive one (the type's next step); other values stay.
    fn next_up(self) -> Self;

    /// A coarse key of the value that never falls as the value grows (any key for NaN):
    /// two bytes that bound a span of values conservatively (a value whose key lies below
    /// a bound's key lies below the bound). The top 16 bits of the value's order.
    fn order_key(self) -> i16;

    /// Whether `unit(v) . axis > cos` (a spotlight's cone, `axis` a unit vector): as the
    /// course writes it, `v` divided by its length first. Fixed point compares
    /// `v . axis > cos |v|` instead, which rounds less.
    #[inline]
    fn within_cone(v: Vec3<Self>, axis: Vec3<Self>, cos: Self) -> bool {
        (v / v.length()).dot(axis) > cos
    }

    /// Whether the value stands for something beyond the type's range: infinite or NaN for
    /// the float types, saturated for fixed point. A ray parameter like that is no hit.
    #[inline]
    fn is_beyond_range(self) -> bool {
        !self.to_f64().is_finite()
    }

    /// The absolute value.
    #[inline]
    fn abs(self) -> Self {
        if self < Self::ZERO { -self } else { self }
    }
    /// The smaller of two values (`self` when they compare equal or unordered).
    #[inline]
    fn min(self, other: Self) -> Self {
        if other < self { other } else { self }
    }
    /// The larger of two values (`self` when they compare equal or unordered).
    #[inline]
    fn max(self, other: Self) -> Self {
        if other > self { other } else { self }
    }

    /// The constants of [`sin`](Self::sin) in the type: `1/2`, `1 / 2 pi`, `2 pi`, `pi`,
    /// `pi / 2`, and the Taylor series' nested factors `1/6, 1/20, 1/42, 1/72, 1/110`
    /// (`1 / ((2k)(2k + 1))`, each small enough for Q16.16 to hold to 0.1 %).
    const SINE: [Self; 10];

    /// The sine of `self` radians: the argument reduced to `[-pi/2, pi/2]` by whole and
    /// half turns, then the Taylor series to `x^11` in nested form, `x (1 - x^2/6 (1 -
    /// x^2/20 (...)))`, which needs no coefficient below Q16.16's step. Within 5e-8 on the
    /// reduced range in exact arithmetic; measured in `f32` and `I16F16` by the tests.
    /// `f64` calls `libm::sin`, as the course's C does.
    fn sin(self) -> Self {
        sine(self, |a, b| a * b)
    }
}

/// [`Scalar::sin`]'s steps, the reduced argument's products by `small_product` where that
/// argument is below 4 in size (then every factor of the series is below 128; else by
/// `*`): fixed point's Cortex-M0 takes them in 32-bit arithmetic, the same values.
#[inline]
pub(crate) fn sine<S: Scalar>(value: S, small_product: impl Fn(S, S) -> S) -> S {
    let [half, per_turn, turn, pi, half_pi, ..] = S::SINE;
    let turns = (value * per_turn + half).floor_to_i32();
    let mut x = value - S::from_i32(turns) * turn;
    if x > half_pi {
        x = pi - x;
    } else if x < -half_pi {
        x = -pi - x;
    }
    let four = S::TWO + S::TWO;
    let small = x < four && x > -four;
    let product = |a: S, b: S| if small { small_product(a, b) } else { a * b };
    let x2 = product(x, x);
    let mut series = S::ONE;
    for &factor in S::SINE[5..].iter().rev() {
        series = S::ONE - product(product(x2, factor), series);
    }
    product(x, series)
}

/// The square root of an `f64`, correctly rounded (as `libm::sqrt`, bit for bit): libm's
/// where the target has an `f64` square root instruction, else [`sqrt_by_digits`], which
/// takes a third of the flash of libm's table-driven version on a Cortex-M0 (where the loader
/// is its only user).
#[inline]
pub(crate) fn sqrt_f64(x: f64) -> f64 {
    if cfg!(any(target_arch = "x86_64", target_arch = "aarch64")) {
        libm::sqrt(x)
    } else {
        sqrt_by_digits(x)
    }
}

/// The square root of an `f64` to within `2^-23` of it (relative), for the render plan,
/// whose angles carry margins of `2e-3`: exact where the target has an `f64` square root
/// instruction, else [`sqrt_by_halves`]. Once per object and frame, the correctly rounded
/// [`sqrt_by_digits`] cost many_spheres 1 % of its instructions on the Cortex-M4F. Built
/// for size, `sqrt_by_digits` still (on the Cortex-M0 `sqrt_by_halves` brings in `f32`'s
/// software root and conversions: 2 KB).
#[cfg_attr(feature = "geometry-f32", allow(dead_code))]
#[inline]
pub(crate) fn sqrt_f64_rough(x: f64) -> f64 {
    if HARD_DOUBLE {
        libm::sqrt(x)
    } else if cfg!(microray_small) {
        sqrt_by_digits(x)
    } else {
        sqrt_by_halves(x)
    }
}

/// `sqrt(x)` as `sqrt(m) 2^k` with `x = m 2^(2k)`, `1 <= m < 4`, and `sqrt(m)` taken in
/// `f32` (the float unit's, where there is one): two roundings of `2^-24`, so within
/// `2^-23` of the root; exact for zeros, infinities, NaN and negatives (as
/// [`sqrt_by_digits`], which also takes the rare subnormals).
#[cfg_attr(feature = "geometry-f32", allow(dead_code))]
#[inline(never)]
pub(crate) fn sqrt_by_halves(x: f64) -> f64 {
    let bits = x.to_bits();
    let field = (bits >> 52) as i32;
    // Positive normal numbers only (the sign bit makes `field` 2048 or more).
    if !(1..2047).contains(&field) {
        return sqrt_by_digits(x);
    }
    let exponent = field - 1023;
    let half = exponent >> 1;
    // `m`: the mantissa with exponent 0 or 1 (what is left after `2^(2 half)`).
    let m = f64::from_bits(
        (bits & 0x000f_ffff_ffff_ffff) | (((1023 + exponent - 2 * half) as u64) << 52),
    );
    // `half` is within -512..=511, a normal power of two.
    let scale = f64::from_bits(((1023 + half) as u64) << 52);
    f64::from(sqrtf(m as f32)) * scale
}

/// The correctly rounded square root, two bits of the radicand at a time in integers: the
/// mantissa `m` (made even-exponent, `2^52 <= m < 2^54`) times `2^52` has a 53-bit root `r`
/// and remainder `rem`; the root is rounded up when `rem > r` (the exact root is then at
/// least `r + 1/2`; it is never exactly that). Out of line: it is for loading, and each
/// inlined copy would cost flash.
#[inline(never)]
pub(crate) fn sqrt_by_digits(x: f64) -> f64 {
    if x.is_nan() || x < 0.0 {
        return f64::NAN;
    }
    if x == 0.0 || x == f64::INFINITY {
        return x;
    }
    let bits = x.to_bits();
    let field = (bits >> 52) as i32;
    let (mut m, mut e) = if field == 0 {
        (bits, -1074)
    } else {
        (bits & ((1 << 52) - 1) | 1 << 52, field - 1075)
    };
    while m < 1 << 52 {
        m <<= 1;
        e -= 1;
    }
    if e % 2 != 0 {
        m <<= 1;
        e -= 1;
    }
    // The radicand m * 2^52 has 106 bits: 53 pairs, the low 26 all zero.
    let (mut root, mut rem) = (0u64, 0u64);
    for pair in (0..53).rev() {
        let shift = 2 * pair - 52;
        let digits = if shift >= 0 { (m >> shift) & 3 } else { 0 };
        rem = (rem << 2) | digits;
        let trial = (root << 2) | 1;
        root <<= 1;
        if rem >= trial {
            rem -= trial;
            root |= 1;
        }
    }
    if rem > root {
        root += 1;
    }
    // root in [2^52, 2^53]: its leading bit adds one to the exponent field (and a carry to
    // 2^53 one more, as it should).
    let half = (e - 52) / 2;
    let field = (half + 52 + 1023 - 1) as u64;
    f64::from_bits((field << 52) + root)
}

/// [`Scalar::SINE`] in `f64`.
const SINE_F64: [f64; 10] = [
    0.5,
    1.0 / core::f64::consts::TAU,
    core::f64::consts::TAU,
    core::f64::consts::PI,
    core::f64::consts::FRAC_PI_2,
    1.0 / 6.0,
    1.0 / 20.0,
    1.0 / 42.0,
    1.0 / 72.0,
    1.0 / 110.0,
];

/// Constants in `f32`, each rounded once.
const fn narrowed(values: [f64; 10]) -> [f32; 10] {
    let [a, b, c, d, e, f, g, h, i, j] = values;
    [
        a as f32, b as f32, c as f32, d as f32, e as f32, f as f32, g as f32, h as f32, i as f32,
        j as f32,
    ]
}

/// `x^y` in `f64`: with `std`, the C library's `pow` (what the course's tracer calls; glibc's
/// is within 0.52 ulp and a third of the time of libm's port of FreeBSD's, which is most of
/// a glint's cost); without, libm's. The two differ by at most one ulp on one argument in
/// ten (`pow_of_std_and_libm_agree_within_one_ulp`) and on no pixel of the course's images.
#[inline]
fn pow_f64(x: f64, y: f64) -> f64 {
    #[cfg(feature = "std")]
    return x.powf(y);
    #[cfg(not(feature = "std"))]
    libm::pow(x, y)
}

impl Scalar for f64 {
    const NAME: &'static str = "f64";
    const CODE: u8 = 1;
    const RAW_BYTES: usize = 8;
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const TWO: Self = 2.0;
    const UNBOUNDED: Self = f64::INFINITY;
    const STEP: Self = 1.0 / 65536.0;
    // Squares of coordinates stay finite below 2^500.
    const MAX_EXTENT: f64 = 3.273390607896142e150;
    const MAX_TERM: f64 = 1e300;
    const MIN_NORMAL: f64 = f64::MIN_POSITIVE;
    // Squares of smaller lengths would leave the normal range.
    const MIN_FEATURE: f64 = 1e-150;
    const UNIT_STEP: f64 = f64::EPSILON;
    const SINE: [Self; 10] = SINE_F64;
    fn sin(self) -> Self {
        libm::sin(self)
    }
    const WIDE_RANGE: bool = true;
    const COURSE_ORDER: bool = true;
    const PIXEL_STEPS: PixelSteps = PixelSteps::Course;
    type Wide = f64;
    #[inline]
    fn positive_dot(a: Vec3<Self>, b: Vec3<Self>) -> Option<Self> {
        let d = Self::dot(a, b);
        (d > 0.0).then_some(d)
    }
    #[inline]
    fn to_wide(self) -> Option<Self> {
        (self > 0.0).then_some(self)
    }
    #[inline]
    fn next_up(self) -> Self {
        if self.is_finite() && self > 0.0 {
            Self::from_bits(self.to_bits() + 1)
        } else {
            self
        }
    }
    /// The order of the bits (negative values' magnitude bits turned), its top 16.
    #[inline]
    fn order_key(self) -> i16 {
        let bits = self.to_bits() as i64;
        let ordered = bits ^ (((bits >> 63) as u64) >> 1) as i64;
        (ordered >> 48) as i16
    }
    #[inline]
    fn wide_mul(a: Self, b: Self) -> Self {
        a * b
    }
    #[inline]
    fn wide_recip(a: Self) -> Self {
        1.0 / a
    }
    #[inline]
    fn scale(self, factor: Self) -> Self {
        self * factor
    }

    #[inline]
    fn to_raw(self) -> u64 {
        self.to_bits()
    }
    #[inline]
    fn from_raw(raw: u64) -> Self {
        f64::from_bits(raw)
    }
    #[inline]
    fn from_f64(value: f64) -> Self {
        value
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline]
    fn sqrt(self) -> Self {
        if self > 0.0 { sqrt_f64(self) } else { 0.0 }
    }
    #[inline]
    fn pow_positive(self, exponent: Self) -> Self {
        if self > 0.0 {
            pow_f64(self, exponent)
        } else {
            0.0
        }
    }
    /// Rust's saturating conversion is the rule itself (255 at or above 255, the
    /// truncation between, 0 at or below 0 and for NaN), without the branches.
    #[inline]
    fn to_byte(self) -> u8 {
        (self * 255.0) as u8
    }
    #[inline]
    fn floor_to_i32(self) -> i32 {
        floor_by_truncation!(self, f64, libm::floor)
    }
    /// Below 2^31 in magnitude, with float additions only: adding 1.5 * 2^52 rounds `v`
    /// to the nearest integer `r` (exactly, in the last bit of the sum, its parity), and
    /// `floor(v)` is `r`, or `r - 1` when `r > v`. Elsewhere (and for NaN), the integer
    /// conversion's saturated floor.
    #[inline]
    fn floor_is_odd(self) -> bool {
        const ROUNDING: f64 = 6_755_399_441_055_744.0;
        if self.abs() < 2_147_483_648.0 {
            let sum = self + ROUNDING;
            let nearest = sum - ROUNDING;
            (sum.to_bits() & 1 == 1) ^ (nearest > self)
        } else {
            self.floor_to_i32() & 1 == 1
        }
    }
    #[inline]
    fn from_i32(value: i32) -> Self {
        f64::from(value)
    }
    #[cfg(feature = "print")]
    fn write_shortest(self, out: &mut dyn fmt::Write) -> fmt::Result {
        write_shortest_float(self, out)
    }
    /// A bit test on the type itself: no conversion to `f64` (software on a Cortex-M4F).
    #[inline]
    fn is_beyond_range(self) -> bool {
        !self.is_finite()
    }
    /// Exact: with a double-precision unit the division costs less than the tests that
    /// would avoid it, and the quotient alone decides (a zero, signs that differ, a zero
    /// `den` or a NaN give no `q` in `(0, limit)`). In software the quotient is not
    /// computed when the signs differ (it is negative) or when `|num| > |den| limit` by
    /// more than 16 units in the last place (it rounds to `limit` or more: the quotient's
    /// and the product's roundings are one unit each).
    #[inline]
    fn parameter_within(num: Self, den: Self, limit: Self) -> Option<Self> {
        if HARD_DOUBLE {
            // Signs that differ make the quotient's sign bit set (or it NaN): no `q > 0`,
            // and no division for the divider (a shadow ray away from a plane).
            if (num.to_bits() ^ den.to_bits()) >> 63 != 0 {
                return None;
            }
            let q = num / den;
            return (q > 0.0 && q < limit).then_some(q);
        }
        if num == 0.0 || den == 0.0 || (num > 0.0) != (den > 0.0) {
            return None;
        }
        if limit > 0.0 && limit.is_finite() {
            let bound = den.abs() * limit;
            // 16 units up: the bit pattern of a positive float is monotone in its value.
            let slack = f64::from_bits(bound.to_bits() + 16);
            if bound >= f64::MIN_POSITIVE && num.abs() > slack {
                return None;
            }
        }
        let q = num / den;
        (q > 0.0 && q < limit).then_some(q)
    }
}

/// `floor(v)` as an `i32`, saturated, NaN 0. With a float unit: the conversion truncates
/// towards zero, so one less when that lands above `v` (a negative fraction). Exact: the
/// truncated value converts back exactly where `v` has a fraction (below `2^24` in `f32`),
/// and where it has none it is `v` itself or saturated.
/// Without one, libm's `floor` on the bits (a soft-float conversion and comparison cost
/// more).
macro_rules! floor_by_truncation {
    ($v:expr, $float:ty, $floor:path) => {{
        let v: $float = $v;
        if HARD_FLOAT {
            // `as` saturates and maps NaN to 0: never undefined, never a panic.
            let truncated = v as i32;
            if (truncated as $float) > v {
                truncated.saturating_sub(1)
            } else {
                truncated
            }
        } else {
            $floor(v) as i32
        }
    }};
}
use floor_by_truncation;

/// Whether the target has a floating-point unit: a float-to-integer conversion is then
/// one instruction (`VCVT` on a Cortex-M4F), else a call into the soft-float routines.
pub(crate) const HARD_FLOAT: bool = cfg!(any(
    target_arch = "x86_64",
    target_arch = "aarch64",
    all(target_arch = "arm", target_abi = "eabihf")
));

/// Whether the target has a double-precision floating-point unit.
pub(crate) const HARD_DOUBLE: bool = cfg!(any(target_arch = "x86_64", target_arch = "aarch64"));

/// `floor(v * 255)` clamped to 0..=255 (NaN 0), exactly as the `f64` product gives it, with
/// the float unit and no branch: `x = v 2^32` is exact (a power of two) and a whole number
/// for `v` in `[2^-9, 1)`; the conversion saturates (negative and NaN to 0, 1 and more to
/// `2^32 - 1`). With `x = 256a + b`, `(x - a) / 2^24` exceeds `255 x / 2^32` by `b / 2^32`,
/// less than 2^-24, which moves the floor only where `255 v` lies that close below a whole
/// number: no `f32` does (checked over all 2^32 of them; the tests check ±40 units around
/// every `k / 255`, which holds every such place), and `2^32 - 1` gives 255.
#[inline]
pub(crate) fn f32_byte_by_scaling(v: f32) -> u8 {
    let x = (v * 4_294_967_296.0) as u32;
    ((x - (x >> 8)) >> 24) as u8
}

/// [`f32_byte_by_scaling`] on the bits, for targets without a float unit: `v * 255` for `v`
/// in (0, 1) is `mantissa * 255 * 2^exponent`, and `mantissa * 255` fits 32 bits;
/// truncating it is what the `f64` product gives. Negative values, zeros and NaN are 0.
#[inline]
pub(crate) fn f32_byte_by_bits(v: f32) -> u8 {
    let bits = v.to_bits() as i32;
    if bits <= 0 {
        return 0;
    }
    if bits >= 0x3f80_0000 {
        // 1 or more, or a NaN (above infinity's bits).
        return if bits <= 0x7f80_0000 { 255 } else { 0 };
    }
    // v = mantissa 2^(exponent - 150): the shift is 24 or more; below 2^-8, v * 255 < 1.
    let shift = 150 - (bits >> 23) as u32;
    if shift >= 32 {
        return 0;
    }
    let mantissa = (bits as u32 & 0x7f_ffff) | 0x80_0000;
    ((mantissa * 255) >> shift) as u8
}

impl Scalar for f32 {
    const NAME: &'static str = "f32";
    const CODE: u8 = 2;
    const RAW_BYTES: usize = 4;
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const TWO: Self = 2.0;
    const UNBOUNDED: Self = f32::INFINITY;
    const STEP: Self = 1.0 / 65536.0;
    // Products of four coordinates (a direction's square times a radius's, in the sphere
    // test) stay finite below 2^30.
    const MAX_EXTENT: f64 = 1_073_741_824.0;
    const MAX_TERM: f64 = 1e36;
    const MIN_NORMAL: f64 = f32::MIN_POSITIVE as f64;
    // Squares of smaller lengths would leave the normal range.
    const MIN_FEATURE: f64 = 1e-18;
    const UNIT_STEP: f64 = f32::EPSILON as f64;
    const SINE: [Self; 10] = narrowed(SINE_F64);
    const WIDE_RANGE: bool = true;
    const COURSE_ORDER: bool = false;
    const PIXEL_STEPS: PixelSteps = PixelSteps::Multiply;
    const AXIS_READS: bool = !cfg!(all(target_arch = "arm", target_abi = "eabihf"));
    type Wide = f32;
    /// The float unit's absolute value (`VABS`): one instruction, where the comparison was a
    /// branch. `-0.0` becomes `0.0`.
    #[inline]
    fn abs(self) -> Self {
        libm::fabsf(self)
    }
    #[inline]
    fn positive_dot(a: Vec3<Self>, b: Vec3<Self>) -> Option<Self> {
        let d = Self::dot(a, b);
        (d > 0.0).then_some(d)
    }
    #[inline]
    fn to_wide(self) -> Option<Self> {
        (self > 0.0).then_some(self)
    }
    #[inline]
    fn next_up(self) -> Self {
        if self.is_finite() && self > 0.0 {
            Self::from_bits(self.to_bits() + 1)
        } else {
            self
        }
    }
    /// The order of the bits (negative values' magnitude bits turned), its top 16.
    #[inline]
    fn order_key(self) -> i16 {
        let bits = self.to_bits() as i32;
        let ordered = bits ^ (((bits >> 31) as u32) >> 1) as i32;
        (ordered >> 16) as i16
    }
    #[inline]
    fn wide_mul(a: Self, b: Self) -> Self {
        a * b
    }
    #[inline]
    fn wide_recip(a: Self) -> Self {
        1.0 / a
    }
    #[inline]
    fn scale(self, factor: Self) -> Self {
        self * factor
    }

    #[inline]
    fn to_raw(self) -> u64 {
        u64::from(self.to_bits())
    }
    #[inline]
    fn from_raw(raw: u64) -> Self {
        f32::from_bits(raw as u32)
    }
    #[inline]
    fn from_f64(value: f64) -> Self {
        value as f32
    }
    #[inline]
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    /// No conversion through `f64` (software on a Cortex-M4F) where the geometry is `f32`.
    #[inline]
    fn to_geo(self) -> geometry::Geo {
        geometry::Geo::from(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        if self > 0.0 { sqrtf(self) } else { 0.0 }
    }
    #[inline]
    fn pow_positive(self, exponent: Self) -> Self {
        if self > 0.0 {
            libm::powf(self, exponent)
        } else {
            0.0
        }
    }
    /// `libm::powf` returns exactly zero (`1e-30 * 1e-30`) where its `exponent * log2(x)`
    /// falls below -150, computed within far less than 1 of the true product. Below
    /// `2^(-160 / exponent)` the true product is below -160: the power is zero, and so is
    /// the glint. Taken a thousandth lower for `exp2f`'s rounding (tested against `powf`).
    #[inline]
    fn glint_floor(exponent: Self) -> Self {
        if exponent > 0.0 {
            libm::exp2f(-160.0 / exponent) * 0.999
        } else {
            0.0
        }
    }
    #[inline]
    fn floor_to_i32(self) -> i32 {
        floor_by_truncation!(self, f32, libm::floorf)
    }
    #[inline]
    fn from_i32(value: i32) -> Self {
        value as f32
    }
    /// Exact without `f64`: with the float unit where there is one (`v 2^32` converted,
    /// times 255, over `2^32`), else on the bits (the mantissa times 255, shifted).
    #[inline]
    fn to_byte(self) -> u8 {
        if HARD_FLOAT {
            f32_byte_by_scaling(self)
        } else {
            f32_byte_by_bits(self)
        }
    }
    #[cfg(feature = "print")]
    fn write_shortest(self, out: &mut dyn fmt::Write) -> fmt::Result {
        write_shortest_float(self, out)
    }
    /// A bit test on the type itself: no conversion to `f64` (software on a Cortex-M4F).
    #[inline]
    fn is_beyond_range(self) -> bool {
        !self.is_finite()
    }
    /// Exact, mostly without the division: the signs first, then `num` against
    /// `den limit (1 + 2^-20)`, which the rounded quotient cannot reach when it is below
    /// `limit` (the two products round by half a unit each, the quotient by another); only
    /// a product in the subnormal range decides nothing.
    #[inline]
    fn parameter_within(num: Self, den: Self, limit: Self) -> Option<Self> {
        const SLACK: f32 = 1.0 + 1.0 / (1u32 << 20) as f32;
        // Behind the ray (or parallel to it): no quotient to compare.
        let ahead = if den > 0.0 {
            num > 0.0
        } else {
            den < 0.0 && num < 0.0
        };
        if !ahead {
            return None;
        }
        let bound = den * (limit * SLACK);
        let beyond = if den > 0.0 {
            num >= bound
        } else {
            num <= bound
        };
        if beyond && !(bound.abs() < f32::MIN_POSITIVE) {
            return None;
        }
        let q = num / den;
        (q > 0.0 && q < limit).then_some(q)
    }
    /// One division and three products (the course's three divisions are for `f64`).
    #[inline]
    fn div_vec(v: Vec3<Self>, d: Self) -> Vec3<Self> {
        let r = 1.0 / d;
        Vec3::new(v.x * r, v.y * r, v.z * r)
    }
}

/// `f32` square root: the FPU's VSQRT where the target has one (Cortex-M4F/M7 with the
/// hard-float ABI), `libm` elsewhere. Both are IEEE square roots, correctly rounded, so the
/// result is the same bits either way.
#[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
#[inline]
fn sqrtf(x: f32) -> f32 {
    libm::sqrtf(x)
}

#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
use vsqrt::sqrtf;

/// VSQRT in a two-instruction function: inline `asm!` with float registers needs an unstable
/// target feature, `global_asm!` does not. The only `unsafe` in the library.
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[allow(unsafe_code)]
mod vsqrt {
    core::arch::global_asm!(
        ".section .text.microray_vsqrtf,\"ax\",%progbits",
        ".global microray_vsqrtf",
        ".type microray_vsqrtf,%function",
        ".fpu fpv4-sp-d16",
        ".thumb_func",
        "microray_vsqrtf:",
        "vsqrt.f32 s0, s0",
        "bx lr",
    );

    unsafe extern "C" {
        fn microray_vsqrtf(x: f32) -> f32;
    }

    #[inline]
    pub(super) fn sqrtf(x: f32) -> f32 {
        // SAFETY: the function above takes and returns its f32 in s0, as the hard-float ABI
        // does, and touches nothing else.
        unsafe { microray_vsqrtf(x) }
    }
}

/// A written value checked at load: finite, and within the number type's range.
pub(crate) fn load<S: Scalar>(value: f64, attr: Attr) -> Result<S, ErrorKind> {
    if !value.is_finite() {
        return Err(ErrorKind::NonFiniteValue { attr });
    }
    // Below the normal range a value is zero for every purpose of the tracer, and scaling it
    // by a power of two would not be exact: it is flushed to zero.
    // (Multiplying by zero keeps the sign, so that `-0` prints back as `-0`.)
    let value = if libm::fabs(value) < f64::MIN_POSITIVE {
        value * 0.0
    } else {
        value
    };
    let loaded = S::from_f64_checked(value).ok_or(ErrorKind::BeyondRange {
        attr,
        number_type: S::NAME,
    })?;
    if loaded.to_f64() != 0.0 && libm::fabs(loaded.to_f64()) < S::MIN_NORMAL {
        return Ok(S::from_f64(loaded.to_f64() * 0.0));
    }
    Ok(loaded)
}

/// A position, multiplied by the scene's scale (exact: a power of two) and loaded.
pub(crate) fn load_position<S: Scalar>(
    v: [f64; 3],
    scale: f64,
    attr: Attr,
) -> Result<Vec3<S>, ErrorKind> {
    if !v.iter().all(|c| c.is_finite()) {
        return Err(ErrorKind::NonFiniteValue { attr });
    }
    load3([v[0] * scale, v[1] * scale, v[2] * scale], attr)
}

/// A length that must be above zero (radius, side, world window), scaled and loaded; it
/// must also be at least the type's resolution.
pub(crate) fn load_length<S: Scalar>(v: f64, scale: f64, attr: Attr) -> Result<S, ErrorKind> {
    if !(v > 0.0) {
        return Err(ErrorKind::NotPositive { attr });
    }
    let length = load::<S>(v * scale, attr)?;
    // Positive as written: a length that rounds to zero is too small for the type.
    if v * scale < S::MIN_FEATURE || !(length > S::ZERO) {
        return Err(ErrorKind::TooSmallForType {
            attr,
            number_type: S::NAME,
        });
    }
    Ok(length)
}

/// A direction (a normal, an `xdir`, an axis): only its direction counts, so one whose
/// components are all below 1/16 or one above 256 is first scaled by a power of two to bring
/// its largest component into `[0.5, 1)`. Exact in floating point (the unit vector made from
/// it is the same, bit for bit); in fixed point it keeps the direction's precision, which a
/// normal of `1e-4 5e-5 0` written as is would lose to the type's step of 2^-16.
pub(crate) fn load_direction<S: Scalar>(v: [f64; 3], attr: Attr) -> Result<Vec3<S>, ErrorKind> {
    let largest = v.iter().fold(0.0_f64, |m, c| m.max(libm::fabs(*c)));
    let mut k = 1.0;
    if largest > 0.0 && largest.is_finite() && !(1.0 / 16.0..=256.0).contains(&largest) {
        // At most 1100 halvings or doublings cover every finite f64.
        for _ in 0..1100 {
            if largest * k < 0.5 {
                k *= 2.0;
            } else if largest * k >= 1.0 {
                k *= 0.5;
            } else {
                break;
            }
        }
    }
    load3(v.map(|c| c * k), attr)
}

/// [`load`] for each component of a vector.
pub(crate) fn load3<S: Scalar>(v: [f64; 3], attr: Attr) -> Result<Vec3<S>, ErrorKind> {
    Ok(Vec3::new(
        load(v[0], attr)?,
        load(v[1], attr)?,
        load(v[2], attr)?,
    ))
}

/// Counts the bytes a formatting would write, without storing them.
#[cfg(feature = "print")]
struct Counter(usize);

#[cfg(feature = "print")]
impl fmt::Write for Counter {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.0 = self.0.saturating_add(s.len());
        Ok(())
    }
}

/// Writes a float with the fewest characters that read back exactly.
///
/// `core` formats both `{}` and `{:e}` with the shortest round-trip digits; the plain form is
/// chosen unless the exponent form is shorter (`1e-7` rather than `0.0000001`).
#[cfg(feature = "print")]
pub(crate) fn write_shortest_float<T: fmt::Display + fmt::LowerExp>(
    value: T,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    let mut plain = Counter(0);
    let mut exponent = Counter(0);
    fmt::write(&mut plain, format_args!("{value}"))?;
    fmt::write(&mut exponent, format_args!("{value:e}"))?;
    if exponent.0 < plain.0 {
        write!(out, "{value:e}")
    } else {
        write!(out, "{value}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The next state of a xorshift generator (test inputs).
    fn xorshift(seed: &mut u64) {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
    }

    /// `count` pairs of test inputs from `seed`: a random bit pattern (any value, the
    /// special ones among them), then the state's top 53 bits as a fraction in [0, 1)
    /// mapped by `scale`.
    fn random_f64s(seed: u64, count: usize, scale: impl Fn(f64) -> f64) -> Vec<f64> {
        let mut seed = seed;
        let mut values = Vec::with_capacity(2 * count);
        for _ in 0..count {
            xorshift(&mut seed);
            values.push(f64::from_bits(seed));
            values.push(scale((seed >> 11) as f64 / (1u64 << 53) as f64));
        }
        values
    }

    /// Below an `f32` glint's floor `powf` is exactly zero, for every exponent from the
    /// course's scenes and others, at the values just below the floor and at random ones
    /// below it; and the floor is not trivially low (at 250, the course's shininess, it
    /// leaves out the cosines below 0.6).
    #[test]
    fn f32_powers_below_the_glint_floor_are_zero() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        for y in [
            1.0f32, 2.5, 10.0, 20.0, 50.0, 100.0, 200.0, 250.0, 1000.0, 1.0e6,
        ] {
            let floor = f32::glint_floor(y);
            // (At 1 the floor, 2^-160, is below every f32: nothing is left out.)
            assert!((0.0..1.0).contains(&floor), "{y}: floor {floor}");
            if floor == 0.0 {
                continue;
            }
            let mut x = floor;
            for _ in 0..10_000 {
                x = f32::from_bits(x.to_bits() - 1);
                assert_eq!(libm::powf(x, y), 0.0, "{x:e}^{y} below the floor {floor:e}");
            }
            for _ in 0..100_000 {
                xorshift(&mut seed);
                let x = floor * ((seed >> 40) as f32 / (1u64 << 24) as f32);
                assert_eq!(libm::powf(x, y), 0.0, "{x:e}^{y} below the floor {floor:e}");
            }
        }
        assert!(f32::glint_floor(250.0) > 0.6);
        assert_eq!(f32::glint_floor(0.0), 0.0);
    }

    #[test]
    fn pow_of_std_and_libm_agree_within_one_ulp() {
        // The glints' arguments: a cosine in (0, 1] to the course's shininesses and others.
        let mut differ = 0;
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..100_000 {
            xorshift(&mut seed);
            let x = (seed >> 11) as f64 / (1u64 << 53) as f64;
            for y in [1.0, 2.5, 20.0, 50.0, 200.0, 250.0] {
                let (ours, reference) = (x.pow_positive(y), libm::pow(x, y));
                let ulps = ours.to_bits().abs_diff(reference.to_bits());
                assert!(
                    ulps <= 1,
                    "{x:e}^{y}: {ours:e} against libm's {reference:e}"
                );
                differ += usize::from(ulps != 0);
            }
        }
        // With `std` they are two implementations (which do differ), without one.
        assert_eq!(differ > 0, cfg!(feature = "std"), "{differ} differ");
    }

    #[test]
    fn f64_parameter_within_is_the_quotients_rule() {
        // The rule as the trait's default writes it: the quotient, kept when in (0, limit).
        let rule = |num: f64, den: f64, limit: f64| {
            let q = num / den;
            (q > 0.0 && q < limit).then_some(q)
        };
        let mut values = vec![
            0.0,
            -0.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            1.0,
            -1.0,
        ];
        values.extend([
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            5e-324,
            -5e-324,
            1e300,
            -1e300,
        ]);
        values.extend(random_f64s(0x853c_49e6_748f_ea9b_u64, 2_000, |u| {
            u * 20.0 - 10.0
        }));
        let limits = [f64::INFINITY, 1e-300, 0.5, 3.0, 1e300, 0.0, -1.0, f64::NAN];
        for (k, &num) in values.iter().enumerate() {
            for &den in values.iter().skip(k % 7).step_by(7) {
                for limit in limits {
                    let (got, want) = (
                        f64::parameter_within(num, den, limit),
                        rule(num, den, limit),
                    );
                    assert_eq!(
                        got.map(f64::to_bits),
                        want.map(f64::to_bits),
                        "{num:e} {den:e}"
                    );
                }
            }
        }
    }

    #[test]
    fn f64_floor_is_odd_is_the_floors_parity() {
        let mut values = vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 0.0, -0.0, 1e300];
        for base in [
            0.0,
            1.0,
            2.0,
            3.0,
            1e6,
            2_147_483_647.0,
            2_147_483_648.0,
            4.5e15,
        ] {
            for sign in [1.0, -1.0] {
                let v: f64 = sign * base;
                let halves = [v - 0.5, v + 0.5, v - 1.5, v + 1.5];
                values.extend([v, v.next_up(), v.next_down()]);
                values.extend(halves);
                values.extend(halves.map(f64::next_up));
                values.extend(halves.map(f64::next_down));
            }
        }
        values.extend(random_f64s(0x9e37_79b9_7f4a_7c15_u64, 200_000, |u| {
            u * 400.0 - 200.0
        }));
        for v in values {
            assert_eq!(v.floor_is_odd(), v.floor_to_i32() & 1 == 1, "{v:e}");
        }
    }

    #[test]
    fn f64_to_byte_is_the_branching_rule() {
        // The rule as the trait's default writes it.
        let rule = |c: f64| {
            let v = c * 255.0;
            if v >= 255.0 {
                255
            } else if v > 0.0 {
                v as u8
            } else {
                0
            }
        };
        let mut values = vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 0.0, -0.0, 1e300];
        for k in 0..=256 {
            let c = f64::from(k) / 255.0;
            values.extend([c, c.next_up(), c.next_down(), -c, c + 1e-9]);
        }
        values.extend(random_f64s(0x2545_f491_4f6c_dd1d_u64, 100_000, |u| {
            u * 3.0 - 1.0
        }));
        for c in values {
            assert_eq!(Scalar::to_byte(c), rule(c), "{c:e}");
        }
    }

    #[test]
    fn floor_to_i32_is_libm_floor_saturated() {
        // Around every whole number that matters (ties at integers, negative fractions,
        // the i32 limits, f32's 2^24), random bit patterns, and the special values.
        let mut values = vec![0.0, -0.0, 0.5, -0.5, 1.0, -1.0, f64::NAN, f64::INFINITY];
        values.push(f64::NEG_INFINITY);
        for base in [
            0.0,
            1.0,
            7.0,
            16_777_216.0,
            2_147_483_647.0,
            2_147_483_648.0,
        ] {
            for sign in [1.0, -1.0] {
                let v: f64 = sign * base;
                let mut below = v;
                let mut above = v;
                for _ in 0..4 {
                    below = below.next_down();
                    above = above.next_up();
                    values.extend([below, above, v + 0.25, v - 0.75]);
                }
            }
        }
        // Mostly moderate numbers, both signs (u 2^33 - 4e9; the scaling is exact).
        values.extend(random_f64s(0x2545_f491_4f6c_dd1d_u64, 200_000, |u| {
            u * 8_589_934_592.0 - 4.0e9
        }));
        for v in values {
            assert_eq!(v.floor_to_i32(), libm::floor(v) as i32, "f64 {v:e}");
            let single = v as f32;
            assert_eq!(
                single.floor_to_i32(),
                libm::floorf(single) as i32,
                "f32 {single:e}"
            );
        }
    }

    #[test]
    fn sqrt_by_digits_is_libm_sqrt() {
        let check = |x: f64| {
            let (ours, libm) = (sqrt_by_digits(x), libm::sqrt(x));
            assert!(
                ours.to_bits() == libm.to_bits() || (ours.is_nan() && libm.is_nan()),
                "{x:e}: {ours:e} {libm:e}"
            );
        };
        // Random bit patterns: every exponent, subnormals, negatives and NaNs among them.
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..1_000_000 {
            xorshift(&mut seed);
            check(f64::from_bits(seed));
            check(f64::from_bits(seed >> 12));
        }
        // Squares of integers and their neighbours (exact roots, and roots just off them),
        // and the special values.
        for n in 1..100_000u64 {
            let square = (n * n) as f64;
            for x in [
                square,
                f64::from_bits(square.to_bits() - 1),
                f64::from_bits(square.to_bits() + 1),
            ] {
                check(x);
            }
        }
        for x in [
            0.0,
            -0.0,
            1.0,
            2.0,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::INFINITY,
            -1.0,
            f64::NAN,
        ] {
            check(x);
        }
        assert_eq!(sqrt_by_digits(-0.0).to_bits(), (-0.0f64).to_bits());
    }

    #[test]
    fn sqrt_by_halves_is_within_two_to_the_minus_23() {
        let check = |x: f64| {
            let (rough, exact) = (sqrt_by_halves(x), libm::sqrt(x));
            if exact.is_nan() {
                assert!(rough.is_nan(), "{x:e}: {rough:e}");
            } else if exact == 0.0 || exact.is_infinite() {
                assert_eq!(rough.to_bits(), exact.to_bits(), "{x:e}");
            } else {
                let error = libm::fabs(rough - exact) / exact;
                assert!(
                    error <= 1.0 / 8_388_608.0,
                    "{x:e}: {rough:e} {exact:e} {error:e}"
                );
            }
        };
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..1_000_000 {
            xorshift(&mut seed);
            check(f64::from_bits(seed));
            check(f64::from_bits(seed >> 12));
        }
        for x in [
            0.0,
            -0.0,
            1.0,
            2.0,
            3.999_999,
            4.0,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
        ] {
            check(x);
        }
        for x in [f64::INFINITY, -1.0, f64::NAN] {
            check(x);
        }
    }

    fn shortest<S: Scalar>(v: S) -> std::string::String {
        let mut s = std::string::String::new();
        v.write_shortest(&mut s).unwrap();
        s
    }

    #[test]
    fn shortest_text_prefers_the_shorter_form() {
        assert_eq!(shortest(640.0f64), "640");
        assert_eq!(shortest(0.8f64), "0.8");
        assert_eq!(shortest(-6.93f64), "-6.93");
        assert_eq!(shortest(1e-7f64), "1e-7");
        assert_eq!(shortest(100000.0f64), "1e5");
        assert_eq!(shortest(0.1f32), "0.1");
        assert_eq!(shortest(-0.0f64), "-0");
    }

    #[test]
    fn shortest_text_reads_back_exactly() {
        for v in [
            0.1f64,
            1.0 / 3.0,
            2.121,
            1e300,
            5e-324,
            -123456.789e-20,
            6.02214076e23,
        ] {
            assert_eq!(shortest(v).parse::<f64>().unwrap(), v);
        }
    }

    #[test]
    fn square_root_of_negative_is_zero() {
        assert_eq!(Scalar::sqrt(-4.0f64), 0.0);
        assert_eq!(Scalar::sqrt(-4.0f32), 0.0);
        assert_eq!(Scalar::sqrt(f64::NAN), 0.0);
        assert_eq!(Scalar::sqrt(9.0f64), 3.0);
    }

    #[test]
    fn bytes_truncate_and_clamp() {
        assert_eq!(0.5f64.to_byte(), 127);
        assert_eq!((1.0f64 / 255.0 * 3.0).to_byte(), 3);
        assert_eq!(2.0f64.to_byte(), 255);
        assert_eq!((-1.0f32).to_byte(), 0);
        assert_eq!(f64::NAN.to_byte(), 0);
    }

    #[test]
    fn power_of_non_positive_is_zero() {
        assert_eq!(Scalar::pow_positive(-0.5f64, 2.0), 0.0);
        assert_eq!(Scalar::pow_positive(0.0f32, 50.0), 0.0);
        assert_eq!(Scalar::pow_positive(0.5f64, 2.0), 0.25);
    }

    #[test]
    fn floor_saturates() {
        assert_eq!((-0.5f64).floor_to_i32(), -1);
        assert_eq!(1e300f64.floor_to_i32(), i32::MAX);
        assert_eq!(f64::NAN.floor_to_i32(), 0);
        assert_eq!((2.5f32).floor_to_i32(), 2);
    }

    #[test]
    fn f32_bytes_equal_the_f64_conversion() {
        check_f32_bytes(Scalar::to_byte);
        check_f32_bytes(f32_byte_by_scaling);
        check_f32_bytes(f32_byte_by_bits);
    }

    fn check_f32_bytes(to_byte: fn(f32) -> u8) {
        // Every f32 near each byte boundary, and a sweep of all exponents below 1.
        for k in 0..=255u32 {
            let edge = k as f32 / 255.0;
            let mut v = edge;
            for _ in 0..40 {
                assert_eq!(to_byte(v), Scalar::to_byte(f64::from(v)), "{v:e}");
                v = f32::from_bits(v.to_bits() + 1);
            }
            let mut v = edge;
            for _ in 0..40 {
                assert_eq!(to_byte(v), Scalar::to_byte(f64::from(v)), "{v:e}");
                v = f32::from_bits(v.to_bits().saturating_sub(1));
            }
        }
        for bits in (0..0x3f80_0000u32).step_by(997) {
            let v = f32::from_bits(bits);
            assert_eq!(to_byte(v), Scalar::to_byte(f64::from(v)), "{v:e}");
        }
        // Above 1, negative, infinite and NaN values.
        for v in [
            1.0f32,
            1.5,
            f32::MAX,
            f32::INFINITY,
            -f32::INFINITY,
            f32::NAN,
            -f32::NAN,
            -0.0,
            -0.5,
            f32::MIN_POSITIVE,
            1e-45,
        ] {
            assert_eq!(to_byte(v), Scalar::to_byte(f64::from(v)), "{v:e}");
        }
    }
}
