//! 32x32 -> 64-bit arithmetic for the fixed-point type, written for Cortex-M0.
//!
//! ARMv6-M has a 32x32 -> 32 multiply and nothing wider, no divide and no CLZ: Rust's `i64`
//! products become calls to a general 64x64 multiply (`__aeabi_lmul`) and divisions a
//! software 64-bit divide of 300 instructions and more. Here products are built from four
//! 16x16 multiplies, and division and square root from a table and Newton's method
//! (multiplies only), corrected to the exact result. Elsewhere (Cortex-M4, RISC-V with M,
//! hosts) the plain 64-bit forms compile to one or two instructions and are used instead;
//! where there is a float unit (Cortex-M4F, hosts), its square root and quotient start the
//! exact ones, which exact products then correct ([`FLOAT_GUESSES`]): the same results.

/// Whether this target lacks a 32x32 -> 64 multiply (ARMv6-M: also the only Arm profile
/// without compare-and-swap atomics, which is how `cfg` can tell).
#[cfg(all(target_arch = "arm", not(target_has_atomic = "32")))]
const HALVES: bool = true;
#[cfg(not(all(target_arch = "arm", not(target_has_atomic = "32"))))]
const HALVES: bool = false;

/// Whether the exact division's and the integer square root's first Newton steps run in
/// 32-bit products: on ARMv6-M, unless built for size (the steps are code of their own; the
/// 64-bit products are one routine shared with everything else).
const STEPS_IN_WORDS: bool = HALVES && !cfg!(microray_small);

/// The full product of two `u32`.
#[inline]
pub(crate) fn mul_u32(a: u32, b: u32) -> u64 {
    if HALVES {
        mul_u32_halves(a, b)
    } else {
        u64::from(a) * u64::from(b)
    }
}

/// [`mul_u32`] from four 16x16 products.
#[inline]
fn mul_u32_halves(a: u32, b: u32) -> u64 {
    let (al, ah) = (a & 0xffff, a >> 16);
    let (bl, bh) = (b & 0xffff, b >> 16);
    // Each partial product is below 2^32.
    let middle = u64::from(al * bh) + u64::from(ah * bl);
    (u64::from(ah * bh) << 32) + (middle << 16) + u64::from(al * bl)
}

/// The full product of two `i32`.
#[inline]
pub(crate) fn mul_i32(a: i32, b: i32) -> i64 {
    if HALVES {
        mul_i32_halves(a, b)
    } else {
        i64::from(a) * i64::from(b)
    }
}

/// [`mul_i32`] from four 16x16 products.
#[inline]
fn mul_i32_halves(a: i32, b: i32) -> i64 {
    // a = ah 2^16 + al with ah signed, al in 0..2^16: every partial product fits 32 bits.
    let (al, ah) = (a & 0xffff, a >> 16);
    let (bl, bh) = (b & 0xffff, b >> 16);
    let middle = i64::from(ah * bl) + i64::from(al * bh);
    let low = (al as u32) * (bl as u32);
    (i64::from(ah * bh) << 32) + (middle << 16) + i64::from(low)
}

/// `v >> s` for any `s` (0 from 64 on), without a call to a 64-bit shift routine.
#[inline]
pub(crate) fn shr_u64(v: u64, s: u32) -> u64 {
    if HALVES {
        shr_u64_halves(v, s)
    } else {
        v.checked_shr(s).unwrap_or(0)
    }
}

/// [`shr_u64`] on 32-bit halves.
#[inline]
fn shr_u64_halves(v: u64, s: u32) -> u64 {
    let (low, high) = (v as u32, (v >> 32) as u32);
    match s {
        0 => v,
        1..=31 => (u64::from(high >> s) << 32) | u64::from((low >> s) | (high << (32 - s))),
        _ => u64::from(high.checked_shr(s - 32).unwrap_or(0)),
    }
}

/// `v << s` for any `s` (0 from 64 on), without a call to a 64-bit shift routine.
#[inline]
fn shl_u64(v: u64, s: u32) -> u64 {
    if HALVES {
        shl_u64_halves(v, s)
    } else {
        v.checked_shl(s).unwrap_or(0)
    }
}

/// [`shl_u64`] on 32-bit halves (0 from 64 on).
#[inline]
fn shl_u64_halves(v: u64, s: u32) -> u64 {
    let (low, high) = (v as u32, (v >> 32) as u32);
    match s {
        0 => v,
        1..=31 => (u64::from((high << s) | (low >> (32 - s))) << 32) | u64::from(low << s),
        32..=63 => u64::from(low << (s - 32)) << 32,
        _ => 0,
    }
}

/// Leading zeros of a `u32`: ARMv6-M has no CLZ, and `u32::leading_zeros` becomes a call
/// to a general routine; two comparisons and a table of bytes are shorter.
#[inline]
pub(crate) fn leading_zeros(v: u32) -> u32 {
    if HALVES {
        leading_zeros_table(v)
    } else {
        v.leading_zeros()
    }
}

/// Leading zeros of each byte value `2k` and `2k + 1` (the same but for `k = 0`: 8 for 0,
/// 7 for 1), by `k`: half the bytes of a table by byte value, read at the same cost (the
/// index is the byte shifted one more place). (Indexing in a constant cannot fail at run
/// time: a bad index would not compile.)
#[allow(clippy::indexing_slicing)]
const PAIR_LEADING_ZEROS: [u8; 128] = {
    let mut table = [0u8; 128];
    let mut k = 0;
    while k < 128 {
        table[k] = ((2 * k + 1) as u8).leading_zeros() as u8;
        k += 1;
    }
    table
};

/// [`leading_zeros`] from the byte that holds the top set bit: two comparisons and a look-up
/// of its top seven bits (its lowest bit matters only for the byte 1, whose pair is 0's).
#[inline]
fn leading_zeros_table(v: u32) -> u32 {
    let (skipped, pair) = if v >> 16 != 0 {
        if v >> 24 != 0 {
            (0, v >> 25)
        } else {
            (8, (v >> 17) & 0x7f)
        }
    } else if v >> 8 != 0 {
        (16, (v >> 9) & 0x7f)
    } else if v != 0 {
        (24, (v >> 1) & 0x7f)
    } else {
        return 32;
    };
    skipped + u32::from(PAIR_LEADING_ZEROS.get(pair as usize).copied().unwrap_or(8))
}

/// Leading zeros of a non-zero `u64`.
#[inline]
fn leading_zeros_u64(v: u64) -> u32 {
    let high = (v >> 32) as u32;
    if high != 0 {
        leading_zeros(high)
    } else {
        32 + leading_zeros(v as u32)
    }
}

/// Whether every one of these Q16.16 raw values is below 2^(16 + bits) in magnitude:
/// `bits = 7` (128) for a product, 6 (64) for the three of a dot product.
#[inline]
pub(crate) fn all_below(values: &[i32], bits: u32) -> bool {
    let bound = 1u32 << (16 + bits);
    // x + bound < 2 bound exactly when -bound <= x < bound.
    let mut any = 0u32;
    for &v in values {
        any |= (v as u32).wrapping_add(bound);
    }
    any < 2 * bound
}

/// `floor(a b / 2^16)` for `|a|, |b| < 2^23` (128 in Q16.16) in 32-bit arithmetic: with
/// `a = ah 2^16 + al`, it is `ah bh 2^16 + ah bl + al bh + floor(al bl / 2^16)`, below 2^31.
#[inline]
pub(crate) fn mul_q16_small(a: i32, b: i32) -> i32 {
    let (al, ah) = (a & 0xffff, a >> 16);
    let (bl, bh) = (b & 0xffff, b >> 16);
    let low = ((al as u32) * (bl as u32)) >> 16;
    ((ah * bh) << 16) + ah * bl + al * bh + low as i32
}

/// `floor(sum of a_i b_i / 2^16)` for three pairs below 2^22 (64 in Q16.16) in 32-bit
/// arithmetic: the high and middle parts summed as they are, the low products' high and
/// low halves apart, so that the one truncation is of the exact sum.
#[inline]
pub(crate) fn dot_q16_small(a: [i32; 3], b: [i32; 3]) -> i32 {
    let mut whole = 0i32;
    let mut high = 0u32;
    let mut low = 0u32;
    for (&x, &y) in a.iter().zip(&b) {
        let (xl, xh) = (x & 0xffff, x >> 16);
        let (yl, yh) = (y & 0xffff, y >> 16);
        whole += ((xh * yh) << 16) + xh * yl + xl * yh;
        let product = (xl as u32) * (yl as u32);
        high += product >> 16;
        low += product & 0xffff;
    }
    whole + (high + (low >> 16)) as i32
}

/// The exact sum of three products `a_i b_i`, for values below 2^22, without a 64-bit
/// multiply: the high and middle parts in 32 bits, the low products in 64.
#[inline]
pub(crate) fn dot_i64_small(a: [i32; 3], b: [i32; 3]) -> i64 {
    let mut high = 0i32;
    let mut middle = 0i32;
    let mut low = 0u64;
    for (&x, &y) in a.iter().zip(&b) {
        let (xl, xh) = (x & 0xffff, x >> 16);
        let (yl, yh) = (y & 0xffff, y >> 16);
        high += xh * yh;
        middle += xh * yl + xl * yh;
        low += u64::from((xl as u32) * (yl as u32));
    }
    (i64::from(high) << 32) + (i64::from(middle) << 16) + low as i64
}

/// Whether the 64-bit arithmetic above is done in halves (ARMv6-M).
pub(crate) const fn in_halves() -> bool {
    HALVES
}

/// `2^63 / m` to 8 bits for `m = (128 + i + 1/2) 2^24`, `i` the table index: the first
/// guess of the reciprocal. (Indexing in a constant cannot fail at run time: a bad index
/// would not compile.)
#[allow(clippy::indexing_slicing)]
const RECIPROCALS: [u32; 128] = {
    let mut table = [0u32; 128];
    let mut i = 0;
    while i < 128 {
        let middle = (256 + 2 * i as u64 + 1) << 23;
        table[i] = ((1u64 << 63) / middle) as u32;
        i += 1;
    }
    table
};

/// The table's first guess for `n` in `[2^31, 2^32)`.
#[inline]
fn first_reciprocal(n: u32) -> u32 {
    RECIPROCALS
        .get(((n >> 24) & 0x7f) as usize)
        .copied()
        .unwrap_or(u32::MAX)
}

/// One Newton step `y (2 - n y / 2^63)` towards `2^63 / n` in 64-bit products.
#[inline]
fn newton_reciprocal(n: u32, y: u32) -> u32 {
    // e = 2^64 - n y, about 2^63; y (e / 2^63) from its top 32 bits.
    let e = mul_u32(n, y).wrapping_neg();
    u32::try_from(mul_u32(y, (e >> 32) as u32) >> 31).unwrap_or(u32::MAX)
}

/// About `2^63 / n` for `n` in `[2^31, 2^32)`, within 2^-22 relative (every `n` checked),
/// from 32-bit products only (one multiply each on ARMv6-M, against four for a 64-bit
/// one): the table's guess `y`, its top 16 bits (error `e` up to 2^-8), times
/// `1 + e + e^2`, which leaves `e^3`; `e = 1 - n y / 2^63` is exact to 2^-23 from two
/// 16x16 products.
// Out of line: in line, it grew the frames of the division's callers (stack).
#[inline(never)]
fn reciprocal_in_words(n: u32) -> u32 {
    let b = first_reciprocal(n) >> 16;
    // n b = high 2^16 + low, about 2^47; its top 24 bits (high is about 2^31: no carry).
    let (high, low) = ((n >> 16) * b, (n & 0xffff) * b);
    let top = high.wrapping_add(low >> 16) >> 8;
    // e 2^23, |e| below 2^-7.9: below 2^15.1 in magnitude.
    let e = (1i32 << 23) - top as i32;
    // y e = b e / 2^7 and y e^2 = b e^2 / 2^30, with b halved to keep b e in 31 bits.
    let half_b_e = (b >> 1) as i32 * e;
    let correction = (half_b_e >> 6) + (((half_b_e >> 15) * e) >> 14);
    u32::try_from(i64::from(b << 16) + i64::from(correction)).unwrap_or(u32::MAX)
}

/// About `2^63 / n` for `n` in `[2^31, 2^32)`, within 2^-28 relative: the table, then two
/// Newton steps; on ARMv6-M (built for speed) the first in 32-bit products ([`reciprocal_in_words`]), where a
/// 64-bit product costs four multiplies (the divisions it serves are exact either way).
#[inline]
fn reciprocal_estimate(n: u32) -> u32 {
    let y = if STEPS_IN_WORDS {
        reciprocal_in_words(n)
    } else {
        newton_reciprocal(n, first_reciprocal(n))
    };
    newton_reciprocal(n, y)
}

/// About `2^63 / n` for `n` in `[2^31, 2^32)` to 2^-16 relative: the table and one Newton
/// step, for wide numbers (the shading needs about 16 bits, not the exact division's 31).
#[inline]
fn reciprocal_rough(n: u32) -> u32 {
    newton_reciprocal(n, first_reciprocal(n))
}

/// A divisor prepared for division: its magnitude, normalised, and its reciprocal.
#[derive(Clone, Copy)]
pub(crate) struct Divisor {
    magnitude: u32,
    zeros: u32,
    reciprocal: u32,
}

impl Divisor {
    /// `None` for zero.
    #[inline]
    pub(crate) fn new(magnitude: u32) -> Option<Self> {
        if magnitude == 0 {
            return None;
        }
        let zeros = leading_zeros(magnitude);
        Some(Self {
            magnitude,
            zeros,
            reciprocal: reciprocal_estimate(magnitude << zeros),
        })
    }

    /// `floor(x 2^16 / magnitude)`, or `None` when it is 2^31 or more: the division of a
    /// Q16.16 number, with one product for the estimate (the numerator's low 16 bits are 0).
    #[inline]
    pub(crate) fn divide_q16(&self, x: u32) -> Option<u32> {
        // x 2^16 / m = x 2^16 2^zeros r / 2^63 = (x r) >> (47 - zeros), zeros in 0..=31.
        let estimate = shr_u64(mul_u32(x, self.reciprocal), 47 - self.zeros);
        self.correct(estimate, u64::from(x) << 16)
    }

    /// `floor(numerator / magnitude)` for a 48-bit `numerator`, or `None` when the quotient
    /// is 2^31 or more: the estimate `numerator * 2^zeros * r / 2^63`, then corrected by
    /// the remainder, so the result is exact.
    #[inline]
    pub(crate) fn divide(&self, numerator: u64) -> Option<u32> {
        // numerator < 2^48 and r < 2^32: split the numerator to keep products in 64 bits.
        let high = (numerator >> 16) as u32;
        let low = (numerator & 0xffff) as u32;
        let product = mul_u32(high, self.reciprocal) + (mul_u32(low, self.reciprocal) >> 16);
        let estimate = shr_u64(product, 47 - self.zeros);
        self.correct(estimate, numerator)
    }

    /// The exact quotient from an estimate within a few units of it.
    #[inline]
    fn correct(&self, estimate: u64, numerator: u64) -> Option<u32> {
        // Above the range by more than the estimate's error (a few units near 2^31, where
        // the reciprocal's 2^-30 matters): the caller saturates.
        if estimate >= (1 << 31) + 4096 {
            return None;
        }
        let q = corrected_quotient(estimate as u32, numerator, self.magnitude);
        (q < 1 << 31).then_some(q)
    }
}

/// `floor(numerator / magnitude)` (`magnitude` above 0) from an estimate a few units from
/// it, by exact products.
#[inline(always)]
fn corrected_quotient(estimate: u32, numerator: u64, magnitude: u32) -> u32 {
    let mut q = estimate;
    let mut back = mul_u32(q, magnitude);
    while back > numerator {
        q = q.wrapping_sub(1);
        back -= u64::from(magnitude);
    }
    while numerator - back >= u64::from(magnitude) {
        q = q.wrapping_add(1);
        back += u64::from(magnitude);
    }
    q
}

/// `2^16 / magnitude` in `f32`, for [`float_quotient_q16`] (`None` for 0): with a float
/// unit (see [`FLOAT_GUESSES`]), one division instead of the exact reciprocal's table and
/// Newton steps.
#[inline(always)]
pub(crate) fn float_scale_q16(magnitude: u32) -> Option<f32> {
    (magnitude != 0).then(|| 65_536.0 / magnitude as f32)
}

/// `floor(x 2^16 / magnitude)` from `scale` ([`float_scale_q16`] of `magnitude`), where
/// the quotient is below `2^22`; `None` where it may not be (the caller divides exactly).
/// Exact: `x scale` is within four roundings of `2^-24` of the quotient, a quarter of a
/// unit below `2^22`, so the truncated estimate is within one unit, which the exact
/// products correct.
#[inline(always)]
pub(crate) fn float_quotient_q16(x: u32, magnitude: u32, scale: f32) -> Option<u32> {
    let estimate = (x as f32 * scale) as u32;
    (estimate < 1 << 22).then(|| corrected_quotient(estimate, u64::from(x) << 16, magnitude))
}

/// The top 32 bits of a non-zero `u64` shifted left until its top bit is set, and the
/// shift: `(top, zeros)` with `v << zeros = top 2^32 + ...`.
#[inline]
fn normalise_u64(v: u64) -> (u32, u32) {
    let (high, low) = ((v >> 32) as u32, v as u32);
    if high != 0 {
        let zeros = leading_zeros(high);
        // zeros < 32: the low word's top `zeros` bits move up.
        let top = if zeros == 0 {
            high
        } else {
            (high << zeros) | (low >> (32 - zeros))
        };
        (top, zeros)
    } else {
        let zeros = leading_zeros(low);
        (low << zeros, 32 + zeros)
    }
}

/// A positive number `mantissa 2^exponent` with a 32-bit mantissa whose top bit is set (or
/// zero): the shading's intermediate products and quotients in fixed point, whose range
/// (distances squared times distances) Q16.16 does not have. Every operation truncates to
/// 32 significant bits (a relative error below 2^-31), the reciprocal to 2^-16.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Wide {
    mantissa: u32,
    exponent: i32,
}

impl Wide {
    const ZERO: Self = Self {
        mantissa: 0,
        exponent: 0,
    };

    /// `value 2^exponent`.
    #[inline]
    pub(crate) fn from_u64(value: u64, exponent: i32) -> Self {
        if value == 0 {
            return Self::ZERO;
        }
        let (mantissa, zeros) = normalise_u64(value);
        Self {
            mantissa,
            exponent: exponent.saturating_add(32 - zeros as i32),
        }
    }

    /// The product.
    #[inline]
    pub(crate) fn mul(self, other: Self) -> Self {
        if self.mantissa == 0 || other.mantissa == 0 {
            return Self::ZERO;
        }
        // Both mantissas are in [2^31, 2^32): the product is in [2^62, 2^64).
        let product = mul_u32(self.mantissa, other.mantissa);
        let exponent = self.exponent.saturating_add(other.exponent);
        if product >> 63 != 0 {
            Self {
                mantissa: (product >> 32) as u32,
                exponent: exponent.saturating_add(32),
            }
        } else {
            Self {
                mantissa: (product >> 31) as u32,
                exponent: exponent.saturating_add(31),
            }
        }
    }

    /// The next number above (for bounds from above: every operation truncates, so a
    /// result one step up is at least the exact value).
    #[inline]
    pub(crate) fn up(self) -> Self {
        match self.mantissa.checked_add(1) {
            _ if self.mantissa == 0 => self,
            Some(mantissa) => Self { mantissa, ..self },
            None => Self {
                mantissa: 1 << 31,
                exponent: self.exponent.saturating_add(1),
            },
        }
    }

    /// Whether `self >= other`.
    #[inline]
    pub(crate) fn at_least(self, other: Self) -> bool {
        if other.mantissa == 0 {
            return true;
        }
        self.mantissa != 0 && (self.exponent, self.mantissa) >= (other.exponent, other.mantissa)
    }

    /// The reciprocal (of zero: the largest value there is).
    #[inline]
    pub(crate) fn recip(self) -> Self {
        if self.mantissa == 0 {
            return Self {
                mantissa: u32::MAX,
                exponent: i32::MAX / 2,
            };
        }
        // 1 / (m 2^e) = (2^63 / m) 2^(-63 - e); the estimate of 2^63 / m is in [2^31, 2^32).
        let estimate = reciprocal_rough(self.mantissa).max(1 << 31);
        Self {
            mantissa: estimate,
            exponent: (-63i32).saturating_sub(self.exponent),
        }
    }

    /// `bits 2^-16 * self` in Q16.16 raw bits: `bits m 2^e`, rounded to nearest (so that
    /// the shading's last step adds no bias to the truncations before it) and saturated.
    #[inline]
    pub(crate) fn scale_bits(self, bits: i32) -> i32 {
        let magnitude = bits.unsigned_abs();
        if magnitude == 0 || self.mantissa == 0 {
            return 0;
        }
        // |bits| m is at least 2^31: with e >= 0 it saturates.
        let saturated = if bits < 0 { i32::MIN } else { i32::MAX };
        if self.exponent >= 0 {
            return saturated;
        }
        let product = mul_u32(magnitude, self.mantissa);
        let shift = self.exponent.unsigned_abs();
        if shift >= 64 {
            // Below half a step of the result.
            return 0;
        }
        let value = if shift > 32 {
            // Half a unit of the result is in the high word: no 64-bit shift needed (the
            // product is below 2^63, so its high word below 2^31, and the sum below 2^32).
            let high = (product >> 32) as u32;
            (high + (1 << (shift - 33))) >> (shift - 32)
        } else {
            // Half a unit of the result, added before the shift (the product is below 2^63);
            // below 2^32, so a 32-bit shift (a 64-bit one is a call on ARMv6-M).
            let half = u64::from(1u32 << (shift - 1));
            match u32::try_from(shr_u64(product + half, shift)) {
                Ok(v) => v,
                Err(_) => return saturated,
            }
        };
        match i32::try_from(value) {
            Ok(v) if bits < 0 => -v,
            Ok(v) => v,
            Err(_) => saturated,
        }
    }

    /// [`scale_bits`](Self::scale_bits) of three values by the same number, with the
    /// checks and the shift worked out once (the same results: a colour times a quotient).
    #[inline]
    pub(crate) fn scale_bits3(self, bits: [i32; 3]) -> [i32; 3] {
        if self.mantissa == 0 {
            return [0; 3];
        }
        if self.exponent >= 0 {
            return bits.map(|b| match b {
                0 => 0,
                b if b < 0 => i32::MIN,
                _ => i32::MAX,
            });
        }
        let shift = self.exponent.unsigned_abs();
        if shift >= 64 {
            return [0; 3];
        }
        let m = self.mantissa;
        let signed = |bits: i32, value: u32| match i32::try_from(value) {
            Ok(v) if bits < 0 => -v,
            Ok(v) => v,
            Err(_) if bits < 0 => i32::MIN,
            Err(_) => i32::MAX,
        };
        if shift > 32 {
            // As in `scale_bits`: half a unit of the result is in the high word.
            let (half, down) = (1u32 << (shift - 33), shift - 32);
            bits.map(|b| {
                let high = (mul_u32(b.unsigned_abs(), m) >> 32) as u32;
                signed(b, (high + half) >> down)
            })
        } else {
            let half = 1u64 << (shift - 1);
            bits.map(|b| {
                let product = mul_u32(b.unsigned_abs(), m);
                match u32::try_from(shr_u64(product + half, shift)) {
                    Ok(v) => signed(b, v),
                    Err(_) if b < 0 => i32::MIN,
                    Err(_) => i32::MAX,
                }
            })
        }
    }

    /// The value as an `f64` (tests and reports).
    pub fn to_f64(self) -> f64 {
        libm::ldexp(f64::from(self.mantissa), self.exponent)
    }
}

/// `1 / sqrt(x)` for `x = (64 + i + 1/2) / 256` in Q2.30, its low 15 bits dropped: the first
/// guess of the reciprocal square root, `i` the table index (`x` in `[1/4, 1)`). Eight bits
/// are all a first guess has, so 16 stored do (half the flash of 32: 384 bytes).
#[allow(clippy::indexing_slicing)]
const RECIPROCAL_ROOTS: [u16; 192] = {
    let mut table = [0u16; 192];
    let mut i = 0;
    while i < 192 {
        // y = sqrt(512 / (128 + 2i + 1)) 2^30, by bisection on y^2 (x + 1/512 ... ) in integers.
        let denominator = 128 + 2 * i as u64 + 1; // x = denominator / 512
        // Largest y with y^2 * denominator <= 512 * 2^60.
        let target = 512u128 << 60;
        let (mut low, mut high) = (1u64 << 30, 1u64 << 31);
        while low < high {
            let middle = (low + high).div_ceil(2);
            if (middle as u128) * (middle as u128) * (denominator as u128) <= target {
                low = middle;
            } else {
                high = middle - 1;
            }
        }
        table[i] = (low >> 15) as u16;
        i += 1;
    }
    table
};

/// `floor(sqrt(n))`, exact: with a float unit, from its square root (see
/// [`FLOAT_GUESSES`]); else, or where that guess is too far, a table and two Newton steps
/// of the reciprocal square root (multiplies only; on ARMv6-M, built for speed, the first
/// in 32-bit products), then corrected with exact squares. The host takes both ways, so
/// the tests try both. Out of line on ARMv6-M built for speed: in line there, its registers
/// grew the row loops' frames (stack).
#[cfg_attr(
    all(
        target_arch = "arm",
        not(target_has_atomic = "32"),
        not(microray_small)
    ),
    inline(never)
)]
#[cfg_attr(
    not(all(
        target_arch = "arm",
        not(target_has_atomic = "32"),
        not(microray_small)
    )),
    inline
)]
pub(crate) fn isqrt(n: u64) -> u32 {
    if FLOAT_GUESSES && let Some(root) = root_near(n, float_root_guess(n)) {
        return root;
    }
    isqrt_by(n, STEPS_IN_WORDS)
}

/// Whether the target's float unit starts fixed point's integer square roots and divisions.
/// Its `sqrt` of `n` as an `f32` is within `2^-23` of the root and a unit (two roundings of
/// `2^-24` in `n`, halved by the root, one in the root, and the truncation): a unit or two
/// below `2^22`, within [`RowRoots::STEPS`] below `2^25`, where the steps of [`root_near`]
/// make it exact (a guess they do not reach falls back to the table). Its quotients, see
/// [`float_quotient_q16`]. `VSQRT` and the conversions take about a third of the table's
/// instructions (`VSQRT` and `VDIV` take 14 cycles each on a Cortex-M4F).
pub(crate) const FLOAT_GUESSES: bool = super::HARD_FLOAT;

/// `sqrt(n)` in `f32`, truncated (saturated beyond `u32`): see [`FLOAT_GUESSES`].
#[inline(always)]
fn float_root_guess(n: u64) -> u32 {
    let (high, low) = ((n >> 32) as u32, n as u32);
    // `high` below 2^24 is exact, and its scaling by 2^32 too: one rounding each for `low`
    // and the sum.
    let x = high as f32 * 4_294_967_296.0 + low as f32;
    super::sqrtf(x) as u32
}

/// [`isqrt`], its first step in 32-bit products or not (the result is the same).
#[inline(always)]
fn isqrt_by(n: u64, in_words: bool) -> u32 {
    if n == 0 {
        return 0;
    }
    // n = m / 2^(2k), m in [2^62, 2^64); x = m / 2^64 in [1/4, 1).
    let k = leading_zeros_u64(n) / 2;
    // 2 k is below 64. Built for size, the routine's call (code shared with the rest) takes
    // less flash than the shift in halves.
    let m = if cfg!(microray_small) {
        n << (2 * k)
    } else {
        shl_u64(n, 2 * k)
    };
    let h = (m >> 32) as u32;
    let top = RECIPROCAL_ROOTS
        .get(((h >> 24) as usize).saturating_sub(64))
        .map_or(1 << 15, |&top| u32::from(top));
    let y = if in_words {
        root_step_in_words(h, top)
    } else {
        root_step(h, top << 15)
    };
    let y = root_step(h, y);
    // sqrt(x) 2^32 = x y 2^32, then undo the normalisation.
    let root = u32::try_from(mul_u32(h, y) >> 30).unwrap_or(u32::MAX);
    let mut s = root >> k;
    // Built for size, each check squares (the 64-bit product is a routine shared with
    // everything else; the steps below are code of their own).
    if cfg!(microray_small) {
        while s > 0 && mul_u32(s, s) > n {
            s -= 1;
        }
        while s < u32::MAX && mul_u32(s + 1, s + 1) <= n {
            s += 1;
        }
        return s;
    }
    // One exact square, then steps by its differences: (s - 1)^2 = s^2 - (2s - 1) and
    // (s + 1)^2 = s^2 + 2s + 1 (a product less than squaring in each check).
    let mut square = mul_u32(s, s);
    // Above n: s is not 0 (0^2 is not above n).
    while square > n {
        square -= (u64::from(s) << 1) - 1;
        s -= 1;
    }
    // s^2 <= n from here on; (s + 1)^2 <= n while n - s^2 >= 2s + 1.
    while s < u32::MAX && n - square > u64::from(s) << 1 {
        square += (u64::from(s) << 1) + 1;
        s += 1;
    }
    s
}

/// The square roots of a row's primary rays' squared lengths, each found from the last
/// three ([`Scalar::row_length`](crate::scalar::Scalar::row_length) in fixed point): the
/// root is the exact `floor(sqrt(n))` either way, so the lengths are the integer square
/// root's bit for bit at a fraction of its cost.
///
/// Along a row the squared length `x^2 + dy^2 + dz^2` changes smoothly with the pixel, so
/// its root's third difference is far below one step: the roots' quadratic extrapolation
/// `3 r1 - 3 r2 + r3` is within a few units of the next (their floors' errors, times 7 at
/// most), and a few steps by differences of squares reach it exactly.
#[derive(Clone, Copy, Debug, Default)]
pub struct RowRoots {
    /// The last three roots, the latest first.
    last: [u32; 3],
    /// How many of them there are (up to three).
    known: u8,
}

impl RowRoots {
    /// The most steps from the extrapolation before [`isqrt`] is asked instead.
    const STEPS: u32 = 8;

    /// `floor(sqrt(n))`, for the next ray of the row.
    #[inline]
    pub(crate) fn next(&mut self, n: u64) -> u32 {
        let [r1, r2, r3] = self.last;
        // Wrapping: a guess out of range only misses (and `isqrt` answers).
        let guess = r3.wrapping_add(3u32.wrapping_mul(r1.wrapping_sub(r2)));
        let near = if self.known >= 3 {
            root_near(n, guess)
        } else {
            None
        };
        let root = near.unwrap_or_else(|| isqrt(n));
        self.last = [root, r1, r2];
        // A guess too far (a kink, a coarse row): three more roots before the next guess,
        // so that such a row pays for `isqrt` and the steps on a quarter of its rays.
        self.known = if near.is_some() || self.known < 3 {
            self.known.saturating_add(1)
        } else {
            0
        };
        root
    }
}

/// `floor(sqrt(n))` from a guess within [`RowRoots::STEPS`] of it: `s` is the root when
/// `0 <= n - s^2 <= 2 s`, and each step moves `s` by one and the remainder `n - s^2` by the
/// difference of the squares. The remainder is kept in 32 bits: for a guess below 2^26
/// (1,024 in Q16.16) within the steps of the root it is below 2 * 8 * 2^26 + 64, and `s`
/// stays below 2^26 + 8, so no sum overflows. `None` for a larger guess or one farther
/// than the steps go.
#[inline]
fn root_near(n: u64, guess: u32) -> Option<u32> {
    if guess >= 1 << 26 {
        return None;
    }
    let mut s = guess as i32;
    let mut remainder = i32::try_from(n.wrapping_sub(mul_u32(guess, guess)) as i64).ok()?;
    for _ in 0..RowRoots::STEPS {
        if remainder < 0 {
            // s > 0: 0^2 is not above n. (s - 1)^2 = s^2 - 2 s + 1.
            s -= 1;
            remainder += 2 * s + 1;
        } else if remainder > 2 * s {
            remainder -= 2 * s + 1;
            s += 1;
        } else {
            return Some(s as u32);
        }
    }
    None
}

/// One Newton step of `y ~ 1 / sqrt(x)`, `x = h / 2^32`, `y` in Q2.30: `y (3 - x y^2) / 2`.
#[inline(always)]
fn root_step(h: u32, y: u32) -> u32 {
    let square = u32::try_from(mul_u32(y, y) >> 30).unwrap_or(u32::MAX);
    let xy2 = (mul_u32(h, square) >> 32) as u32;
    let three_minus = (3u32 << 30).saturating_sub(xy2);
    u32::try_from(mul_u32(y, three_minus) >> 31).unwrap_or(u32::MAX)
}

/// The first step from the table's `top` (`y = top / 2^15`) in 32-bit products: `y` to 8
/// bits, `t = y 2^7` rounded, `e = 1 - x t^2 / 2^14` (to 2^-23 from two 16x16 products, |e|
/// below 2^-6), then `t (1 + e / 2 + 3 e^2 / 8)`, which leaves `5 e^3 / 16`: within 2^-21
/// (every `h` checked), which the next step squares. In Q2.30.
#[inline(never)]
fn root_step_in_words(h: u32, top: u32) -> u32 {
    let t = (top + 128) >> 8;
    let t2 = t * t;
    // h t^2 = high 2^16 + low, about 2^46; e 2^23 from its top bits (high about 2^30).
    let (high, low) = ((h >> 16) * t2, (h & 0xffff) * t2);
    let e = (1i32 << 23) - (high.wrapping_add(low >> 16) >> 7) as i32;
    // t e 2^23 is below 2^25; y e / 2 = t e / 2 in Q2.30, y 3e^2/8 = 3 t e^2 / 2^26.
    let te = t as i32 * e;
    let correction = (te >> 1) + ((3 * (te >> 12) * e) >> 14);
    u32::try_from(i64::from(t << 23) + i64::from(correction)).unwrap_or(u32::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn extremes() {
        for (a, b) in [
            (i32::MIN, i32::MIN),
            (i32::MIN, i32::MAX),
            (i32::MAX, i32::MAX),
            (-1, i32::MIN),
            (0, -5),
        ] {
            assert_eq!(mul_i32_halves(a, b), i64::from(a) * i64::from(b), "{a} {b}");
        }
        assert_eq!(
            mul_u32_halves(u32::MAX, u32::MAX),
            u64::from(u32::MAX) * u64::from(u32::MAX)
        );
        assert_eq!(isqrt(u64::MAX), u32::MAX);
        assert_eq!(isqrt(1), 1);
        assert_eq!(isqrt(3), 1);
        assert_eq!(isqrt(4), 2);
        let d = Divisor::new(1).unwrap();
        assert_eq!(d.divide((1 << 31) - 1), Some(u32::MAX >> 1));
        assert_eq!(d.divide(1 << 31), None);
        assert_eq!(Divisor::new(0).map(|_| ()), None);
        let big = Divisor::new(u32::MAX).unwrap();
        assert_eq!(big.divide((1 << 48) - 1), Some(65536));
    }

    /// The roots of rows of squared lengths as the camera makes them, from one another:
    /// each equals `u64::isqrt`. With the eye as far from the image as the image is wide or
    /// more, every one after the first three comes from the guess (else the rows would pay
    /// for `isqrt` as well as for the steps); with the eye almost on the image, whose
    /// lengths have a kink, or a few pixels across a wide view, only some do.
    #[test]
    fn row_roots_are_exact_and_stepped() {
        let ordinary = [
            (240i64, 8i64 << 16, 3i64 << 16, -3i64 << 16, true),
            (640, 8 << 16, 0, -(8 << 16), true),
            (320, 60 << 16, 20 << 16, -(40 << 16), true),
            (120, 100 << 16, 1 << 10, -(100 << 16), true),
        ];
        let extreme = [
            (640, 8 << 16, 0, -(3 << 16) / 100, false),
            (32, 100 << 16, 1 << 10, -(1 << 16), false),
            (160, 1 << 16, 0, 1, false),
            (32, 100 << 16, 1 << 10, -(100 << 16), false),
        ];
        for (width, world, dy, dz, all_stepped) in ordinary.into_iter().chain(extreme) {
            let squares = (dy * dy + dz * dz) as u64;
            let mut roots = RowRoots::default();
            let mut stepped = 0;
            for i in 0..width {
                let x = world * i / width - world / 2;
                let n = (x * x) as u64 + squares;
                if roots.known >= 3 {
                    let [r1, r2, r3] = roots.last.map(i64::from);
                    stepped += u32::from(root_near(n, (3 * (r1 - r2) + r3) as u32).is_some());
                }
                assert_eq!(roots.next(n), n.isqrt() as u32, "{n}");
            }
            if all_stepped {
                assert_eq!(i64::from(stepped), width - 3, "{width} {world} {dz}");
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200_000))]

        #[test]
        fn products_are_exact(a: i32, b: i32, c: u32, d: u32) {
            prop_assert_eq!(mul_i32_halves(a, b), i64::from(a) * i64::from(b));
            prop_assert_eq!(mul_u32_halves(c, d), u64::from(c) * u64::from(d));
            prop_assert_eq!(mul_i32(a, b), i64::from(a) * i64::from(b));
        }

        /// Any sequence at all, smooth or not: every root exact.
        #[test]
        fn row_roots_of_any_sequence_are_exact(values in prop::collection::vec(any::<u64>(), 1..12), base: u64, shift in 0u32..64) {
            let mut roots = RowRoots::default();
            for v in values {
                let n = base.wrapping_add(v >> shift);
                prop_assert_eq!(roots.next(n), n.isqrt() as u32);
            }
        }

        /// From any guess near the root or not: the root, or `None`, never another value
        /// (and no overflow).
        #[test]
        fn root_near_is_exact_or_none(n: u64, off in -12i64..12, far: u32) {
            let root = n.isqrt();
            for guess in [(root as i64 + off).clamp(0, u32::MAX.into()) as u32, far] {
                if let Some(s) = root_near(n, guess) {
                    prop_assert_eq!(u64::from(s), root);
                }
            }
            // Within reach: found exactly when the steps reach it.
            let small = n >> 12;
            let guess = (small.isqrt() as i64 + off).max(0) as u32;
            let found = root_near(small, guess);
            prop_assert!(found.is_none_or(|s| u64::from(s) == small.isqrt()));
            prop_assert_eq!(found.is_some(), small.isqrt().abs_diff(u64::from(guess)) < u64::from(RowRoots::STEPS) && guess < 1 << 26);
        }

        #[test]
        fn small_products_and_dots_are_exact(v in prop::array::uniform6(-(1i32 << 22)..(1 << 22)), a in -(1i32 << 23)..(1 << 23), b in -(1i32 << 23)..(1 << 23)) {
            prop_assert_eq!(i64::from(mul_q16_small(a, b)), (i64::from(a) * i64::from(b)) >> 16);
            let (x, y) = ([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
            let exact: i64 = x.iter().zip(&y).map(|(&p, &q)| i64::from(p) * i64::from(q)).sum();
            prop_assert_eq!(dot_i64_small(x, y), exact);
            prop_assert_eq!(i64::from(dot_q16_small(x, y)), exact >> 16);
            prop_assert!(all_below(&v, 6));
            prop_assert_eq!(all_below(&[a, b], 7), true);
        }

        #[test]
        fn bounds_and_leading_zeros(v: i32, w: u32) {
            let inside = i64::from(v).abs() < (1 << 22) || v == -(1 << 22);
            prop_assert_eq!(all_below(&[v], 6), inside);
            let shifted = w >> (w % 32);
            prop_assert_eq!(leading_zeros_table(w), w.leading_zeros());
            prop_assert_eq!(leading_zeros_table(shifted), shifted.leading_zeros());
            prop_assert_eq!(leading_zeros_table(0), 32);
        }

        #[test]
        fn shifts_are_exact(v: u64, s in 0u32..70) {
            prop_assert_eq!(shl_u64_halves(v, s), v.checked_shl(s).unwrap_or(0));
            prop_assert_eq!(shl_u64(v, s), v.checked_shl(s).unwrap_or(0));
            prop_assert_eq!(shr_u64_halves(v, s), v.checked_shr(s).unwrap_or(0));
            prop_assert_eq!(shr_u64(v, s), v.checked_shr(s).unwrap_or(0));
        }

        #[test]
        fn division_is_exact(n in 0u64..(1 << 48), m in 1u32..) {
            let q = n / u64::from(m);
            let got = Divisor::new(m).unwrap().divide(n);
            if q < 1 << 31 {
                prop_assert_eq!(got, Some(q as u32));
            } else {
                prop_assert_eq!(got, None);
            }
        }

        #[test]
        fn q16_division_is_exact(x: u32, m in 1u32..) {
            let q = (u64::from(x) << 16) / u64::from(m);
            prop_assert_eq!(Divisor::new(m).unwrap().divide_q16(x), (q < 1 << 31).then_some(q as u32));
        }

        #[test]
        fn q16_division_near_the_top_is_exact(q in (1u64 << 30)..(1u64 << 32), m in 1u32..200_000) {
            // Numerators whose quotient is near 2^31, where the estimate's error is largest.
            let x = ((q * u64::from(m)) >> 16).min(u64::from(u32::MAX)) as u32;
            let exact = (u64::from(x) << 16) / u64::from(m);
            prop_assert_eq!(Divisor::new(m).unwrap().divide_q16(x), (exact < 1 << 31).then_some(exact as u32));
        }

        #[test]
        fn small_divisors_are_exact(n in 0u64..(1 << 40), m in 1u32..70_000) {
            let q = n / u64::from(m);
            let got = Divisor::new(m).unwrap().divide(n);
            prop_assert_eq!(got, (q < 1 << 31).then_some(q as u32));
        }

        #[test]
        fn rough_reciprocals_within_2_to_the_minus_16(n in (1u32 << 31)..) {
            let exact = (1u128 << 63) as f64 / f64::from(n);
            let got = f64::from(reciprocal_rough(n));
            prop_assert!((got - exact).abs() <= exact * 2f64.powi(-16), "{} vs {}", got, exact);
        }

        #[test]
        fn reciprocals_in_words_within_2_to_the_minus_22(n in (1u32 << 31)..) {
            let exact = (1u128 << 63) as f64 / f64::from(n);
            let got = f64::from(reciprocal_in_words(n));
            prop_assert!((got - exact).abs() <= exact * 2f64.powi(-22), "{} vs {}", got, exact);
        }

        #[test]
        fn estimates_within_2_to_the_minus_28(n in (1u32 << 31)..) {
            // Both ways: the one the target uses and the other.
            let exact = (1u128 << 63) as f64 / f64::from(n);
            for y in [reciprocal_in_words(n), newton_reciprocal(n, first_reciprocal(n))] {
                let got = f64::from(newton_reciprocal(n, y));
                prop_assert!((got - exact).abs() <= exact * 2f64.powi(-28), "{} vs {}", got, exact);
            }
        }

        /// Both square roots exact, the float unit's and the table's, and the float unit's
        /// guess within `2^-23` of the root and a unit (within the steps' reach below
        /// `2^25`).
        #[test]
        fn square_roots_are_exact_both_ways(n: u64, shift in 0u32..64) {
            for n in [n, n >> shift] {
                let root = n.isqrt() as u32;
                prop_assert_eq!(isqrt(n), root);
                prop_assert_eq!(isqrt_by(n, true), root);
                prop_assert_eq!(isqrt_by(n, false), root);
                let guess = float_root_guess(n);
                if root < 1 << 25 {
                    prop_assert!(root.abs_diff(guess) <= (root >> 23) + 1, "{} from {}", root, guess);
                    prop_assert_eq!(root_near(n, guess), Some(root));
                }
            }
        }

        /// The float unit's quotient exact wherever it answers, its estimate within a unit,
        /// and an answer for every quotient below `2^21`; the exact reciprocal's the same.
        #[test]
        fn float_quotients_are_exact(x: u32, m in 1u32.., shift in 0u32..32) {
            for (x, m) in [(x, m), (x >> shift, m), (x, m >> shift | 1)] {
                let exact = (u64::from(x) << 16) / u64::from(m);
                let scale = float_scale_q16(m).unwrap();
                let estimate = (x as f32 * scale) as u32;
                if exact < 1 << 22 {
                    prop_assert!(u64::from(estimate).abs_diff(exact) <= 1, "{} for {}", estimate, exact);
                }
                let float = float_quotient_q16(x, m, scale);
                prop_assert!(float.is_none_or(|q| u64::from(q) == exact));
                prop_assert_eq!(float.is_some(), estimate < 1 << 22);
                prop_assert!(float.is_some() || exact >= 1 << 21);
                let divisor = Divisor::new(m).unwrap().divide_q16(x);
                prop_assert_eq!(divisor.map(u64::from), (exact < 1 << 31).then_some(exact));
            }
            prop_assert_eq!(float_scale_q16(0), None);
        }

        #[test]
        fn three_scales_equal_one_at_a_time(m: u32, e in -80i32..8, b: [i32; 3]) {
            let w = Wide { mantissa: m | 1 << 31, exponent: e };
            prop_assert_eq!(w.scale_bits3(b), b.map(|b| w.scale_bits(b)));
            let small = b.map(|b| b >> 12);
            prop_assert_eq!(w.scale_bits3(small), small.map(|b| w.scale_bits(b)));
            prop_assert_eq!(Wide::ZERO.scale_bits3(b), [0; 3]);
        }

        #[test]
        fn square_roots_are_exact(n: u64) {
            prop_assert_eq!(isqrt(n), n.isqrt() as u32);
        }

        #[test]
        fn square_roots_of_small_numbers_are_exact(n in 0u64..(1 << 40)) {
            prop_assert_eq!(isqrt(n), n.isqrt() as u32);
        }

        #[test]
        fn square_roots_next_to_squares_are_exact(s: u32, offset in -2i64..=2) {
            // Where the corrections step across a square; both first steps.
            let n = (u64::from(s) * u64::from(s)).saturating_add_signed(offset);
            prop_assert_eq!(isqrt_by(n, true), n.isqrt() as u32);
            prop_assert_eq!(isqrt_by(n, false), n.isqrt() as u32);
        }

        #[test]
        fn square_roots_by_words_are_exact(n: u64, small in 0u64..(1 << 40)) {
            prop_assert_eq!(isqrt_by(n, true), n.isqrt() as u32);
            prop_assert_eq!(isqrt_by(small, true), small.isqrt() as u32);
        }

        #[test]
        fn first_root_steps_in_words_within_2_to_the_minus_21(h in (1u32 << 30)..) {
            let top = RECIPROCAL_ROOTS.get(((h >> 24) as usize) - 64).copied().map(u32::from).unwrap();
            let exact = (1u64 << 30) as f64 / (f64::from(h) / 4_294_967_296.0).sqrt();
            let got = f64::from(root_step_in_words(h, top));
            prop_assert!((got - exact).abs() <= exact * 2f64.powi(-21), "{} vs {}", got, exact);
        }
    }
}
