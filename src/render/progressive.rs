//! Progressive rendering: the whole picture early, then refined, every pixel traced once.
//!
//! Pass 1 traces one pixel in every 8x8 block (its top-left one) and fills the block with
//! it; pass 2 the top-left pixel of every 4x4 block that pass 1 did not trace, filling 4x4
//! blocks; then 2x2; then every pixel left, one by one. A block never covers a pixel an
//! earlier pass traced (it lies in its own quarter of the block before), so when the last
//! pass ends every pixel holds its own colour: the image of
//! [`render_area`](super::Renderer::render_area), bit for bit (tests/progressive.rs checks
//! every scene in every number type).
//!
//! Each pixel is shaded as the plain order shades it: a row's plan (its object list, its
//! objects' row tests and, where its pixels share a plane, its row shading) is prepared
//! once per row and pass, and the row's traced pixels are shaded by the plain order's row
//! loop, segment by segment as the plain order cuts its rows, into the row buffer before
//! any is drawn. A row of a pass's own grid (every block
//! of it new) goes out as one `fill_contiguous` of its blocks side by side; the others'
//! blocks one `fill_solid` each; the last pass's rows traced whole as `render_area`'s rows,
//! and its single pixels as one `draw_iter` a row. Pass 1 traces 1/64 of the pixels, pass 2
//! 3/64, pass 3 12/64; the last pass traces the odd rows whole (1/2) and the odd pixels of
//! the even rows (1/4).

use super::{RenderError, Rendered, Renderer, RowTests};
use crate::scalar::Scalar;
use crate::shade::{Shader, ShadowCache};
use core::ops::ControlFlow;
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::{DrawTarget, Pixel, Point, Size};
use embedded_graphics::primitives::Rectangle;

/// The block sides of the passes, largest first.
pub const BLOCKS: [u16; 4] = [8, 4, 2, 1];

/// Sent to the pass callback after each pass is on the target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PassDone {
    /// The side of the blocks this pass filled (1: the last pass, every pixel its own).
    pub block: u16,
    /// Passes done so far, from 1.
    pub done: u8,
    /// Passes in all.
    pub total: u8,
}

/// The pixels of a row a pass traces: row `y`, from column `first`, `stride` apart, each
/// filling a `block`-sided square.
#[derive(Clone, Copy)]
struct Traced {
    y: u16,
    first: u16,
    stride: u16,
    block: u16,
}

impl<S: Scalar, const OBJECTS: usize> Renderer<'_, S, OBJECTS> {
    /// Renders the whole image into `target` progressively: four passes ([`BLOCKS`]), each on the target when `on_pass` is called,
    /// the last one leaving exactly the image [`render_area`](Self::render_area) draws.
    /// `row` is the row buffer (at least the image's width); returning
    /// `ControlFlow::Break` from `on_pass` stops after that pass. No heap: the pixels
    /// traced earlier stay on the target, not in memory.
    ///
    /// ```
    /// use core::ops::ControlFlow;
    /// use embedded_graphics::{mock_display::MockDisplay, pixelcolor::Rgb888, prelude::*};
    /// use microray::{parse::{no_textures, parse_scene}, render::Renderer, Scene};
    ///
    /// let text = b"camera c { pixeldim 16 12 worlddim 8 6 viewpoint 4 3 4 }
    ///              material red { ambient 2 0 0 diffuse 4 0 0 }
    ///              sphere ball { material red center 4 3 -6 radius 2 }";
    /// let scene: Scene<f32, 4, 2, 1, 0, 16> = parse_scene(text, no_textures)?;
    /// let renderer = Renderer::new(&scene);
    /// let mut display: MockDisplay<Rgb888> = MockDisplay::new();
    /// display.set_allow_overdraw(true);
    /// let mut row = [Rgb888::BLACK; 16];
    /// let mut blocks = Vec::new();
    /// renderer.render_progressive(&mut display, &mut row, |pass| {
    ///     blocks.push(pass.block);
    ///     ControlFlow::Continue(())
    /// })?;
    /// assert_eq!(blocks, [8, 4, 2, 1]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn render_progressive<D>(
        &self,
        target: &mut D,
        row: &mut [D::Color],
        mut on_pass: impl FnMut(PassDone) -> ControlFlow<()>,
    ) -> Result<Rendered, RenderError<D::Error>>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let total = BLOCKS.len() as u8;
        for (pass, &block) in BLOCKS.iter().enumerate() {
            self.render_pass(target, row, pass)?;
            let done = PassDone {
                block,
                done: pass as u8 + 1,
                total,
            };
            if on_pass(done).is_break() && block != 1 {
                return Ok(Rendered::StoppedAfterPass { block });
            }
        }
        Ok(Rendered::Complete)
    }

    /// Pass `pass` (0 to 3) of [`render_progressive`](Self::render_progressive) alone, for a
    /// caller that shows the target between passes (a window, a panel's refresh); the
    /// passes must run in order. A pass past the last draws nothing.
    pub fn render_pass<D>(
        &self,
        target: &mut D,
        row: &mut [D::Color],
        pass: usize,
    ) -> Result<(), RenderError<D::Error>>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let (width, height) = (self.camera.width(), self.camera.height());
        let len = row.len();
        let row = row
            .get_mut(..usize::from(width))
            .ok_or(RenderError::RowBufferTooSmall {
                needed: usize::from(width),
                len,
            })?;
        let Some(&block) = BLOCKS.get(pass) else {
            return Ok(());
        };
        let cache = ShadowCache::new();
        let shader = self.shader().with_shadow_cache(&cache);
        // The previous pass's block: its grid's pixels are traced already.
        let coarser = if pass == 0 { 0 } else { block * 2 };
        // The rows' object tests, prepared in place row by row.
        let mut tests = heapless::Vec::new();
        let mut y = 0;
        while y < height {
            // A row of the coarser grid keeps its traced pixels: only the ones between.
            let new_row = coarser == 0 || y % coarser != 0;
            if block == 1 && new_row {
                self.render_row(&shader, target, y, 0, &mut tests, row)?;
            } else {
                let (first, stride) = if new_row {
                    (0, block)
                } else {
                    (block, coarser)
                };
                let traced = Traced {
                    y,
                    first,
                    stride,
                    block,
                };
                self.row_of_blocks(&shader, target, traced, &mut tests, row)?;
            }
            y = y.saturating_add(block);
        }
        Ok(())
    }

    /// Traces the pixels of a row `traced` names into `row` (its tests prepared in
    /// `tests`), then fills a block from each.
    fn row_of_blocks<D>(
        &self,
        shader: &Shader<'_, S>,
        target: &mut D,
        traced: Traced,
        tests: &mut RowTests<S, OBJECTS>,
        row: &mut [D::Color],
    ) -> Result<(), RenderError<D::Error>>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let Traced {
            y,
            first,
            stride,
            block,
        } = traced;
        let camera_y = self.camera.row_from_top(y);
        let stride = stride.max(1);
        // Only the traced pixels, shaded as whole rows are.
        let count = usize::from(self.camera.width().saturating_sub(first).div_ceil(stride));
        let colors = row.get_mut(..count).unwrap_or_default();
        self.shade_every(shader, camera_y, first, stride, tests, colors);
        let columns = (first..self.camera.width()).step_by(usize::from(stride));
        let (width, height) = (self.camera.width(), self.camera.height());
        let rows = block.min(height.saturating_sub(y));
        if block > 1 && first == 0 && stride == block {
            // A row of this pass's own grid: its blocks side by side, one rectangle (one
            // call instead of one a block).
            let line = || {
                colors.iter().zip(columns.clone()).flat_map(move |(&c, x)| {
                    core::iter::repeat_n(c, usize::from(block.min(width.saturating_sub(x))))
                })
            };
            let area = Rectangle::new(
                Point::new(0, i32::from(y)),
                Size::new(u32::from(width), u32::from(rows)),
            );
            return target
                .fill_contiguous(&area, (0..rows).flat_map(|_| line()))
                .map_err(RenderError::Target);
        }
        let pixels = columns.zip(colors.iter().copied());
        if block == 1 {
            let y = i32::from(y);
            let pixels = pixels.map(|(x, c)| Pixel(Point::new(i32::from(x), y), c));
            return target.draw_iter(pixels).map_err(RenderError::Target);
        }
        for (x, color) in pixels {
            let square = Rectangle::new(
                Point::new(i32::from(x), i32::from(y)),
                Size::new(
                    u32::from(block.min(width.saturating_sub(x))),
                    u32::from(rows),
                ),
            );
            target
                .fill_solid(&square, color)
                .map_err(RenderError::Target)?;
        }
        Ok(())
    }
}
