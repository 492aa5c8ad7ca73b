//! Rgb565 output: the tracer's 8-bit channels to a panel's 5-6-5, truncated or with an
//! ordered (Bayer 4x4) dither that needs no memory at all.
//!
//! [`Rgb565Dither`] wraps an `Rgb565` [`DrawTarget`](https://docs.rs/embedded-graphics/0.8/embedded_graphics/draw_target/trait.DrawTarget.html) and is itself an `Rgb888` one: the
//! renderer draws into it as into any target, and each pixel is dithered by its position as
//! it passes through (rows, blocks of the progressive order and single pixels alike). The
//! dither is integer arithmetic only, so host and firmware frames agree byte for byte.
//!
//! A channel `v` (0 to 255) becomes `floor(v n / 255 + (m + 1/2) / 16)` for `n` = 31 (red,
//! blue) or 63 (green) levels, `m` the pixel's entry of the 4x4 Bayer matrix: over every 4x4
//! tile the 16 thresholds are evenly spread over one level, so the tile's mean is the exact
//! scaled value (truncation loses half a level on average, and bands gradients). The
//! largest value stays within its level count without clamping.

use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::{Dimensions, DrawTarget, Pixel, Point, PointsIter};
use embedded_graphics::primitives::Rectangle;

/// The 4x4 Bayer matrix (rows by `y`, columns by `x`).
#[cfg(test)]
const BAYER: [[u16; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// The thresholds in 255ths of a level: `floor((2m + 1) 255 / 32)` for each Bayer entry
/// `m` of the 4x4 Bayer matrix (checked against it by the tests).
#[cfg(test)]
const THRESHOLDS: [[u16; 4]; 4] = [
    [7, 135, 39, 167],
    [199, 71, 231, 103],
    [55, 183, 23, 151],
    [247, 119, 215, 87],
];

/// Each threshold `t` of [`THRESHOLDS`] as the offset `(t + 1) 257` that [`quantize`] adds
/// (checked against them by the tests).
const OFFSETS: [[u32; 4]; 4] = [
    [2056, 34952, 10280, 43176],
    [51400, 18504, 59624, 26728],
    [14392, 47288, 6168, 39064],
    [63736, 30840, 55512, 22616],
];

/// `floor((v levels 32 + (2m + 1) 255) / (255 32))` for a Bayer entry `m` whose threshold is
/// `t`: `a = v levels + t` is the numerator over 32, floored (`v levels 32` is a multiple of
/// 32). The reference [`quantize`] is tested against.
#[cfg(test)]
fn channel(v: u8, levels: u16, t: u16) -> u8 {
    ((u32::from(v) * u32::from(levels) + u32::from(t)) / 255) as u8
}

/// The pixel at `p` of colour `c`, dithered to Rgb565.
#[inline]
pub fn dither_rgb565(c: Rgb888, p: Point) -> Rgb565 {
    let row = OFFSETS.get((p.y & 3) as usize).copied().unwrap_or([0; 4]);
    quantize(c, row.get((p.x & 3) as usize).copied().unwrap_or(0))
}

/// `c` to Rgb565 with the offset `k = (t + 1) 257` of threshold `t`: per channel
/// `floor((v levels + t) / 255)` as `((v levels + t + 1) 257) >> 16`, exact while the
/// quotient stays below 257 (here below 64): one multiply-add and a shift, no division (the
/// Cortex-M0 has none).
#[inline(always)]
fn quantize(c: Rgb888, k: u32) -> Rgb565 {
    let r = (u32::from(c.r()) * (31 * 257) + k) >> 16;
    let g = (u32::from(c.g()) * (63 * 257) + k) >> 16;
    let b = (u32::from(c.b()) * (31 * 257) + k) >> 16;
    // Rgb565's storage: red in bits 11-15, green 5-10, blue 0-4.
    Rgb565::from(RawU16::new(((r << 11) | (g << 5) | b) as u16))
}

/// `c` truncated to Rgb565 (the top 5, 6 and 5 bits): what a panel shows without a dither.
#[inline]
pub fn truncate_rgb565(c: Rgb888) -> Rgb565 {
    Rgb565::new(c.r() >> 3, c.g() >> 2, c.b() >> 3)
}

/// An `Rgb888` target in front of an `Rgb565` one, dithering each pixel on its way
/// ([`dither_rgb565`]). No memory: each pixel is converted as the inner target takes it.
///
/// ```
/// use embedded_graphics::{mock_display::MockDisplay, pixelcolor::{Rgb565, Rgb888}, prelude::*};
/// use microray::{dither::Rgb565Dither, parse::{no_textures, parse_scene}, render::render, Scene};
///
/// let text = b"camera c { pixeldim 8 6 worlddim 8 6 viewpoint 4 3 4 }
///              material grey { ambient 1 1 1 diffuse 3 3 3 }
///              plane floor { material grey normal 0 1 0 point 0 0 0 }
///              light sun { location 4 5 -2 emissivity 4 4 4 }";
/// let scene: Scene<f32, 2, 1, 1, 0, 8> = parse_scene(text, no_textures)?;
/// let mut panel: MockDisplay<Rgb565> = MockDisplay::new();
/// render(&scene, &mut Rgb565Dither::new(&mut panel))?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Rgb565Dither<'t, T> {
    inner: &'t mut T,
    dither: bool,
}

impl<'t, T> Rgb565Dither<'t, T> {
    /// Dithers into `inner` (borrowed for as long as the wrapper lives).
    pub fn new(inner: &'t mut T) -> Self {
        Self {
            inner,
            dither: true,
        }
    }

    /// Truncates into `inner` instead ([`truncate_rgb565`]) until
    /// [`set_dither`](Self::set_dither) turns the dither on: one target type for both, so
    /// that a panel can switch at run time.
    pub fn truncating(inner: &'t mut T) -> Self {
        Self {
            inner,
            dither: false,
        }
    }

    /// Turns the dither on or off (off: truncation).
    pub fn set_dither(&mut self, dither: bool) {
        self.dither = dither;
    }
}

impl<T: Dimensions> Dimensions for Rgb565Dither<'_, T> {
    fn bounding_box(&self) -> Rectangle {
        self.inner.bounding_box()
    }
}

impl<T: DrawTarget<Color = Rgb565>> DrawTarget for Rgb565Dither<'_, T> {
    type Color = Rgb888;
    type Error = T::Error;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Self::Error> {
        let dither = self.dither;
        self.inner.draw_iter(pixels.into_iter().map(|Pixel(p, c)| {
            let converted = if dither {
                dither_rgb565(c, p)
            } else {
                truncate_rgb565(c)
            };
            Pixel(p, converted)
        }))
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Self::Error> {
        if !self.dither {
            let truncated = colors.into_iter().map(truncate_rgb565);
            return self.inner.fill_contiguous(area, truncated);
        }
        if area.size.height == 1 {
            // A row (the renderer's case): one row of thresholds, the column by counting.
            let row = OFFSETS
                .get((area.top_left.y & 3) as usize)
                .copied()
                .unwrap_or([0; 4]);
            let mut x = (area.top_left.x & 3) as usize;
            let dithered = colors.into_iter().map(|c| {
                let t = row.get(x).copied().unwrap_or(0);
                x = (x + 1) & 3;
                quantize(c, t)
            });
            return self.inner.fill_contiguous(area, dithered);
        }
        let dithered = area.points().zip(colors).map(|(p, c)| dither_rgb565(c, p));
        self.inner.fill_contiguous(area, dithered)
    }

    fn fill_solid(&mut self, area: &Rectangle, color: Rgb888) -> Result<(), Self::Error> {
        if !self.dither {
            return self.inner.fill_solid(area, truncate_rgb565(color));
        }
        let dithered = area.points().map(|p| dither_rgb565(color, p));
        self.inner.fill_contiguous(area, dithered)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The threshold of Bayer entry `m`.
    fn threshold(m: u16) -> u16 {
        (2 * m + 1) * 255 / 32
    }

    #[test]
    fn the_thresholds_are_the_bayer_matrix() {
        for (row, bayer) in THRESHOLDS.iter().zip(BAYER) {
            for (&t, m) in row.iter().zip(bayer) {
                assert_eq!(t, threshold(m));
            }
        }
    }

    #[test]
    fn the_offsets_are_the_thresholds() {
        for (offsets, thresholds) in OFFSETS.iter().zip(THRESHOLDS) {
            for (&k, t) in offsets.iter().zip(thresholds) {
                assert_eq!(k, (u32::from(t) + 1) * 257);
            }
        }
    }

    #[test]
    fn the_threshold_form_is_the_exact_level() {
        for v in 0..=255u8 {
            for levels in [31u16, 63] {
                for m in 0..16u16 {
                    let exact = (u32::from(v) * u32::from(levels) * 32
                        + (2 * u32::from(m) + 1) * 255)
                        / (255 * 32);
                    assert_eq!(u32::from(channel(v, levels, threshold(m))), exact);
                }
            }
        }
    }

    #[test]
    fn the_multiply_shift_form_is_the_division() {
        // Every red and blue value with every threshold (green runs alongside).
        for r in 0..=255u8 {
            for b in 0..=255u8 {
                for m in 0..16u16 {
                    let t = threshold(m);
                    let g = r.wrapping_add(b);
                    let alone =
                        Rgb565::new(channel(r, 31, t), channel(g, 63, t), channel(b, 31, t));
                    let k = (u32::from(t) + 1) * 257;
                    assert_eq!(quantize(Rgb888::new(r, g, b), k), alone, "{r} {g} {b} {t}");
                }
            }
        }
    }

    #[test]
    fn every_tile_keeps_the_mean_and_stays_in_range() {
        for v in 0..=255u8 {
            for (levels, expanded) in [(31u16, 255.0 / 31.0), (63, 255.0 / 63.0)] {
                let mut sum = 0.0;
                for m in 0..16 {
                    let q = channel(v, levels, threshold(m));
                    assert!(u16::from(q) <= levels, "{v} {levels} {m}");
                    sum += f64::from(q) * expanded;
                }
                // The tile's mean of the expanded levels is v within rounding of the
                // thresholds (at most half of a sixteenth of a level).
                let mean = sum / 16.0;
                assert!(
                    (mean - f64::from(v)).abs() <= expanded / 32.0 + 1e-9,
                    "{v}: {mean}"
                );
            }
        }
    }

    #[test]
    fn flat_colours_on_a_level_are_not_dithered() {
        // A value exactly on a level stays there at every threshold.
        for level in 0..=31u8 {
            let v = (u32::from(level) * 255 / 31) as u8;
            if u32::from(v) * 31 % 255 == 0 {
                for m in 0..16 {
                    assert_eq!(channel(v, 31, threshold(m)), level);
                }
            }
        }
        assert_eq!(
            dither_rgb565(Rgb888::WHITE, Point::new(3, 2)),
            Rgb565::WHITE
        );
        assert_eq!(
            dither_rgb565(Rgb888::BLACK, Point::new(1, 0)),
            Rgb565::BLACK
        );
    }
}
