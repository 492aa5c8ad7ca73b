//! Anti-aliasing with fixed sample positions: the same frame on every run and every
//! machine (the course's `aademo` jittered its samples at random).
//!
//! A pixel's samples lie on a grid of `side x side` points ([`Samples`]): sample `k` of
//! every pixel of a row sits at the same offset from the pixel's point, so the samples
//! with one `k` form a whole row of rays, shifted. Each is rendered as a row is (the plan's
//! object list, row tests and shared shading all apply), and the bytes are summed per
//! pixel and averaged, rounding to nearest. One sample is the plain render, bit for bit.
//!
//! [`Antialias::Adaptive`] traces the plain render's rays first and supersamples only the
//! pixels that differ from a neighbour (left, right, above or below): another object seen,
//! or a channel more than the threshold apart. It keeps two rows (the row being drawn and
//! the one below it) and never more.
//!
//! ```
//! use embedded_graphics::{mock_display::MockDisplay, pixelcolor::Rgb888, prelude::*};
//! use embedded_graphics::primitives::Rectangle;
//! use microray::parse::{no_textures, parse_scene};
//! use microray::render::{AaPixel, Antialias, Renderer, Samples};
//! use microray::Scene;
//! use core::ops::ControlFlow;
//!
//! let text = b"camera c { pixeldim 16 12 worlddim 8 6 viewpoint 4 3 4 }
//!              material red { ambient 50 0 0 }
//!              sphere ball { material red center 4 3 -2 radius 2 }";
//! let scene: Scene<f32, 4, 4, 2, 0, 16> = parse_scene(text, no_textures)?;
//! let renderer = Renderer::new(&scene);
//! let aa = Antialias::Adaptive { samples: Samples::rotated(16).ok_or("not a square")?, threshold: 8 };
//! // Two rows and a pixel each side: no frame in memory.
//! let mut buffer = [AaPixel::NEW; Antialias::buffer_len(16)];
//! let mut display = MockDisplay::<Rgb888>::new();
//! let all = Rectangle::new(Point::zero(), renderer.size());
//! renderer
//!     .render_antialiased(&mut display, all, aa, &mut buffer, |_| ControlFlow::Continue(()))
//!     .map_err(|_| "display error")?;
//! // The ball's middle is plain red (its ambient saturates); its rim is blended with the
//! // black around it, where a plain render has only full red and black.
//! assert_eq!(display.get_pixel(Point::new(8, 6)), Some(Rgb888::new(255, 0, 0)));
//! let reds = all.points().filter_map(|p| display.get_pixel(p)).map(|c| c.r());
//! assert!(reds.filter(|&r| r > 0 && r < 255).count() > 4);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::{RenderError, Rendered, Renderer, RowDone, RowTests, among, bytes};
use crate::hits::Among;
use crate::ray::Ray;
use crate::scalar::Scalar;
use crate::shade::{RowShadows, Shader, ShadowCache};
use crate::vec3::Vec3;
use core::ops::ControlFlow;
use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use embedded_graphics::prelude::{DrawTarget, Point, Size};
use embedded_graphics::primitives::Rectangle;

/// The most samples a pixel takes (16 x 16): their byte sums fit 16 bits.
pub const MAX_SAMPLES: u16 = 256;

/// How a pixel's `side x side` sample points are placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pattern {
    /// A square grid: `side` distinct columns and rows.
    Regular,
    /// The square grid turned by `atan(1/side)` and scaled so that every sample has a
    /// column and a row of its own (`side²` distinct each): edges near horizontal or
    /// vertical get `side²` levels instead of `side + 1`.
    Rotated,
}

/// A pixel's sample positions: `count` points on a grid, fixed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Samples {
    side: u8,
    pattern: Pattern,
}

impl Samples {
    /// One sample at the pixel's point: the plain render.
    pub const ONE: Self = Self {
        side: 1,
        pattern: Pattern::Rotated,
    };

    /// `count` samples placed by `pattern`; `None` unless `count` is a square from 1 to
    /// [`MAX_SAMPLES`].
    pub const fn new(count: u16, pattern: Pattern) -> Option<Self> {
        let mut side = 1;
        while side * side < count && side < 16 {
            side += 1;
        }
        if side * side == count {
            Some(Self {
                side: side as u8,
                pattern,
            })
        } else {
            None
        }
    }

    /// `count` samples on the rotated grid (see [`Pattern::Rotated`]).
    pub const fn rotated(count: u16) -> Option<Self> {
        Self::new(count, Pattern::Rotated)
    }

    /// The number of samples.
    pub const fn count(self) -> u16 {
        self.side as u16 * self.side as u16
    }

    /// The pattern.
    pub const fn pattern(self) -> Pattern {
        self.pattern
    }

    /// Sample `k`'s offset from the pixel's point, `x` and `y`, in `1 / (2 count)` of the
    /// pixel pitch: each within `-count..count`, the pixel's own square.
    pub fn offset(self, k: u16) -> [i32; 2] {
        let side = i32::from(self.side);
        let count = side * side;
        let k = i32::from(k) % count;
        let (i, j) = (k % side, k / side);
        match self.pattern {
            // Cell (i, j) of a side x side grid, in count ths: (2i + 1 - side) side.
            Pattern::Regular => [(2 * i + 1 - side) * side, (2 * j + 1 - side) * side],
            // The lattice spanned by (side, 1) and (-1, side) modulo count: a permutation
            // of the count x count cells, one per column and one per row.
            Pattern::Rotated => {
                let column = (i * side + count - j) % count;
                let row = i + j * side;
                [2 * column + 1 - count, 2 * row + 1 - count]
            }
        }
    }

    /// Sample `k`'s offset on the image plane, for a camera of pixel pitch `pitch`.
    pub fn shift<S: Scalar>(self, k: u16, pitch: [S; 2]) -> [S; 2] {
        self.shift_of(self.offset(k), pitch)
    }

    /// An [`offset`](Self::offset) on the image plane, for a camera of pixel pitch `pitch`.
    fn shift_of<S: Scalar>(self, [x, y]: [i32; 2], pitch: [S; 2]) -> [S; 2] {
        let denominator = 2 * self.count();
        let along = |offset: i32, pitch: S| {
            // |offset| < count <= 256: fits u16.
            let size = pitch.mul_ratio(offset.unsigned_abs() as u16, denominator);
            if offset < 0 { S::ZERO - size } else { size }
        };
        [along(x, pitch[0]), along(y, pitch[1])]
    }
}

/// `count` samples on a rotated grid, for a count known to be a square.
const fn rotated(count: u16) -> Samples {
    match Samples::rotated(count) {
        Some(samples) => samples,
        None => Samples::ONE,
    }
}

/// Anti-aliasing for [`Renderer::render_antialiased`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Antialias {
    /// Every pixel the average of its samples.
    Grid(Samples),
    /// The plain render, with the pixels that differ from a neighbour (another object, or
    /// a channel more than `threshold` levels apart) the average of their samples.
    Adaptive {
        /// The samples of a pixel on an edge.
        samples: Samples,
        /// The largest channel difference between neighbours that is not an edge.
        threshold: u8,
    },
}

impl Antialias {
    /// 4 samples a pixel on a rotated grid.
    pub const GRID_4: Self = Self::Grid(rotated(4));
    /// 9 samples a pixel on a rotated grid.
    pub const GRID_9: Self = Self::Grid(rotated(9));
    /// 16 samples a pixel on a rotated grid.
    pub const GRID_16: Self = Self::Grid(rotated(16));
    /// 16 samples on a rotated grid for the pixels whose neighbours differ by more than 8
    /// levels or see another object; one ray elsewhere (`microray render --aa adaptive`).
    pub const ADAPTIVE: Self = Self::Adaptive {
        samples: rotated(16),
        threshold: 8,
    };
    /// The modes the project measures (the firmware's anti-aliased frames in QEMU, the host
    /// benchmarks), each with a short name.
    pub const MEASURED: [(&'static str, Self); 4] = [
        ("4", Self::GRID_4),
        ("9", Self::GRID_9),
        ("16", Self::GRID_16),
        ("adaptive", Self::ADAPTIVE),
    ];

    /// The [`AaPixel`]s [`Renderer::render_antialiased`] needs for an area `width` pixels
    /// wide, in either mode: two rows of `width + 2` (the adaptive mode's row and the one
    /// below it, each with a neighbour on either side).
    pub const fn buffer_len(width: u16) -> usize {
        2 * (width as usize + 2)
    }

    /// The samples of a supersampled pixel.
    pub const fn samples(self) -> Samples {
        match self {
            Self::Grid(samples) | Self::Adaptive { samples, .. } => samples,
        }
    }
}

/// One pixel's working state during an anti-aliased render (sums of sample bytes, or a
/// plain pixel and what it sees).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AaPixel {
    sum: [u16; 3],
    /// The object seen, plus one (0: none).
    object: u16,
    edge: bool,
}

impl AaPixel {
    /// A cleared pixel.
    pub const NEW: Self = Self {
        sum: [0; 3],
        object: 0,
        edge: false,
    };

    #[inline]
    fn add(&mut self, c: Rgb888) {
        let [r, g, b] = &mut self.sum;
        *r = r.saturating_add(u16::from(c.r()));
        *g = g.saturating_add(u16::from(c.g()));
        *b = b.saturating_add(u16::from(c.b()));
    }

    /// The mean of `count` samples, rounded to nearest.
    fn mean(self, count: u16) -> Rgb888 {
        let count = u32::from(count.max(1));
        let mean = |sum: u16| ((u32::from(sum) + count / 2) / count).min(255) as u8;
        Rgb888::new(mean(self.sum[0]), mean(self.sum[1]), mean(self.sum[2]))
    }

    /// Whether two neighbours differ: another object, or a channel more than `threshold`.
    fn differs(&self, other: &Self, threshold: u8) -> bool {
        self.object != other.object
            || self
                .sum
                .iter()
                .zip(other.sum)
                .any(|(a, b)| a.abs_diff(b) > u16::from(threshold))
    }
}

impl<S: Scalar, const OBJECTS: usize> Renderer<'_, S, OBJECTS> {
    /// Renders `area` (clipped to the image) anti-aliased by `aa` into `target`, one
    /// `fill_contiguous` call per row, top to bottom, as
    /// [`render_area`](Self::render_area) does; `buffer` holds at least
    /// [`Antialias::buffer_len`] of the area's width. The frame depends on nothing but the
    /// scene, the number type and `aa` (an area gives the whole image's pixels there).
    pub fn render_antialiased<D>(
        &self,
        target: &mut D,
        area: Rectangle,
        aa: Antialias,
        buffer: &mut [AaPixel],
        mut on_row: impl FnMut(RowDone) -> ControlFlow<()>,
    ) -> Result<Rendered, RenderError<D::Error>>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let [left, top, width, height] = self.clip(&area);
        let area = Rectangle::new(
            Point::new(left.into(), top.into()),
            Size::new(width.into(), height.into()),
        );
        let needed = Antialias::buffer_len(width);
        let len = buffer.len();
        let buffer = buffer
            .get_mut(..needed)
            .ok_or(RenderError::RowBufferTooSmall { needed, len })?;
        let cache = ShadowCache::new();
        let shader = self.shader().with_shadow_cache(&cache);
        let lines = Lines {
            renderer: self,
            shader: &shader,
            samples: aa.samples(),
            pitch: self.camera.pitch(),
        };
        match aa {
            Antialias::Grid(_) => lines.grid(target, area, buffer, &mut on_row),
            Antialias::Adaptive { threshold, .. } => {
                lines.adaptive(target, area, threshold, buffer, &mut on_row)
            }
        }
    }
}

/// What an anti-aliased render's rows share.
struct Lines<'a, 'r, S: Scalar, const OBJECTS: usize> {
    renderer: &'a Renderer<'r, S, OBJECTS>,
    shader: &'a Shader<'a, S>,
    samples: Samples,
    pitch: [S; 2],
}

impl<S: Scalar, const OBJECTS: usize> Lines<'_, '_, S, OBJECTS> {
    /// Every pixel of the area the mean of its samples.
    fn grid<D>(
        &self,
        target: &mut D,
        area: Rectangle,
        buffer: &mut [AaPixel],
        on_row: &mut impl FnMut(RowDone) -> ControlFlow<()>,
    ) -> Result<Rendered, RenderError<D::Error>>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let left = u16::try_from(area.top_left.x).unwrap_or(0);
        let top = u16::try_from(area.top_left.y).unwrap_or(0);
        let total = u16::try_from(area.size.height).unwrap_or(0);
        let sums = buffer
            .get_mut(..area.size.width as usize)
            .unwrap_or_default();
        let count = self.samples.count();
        // The rows' object tests, prepared in place row by row.
        let mut tests = RowTests::new();
        for done in 1..=total {
            let y = top.saturating_add(done - 1);
            sums.fill(AaPixel::NEW);
            let camera_y = self.renderer.camera.row_from_top(y);
            let last = self.renderer.camera.width().saturating_sub(1);
            let width = sums.len();
            for k in 0..count {
                let [x, y] = self.samples.offset(k);
                let y = self.inside(y, camera_y, self.renderer.camera.height());
                let shift = self.samples.shift_of([x, y], self.pitch);
                // The image's first and last columns take the samples that would leave the
                // image mirrored into it.
                let mirror_first = left == 0 && x < 0;
                let mirror_last = usize::from(left) + width == usize::from(last) + 1 && x > 0;
                let (lo, hi) = (usize::from(mirror_first), width - usize::from(mirror_last));
                if let Some(middle) = sums.get_mut(lo..hi) {
                    self.add_row(&mut tests, camera_y, left + lo as u16, shift, middle, false);
                }
                let mirrored = self.samples.shift_of([-x, y], self.pitch);
                if mirror_first && let Some(p) = sums.first_mut() {
                    p.add(self.sample(camera_y, 0, mirrored, Among::All));
                }
                if mirror_last && let Some(p) = sums.last_mut() {
                    p.add(self.sample(camera_y, last, mirrored, Among::All));
                }
            }
            let line = Rectangle::new(
                Point::new(area.top_left.x, i32::from(y)),
                Size::new(area.size.width, 1),
            );
            let colors = sums.iter().map(|p| p.mean(count).into());
            let row = RowDone {
                row: y,
                done,
                total,
            };
            if let Some(stopped) = send_row(target, line, colors, row, on_row)? {
                return Ok(stopped);
            }
        }
        Ok(Rendered::Complete)
    }

    /// The plain render, with the pixels on edges supersampled.
    fn adaptive<D>(
        &self,
        target: &mut D,
        area: Rectangle,
        threshold: u8,
        buffer: &mut [AaPixel],
        on_row: &mut impl FnMut(RowDone) -> ControlFlow<()>,
    ) -> Result<Rendered, RenderError<D::Error>>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let left = u16::try_from(area.top_left.x).unwrap_or(0);
        let top = u16::try_from(area.top_left.y).unwrap_or(0);
        let width = u16::try_from(area.size.width).unwrap_or(0);
        let total = u16::try_from(area.size.height).unwrap_or(0);
        // A row's plain pixels with one more on each side where the image has them (the
        // row's slot: from column `left - 1`, or from `left` at the image's side, in slot 1).
        let slot = usize::from(width) + 2;
        let (mut this, rest) = buffer.split_at_mut(slot.min(buffer.len()));
        let mut tests = RowTests::new();
        let mut below = rest.get_mut(..slot).unwrap_or_default();
        let image_width = self.renderer.camera.width();
        let first = left.saturating_sub(1);
        let skip = usize::from(left == 0);
        let end = (usize::from(image_width.saturating_sub(first)) + skip).min(slot);
        let columns = skip..end;
        let height = self.renderer.camera.height();
        // The row above the area's first, for its comparisons, then the first.
        let above = top > 0;
        if above {
            self.plain_row(
                &mut tests,
                top - 1,
                first,
                this.get_mut(columns.clone()).unwrap_or_default(),
            );
        }
        let mut next = below.get_mut(columns.clone()).unwrap_or_default();
        self.plain_row(&mut tests, top, first, next);
        mark_edges(next, threshold);
        if above {
            mark_between(
                this.get_mut(columns.clone()).unwrap_or_default(),
                next,
                threshold,
            );
        }
        core::mem::swap(&mut this, &mut below);
        for done in 1..=total {
            let y = top.saturating_add(done - 1);
            if y.saturating_add(1) < height {
                next = below.get_mut(columns.clone()).unwrap_or_default();
                self.plain_row(&mut tests, y + 1, first, next);
                mark_edges(next, threshold);
                mark_between(
                    this.get_mut(columns.clone()).unwrap_or_default(),
                    next,
                    threshold,
                );
            }
            let camera_y = self.renderer.camera.row_from_top(y);
            let objects = self.renderer.row_objects(y);
            // The edges' samples before the row goes out: the target's call is output only.
            let shown = this.get_mut(1..=usize::from(width)).unwrap_or_default();
            for (p, x) in shown.iter_mut().zip(left..) {
                if p.edge {
                    let c = self.supersampled(camera_y, x, among(&objects));
                    p.sum = [c.r(), c.g(), c.b()].map(u16::from);
                }
            }
            let shown = shown.iter().map(|p| p.mean(1).into());
            let line = Rectangle::new(
                Point::new(i32::from(left), i32::from(y)),
                Size::new(u32::from(width), 1),
            );
            let row = RowDone {
                row: y,
                done,
                total,
            };
            if let Some(stopped) = send_row(target, line, shown, row, on_row)? {
                return Ok(stopped);
            }
            core::mem::swap(&mut this, &mut below);
        }
        Ok(Rendered::Complete)
    }

    /// Adds sample `shift` of each pixel of camera row `camera_y` (0 the bottom) from
    /// column `first` to `sums` (as many as it holds), shaded as
    /// [`Renderer::render_area`] shades a row; with `objects`, records what each sees.
    fn add_row(
        &self,
        tests: &mut RowTests<S, OBJECTS>,
        camera_y: u16,
        first: u16,
        shift: [S; 2],
        sums: &mut [AaPixel],
        objects: bool,
    ) {
        let renderer = self.renderer;
        let shader = self.shader;
        let rays = renderer.camera.shifted_row_rays(camera_y, first, shift);
        if !renderer.prepare_row(camera_y, &rays, tests) {
            for (p, ray) in sums.iter_mut().zip(rays) {
                p.add(renderer.color(shader, ray, Among::All));
                if objects {
                    p.object = seen(ray.and_then(|r| shader.first_object_among(&r, Among::All)));
                }
            }
            return;
        }
        let tests: &RowTests<S, OBJECTS> = tests;
        let first_object =
            |ray: Option<Ray<S>>| seen(ray.and_then(|r| shader.first_object_in_row(&r, tests)));
        // Made in place, as `render_area`'s rows make theirs.
        let mut slot = None;
        renderer.row_shading_in(&mut slot, shader, tests, &rays, None);
        match &slot {
            // The row's fast case in a loop of its own, as `render_area` has it; every ray
            // meets the row's plane.
            Some(shading) if shading.plain() => {
                let plane = seen(shading.plane());
                for (p, ray) in sums.iter_mut().zip(rays) {
                    let c = ray.map_or(Vec3::ZERO, |r| shader.shade_in_plain_row(shading, &r));
                    p.add(bytes(c));
                    if objects {
                        p.object = if ray.is_some() { plane } else { 0 };
                    }
                }
            }
            Some(shading) => {
                let mut shadows = RowShadows::new();
                let resolution = crate::plan::resolution(self.renderer.camera);
                shader.prepare_row_shadows(&mut shadows, shading, resolution);
                for (p, ray) in sums.iter_mut().zip(rays) {
                    let c = ray.map_or(Vec3::ZERO, |r| {
                        shader.shade_in_row(shading, &shadows, tests, &r)
                    });
                    p.add(bytes(c));
                    if objects {
                        p.object = first_object(ray);
                    }
                }
            }
            None => {
                for (p, ray) in sums.iter_mut().zip(rays) {
                    p.add(renderer.color_in_row(shader, ray, tests));
                    if objects {
                        p.object = first_object(ray);
                    }
                }
            }
        }
    }

    /// Image row `y`'s plain pixels (0 the top) from column `first` into `row` (as many
    /// as it holds), each with the object it sees.
    fn plain_row(&self, tests: &mut RowTests<S, OBJECTS>, y: u16, first: u16, row: &mut [AaPixel]) {
        row.fill(AaPixel::NEW);
        let camera_y = self.renderer.camera.row_from_top(y);
        self.add_row(tests, camera_y, first, [S::ZERO; 2], row, true);
    }

    /// A sample offset (in `1 / (2 count)` of a pixel) along an axis of `size` pixels at
    /// pixel `at`, mirrored into the image where it would leave it: the first and last
    /// pixels' footprints end at the window's edge, as the course's pixels do (their
    /// points lie on it).
    fn inside(&self, offset: i32, at: u16, size: u16) -> i32 {
        let leaves = (at == 0 && offset < 0) || (at.saturating_add(1) >= size && offset > 0);
        if leaves { -offset } else { offset }
    }

    /// The colour of one sample, shifted by `shift` from pixel `(x, camera_y)`.
    fn sample(&self, camera_y: u16, x: u16, shift: [S; 2], among: Among<'_, S>) -> Rgb888 {
        let ray = self
            .renderer
            .camera
            .shifted_row_rays(camera_y, x, shift)
            .next()
            .flatten();
        self.renderer.color(self.shader, ray, among)
    }

    /// The mean of pixel `(x, camera_y)`'s samples, each traced alone among the row's
    /// objects (their sub-pixel offsets stay within the row's list: see [`crate::plan`]).
    fn supersampled(&self, camera_y: u16, x: u16, among: Among<'_, S>) -> Rgb888 {
        let camera = self.renderer.camera;
        let mut sum = AaPixel::NEW;
        let count = self.samples.count();
        for k in 0..count {
            let [ox, oy] = self.samples.offset(k);
            let offset = [
                self.inside(ox, x, camera.width()),
                self.inside(oy, camera_y, camera.height()),
            ];
            let shift = self.samples.shift_of(offset, self.pitch);
            sum.add(self.sample(camera_y, x, shift, among));
        }
        sum.mean(count)
    }
}

/// An object index as [`AaPixel`] keeps it: plus one, 0 for none.
fn seen(index: Option<usize>) -> u16 {
    index.map_or(0, |i| {
        u16::try_from(i).unwrap_or(u16::MAX - 1).saturating_add(1)
    })
}

/// Draws a row's colours on `target` and reports the row; `Some` when `on_row` stops.
fn send_row<D: DrawTarget>(
    target: &mut D,
    line: Rectangle,
    colors: impl IntoIterator<Item = D::Color>,
    row: RowDone,
    on_row: &mut impl FnMut(RowDone) -> ControlFlow<()>,
) -> Result<Option<Rendered>, RenderError<D::Error>> {
    target
        .fill_contiguous(&line, colors)
        .map_err(RenderError::Target)?;
    Ok(on_row(row)
        .is_break()
        .then_some(Rendered::Stopped { rows: row.done }))
}

/// Marks the pixels of a row that differ from their right-hand neighbour, and it.
fn mark_edges(row: &mut [AaPixel], threshold: u8) {
    let mut left: Option<&mut AaPixel> = None;
    for p in row.iter_mut() {
        if let Some(a) = left
            && a.differs(p, threshold)
        {
            a.edge = true;
            p.edge = true;
        }
        left = Some(p);
    }
}

/// Marks the pixels that differ from the one below them, and it.
fn mark_between(above: &mut [AaPixel], below: &mut [AaPixel], threshold: u8) {
    for (a, b) in above.iter_mut().zip(below.iter_mut()) {
        if a.differs(b, threshold) {
            a.edge = true;
            b.edge = true;
        }
    }
}
