//! Rgb565 dithering against truncation, on the course's scenes: each f64 image converted
//! both ways, expanded back to 8 bits (as embedded-graphics converts), and compared with the
//! f64 Rgb888 image after a 4x4 box filter (the eye's blur at a panel's pixel size). The
//! dithered image must be the closer one on every scene with gradients (all of them).
//! Prints the table docs/panels.md quotes.

mod common;

use embedded_graphics::mock_display::MockDisplay;
use embedded_graphics::pixelcolor::{BinaryColor, Gray2, Gray4, Gray8, Rgb555, Rgb666};
use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use microray::Scene;
use microray::dither::{
    Diffusion, Dither, DitherError, Format, Kernel, Matrix, Method, PanelColor, Rgb332, Rgb444,
    Rgb565Dither, dither_ordered, dither_rgb565, shown, truncate_rgb565,
};
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

/// The RMS difference (8-bit levels) between two images after a 4x4 box filter at every
/// position (the boxes overlap). Not only at the 4x4 tiles: those line up with the 4x4 Bayer
/// matrix, whose every tile keeps its exact mean, and would favour it over the others.
fn sliding_box_rms(width: usize, a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let height = a.len() / width;
    if width < 4 || height < 4 {
        return 0.0;
    }
    let (mut sum, mut n) = (0.0, 0usize);
    for k in 0..3 {
        // Summed-area table of the difference, one row and column of zeros in front.
        let mut table = vec![0.0; (width + 1) * (height + 1)];
        for y in 0..height {
            let mut run = 0.0;
            for x in 0..width {
                run += a[y * width + x][k] - b[y * width + x][k];
                table[(y + 1) * (width + 1) + x + 1] = table[y * (width + 1) + x + 1] + run;
            }
        }
        let at = |x: usize, y: usize| table[y * (width + 1) + x];
        for y in 0..=height - 4 {
            for x in 0..=width - 4 {
                let d = (at(x + 4, y + 4) - at(x, y + 4) - at(x + 4, y) + at(x, y)) / 16.0;
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

/// A panel of any format in memory.
struct Panel<C> {
    size: Size,
    pixels: Vec<Option<C>>,
}

impl<C: PanelColor> Panel<C> {
    fn new(size: Size) -> Self {
        Panel {
            size,
            pixels: vec![None; (size.width * size.height) as usize],
        }
    }

    /// Every pixel, each drawn (a pixel never drawn fails the test).
    fn drawn(&self) -> Vec<C> {
        self.pixels
            .iter()
            .map(|p| p.expect("every pixel drawn"))
            .collect()
    }
}

impl<C: PanelColor> Dimensions for Panel<C> {
    fn bounding_box(&self) -> Rectangle {
        Rectangle::new(Point::zero(), self.size)
    }
}

impl<C: PanelColor> DrawTarget for Panel<C> {
    type Color = C;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<C>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Self::Error> {
        for Pixel(p, c) in pixels {
            if self.bounding_box().contains(p) {
                self.pixels[(p.y as u32 * self.size.width + p.x as u32) as usize] = Some(c);
            }
        }
        Ok(())
    }
}

/// An Rgb888 picture through `method` (None: truncation) into a `C` panel, drawn as the
/// renderer draws: one `fill_contiguous` a row.
fn through<C: PanelColor>(size: Size, image: &[Rgb888], method: Option<Method>) -> Vec<C> {
    let mut panel = Panel::<C>::new(size);
    let mut memory = vec![0i16; Diffusion::<C>::cells(Kernel::Atkinson, size.width as usize)];
    let mut dither = match method {
        None => Dither::truncating(&mut panel),
        Some(Method::Ordered(m)) => Dither::ordered(&mut panel, m),
        Some(Method::Diffusion { kernel, serpentine }) => {
            Dither::diffusing(&mut panel, kernel, serpentine, &mut memory).unwrap()
        }
    };
    for (y, row) in image.chunks(size.width as usize).enumerate() {
        let line = Rectangle::new(Point::new(0, y as i32), Size::new(size.width, 1));
        dither.fill_contiguous(&line, row.iter().copied()).unwrap();
    }
    panel.drawn()
}

/// The picture in the panel's colour space, exactly: 8-bit channels, or BT.601 luma in
/// 256ths for grey (the rule the dithers quantize).
fn in_panel_space<C: PanelColor>(image: &[Rgb888]) -> Vec<[f64; 3]> {
    image
        .iter()
        .map(|c| {
            let (r, g, b) = (f64::from(c.r()), f64::from(c.g()), f64::from(c.b()));
            if C::GREY {
                [(77.0 * r + 150.0 * g + 29.0 * b) / 256.0, 0.0, 0.0]
            } else {
                [r, g, b]
            }
        })
        .collect()
}

fn shown_in_panel_space<C: PanelColor>(panel: &[C]) -> Vec<[f64; 3]> {
    panel
        .iter()
        .map(|&c| {
            let s = shown(c);
            if C::GREY {
                [f64::from(s.r()), 0.0, 0.0]
            } else {
                [f64::from(s.r()), f64::from(s.g()), f64::from(s.b())]
            }
        })
        .collect()
}

/// Every method and the serpentine diffusions, by name.
fn methods() -> Vec<Method> {
    let mut all: Vec<Method> = Method::ALL.iter().map(|&(_, m)| m).collect();
    for kernel in [Kernel::FloydSteinberg, Kernel::Atkinson] {
        all.push(Method::Diffusion {
            kernel,
            serpentine: true,
        });
    }
    all
}

/// Box-filtered RMS of truncation and of each method against the picture, in `C`'s space.
fn errors<C: PanelColor>(size: Size, image: &[Rgb888]) -> (f64, Vec<f64>) {
    let width = size.width as usize;
    let reference = in_panel_space::<C>(image);
    let rms = |method| {
        let panel = through::<C>(size, image, method);
        sliding_box_rms(width, &reference, &shown_in_panel_space(&panel))
    };
    (
        rms(None),
        methods().into_iter().map(|m| rms(Some(m))).collect(),
    )
}

fn each_format(size: Size, image: &[Rgb888]) -> Vec<(Format, f64, Vec<f64>)> {
    let row = |f, (t, m)| (f, t, m);
    vec![
        row(Format::Binary, errors::<BinaryColor>(size, image)),
        row(Format::Gray2, errors::<Gray2>(size, image)),
        row(Format::Gray4, errors::<Gray4>(size, image)),
        row(Format::Gray8, errors::<Gray8>(size, image)),
        row(Format::Rgb332, errors::<Rgb332>(size, image)),
        row(Format::Rgb444, errors::<Rgb444>(size, image)),
        row(Format::Rgb555, errors::<Rgb555>(size, image)),
        row(Format::Rgb565, errors::<Rgb565>(size, image)),
        row(Format::Rgb666, errors::<Rgb666>(size, image)),
    ]
}

/// The course's f64 pictures, by name.
fn course_pictures() -> Vec<(String, Size, Vec<Rgb888>)> {
    let dir = common::required_conformance_dir();
    common::scene_files(&dir)
        .into_iter()
        .map(|path| {
            let name = path.file_stem().unwrap().to_str().unwrap().to_string();
            let text = std::fs::read(&path).unwrap();
            let scene: HostScene<'_, f64> =
                parse_scene(&text, texture_files(path.parent().unwrap())).unwrap();
            let camera = scene.camera();
            let size = Size::new(u32::from(camera.width()), u32::from(camera.height()));
            let mut image = Framebuffer::new(size);
            render(&scene, &mut image).unwrap();
            let pixels = image
                .rgb()
                .chunks(3)
                .map(|c| Rgb888::new(c[0], c[1], c[2]))
                .collect();
            (name, size, pixels)
        })
        .collect()
}

#[test]
#[cfg_attr(
    not(microray_conformance),
    ignore = "needs the course's scenes: set MICRORAY_CONFORMANCE to their folder"
)]
fn every_method_beats_truncation_in_every_format_on_every_course_scene() {
    let pictures = course_pictures();
    let names: Vec<&str> = methods().iter().map(|m| m.name()).collect();
    // format -> (sum of truncation's RMS, sums of each method's)
    let mut sums: Vec<(Format, f64, Vec<f64>)> = Vec::new();
    let mut failures = Vec::new();
    let results: Vec<_> = std::thread::scope(|s| {
        let jobs: Vec<_> = pictures
            .iter()
            .map(|(name, size, image)| s.spawn(move || (name, each_format(*size, image))))
            .collect();
        jobs.into_iter().map(|j| j.join().unwrap()).collect()
    });
    for (scene, rows) in &results {
        for (format, truncated, each) in rows {
            for (name, &e) in names.iter().zip(each) {
                // Better, or exact where truncation is (a picture of whole levels).
                let better = if *truncated == 0.0 {
                    e == 0.0
                } else {
                    e < *truncated
                };
                if !better {
                    failures.push(format!(
                        "{scene} {} {name}: {e:.3} >= {truncated:.3}",
                        format.name()
                    ));
                }
            }
            match sums.iter_mut().find(|(f, _, _)| f == format) {
                Some((_, t, m)) => {
                    *t += truncated;
                    for (s, e) in m.iter_mut().zip(each) {
                        *s += e;
                    }
                }
                None => sums.push((*format, *truncated, each.clone())),
            }
        }
    }
    let n = results.len() as f64;
    let mut table = format!(
        "| format | truncated | {} | best | best ordered |\n|---|---|{}---|---|\n",
        names.join(" | "),
        "---|".repeat(names.len())
    );
    let mut wrong_default = Vec::new();
    for (format, t, m) in &sums {
        let means: Vec<f64> = m.iter().map(|s| s / n).collect();
        let best = (0..means.len())
            .min_by(|&a, &b| means[a].total_cmp(&means[b]))
            .unwrap();
        let ordered = (0..means.len())
            .filter(|&i| matches!(methods()[i], Method::Ordered(_)))
            .min_by(|&a, &b| means[a].total_cmp(&means[b]))
            .unwrap();
        let cells: Vec<String> = means.iter().map(|v| format!("{v:.3}")).collect();
        table += &format!(
            "| {} | {:.3} | {} | {} | {} |\n",
            format.name(),
            t / n,
            cells.join(" | "),
            names[best],
            names[ordered]
        );
        for (chosen, want, what) in [
            (format.best_method(), best, "best"),
            (format.best_ordered(), ordered, "best ordered"),
        ] {
            if chosen.name() != names[want] {
                wrong_default.push(format!(
                    "{}: {} ({what}: {})",
                    format.name(),
                    chosen.name(),
                    names[want]
                ));
            }
        }
    }
    eprintln!(
        "mean 4x4 box-filtered RMS over {} course scenes, in 8-bit steps:\n{table}",
        results.len()
    );
    assert!(
        failures.is_empty(),
        "not better than truncation: {failures:#?}"
    );
    assert!(
        wrong_default.is_empty(),
        "Format::best_method is not the table's best: {wrong_default:?}"
    );
}

#[test]
fn the_wrapper_diffuses_what_the_renderer_draws() {
    // The renderer's rows through the wrapper equal the same rows diffused by hand.
    let text = b"camera c { pixeldim 48 36 worlddim 8 6 viewpoint 4 3 4 }
                 material grey { ambient 1 1 1 diffuse 3 3 3 }
                 plane floor { material grey normal 0 1 0 point 0 0 0 }
                 sphere ball { material grey center 4 2 -3 radius 1.5 }
                 light sun { location 4 5 -2 emissivity 4 4 4 }";
    let scene: Scene<f32, 2, 1, 1, 0, 48> = parse_scene(text, no_textures).unwrap();
    let size = Size::new(48, 36);
    let mut image = Framebuffer::new(size);
    render(&scene, &mut image).unwrap();
    let pixels: Vec<Rgb888> = image
        .rgb()
        .chunks(3)
        .map(|c| Rgb888::new(c[0], c[1], c[2]))
        .collect();
    for kernel in [Kernel::FloydSteinberg, Kernel::Atkinson] {
        for serpentine in [false, true] {
            let mut panel = Panel::<Gray2>::new(size);
            let mut memory = vec![0i16; Diffusion::<Gray2>::cells(kernel, 48)];
            let mut dither =
                Dither::diffusing(&mut panel, kernel, serpentine, &mut memory).unwrap();
            render(&scene, &mut dither).unwrap();
            // And again: after the last row the wrapper starts over at the top.
            render(&scene, &mut dither).unwrap();
            let expected = common::diffused_by_hand::<Gray2>(&pixels, 48, kernel, serpentine);
            assert_eq!(panel.drawn(), expected, "{kernel:?} {serpentine}");
            let levels: std::collections::BTreeSet<u8> =
                expected.iter().map(|c| c.luma()).collect();
            assert!(levels.len() >= 3, "a gradient: {levels:?}");
        }
    }
    // The ordered methods give what dither_ordered gives, pixel by pixel.
    let mut panel = Panel::<Rgb444>::new(size);
    render(&scene, &mut Dither::ordered(&mut panel, Matrix::BlueNoise)).unwrap();
    for (i, (&got, &c)) in panel.drawn().iter().zip(&pixels).enumerate() {
        let p = Point::new((i % 48) as i32, (i / 48) as i32);
        assert_eq!(got, dither_ordered::<Rgb444>(c, p, Matrix::BlueNoise));
    }
}

#[test]
fn error_diffusion_refuses_the_progressive_order() {
    let text = b"camera c { pixeldim 32 24 worlddim 8 6 viewpoint 4 3 4 }
                 material grey { ambient 1 1 1 diffuse 3 3 3 }
                 plane floor { material grey normal 0 1 0 point 0 0 0 }
                 light sun { location 4 5 -2 emissivity 4 4 4 }";
    let scene: Scene<f32, 2, 1, 1, 0, 32> = parse_scene(text, no_textures).unwrap();
    let renderer = microray::render::Renderer::new(&scene);
    let mut panel = Panel::<BinaryColor>::new(Size::new(32, 24));
    let mut memory = vec![0i16; Diffusion::<BinaryColor>::cells(Kernel::FloydSteinberg, 32)];
    let mut dither =
        Dither::diffusing(&mut panel, Kernel::FloydSteinberg, false, &mut memory).unwrap();
    let mut row = [Rgb888::BLACK; 32];
    // The first passes fill whole rows (blocks side by side); a later one draws single
    // pixels, which the diffusion refuses.
    let e = (0..microray::render::BLOCKS.len())
        .find_map(|pass| renderer.render_pass(&mut dither, &mut row, pass).err())
        .expect("refused");
    match &e {
        microray::render::RenderError::Target(
            d @ DitherError::OutOfOrder { expected_row, got },
        ) => {
            assert_ne!(got.y, *expected_row, "{got:?}");
            assert!(d.to_string().contains("use an ordered dither"), "{d}");
        }
        other => panic!("{other:?}"),
    }
    // An ordered dither takes the progressive order.
    let mut panel = Panel::<BinaryColor>::new(Size::new(32, 24));
    let mut dither = Dither::ordered(&mut panel, Matrix::Bayer8);
    for pass in 0..microray::render::BLOCKS.len() {
        renderer.render_pass(&mut dither, &mut row, pass).unwrap();
    }
    let _ = panel.drawn();
}

#[test]
fn a_partial_area_is_diffused_on_its_own() {
    // render_area into a rectangle of the panel, the diffusion set to that rectangle.
    let text = b"camera c { pixeldim 40 30 worlddim 8 6 viewpoint 4 3 4 }
                 material grey { ambient 1 1 1 diffuse 3 3 3 }
                 plane floor { material grey normal 0 1 0 point 0 0 0 }
                 light sun { location 4 5 -2 emissivity 4 4 4 }";
    let scene: Scene<f32, 2, 1, 1, 0, 40> = parse_scene(text, no_textures).unwrap();
    let renderer = microray::render::Renderer::new(&scene);
    let area = Rectangle::new(Point::new(5, 7), Size::new(20, 10));
    let mut panel = Panel::<Gray4>::new(Size::new(40, 30));
    let mut memory = vec![0i16; Diffusion::<Gray4>::cells(Kernel::Atkinson, 20)];
    let mut dither =
        Dither::diffusing_area(&mut panel, area, Kernel::Atkinson, true, &mut memory).unwrap();
    let mut row = [Rgb888::BLACK; 40];
    renderer
        .render_area(&mut dither, area, &mut row, |_| {
            core::ops::ControlFlow::Continue(())
        })
        .unwrap();
    let mut whole = Framebuffer::new(Size::new(40, 30));
    render(&scene, &mut whole).unwrap();
    // The area's pixels of the whole picture, diffused by hand as a picture of their own.
    let cut: Vec<Rgb888> = (7..17)
        .flat_map(|y| (5..25).map(move |x| (y, x)))
        .map(|(y, x)| {
            let c = &whole.rgb()[(y * 40 + x) * 3..];
            Rgb888::new(c[0], c[1], c[2])
        })
        .collect();
    let expected = common::diffused_by_hand::<Gray4>(&cut, 20, Kernel::Atkinson, true);
    for (i, c) in expected.into_iter().enumerate() {
        let (y, x) = (7 + i / 20, 5 + i % 20);
        assert_eq!(panel.pixels[y * 40 + x], Some(c), "{x} {y}");
    }
    assert_eq!(panel.pixels.iter().filter(|p| p.is_some()).count(), 200);
}

#[test]
fn anti_aliased_rows_are_diffused_in_order() {
    // The anti-aliased render through the wrapper equals the anti-aliased image diffused by
    // hand: its rows come whole, top to bottom.
    use microray::render::{AaPixel, Antialias, Samples};
    let text = b"camera c { pixeldim 40 30 worlddim 8 6 viewpoint 4 3 4 }
                 material grey { ambient 1 1 1 diffuse 3 3 3 }
                 plane floor { material grey normal 0 1 0 point 0 0 0 }
                 sphere ball { material grey center 4 2 -3 radius 1.5 }
                 light sun { location 4 5 -2 emissivity 4 4 4 }";
    let scene: Scene<f32, 2, 1, 1, 0, 40> = parse_scene(text, no_textures).unwrap();
    let renderer = microray::render::Renderer::new(&scene);
    let aa = Antialias::Grid(Samples::rotated(4).unwrap());
    let image = microray::host::antialiased(&renderer, aa).unwrap();
    let size = Size::new(40, 30);
    let mut panel = Panel::<Gray2>::new(size);
    let mut memory = vec![0i16; Diffusion::<Gray2>::cells(Kernel::FloydSteinberg, 40)];
    let mut dither =
        Dither::diffusing(&mut panel, Kernel::FloydSteinberg, true, &mut memory).unwrap();
    let mut buffer = vec![AaPixel::NEW; Antialias::buffer_len(40)];
    renderer
        .render_antialiased(
            &mut dither,
            Rectangle::new(Point::zero(), size),
            aa,
            &mut buffer,
            |_| core::ops::ControlFlow::Continue(()),
        )
        .unwrap();
    let pixels: Vec<Rgb888> = image
        .rgb()
        .chunks(3)
        .map(|c| Rgb888::new(c[0], c[1], c[2]))
        .collect();
    let expected = common::diffused_by_hand::<Gray2>(&pixels, 40, Kernel::FloydSteinberg, true);
    assert_eq!(panel.drawn(), expected);
    // Anti-aliasing changed the picture (its edges), so the test saw the anti-aliased rows.
    let mut plain = Framebuffer::new(size);
    render(&scene, &mut plain).unwrap();
    assert_ne!(plain.rgb(), image.rgb());
}
