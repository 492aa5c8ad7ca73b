//! `f64` arithmetic across a batch's lanes (feature `batch`): the same IEEE operations in
//! the same order as each lane's own `f64` code, written as loops over arrays so that the
//! compiler packs them (two lanes an instruction with SSE2, four in a build for AVX). A
//! division or a square root costs the divider the same time packed as alone, so a packed
//! one does two or four lanes' for the price of one; the results are the same bits.

/// Pixels shaded together: enough chains to fill the processor's window, little enough
/// stack per level of mirrors (about 5 KB in `f64`).
pub const BATCH: usize = 16;

/// Lanes of `f64`.
pub(crate) type Lanes = [f64; BATCH];

/// The square root of every lane, or 0 where it is not above 0 (as `f64`'s
/// [`Scalar::sqrt`](crate::scalar::Scalar::sqrt)).
#[inline(always)]
fn sqrt_or_zero(x: f64) -> f64 {
    #[cfg(feature = "std")]
    let root = x.sqrt();
    // Without `std` there is no square root the compiler can pack.
    #[cfg(not(feature = "std"))]
    let root = crate::scalar::sqrt_f64(x);
    if x > 0.0 { root } else { 0.0 }
}

/// `f(a, b)` lane by lane.
#[inline(always)]
pub(crate) fn map2(a: &Lanes, b: &Lanes, f: impl Fn(f64, f64) -> f64) -> Lanes {
    let mut out = [0.0; BATCH];
    for ((out, a), b) in out.iter_mut().zip(a).zip(b) {
        *out = f(*a, *b);
    }
    out
}

/// `f(a)` lane by lane.
#[inline(always)]
pub(crate) fn map(a: &Lanes, f: impl Fn(f64) -> f64) -> Lanes {
    let mut out = [0.0; BATCH];
    for (out, a) in out.iter_mut().zip(a) {
        *out = f(*a);
    }
    out
}

/// Unit directions `(dx, dy, dz) / |(dx, dy, dz)|` with `dy` and `dz` shared: as
/// [`Vec3::unit`](crate::vec3::Vec3::unit) in `f64` lane by lane. Returns the three
/// components and the length (a lane has no direction where the length is not above 0).
#[inline(always)]
pub(crate) fn unit_directions(dx: &Lanes, dy: f64, dz: f64) -> [Lanes; 4] {
    let length = map(dx, |dx| sqrt_or_zero(dx * dx + dy * dy + dz * dz));
    [
        map2(dx, &length, |dx, length| dx / length),
        map(&length, |length| dy / length),
        map(&length, |length| dz / length),
        length,
    ]
}

/// `world * i / n + shift - eye_x` for each lane's `i`: the positions of a row's pixels on
/// the image plane (as [`Scalar::mul_ratio`](crate::scalar::Scalar::mul_ratio)), moved by
/// `shift`, less the eye's `x`.
#[inline(always)]
pub(crate) fn row_offsets(world: f64, i: &[u16; BATCH], n: u16, shift: f64, eye_x: f64) -> Lanes {
    let mut dx = [0.0; BATCH];
    let n = f64::from(n);
    for (dx, i) in dx.iter_mut().zip(i) {
        *dx = world * f64::from(*i) / n + shift - eye_x;
    }
    dx
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scalar::Scalar;
    use crate::vec3::Vec3;

    #[test]
    fn unit_directions_are_vec3_unit_bit_for_bit() {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 20.0 - 10.0
        };
        for round in 0..2000 {
            let mut dx = [0.0; BATCH];
            for d in &mut dx {
                *d = next();
            }
            // Zero vectors and tiny ones too.
            let (dy, dz) = match round % 4 {
                0 => (0.0, 0.0),
                1 => (1e-160, -1e-170),
                _ => (next(), next()),
            };
            dx[3] = 0.0;
            dx[5] = -0.0;
            let [x, y, z, length] = unit_directions(&dx, dy, dz);
            for k in 0..BATCH {
                let v = Vec3::new(dx[k], dy, dz);
                assert_eq!(length[k].to_bits(), Scalar::length(v).to_bits());
                match v.unit() {
                    Some(u) => {
                        assert!(length[k] > 0.0);
                        assert_eq!(
                            [x[k].to_bits(), y[k].to_bits(), z[k].to_bits()],
                            [u.x.to_bits(), u.y.to_bits(), u.z.to_bits()]
                        );
                    }
                    None => assert!(!(length[k] > 0.0)),
                }
            }
        }
    }
}
