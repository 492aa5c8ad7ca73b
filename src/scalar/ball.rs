//! Fixed point's exact pre-test of a sphere: whether its test of a shadow ray certainly
//! misses, from exact integer sums, before the ray's length, reciprocal and unit direction
//! are worked out.
//!
//! [`Sphere::nearest`](crate::object::sphere::Sphere::nearest) tests a ray whose length is
//! not stored (a shadow ray) in fixed point by dividing its direction by its length first:
//! a square root, a reciprocal and three quotients, then two dot products, whatever the
//! outcome. Most such tests miss (in the showcase 96 %: 81 % by the discriminant, 15 %
//! because the ray leaves the centre behind). Whether they miss can be decided from the
//! direction as it is, with integer sums that make no error, against a margin that bounds
//! every rounding of the test it stands for: where the pre-test says miss, the test would
//! have missed, so the images are the same bit for bit.
//!
//! The bounds, with `ε = 2^-16`, `f = base - center`, `F1 = |f|₁`, `len = ⌊|dir|⌋` (what
//! the test divides by; at least 2 steps, so `κ = |dir| / len <= 1.5`) and `v = dir / len`:
//!
//! - the test's unit direction `ũ` is `v` within `ε (1.5 + |v_i|)` a component (the
//!   reciprocal is good to `2^-16` relative, each quotient to half a step, and more);
//! - its `b̃ = ⌊f . ũ⌋` is within `β = ε (1 + 3 F1)` of `f . v`, so it is above zero (a miss)
//!   when `f . dir >= |dir|₁ ε (1 + 3 F1)`: [`leaves_behind`], with a factor of two to spare;
//! - its perpendicular `f - ũ b̃` is within `ε (5.6 + 18.5 F1)` (the sum of the components'
//!   errors) of `f - v (f . v)`, which is never nearer the centre than the true
//!   perpendicular `p` (`|f - v (f . v)|^2 - |p|^2 = (f . v)^2 (κ - 1/κ)^2`); its floored
//!   square reaches `r² + ε` (a miss) when `|p| >= R + M` with `R² = r² + ε` and
//!   `M = ε (8 + 20 F1)`. As `(R + M)^2 <= 9/8 R^2 + 9 M^2` and `|p|^2 |dir|^2 = |f|^2
//!   |dir|^2 - (f . dir)^2`, that holds when `|dir|^2 (|f|^2 - 9/8 R^2 - 9 M^2) >=
//!   (f . dir)^2`: [`passes_outside`], in exact 128-bit products, or on the Cortex-M0
//!   (where one is sixteen multiplies) with 32-bit mantissas, the left side rounded down
//!   and the right up.
//!
//! tests/sphere_miss.rs checks the claim on a million rays aimed at, near and past
//! spheres of every size: wherever the pre-test says miss, the test returns none.
//!
//! Cheaper still, on the Cortex-M0, for a shadow ray's segment: [`segment_clears_box`]
//! compares its ends with a ball's (or a surface of revolution's) box, and most segments
//! lie beside it on some axis.

use super::wide::{Wide, in_halves, mul_i32, mul_u32};

/// The largest `|f|₁`, in Q16.16 bits, the pre-test takes (256 units; beyond, the test runs
/// alone): below it `f . dir` and `|f|^2` fit 64 bits and the margins their bounds.
const MAX_SPAN_BITS: u32 = 1 << 24;

/// A shadow ray and a sphere, in Q16.16 bits: `f = base - center`, the ray's direction and
/// the sphere's squared radius.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BallTest {
    pub f: [i32; 3],
    pub dir: [i32; 3],
    pub radius_squared: i32,
}

impl BallTest {
    /// Whether the sphere test of this ray certainly misses (see the module's docs); `false`
    /// when it cannot tell, or when the numbers are beyond the bounds' reach.
    pub(crate) fn misses(&self) -> bool {
        let (span, dir_span) = (sum_abs(self.f), sum_abs(self.dir));
        // |dir|₁ >= 4: |dir| >= 4/√3, so the test's length is at least 2 steps; below 2^31:
        // the length is not saturated.
        if span >= MAX_SPAN_BITS || !(4..1 << 31).contains(&dir_span) {
            return false;
        }
        // |f_i dir_i| below 2^55: exact.
        let along = exact_dot(self.f, self.dir);
        leaves_behind(along, dir_span, span)
            || passes_outside(
                square_sum(self.f),
                self.dir,
                along,
                span,
                self.radius_squared,
            )
    }
}

/// The largest radius with its margin, in Q16.16 bits, [`ray_clears_wide_of`] takes
/// (128 units): its square with the margin fits `passes_outside`'s 32 bits.
const MAX_RADIUS_BITS: u32 = 1 << 23;

/// Whether the ray from `base` along `dir` (`f = base - center`, Q16.16 bits), for `t >=
/// 0`, stays farther from the centre than `radius` (bits) plus `(|f|₁ + radius + 1) /
/// 256`, a margin that grows with how far off the ray is looked at: its base lies beyond
/// that and it moves away (`f . dir >= 0`: every point ahead is farther still), or its
/// whole line passes outside ([`passes_outside`]). `false` when it cannot tell or the
/// numbers are beyond the bounds' reach. Unlike [`BallTest::misses`] the base may lie
/// inside, and it stands for no particular test's roundings: its margin, `2^8 ε` a unit,
/// is the caller's to cover them (`RevSurf::nearest`, whose search finds nothing so far
/// from its bounding sphere).
pub(crate) fn ray_clears_wide_of(f: [i32; 3], dir: [i32; 3], radius: u32) -> bool {
    let (span, dir_span) = (sum_abs(f), sum_abs(dir));
    let wide = widened(radius, span);
    if span >= MAX_SPAN_BITS || !(4..1 << 31).contains(&dir_span) || wide >= MAX_RADIUS_BITS {
        return false;
    }
    // As in `misses`: exact, below 2^55.
    let along = exact_dot(f, dir);
    // `wide^2` in Q16.16, rounded up: below 2^30.
    let Ok(wide_squared) = i32::try_from(mul_u32(wide, wide).div_ceil(1 << 16)) else {
        return false;
    };
    // Q32.32 both, below 2^48.
    let f_squared = square_sum(f);
    let outside = f_squared > u64::from(wide_squared.unsigned_abs()) << 16;
    (along >= 0 && outside) || passes_outside(f_squared, dir, along, span, wide_squared)
}

/// Whether the line in the plane through `f` (a point less the centre, Q16.16 bits) along
/// `dir` passes the centre farther than `radius` (bits) plus `(|f|₁ + radius + 1) / 256`,
/// the margin of [`ray_clears_wide_of`]: an upright cylinder's test on a ray's `x` and
/// `z`. Without squares: the line's distance is `|f x dir| / |dir|`, and `|dir| <= max +
/// min / 2` of its components' sizes (at most 6 % above it), so `|f x dir| > wide (max +
/// min / 2)` is enough: two exact 64-bit products and one more, where the sphere's test
/// takes nine and a 128-bit comparison. `false` when it cannot tell.
pub(crate) fn line_clears_disc(f: [i32; 2], dir: [i32; 2], radius: u32) -> bool {
    let [fx, fz] = f;
    let [dx, dz] = dir;
    let span = fx.unsigned_abs().saturating_add(fz.unsigned_abs());
    let wide = widened(radius, span);
    let (ax, az) = (dx.unsigned_abs(), dz.unsigned_abs());
    if span >= MAX_SPAN_BITS || ax.max(az) >= 1 << 30 || wide >= MAX_RADIUS_BITS {
        return false;
    }
    // `max + ceil(min / 2)`, below 2^31; the cross product exact below 2^55.
    let norm = ax.max(az) + ax.min(az).div_ceil(2);
    let cross = mul_i32(fz, dx) - mul_i32(fx, dz);
    cross.unsigned_abs() > mul_u32(wide, norm)
}

/// Whether the segment from `f` to `f + dir` (Q16.16 bits, `f` a point less a box's
/// centre) lies, on some axis, wholly beyond the box of half-sides `half` (bits), each
/// widened by the margin of [`ray_clears_wide_of`] (`(|f|₁ + h + 1) / 256`, `h` the
/// largest half-side). A test that reports a hit at `0 < t < 1` of a shape within the box
/// (a ball, a surface of revolution) puts it on the segment, and within the box but for
/// its roundings, which move a point by far less than the margin; so where the segment
/// clears the widened box, the test finds nothing. A shadow ray's segment, from a hit to
/// its light, is most often far beside a ball: six comparisons settle it, where
/// [`BallTest::misses`] takes nine exact 64-bit products. `false` when it cannot tell.
pub(crate) fn segment_clears_box(f: [i32; 3], dir: [i32; 3], half: [u32; 3]) -> bool {
    let margin = margin(half[0].max(half[1]).max(half[2]), sum_abs(f));
    // Saturated ends stay beyond the box's sides (each below 2^31), so the comparisons
    // are the true ends'.
    f.iter().zip(dir).zip(half).any(|((&from, step), half)| {
        let Ok(wide) = i32::try_from(half.saturating_add(margin)) else {
            return false;
        };
        let to = from.saturating_add(step);
        from.min(to) > wide || from.max(to) < -wide
    })
}

/// `radius` plus the pre-tests' margin `(|f|₁ + radius + 1) / 256`, in Q16.16 bits (`span`
/// is `|f|₁`), saturated.
#[inline]
fn widened(radius: u32, span: u32) -> u32 {
    radius.saturating_add(margin(radius, span))
}

/// The pre-tests' margin `(|f|₁ + radius + 1) / 256`, in Q16.16 bits.
#[inline]
fn margin(radius: u32, span: u32) -> u32 {
    (span.saturating_add(radius) >> 8) + 256
}

/// `a . b` in Q32.32 bits, exact (below 2^55 within the callers' bounds). In line: out of
/// line on the Cortex-M0 (with [`square_sum`]) it saved the film firmware 228 bytes of
/// flash and cost the micro:bit's showcase 1.4 % (its spheres' shadow rays).
#[inline]
fn exact_dot(a: [i32; 3], b: [i32; 3]) -> i64 {
    mul_i32(a[0], b[0]) + mul_i32(a[1], b[1]) + mul_i32(a[2], b[2])
}

/// `|v|^2` in Q32.32 bits, exact (below `3 2^62`).
#[inline]
fn square_sum(v: [i32; 3]) -> u64 {
    v.iter()
        .map(|&c| mul_u32(c.unsigned_abs(), c.unsigned_abs()))
        .sum()
}

/// `|x| + |y| + |z|`, saturated (the callers' limits are far below).
#[inline]
fn sum_abs(v: [i32; 3]) -> u32 {
    v.iter()
        .fold(0u32, |sum, &c| sum.saturating_add(c.unsigned_abs()))
}

/// Whether `b̃` is certainly above zero: `f . dir >= 2 |dir|₁ ε (1 + 3 F1)`, in bits
/// (`along` in Q32.32, the sums in Q16.16).
#[inline]
fn leaves_behind(along: i64, dir_span: u32, span: u32) -> bool {
    // Below 2^31 and 2^24: no overflow.
    let len = u64::from(dir_span);
    let margin = 2 * len + ((6 * len * u64::from(span)) >> 16) + 1;
    along > 0 && along.unsigned_abs() >= margin
}

/// Whether the line passes certainly outside: `|dir|^2 (|f|^2 - 9/8 (r² + ε) - 9 M^2) >=
/// (f . dir)^2` with `M = ε (8 + 20 F1)`, in Q32.32 bits, the product on the left rounded
/// down and the square on the right up.
#[inline]
fn passes_outside(
    f_squared: u64,
    dir: [i32; 3],
    along: i64,
    span: u32,
    radius_squared: i32,
) -> bool {
    // Below 3 2^62 (`f_squared`, the caller's, below 2^48).
    let dir_squared = square_sum(dir);
    // M in bits, rounded up, below 2^13 (the callers keep `span` below 2^24), and 9 M^2
    // below 2^30: 32-bit products (a 64-bit one is a library call on the Cortex-M0).
    // 9/8 (r² + ε) 2^16 is below 2^48 and exact: `r² + ε` in bits times 2^16 + 2^13.
    let m = 8 + span.saturating_mul(20).div_ceil(1 << 16);
    let r = u64::from(radius_squared.max(0).unsigned_abs()) + 1;
    let reach = u64::from(m.saturating_mul(m).saturating_mul(9)) + (r << 16) + (r << 13);
    let Some(room) = f_squared.checked_sub(reach) else {
        return false;
    };
    let along = along.unsigned_abs();
    if in_halves() {
        // Cortex-M0: 32-bit mantissas rounded outwards (a 64x64-bit product is 16 multiplies).
        let low = Wide::from_u64(dir_squared, 0).mul(Wide::from_u64(room, 0));
        let b = Wide::from_u64(along, 0).up();
        low.at_least(b.mul(b).up())
    } else {
        mul_u64(dir_squared, room) >= mul_u64(along, along)
    }
}

/// The full product of two `u64` (four 32x32 products: `u128`'s general multiply is a
/// library call on 32-bit Arm).
#[inline]
fn mul_u64(a: u64, b: u64) -> u128 {
    let (al, ah) = (a as u32, (a >> 32) as u32);
    let (bl, bh) = (b as u32, (b >> 32) as u32);
    let product = |x: u32, y: u32| u128::from(mul_u32(x, y));
    (product(ah, bh) << 64) + ((product(ah, bl) + product(al, bh)) << 32) + product(al, bl)
}
