//! Error diffusion, one row at a time: each pixel's quantization error is spread over the
//! pixels not yet quantized, so the picture keeps its local means at full resolution.
//!
//! The row memory is the caller's, a slice of `i16` cells: [`Diffusion::cells`] for a
//! width (2 rows for Floyd-Steinberg, 3 for Atkinson, each `width` x channels cells; twice
//! that in bytes). For a 128-pixel one-bit panel, Floyd-Steinberg takes 512 bytes and
//! Atkinson 768; for a 240-pixel Rgb565 panel, 2,880 and 4,320.
//!
//! Values are kept in 16ths of an 8-bit step (so grey keeps a 16th of the luma's fraction).
//! A pixel's wanted value (its colour plus the errors it received) is clamped to the panel's
//! range, the nearest level is taken, and the error against that level as the panel shows it
//! (`round(255 q / max)`, [`expand`](super::color::expand)) is spread: Floyd-Steinberg's 7, 3, 5, 1 sixteenths
//! (the rounding remainder to the pixel below, so the whole error moves on), or Atkinson's
//! six eighths (a quarter is dropped: sharper, lighter shadows). Errors leaving the row's
//! ends are dropped. In serpentine order odd rows run right to left with the kernel
//! mirrored. All integer arithmetic: host and firmware agree bit for bit.

use super::color::{PanelColor, channels, expand_by, expand_scale, fine_values};
use super::ordered::level;
use core::marker::PhantomData;
use embedded_graphics::pixelcolor::Rgb888;

/// An error-diffusion kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kernel {
    /// Floyd and Steinberg (1976): 7/16 right, 3/16, 5/16, 1/16 on the next row.
    FloydSteinberg,
    /// Bill Atkinson's (Apple, 1984): 1/8 each to two on the right, three below, one two
    /// rows down; 3/4 of the error is kept.
    Atkinson,
}

impl Kernel {
    /// Rows of errors the kernel keeps: the current one and those it reaches.
    pub const fn rows(self) -> usize {
        match self {
            Kernel::FloydSteinberg => 2,
            Kernel::Atkinson => 3,
        }
    }
}

/// Why a diffusion cannot start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SetupError {
    /// The row memory holds fewer cells than [`Diffusion::cells`] asks for.
    TooLittleMemory {
        /// The cells needed.
        needed: usize,
        /// The cells given.
        given: usize,
    },
}

impl core::fmt::Display for SetupError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SetupError::TooLittleMemory { needed, given } => write!(
                f,
                "the error diffusion needs {needed} cells of row memory ({} bytes), given {given}",
                needed * 2
            ),
        }
    }
}

impl core::error::Error for SetupError {}

/// Adds a pixel's colour, in 16ths, to its cells (the errors it has received).
#[inline(always)]
fn add_colour<C: PanelColor>(cells: &mut [i16], c: Rgb888) {
    for (cell, v) in cells.iter_mut().zip(fine_values::<C>(c)) {
        let wanted = i32::from(*cell) + (v >> 4) as i32;
        *cell = wanted.clamp(i32::from(i16::MIN), i32::from(i16::MAX)) as i16;
    }
}

/// One channel of a row: where its cells are and how it quantizes.
struct Channel {
    k: usize,
    n: usize,
    width: usize,
    backwards: bool,
    max: u8,
    scale: u32,
}

/// An error as a cell holds it.
fn cell(e: i32) -> i16 {
    e.clamp(-32768, 32767) as i16
}

impl Channel {
    /// The cells of the row's pixels in the row's order: the first, and the step.
    #[inline(always)]
    fn cells(&self) -> (usize, isize) {
        let stride = self.n as isize;
        if self.backwards {
            ((self.width.saturating_sub(1)) * self.n + self.k, -stride)
        } else {
            (self.k, stride)
        }
    }

    /// Quantizes the wanted value in `cell` (replaced by the level); the error.
    #[inline(always)]
    fn quantize(&self, cell: &mut i16, carried: i32) -> i32 {
        let wanted = (i32::from(*cell) + carried).clamp(0, TOP);
        // The nearest level: floor((w max + 2040) / 4080), division-free as the ordered
        // dithers do it (w in 16ths is w 16 in 256ths).
        let q = level((wanted as u32) << 4, self.max, 32640);
        *cell = i16::from(q);
        wanted - i32::from(expand_by(q, self.scale)) * 16
    }

    /// Floyd-Steinberg: the error to the right is carried in a register, and each cell of
    /// the next row (which only this row reaches) is written once, when it is complete.
    fn floyd_steinberg(&self, current: &mut [i16], next: &mut [i16]) {
        // Next row: the sum so far for the previous pixel's cell and for this one's.
        let (mut right, mut behind, mut here) = (0, 0, 0);
        let (mut at, step) = self.cells();
        let mut previous = None;
        for _ in 0..self.width {
            let Some(c) = current.get_mut(at) else {
                return;
            };
            let e = self.quantize(c, right);
            let (r, back, on) = (e * 7 / 16, e * 3 / 16, e / 16);
            right = r;
            if let Some(prev) = previous.and_then(|p| next.get_mut(p)) {
                *prev = cell(behind + back);
            }
            behind = here + (e - r - back - on);
            here = on;
            previous = Some(at);
            at = at.wrapping_add_signed(step);
        }
        if let Some(last) = previous.and_then(|p| next.get_mut(p)) {
            *last = cell(behind);
        }
    }

    /// Atkinson: an eighth to two on the right (in registers), three below (added: the row
    /// before also reached that row) and one two rows down (written: this row is the first
    /// to reach it).
    fn atkinson(&self, current: &mut [i16], next: &mut [i16], after: &mut [i16]) {
        let (mut right, mut right2) = (0, 0);
        // The eighths of the last two pixels.
        let (mut e1, mut e2) = (0, 0);
        let (mut at, step) = self.cells();
        let mut previous = None;
        for _ in 0..self.width {
            let Some(c) = current.get_mut(at) else {
                return;
            };
            let e = self.quantize(c, right) / 8;
            right = right2 + e;
            right2 = e;
            if let Some(prev) = previous.and_then(|p| next.get_mut(p)) {
                *prev = cell(i32::from(*prev) + e2 + e1 + e);
            }
            if let Some(below2) = after.get_mut(at) {
                *below2 = cell(e);
            }
            e2 = e1;
            e1 = e;
            previous = Some(at);
            at = at.wrapping_add_signed(step);
        }
        if let Some(last) = previous.and_then(|p| next.get_mut(p)) {
            *last = cell(i32::from(*last) + e2 + e1);
        }
    }
}

/// The largest value, 255 in 16ths.
const TOP: i32 = 255 * 16;

/// An error diffusion into the format `C`, `width` pixels a row, its rows in `M` (the
/// caller's: a `&mut [i16]` or `&mut [i16; N]`, or a `Vec<i16>` on a host).
///
/// Feed a row with [`set`](Self::set) (any order within the row), then
/// [`finish_row`](Self::finish_row) quantizes it and [`levels`](Self::levels) reads it out;
/// [`next_row`](Self::next_row) moves on.
///
/// ```
/// use embedded_graphics::pixelcolor::{BinaryColor, Rgb888};
/// use microray::dither::{Diffusion, Kernel};
///
/// let mut memory = [0i16; Diffusion::<BinaryColor>::cells(Kernel::FloydSteinberg, 4)];
/// let mut d = Diffusion::<BinaryColor, _>::new(Kernel::FloydSteinberg, false, 4, &mut memory)?;
/// let mut on = 0;
/// for _ in 0..4 {
///     for x in 0..4 {
///         d.set(x, Rgb888::new(128, 128, 128));
///     }
///     d.finish_row();
///     on += d.levels().filter(|c| c.is_on()).count();
///     d.next_row();
/// }
/// assert_eq!(on, 8); // half of the 16 pixels
/// # Ok::<(), microray::dither::SetupError>(())
/// ```
#[derive(Debug)]
pub struct Diffusion<C, M = &'static mut [i16]> {
    kernel: Kernel,
    serpentine: bool,
    width: usize,
    /// Its first [`cells`](Self::cells) hold the rows.
    memory: M,
    /// Rows finished since the start (the serpentine's parity).
    row: usize,
    /// The current row's place in the ring (`row` modulo the kernel's rows).
    base: usize,
    color: PhantomData<C>,
}

impl<C: PanelColor> Diffusion<C> {
    /// The `i16` cells of row memory `kernel` needs for rows of `width` pixels.
    pub const fn cells(kernel: Kernel, width: usize) -> usize {
        kernel.rows() * width * channels::<C>()
    }
}

impl<C: PanelColor, M: AsMut<[i16]> + AsRef<[i16]>> Diffusion<C, M> {
    /// A diffusion over rows of `width` pixels (serpentine: odd rows right to left), its
    /// rows in `memory` (at least [`cells`](Diffusion::cells); cleared here).
    pub fn new(
        kernel: Kernel,
        serpentine: bool,
        width: usize,
        mut memory: M,
    ) -> Result<Self, SetupError> {
        let needed = Diffusion::<C>::cells(kernel, width);
        let given = memory.as_ref().len();
        memory
            .as_mut()
            .get_mut(..needed)
            .ok_or(SetupError::TooLittleMemory { needed, given })?
            .fill(0);
        Ok(Diffusion {
            kernel,
            serpentine,
            width,
            memory,
            row: 0,
            base: 0,
            color: PhantomData,
        })
    }

    /// The row width.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rows finished since the start (or the last [`reset`](Self::reset)).
    pub fn rows_done(&self) -> usize {
        self.row
    }

    /// Starts again at the top: no errors carried.
    pub fn reset(&mut self) {
        let needed = Diffusion::<C>::cells(self.kernel, self.width);
        if let Some(rows) = self.memory.as_mut().get_mut(..needed) {
            rows.fill(0);
        }
        self.row = 0;
        self.base = 0;
    }

    /// The cells of the row `ahead` rows below the current one.
    fn ring(&mut self, ahead: usize) -> &mut [i16] {
        let span = self.span(ahead);
        self.memory.as_mut().get_mut(span).unwrap_or(&mut [])
    }

    /// Where the row `ahead` rows below the current one lies in the memory.
    fn span(&self, ahead: usize) -> core::ops::Range<usize> {
        let len = self.width * channels::<C>();
        let mut k = self.base + ahead;
        if k >= self.kernel.rows() {
            k -= self.kernel.rows();
        }
        k * len..(k + 1) * len
    }

    /// Adds pixel `x`'s colour to the errors it has received (columns past the width are
    /// ignored).
    #[inline]
    pub fn set(&mut self, x: usize, c: Rgb888) {
        let n = channels::<C>();
        if let Some(cells) = self.ring(0).get_mut(x * n..(x + 1) * n) {
            add_colour::<C>(cells, c);
        }
    }

    /// [`set`](Self::set) for pixels `0, 1, ...` of the row from `colors` (those past the
    /// width are left); the pixels set.
    #[inline]
    pub fn set_row(&mut self, colors: impl IntoIterator<Item = Rgb888>) -> usize {
        let n = channels::<C>();
        let mut count = 0;
        for (cells, c) in self.ring(0).chunks_exact_mut(n).zip(colors) {
            add_colour::<C>(cells, c);
            count += 1;
        }
        count
    }

    /// Quantizes the current row, in its order, spreading the errors; its cells then hold
    /// the levels.
    pub fn finish_row(&mut self) {
        let n = channels::<C>();
        let len = self.width * n;
        let rows = self.kernel.rows();
        let (kernel, width, base) = (self.kernel, self.width, self.base);
        let backwards = self.serpentine && self.row % 2 == 1;
        let Some(memory) = self.memory.as_mut().get_mut(..rows * len) else {
            return;
        };
        // The ring's rows in order from the current one, split once a row.
        let mut parts = memory.chunks_exact_mut(len.max(1));
        let mut ring = [parts.next(), parts.next(), parts.next()];
        if let Some(used) = ring.get_mut(..rows) {
            used.rotate_left(base);
        }
        let [Some(current), Some(next), after] = ring else {
            return;
        };
        let mut none = [0i16; 0];
        let after = after.unwrap_or(&mut none);
        for (k, &max) in C::MAX.iter().enumerate().take(n) {
            let channel = Channel {
                k,
                n,
                width,
                backwards,
                max,
                scale: expand_scale(max),
            };
            match kernel {
                Kernel::FloydSteinberg => channel.floyd_steinberg(current, next),
                Kernel::Atkinson => channel.atkinson(current, next, after),
            }
        }
    }

    /// The current row's colours, left to right (after [`finish_row`](Self::finish_row)).
    pub fn levels(&self) -> impl Iterator<Item = C> + '_ {
        let n = channels::<C>();
        let row = self.memory.as_ref().get(self.span(0)).unwrap_or(&[]);
        row.chunks_exact(n.max(1)).map(move |cells| {
            let level = |i: usize| cells.get(i).map_or(0, |&v| v.clamp(0, 255) as u8);
            C::from_levels([level(0), level(1), level(2)])
        })
    }

    /// Moves to the next row: the current row's cells are cleared for the furthest one.
    pub fn next_row(&mut self) {
        self.ring(0).fill(0);
        self.row += 1;
        self.base = if self.base + 1 == self.kernel.rows() {
            0
        } else {
            self.base + 1
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_graphics::pixelcolor::{BinaryColor, Gray2, Rgb565, RgbColor};

    fn run<C: PanelColor>(kernel: Kernel, serpentine: bool, image: &[Vec<Rgb888>]) -> Vec<Vec<C>> {
        let width = image[0].len();
        let mut memory = vec![0i16; Diffusion::<C>::cells(kernel, width)];
        let mut d = Diffusion::<C, _>::new(kernel, serpentine, width, &mut memory).unwrap();
        image
            .iter()
            .map(|row| {
                for (x, &c) in row.iter().enumerate().rev() {
                    d.set(x, c);
                }
                d.finish_row();
                let out = d.levels().collect();
                d.next_row();
                out
            })
            .collect()
    }

    #[test]
    fn too_little_memory_is_an_error() {
        let mut memory = [0i16; 11];
        let e =
            Diffusion::<Gray2, _>::new(Kernel::FloydSteinberg, false, 6, &mut memory).unwrap_err();
        assert_eq!(
            e,
            SetupError::TooLittleMemory {
                needed: 12,
                given: 11
            }
        );
        assert!(e.to_string().contains("24 bytes"));
        assert_eq!(Diffusion::<Rgb565>::cells(Kernel::Atkinson, 240) * 2, 4320);
    }

    #[test]
    fn floyd_steinberg_keeps_a_flat_mean() {
        // A flat grey on a one-bit panel: the share of pixels on is the grey's share.
        for v in [16u8, 64, 100, 128, 200, 240] {
            for serpentine in [false, true] {
                let image = vec![vec![Rgb888::new(v, v, v); 64]; 64];
                let out = run::<BinaryColor>(Kernel::FloydSteinberg, serpentine, &image);
                let on = out.iter().flatten().filter(|c| c.is_on()).count() as f64;
                let share = on / 4096.0;
                // Errors leave at the right edge and the bottom: a few rows' worth.
                assert!((share - f64::from(v) / 255.0).abs() < 0.01, "{v}: {share}");
            }
        }
    }

    #[test]
    fn atkinson_keeps_flat_areas_clean_and_loses_extremes() {
        // Atkinson drops a quarter of each error: near-black areas go wholly black.
        let image = vec![vec![Rgb888::new(20, 20, 20); 32]; 32];
        let out = run::<BinaryColor>(Kernel::Atkinson, false, &image);
        let on = out.iter().flatten().filter(|c| c.is_on()).count();
        let fs = run::<BinaryColor>(Kernel::FloydSteinberg, false, &image);
        let fs_on = fs.iter().flatten().filter(|c| c.is_on()).count();
        assert!(on < fs_on, "{on} {fs_on}");
        let mid = vec![vec![Rgb888::new(128, 128, 128); 32]; 32];
        let out = run::<BinaryColor>(Kernel::Atkinson, false, &mid);
        let on = out.iter().flatten().filter(|c| c.is_on()).count();
        assert!((450..=574).contains(&on), "{on}");
    }

    #[test]
    fn serpentine_rows_alternate() {
        // One row: the first pixel of a left-to-right row is decided by itself alone; in a
        // right-to-left row the last is.
        let mut image = vec![vec![Rgb888::new(100, 100, 100); 8]; 2];
        image[1][7] = Rgb888::new(180, 180, 180);
        let plain = run::<BinaryColor>(Kernel::FloydSteinberg, false, &image);
        let snake = run::<BinaryColor>(Kernel::FloydSteinberg, true, &image);
        assert_eq!(plain[0], snake[0]);
        assert_ne!(plain[1], snake[1]);
        // The snake's second row starts at its right end: 180 plus what it received.
        assert!(snake[1][7].is_on());
    }

    #[test]
    fn levels_are_in_range_for_extremes() {
        let mut image = vec![vec![Rgb888::WHITE; 16]; 8];
        for (y, row) in image.iter_mut().enumerate() {
            for (x, c) in row.iter_mut().enumerate() {
                if (x + y) % 3 == 0 {
                    *c = Rgb888::BLACK;
                }
            }
        }
        for kernel in [Kernel::FloydSteinberg, Kernel::Atkinson] {
            for row in run::<Rgb565>(kernel, true, &image) {
                for c in row {
                    assert!(c.r() <= 31 && c.g() <= 63 && c.b() <= 31);
                }
            }
            // White and black are levels: nothing to spread, the image is exact.
            let out = run::<Gray2>(kernel, false, &image);
            for (row, want) in out.iter().zip(&image) {
                for (c, w) in row.iter().zip(want) {
                    assert_eq!(c.levels()[0], if *w == Rgb888::WHITE { 3 } else { 0 });
                }
            }
        }
    }
}
