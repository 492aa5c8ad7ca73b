//! `microray animate`: a scene's film into an animated PNG, each frame after the first
//! traced only where its changes can touch it (`microray::region`).

use super::{
    Options, Stop, cannot_write, empty_scene, format_of, load_text, located, note, read, shown,
    warnings, write_whole,
};
use crate::output::{Format, is_stdio};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::Point;
use embedded_graphics::primitives::Rectangle;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use microray::Scalar;
use microray::host::{Framebuffer, HostRenderer};
use microray::parse::parse_animation;
use microray::region::Region;
use microray::render::{AaPixel, Antialias, Renderer};
use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::path::Path;
use std::time::Instant;

/// The most motions a film may have.
pub(crate) const MOTIONS: usize = 64;

/// The most rectangles a frame's region keeps apart (more are merged).
const AREAS: usize = 16;

/// How to play the film.
pub(crate) struct Film {
    /// Trace every frame whole.
    pub(crate) full: bool,
    /// Milliseconds a frame.
    pub(crate) delay: u16,
    /// The size, if not the scene's.
    pub(crate) size: Option<(u16, u16)>,
}

#[inline(never)]
pub(crate) fn animate<S: Scalar>(
    path: &Path,
    output: &Path,
    options: &Options,
    film: Film,
) -> Result<(), Stop> {
    let named = (!is_stdio(output))
        .then(|| Format::of_name(output))
        .flatten();
    if named == Some(Format::Ppm) || format_of(output, Some(Format::Png))? != Format::Png {
        return Err(Stop::Failed(format!(
            "{}: error: animate writes an animated PNG: name it .png",
            output.display()
        )));
    }
    if is_stdio(output) && std::io::stdout().is_terminal() {
        return Err(Stop::Failed(
            "error: standard output is a terminal: send the film to a file or a pipe".into(),
        ));
    }
    let name = shown(path, "<stdin>");
    let (text, dir) = read(path)?;
    let mut scene = empty_scene::<S>();
    load_text(&name, &text, &dir, &mut scene)?;
    if let Some((width, height)) = film.size {
        scene
            .set_resolution(width, height)
            .map_err(|e| format!("{name}: error: --size: {e}"))?;
    }
    let animation = parse_animation::<MOTIONS>(&text)
        .map_err(|e| located(&name, &e))?
        .ok_or_else(|| {
            format!(
                "{name}: error: no `animation` block: nothing moves (docs/scene-format.md \
                 describes `animation`, `line`, `orbit` and `bounce`)"
            )
        })?;
    if !options.quiet {
        for line in warnings(&scene, &name) {
            note(&line)?;
        }
    }
    let size = scene.camera();
    let size = embedded_graphics::prelude::Size::new(size.width().into(), size.height().into());
    let frames = animation.frames();
    let bar = (!options.quiet).then(|| {
        let bar = ProgressBar::with_draw_target(Some(frames.into()), ProgressDrawTarget::stderr());
        let style = ProgressStyle::with_template("{bar:40} {pos}/{len} frames, {eta} left");
        bar.set_style(style.unwrap_or_else(|_| ProgressStyle::default_bar()));
        bar
    });
    // Adaptive anti-aliasing supersamples a pixel by what its neighbours show; without
    // anti-aliasing a pixel is the one ray through its point.
    let border = u16::from(matches!(options.aa, Some(Antialias::Adaptive { .. })));
    let mut region = Region::<AREAS>::new(size).with_border(border);
    if options.aa.is_none() {
        region = region.with_one_ray_a_pixel();
    }
    // The moving objects' last region, so each frame works out only its new one.
    let mut last = microray::animation::LastFrame::<AREAS>::new();
    let mut image = Framebuffer::new(size);
    let mut traced = 0u64;
    // A row, and anti-aliasing's rows, for every rectangle of every frame.
    let width = size.width as usize;
    let mut buffers = (
        vec![Default::default(); width],
        vec![AaPixel::NEW; Antialias::buffer_len(size.width as u16)],
    );
    let start = Instant::now();
    write_whole(output, |out| {
        let encoding = |e: png::EncodingError| cannot_write(output, std::io::Error::other(e));
        let mut encoder = png::Encoder::new(out, size.width, size.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_animated(frames.into(), 0).map_err(encoding)?;
        encoder
            .set_frame_delay(film.delay, 1000)
            .map_err(encoding)?;
        let mut writer = encoder.write_header().map_err(encoding)?;
        for frame in 0..frames {
            region.clear();
            if frame > 0 {
                animation
                    .show_next_frame(frame, &mut scene, &mut region, &mut last)
                    .map_err(|e| format!("{name}: error: frame {frame}: {e}"))?;
            }
            if frame == 0 || film.full {
                region.add_whole();
            }
            let renderer = Renderer::new(&*scene)
                .with_shading(options.shading)
                .with_plan(options.planned);
            for area in region.rectangles() {
                draw(&renderer, &mut image, area, options.aa, &mut buffers)
                    .map_err(|e| format!("{name}: error: frame {frame}: {e}"))?;
            }
            traced += u64::from(region.pixels());
            // Only the region's bounding box is stored: the player keeps the rest.
            let (x, y, w, h) = bounding_box(&region, size);
            let mut part = cut(image.rgb(), size.width, (x, y, w, h));
            crate::panel::to_panel(
                &mut part,
                w as usize,
                (x as usize, y as usize),
                options.depth,
            );
            writer.reset_frame_position().map_err(encoding)?;
            writer.set_frame_dimension(w, h).map_err(encoding)?;
            writer.set_frame_position(x, y).map_err(encoding)?;
            writer.write_image_data(&part).map_err(encoding)?;
            if let Some(bar) = &bar {
                bar.inc(1);
            }
        }
        writer.finish().map_err(encoding)
    })?;
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    if options.quiet {
        return Ok(());
    }
    let all = u64::from(frames) * u64::from(size.width) * u64::from(size.height);
    note(&format!(
        "{name}: {frames} frames of {}x{} in {:.2} s ({}, {:.1} % of the pixels traced{}) -> {}",
        size.width,
        size.height,
        start.elapsed().as_secs_f64(),
        S::NAME,
        100.0 * traced as f64 / all.max(1) as f64,
        if film.full { ", every frame whole" } else { "" },
        shown(output, "<stdout>")
    ))
}

/// Renders `area` of the picture into `image`, anti-aliased by `aa` when given.
fn draw<S: Scalar>(
    renderer: &HostRenderer<'_, S>,
    image: &mut Framebuffer,
    area: Rectangle,
    aa: Option<Antialias>,
    (row, aa_rows): &mut (Vec<Rgb888>, Vec<AaPixel>),
) -> Result<(), String> {
    let go_on = |_| ControlFlow::Continue(());
    let done = match aa {
        Some(aa) => renderer.render_antialiased(image, area, aa, aa_rows, go_on),
        None => renderer.render_area(image, area, row, go_on),
    };
    done.map(|_| ()).map_err(|e| e.to_string())
}

/// The smallest rectangle holding the region (one pixel when it is empty): `x, y, w, h`.
fn bounding_box<const N: usize>(
    region: &Region<N>,
    size: embedded_graphics::prelude::Size,
) -> (u32, u32, u32, u32) {
    let corners = |r: Rectangle| {
        let end = r.top_left + Point::new(r.size.width as i32, r.size.height as i32);
        (r.top_left, end)
    };
    let joined = region
        .rectangles()
        .map(corners)
        .reduce(|(a, b), (c, d)| (a.component_min(c), b.component_max(d)));
    let Some((low, high)) = joined else {
        return (0, 0, 1, 1);
    };
    let (x, y) = (low.x.max(0) as u32, low.y.max(0) as u32);
    let w = (high.x.max(0) as u32)
        .min(size.width)
        .saturating_sub(x)
        .max(1);
    let h = (high.y.max(0) as u32)
        .min(size.height)
        .saturating_sub(y)
        .max(1);
    (x, y, w, h)
}

/// The RGB bytes of `(x, y, w, h)` of a picture `width` pixels wide.
fn cut(rgb: &[u8], width: u32, (x, y, w, h): (u32, u32, u32, u32)) -> Vec<u8> {
    let (width, x, w) = (width as usize * 3, x as usize * 3, w as usize * 3);
    (y as usize..(y + h) as usize)
        .flat_map(|row| &rgb[row * width + x..row * width + x + w])
        .copied()
        .collect()
}
