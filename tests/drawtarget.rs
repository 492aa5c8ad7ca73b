//! Rendering into DrawTargets: one `fill_contiguous` per row, top to bottom, nothing else;
//! the simulator display gets exactly the std tracer's pixels; degenerate scenes give the
//! defined image.

mod common;

use embedded_graphics::pixelcolor::{Gray8, Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use embedded_graphics_simulator::SimulatorDisplay;
use microray::host::{Framebuffer, HostScene, read_ppm, texture_files};
use microray::parse::{no_textures, parse_scene};
use microray::render::{RenderError, Rendered, Renderer, render};
use std::convert::Infallible;
use std::ops::ControlFlow;
use std::path::Path;
use std::process::Command;

/// Records every call a renderer makes.
#[derive(Default)]
struct Recorder {
    rows: Vec<(Rectangle, Vec<Rgb888>)>,
    other_calls: usize,
}

impl OriginDimensions for Recorder {
    fn size(&self) -> Size {
        Size::new(9, 7)
    }
}

impl DrawTarget for Recorder {
    type Color = Rgb888;
    type Error = Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, _: I) -> Result<(), Infallible> {
        self.other_calls += 1;
        Ok(())
    }
    fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Infallible> {
        self.rows.push((*area, colors.into_iter().collect()));
        Ok(())
    }
    fn fill_solid(&mut self, _: &Rectangle, _: Rgb888) -> Result<(), Infallible> {
        self.other_calls += 1;
        Ok(())
    }
    fn clear(&mut self, _: Rgb888) -> Result<(), Infallible> {
        self.other_calls += 1;
        Ok(())
    }
}

/// A 9 x 7 scene: a red ambient wall 5 behind the image plane, seen from 3 in front of it.
const WALL: &[u8] = b"camera c { pixeldim 9 7 worlddim 8 6 viewpoint 4 3 3 }
    material red { ambient 1 0 0 diffuse 2 0 0 }
    plane back { material red normal 0 0 1 point 0 0 -5 }";

type Small<'t> = microray::Scene<'t, f64, 4, 4, 2, 0, 16>;

fn small(text: &[u8]) -> Small<'static> {
    parse_scene(text, no_textures).unwrap()
}

#[test]
fn each_row_is_one_fill_contiguous_call_top_to_bottom() {
    let mut recorder = Recorder::default();
    assert_eq!(render(&small(WALL), &mut recorder), Ok(Rendered::Complete));
    assert_eq!(recorder.other_calls, 0);
    assert_eq!(recorder.rows.len(), 7);
    for (row, (area, colors)) in recorder.rows.iter().enumerate() {
        assert_eq!(
            *area,
            Rectangle::new(Point::new(0, row as i32), Size::new(9, 1))
        );
        assert_eq!(colors.len(), 9);
    }
    // The centre pixel (4, 3) looks straight down -z: t = 8, so ambient 1 / 8 = 0.125, and
    // 0.125 * 255 = 31.875 truncates to 31. No lights: no diffuse.
    assert_eq!(recorder.rows[3].1[4], Rgb888::new(31, 0, 0));
}

#[test]
fn sub_rectangles_and_stopping() {
    let scene = small(WALL);
    let renderer = Renderer::new(&scene);
    let mut full = Recorder::default();
    render(&scene, &mut full).unwrap();

    let mut part = Recorder::default();
    let mut row = [Rgb888::BLACK; 3];
    let area = Rectangle::new(Point::new(2, 1), Size::new(3, 2));
    let mut seen = Vec::new();
    let done = renderer.render_area(&mut part, area, &mut row, |r| {
        seen.push((r.row, r.done, r.total));
        ControlFlow::Continue(())
    });
    assert_eq!(done, Ok(Rendered::Complete));
    assert_eq!(seen, [(1, 1, 2), (2, 2, 2)]);
    assert_eq!(part.rows.len(), 2);
    for (i, (area, colors)) in part.rows.iter().enumerate() {
        assert_eq!(
            *area,
            Rectangle::new(Point::new(2, 1 + i as i32), Size::new(3, 1))
        );
        assert_eq!(colors[..], full.rows[1 + i].1[2..5]);
    }

    // An area partly outside the image is clipped to it.
    let mut clipped = Recorder::default();
    let mut wide = [Rgb888::BLACK; 16];
    let outside = Rectangle::new(Point::new(7, 5), Size::new(10, 10));
    renderer
        .render_area(&mut clipped, outside, &mut wide, |_| {
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(
        clipped.rows.iter().map(|(a, _)| *a).collect::<Vec<_>>(),
        [
            Rectangle::new(Point::new(7, 5), Size::new(2, 1)),
            Rectangle::new(Point::new(7, 6), Size::new(2, 1)),
        ]
    );

    // The callback can stop the render.
    let mut stopped = Recorder::default();
    let all = Rectangle::new(Point::zero(), Size::new(9, 7));
    let mut row = [Rgb888::BLACK; 9];
    let result = renderer.render_area(&mut stopped, all, &mut row, |r| {
        if r.done == 2 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    assert_eq!(result, Ok(Rendered::Stopped { rows: 2 }));
    assert_eq!(stopped.rows.len(), 2);

    // A row buffer narrower than the area is an error, not a panic.
    let mut short = [Rgb888::BLACK; 8];
    let result = renderer.render_area(&mut Recorder::default(), all, &mut short, |_| {
        ControlFlow::Continue(())
    });
    assert_eq!(
        result,
        Err(RenderError::RowBufferTooSmall { needed: 9, len: 8 })
    );
}

fn all_black(text: &[u8]) {
    let mut recorder = Recorder::default();
    render(&small(text), &mut recorder).unwrap();
    assert_eq!(recorder.rows.len(), 7);
    assert!(
        recorder
            .rows
            .iter()
            .all(|(_, c)| c.iter().all(|&p| p == Rgb888::BLACK))
    );
}

#[test]
fn degenerate_scenes_give_the_defined_image() {
    // No objects at all.
    all_black(b"camera c { pixeldim 9 7 worlddim 8 6 viewpoint 4 3 3 } light l { location 4 3 0 emissivity 1 1 1 }");
    // Only objects in front of the image plane (z > 0.01): never hit.
    all_black(
        b"camera c { pixeldim 9 7 worlddim 8 6 viewpoint 4 3 3 }
          material m { ambient 1 1 1 }
          sphere s { material m center 4 3 1.5 radius 1 }
          plane p { material m normal 0 0 1 point 0 0 0.5 }
          light l { location 4 3 0 emissivity 1 1 1 }",
    );
    // A black material, and a light behind the surface.
    all_black(
        b"camera c { pixeldim 9 7 worlddim 8 6 viewpoint 4 3 3 }
          material m { }
          material d { diffuse 1 1 1 }
          plane p { material m normal 0 0 1 point 0 0 -5 }
          plane q { material d normal 0 0 1 point 0 0 -9 }
          light l { location 4 3 -20 emissivity 1 1 1 }",
    );
    // The eye on the image plane: every primary ray runs within z = 0, parallel to the wall;
    // the pixel under the eye has no direction at all.
    all_black(
        b"camera c { pixeldim 9 7 worlddim 8 6 viewpoint 4 3 0 }
          material red { ambient 1 0 0 }
          plane back { material red normal 0 0 1 point 0 0 -5 }",
    );
}

fn ppm_from_the_std_tracer(scene: &Path) -> Framebuffer {
    let out = std::env::temp_dir().join(format!(
        "microray-{}-{}.ppm",
        std::process::id(),
        scene.file_stem().unwrap().to_str().unwrap()
    ));
    let status = Command::new(env!("CARGO_BIN_EXE_microray"))
        .args([
            "render",
            "--quiet",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .status()
        .unwrap();
    assert!(status.success());
    let image = read_ppm(&std::fs::read(&out).unwrap()).unwrap();
    std::fs::remove_file(&out).unwrap();
    image
}

#[test]
fn simulator_display_gets_the_std_tracers_pixels() {
    for path in common::project_scenes() {
        let text = std::fs::read(&path).unwrap();
        let scene: HostScene<'_, f64> =
            parse_scene(&text, texture_files(path.parent().unwrap())).unwrap();
        let size = Size::new(
            u32::from(scene.camera().width()),
            u32::from(scene.camera().height()),
        );
        let expected = ppm_from_the_std_tracer(&path);

        let mut rgb888 = SimulatorDisplay::<Rgb888>::new(size);
        render(&scene, &mut rgb888).unwrap();
        let mut rgb565 = SimulatorDisplay::<Rgb565>::new(size);
        render(&scene, &mut rgb565).unwrap();
        let mut gray = SimulatorDisplay::<Gray8>::new(size);
        render(&scene, &mut gray).unwrap();

        for (i, px) in expected.rgb().chunks(3).enumerate() {
            let p = Point::new(
                (i as u32 % size.width) as i32,
                (i as u32 / size.width) as i32,
            );
            let want = Rgb888::new(px[0], px[1], px[2]);
            assert_eq!(rgb888.get_pixel(p), want, "{} at {p:?}", path.display());
            assert_eq!(
                rgb565.get_pixel(p),
                Rgb565::from(want),
                "{} at {p:?}",
                path.display()
            );
            assert_eq!(
                gray.get_pixel(p),
                Gray8::from(want),
                "{} at {p:?}",
                path.display()
            );
        }
    }
}
