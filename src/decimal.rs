//! Decimal numbers, read without `core`'s float parser.
//!
//! `core`'s `str::parse::<f64>` (and nom's `double`, which uses it) carries tables of powers
//! that cost tens of KiB of flash on Cortex-M. This reader needs none: numbers of up to 15
//! digits with exponents up to ±22 (every number in the course's files) take Clinger's fast
//! path, one exact conversion and one correctly rounded multiply or divide; the rest go
//! through a small fixed-size big integer. The result is the correctly rounded `f64` for
//! every input of up to 40 significant digits; digits beyond the 40th are folded into a
//! sticky bit (exact unless the value lies within 1e-40 of a rounding boundary).
//!
//! Grammar: `[+-]? (digits [. digits?] | . digits) ([eE] [+-]? digits)?`. `nan`, `inf` and
//! `infinity` are rejected as non-finite; values beyond ±1.8e308 as too large; values too
//! small for a subnormal round to zero.

/// A decimal as recognised: sign, integer and fraction digits, and the written exponent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Decimal<'a> {
    /// A leading `-`.
    pub negative: bool,
    /// Digits before the point.
    pub integer: &'a [u8],
    /// Digits after the point.
    pub fraction: &'a [u8],
    /// The exponent after `e`, saturated to ±1e9.
    pub exponent: i64,
}

/// Why a token is not a number microray accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NumberError {
    /// Not of the decimal grammar.
    NotANumber,
    /// `nan`, `inf`, `infinity` (any case, any sign).
    NotFinite,
    /// Beyond the range of `f64`.
    TooLarge,
}

impl core::fmt::Display for NumberError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            NumberError::NotANumber => "not a decimal number",
            NumberError::NotFinite => "not a finite number (`nan` and `inf` are not accepted)",
            NumberError::TooLarge => "too large (beyond about 1.8e308)",
        })
    }
}

impl core::error::Error for NumberError {}

/// Recognises the decimal grammar at the start of `input`: the number and what follows it,
/// or `None`. A loop over bytes rather than nom's combinators: the scene parser hands this
/// whole tokens, and the combinators cost 400 bytes more of a Cortex-M0's flash.
pub(crate) fn decimal(input: &[u8]) -> Option<(&[u8], Decimal<'_>)> {
    let (negative, rest) = sign(input);
    let (integer, rest) = digits(rest);
    let (fraction, rest) = match rest.split_first() {
        Some((b'.', after)) => digits(after),
        _ => (&[][..], rest),
    };
    if integer.is_empty() && fraction.is_empty() {
        return None;
    }
    // An exponent only with at least one digit; else the `e` is left to the caller.
    let (exponent, rest) = match rest.split_first() {
        Some((b'e' | b'E', after)) => {
            let (minus, after) = sign(after);
            let (written, after) = digits(after);
            if written.is_empty() {
                (0, rest)
            } else {
                let magnitude = written.iter().fold(0i64, |acc, d| {
                    (acc * 10 + i64::from(d - b'0')).min(1_000_000_000)
                });
                (if minus { -magnitude } else { magnitude }, after)
            }
        }
        _ => (0, rest),
    };
    Some((
        rest,
        Decimal {
            negative,
            integer,
            fraction,
            exponent,
        },
    ))
}

/// An optional `+` or `-` at the start of `input`: whether it is `-`, and the rest.
fn sign(input: &[u8]) -> (bool, &[u8]) {
    match input.split_first() {
        Some((b'-', rest)) => (true, rest),
        Some((b'+', rest)) => (false, rest),
        _ => (false, input),
    }
}

/// The ASCII digits at the start of `input`, and the rest.
fn digits(input: &[u8]) -> (&[u8], &[u8]) {
    let count = input.iter().take_while(|b| b.is_ascii_digit()).count();
    input.split_at_checked(count).unwrap_or((input, &[]))
}

/// Reads a whole token as a finite `f64`.
pub fn parse_number(token: &[u8]) -> Result<f64, NumberError> {
    match decimal(token) {
        Some((&[], d)) => to_f64(&d),
        _ => {
            let unsigned = token
                .strip_prefix(b"-")
                .or(token.strip_prefix(b"+"))
                .unwrap_or(token);
            let named = [&b"nan"[..], b"inf", b"infinity"];
            if named.iter().any(|n| unsigned.eq_ignore_ascii_case(n)) {
                Err(NumberError::NotFinite)
            } else {
                Err(NumberError::NotANumber)
            }
        }
    }
}

/// Significant digits kept exactly; the rest only set the sticky bit.
const MAX_DIGITS: usize = 40;

/// The correctly rounded `f64` of a recognised decimal.
pub fn to_f64(d: &Decimal<'_>) -> Result<f64, NumberError> {
    // Significant digits, without leading zeros; `exponent` makes value = digits * 10^exponent.
    let mut digits = [0u8; MAX_DIGITS];
    let mut count = 0usize;
    let mut exponent = d.exponent;
    let mut inexact = false;
    for (&c, in_fraction) in d
        .integer
        .iter()
        .map(|c| (c, false))
        .chain(d.fraction.iter().map(|c| (c, true)))
    {
        let digit = c - b'0';
        if count == 0 && digit == 0 {
            exponent -= i64::from(in_fraction);
        } else if let Some(slot) = digits.get_mut(count) {
            *slot = digit;
            count += 1;
            exponent -= i64::from(in_fraction);
        } else {
            inexact |= digit != 0;
            exponent += i64::from(!in_fraction);
        }
    }
    while count > 0 && digits.get(count - 1) == Some(&0) {
        count -= 1;
        exponent += 1;
    }
    let sign = if d.negative { -1.0 } else { 1.0 };
    if count == 0 {
        return Ok(sign * 0.0);
    }
    let significant = digits.get(..count).unwrap_or(&[]);
    // The value lies in [10^(order-1), 10^order).
    let order = exponent + count as i64;
    if order > 309 {
        return Err(NumberError::TooLarge);
    }
    if order < -325 {
        return Ok(sign * 0.0);
    }
    // Both in range now, so the narrowing cannot lose anything.
    let exponent = exponent as i32;
    if !inexact && count <= 15 && (-22..=22).contains(&exponent) {
        // Clinger's fast path: both operands are exact, so one rounding is all there is.
        let m = significant
            .iter()
            .fold(0u64, |acc, &c| acc * 10 + u64::from(c)) as f64;
        let p = POWERS_OF_TEN
            .get(exponent.unsigned_abs() as usize)
            .copied()
            .unwrap_or(1.0);
        let v = if exponent >= 0 { m * p } else { m / p };
        return Ok(sign * v);
    }
    let value = slow_path(significant, exponent, inexact).ok_or(NumberError::TooLarge)?;
    Ok(sign * value)
}

const POWERS_OF_TEN: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// digits * 10^exponent, correctly rounded, via an exact big integer. Out of line: its
/// big integers (about a KiB of stack on a Cortex-M0) are needed only off the fast path.
#[inline(never)]
fn slow_path(digits: &[u8], exponent: i32, inexact: bool) -> Option<f64> {
    let mut n = Big::ZERO;
    for &digit in digits {
        n.mul_small(10);
        n.add_small(u32::from(digit));
    }
    if exponent >= 0 {
        // value = n * 5^e * 2^e.
        n.mul_pow5(exponent.unsigned_abs());
        let (top, shift, sticky) = n.top64();
        round(top, exponent + shift, sticky || inexact)
    } else {
        // value = n / 5^k * 2^-k: divide with enough extra bits for a 64-bit quotient.
        let k = exponent.unsigned_abs();
        let mut divisor = Big::ONE;
        divisor.mul_pow5(k);
        // Line the operands up so that the quotient has 65 or 66 bits.
        let target = divisor.bit_len() + 65;
        let mut binary_exponent = -(k as i32);
        let length = n.bit_len();
        if length < target {
            n.shl(target - length);
            binary_exponent -= (target - length) as i32;
        } else {
            divisor.shl(length - target);
            binary_exponent += (length - target) as i32;
        }
        let (quotient, remainder_nonzero) = n.divide_small_quotient(&divisor);
        // Keep 64 bits, folding the rest into the sticky bit.
        let excess = 128 - quotient.leading_zeros() - 64;
        let dropped = quotient & ((1u128 << excess) - 1);
        let top = (quotient >> excess) as u64;
        let binary_exponent = binary_exponent + excess as i32;
        round(
            top,
            binary_exponent,
            remainder_nonzero || dropped != 0 || inexact,
        )
    }
}

/// Rounds `top * 2^exponent` (+ a little more when `sticky`), `top` with bit 63 set, to the
/// nearest `f64`, ties to even; `None` when it overflows.
fn round(top: u64, exponent: i32, sticky: bool) -> Option<f64> {
    let leading = exponent + 63; // the exponent of the leading bit
    if leading > 1023 {
        return None;
    }
    // Bits below the 53 an f64 keeps (more for subnormals).
    let drop = if leading >= -1022 {
        11
    } else {
        11 + (-1022 - leading)
    };
    if drop > 64 {
        return Some(0.0);
    }
    let drop = drop as u32;
    let (kept, rest) = if drop == 64 {
        (0, top)
    } else {
        (top >> drop, top & ((1u64 << drop) - 1))
    };
    let half = 1u64 << (drop - 1);
    let up = rest > half || (rest == half && (sticky || kept & 1 == 1));
    let mut kept = kept + u64::from(up);
    if leading < -1022 {
        // Subnormal: the biased exponent is 0, and a carry into bit 52 makes the smallest
        // normal number, whose encoding is exactly that.
        return Some(f64::from_bits(kept));
    }
    let mut leading = leading;
    if kept == 1 << 53 {
        kept >>= 1;
        leading += 1;
        if leading > 1023 {
            return None;
        }
    }
    let biased = (leading + 1023) as u64;
    Some(f64::from_bits((biased << 52) | (kept & ((1u64 << 52) - 1))))
}

/// A fixed-size unsigned big integer, little-endian 32-bit limbs: large enough for
/// 10^40 * 5^350 with 66 bits to spare.
#[derive(Clone, Copy)]
struct Big {
    limbs: [u32; 40],
}

impl Big {
    const ZERO: Big = Big { limbs: [0; 40] };
    const ONE: Big = {
        let mut limbs = [0; 40];
        limbs[0] = 1;
        Big { limbs }
    };

    fn mul_small(&mut self, factor: u32) {
        let mut carry = 0u64;
        for limb in self.limbs.iter_mut() {
            let product = u64::from(*limb) * u64::from(factor) + carry;
            *limb = product as u32;
            carry = product >> 32;
        }
    }

    fn add_small(&mut self, value: u32) {
        let mut carry = u64::from(value);
        for limb in self.limbs.iter_mut() {
            if carry == 0 {
                break;
            }
            let sum = u64::from(*limb) + carry;
            *limb = sum as u32;
            carry = sum >> 32;
        }
    }

    fn mul_pow5(&mut self, mut k: u32) {
        const FIVE_13: u32 = 1_220_703_125;
        while k >= 13 {
            self.mul_small(FIVE_13);
            k -= 13;
        }
        self.mul_small(5u32.pow(k));
    }

    fn bit_len(&self) -> u32 {
        for (i, limb) in self.limbs.iter().enumerate().rev() {
            if *limb != 0 {
                return i as u32 * 32 + (32 - limb.leading_zeros());
            }
        }
        0
    }

    fn bit(&self, i: u32) -> bool {
        self.limbs
            .get((i / 32) as usize)
            .is_some_and(|limb| limb >> (i % 32) & 1 == 1)
    }

    fn shl(&mut self, bits: u32) {
        let words = (bits / 32) as usize;
        let bits = bits % 32;
        let mut out = [0u32; 40];
        for (i, slot) in out.iter_mut().enumerate().skip(words) {
            let from = i - words;
            let low = self.limbs.get(from).copied().unwrap_or(0);
            let below = if bits > 0 && from > 0 {
                self.limbs.get(from - 1).copied().unwrap_or(0) >> (32 - bits)
            } else {
                0
            };
            *slot = (low << bits) | below;
        }
        self.limbs = out;
    }

    fn shr1(&mut self) {
        let mut carry = 0u32;
        for limb in self.limbs.iter_mut().rev() {
            let next = *limb & 1;
            *limb = (*limb >> 1) | (carry << 31);
            carry = next;
        }
    }

    fn ge(&self, other: &Big) -> bool {
        for (a, b) in self.limbs.iter().zip(other.limbs.iter()).rev() {
            if a != b {
                return a > b;
            }
        }
        true
    }

    fn sub(&mut self, other: &Big) {
        let mut borrow = 0i64;
        for (a, b) in self.limbs.iter_mut().zip(other.limbs.iter()) {
            let diff = i64::from(*a) - i64::from(*b) - borrow;
            borrow = i64::from(diff < 0);
            *a = diff.rem_euclid(1 << 32) as u32;
        }
    }

    fn is_zero(&self) -> bool {
        self.limbs.iter().all(|&l| l == 0)
    }

    /// The top 64 bits, the binary exponent of their lowest bit, and whether any bit below
    /// them is set. A number of fewer than 64 bits is shifted up.
    fn top64(&self) -> (u64, i32, bool) {
        let len = self.bit_len();
        let low = len.saturating_sub(64);
        let mut top = 0u64;
        for i in (low..len).rev() {
            top = (top << 1) | u64::from(self.bit(i));
        }
        let sticky = (0..low).any(|i| self.bit(i));
        let up = 64 - (len - low);
        (top << up, low as i32 - up as i32, sticky)
    }

    /// `self / divisor` for a quotient below 2^66, and whether the remainder is non-zero.
    fn divide_small_quotient(mut self, divisor: &Big) -> (u128, bool) {
        let mut shifted = *divisor;
        shifted.shl(66);
        let mut quotient = 0u128;
        for i in (0..66).rev() {
            shifted.shr1();
            if self.ge(&shifted) {
                self.sub(&shifted);
                quotient |= 1 << i;
            }
        }
        (quotient, !self.is_zero())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn read(s: &str) -> Result<f64, NumberError> {
        parse_number(s.as_bytes())
    }

    #[test]
    fn course_numbers() {
        for s in [
            "4", "-6.93", "0.8", "1e-3", "2.121", "-5.121", "250.0", "0.4", "100000", "+3", ".5",
            "5.",
        ] {
            assert_eq!(read(s).unwrap(), s.parse::<f64>().unwrap(), "{s}");
        }
        assert_eq!(read("-0").unwrap().to_bits(), (-0.0f64).to_bits());
    }

    #[test]
    fn hard_cases_round_correctly() {
        for s in [
            "0.30000000000000004",
            "9007199254740993",
            "1.7976931348623157e308",
            "2.2250738585072011e-308",
            "4.9406564584124654e-324",
            "2.4703282292062328e-324",
            "2.4703282292062327e-324",
            "1e23",
            "8.98846567431158e307",
            "123456789012345678901234567890",
            "0.1000000000000000055511151231257827021181583404541015625",
            "1e-400",
            "7.2057594037927933e16",
        ] {
            assert_eq!(
                read(s).unwrap().to_bits(),
                s.parse::<f64>().unwrap().to_bits(),
                "{s}"
            );
        }
    }

    #[test]
    fn rejects() {
        assert_eq!(read("1.8e308"), Err(NumberError::TooLarge));
        assert_eq!(read("1e99999999999999"), Err(NumberError::TooLarge));
        assert_eq!(read("0e99999999999999"), Ok(0.0));
        for s in ["nan", "-inf", "Infinity", "NaN"] {
            assert_eq!(read(s), Err(NumberError::NotFinite), "{s}");
        }
        for s in [
            "", ".", "-", "e5", "1e", "1.2.3", "0x10", "1,5", "--1", "1e+",
        ] {
            assert_eq!(read(s), Err(NumberError::NotANumber), "{s}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]

        #[test]
        fn matches_core_for_short_decimals(
            digits in "[0-9]{1,40}", point in 0usize..41, exponent in -360i32..340, negative: bool,
        ) {
            let point = point.min(digits.len());
            let text = format!("{}{}.{}e{}", if negative { "-" } else { "" },
                &digits[..point], &digits[point..], exponent);
            let expected: f64 = text.parse().unwrap();
            match read(&text) {
                Ok(v) => prop_assert_eq!(v.to_bits(), expected.to_bits(), "{}", text),
                Err(NumberError::TooLarge) => prop_assert!(expected.is_infinite(), "{}", text),
                Err(e) => prop_assert!(false, "{} gave {:?}", text, e),
            }
        }

        #[test]
        fn accepts_what_core_accepts(text in "[-+.eE0-9]{0,9}") {
            // The grammar is core's without `inf` and `nan`: the same strings, the same
            // values (and beyond the range, an error where core gives infinity).
            match (read(&text), text.parse::<f64>()) {
                (Ok(ours), Ok(core)) => prop_assert_eq!(ours.to_bits(), core.to_bits(), "{}", text),
                (Err(NumberError::TooLarge), Ok(core)) => prop_assert!(core.is_infinite(), "{}", text),
                (Err(NumberError::NotANumber), Err(_)) => {}
                (ours, core) => prop_assert!(false, "{}: {:?} against {:?}", text, ours, core),
            }
        }

        #[test]
        fn any_float_reads_back_from_its_shortest_text(bits: u64) {
            let v = f64::from_bits(bits);
            prop_assume!(v.is_finite());
            for text in [format!("{v}"), format!("{v:e}")] {
                prop_assert_eq!(read(&text).unwrap().to_bits(), v.to_bits(), "{}", text);
            }
        }
    }
}
