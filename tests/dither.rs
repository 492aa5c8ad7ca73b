//! Rgb565 dithering against truncation, on the course's scenes: each f64 image converted
//! both ways, expanded back to 8 bits (as embedded-graphics converts), and compared with the
//! f64 Rgb888 image after a 4x4 box filter (the eye's blur at a panel's pixel size). The
//! dithered image must be the closer one on every scene with gradients (all of them).
//! Prints the table docs/panels.md quotes.

mod common;

use embedded_graphics::mock_display::MockDisplay;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::*;
use microray::Scene;
use microray::dither::{Rgb565Dither, dither_rgb565, truncate_rgb565};
use microray::host::{Framebuffer, HostScene, texture_files};
use microray::parse::{no_textures, parse_scene};
use microray::render::render;

/// The RMS difference (8-bit levels) between the 4x4 tile means of two images.
fn box_filtered_rms(width: usize, a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let height = a.len() / width;
    let (mut sum, mut n) = (0.0, 0usize);
    for ty in 0..height / 4 {
        for tx in 0..width / 4 {
            for k in 0..3 {
                let mean = |img: &[[f64; 3]]| {
                    let mut s = 0.0;
                    for y in 0..4 {
                        for x in 0..4 {
                            s += img[(ty * 4 + y) * width + tx * 4 + x][k];
                        }
                    }
                    s / 16.0
                };
                let d = mean(a) - mean(b);
                sum += d * d;
                n += 1;
            }
        }
    }
    (sum / n.max(1) as f64).sqrt()
}

fn expanded(c: Rgb565) -> [f64; 3] {
    let c = Rgb888::from(c);
    [f64::from(c.r()), f64::from(c.g()), f64::from(c.b())]
}

#[test]
#[cfg_attr(
    not(microray_conformance),
    ignore = "needs the course's scenes: set MICRORAY_CONFORMANCE to their folder"
)]
fn dithering_beats_truncation_on_every_course_scene() {
    let dir = common::required_conformance_dir();
    let mut table = String::from("| scene | truncated | dithered |\n|---|---|---|\n");
    let mut worse = Vec::new();
    for path in common::scene_files(&dir) {
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        let text = std::fs::read(&path).unwrap();
        let scene: HostScene<'_, f64> =
            parse_scene(&text, texture_files(path.parent().unwrap())).unwrap();
        let camera = scene.camera();
        let (width, height) = (usize::from(camera.width()), usize::from(camera.height()));
        let mut image = Framebuffer::new(Size::new(width as u32, height as u32));
        render(&scene, &mut image).unwrap();
        let pixels: Vec<Rgb888> = image
            .rgb()
            .chunks(3)
            .map(|c| Rgb888::new(c[0], c[1], c[2]))
            .collect();
        let reference: Vec<[f64; 3]> = pixels
            .iter()
            .map(|c| [f64::from(c.r()), f64::from(c.g()), f64::from(c.b())])
            .collect();
        let truncated: Vec<[f64; 3]> = pixels
            .iter()
            .map(|&c| expanded(truncate_rgb565(c)))
            .collect();
        let dithered: Vec<[f64; 3]> = pixels
            .iter()
            .enumerate()
            .map(|(i, &c)| {
                let p = Point::new((i % width) as i32, (i / width) as i32);
                expanded(dither_rgb565(c, p))
            })
            .collect();
        let t = box_filtered_rms(width, &reference, &truncated);
        let d = box_filtered_rms(width, &reference, &dithered);
        table.push_str(&format!("| {name} | {t:.3} | {d:.3} |\n"));
        if d >= t || d.is_nan() {
            worse.push(name);
        }
    }
    eprintln!("{table}");
    assert!(worse.is_empty(), "dithering not better on {worse:?}");
}

#[test]
fn the_wrapper_dithers_what_the_renderer_draws() {
    // A floor under a lamp: a gradient. Rendered through the wrapper into an Rgb565 display,
    // and as Rgb888 then dithered pixel by pixel: the same.
    let text = b"camera c { pixeldim 48 36 worlddim 8 6 viewpoint 4 3 4 }
                 material grey { ambient 1 1 1 diffuse 3 3 3 }
                 plane floor { material grey normal 0 1 0 point 0 0 0 }
                 light sun { location 4 5 -2 emissivity 4 4 4 }";
    let scene: Scene<f32, 2, 1, 1, 0, 48> = parse_scene(text, no_textures).unwrap();
    let mut panel: MockDisplay<Rgb565> = MockDisplay::new();
    panel.set_allow_overdraw(true);
    render(&scene, &mut Rgb565Dither::new(&mut panel)).unwrap();
    let mut full: MockDisplay<Rgb888> = MockDisplay::new();
    render(&scene, &mut full).unwrap();
    let mut distinct = std::collections::BTreeSet::new();
    for y in 0..36 {
        for x in 0..48 {
            let p = Point::new(x, y);
            let expected = dither_rgb565(full.get_pixel(p).unwrap(), p);
            assert_eq!(panel.get_pixel(p), Some(expected), "{p:?}");
            distinct.insert(expected.into_storage());
        }
    }
    assert!(distinct.len() > 4, "a gradient, not a flat colour");
}
