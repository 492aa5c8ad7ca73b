//! Anti-aliasing at fixed sample positions: one sample is the plain render; the plan
//! changes no pixel; an area is the whole image's pixels there; more samples come closer to
//! a 64-sample render; the adaptive mode supersamples only edges. Prints the quality table
//! docs/benchmarks.md quotes.

mod common;

use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use microray::Scalar;
use microray::host::{
    Difference, Framebuffer, HostRenderer, HostScene, antialiased, texture_files,
};
use microray::parse::parse_scene;
use microray::render::{AaPixel, Antialias, Pattern, RenderError, Renderer, Samples};
use microray::scalar::I16F16;
use std::collections::HashSet;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

fn scenes() -> Vec<PathBuf> {
    common::all_scenes_with("stress")
}

/// The scene at `path` in `S`, at `size` if given; `None` when the type cannot hold it.
fn load<S: Scalar>(path: &Path, size: Option<(u16, u16)>) -> Option<HostScene<'static, S>> {
    let text = std::fs::read(path).unwrap();
    let mut scene: HostScene<'static, S> =
        parse_scene(&text, texture_files(path.parent().unwrap())).ok()?;
    if let Some((w, h)) = size {
        scene.set_resolution(w, h).ok()?;
    }
    Some(scene)
}

const ADAPTIVE: Antialias = Antialias::Adaptive {
    samples: match Samples::rotated(16) {
        Some(s) => s,
        None => Samples::ONE,
    },
    threshold: 8,
};

fn grid(count: u16) -> Antialias {
    Antialias::Grid(Samples::rotated(count).unwrap())
}

#[test]
fn sample_offsets_stay_in_the_pixel_and_the_rotated_grid_has_a_row_and_column_each() {
    for side in 1..=16u16 {
        let count = side * side;
        for pattern in [Pattern::Regular, Pattern::Rotated] {
            let samples = Samples::new(count, pattern).unwrap();
            assert_eq!(samples.count(), count);
            let offsets: Vec<[i32; 2]> = (0..count).map(|k| samples.offset(k)).collect();
            let limit = i32::from(count);
            assert!(offsets.iter().flatten().all(|&o| -limit < o && o < limit));
            let distinct = |axis: usize| {
                offsets
                    .iter()
                    .map(|o| o[axis])
                    .collect::<HashSet<_>>()
                    .len()
            };
            let points = offsets.iter().collect::<HashSet<_>>().len();
            assert_eq!(
                points,
                usize::from(count),
                "{pattern:?} {count}: distinct points"
            );
            let expected = match pattern {
                Pattern::Regular => usize::from(side),
                Pattern::Rotated => usize::from(count),
            };
            assert_eq!(
                (distinct(0), distinct(1)),
                (expected, expected),
                "{pattern:?} {count}"
            );
            // Centred on the pixel's point: the offsets sum to zero on each axis.
            let sum = |axis: usize| offsets.iter().map(|o| o[axis]).sum::<i32>();
            assert_eq!((sum(0), sum(1)), (0, 0), "{pattern:?} {count}");
        }
    }
    assert_eq!(Samples::rotated(1).unwrap().offset(0), [0, 0]);
    for count in [0, 2, 3, 5, 8, 255, 257, 289] {
        assert!(Samples::rotated(count).is_none(), "{count}");
    }
}

fn one_sample_is_the_plain_render<S: Scalar>(path: &Path) {
    let Some(scene) = load::<S>(path, None) else {
        return;
    };
    let renderer: HostRenderer<'_, S> = Renderer::new(&scene);
    let plain = common::image(&renderer);
    let one = antialiased(&renderer, Antialias::Grid(Samples::ONE)).unwrap();
    assert!(
        one.rgb() == plain.rgb(),
        "{} in {}: one sample differs from the plain render",
        path.display(),
        S::NAME
    );
}

#[test]
fn one_sample_a_pixel_is_the_plain_render_in_every_type() {
    let files = scenes();
    assert!(files.len() >= 20, "{} scenes", files.len());
    for path in &files {
        one_sample_is_the_plain_render::<f64>(path);
        one_sample_is_the_plain_render::<f32>(path);
        one_sample_is_the_plain_render::<I16F16>(path);
    }
}

/// The plan gives the pixels of the render without it, and an area the whole image's
/// pixels there (a band of rows and columns inside the image, whose adaptive edges compare
/// with pixels outside it).
fn plan_and_areas_change_nothing<S: Scalar>(path: &Path) {
    let Some(scene) = load::<S>(path, Some((96, 72))) else {
        return;
    };
    let renderer: HostRenderer<'_, S> = Renderer::new(&scene);
    let unplanned = renderer.clone().with_plan(false);
    let name = format!("{} in {}", path.display(), S::NAME);
    for aa in [grid(4), ADAPTIVE] {
        let planned_image = antialiased(&renderer, aa).unwrap();
        let unplanned_image = antialiased(&unplanned, aa).unwrap();
        assert!(
            planned_image.rgb() == unplanned_image.rgb(),
            "{name} {aa:?}: the plan changed pixels"
        );
        let band = Rectangle::new(Point::new(13, 20), Size::new(50, 31));
        let mut partial = Framebuffer::new(renderer.size());
        let mut buffer = vec![AaPixel::NEW; Antialias::buffer_len(50)];
        renderer
            .render_antialiased(&mut partial, band, aa, &mut buffer, |_| {
                ControlFlow::Continue(())
            })
            .unwrap();
        for p in band.points() {
            let at = |image: &Framebuffer| {
                let i = 3 * (p.y as usize * 96 + p.x as usize);
                image.rgb()[i..i + 3].to_vec()
            };
            assert_eq!(at(&partial), at(&planned_image), "{name} {aa:?} at {p:?}");
        }
    }
}

#[test]
fn the_plan_and_areas_change_no_pixel_in_any_type() {
    for path in &scenes() {
        plan_and_areas_change_nothing::<f64>(path);
        plan_and_areas_change_nothing::<f32>(path);
        plan_and_areas_change_nothing::<I16F16>(path);
    }
}

#[test]
fn a_small_buffer_is_an_error() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/vases.txt");
    let scene = load::<f32>(&path, Some((40, 30))).unwrap();
    let renderer: HostRenderer<'_, f32> = Renderer::new(&scene);
    let mut image = Framebuffer::new(renderer.size());
    let mut buffer = vec![AaPixel::NEW; Antialias::buffer_len(40) - 1];
    let all = Rectangle::new(Point::zero(), renderer.size());
    let result = renderer.render_antialiased(&mut image, all, ADAPTIVE, &mut buffer, |_| {
        ControlFlow::Continue(())
    });
    assert_eq!(
        result,
        Err(RenderError::RowBufferTooSmall {
            needed: 84,
            len: 83
        })
    );
}

/// PSNR against a 64-sample render of each course scene at 160x120, for 1, 4, 9, 16 samples
/// and the adaptive mode.
#[test]
fn quality_against_64_samples() {
    let mut files: Vec<PathBuf> = Vec::new();
    if let Some(dir) = common::conformance_dir() {
        files.extend(common::scene_files(&dir));
    } else {
        return;
    }
    let modes: [(&str, Antialias); 5] = [
        ("1", Antialias::Grid(Samples::ONE)),
        ("4", grid(4)),
        ("9", grid(9)),
        ("16", grid(16)),
        ("adaptive", ADAPTIVE),
    ];
    println!("| scene | {} |", modes.map(|(name, _)| name).join(" | "));
    println!("|---|{}", "---|".repeat(modes.len()));
    for path in &files {
        let scene = load::<f64>(path, Some((160, 120))).unwrap();
        let renderer: HostRenderer<'_, f64> = Renderer::new(&scene);
        let reference = antialiased(&renderer, grid(64)).unwrap();
        let psnr: Vec<f64> = modes
            .iter()
            .map(|&(_, aa)| {
                let image = antialiased(&renderer, aa).unwrap();
                Difference::between(reference.rgb(), image.rgb(), |_| false).psnr()
            })
            .collect();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let cells: Vec<String> = psnr.iter().map(|p| format!("{p:.1} dB")).collect();
        println!("| {name} | {} |", cells.join(" | "));
        // Every scene has edges: each grid comes at least 3 dB closer than one sample, 16
        // closer than 4, and the adaptive mode (16 samples on edges) closer than 4 on every
        // pixel.
        for (i, &(mode, _)) in modes.iter().enumerate().skip(1).take(3) {
            assert!(
                psnr[i] > psnr[0] + 3.0,
                "{name}: {mode} samples {:.1} dB against 1 sample {:.1} dB",
                psnr[i],
                psnr[0]
            );
        }
        assert!(psnr[3] > psnr[1], "{name}: 16 samples no closer than 4");
        assert!(
            psnr[4] > psnr[1],
            "{name}: adaptive no closer than 4 samples"
        );
    }
}

#[test]
#[cfg_attr(
    not(microray_conformance),
    ignore = "needs the course's scenes: set MICRORAY_CONFORMANCE to their folder"
)]
fn aademo_comes_closer_to_the_course_image() {
    // The course's aademo jittered its samples, so no render matches it; anti-aliasing
    // must still come closer to it than one ray a pixel.
    let dir = common::required_conformance_dir();
    let path = dir.join("aa/aademo.txt");
    let reference =
        microray::host::read_ppm(&std::fs::read(dir.join("aa/aademo.ppm")).unwrap()).unwrap();
    let scene = load::<f64>(&path, None).unwrap();
    let renderer: HostRenderer<'_, f64> = Renderer::new(&scene);
    let psnr = |aa| {
        let image = antialiased(&renderer, aa).unwrap();
        Difference::between(reference.rgb(), image.rgb(), |_| false).psnr()
    };
    let (one, sixteen, adaptive) = (
        psnr(Antialias::Grid(Samples::ONE)),
        psnr(grid(16)),
        psnr(ADAPTIVE),
    );
    println!(
        "aademo against the course's image: 1 sample {one:.2} dB, 16 {sixteen:.2} dB, adaptive {adaptive:.2} dB"
    );
    assert!(sixteen > one + 5.0 && adaptive > one + 5.0);
}

#[test]
#[cfg_attr(
    not(microray_conformance),
    ignore = "needs the course's scenes: set MICRORAY_CONFORMANCE to their folder"
)]
fn adaptive_supersamples_only_edges() {
    // Every pixel the adaptive render changes is on an edge of the plain render (it differs
    // from a neighbour there); on the course's aademo, a few percent of the pixels.
    let dir = common::required_conformance_dir();
    let scene = load::<f64>(&dir.join("aa/aademo.txt"), None).unwrap();
    let renderer: HostRenderer<'_, f64> = Renderer::new(&scene);
    let plain = common::image(&renderer);
    let objects = microray::host::object_ids(&renderer);
    let adaptive = antialiased(&renderer, ADAPTIVE).unwrap();
    let size = renderer.size();
    let (w, h) = (size.width as i64, size.height as i64);
    let at = |image: &Framebuffer, x: i64, y: i64| {
        let i = 3 * (y * w + x) as usize;
        [image.rgb()[i], image.rgb()[i + 1], image.rgb()[i + 2]]
    };
    let mut changed = 0;
    for y in 0..h {
        for x in 0..w {
            if at(&plain, x, y) == at(&adaptive, x, y) {
                continue;
            }
            changed += 1;
            let c = at(&plain, x, y);
            let on_edge = [(-1, 0), (1, 0), (0, -1), (0, 1)].iter().any(|&(dx, dy)| {
                let (nx, ny) = (x + dx, y + dy);
                (0..w).contains(&nx)
                    && (0..h).contains(&ny)
                    && (objects[(ny * w + nx) as usize] != objects[(y * w + x) as usize]
                        || at(&plain, nx, ny)
                            .iter()
                            .zip(c)
                            .any(|(a, b)| a.abs_diff(b) > 8))
            });
            assert!(on_edge, "({x}, {y}) changed but is not on an edge");
        }
    }
    let share = changed as f64 / (w * h) as f64;
    println!(
        "aademo adaptive: {changed} pixels changed ({:.2} %)",
        100.0 * share
    );
    assert!(share > 0.001 && share < 0.05, "{share}");
}
