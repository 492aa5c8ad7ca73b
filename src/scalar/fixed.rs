//! Fixed point: [`I16F16`], 32 bits with 16 fractional bits, for microcontrollers without a
//! floating-point unit (Cortex-M0/M0+, RP2040, ESP32-C3).
//!
//! The type wraps the `fixed` crate's `I16F16` and does its arithmetic on the raw bits, so
//! that nothing can panic and the hot operations are the cheap ones:
//!
//! | operation | how | result |
//! |---|---|---|
//! | `+`, `-`, negation | `i32` saturating | exact, or saturated at ±32768 |
//! | `*` | 32x32 -> 64-bit product (four 16x16 products on Cortex-M0), shift, saturate | truncated toward -inf: equal to the crate's `saturating_mul` |
//! | `/` | a table and two Newton steps for `1 / d`, one multiply, corrected by the remainder | truncated toward 0: equal to the crate's `saturating_div`; `x / 0` is ±MAX (0 for 0 / 0) |
//! | [`Scalar::div_vec`] | one reciprocal, three quotients | the same as three `/` |
//! | [`Scalar::dot`] | three 64-bit products summed, one shift | one truncation instead of three; no intermediate overflow |
//! | [`Scalar::length`] | 64-bit sum of squares, integer square root | floor of the exact length; no overflow below 2^31 |
//! | `sqrt` | integer square root of `bits << 16` (a table and Newton steps on the reciprocal root, corrected) | floor of the exact root |
//! | [`Scalar::pow_positive`] | `exp2(e * log2(x))`, both bit by bit to 24 bits | within 0.8 of a step (2^-16) of the exact power for `x` in (0, 1], `e` up to 250 (measured: 0.76) |
//! | [`Scalar::to_byte`] | `(bits * 255) >> 16` | exactly the f64 conversion of the same value |

use super::ball::{BallTest, line_clears_disc, ray_clears_wide_of, segment_clears_box};
pub use super::wide::Wide;
use super::wide::{
    Divisor, FLOAT_GUESSES, all_below, dot_i64_small, dot_q16_small, float_quotient_q16,
    float_scale_q16, in_halves, isqrt, leading_zeros, mul_i32, mul_q16_small, mul_u32, shr_u64,
};
use super::{PixelSteps, RowRoots, Scalar};
use crate::vec3::Vec3;
use core::cmp::Ordering;
use core::fmt;
use core::ops::{Add, Div, Mul, Neg, Sub};

type Inner = fixed::types::I16F16;

/// Fractional bits.
const FRAC: u32 = 16;

/// A Q16.16 fixed-point number: range -32768 to 32767.99998, resolution 2^-16 (1.5e-5).
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct I16F16(pub Inner);

impl I16F16 {
    /// The largest value.
    pub const MAX: Self = Self(Inner::MAX);
    /// The smallest (most negative) value.
    pub const MIN: Self = Self(Inner::MIN);

    /// The value with these raw bits (`bits / 65536`).
    #[inline]
    pub const fn from_bits(bits: i32) -> Self {
        Self(Inner::from_bits(bits))
    }

    /// The raw bits.
    #[inline]
    pub const fn to_bits(self) -> i32 {
        self.0.to_bits()
    }

    #[inline]
    fn saturate(wide: i64) -> Self {
        // In range exactly when the value is its low word sign-extended (two instructions
        // on a 32-bit target, where a clamp of an i64 is a dozen).
        let low = wide as i32;
        if i64::from(low) == wide {
            Self::from_bits(low)
        } else if wide < 0 {
            Self::MIN
        } else {
            Self::MAX
        }
    }

    /// `x / d` with `d` prepared: `trunc(x 2^16 / d)`, saturated; `d` is the divisor's
    /// magnitude and `negative` its sign.
    #[inline]
    fn divide_by(self, d: &Divisor, negative: bool) -> Self {
        let bits = self.to_bits();
        let negative = (bits < 0) != negative;
        match d.divide_q16(bits.unsigned_abs()) {
            Some(q) if negative => Self::from_bits(-(q as i32)),
            Some(q) => Self::from_bits(q as i32),
            None if negative => Self::MIN,
            None => Self::MAX,
        }
    }

    /// [`divide_by`](Self::divide_by) from the float unit's estimate (see
    /// [`float_quotient_q16`]), where the quotient's bits are below `2^22` (64 in Q16.16):
    /// the same value; `None` elsewhere.
    #[inline(always)]
    fn divide_by_float(self, magnitude: u32, scale: f32, negative: bool) -> Option<Self> {
        let bits = self.to_bits();
        let negative = (bits < 0) != negative;
        // Below 2^22: the negation cannot overflow.
        let q = float_quotient_q16(bits.unsigned_abs(), magnitude, scale)? as i32;
        Some(Self::from_bits(if negative { -q } else { q }))
    }

    /// `x / 0`: saturated by the sign of `x`, 0 for 0.
    #[inline]
    fn divide_by_zero(self) -> Self {
        match self.to_bits().cmp(&0) {
            Ordering::Greater => Self::MAX,
            Ordering::Less => Self::MIN,
            Ordering::Equal => Self::ZERO,
        }
    }

    /// `log2(self)` as a Q8.24 number, for `self > 0` (bit-by-bit squaring: 24 bits, each
    /// step truncating).
    fn log2_q24(self) -> i64 {
        let bits = self.to_bits();
        if bits <= 0 {
            return i64::MIN;
        }
        let msb = 31 - leading_zeros(bits as u32);
        let mut m = (bits as u32) << (30 - msb); // mantissa in [1, 2) as Q2.30
        // In 32 bits: a variable shift of an `i64` is a library call on ARMv6-M.
        let mut fraction = 0u32;
        for i in 1..=24 {
            // m^2 is below 4: Q2.30 again after the shift.
            m = (mul_u32(m, m) >> 30) as u32;
            if m >= 1 << 31 {
                m >>= 1;
                fraction |= 1 << (24 - i);
            }
        }
        ((i64::from(msb) - i64::from(FRAC)) << 24) + i64::from(fraction)
    }

    /// `2^y` for a Q.24 exponent: the integer part shifts, the fraction multiplies the
    /// constants `2^(2^-i)`.
    /// `2^y` for a Q.24 exponent as a wide number: the fraction's Q2.30 mantissa and the
    /// integer part as the exponent, so that small powers keep 30 significant bits.
    fn exp2_q24_wide(y: i64) -> Option<Wide> {
        let k = y >> 24;
        if !(-1000..15).contains(&k) {
            return None;
        }
        let p = Self::exp2_mantissa(y);
        Some(Wide::from_u64(u64::from(p), k as i32 - 30))
    }

    /// `2^f` as Q2.30 for the fraction `f` in `[0, 1)` of a Q.24 exponent `y` (its low 24
    /// bits).
    fn exp2_mantissa(y: i64) -> u32 {
        // 2^(2^-i) as Q2.30, i = 1..24.
        const ROOTS: [u32; 24] = [
            1518500250, 1276901417, 1170923762, 1121280436, 1097253708, 1085434106, 1079572136,
            1076653033, 1075196443, 1074468888, 1074105294, 1073923544, 1073832680, 1073787251,
            1073764537, 1073753181, 1073747502, 1073744663, 1073743244, 1073742534, 1073742179,
            1073742001, 1073741913, 1073741868,
        ];
        // The fraction's 24 bits in a `u32`: a variable shift of an `i64` is a library call
        // on ARMv6-M.
        let fraction = (y & ((1 << 24) - 1)) as u32;
        let mut p: u32 = 1 << 30;
        for (i, root) in ROOTS.iter().enumerate() {
            if fraction & (1 << (23 - i)) != 0 {
                // Both below 2^31, the product below 2^62: Q2.30 again after the shift.
                p = (mul_u32(p, *root) >> 30) as u32;
            }
        }
        p
    }

    fn exp2_q24(y: i64) -> Self {
        let k = y >> 24;
        if k >= 15 {
            return Self::MAX;
        }
        if k < -18 {
            return Self::from_bits(0);
        }
        let p = Self::exp2_mantissa(y);
        // p is 2^fraction as Q2.30; the result in Q16.16 is p * 2^k >> 14, rounded.
        let shift = 14 - k; // 1..=32
        // Half a unit below 2^32: a 32-bit shift (a 64-bit one is a call on ARMv6-M).
        let half = u64::from(1u32 << (shift - 1));
        let rounded = shr_u64(u64::from(p) + half, shift as u32);
        Self::saturate(rounded as i64)
    }
}

impl Vec3<I16F16> {
    /// The raw bits of the components.
    #[inline]
    fn bits(self) -> [i32; 3] {
        [self.x.to_bits(), self.y.to_bits(), self.z.to_bits()]
    }
}

impl fmt::Debug for I16F16 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

impl fmt::Display for I16F16 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

impl Add for I16F16 {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self::from_bits(self.to_bits().saturating_add(o.to_bits()))
    }
}

impl Sub for I16F16 {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self::from_bits(self.to_bits().saturating_sub(o.to_bits()))
    }
}

impl Neg for I16F16 {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self::from_bits(self.to_bits().saturating_neg())
    }
}

// A fixed-point product is the integer product shifted back by the fractional bits.
#[allow(clippy::suspicious_arithmetic_impl)]
impl Mul for I16F16 {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let (a, b) = (self.to_bits(), o.to_bits());
        // Cortex-M0: below 128 the product needs no 64-bit sum (the same result).
        if in_halves() && all_below(&[a, b], 7) {
            return Self::from_bits(mul_q16_small(a, b));
        }
        Self::saturate(mul_i32(a, b) >> FRAC)
    }
}

impl Div for I16F16 {
    type Output = Self;
    #[inline]
    fn div(self, o: Self) -> Self {
        let b = o.to_bits();
        if FLOAT_GUESSES
            && let Some(scale) = float_scale_q16(b.unsigned_abs())
            && let Some(q) = self.divide_by_float(b.unsigned_abs(), scale, b < 0)
        {
            return q;
        }
        match Divisor::new(b.unsigned_abs()) {
            Some(d) => self.divide_by(&d, b < 0),
            None => self.divide_by_zero(),
        }
    }
}

/// The axis of a vector that is one (`false`) or minus one (`true`) along it and zero
/// elsewhere: 0 for x, 1 for y, 2 for z.
#[inline]
fn axis_of(n: Vec3<I16F16>) -> Option<(usize, bool)> {
    const ONE: u32 = 1 << FRAC;
    let [x, y, z] = n.bits();
    // Floors first, then walls.
    let (coordinate, value) = if x == 0 && z == 0 {
        (1, y)
    } else if x == 0 && y == 0 {
        (2, z)
    } else if y == 0 && z == 0 {
        (0, x)
    } else {
        return None;
    };
    (value.unsigned_abs() == ONE).then_some((coordinate, value < 0))
}

/// `v . n`, read off one coordinate when `n` is one along an axis. Exact: the other
/// products are zero and the one left is the coordinate times 2^16, which the truncation
/// gives back.
#[inline]
fn dot_along_axis(v: Vec3<I16F16>, n: Vec3<I16F16>) -> I16F16 {
    match axis_of(n) {
        Some((coordinate, false)) => v.at(coordinate),
        Some((coordinate, true)) => -v.at(coordinate),
        None => I16F16::dot(v, n),
    }
}

/// `dir - 2 (dir . n) n`, with one coordinate changed when `n` is one along an axis.
/// Exact: `n k` is then `k` or `-k` there (both saturating as the product does) and zero
/// elsewhere, and subtracting zero changes nothing.
#[inline]
fn reflect_along_axis(dir: Vec3<I16F16>, n: Vec3<I16F16>) -> Vec3<I16F16> {
    let Some((coordinate, negative)) = axis_of(n) else {
        return dir - n * (I16F16::TWO * I16F16::dot(dir, n));
    };
    let along = dir.at(coordinate);
    let twice = I16F16::TWO * if negative { -along } else { along };
    let change = if negative { -twice } else { twice };
    let mut out = dir;
    match coordinate {
        0 => out.x = along - change,
        1 => out.y = along - change,
        _ => out.z = along - change,
    }
    out
}

/// `positive_dot(v, n)` as [`dot_along_axis`]: the sum is the coordinate times 2^16, the
/// same wide number.
#[inline]
fn positive_dot_along_axis(v: Vec3<I16F16>, n: Vec3<I16F16>) -> Option<Wide> {
    // In 64 bits: minus the most negative value is not saturated here.
    let value = match axis_of(n) {
        Some((coordinate, false)) => i64::from(v.at(coordinate).to_bits()),
        Some((coordinate, true)) => -i64::from(v.at(coordinate).to_bits()),
        None => return I16F16::positive_dot(v, n),
    };
    (value > 0).then(|| Wide::from_u64(value as u64, -16))
}

impl Vec3<I16F16> {
    /// The coordinate `0` (x), `1` (y) or `2` (z).
    #[inline]
    fn at(self, coordinate: usize) -> I16F16 {
        match coordinate {
            0 => self.x,
            1 => self.y,
            _ => self.z,
        }
    }
}

impl Scalar for I16F16 {
    const NAME: &'static str = "i16f16";
    const CODE: u8 = 3;
    const RAW_BYTES: usize = 4;
    const ZERO: Self = Self::from_bits(0);
    const ONE: Self = Self::from_bits(1 << FRAC);
    const TWO: Self = Self::from_bits(2 << FRAC);
    const UNBOUNDED: Self = Self::MAX;
    const STEP: Self = Self::from_bits(1 << (FRAC - 16));
    // Distances between points of a cube of half-side 8192 stay below 2 sqrt(3) 8192 = 28378.
    const MAX_EXTENT: f64 = 8192.0;
    // Half the range: room for a few lights' terms to be added before the division.
    const MAX_TERM: f64 = 16384.0;
    const MIN_NORMAL: f64 = 1.0 / 65536.0;
    // 256 steps of 2^-16.
    const MIN_FEATURE: f64 = 1.0 / 256.0;
    const UNIT_STEP: f64 = 1.0 / 65536.0;
    // Rounded to the nearest step.
    const SINE: [Self; 10] = [
        Self::from_bits(32768),
        Self::from_bits(10430),
        Self::from_bits(411775),
        Self::from_bits(205887),
        Self::from_bits(102944),
        Self::from_bits(10923),
        Self::from_bits(3277),
        Self::from_bits(1560),
        Self::from_bits(910),
        Self::from_bits(596),
    ];
    /// The series' products in 32-bit arithmetic on the Cortex-M0, whose `Mul` checks each
    /// product's size first (the same values: `Mul` takes this product below 128). Not
    /// built for size: a second caller of `mul_q16_small` left it out of `Mul`'s line there
    /// (the minimal build's `basic` +1.3 %).
    #[inline]
    fn sin(self) -> Self {
        super::sine(self, |a, b| {
            if in_halves() && !cfg!(microray_small) {
                Self::from_bits(mul_q16_small(a.to_bits(), b.to_bits()))
            } else {
                a * b
            }
        })
    }
    const WIDE_RANGE: bool = false;
    const COURSE_ORDER: bool = false;
    const PIXEL_STEPS: PixelSteps = PixelSteps::Exact;
    type Wide = Wide;
    /// `dy^2 + dz^2`, exact.
    #[inline(always)]
    fn row_squares(dy: Self, dz: Self) -> u64 {
        square_bits(dy) + square_bits(dz)
    }
    /// The exact pre-test of `src/scalar/ball.rs`, for rays whose length the test works
    /// out (built for size, left out: the test alone decides).
    #[inline]
    fn misses_ball(f: Vec3<Self>, dir: Vec3<Self>, len: Self, r_squared: Self) -> bool {
        !cfg!(microray_small)
            && len == Self::ZERO
            && BallTest {
                f: f.bits(),
                dir: dir.bits(),
                radius_squared: r_squared.to_bits(),
            }
            .misses()
    }
    /// `src/scalar/ball.rs`'s box test, on the Cortex-M0 only: there the exact test's
    /// products are library-sized (a settled ray saves some 300 instructions, a box test
    /// that cannot tell costs about 30), while with 64-bit multiplies the exact test is
    /// cheap enough that spec3, whose balls sit by its lights, lost more than the
    /// showcase gained (M4F Q16.16: spec3 +2.3 %, showcase -2.9 %). Built for size, left
    /// out: the test alone decides.
    #[inline]
    fn segment_clears_box(f: Vec3<Self>, dir: Vec3<Self>, half: Vec3<Self>) -> bool {
        let [Ok(x), Ok(y), Ok(z)] = half.bits().map(u32::try_from) else {
            return false;
        };
        in_halves() && !cfg!(microray_small) && segment_clears_box(f.bits(), dir.bits(), [x, y, z])
    }
    /// `src/scalar/ball.rs`'s exact test (built for size, left out: the search alone
    /// decides).
    #[inline]
    fn ray_clears_ball(f: Vec3<Self>, dir: Vec3<Self>, radius: Self) -> bool {
        let Ok(radius) = u32::try_from(radius.to_bits()) else {
            return false;
        };
        !cfg!(microray_small) && ray_clears_wide_of(f.bits(), dir.bits(), radius)
    }
    /// `src/scalar/ball.rs`'s exact test on `x` and `z` (left out built for size).
    #[inline]
    fn line_clears_upright(f: Vec3<Self>, dir: Vec3<Self>, radius: Self) -> bool {
        let Ok(radius) = u32::try_from(radius.to_bits()) else {
            return false;
        };
        let (f, dir) = (f.bits(), dir.bits());
        !cfg!(microray_small) && line_clears_disc([f[0], f[2]], [dir[0], dir[2]], radius)
    }
    /// [`length`](Scalar::length)'s exact sum of squares, two of them from the row, and
    /// its exact root from the row's last ones (built for size, the integer square root
    /// alone).
    #[inline(always)]
    fn row_length(x: Self, _: Self, _: Self, squares: u64, roots: &mut RowRoots) -> Self {
        let n = square_bits(x) + squares;
        // With a float unit, its guess is as near as the row's (see `FLOAT_GUESSES`).
        let root = if cfg!(microray_small) || FLOAT_GUESSES {
            isqrt(n)
        } else {
            roots.next(n)
        };
        Self::saturate(i64::from(root))
    }
    /// The exact 64-bit sum of the products, then 32 significant bits.
    #[inline]
    fn positive_dot(a: Vec3<Self>, b: Vec3<Self>) -> Option<Wide> {
        let (x, y) = (a.bits(), b.bits());
        let p = |x: Self, y: Self| mul_i32(x.to_bits(), y.to_bits());
        let sum = if all_below(&[x[0], x[1], x[2], y[0], y[1], y[2]], 6) {
            // Below 64 the products are below 2^44: their sum cannot overflow.
            if in_halves() {
                dot_i64_small(x, y)
            } else {
                p(a.x, b.x) + p(a.y, b.y) + p(a.z, b.z)
            }
        } else {
            p(a.x, b.x)
                .saturating_add(p(a.y, b.y))
                .saturating_add(p(a.z, b.z))
        };
        (sum > 0).then(|| Wide::from_u64(sum as u64, -32))
    }
    /// The exact sum of the squares, two of them from the row: the sum of
    /// [`positive_dot`](Scalar::positive_dot), whose saturating sum of squares is the
    /// exact one up to `i64::MAX`.
    #[inline(always)]
    fn positive_row_square(v: Vec3<Self>, squares: u64) -> Option<Wide> {
        let sum = (square_bits(v.x) + squares).min(i64::MAX as u64);
        (sum > 0).then(|| Wide::from_u64(sum, -32))
    }
    /// Along an axis on Cortex-M0 (see `dot_along_axis`), where products are dear;
    /// elsewhere the test would cost what it saves.
    #[inline]
    fn dot_unit(v: Vec3<Self>, n: Vec3<Self>) -> Self {
        if in_halves() {
            dot_along_axis(v, n)
        } else {
            Self::dot(v, n)
        }
    }
    /// Along an axis on Cortex-M0, as [`dot_unit`](Self::dot_unit) (see
    /// `reflect_along_axis`).
    #[inline]
    fn reflect(dir: Vec3<Self>, n: Vec3<Self>) -> Vec3<Self> {
        if in_halves() {
            reflect_along_axis(dir, n)
        } else {
            dir - n * (Self::TWO * Self::dot(dir, n))
        }
    }
    /// As [`dot_unit`](Self::dot_unit), with `positive_dot_along_axis`.
    #[inline]
    fn positive_dot_unit(v: Vec3<Self>, n: Vec3<Self>) -> Option<Wide> {
        if in_halves() {
            positive_dot_along_axis(v, n)
        } else {
            Self::positive_dot(v, n)
        }
    }
    #[inline]
    fn next_up(self) -> Self {
        Self::from_bits(self.to_bits().saturating_add(1))
    }
    /// The value in 1/256ths, floored, clamped to 16 bits.
    #[inline]
    fn order_key(self) -> i16 {
        (self.to_bits() >> 8).clamp(i32::from(i16::MIN), i32::from(i16::MAX)) as i16
    }
    #[inline]
    fn to_wide(self) -> Option<Wide> {
        let bits = self.to_bits();
        (bits > 0).then(|| Wide::from_u64(bits as u64, -16))
    }
    #[inline]
    fn wide_mul(a: Wide, b: Wide) -> Wide {
        a.mul(b)
    }
    #[inline]
    fn wide_recip(a: Wide) -> Wide {
        a.recip()
    }
    #[inline]
    fn scale(self, factor: Wide) -> Self {
        Self::from_bits(factor.scale_bits(self.to_bits()))
    }
    #[inline]
    fn scale3(v: Vec3<Self>, factor: Wide) -> Vec3<Self> {
        let [x, y, z] = factor.scale_bits3(v.bits());
        Vec3::new(Self::from_bits(x), Self::from_bits(y), Self::from_bits(z))
    }

    #[inline]
    fn to_raw(self) -> u64 {
        u64::from(self.to_bits() as u32)
    }
    #[inline]
    fn from_raw(raw: u64) -> Self {
        Self::from_bits(raw as u32 as i32)
    }

    /// Saturated at either end: every operation saturates instead of wrapping, so a result
    /// at the ends of the range may stand for a larger one. (Distances within a scene of
    /// extent [`Self::MAX_EXTENT`] stay below 28378, clear of the ends.)
    #[inline]
    fn is_beyond_range(self) -> bool {
        self == Self::MAX || self == Self::MIN
    }

    /// Rounded to nearest, ties to even, saturated; NaN is 0. On the bits (see
    /// `q16_bits_of_f64`): no floating-point arithmetic, which a Cortex-M has only in
    /// software for `f64`. Out of line: scenes are loaded once, and every inlined copy
    /// would cost flash.
    #[inline(never)]
    fn from_f64(value: f64) -> Self {
        let bits = q16_bits_of_f64(value).unwrap_or(0);
        Self::from_bits(bits.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32)
    }
    #[inline(never)]
    fn from_f64_checked(value: f64) -> Option<Self> {
        let bits = q16_bits_of_f64(value)?;
        i32::try_from(bits).ok().map(Self::from_bits)
    }
    #[inline]
    fn to_f64(self) -> f64 {
        f64::from(self.to_bits()) / 65536.0
    }
    /// One rounding of the bits (no conversion through `f64`, software on a Cortex-M0).
    #[inline]
    fn to_geo(self) -> crate::scalar::geometry::Geo {
        self.to_bits() as crate::scalar::geometry::Geo / 65536.0
    }
    #[inline]
    fn sqrt(self) -> Self {
        let bits = self.to_bits();
        if bits <= 0 {
            return Self::ZERO;
        }
        // sqrt(b / 2^16) * 2^16 = sqrt(b * 2^16); below 2^24, so it fits.
        Self::from_bits(isqrt((bits as u64) << FRAC) as i32)
    }
    fn pow_positive(self, exponent: Self) -> Self {
        if self.to_bits() <= 0 {
            return Self::ZERO;
        }
        let y = (self.log2_q24() * i64::from(exponent.to_bits())) >> FRAC;
        Self::exp2_q24(y)
    }
    /// The power with 30 significant bits however small it is (a glint times a bright
    /// light would multiply Q16.16's absolute step).
    fn pow_wide(self, exponent: Self) -> Option<Wide> {
        if self.to_bits() <= 0 {
            return None;
        }
        let y = (self.log2_q24() * i64::from(exponent.to_bits())) >> FRAC;
        Self::exp2_q24_wide(y)
    }
    #[inline]
    fn to_byte(self) -> u8 {
        let bits = self.to_bits();
        if bits <= 0 {
            return 0;
        }
        (mul_u32(bits as u32, 255) >> FRAC).min(255) as u8
    }
    #[inline]
    fn floor_to_i32(self) -> i32 {
        self.to_bits() >> FRAC
    }
    #[inline]
    fn from_i32(value: i32) -> Self {
        Self::saturate(i64::from(value) << FRAC)
    }
    /// Exact: `bits * numerator` in 64 bits, then the division, truncated.
    #[inline]
    fn mul_ratio(self, numerator: u16, denominator: u16) -> Self {
        if denominator == 0 {
            return self / Self::ZERO;
        }
        // |bits * numerator| < 2^47: the exact division fits the divisor's 48-bit numerator.
        let product = mul_i32(self.to_bits(), i32::from(numerator));
        match Divisor::new(u32::from(denominator)).and_then(|d| d.divide(product.unsigned_abs())) {
            Some(q) if product < 0 => Self::from_bits(-(q as i32)),
            Some(q) => Self::from_bits(q as i32),
            None if product < 0 => Self::MIN,
            None => Self::MAX,
        }
    }
    #[cfg(feature = "print")]
    fn write_shortest(self, out: &mut dyn fmt::Write) -> fmt::Result {
        // Five decimals always suffice: 10^-5 / 2 is below half a step (2^-17).
        let value = self.to_f64();
        for decimals in 0..=5 {
            let mut text = heapless::String::<24>::new();
            if fmt::write(&mut text, format_args!("{value:.decimals$}")).is_ok() {
                let back = crate::decimal::parse_number(text.as_bytes()).map(Self::from_f64);
                if back == Ok(self) {
                    return out.write_str(&text);
                }
            }
        }
        write!(out, "{value}")
    }

    #[inline]
    fn dot(a: Vec3<Self>, b: Vec3<Self>) -> Self {
        let (x, y) = (a.bits(), b.bits());
        let p = |x: Self, y: Self| mul_i32(x.to_bits(), y.to_bits());
        if all_below(&[x[0], x[1], x[2], y[0], y[1], y[2]], 6) {
            if in_halves() {
                return Self::from_bits(dot_q16_small(x, y));
            }
            // Below 64 the products are below 2^44: their sum cannot overflow, nor can
            // the result.
            return Self::from_bits(((p(a.x, b.x) + p(a.y, b.y) + p(a.z, b.z)) >> FRAC) as i32);
        }
        let sum = p(a.x, b.x)
            .saturating_add(p(a.y, b.y))
            .saturating_add(p(a.z, b.z));
        Self::saturate(sum >> FRAC)
    }
    /// The divisor's reciprocal once, then three exact quotients: the same results as
    /// three divisions.
    #[inline]
    fn div_vec(v: Vec3<Self>, d: Self) -> Vec3<Self> {
        let bits = d.to_bits();
        if FLOAT_GUESSES && let Some(scale) = float_scale_q16(bits.unsigned_abs()) {
            let each = |x: Self| x.divide_by_float(bits.unsigned_abs(), scale, bits < 0);
            if let (Some(x), Some(y), Some(z)) = (each(v.x), each(v.y), each(v.z)) {
                return Vec3::new(x, y, z);
            }
        }
        match Divisor::new(bits.unsigned_abs()) {
            Some(divisor) => Vec3::new(
                v.x.divide_by(&divisor, bits < 0),
                v.y.divide_by(&divisor, bits < 0),
                v.z.divide_by(&divisor, bits < 0),
            ),
            None => Vec3::new(
                v.x.divide_by_zero(),
                v.y.divide_by_zero(),
                v.z.divide_by_zero(),
            ),
        }
    }
    /// `v . axis > cos |v|`: one truncation on each side, where dividing `v` by its
    /// length first would round every component.
    #[inline]
    fn within_cone(v: Vec3<Self>, axis: Vec3<Self>, cos: Self) -> bool {
        v.dot(axis) > cos * v.length()
    }
    /// Exact without the division when the quotient is not in `(0, limit)`: it is
    /// negative when the signs differ, and for positive `a / b` the truncated quotient
    /// `floor(a 2^16 / b)` (saturated) is at least `l` exactly when `a 2^16 >= l b`, a
    /// 64-bit comparison.
    #[inline]
    fn parameter_within(num: Self, den: Self, limit: Self) -> Option<Self> {
        let (a, b, l) = (num.to_bits(), den.to_bits(), limit.to_bits());
        if a == 0 || b == 0 || (a ^ b) < 0 || l <= 0 {
            return None;
        }
        let scaled = u64::from(a.unsigned_abs()) << FRAC;
        if scaled >= mul_u32(l as u32, b.unsigned_abs()) {
            return None;
        }
        let q = num / den;
        (q > Self::ZERO).then_some(q)
    }
    #[inline]
    fn length(v: Vec3<Self>) -> Self {
        // Each square is at most 2^62, so the sum of three fits in 64 bits.
        let sum = square_bits(v.x) + square_bits(v.y) + square_bits(v.z);
        Self::saturate(i64::from(isqrt(sum)))
    }
}

/// The square of a value's bits (at most 2^62: three of them sum within 64 bits).
#[inline(always)]
fn square_bits(x: I16F16) -> u64 {
    let b = x.to_bits().unsigned_abs();
    mul_u32(b, b)
}

/// `value * 2^16` rounded to the nearest integer, ties to even (what the `fixed` crate's
/// conversion gives), from the bits of `value`; beyond ±2^62 it is kept at ±2^62 (far out
/// of Q16.16's range either way). `None` for NaN.
#[inline]
fn q16_bits_of_f64(value: f64) -> Option<i64> {
    let bits = value.to_bits();
    let negative = bits >> 63 != 0;
    let exponent = ((bits >> 52) & 0x7ff) as i32;
    if exponent == 0x7ff && bits & ((1 << 52) - 1) != 0 {
        return None;
    }
    // value = mantissa 2^(exponent - 1075); value 2^16 = mantissa 2^(exponent - 1059).
    let mantissa = if exponent == 0 {
        bits & ((1 << 52) - 1)
    } else {
        (bits & ((1 << 52) - 1)) | (1 << 52)
    };
    let shift = exponent.max(1) - 1059;
    let magnitude: u64 = if shift >= 10 {
        // 2^62 or more (infinities included).
        1 << 62
    } else if shift >= 0 {
        mantissa << shift
    } else if shift > -64 {
        let down = shift.unsigned_abs();
        let whole = mantissa >> down;
        let rest = mantissa & ((1u64 << down) - 1);
        let half = 1u64 << (down - 1);
        // Round half to even.
        if rest > half || (rest == half && whole & 1 == 1) {
            whole + 1
        } else {
            whole
        }
    } else {
        0
    };
    let magnitude = magnitude as i64;
    Some(if negative { -magnitude } else { magnitude })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fx(v: f64) -> I16F16 {
        I16F16::from_f64(v)
    }

    /// The sine with the Cortex-M0's 32-bit products equals it with `Mul`'s, bit for bit,
    /// on every step of [-64, 64] and on values out to the ends of the range (where the
    /// reduced argument is not small and `Mul` takes over).
    #[test]
    fn sine_in_words_equals_the_products() {
        let words =
            |a: I16F16, b: I16F16| I16F16::from_bits(mul_q16_small(a.to_bits(), b.to_bits()));
        let check = |bits: i32| {
            let x = I16F16::from_bits(bits);
            assert_eq!(
                super::super::sine(x, words),
                super::super::sine(x, |a, b| a * b),
                "{x:?}"
            );
        };
        (-(64 << 16)..=(64 << 16)).for_each(check);
        (0..=u16::MAX).for_each(|k| {
            let bits = (i32::from(k) << 15) ^ i32::from(k);
            check(bits);
            check(bits.wrapping_neg());
        });
        check(i32::MAX);
        check(i32::MIN);
    }

    /// The conversion on the bits equals the `fixed` crate's (round to nearest, ties to
    /// even, saturating or checked), at ties, at the ends of the range and anywhere.
    #[test]
    fn conversion_from_f64_matches_the_fixed_crate() {
        let check = |v: f64| {
            let ours = I16F16::from_f64(v);
            let theirs = if v.is_nan() {
                I16F16::ZERO
            } else {
                I16F16(Inner::saturating_from_num(v))
            };
            assert_eq!(ours, theirs, "{v:e}");
            let checked = if v.is_nan() {
                None
            } else {
                Inner::checked_from_num(v).map(I16F16)
            };
            assert_eq!(I16F16::from_f64_checked(v), checked, "{v:e}");
        };
        let step = 1.0 / 65536.0;
        for k in -70000i64..70000 {
            // Whole steps, and exact ties between steps (even and odd below).
            let at = k as f64 * step * 7.0;
            check(at);
            check(at + step / 2.0);
            check(at - step / 2.0);
            check(f64::from_bits(at.to_bits() + 1));
        }
        for v in [
            0.0,
            -0.0,
            32_767.999_992_370_605,
            32_767.999_996_185_3,
            32768.0,
            -32768.0,
            -32_768.000_007_629_4,
            -32_768.000_003_814_7,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            5e-324,
            -5e-324,
            1.5 * step,
            2.5 * step,
            -2.5 * step,
        ] {
            check(v);
        }
    }

    proptest! {
        #[test]
        fn conversion_from_any_f64_matches_the_fixed_crate(bits: u64) {
            let v = f64::from_bits(bits);
            let theirs = if v.is_nan() { I16F16::ZERO } else { I16F16(Inner::saturating_from_num(v)) };
            prop_assert_eq!(I16F16::from_f64(v), theirs);
            let scaled = v / 1e300 * 4e4;
            if !scaled.is_nan() {
                prop_assert_eq!(I16F16::from_f64(scaled), I16F16(Inner::saturating_from_num(scaled)));
                prop_assert_eq!(I16F16::from_f64_checked(scaled), Inner::checked_from_num(scaled).map(I16F16));
            }
        }
    }

    #[test]
    fn constants_and_conversions() {
        assert_eq!(I16F16::ONE.to_f64(), 1.0);
        assert_eq!(fx(0.5).to_bits(), 32768);
        assert_eq!(fx(1e9), I16F16::MAX);
        assert_eq!(fx(-1e9), I16F16::MIN);
        assert_eq!(I16F16::from_f64_checked(40000.0), None);
        assert_eq!(I16F16::from_f64_checked(-32768.0), Some(I16F16::MIN));
        assert_eq!(fx(f64::NAN), I16F16::ZERO);
    }

    #[test]
    fn division_by_zero_saturates() {
        assert_eq!(fx(3.0) / I16F16::ZERO, I16F16::MAX);
        assert_eq!(fx(-3.0) / I16F16::ZERO, I16F16::MIN);
        assert_eq!(I16F16::ZERO / I16F16::ZERO, I16F16::ZERO);
        assert_eq!(I16F16::MIN / fx(-1.0), I16F16::MAX);
        assert_eq!(-I16F16::MIN, I16F16::MAX);
    }

    #[test]
    fn square_roots_at_the_extremes() {
        assert_eq!(I16F16::MAX.sqrt().to_bits(), 11_863_283); // isqrt((2^31 - 1) << 16): 181.019

        assert_eq!(I16F16::from_bits(1).sqrt().to_bits(), 256);
        assert_eq!(fx(-4.0).sqrt(), I16F16::ZERO);
        assert_eq!(fx(2.0).sqrt().to_bits(), (2f64.sqrt() * 65536.0) as i32);
        // A vector of three maximal components: the length saturates instead of wrapping.
        let big = Vec3::new(I16F16::MAX, I16F16::MAX, I16F16::MIN);
        assert_eq!(big.length(), I16F16::MAX);
        assert_eq!(Vec3::new(fx(3.0), fx(4.0), fx(0.0)).length(), fx(5.0));
        // 3000^2 overflows Q16.16, the length of (3000, 4000, 0) does not.
        assert_eq!(
            Vec3::new(fx(3000.0), fx(4000.0), fx(0.0)).length(),
            fx(5000.0)
        );
    }

    #[test]
    fn reciprocals_at_the_extremes() {
        assert_eq!(fx(2.0).recip(), fx(0.5));
        assert_eq!(fx(-4.0).recip(), fx(-0.25));
        assert_eq!(I16F16::ZERO.recip(), I16F16::MAX);
        assert_eq!(I16F16::from_bits(1).recip(), I16F16::MAX);
        assert_eq!(I16F16::MAX.recip().to_bits(), 2);
        assert_eq!(I16F16::MIN.recip().to_bits(), -2);
        assert_eq!(fx(3.0).recip().to_bits(), 65536 / 3);
    }

    #[test]
    fn bytes_match_the_f64_conversion() {
        // Every value from below 0 to above 1, and the ends of the range.
        for bits in (-70_000..=140_000).chain([i32::MAX, i32::MAX - 1, i32::MIN]) {
            let v = I16F16::from_bits(bits);
            assert_eq!(v.to_byte(), v.to_f64().to_byte(), "{bits}");
        }
    }

    #[test]
    fn powers_match_f64_within_the_stated_bound() {
        let mut worst_steps: f64 = 0.0;
        for i in 1..=2000 {
            let x = fx(i as f64 / 2000.0);
            for e in [1.0, 2.0, 7.5, 50.0, 200.0, 250.0] {
                let got = x.pow_positive(fx(e)).to_f64();
                let want = x.to_f64().powf(e);
                let error = (got - want).abs();
                assert!(
                    error <= 2f64.powi(-16) + want * 2f64.powi(-20),
                    "{x:?}^{e}: {got} vs {want}"
                );
                worst_steps = worst_steps.max(error * 65536.0);
            }
        }
        // Measured: 0.764 of a step of 2^-16 at worst over these 12,000 cases.
        assert!(worst_steps <= 0.8, "worst error {worst_steps} steps");
        assert_eq!(fx(-0.5).pow_positive(fx(2.0)), I16F16::ZERO);
        assert_eq!(fx(2.0).pow_positive(fx(20.0)), I16F16::MAX);
    }

    #[test]
    fn shortest_text_reads_back() {
        for v in [
            0.0,
            1.0,
            -6.93,
            0.1,
            2.121,
            32767.99998,
            -32768.0,
            1.0 / 65536.0,
        ] {
            let mut s = std::string::String::new();
            fx(v).write_shortest(&mut s).unwrap();
            let back = fx(crate::decimal::parse_number(s.as_bytes()).unwrap());
            assert_eq!(back, fx(v), "{v} printed as {s}");
        }
        let mut s = std::string::String::new();
        fx(-6.93).write_shortest(&mut s).unwrap();
        assert_eq!(s, "-6.93");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(100_000))]

        #[test]
        fn multiply_and_divide_match_the_fixed_crate(a: i32, b: i32) {
            let (x, y) = (I16F16::from_bits(a), I16F16::from_bits(b));
            prop_assert_eq!((x * y).0, x.0.saturating_mul(y.0));
            if b != 0 {
                prop_assert_eq!((x / y).0, x.0.saturating_div(y.0));
            }
            prop_assert_eq!((x + y).0, x.0.saturating_add(y.0));
            prop_assert_eq!((x - y).0, x.0.saturating_sub(y.0));
        }

        #[test]
        fn dots_with_axis_normals_equal_the_general_ones(v: [i32; 3], axis in 0usize..3, negative: bool, other: [i32; 3]) {
            let v = Vec3::new(I16F16::from_bits(v[0]), I16F16::from_bits(v[1]), I16F16::from_bits(v[2]));
            let mut n = [0i32; 3];
            n[axis] = if negative { -(1 << FRAC) } else { 1 << FRAC };
            let n = Vec3::new(I16F16::from_bits(n[0]), I16F16::from_bits(n[1]), I16F16::from_bits(n[2]));
            prop_assert_eq!(dot_along_axis(v, n), I16F16::dot(v, n));
            prop_assert_eq!(positive_dot_along_axis(v, n), I16F16::positive_dot(v, n));
            // Not along an axis: the general products.
            let m = Vec3::new(I16F16::from_bits(other[0]), I16F16::from_bits(other[1] | 1), I16F16::from_bits(other[2] | 1));
            prop_assert_eq!(dot_along_axis(v, m), I16F16::dot(v, m));
            prop_assert_eq!(positive_dot_along_axis(v, m), I16F16::positive_dot(v, m));
            let general = |d: Vec3<I16F16>, n: Vec3<I16F16>| d - n * (I16F16::TWO * I16F16::dot(d, n));
            prop_assert_eq!(reflect_along_axis(v, n), general(v, n));
            prop_assert_eq!(reflect_along_axis(v, m), general(v, m));
            let extreme = Vec3::new(I16F16::MIN, I16F16::MIN, I16F16::MIN);
            prop_assert_eq!(dot_along_axis(extreme, n), I16F16::dot(extreme, n));
            prop_assert_eq!(positive_dot_along_axis(extreme, n), I16F16::positive_dot(extreme, n));
            prop_assert_eq!(reflect_along_axis(extreme, n), general(extreme, n));
        }

        #[test]
        fn dot_and_length_are_within_one_step_of_exact(v in prop::array::uniform6(-(1i32 << 24)..(1 << 24))) {
            let a = Vec3::new(I16F16::from_bits(v[0]), I16F16::from_bits(v[1]), I16F16::from_bits(v[2]));
            let b = Vec3::new(I16F16::from_bits(v[3]), I16F16::from_bits(v[4]), I16F16::from_bits(v[5]));
            let exact = a.to_f64().dot(b.to_f64());
            let dot = a.dot(b).to_f64();
            if exact.abs() < 32767.0 {
                // One truncation toward -inf: at most one step below.
                prop_assert!(dot <= exact && exact - dot < 1.0 / 65536.0, "{} vs {}", dot, exact);
            }
            let length = a.length().to_f64();
            let exact = a.to_f64().dot(a.to_f64()).sqrt();
            if exact < 32767.0 {
                prop_assert!(length <= exact && exact - length < 1.0 / 65536.0, "{} vs {}", length, exact);
            }
        }

        #[test]
        fn vector_division_equals_three_divisions(x: i32, y: i32, z: i32, d: i32) {
            let (vx, vy, vz, vd) =
                (I16F16::from_bits(x), I16F16::from_bits(y), I16F16::from_bits(z), I16F16::from_bits(d));
            let q = Vec3::new(vx, vy, vz) / vd;
            prop_assert_eq!(q, Vec3::new(vx / vd, vy / vd, vz / vd));
            if d != 0 {
                prop_assert_eq!(q.x.0, vx.0.saturating_div(vd.0));
            }
        }

        #[test]
        fn pixel_ratios_are_exact(bits: i32, numerator: u16, denominator in 1u16..) {
            let got = I16F16::from_bits(bits).mul_ratio(numerator, denominator).to_bits();
            let exact = i64::from(bits) * i64::from(numerator) / i64::from(denominator);
            prop_assert_eq!(i64::from(got), exact.clamp(i64::from(i32::MIN), i64::from(i32::MAX)));
        }

        #[test]
        fn sqrt_is_the_floor_of_the_exact_root(bits in 0i32..) {
            let root = I16F16::from_bits(bits).sqrt().to_f64();
            let exact = (f64::from(bits) / 65536.0).sqrt();
            prop_assert!(root <= exact && exact - root < 1.0 / 65536.0);
        }
    }
}
