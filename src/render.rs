//! Rendering into any embedded-graphics [`DrawTarget`](https://docs.rs/embedded-graphics/0.8/embedded_graphics/draw_target/trait.DrawTarget.html), one row at a time.
//!
//! Each row is computed into a row buffer (the caller's, or one of the scene's `MAX_WIDTH`
//! on the stack) and sent with one `fill_contiguous` call for a 1-pixel-high rectangle, top
//! row first: no framebuffer, RAM of one row. Colours go through
//! [`Rgb888`](https://docs.rs/embedded-graphics/0.8/embedded_graphics/pixelcolor/struct.Rgb888.html), so any colour
//! type with `From<Rgb888>` works (`Rgb565`, `Rgb888`, `Gray8`, ...).
//!
//! ```
//! use embedded_graphics::{mock_display::MockDisplay, pixelcolor::Rgb565, prelude::*};
//! use microray::{parse::{no_textures, parse_scene}, render::render, Scene};
//!
//! let text = b"camera c { pixeldim 8 6 worlddim 8 6 viewpoint 4 3 3 }
//!              material red { ambient 1 0 0 }
//!              plane back { material red normal 0 0 1 point 0 0 -5 }";
//! let scene: Scene<f32, 4, 4, 2, 0, 8> = parse_scene(text, no_textures)?;
//! let mut display = MockDisplay::<Rgb565>::new();
//! render(&scene, &mut display).map_err(|_| "display error")?;
//! assert_eq!(display.get_pixel(Point::new(0, 0)), Some(Rgb565::new(2, 0, 0)));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::bvh::Bvh;
use crate::camera::{Camera, RowRays};
use crate::hits::Among;
use crate::object::{Object, RowEntry, RowTest};
use crate::plan::{Plan, RowSpan, ShadowBoxes};
use crate::ray::Ray;
use crate::scalar::geometry::Geo;
use crate::scalar::{HARD_FLOAT, Scalar};
use crate::scene::Scene;
use crate::shade::{RowShading, RowShadows, Shader, ShadowCache};
use crate::vec3::Vec3;
use core::ops::ControlFlow;
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::{DrawTarget, Point, Size};
use embedded_graphics::primitives::Rectangle;

#[cfg(feature = "antialias")]
mod antialias;
#[cfg(feature = "antialias")]
pub use antialias::{AaPixel, Antialias, MAX_SAMPLES, Pattern, Samples};
mod progressive;
pub use progressive::{BLOCKS, PassDone};

/// Why rendering stopped short.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderError<E> {
    /// The draw target failed.
    Target(E),
    /// The row buffer is narrower than the area to render.
    RowBufferTooSmall {
        /// Pixels in a row of the area.
        needed: usize,
        /// Pixels the buffer holds.
        len: usize,
    },
}

impl<E: core::fmt::Debug> core::fmt::Display for RenderError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RenderError::Target(e) => write!(f, "the display failed: {e:?}"),
            RenderError::RowBufferTooSmall { needed, len } => {
                write!(f, "row buffer holds {len} pixels; a row needs {needed}")
            }
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for RenderError<E> {}

/// Whether rendering ran to the end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rendered {
    /// Every row was drawn.
    Complete,
    /// The row callback asked to stop after this many rows.
    Stopped {
        /// Rows drawn.
        rows: u16,
    },
    /// The pass callback of a progressive render asked to stop after the pass that
    /// filled blocks of this side (every pixel shows its block's colour).
    StoppedAfterPass {
        /// The side of the last pass's blocks.
        block: u16,
    },
}

/// Sent to the row callback after each row is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowDone {
    /// The image row just drawn (0 is the top).
    pub row: u16,
    /// Rows of the area drawn so far.
    pub done: u16,
    /// Rows in the area.
    pub total: u16,
}

/// What a pixel shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Shading {
    /// The course's shading.
    #[default]
    Color,
    /// A distinct colour per object (black where nothing is hit): shows which object each
    /// pixel sees, for comparing number types and for debugging scenes.
    Ids,
}

/// The colour of object `index` in the object-id view: 16 distinct colours, repeating.
pub fn id_color(index: Option<usize>) -> Rgb888 {
    const COLORS: [(u8, u8, u8); 16] = [
        (230, 25, 75),
        (60, 180, 75),
        (255, 225, 25),
        (0, 130, 200),
        (245, 130, 48),
        (145, 30, 180),
        (70, 240, 240),
        (240, 50, 230),
        (210, 245, 60),
        (250, 190, 212),
        (0, 128, 128),
        (220, 190, 255),
        (170, 110, 40),
        (255, 250, 200),
        (128, 0, 0),
        (170, 255, 195),
    ];
    match index.and_then(|i| COLORS.get(i % COLORS.len())) {
        Some(&(r, g, b)) => Rgb888::new(r, g, b),
        None => Rgb888::new(0, 0, 0),
    }
}

/// Computes pixels of a scene: the camera, the shader and the scene's render plan, with
/// nothing borrowed mutably. `OBJECTS` is the scene's object capacity (the plan's lists
/// hold that many indices).
#[derive(Clone, Debug)]
pub struct Renderer<'s, S: Scalar, const OBJECTS: usize = 32> {
    camera: &'s Camera<S>,
    shader: Shader<'s, S>,
    plan: Plan<OBJECTS>,
    bvh: Bvh<S, OBJECTS>,
    /// Each light's list of the plan's objects that can block it (the host's `f64`).
    #[cfg(feature = "batch")]
    blockers: Option<crate::shade::LightBlockers>,
    /// Where each object that depends on `x` can shadow the rows' planes, per light (with
    /// rows shaded together; see [`crate::plan::ShadowBoxes`]).
    #[cfg(feature = "plan")]
    shadow_boxes: Option<ShadowBoxes>,
    planned: bool,
    shading: Shading,
    /// Whether rows can be shaded together in this render (see
    /// [`Shader::row_shading`]): checked once, at set-up.
    rows_shared: bool,
}

impl<'s, S: Scalar, const OBJECTS: usize> Renderer<'s, S, OBJECTS> {
    /// A renderer for a scene, with its render plan (see [`crate::plan`]).
    pub fn new<
        const MATERIALS: usize,
        const LIGHTS: usize,
        const TEXTURES: usize,
        const MAX_WIDTH: usize,
    >(
        scene: &'s Scene<'_, S, OBJECTS, MATERIALS, LIGHTS, TEXTURES, MAX_WIDTH>,
    ) -> Self {
        // Without the `plan` feature neither is built, and the code that builds and uses
        // them is left out of the binary.
        let (plan, bvh) = if cfg!(feature = "plan") {
            let plan = Plan::new(
                scene.camera(),
                scene.materials(),
                scene.lights(),
                scene.objects(),
                scene.z_limit(),
            );
            let bvh = Bvh::new(scene.objects(), plan.kept(), scene.camera().viewpoint());
            (plan, bvh)
        } else {
            (Plan::empty(), Bvh::empty())
        };
        // Only for a plan's list (a tree's walks are left as they are).
        #[cfg(feature = "batch")]
        let blockers = match bvh.tree() {
            None if cfg!(feature = "plan") => {
                crate::shade::LightBlockers::new(scene.objects(), plan.kept(), scene.lights())
            }
            _ => None,
        };
        let mut renderer = Self {
            camera: scene.camera(),
            shader: Shader::new(scene.objects(), scene.lights(), scene.palette()),
            plan,
            bvh,
            #[cfg(feature = "batch")]
            blockers,
            #[cfg(feature = "plan")]
            shadow_boxes: None,
            planned: true,
            shading: Shading::Color,
            rows_shared: false,
        };
        // Rows are shaded together only with the plan (see `prepare_row`).
        renderer.rows_shared = renderer.planned() && renderer.shader().shares_rows();
        // Built for size, rows test their shadow rays as they did (flash).
        #[cfg(feature = "plan")]
        if renderer.rows_shared
            && !cfg!(microray_small)
            && ShadowBoxes::possible(scene.objects(), renderer.plan.kept())
        {
            renderer.shadow_boxes = ShadowBoxes::new(
                scene.camera(),
                scene.lights(),
                scene.objects(),
                renderer.plan.kept(),
            );
        }
        renderer
    }

    /// The same renderer showing `shading`.
    pub fn with_shading(self, shading: Shading) -> Self {
        Self { shading, ..self }
    }

    /// The same renderer with its plan (`true`, the default) or without (`false`: every
    /// stage runs and every ray is tested against every object). The pixels are the same
    /// either way; without a plan is the reference the plan is tested against. A build
    /// without the `plan` feature has no plan to switch on.
    pub fn with_plan(self, planned: bool) -> Self {
        Self { planned, ..self }
    }

    /// [`with_plan`](Self::with_plan) in place (no copy of the renderer: RAM on a
    /// microcontroller, whose stack holds it under the render's calls).
    pub fn set_plan(&mut self, planned: bool) {
        self.planned = planned;
    }

    /// The bounding-volume hierarchy of the plan's objects (empty below
    /// [`crate::bvh::MIN_OBJECTS`] bounded objects; not used without the plan).
    pub fn bvh(&self) -> &Bvh<S, OBJECTS> {
        &self.bvh
    }

    /// The render plan (also when it is switched off).
    pub fn plan(&self) -> &Plan<OBJECTS> {
        &self.plan
    }

    /// Whether the plan is used: switched on, and compiled in (the `cfg!` lets the compiler
    /// leave out everything planned rendering needs when it is not).
    #[inline]
    fn planned(&self) -> bool {
        cfg!(feature = "plan") && self.planned
    }

    /// The shadow boxes, where this render has them (built for size there are none, and
    /// no code for them).
    #[inline]
    fn boxes(&self) -> Option<&ShadowBoxes> {
        #[cfg(feature = "plan")]
        return self.shadow_boxes.as_ref().filter(|_| !cfg!(microray_small));
        #[cfg(not(feature = "plan"))]
        return None;
    }

    /// The shader with the plan's stages and objects, or everything without a plan.
    fn shader(&self) -> Shader<'_, S> {
        if self.planned() {
            let plan = &self.plan;
            let among = match self.bvh.tree() {
                Some(tree) => Among::Tree(tree),
                None => Among::Only(plan.kept()),
            };
            let shader = self.shader.planned(plan.stages(), among);
            #[cfg(feature = "batch")]
            let shader = shader.with_blockers(self.blockers);
            shader
        } else {
            self.shader
        }
    }

    /// The objects primary rays of `row` (0 the top) can hit, by index; `None` means all.
    fn row_objects(&self, row: u16) -> Option<heapless::Vec<u16, OBJECTS>> {
        let y = self.camera.row_from_top(row);
        self.planned().then(|| self.plan.objects_in_row(y))
    }

    /// The image size in pixels.
    pub fn size(&self) -> Size {
        Size::new(
            u32::from(self.camera.width()),
            u32::from(self.camera.height()),
        )
    }

    /// `area` clipped to the image: left, top, width and height (zero sizes when they do
    /// not meet). In integers rather than with `Rectangle::intersection`, whose general
    /// form cost 170 bytes of the Cortex-M0's minimal build.
    pub(crate) fn clip(&self, area: &Rectangle) -> [u16; 4] {
        let span = |start: i32, len: u32, limit: u16| {
            let limit = i32::from(limit);
            let first = start.clamp(0, limit);
            let end = start.saturating_add_unsigned(len).clamp(first, limit);
            // Both in 0..=limit, which fits u16.
            [first, end - first].map(|v| u16::try_from(v).unwrap_or(0))
        };
        let [left, width] = span(area.top_left.x, area.size.width, self.camera.width());
        let [top, height] = span(area.top_left.y, area.size.height, self.camera.height());
        [left, top, width, height]
    }

    /// The radiance at pixel `(x, row)`, `row` 0 the top (before conversion to bytes).
    pub fn radiance(&self, x: u16, row: u16) -> Vec3<S> {
        let objects = self.row_objects(row);
        self.radiance_among(&self.shader(), x, row, among(&objects))
    }

    fn radiance_among(
        &self,
        shader: &Shader<'_, S>,
        x: u16,
        row: u16,
        among: Among<'_, S>,
    ) -> Vec3<S> {
        let y = self.camera.row_from_top(row);
        self.camera
            .primary_ray(x, y)
            .map_or(Vec3::ZERO, |ray| shader.primary_among(&ray, among))
    }

    /// The index of the object seen at pixel `(x, row)`, if any: the object-id view used to
    /// check that a number type makes no object appear or vanish.
    pub fn object_at(&self, x: u16, row: u16) -> Option<usize> {
        let objects = self.row_objects(row);
        let y = self.camera.row_from_top(row);
        self.camera
            .primary_ray(x, y)
            .and_then(|ray| self.shader().first_object_among(&ray, among(&objects)))
    }

    /// The colour at pixel `(x, row)`, `row` 0 the top. Rendering a whole row through
    /// [`render_area`](Self::render_area) works out the row's objects once instead of per
    /// pixel.
    pub fn pixel(&self, x: u16, row: u16) -> Rgb888 {
        let objects = self.row_objects(row);
        let y = self.camera.row_from_top(row);
        self.color(
            &self.shader(),
            self.camera.primary_ray(x, y),
            among(&objects),
        )
    }

    /// The colour seen along a primary ray (black without one).
    #[inline]
    fn color(&self, shader: &Shader<'_, S>, ray: Option<Ray<S>>, among: Among<'_, S>) -> Rgb888 {
        match self.shading {
            Shading::Color => {
                let c = ray.map_or(Vec3::ZERO, |ray| shader.primary_among(&ray, among));
                bytes(c)
            }
            Shading::Ids => id_color(ray.and_then(|ray| shader.first_object_among(&ray, among))),
        }
    }

    /// [`color`](Self::color) for a primary ray of a row whose objects' tests are prepared.
    #[inline]
    fn color_in_row(
        &self,
        shader: &Shader<'_, S>,
        ray: Option<Ray<S>>,
        row: &[RowEntry<S>],
    ) -> Rgb888 {
        match self.shading {
            Shading::Color => {
                let c = ray.map_or(Vec3::ZERO, |ray| shader.primary_in_row(&ray, row));
                bytes(c)
            }
            Shading::Ids => id_color(ray.and_then(|ray| shader.first_object_in_row(&ray, row))),
        }
    }

    /// The plan's objects for a row (`camera_y`, 0 the bottom), each with its kind's test of
    /// the row's primary rays; `None` without a plan.
    fn row_tests(
        &self,
        camera_y: u16,
        rays: &RowRays<S>,
    ) -> Option<heapless::Vec<RowEntry<S>, OBJECTS>> {
        let mut tests = heapless::Vec::new();
        self.prepare_row(camera_y, rays, &mut tests)
            .then_some(tests)
    }

    /// [`row_tests`](Self::row_tests) into `tests`, cleared first; `false` without a plan.
    /// The list holds `OBJECTS` slots: filled where it lives instead of moved there.
    fn prepare_row(
        &self,
        camera_y: u16,
        rays: &RowRays<S>,
        tests: &mut RowTests<S, OBJECTS>,
    ) -> bool {
        tests.clear();
        if !self.planned() {
            return false;
        }
        let origin = rays.origin(self.shader.z_limit());
        for index in self.plan.in_row(camera_y) {
            // The tree's objects are found by walking it.
            if self.bvh.contains(index) {
                continue;
            }
            if let Some(object) = self.shader.objects().get(usize::from(index)) {
                let test = object.row_test(&origin);
                // Cannot fail: the row holds at most the plan's objects.
                let _ = tests.push(RowEntry { index, test });
            }
        }
        // The planes the row's rays meet only behind another (`f64`, in batches).
        #[cfg(all(feature = "batch", feature = "plan"))]
        if self.shading == Shading::Color {
            let span = rays.span_from_eye(self.camera.world()[0]);
            crate::object::behind::hide_behind(self.shader.objects(), tests, &origin, span);
        }
        true
    }

    /// Whether the pixels of image row `row` (0 the top) are shaded together, as a
    /// [`RowShading`]: a plain plane at the same `t` for every primary ray of the row (with
    /// a plan, in the types that do not normalise primary rays). The pixels are the same
    /// either way; this tells where the work is shared.
    pub fn shades_row_together(&self, row: u16) -> bool {
        if self.shading != Shading::Color || row >= self.camera.height() {
            return false;
        }
        let camera_y = self.camera.row_from_top(row);
        let rays = self.camera.row_rays(camera_y, 0);
        let shader = self.shader();
        self.row_tests(camera_y, &rays).is_some_and(|tests| {
            let mut slot = None;
            self.row_shading_in(&mut slot, &shader, &tests, &rays, None);
            slot.is_some()
        })
    }

    /// The shading of a row whose tests are prepared, made in `slot` (`None` when its
    /// pixels are not shaded together; colours only: the object-id view shades each pixel
    /// alone). In place: a shading returned by value is copied (see
    /// `Shader::shared_row_shading`). Out of line: it runs once a row, and in line its
    /// levels and lights sat in the render's frame for the whole render (about 1.5 KB of
    /// the micro:bit's peak stack: docs/speed-log.md, step 6).
    #[inline(never)]
    fn row_shading_in<'r>(
        &self,
        slot: &mut Option<RowShading<'r, S>>,
        shader: &Shader<'r, S>,
        tests: &[RowEntry<S>],
        rays: &RowRays<S>,
        within: Option<[u16; 2]>,
    ) {
        match self.shading {
            Shading::Color if self.rows_shared => {
                let origin = rays.origin(self.shader.z_limit());
                let by_boxes = self.boxes().is_some();
                shader.shared_row_shading(slot, tests, &origin, by_boxes, within);
            }
            _ => *slot = None,
        }
    }

    /// Renders `area` (clipped to the image) into `target` at the same coordinates, one
    /// `fill_contiguous` call per row, top to bottom, using `row` as the row buffer.
    /// `on_row` runs after each row; returning `ControlFlow::Break` stops early.
    pub fn render_area<D>(
        &self,
        target: &mut D,
        area: Rectangle,
        row: &mut [D::Color],
        mut on_row: impl FnMut(RowDone) -> ControlFlow<()>,
    ) -> Result<Rendered, RenderError<D::Error>>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let [left, top, width, total] = self.clip(&area);
        let width = usize::from(width);
        let len = row.len();
        let row = row
            .get_mut(..width)
            .ok_or(RenderError::RowBufferTooSmall { needed: width, len })?;
        // One cache per render: neighbouring pixels share their shadows' blockers.
        let cache = ShadowCache::new();
        let shader = self.shader().with_shadow_cache(&cache);
        let mut tests = heapless::Vec::new();
        for done in 1..=total {
            let y = top.saturating_add(done - 1);
            self.render_row(&shader, target, y, left, &mut tests, row)?;
            if on_row(RowDone {
                row: y,
                done,
                total,
            })
            .is_break()
            {
                return Ok(Rendered::Stopped { rows: done });
            }
        }
        Ok(Rendered::Complete)
    }
}

/// How a row is cut: by the shadow boxes on its plane (with the plane's index, besides the
/// entries' spans), its first segment ending at `to`.
#[derive(Clone, Copy, Debug)]
struct Cut<'b> {
    boxes: Option<(&'b ShadowBoxes, usize)>,
    to: usize,
}

/// A segment of a row: the columns `from..to` of camera row `camera_y`, counted from
/// image column `left`.
#[derive(Clone, Copy, Debug)]
struct Segment {
    camera_y: u16,
    left: u16,
    from: usize,
    to: usize,
}

/// A row's objects with their row tests (`OBJECTS` slots).
type RowTests<S, const OBJECTS: usize> = heapless::Vec<RowEntry<S>, OBJECTS>;

impl<S: Scalar, const OBJECTS: usize> Renderer<'_, S, OBJECTS> {
    /// Renders image row `y` (0 the top) from column `left` into `target`, as many pixels
    /// as `row` holds: every row of [`render_area`](Self::render_area) and the progressive
    /// order's whole rows.
    fn render_row<D>(
        &self,
        shader: &Shader<'_, S>,
        target: &mut D,
        y: u16,
        left: u16,
        tests: &mut RowTests<S, OBJECTS>,
        row: &mut [D::Color],
    ) -> Result<(), RenderError<D::Error>>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let camera_y = self.camera.row_from_top(y);
        let rays = self.camera.row_rays(camera_y, left);
        // `shade_every` with a stride of 1, written out: through it, every row cost 1-2 %
        // more (tplane4, spotlight on the M4F, when it was the progressive order's
        // `with_row` and `fill_row`).
        if self.prepare_row(camera_y, &rays, tests) {
            let spans = self.column_spans(tests, left, row.len());
            self.shade_segments(shader, camera_y, left, tests, &spans, rays, row);
        } else {
            for (slot, ray) in slots_with_rays(row, rays) {
                *slot = self.color(shader, ray, Among::All).into();
            }
        }
        // The row's width fits u16, as the image's does.
        let width = u32::try_from(row.len()).unwrap_or(0);
        let line = Rectangle::new(
            Point::new(i32::from(left), i32::from(y)),
            Size::new(width, 1),
        );
        target
            .fill_contiguous(&line, row.iter().copied())
            .map_err(RenderError::Target)
    }

    /// Shades a row whose tests are prepared into `row`; where some entries can be met only
    /// in some of its columns (`spans`, see [`column_spans`](Self::column_spans)), segment
    /// by segment, each with those entries turned to misses where they cannot be met: the
    /// same pixels, fewer tests, and segments without such entries shaded as the row's
    /// plane's.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn shade_segments<C: From<Rgb888> + Copy>(
        &self,
        shader: &Shader<'_, S>,
        camera_y: u16,
        left: u16,
        tests: &mut [RowEntry<S>],
        spans: &[(u8, RowSpan)],
        rays: RowRays<S>,
        row: &mut [C],
    ) {
        let mut shading = None;
        self.row_shading_in(&mut shading, shader, tests, &rays, None);
        // No object in the row (a scene's sky): every pixel black, with no ray made (the
        // host's; the firmware keeps its flash).
        #[cfg(feature = "batch")]
        if shading.is_none()
            && self.shading == Shading::Color
            && self.plan.in_row(camera_y).next().is_none()
        {
            row.fill(Rgb888::new(0, 0, 0).into());
            return;
        }
        let plane = shading.as_ref().and_then(RowShading::first_plane);
        let boxes = self.boxes().zip(plane);
        let width = row.len();
        // Built for size, there are neither spans nor boxes: one segment, no search.
        let cut = |from| {
            if cfg!(microray_small) {
                width
            } else {
                next_cut(spans, boxes, camera_y, left, width, from)
            }
        };
        let to = cut(0);
        // Rectangles' runs of columns: their segments shaded as their planes'.
        if has_runs(self.shader.objects(), tests)
            && self.rows_shared
            && self.shading == Shading::Color
        {
            let cut = Cut { boxes, to };
            self.shade_with_runs(shader, camera_y, left, tests, spans, cut, &mut shading, row);
            return;
        }
        if to >= width {
            // One segment (most rows): the row's own rays, moved in.
            self.set_segment(
                tests,
                spans,
                boxes,
                shading.as_mut(),
                camera_y,
                left,
                0,
                width,
            );
            self.shade_part(shader, tests, shading.as_ref(), rays, row);
            return;
        }
        // Several: the row's rays are not used again (each segment makes its own).
        let cut = Cut { boxes, to };
        self.shade_cut_row(
            shader,
            camera_y,
            left,
            tests,
            spans,
            cut,
            shading.as_mut(),
            row,
        );
    }

    /// [`shade_segments`](Self::shade_segments) for a row cut in several, the first ending
    /// at `cut.to`. Out of line: in line, its locals sat in the caller's frame under every
    /// row's calls (the micro:bit's stack for spec0, 96 B).
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn shade_cut_row<C: From<Rgb888> + Copy>(
        &self,
        shader: &Shader<'_, S>,
        camera_y: u16,
        left: u16,
        tests: &mut [RowEntry<S>],
        spans: &[(u8, RowSpan)],
        cut: Cut<'_>,
        mut shading: Option<&mut RowShading<'_, S>>,
        row: &mut [C],
    ) {
        let boxes = cut.boxes;
        self.each_segment(camera_y, left, spans, cut, row, |segment, part| {
            let Segment { from, to, .. } = segment;
            let here = shading.as_deref_mut();
            let first = self.set_segment(tests, spans, boxes, here, camera_y, left, from, to);
            let rays = self.camera.row_rays(camera_y, first);
            self.shade_part(shader, tests, shading.as_deref(), rays, part);
        });
    }

    /// [`shade_cut_row`](Self::shade_cut_row) for a row with rectangles' runs of columns
    /// (one segment or several, the first ending at `cut.to`), each segment readied by
    /// [`ready_segment`](Self::ready_segment). Out of line, apart from `shade_cut_row`:
    /// rows without runs keep their stack (the segments' shadings' set-up, about 700 bytes
    /// deeper on the micro:bit for every scene when the two were one).
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn shade_with_runs<'s, C: From<Rgb888> + Copy>(
        &self,
        shader: &Shader<'s, S>,
        camera_y: u16,
        left: u16,
        tests: &mut [RowEntry<S>],
        spans: &[(u8, RowSpan)],
        cut: Cut<'_>,
        shading: &mut Option<RowShading<'s, S>>,
        row: &mut [C],
    ) {
        let boxes = cut.boxes;
        // The row's rays, for the segments' own shadings (they take what the rays share).
        let row_rays = self.camera.row_rays(camera_y, left);
        let mut in_run = false;
        self.each_segment(camera_y, left, spans, cut, row, |segment, part| {
            let run = &mut in_run;
            let first = self.ready_segment(
                shader, tests, spans, boxes, shading, run, &row_rays, segment,
            );
            let rays = self.camera.row_rays(camera_y, first);
            self.shade_part(shader, tests, shading.as_ref(), rays, part);
        });
    }

    /// Calls `shade` with each segment of a row cut as [`next_cut`] cuts it (the first
    /// ending at `cut.to`) and its part of `row`. Each segment's rays are made afresh by
    /// value (through one `&mut` for all, the loops could not keep them in registers, and
    /// soft-float f32 spec0 cost the Cortex-M0 16 % more).
    #[inline(always)]
    fn each_segment<C>(
        &self,
        camera_y: u16,
        left: u16,
        spans: &[(u8, RowSpan)],
        cut: Cut<'_>,
        row: &mut [C],
        mut shade: impl FnMut(Segment, &mut [C]),
    ) {
        let width = row.len();
        let (mut from, mut to) = (0, cut.to);
        while from < width {
            let Some(part) = row.get_mut(from..to) else {
                break;
            };
            let segment = Segment {
                camera_y,
                left,
                from,
                to,
            };
            shade(segment, part);
            from = to;
            to = next_cut(spans, cut.boxes, camera_y, left, width, from);
        }
    }

    /// Readies the row's tests and `shading` for a segment, as
    /// [`set_segment`](Self::set_segment) does, and returns its first image column; but
    /// where a rectangle's run of columns ([`RowTest::AtAcross`]) holds the whole segment,
    /// every ray of the segment meets the rectangle at one `t`, as a row's rays meet a
    /// plane, and the segment gets a shading of its own, with the runs that hold it as
    /// planes (the nearest of those and the row's planes first, as each ray's closest hit
    /// finds it). It is built in the row's shading's place (`runs` says it is there: a later
    /// segment outside the runs builds the row's again), and the shadow boxes are applied to
    /// it.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn ready_segment<'s>(
        &self,
        shader: &Shader<'s, S>,
        tests: &mut [RowEntry<S>],
        spans: &[(u8, RowSpan)],
        boxes: Option<(&ShadowBoxes, usize)>,
        shading: &mut Option<RowShading<'s, S>>,
        runs: &mut bool,
        rays: &RowRays<S>,
        segment: Segment,
    ) -> u16 {
        let Segment {
            camera_y,
            left,
            from,
            to,
        } = segment;
        let column = |c: usize| left.saturating_add(u16::try_from(c).unwrap_or(u16::MAX));
        let within = [column(from), column(to.saturating_sub(1))];
        if self.rows_shared
            && self.shading == Shading::Color
            && in_run(self.shader.objects(), tests, within)
        {
            // The spanned entries first: the segment's shading reads them.
            let first = self.set_segment(tests, spans, boxes, None, camera_y, left, from, to);
            self.row_shading_in(shading, shader, tests, rays, Some(within));
            if let (Some(own), Some(boxes)) = (shading.as_mut(), self.boxes()) {
                own.set_segment(boxes, camera_y, within[0], within[1]);
            }
            *runs = true;
            return first;
        }
        if *runs {
            self.row_shading_in(shading, shader, tests, rays, None);
            *runs = false;
        }
        self.set_segment(
            tests,
            spans,
            boxes,
            shading.as_mut(),
            camera_y,
            left,
            from,
            to,
        )
    }

    /// Readies the row's tests and shading for the segment of columns `from..to` (counted
    /// from `left`): the entries with `spans` tested only where they can be met, and the
    /// shadow boxes that cover it; its first image column.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn set_segment(
        &self,
        tests: &mut [RowEntry<S>],
        spans: &[(u8, RowSpan)],
        boxes: Option<(&ShadowBoxes, usize)>,
        shading: Option<&mut RowShading<'_, S>>,
        camera_y: u16,
        left: u16,
        from: usize,
        to: usize,
    ) -> u16 {
        let first = left.saturating_add(u16::try_from(from).unwrap_or(u16::MAX));
        let Some(shading) = shading else {
            set_spanned(tests, spans, first);
            return first;
        };
        if let Some((boxes, _)) = boxes {
            let last = left.saturating_add(u16::try_from(to.saturating_sub(1)).unwrap_or(u16::MAX));
            shading.set_segment(boxes, camera_y, first, last);
        }
        if !spans.is_empty() {
            set_spanned(tests, spans, first);
            shading.set_tested(tests, first);
        }
        first
    }

    /// Shades the rays `rays` of (part of) a row whose tests are prepared into `row` (as
    /// many as it holds), with the row's shading where its pixels share a plane. The
    /// loops are out of line: they keep their registers to themselves (in line in
    /// `render_row`, f32 scenes cost up to 30 % more on the Cortex-M4F).
    #[inline(always)]
    fn shade_part<C: From<Rgb888> + Copy>(
        &self,
        shader: &Shader<'_, S>,
        tests: &[RowEntry<S>],
        shading: Option<&RowShading<'_, S>>,
        rays: RowRays<S>,
        row: &mut [C],
    ) {
        match shading {
            Some(shading) => {
                let resolution = crate::plan::resolution(self.camera);
                shade_row(shader, shading, tests, rays, row, resolution);
            }
            #[cfg(feature = "batch")]
            None if self.shading == Shading::Color => {
                shade_batches(shader, tests, rays, row);
            }
            None => self.shade_pixels(shader, tests, rays, row),
        }
    }

    /// The pixels of a row whose objects' tests are prepared, one by one.
    #[inline(never)]
    fn shade_pixels<C: From<Rgb888> + Copy>(
        &self,
        shader: &Shader<'_, S>,
        tests: &[RowEntry<S>],
        rays: RowRays<S>,
        row: &mut [C],
    ) {
        // Nothing the rays can meet (every entry a miss or a run of columns beside these,
        // no tree: a scene's sky, the columns beside a ball or a rectangle): each pixel's
        // search finds nothing, and its colour is black. No ray made (in fixed point each
        // ray's length is a square root).
        #[cfg(all(feature = "plan", not(microray_small)))]
        let columns = rays.next_columns(row.len());
        #[cfg(not(all(feature = "plan", not(microray_small))))]
        let columns = [0, 0];
        if self.shading == Shading::Color && shader.tree().is_none() && nothing_met(tests, columns)
        {
            row.fill(Rgb888::new(0, 0, 0).into());
            return;
        }
        for (slot, ray) in slots_with_rays(row, rays) {
            *slot = self.color_in_row(shader, ray, tests).into();
        }
    }

    /// The entries of a row's prepared tests (by position) that are tested ray by ray and
    /// can be met only in some of the columns `left..left + width`, with their column
    /// spans; empty when none (or too many: the row is then shaded whole).
    fn column_spans(
        &self,
        tests: &[RowEntry<S>],
        left: u16,
        width: usize,
    ) -> heapless::Vec<(u8, RowSpan), MAX_SPANNED, u8> {
        let mut spans = heapless::Vec::new();
        // Built for size, rows are shaded whole (`shade_segments` is a second row loop).
        if cfg!(microray_small) {
            return spans;
        }
        let last = usize::from(left).saturating_add(width).saturating_sub(1);
        let kept = self.plan.kept();
        for (position, entry) in tests.iter().enumerate() {
            let span = match entry.test {
                RowTest::Hits => {
                    let Ok(found) = kept.binary_search(&entry.index) else {
                        continue;
                    };
                    let Some(&span) = self.plan.columns().get(found) else {
                        continue;
                    };
                    span
                }
                // Its own run: the segments outside it can then be the row's plane's.
                #[cfg(all(feature = "plan", not(microray_small)))]
                RowTest::AtAcross { first, last, .. } => RowSpan { first, last },
                _ => continue,
            };
            if span.first <= left && usize::from(span.last) >= last {
                continue;
            }
            let pushed = u8::try_from(position)
                .ok()
                .and_then(|position| spans.push((position, span)).ok());
            if pushed.is_none() {
                spans.clear();
                break;
            }
        }
        spans
    }

    /// The pixels of camera row `camera_y` at columns `first`, `first + stride`, ... into
    /// `row` (as many as it holds), shaded as [`render_row`](Self::render_row) shades a
    /// whole row: the row's tests prepared once, then segment by segment (the columns each
    /// object can be met in, the shadow boxes), each segment's pixels with rays of their
    /// own, the same as the row's. The progressive order's sparse rows.
    pub(crate) fn shade_every<C: From<Rgb888> + Copy>(
        &self,
        shader: &Shader<'_, S>,
        camera_y: u16,
        first: u16,
        stride: u16,
        tests: &mut RowTests<S, OBJECTS>,
        row: &mut [C],
    ) {
        let stride = stride.max(1);
        let rays = self.camera.row_rays_every(camera_y, first, stride);
        if !self.prepare_row(camera_y, &rays, tests) {
            for (slot, ray) in slots_with_rays(row, rays) {
                *slot = self.color(shader, ray, Among::All).into();
            }
            return;
        }
        let width = usize::from(self.camera.width());
        let spans = self.column_spans(tests, 0, width);
        let mut shading = None;
        self.row_shading_in(&mut shading, shader, tests, &rays, None);
        // No object in the row (a scene's sky), as `shade_segments` has it.
        #[cfg(feature = "batch")]
        if shading.is_none()
            && self.shading == Shading::Color
            && self.plan.in_row(camera_y).next().is_none()
        {
            row.fill(Rgb888::new(0, 0, 0).into());
            return;
        }
        let plane = shading.as_ref().and_then(RowShading::first_plane);
        let boxes = self.boxes().zip(plane);
        // The pixels before `column`: pixel `i` is column `first + i stride`.
        let (first_column, step) = (usize::from(first), usize::from(stride));
        let count = row.len();
        let before = |column: usize| {
            column
                .saturating_sub(first_column)
                .div_ceil(step)
                .min(count)
        };
        let mut runs = false;
        let mut from = 0;
        while from < width {
            let to = if cfg!(microray_small) {
                width
            } else {
                next_cut(&spans, boxes, camera_y, 0, width, from)
            };
            let (start, end) = (before(from), before(to));
            if let (true, Some(part)) = (start < end, row.get_mut(start..end)) {
                let segment = Segment {
                    camera_y,
                    left: 0,
                    from,
                    to,
                };
                let shading = &mut shading;
                self.ready_segment(
                    shader, tests, &spans, boxes, shading, &mut runs, &rays, segment,
                );
                let column = first_column + start * step;
                let rays = self.camera.row_rays_every(
                    camera_y,
                    u16::try_from(column).unwrap_or(u16::MAX),
                    stride,
                );
                self.shade_part(shader, tests, shading.as_ref(), rays, part);
            }
            from = to;
        }
    }
}

/// The pixels of a row whose objects' tests are prepared, [`BATCH`](crate::shade::BATCH)
/// at a time (see [`Shader::primary_batch_in_row`]).
#[cfg(feature = "batch")]
#[inline(never)]
fn shade_batches<S: Scalar, C: From<Rgb888>>(
    shader: &Shader<'_, S>,
    tests: &[RowEntry<S>],
    mut rays: RowRays<S>,
    row: &mut [C],
) {
    use crate::shade::BATCH;
    // Cleared once a row, not once a batch: every call writes all of it.
    let mut colors = [Vec3::ZERO; BATCH];
    for slots in row.chunks_mut(BATCH) {
        shader.primary_batch_in_row(&mut rays, slots.len(), tests, &mut colors);
        for (slot, c) in slots.iter_mut().zip(&colors) {
            *slot = bytes(*c).into();
        }
    }
}

/// The pixels of a row prepared for shading together (out of line: the loop keeps its
/// registers to itself); `resolution` as [`crate::plan::resolution`] has it for the camera.
#[inline(never)]
fn shade_row<S: Scalar, C: From<Rgb888>>(
    shader: &Shader<'_, S>,
    shading: &RowShading<'_, S>,
    tests: &[RowEntry<S>],
    rays: RowRays<S>,
    row: &mut [C],
    resolution: Geo,
) {
    if shading.plain() {
        // A bare row's loop of its own where a float unit makes it worth its flash (not the
        // Cortex-M0's).
        if HARD_FLOAT && !cfg!(microray_small) && shading.bare() {
            shade_bare_row(shader, shading, rays, row);
        } else {
            shade_plain_row(shader, shading, rays, row);
        }
    } else {
        shade_row_testing(shader, shading, tests, rays, row, resolution);
    }
}

/// [`shade_row`] for a plain row (every ray on the row's plane, every shadow decided).
/// Built for size, in line (a function more was flash).
#[cfg_attr(not(microray_small), inline(never))]
#[cfg_attr(microray_small, inline(always))]
fn shade_plain_row<S: Scalar, C: From<Rgb888>>(
    shader: &Shader<'_, S>,
    shading: &RowShading<'_, S>,
    rays: RowRays<S>,
    row: &mut [C],
) {
    for (slot, ray) in slots_with_rays(row, rays) {
        let c = ray.map_or(Vec3::ZERO, |ray| shader.shade_in_plain_row(shading, &ray));
        *slot = bytes(c).into();
    }
}

/// [`shade_plain_row`] for a [bare](RowShading::bare) row: no branch a pixel on its
/// mirror, transparency or glints (fplane0, aademo and spotlight 10-16 % cheaper on the
/// Cortex-M4F in `f32`). Out of line, apart from the plain rows' loop: in one function,
/// the two loops cost fixed point's plain rows up to 4 % more, and as one function generic
/// over which, spec0 3.4 % more.
#[inline(never)]
fn shade_bare_row<S: Scalar, C: From<Rgb888>>(
    shader: &Shader<'_, S>,
    shading: &RowShading<'_, S>,
    rays: RowRays<S>,
    row: &mut [C],
) {
    // Written out as `shade_plain_row`'s: through a closure-taking helper for both, spec0
    // cost 4 % more.
    for (slot, ray) in slots_with_rays(row, rays) {
        let c = ray.map_or(Vec3::ZERO, |ray| shader.shade_in_bare_row(shading, &ray));
        *slot = bytes(c).into();
    }
}

/// [`shade_row`] for a row that is not plain: its shadow tests prepared first (see
/// [`Shader::prepare_row_shadows`]). Out of line: the plain rows' loop (spec0's) keeps its stack.
/// Built for size (no tests prepared), in line.
#[cfg_attr(not(microray_small), inline(never))]
#[cfg_attr(microray_small, inline(always))]
fn shade_row_testing<S: Scalar, C: From<Rgb888>>(
    shader: &Shader<'_, S>,
    shading: &RowShading<'_, S>,
    tests: &[RowEntry<S>],
    rays: RowRays<S>,
    row: &mut [C],
    resolution: Geo,
) {
    let mut shadows = RowShadows::new();
    shader.prepare_row_shadows(&mut shadows, shading, resolution);
    // Asked once a row (see `Shader::shade_in_row_of`); built for size, no projector's copy.
    if shading.projected() && !cfg!(microray_small) {
        for (slot, ray) in slots_with_rays(row, rays) {
            let c = ray.map_or(Vec3::ZERO, |ray| {
                shader.shade_in_row_of::<true>(shading, &shadows, tests, &ray)
            });
            *slot = bytes(c).into();
        }
        return;
    }
    for (slot, ray) in slots_with_rays(row, rays) {
        let c = ray.map_or(Vec3::ZERO, |ray| {
            shader.shade_in_row_of::<false>(shading, &shadows, tests, &ray)
        });
        *slot = bytes(c).into();
    }
}

/// Each slot of `row` with the next of `rays`, as `row.iter_mut().zip(rays)` pairs them,
/// the rays' step always in line in the loop (not built for size): fixed point's
/// `Zip::next`, with the row's roots in it, was left out of line (a call a pixel, the ray
/// handed back through memory: fplane0 on the micro:bit 382 -> 332 instructions a pixel
/// without it).
#[inline(always)]
fn slots_with_rays<S: Scalar, C>(row: &mut [C], rays: RowRays<S>) -> SlotsWithRays<'_, S, C> {
    SlotsWithRays {
        slots: row.iter_mut(),
        rays,
    }
}

/// See [`slots_with_rays`].
struct SlotsWithRays<'r, S: Scalar, C> {
    slots: core::slice::IterMut<'r, C>,
    rays: RowRays<S>,
}

impl<'r, S: Scalar, C> Iterator for SlotsWithRays<'r, S, C> {
    type Item = (&'r mut C, Option<Ray<S>>);

    // Built for size, left to the compiler (flash: the step in each loop of its own).
    #[cfg_attr(not(microray_small), inline(always))]
    #[cfg_attr(microray_small, inline)]
    fn next(&mut self) -> Option<Self::Item> {
        let slot = self.slots.next()?;
        Some((slot, self.rays.next()?))
    }
}

/// A colour's channel bytes.
#[inline]
fn bytes<S: Scalar>(c: Vec3<S>) -> Rgb888 {
    Rgb888::new(c.x.to_byte(), c.y.to_byte(), c.z.to_byte())
}

/// The most entries of a row cut into segments by their column spans (more: shaded whole).
const MAX_SPANNED: usize = 4;

/// Whether no ray of the columns `[first, last]` of a row can meet an entry of its
/// prepared `tests`: each is a miss, or a run of columns beside these (whose rays are those
/// of its columns, see `Rect::row_test`). Out of line: in line, the rays' loop after it
/// kept its values in memory (tplane4 and fplane4 up to 1 % dearer on the Cortex-M4F).
#[inline(never)]
fn nothing_met<S: Scalar>(tests: &[RowEntry<S>], [first, last]: [u16; 2]) -> bool {
    #[cfg(any(not(feature = "plan"), microray_small))]
    let _ = (first, last);
    tests.iter().all(|entry| match entry.test {
        RowTest::Miss => true,
        #[cfg(all(feature = "plan", not(microray_small)))]
        RowTest::AtAcross {
            first: from,
            last: to,
            ..
        } => to < first || from > last,
        _ => false,
    })
}

/// Whether some entry is a rectangle met in a run of columns ([`RowTest::AtAcross`]), whose
/// segments can be shaded as its plane's (a plain or a textured one). Never built for size
/// (rectangles have no runs there).
#[inline(always)]
fn has_runs<S: Scalar>(objects: &[Object<S>], tests: &[RowEntry<S>]) -> bool {
    tests
        .iter()
        .any(|entry| run_of_plane(objects, entry).is_some())
}

/// Whether a run of columns of a rectangle (see [`has_runs`]) holds the image columns
/// `within` (first and last).
#[inline(always)]
fn in_run<S: Scalar>(objects: &[Object<S>], tests: &[RowEntry<S>], within: [u16; 2]) -> bool {
    tests.iter().any(|entry| {
        run_of_plane(objects, entry)
            .is_some_and(|[first, last]| first <= within[0] && within[1] <= last)
    })
}

/// The run of columns (first and last) of an entry that is a plain or textured rectangle
/// met in one.
#[inline(always)]
fn run_of_plane<S: Scalar>(objects: &[Object<S>], entry: &RowEntry<S>) -> Option<[u16; 2]> {
    #[cfg(all(feature = "plan", not(microray_small)))]
    if let RowTest::AtAcross { first, last, .. } = entry.test {
        let object = objects.get(usize::from(entry.index))?;
        let textured = matches!(object.shape(), crate::object::Shape::TexPlane(_));
        return (object.surface_is_uniform() || textured).then_some([first, last]);
    }
    let _ = (objects, entry);
    None
}

/// Turns the entries with column `spans` to tests where column `first` (and the segment it
/// starts) lies in their span, to misses where it does not. A run of columns
/// ([`RowTest::AtAcross`]) stays: it tells the segments itself (see
/// [`RowShading::set_tested`]).
fn set_spanned<S: Scalar>(tests: &mut [RowEntry<S>], spans: &[(u8, RowSpan)], first: u16) {
    for &(position, span) in spans {
        if let Some(entry) = tests.get_mut(usize::from(position)) {
            #[cfg(all(feature = "plan", not(microray_small)))]
            if matches!(entry.test, RowTest::AtAcross { .. }) {
                continue;
            }
            entry.test = if span.contains(first) {
                RowTest::Hits
            } else {
                RowTest::Miss
            };
        }
    }
}

/// Where the segment of a row `width` pixels long (its first at column `left`, which the
/// spans and boxes count from) that starts at `from` ends: at the first column after `from`
/// where one of the entries' spans, or one of the shadow boxes on the row's plane (`boxes`,
/// with the plane's index) that hold row `y`, starts or ends; `width` if none does. Found
/// anew for each segment (a row has a few), with no list of cuts to keep or sort.
fn next_cut(
    spans: &[(u8, RowSpan)],
    boxes: Option<(&ShadowBoxes, usize)>,
    y: u16,
    left: u16,
    width: usize,
    from: usize,
) -> usize {
    let mut next = width;
    let mut cut_at = |column: u16| {
        let cut = usize::from(column.saturating_sub(left));
        if cut > from && cut < next {
            next = cut;
        }
    };
    for (_, span) in spans {
        cut_at(span.first);
        cut_at(span.last.saturating_add(1));
    }
    if let Some((boxes, plane)) = boxes {
        boxes.cuts(plane, y, &mut cut_at);
    }
    next
}

/// A row's list as the closest-hit search takes it.
fn among<S, const N: usize>(objects: &Option<heapless::Vec<u16, N>>) -> Among<'_, S> {
    objects
        .as_ref()
        .map_or(Among::All, |list| Among::Only(list))
}

/// Renders the whole image into `target` with a row buffer of the scene's `MAX_WIDTH` pixels
/// on the stack.
pub fn render<
    S: Scalar,
    D,
    const OBJECTS: usize,
    const MATERIALS: usize,
    const LIGHTS: usize,
    const TEXTURES: usize,
    const MAX_WIDTH: usize,
>(
    scene: &Scene<'_, S, OBJECTS, MATERIALS, LIGHTS, TEXTURES, MAX_WIDTH>,
    target: &mut D,
) -> Result<Rendered, RenderError<D::Error>>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let renderer = Renderer::new(scene);
    let mut row = [D::Color::from(Rgb888::new(0, 0, 0)); MAX_WIDTH];
    let all = Rectangle::new(Point::zero(), renderer.size());
    renderer.render_area(target, all, &mut row, |_| ControlFlow::Continue(()))
}

#[cfg(all(test, feature = "std", feature = "plan"))]
mod tests {
    use super::*;
    use crate::camera::CameraDef;
    use crate::light::LightDef;
    use crate::material::MaterialDef;
    use crate::object::{ObjectDef, RectDef};
    use crate::shade::ROW_LIGHTS;
    use std::vec::Vec;

    /// A rectangle facing the eye, its edges slanted (aademo's), lit by `lights` lights:
    /// its rows have runs of columns, and with more than `ROW_LIGHTS` lights no shading
    /// of their own.
    fn tilted_panel<S: Scalar>(lights: usize) -> Scene<'static, S, 4, 4, 8, 0, 80> {
        let camera = CameraDef::new("c", [80, 60], [8.0, 6.0], [4.0, 4.0, 4.0]);
        let white = MaterialDef::new("white")
            .diffuse([5.0; 3])
            .ambient([2.0; 3]);
        let rect = RectDef::new(
            [0.0, 0.0, 1.0],
            [1.0, -2.0, -3.0],
            [1.0, 0.4, 0.0],
            [8.0, 6.0],
        );
        let panel = ObjectDef::fplane("p", "white", rect);
        let lights: Vec<_> = (0..lights)
            .map(|i| LightDef::point("l", [2.0 + i as f64, 3.0, 0.0], [1.0; 3]))
            .collect();
        Scene::from_defs(&camera, &[white], &[], &lights, &[panel])
            .unwrap_or_else(|e| panic!("{e:?}"))
    }

    /// Shades every segment of every row with `shade_pixels` (the firmware's loop, which
    /// fills black where no ray can meet anything) and with each pixel's own search; returns
    /// how many segments beside a run of columns were filled black.
    fn segments_match<S: Scalar>(lights: usize) -> usize {
        let scene = tilted_panel::<S>(lights);
        let renderer: Renderer<'_, S, 4> = Renderer::new(&scene);
        let shader = renderer.shader();
        let width = usize::from(renderer.camera.width());
        let mut filled = 0;
        for camera_y in 0..renderer.camera.height() {
            let mut tests = heapless::Vec::new();
            let rays = renderer.camera.row_rays(camera_y, 0);
            assert!(renderer.prepare_row(camera_y, &rays, &mut tests));
            let spans = renderer.column_spans(&tests, 0, width);
            let mut from = 0;
            while from < width {
                let to = next_cut(&spans, None, camera_y, 0, width, from);
                let first = u16::try_from(from).unwrap();
                set_spanned(&mut tests, &spans, first);
                let mut fast = [Rgb888::new(1, 2, 3); 80];
                let rays = renderer.camera.row_rays(camera_y, first);
                renderer.shade_pixels(&shader, &tests, rays, &mut fast[from..to]);
                let rays = renderer.camera.row_rays(camera_y, first);
                for (column, ray) in (from..to).zip(rays) {
                    let alone = renderer.color_in_row(&shader, ray, &tests);
                    assert_eq!(
                        fast[column],
                        alone,
                        "{} row {camera_y} column {column}",
                        S::NAME
                    );
                }
                let beside_run = tests
                    .iter()
                    .any(|e| matches!(e.test, RowTest::AtAcross { .. }));
                let columns = [first, u16::try_from(to - 1).unwrap()];
                if beside_run && nothing_met(&tests, columns) {
                    filled += 1;
                }
                from = to;
            }
        }
        filled
    }

    #[test]
    fn the_pixels_beside_a_run_of_columns_are_black_and_those_in_it_are_shaded() {
        for lights in [1, ROW_LIGHTS + 1] {
            // Rows beside the rectangle's runs are filled without rays.
            assert!(segments_match::<f32>(lights) > 0, "{lights} lights");
            assert!(
                segments_match::<crate::scalar::I16F16>(lights) > 0,
                "{lights} lights"
            );
        }
    }
}
