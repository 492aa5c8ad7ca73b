//! Progressive rendering: for every scene (the project's, the course's and its later ones,
//! the stress scenes) in every number type, the progressive order leaves exactly the image
//! of the plain order, tracing every pixel once; each pass covers the whole image.

mod common;

use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use microray::Scalar;
use microray::host::{Framebuffer, HostRenderer, HostScene, texture_files};
use microray::parse::parse_scene;
use microray::render::{BLOCKS, Rendered, Renderer};
use microray::scalar::I16F16;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

/// A framebuffer that counts the pixels each kind of call writes.
struct Counting {
    frame: Framebuffer,
    /// The side of the current pass's blocks.
    block: u32,
    /// Pixels traced: one per `fill_solid` (a block's own pixel), one per pixel of a
    /// one-row `fill_contiguous` or of a `draw_iter`, one per block of a taller
    /// `fill_contiguous` (a row of blocks, checked to be blocks of one colour each).
    traced: usize,
    /// The pixels written at least once so far.
    covered: Vec<bool>,
}

impl OriginDimensions for Counting {
    fn size(&self) -> Size {
        self.frame.size()
    }
}

impl Counting {
    fn cover(&mut self, area: &Rectangle) {
        let width = self.frame.size().width as usize;
        for p in area.points() {
            self.covered[p.y as usize * width + p.x as usize] = true;
        }
    }
}

impl DrawTarget for Counting {
    type Color = Rgb888;
    type Error = core::convert::Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Self::Error> {
        for Pixel(p, color) in pixels {
            let one = Rectangle::new(p, Size::new(1, 1));
            self.traced += 1;
            self.cover(&one);
            self.frame.fill_solid(&one, color)?;
        }
        Ok(())
    }
    fn fill_solid(&mut self, area: &Rectangle, color: Rgb888) -> Result<(), Self::Error> {
        self.traced += 1;
        self.cover(area);
        self.frame.fill_solid(area, color)
    }
    fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Self::Error> {
        let colors: Vec<Rgb888> = colors.into_iter().collect();
        let (width, height) = (area.size.width as usize, area.size.height as usize);
        assert_eq!(colors.len(), width * height);
        if height == 1 {
            self.traced += width;
        } else {
            // A row of blocks: `block` wide (the last one cut), every row alike.
            let block = self.block as usize;
            assert!(height <= block, "{height} rows of blocks of {block}");
            let first = &colors[..width];
            for row in colors.chunks(width) {
                assert_eq!(row, first, "the rows of a row of blocks differ");
            }
            for run in first.chunks(block) {
                assert!(run.iter().all(|&c| c == run[0]), "a block of two colours");
            }
            self.traced += width.div_ceil(block);
        }
        self.cover(area);
        self.frame.fill_contiguous(area, colors)
    }
}

fn scenes() -> Vec<PathBuf> {
    common::all_scenes_with("stress")
}

fn check<S: Scalar>(path: &Path) {
    let text = std::fs::read(path).unwrap();
    let parsed: Result<HostScene<'_, S>, _> =
        parse_scene(&text, texture_files(path.parent().unwrap()));
    let Ok(scene) = parsed else {
        // A scene the type cannot hold (tests/stress.rs checks that it says so).
        return;
    };
    let renderer: HostRenderer<'_, S> = Renderer::new(&scene);
    let size = renderer.size();
    let mut plain = Framebuffer::new(size);
    let mut row = vec![Rgb888::BLACK; size.width as usize];
    let all = Rectangle::new(Point::zero(), size);
    renderer
        .render_area(&mut plain, all, &mut row, |_| ControlFlow::Continue(()))
        .unwrap();
    let mut progressive = Counting {
        frame: Framebuffer::new(size),
        block: 0,
        traced: 0,
        covered: vec![false; (size.width * size.height) as usize],
    };
    for (pass, &block) in BLOCKS.iter().enumerate() {
        progressive.block = u32::from(block);
        renderer
            .render_pass(&mut progressive, &mut row, pass)
            .unwrap();
    }
    let name = format!("{} in {}", path.display(), S::NAME);
    assert_eq!(
        progressive.traced,
        (size.width * size.height) as usize,
        "{name}: every pixel traced once"
    );
    assert!(progressive.covered.iter().all(|&c| c), "{name}");
    assert!(
        progressive.frame.rgb() == plain.rgb(),
        "{name}: the progressive image differs from the plain one"
    );
}

#[test]
fn the_progressive_order_gives_the_plain_image_in_every_type() {
    let files = scenes();
    assert!(files.len() >= 20, "{} scenes", files.len());
    for path in &files {
        check::<f64>(path);
        check::<f32>(path);
        check::<I16F16>(path);
    }
}

#[test]
fn render_progressive_runs_the_passes_in_order() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/vases.txt");
    let text = std::fs::read(&path).unwrap();
    let scene: HostScene<'_, f32> =
        parse_scene(&text, texture_files(path.parent().unwrap())).unwrap();
    let renderer: HostRenderer<'_, f32> = Renderer::new(&scene);
    let mut frame = Framebuffer::new(renderer.size());
    let mut row = vec![Rgb888::BLACK; renderer.size().width as usize];
    let mut passes = Vec::new();
    let done = renderer
        .render_progressive(&mut frame, &mut row, |pass| {
            passes.push(pass.block);
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(done, Rendered::Complete);
    assert_eq!(passes, BLOCKS);
    assert!(frame.rgb() == common::image(&renderer).rgb());
}

#[test]
fn the_first_pass_covers_the_image() {
    // Stop after the first pass: every pixel is written, with 1/64 of them traced.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/vases.txt");
    let text = std::fs::read(&path).unwrap();
    let scene: HostScene<'_, f32> =
        parse_scene(&text, texture_files(path.parent().unwrap())).unwrap();
    let renderer: HostRenderer<'_, f32> = Renderer::new(&scene);
    let size = renderer.size();
    let mut target = Counting {
        frame: Framebuffer::new(size),
        block: 8,
        traced: 0,
        covered: vec![false; (size.width * size.height) as usize],
    };
    let mut row = vec![Rgb888::BLACK; size.width as usize];
    let done = renderer
        .render_progressive(&mut target, &mut row, |_| ControlFlow::Break(()))
        .unwrap();
    assert_eq!(done, Rendered::StoppedAfterPass { block: 8 });
    assert!(target.covered.iter().all(|&c| c));
    let blocks = size.width.div_ceil(8) * size.height.div_ceil(8);
    assert_eq!(target.traced, blocks as usize);
}
