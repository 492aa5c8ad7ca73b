//! The std tracer: a thin shell over the library.

use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use microray::Scalar;
use microray::host::{Framebuffer, HostRenderer, HostScene, StreamError, texture_files};
use microray::parse::parse_scene_into;
use microray::print::print_scene;
use microray::render::{Antialias, Pattern, Renderer, Samples, Shading};
use microray::scalar::I16F16;
use std::io::{Seek, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

#[derive(Parser)]
#[command(
    name = "microray",
    version,
    about = "A no_std ray tracer for microcontroller displays: the std front end"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check a scene file: prints `ok` and a summary, or `FILE:LINE:COL: error: ...`.
    Check {
        /// The scene file.
        scene: PathBuf,
    },
    /// Print a scene as microray reads it (valid scene text that reads back equal).
    Print {
        /// The scene file.
        scene: PathBuf,
    },
    /// Compile a scene for firmware: its values as loaded in one number type, bit for bit,
    /// which `Scene::load_compiled` reads without the parser and without f64 arithmetic.
    Compile {
        /// The scene file.
        scene: PathBuf,
        /// The compiled scene to write.
        #[arg(short, long)]
        output: PathBuf,
        /// The number type the firmware computes in.
        #[arg(long, value_enum)]
        number: Number,
        /// The image size, WIDTHxHEIGHT, if not the scene's `pixeldim`.
        #[arg(long, value_parser = parse_size)]
        size: Option<(u16, u16)>,
    },
    /// Render a scene to a binary PPM (`.ppm`) or PNG (`.png`) image.
    Render {
        /// The scene file.
        scene: PathBuf,
        /// The image to write; the extension picks the format.
        #[arg(short, long)]
        output: PathBuf,
        /// The number type to compute in.
        #[arg(long, value_enum, default_value_t = Number::F64)]
        number: Number,
        /// What pixels show: the course's shading, or a colour per object.
        #[arg(long, value_enum, default_value_t = ShadeMode::Color)]
        shade: ShadeMode,
        /// No progress bar and no summary line.
        #[arg(short, long)]
        quiet: bool,
        /// Render without the render plan: every shading stage runs and every ray is tested
        /// against every object (the same image, for comparison).
        #[arg(long)]
        no_plan: bool,
        /// Render in the progressive order (8x8 blocks, 4x4, 2x2, every pixel; the same
        /// image) and write each preview pass too, as OUT-8, OUT-4 and OUT-2 beside OUT.
        #[arg(long)]
        progressive: bool,
        /// The panel's colour depth: `rgb565` writes the picture as a 5-6-5 panel shows it
        /// with the channels truncated, expanded back to 8 bits per channel.
        #[arg(long, value_enum, default_value_t = Depth::Rgb888)]
        color: Depth,
        /// Dither to a panel's colour depth instead (`rgb565`: an ordered 4x4 dither, as
        /// `microray::dither::Rgb565Dither` draws it), expanded back to 8 bits per channel.
        #[arg(long, value_enum)]
        dither: Option<DitherTo>,
        /// Anti-aliasing at fixed sample positions: N samples a pixel (a square: 1, 4, 9,
        /// 16, ... 256; 1 is the plain render), or `adaptive` (16 samples on the pixels that
        /// differ from a neighbour, the plain ray elsewhere; `adaptive:N` for N).
        #[arg(long, value_parser = parse_aa, default_value = "1")]
        aa: AaMode,
        /// Adaptive anti-aliasing: neighbours whose channels differ by more than this many
        /// levels (or that see different objects) are supersampled.
        #[arg(long, default_value_t = 8)]
        aa_threshold: u8,
        /// Where a pixel's samples lie: a rotated grid (every sample its own row and column)
        /// or a regular one.
        #[arg(long, value_enum, default_value_t = AaPattern::Rotated)]
        aa_pattern: AaPattern,
        /// Threads to render with (each takes bands of rows; the image is the same for
        /// any number); all cores by default, 1 for one thread.
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
        threads: Option<u16>,
    },
}

/// `--aa` as given: a sample count, adaptive or not.
#[derive(Clone, Copy)]
struct AaMode {
    adaptive: bool,
    count: u16,
}

fn parse_aa(text: &str) -> Result<AaMode, String> {
    let (adaptive, count) = match text.strip_prefix("adaptive") {
        Some("") => (true, "16"),
        Some(rest) => (true, rest.strip_prefix(':').unwrap_or(rest)),
        None => (false, text),
    };
    let count = count
        .parse::<u16>()
        .ok()
        .filter(|&n| microray::render::Samples::rotated(n).is_some())
        .ok_or_else(|| {
            format!("`{text}`: expected a square sample count from 1 to 256 (1, 4, 9, 16, ...), `adaptive` or `adaptive:N`")
        })?;
    Ok(AaMode { adaptive, count })
}

#[derive(Clone, Copy, ValueEnum)]
enum AaPattern {
    Rotated,
    Regular,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Depth {
    Rgb888,
    Rgb565,
}

#[derive(Clone, Copy, ValueEnum)]
enum DitherTo {
    Rgb565,
}

#[derive(Clone, Copy, ValueEnum)]
enum ShadeMode {
    Color,
    Ids,
}

#[derive(Clone, Copy, ValueEnum)]
enum Number {
    F64,
    F32,
    I16f16,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Check { scene } => check(scene),
        Command::Print { scene } => print(scene),
        Command::Compile {
            scene,
            output,
            number,
            size,
        } => match number {
            Number::F64 => compile::<f64>(scene, output, *size),
            Number::F32 => compile::<f32>(scene, output, *size),
            Number::I16f16 => compile::<I16F16>(scene, output, *size),
        },
        Command::Render {
            scene,
            output,
            number,
            shade,
            quiet,
            no_plan,
            progressive,
            color,
            dither,
            aa,
            aa_threshold,
            aa_pattern,
            threads,
        } => {
            let pattern = match aa_pattern {
                AaPattern::Rotated => Pattern::Rotated,
                AaPattern::Regular => Pattern::Regular,
            };
            // parse_aa let only squares through.
            let samples = Samples::new(aa.count, pattern).unwrap_or(Samples::ONE);
            let options = Options {
                shading: match shade {
                    ShadeMode::Color => Shading::Color,
                    ShadeMode::Ids => Shading::Ids,
                },
                quiet: *quiet,
                planned: !no_plan,
                progressive: *progressive,
                depth: match (dither, color) {
                    (Some(DitherTo::Rgb565), _) => Output::Rgb565Dithered,
                    (None, Depth::Rgb565) => Output::Rgb565,
                    (None, Depth::Rgb888) => Output::Rgb888,
                },
                threads: threads.map_or_else(
                    || std::thread::available_parallelism().map_or(1, |n| n.get()),
                    usize::from,
                ),
                aa: match (aa.adaptive, aa.count) {
                    (false, 1) => None,
                    (false, _) => Some(Antialias::Grid(samples)),
                    (true, _) => Some(Antialias::Adaptive {
                        samples,
                        threshold: *aa_threshold,
                    }),
                },
            };
            match number {
                Number::F64 => render::<f64>(scene, output, &options),
                Number::F32 => render::<f32>(scene, output, &options),
                Number::I16f16 => render::<I16F16>(scene, output, &options),
            }
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("{message}");
            ExitCode::FAILURE
        }
    }
}

/// An empty scene on the heap. On the stack its room for 256 objects (about 100 KB) is a
/// frame the stack probes fault in page by page, all of it, whatever the scene holds; on
/// the heap only the pages written are (25 page faults fewer: 0.07 ms of a run, measured).
fn empty_scene<S: Scalar>() -> Box<HostScene<'static, S>> {
    Box::new(HostScene::empty())
}

// Each command is a function of its own, never inlined: a frame with a command's locals
// in `main` would be stack that every command faults in.
#[inline(never)]
fn print(path: &Path) -> Result<(), String> {
    let mut s = empty_scene::<f64>();
    load(path, &mut s)?;
    let mut text = String::new();
    print_scene(&s, &mut text)
        .map_err(|_| format!("{}: error: printing failed", path.display()))?;
    print!("{text}");
    Ok(())
}

#[inline(never)]
fn check(path: &Path) -> Result<(), String> {
    let mut s = empty_scene::<f64>();
    load(path, &mut s)?;
    let cam = s.camera();
    let spots = s.lights().iter().filter(|l| l.spot.is_some()).count();
    println!(
        "ok: {}: {}x{} pixels, {}, {}, {} ({} spot), {}",
        path.display(),
        cam.width(),
        cam.height(),
        count(s.materials().len(), "material"),
        count(s.textures().len(), "texture"),
        count(s.lights().len(), "light"),
        spots,
        count(s.objects().len(), "object"),
    );
    println!("{}", plan_summary(&Renderer::new(&s)));
    Ok(())
}

/// One line on what the render plan skips.
fn plan_summary(renderer: &HostRenderer<'_, f64>) -> String {
    let plan = renderer.plan();
    let stages = plan.stages();
    let mut on = Vec::new();
    for (name, runs) in [
        ("illumination", stages.illumination),
        ("shadows", stages.shadows),
        ("reflection", stages.reflection),
        ("transparency", stages.transparency),
        ("glints", stages.glints),
    ] {
        if runs {
            on.push(name);
        }
    }
    if stages.shadows {
        on.push(if stages.filtered_shadows {
            "filtered shadow walk"
        } else {
            "any-hit shadows"
        });
    }
    let height = renderer.size().height;
    let rows: u64 = plan
        .spans()
        .iter()
        .map(|s| u64::from(s.rows(u16::try_from(height).unwrap_or(u16::MAX))))
        .sum();
    let all = u64::from(height) * plan.kept().len() as u64;
    format!(
        "plan: {}; {} kept, primary rays test {:.1}% of object-rows",
        if on.is_empty() {
            "ambient only".to_string()
        } else {
            on.join(", ")
        },
        count(plan.kept().len(), "object"),
        if all == 0 {
            0.0
        } else {
            100.0 * rows as f64 / all as f64
        }
    )
}

fn count(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}

/// Reads and parses a scene into `scene`; the error is the full `FILE:LINE:COL: error: ...`
/// line. In place, not returned: the scene is 100 KB, and every copy of it on the way out
/// (the parser's, the `Result`'s) is stack that the process must fault in, 0.1 ms a render.
#[inline(never)]
fn load<S: Scalar>(path: &Path, scene: &mut HostScene<'static, S>) -> Result<(), String> {
    let text =
        std::fs::read(path).map_err(|e| format!("{}: error: cannot read: {e}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    parse_scene_into(&text, texture_files(dir), scene).map_err(|e| match e.position {
        Some(p) => format!(
            "{}:{}:{}: error: {}",
            path.display(),
            p.line,
            p.column,
            e.kind
        ),
        None => format!("{}: error: {}", path.display(), e.kind),
    })
}

fn parse_size(text: &str) -> Result<(u16, u16), String> {
    let (w, h) = text
        .split_once('x')
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, found `{text}`"))?;
    let number = |v: &str| v.parse::<u16>().map_err(|e| format!("`{v}`: {e}"));
    Ok((number(w)?, number(h)?))
}

#[inline(never)]
fn compile<S: Scalar>(path: &Path, output: &Path, size: Option<(u16, u16)>) -> Result<(), String> {
    let mut scene = empty_scene::<S>();
    load(path, &mut scene)?;
    if let Some((width, height)) = size {
        scene
            .set_resolution(width, height)
            .map_err(|e| format!("{}: error: --size: {e}", path.display()))?;
    }
    let mut bytes = Vec::new();
    scene.write_compiled(&mut |piece| bytes.extend_from_slice(piece));
    std::fs::write(output, &bytes)
        .map_err(|e| format!("{}: error: cannot write: {e}", output.display()))?;
    eprintln!(
        "{}: {} bytes ({}) -> {}",
        path.display(),
        bytes.len(),
        S::NAME,
        output.display()
    );
    Ok(())
}

#[derive(Clone, Copy)]
enum Format {
    Ppm,
    Png,
}

struct Options {
    shading: Shading,
    quiet: bool,
    planned: bool,
    progressive: bool,
    depth: Output,
    aa: Option<Antialias>,
    threads: usize,
}

/// The colour depth of the written picture.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Output {
    Rgb888,
    Rgb565,
    Rgb565Dithered,
}

/// Rows of the picture (`top` the first, `width` pixels each, three bytes a pixel) as a
/// panel of `depth` shows them, expanded back to 8 bits per channel.
fn to_depth(rgb: &mut [u8], width: usize, top: usize, depth: Output) {
    use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
    use embedded_graphics::prelude::Point;
    use microray::dither::{dither_rgb565, truncate_rgb565};
    if depth == Output::Rgb888 || width == 0 {
        return;
    }
    for (i, c) in rgb.chunks_exact_mut(3).enumerate() {
        let p = Point::new((i % width) as i32, (top + i / width) as i32);
        let color = Rgb888::new(c[0], c[1], c[2]);
        let panel: Rgb565 = match depth {
            Output::Rgb565Dithered => dither_rgb565(color, p),
            _ => truncate_rgb565(color),
        };
        let back = Rgb888::from(panel);
        c.copy_from_slice(&[back.r(), back.g(), back.b()]);
    }
}

#[inline(never)]
fn render<S: Scalar>(path: &Path, output: &Path, options: &Options) -> Result<(), String> {
    let quiet = options.quiet;
    let extension = output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let format = match extension.as_deref() {
        Some("ppm") => Format::Ppm,
        Some("png") => Format::Png,
        _ => {
            return Err(format!(
                "{}: error: unknown image format (use .ppm or .png)",
                output.display()
            ));
        }
    };
    let mut scene = empty_scene::<S>();
    load(path, &mut scene)?;
    let renderer = Renderer::new(&scene)
        .with_shading(options.shading)
        .with_plan(options.planned);
    let size = renderer.size();
    let start = Instant::now();
    let image = if options.progressive {
        if options.aa.is_some() {
            return Err("error: --aa and --progressive cannot be combined (the progressive order traces one ray a pixel)".into());
        }
        let mut image = Framebuffer::new(size);
        let mut row = vec![Default::default(); size.width as usize];
        for (pass, block) in microray::render::BLOCKS.iter().enumerate() {
            renderer
                .render_pass(&mut image, &mut row, pass)
                .map_err(|e| format!("{}: error: {e}", path.display()))?;
            if *block > 1 {
                let stem = output.file_stem().and_then(|s| s.to_str()).unwrap_or("out");
                let preview = output.with_file_name(format!(
                    "{stem}-{block}.{}",
                    extension.as_deref().unwrap_or("png")
                ));
                write_image(&image, format, &preview)?;
            }
        }
        let file = open_over(output).map_err(|e| cannot_write(output, e))?;
        Some((image, file))
    } else {
        // Only renders that take more than a moment get a bar.
        let bar: std::sync::OnceLock<ProgressBar> = std::sync::OnceLock::new();
        let rows = AtomicU64::new(0);
        let total = u64::from(size.height);
        let progress = |_| {
            let done = rows.fetch_add(1, Ordering::Relaxed) + 1;
            if quiet {
                return;
            }
            if bar.get().is_none() && start.elapsed() > Duration::from_millis(300) {
                let _ = bar.get_or_init(|| {
                    let b =
                        ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
                    let style =
                        ProgressStyle::with_template("{bar:40} {pos}/{len} rows, {eta} left");
                    b.set_style(style.unwrap_or_else(|_| ProgressStyle::default_bar()));
                    b
                });
            }
            if let Some(b) = bar.get() {
                b.set_position(done);
            }
        };
        let width = size.width as usize;
        // A PPM to a file is written band by band as the threads finish them, with no image
        // in memory; other outputs (PNG, a pipe) from a framebuffer.
        let file = open_over(output).map_err(|e| cannot_write(output, e))?;
        let regular = file
            .metadata()
            .map_err(|e| cannot_write(output, e))?
            .is_file();
        // Writing at an offset is a Unix call (Windows has one that moves the file's cursor).
        let streamed = match format {
            Format::Ppm if regular && cfg!(unix) => Some(&file),
            _ => None,
        };
        let image = match streamed {
            Some(file) => {
                let header = microray::host::ppm_header(size);
                let write_band = |top: usize, pixels: &mut [u8]| {
                    to_depth(pixels, width, top, options.depth);
                    write_at(file, pixels, header.len() + top * width * 3)
                };
                write_at(file, header.as_bytes(), 0).map_err(|e| cannot_write(output, e))?;
                match microray::host::render_streamed(
                    &renderer,
                    options.threads,
                    options.aa,
                    progress,
                    write_band,
                ) {
                    Ok(()) => {}
                    Err(StreamError::Write(e)) => return Err(cannot_write(output, e)),
                    Err(StreamError::Render(e)) => {
                        return Err(format!("{}: error: {e}", path.display()));
                    }
                }
                let length = header.len() + width * size.height as usize * 3;
                file.set_len(length as u64)
                    .map_err(|e| cannot_write(output, e))?;
                None
            }
            None => {
                let rendered = microray::host::render_parallel(
                    &renderer,
                    options.threads,
                    options.aa,
                    progress,
                );
                let image = rendered.map_err(|e| format!("{}: error: {e}", path.display()))?;
                Some((image, file))
            }
        };
        if let Some(b) = bar.get() {
            b.finish_and_clear();
        }
        image
    };
    if let Some((mut image, mut file)) = image {
        to_depth(image.rgb_mut(), size.width as usize, 0, options.depth);
        write_image_to(&image, format, &mut file, output)?;
    }
    if !quiet {
        let order = match options.aa {
            Some(Antialias::Grid(samples)) => format!("{} samples a pixel, ", samples.count()),
            Some(Antialias::Adaptive { samples, .. }) => {
                format!("{} samples on edges, ", samples.count())
            }
            None if options.progressive => "progressive, ".into(),
            None => String::new(),
        };
        let threads = if options.progressive || options.threads == 1 {
            String::new()
        } else {
            format!(", {} threads", options.threads)
        };
        // Milliseconds below a second: the host tracer's renders mostly take a few, and
        // `cargo xtask host-bench` reads this figure.
        let seconds = start.elapsed().as_secs_f64();
        let took = if seconds < 1.0 {
            format!("{:.2} ms", seconds * 1e3)
        } else {
            format!("{seconds:.2} s")
        };
        eprintln!(
            "{}: {}x{} in {took} ({order}{}{threads}) -> {}",
            path.display(),
            size.width,
            size.height,
            S::NAME,
            output.display()
        );
    }
    Ok(())
}

/// Writes an image in `format` to `output`.
fn write_image(image: &Framebuffer, format: Format, output: &Path) -> Result<(), String> {
    let mut file = open_over(output).map_err(|e| cannot_write(output, e))?;
    write_image_to(image, format, &mut file, output)
}

/// Writes an image in `format` to `file`, opened by [`open_over`] (`output` names it).
fn write_image_to(
    image: &Framebuffer,
    format: Format,
    file: &mut std::fs::File,
    output: &Path,
) -> Result<(), String> {
    match format {
        // Straight from the framebuffer: no copy of the image first.
        Format::Ppm => write_over(file, |file| image.write_ppm(file)),
        Format::Png => {
            let bytes = image
                .to_png()
                .map_err(|e| format!("{}: error: PNG encoding failed: {e}", output.display()))?;
            write_over(file, |file| file.write_all(&bytes))
        }
    }
    .map_err(|e| cannot_write(output, e))
}

fn cannot_write(output: &Path, e: std::io::Error) -> String {
    format!("{}: error: cannot write: {e}", output.display())
}

/// `output` opened for writing over what it held: an existing file is cut to the new length
/// after the writing ([`write_over`]), not emptied before it (emptying it first frees its
/// pages and blocks only for the writing to take new ones: a millisecond for a 640x480 PPM,
/// a twentieth of a render).
fn open_over(output: &Path) -> std::io::Result<std::fs::File> {
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(output)
}

/// Writes all of `bytes` at `offset` in `file`, whatever other threads write elsewhere.
#[cfg(unix)]
fn write_at(file: &std::fs::File, bytes: &[u8], offset: usize) -> std::io::Result<()> {
    std::os::unix::fs::FileExt::write_all_at(file, bytes, offset as u64)
}

/// Not called: streaming is for Unix (see `render`).
#[cfg(not(unix))]
fn write_at(_file: &std::fs::File, _bytes: &[u8], _offset: usize) -> std::io::Result<()> {
    Err(std::io::Error::other("writing at an offset needs Unix"))
}

/// Writes `file` (from [`open_over`]) with `write`, then cuts it to what was written.
fn write_over(
    file: &mut std::fs::File,
    write: impl FnOnce(&mut std::fs::File) -> std::io::Result<()>,
) -> std::io::Result<()> {
    write(file)?;
    // Only a regular file has a length to set (not a pipe or a terminal).
    if file.metadata()?.is_file() {
        let written = file.stream_position()?;
        file.set_len(written)?;
    }
    Ok(())
}
