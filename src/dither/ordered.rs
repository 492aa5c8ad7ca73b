//! Ordered dithers: a threshold per screen position from a tiled matrix, no memory, any
//! drawing order (rows, blocks of the progressive order, single pixels, patches).
//!
//! A channel of fine value `x` (256ths of an 8-bit step, [`fine_values`]) becomes level
//! `floor(x max / 65280 + (r + 1/2) / R)` for the pixel's rank `r` of the matrix's `R`
//! ranks: over a tile the thresholds spread evenly over one level, so a flat area keeps its
//! exact mean, where truncation loses half a level and bands gradients.

use super::blue_noise::BLUE_NOISE;
use super::color::{PanelColor, fine_values};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::Point;

/// A threshold matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Matrix {
    /// Bayer's 2x2 matrix (4 ranks).
    Bayer2,
    /// Bayer's 4x4 matrix (16 ranks).
    Bayer4,
    /// Bayer's 8x8 matrix (64 ranks).
    Bayer8,
    /// 32x32 blue noise by void and cluster (1,024 ranks stored as 256: 1 KiB of flash);
    /// see [`blue_noise`](super::blue_noise).
    BlueNoise,
}

/// Bayer's `N`x`N` matrix (`N` a power of two): `B(2n) = [[4B, 4B+2], [4B+3, 4B+1]]`.
// Evaluated at compile time only: an index out of range fails the build, not a program.
#[allow(clippy::indexing_slicing)]
const fn bayer<const N: usize>() -> [[u8; N]; N] {
    let two = [[0u8, 2], [3, 1]];
    let mut m = [[0u8; N]; N];
    let mut s = 1;
    while s < N {
        let old = m;
        let mut y = 0;
        while y < 2 * s {
            let mut x = 0;
            while x < 2 * s {
                m[y][x] = 4 * old[y % s][x % s] + two[y / s][x / s];
                x += 1;
            }
            y += 1;
        }
        s *= 2;
    }
    m
}

const BAYER2: [[u8; 2]; 2] = bayer::<2>();
const BAYER4: [[u8; 4]; 4] = bayer::<4>();
const BAYER8: [[u8; 8]; 8] = bayer::<8>();

/// The rank of `p` in an `N`x`N` table, tiled.
#[inline(always)]
fn rank_in<const N: usize>(table: &[[u8; N]; N], p: Point) -> u32 {
    let (x, y) = (p.x as usize & (N - 1), p.y as usize & (N - 1));
    table
        .get(y)
        .and_then(|row| row.get(x))
        .map_or(0, |&r| u32::from(r))
}

impl Matrix {
    /// The threshold at `p` in 65280ths of a level: `(2r + 1) 65280 / 2R` for rank `r`.
    #[inline(always)]
    pub fn threshold(self, p: Point) -> u32 {
        match self {
            Matrix::Bayer2 => (2 * rank_in(&BAYER2, p) + 1) * 8160,
            Matrix::Bayer4 => (2 * rank_in(&BAYER4, p) + 1) * 2040,
            Matrix::Bayer8 => (2 * rank_in(&BAYER8, p) + 1) * 510,
            Matrix::BlueNoise => ((2 * rank_in(&BLUE_NOISE, p) + 1) * 255) >> 1,
        }
    }

    /// The matrix's side in pixels.
    pub const fn side(self) -> u32 {
        match self {
            Matrix::Bayer2 => 2,
            Matrix::Bayer4 => 4,
            Matrix::Bayer8 => 8,
            Matrix::BlueNoise => 32,
        }
    }
}

/// `floor((x max + t) / 65280)` without a division (the Cortex-M0 has none):
/// `floor(floor(y / 256) / 255)`, the second as `((z + 1) 257) >> 16`, exact for
/// `z < 65535` (here at most 65279).
#[inline(always)]
pub(crate) fn level(x: u32, max: u8, t: u32) -> u8 {
    let z = (x * u32::from(max) + t) >> 8;
    (((z + 1) * 257) >> 16) as u8
}

/// The pixel at `p` of colour `c`, dithered by `matrix` into the format `C`.
#[inline]
pub fn dither_ordered<C: PanelColor>(c: Rgb888, p: Point, matrix: Matrix) -> C {
    let t = matrix.threshold(p);
    let [a, b, d] = fine_values::<C>(c);
    let [ma, mb, md] = C::MAX;
    if C::GREY {
        C::from_levels([level(a, ma, t), 0, 0])
    } else {
        C::from_levels([level(a, ma, t), level(b, mb, t), level(d, md, t)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dither::color::Rgb332;
    use crate::dither::rgb565::dither_rgb565;
    use embedded_graphics::pixelcolor::{BinaryColor, Gray4, Rgb565, RgbColor};

    #[test]
    fn bayer_matrices_hold_every_rank_once() {
        fn check<const N: usize>(m: &[[u8; N]; N]) {
            let mut seen = [false; 64];
            for row in m {
                for &r in row {
                    assert!(!seen[usize::from(r)]);
                    seen[usize::from(r)] = true;
                }
            }
            assert!(seen[..N * N].iter().all(|&s| s));
        }
        check(&BAYER2);
        check(&BAYER4);
        check(&BAYER8);
        assert_eq!(
            BAYER4,
            [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]]
        );
    }

    #[test]
    fn the_division_free_level_is_the_division() {
        for z in 0..65535u32 {
            assert_eq!(((z + 1) * 257) >> 16, z / 255, "{z}");
        }
        for max in [1u8, 3, 7, 15, 31, 63, 255] {
            for x in (0..=65280u32).step_by(17).chain([65280]) {
                for t in [0, 1, 32639, 32640, 65279] {
                    let exact = (x * u32::from(max) + t) / 65280;
                    assert_eq!(u32::from(level(x, max, t)), exact, "{x} {max} {t}");
                    assert!(level(x, max, t) <= max);
                }
            }
        }
    }

    #[test]
    fn bayer4_into_rgb565_is_the_rgb565_dither() {
        for i in 0..40_000u32 {
            let c = Rgb888::new((i * 7) as u8, (i * 13 / 3) as u8, (i / 157) as u8);
            let p = Point::new((i % 11) as i32, (i / 5 % 9) as i32);
            let ours: Rgb565 = dither_ordered(c, p, Matrix::Bayer4);
            assert_eq!(ours, dither_rgb565(c, p), "{c:?} {p:?}");
        }
    }

    #[test]
    fn every_tile_keeps_the_mean() {
        // A flat grey over one tile of each matrix: the shown levels' mean is the value
        // within the threshold's rounding (a 2R-th of a level).
        for matrix in [
            Matrix::Bayer2,
            Matrix::Bayer4,
            Matrix::Bayer8,
            Matrix::BlueNoise,
        ] {
            let side = matrix.side() as i32;
            for v in (0..=255u8).step_by(5) {
                let c = Rgb888::new(v, v, v);
                let mut sum = 0.0;
                for y in 0..side {
                    for x in 0..side {
                        let q: Gray4 = dither_ordered(c, Point::new(x, y), matrix);
                        sum += f64::from(q.levels()[0]) * 255.0 / 15.0;
                    }
                }
                let mean = sum / f64::from(side * side);
                let ranks = if matrix == Matrix::BlueNoise {
                    256.0
                } else {
                    f64::from(side * side)
                };
                assert!(
                    (mean - f64::from(v)).abs() <= 17.0 / (2.0 * ranks) + 1e-9,
                    "{matrix:?} {v}: {mean}"
                );
            }
        }
    }

    #[test]
    fn black_and_white_stay() {
        for matrix in [Matrix::Bayer2, Matrix::Bayer8, Matrix::BlueNoise] {
            for i in 0..64 {
                let p = Point::new(i % 37, i / 3);
                assert_eq!(
                    dither_ordered::<BinaryColor>(Rgb888::WHITE, p, matrix),
                    BinaryColor::On
                );
                assert_eq!(
                    dither_ordered::<BinaryColor>(Rgb888::BLACK, p, matrix),
                    BinaryColor::Off
                );
                assert_eq!(
                    dither_ordered::<Rgb332>(Rgb888::WHITE, p, matrix),
                    Rgb332::WHITE
                );
            }
        }
    }
}
