//! The std tracer: a thin shell over the library.
//!
//! Every write is checked: a full disk or a closed standard error ends the run with one
//! line and exit code 1; a reader that closes standard output early (`| head -1`) ends it
//! quietly, with exit code 0.

mod animate;
mod output;
mod panel;

use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use microray::Scalar;
use microray::host::{Framebuffer, HostRenderer, HostScene, StreamError, texture_files};
use microray::parse::parse_scene_into;
use microray::print::print_scene;
use microray::render::{Antialias, Pattern, Renderer, Samples, Shading};
use microray::scalar::I16F16;
use output::{Format, Image, Staged, is_stdio};
use std::io::{IsTerminal, Read, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

#[derive(Parser)]
#[command(
    name = "microray",
    version,
    about = "A no_std ray tracer for microcontroller displays: the std front end",
    after_help = "A scene path of `-` reads standard input (texture files are then found in the \
                  current folder); an output of `-` writes standard output."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check a scene file: prints `ok` and a summary, or `FILE:LINE:COL: error: ...`.
    Check {
        /// The scene file (`-`: standard input).
        scene: PathBuf,
    },
    /// Print a scene as microray reads it (valid scene text that reads back equal).
    Print {
        /// The scene file (`-`: standard input).
        scene: PathBuf,
    },
    /// Compile a scene for firmware: its values as loaded in one number type, bit for bit,
    /// which `Scene::load_compiled` reads without the parser and without f64 arithmetic.
    Compile {
        /// The scene file (`-`: standard input).
        scene: PathBuf,
        /// The compiled scene to write (`-`: standard output).
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
        /// The scene file (`-`: standard input).
        scene: PathBuf,
        /// The image to write (`-`: standard output); the extension picks the format,
        /// unless `--format` does.
        #[arg(short, long)]
        output: PathBuf,
        /// The image format, for an output whose name has no `.ppm` or `.png` (`-`, a
        /// device, a pipe); PPM if neither says.
        #[arg(long, value_enum)]
        format: Option<Format>,
        #[command(flatten)]
        look: Look,
        /// Render in the progressive order (8x8 blocks, 4x4, 2x2, every pixel; the same
        /// image) on one thread, and write each preview pass too, as OUT-8, OUT-4 and
        /// OUT-2 beside OUT.
        #[arg(long)]
        progressive: bool,
        /// Threads to render with (each takes bands of rows; the image is the same for
        /// any number); all cores by default, 1 for one thread. `--progressive` renders
        /// on one.
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
        threads: Option<u16>,
    },
    /// Play a scene's `animation` into an animated PNG (APNG): frame 0 traced whole, each
    /// later one only where its changes can touch the picture (the same frames as tracing
    /// each whole, byte for byte).
    Animate {
        /// The scene file (`-`: standard input), with an `animation` block and motions.
        scene: PathBuf,
        /// The animated PNG to write (`-`: standard output).
        #[arg(short, long)]
        output: PathBuf,
        #[command(flatten)]
        look: Look,
        /// Trace every frame whole, for comparison.
        #[arg(long)]
        full: bool,
        /// How long each frame shows, in milliseconds.
        #[arg(long, default_value_t = 40, value_parser = clap::value_parser!(u16).range(1..))]
        delay: u16,
        /// The film's size, WIDTHxHEIGHT, if not the scene's `pixeldim` (a panel's).
        #[arg(long, value_parser = parse_size)]
        size: Option<(u16, u16)>,
    },
}

/// How a picture is computed and shown: the options `render` and `animate` share.
#[derive(clap::Args)]
struct Look {
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
    /// A panel's colour format: the picture as that panel shows it with each channel
    /// truncated to its top bits, expanded back to 8 bits a channel. FORMAT: binary gray2
    /// gray4 gray8 rgb332 rgb444 rgb555 rgb565 rgb666 (or rgb888, the tracer's own).
    #[arg(long, value_name = "FORMAT", value_parser = panel::parse_color)]
    color: Option<panel::Color>,
    /// Dither to a panel's colour format instead of truncating, expanded back to 8 bits a
    /// channel. METHOD: bayer2 bayer4 bayer8 blue-noise floyd-steinberg atkinson (the last
    /// two also with -serpentine); the default is the format's best in docs/dither.md.
    /// `--color` may name the same format, not another.
    #[arg(long, value_name = "FORMAT[:METHOD]", value_parser = panel::parse_dither)]
    dither: Option<panel::PanelDither>,
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
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage(&e),
    };
    match run(&cli.command) {
        Ok(()) | Err(Stop::Closed) => ExitCode::SUCCESS,
        Err(Stop::Failed(message)) => {
            // If standard error is what failed, there is nowhere left to say so.
            let _ = writeln!(std::io::stderr(), "{message}");
            ExitCode::FAILURE
        }
    }
}

/// Why a command stopped early.
enum Stop {
    /// What went wrong, in one line.
    Failed(String),
    /// The reader of standard output (or error) went away: nothing more to write, and
    /// nothing to report.
    Closed,
}

impl From<String> for Stop {
    fn from(message: String) -> Self {
        Stop::Failed(message)
    }
}

/// Help, the version or a usage error from clap, written where clap would, with the write
/// checked.
fn usage(e: &clap::Error) -> ExitCode {
    let to_stderr = e.use_stderr();
    let styled = if to_stderr {
        std::io::stderr().is_terminal()
    } else {
        std::io::stdout().is_terminal()
    };
    let rendered = e.render();
    let text = if styled {
        rendered.ansi().to_string()
    } else {
        rendered.to_string()
    };
    let written = if to_stderr {
        say_to(&mut std::io::stderr(), "standard error", &text)
    } else {
        say(&text)
    };
    match written {
        Ok(()) | Err(Stop::Closed) => ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(2)),
        Err(Stop::Failed(message)) => {
            let _ = writeln!(std::io::stderr(), "{message}");
            ExitCode::FAILURE
        }
    }
}

/// Writes `text` to standard output.
fn say(text: &str) -> Result<(), Stop> {
    say_to(&mut std::io::stdout().lock(), "standard output", text)
}

/// Writes a line to standard error.
fn note(line: &str) -> Result<(), Stop> {
    say_to(
        &mut std::io::stderr().lock(),
        "standard error",
        &format!("{line}\n"),
    )
}

fn say_to(out: &mut impl Write, name: &str, text: &str) -> Result<(), Stop> {
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| written_to(name, e))
}

/// A failed write to a standard stream: quiet if its reader has gone.
fn written_to(name: &str, e: std::io::Error) -> Stop {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        Stop::Closed
    } else {
        Stop::Failed(format!("error: cannot write to {name}: {e}"))
    }
}

fn run(command: &Command) -> Result<(), Stop> {
    match command {
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
            format,
            look,
            progressive,
            threads,
        } => {
            if *progressive && threads.is_some_and(|n| n > 1) {
                return Err(Stop::Failed(
                    "error: --progressive renders on one thread (its passes fill one image in \
                     order): leave out --threads or give 1"
                        .into(),
                ));
            }
            let options = Options {
                format: *format,
                progressive: *progressive,
                threads: threads.map_or_else(
                    || std::thread::available_parallelism().map_or(1, |n| n.get()),
                    usize::from,
                ),
                ..options_of(look, false)?
            };
            match look.number {
                Number::F64 => render::<f64>(scene, output, &options),
                Number::F32 => render::<f32>(scene, output, &options),
                Number::I16f16 => render::<I16F16>(scene, output, &options),
            }
        }
        Command::Animate {
            scene,
            output,
            look,
            full,
            delay,
            size,
        } => {
            let options = options_of(look, true)?;
            let film = animate::Film {
                full: *full,
                delay: *delay,
                size: *size,
            };
            match look.number {
                Number::F64 => animate::animate::<f64>(scene, output, &options, film),
                Number::F32 => animate::animate::<f32>(scene, output, &options, film),
                Number::I16f16 => animate::animate::<I16F16>(scene, output, &options, film),
            }
        }
    }
}

/// The colours `--dither` and `--color` ask for (`moving`: for an animation, whose frames
/// are patches, so error diffusion is out and an unnamed method is the best ordered one).
fn output_of(
    dither: Option<panel::PanelDither>,
    color: Option<panel::Color>,
    moving: bool,
) -> Result<panel::Output, Stop> {
    use microray::dither::Method;
    use panel::Output;
    let refuse = |text: String| Err(Stop::Failed(format!("error: {text}")));
    let Some(d) = dither else {
        return Ok(match color {
            Some(panel::Color::Panel(format)) => Output::Panel {
                format,
                method: None,
            },
            Some(panel::Color::Rgb888) | None => Output::Rgb888,
        });
    };
    match color {
        Some(panel::Color::Rgb888) => {
            return refuse(format!(
                "--dither {} reduces the picture to a panel's colours, which --color rgb888 \
                 does not: leave out one of them",
                d.format.name()
            ));
        }
        Some(panel::Color::Panel(f)) if f != d.format => {
            return refuse(format!(
                "--dither {} and --color {} name different panels: leave out one of them",
                d.format.name(),
                f.name()
            ));
        }
        _ => {}
    }
    let method = match (d.method, moving) {
        (Some(m @ Method::Diffusion { .. }), true) => {
            return refuse(format!(
                "--dither {}:{}: error diffusion spreads each pixel's error over the rest \
                 of the frame, and an animation redraws patches: use bayer2, bayer4, bayer8 \
                 or blue-noise",
                d.format.name(),
                m.name()
            ));
        }
        (Some(m), _) => m,
        (None, true) => d.format.best_ordered(),
        (None, false) => d.format.best_method(),
    };
    Ok(Output::Panel {
        format: d.format,
        method: Some(method),
    })
}

/// The options `look` gives (one thread, no progressive order, the format by the name).
fn options_of(look: &Look, moving: bool) -> Result<Options, Stop> {
    let pattern = match look.aa_pattern {
        AaPattern::Rotated => Pattern::Rotated,
        AaPattern::Regular => Pattern::Regular,
    };
    // parse_aa let only squares through.
    let samples = Samples::new(look.aa.count, pattern).unwrap_or(Samples::ONE);
    let depth = output_of(look.dither, look.color, moving)?;
    Ok(Options {
        format: None,
        shading: match look.shade {
            ShadeMode::Color => Shading::Color,
            ShadeMode::Ids => Shading::Ids,
        },
        quiet: look.quiet,
        planned: !look.no_plan,
        progressive: false,
        depth,
        threads: 1,
        aa: match (look.aa.adaptive, look.aa.count) {
            (false, 1) => None,
            (false, _) => Some(Antialias::Grid(samples)),
            (true, _) => Some(Antialias::Adaptive {
                samples,
                threshold: look.aa_threshold,
            }),
        },
    })
}

/// An empty scene on the heap. On the stack its room for 256 objects (about 100 KB) is a
/// frame the stack probes fault in page by page, all of it, whatever the scene holds; on
/// the heap only the pages written are (25 page faults fewer: 0.07 ms of a run, measured).
fn empty_scene<S: Scalar>() -> Box<HostScene<'static, S>> {
    Box::new(HostScene::empty())
}

/// How a path appears in messages: `-` is standard input or output.
fn shown(path: &Path, stdio: &str) -> String {
    if is_stdio(path) {
        stdio.to_string()
    } else {
        path.display().to_string()
    }
}

// Each command is a function of its own, never inlined: a frame with a command's locals
// in `main` would be stack that every command faults in.
#[inline(never)]
fn print(path: &Path) -> Result<(), Stop> {
    let name = shown(path, "<stdin>");
    let (source, dir) = read(path)?;
    let mut s = empty_scene::<f64>();
    load_text(&name, &source, &dir, &mut s)?;
    let animation = microray::parse::parse_animation::<{ animate::MOTIONS }>(&source)
        .map_err(|e| located(&name, &e))?;
    let mut text = String::new();
    print_scene(&s, &mut text)
        .and_then(|()| match &animation {
            Some(a) => microray::print::print_animation(a, &mut text),
            None => Ok(()),
        })
        .map_err(|_| format!("{name}: error: printing failed"))?;
    say(&text)
}

#[inline(never)]
fn check(path: &Path) -> Result<(), Stop> {
    let mut s = empty_scene::<f64>();
    load(path, &mut s)?;
    let cam = s.camera();
    let spots = s.lights().iter().filter(|l| l.spot.is_some()).count();
    say(&format!(
        "ok: {}: {}x{} pixels, {}, {}, {} ({} spot), {}\n{}\n",
        shown(path, "<stdin>"),
        cam.width(),
        cam.height(),
        count(s.materials().len(), "material"),
        count(s.textures().len(), "texture"),
        count(s.lights().len(), "light"),
        spots,
        count(s.objects().len(), "object"),
        plan_summary(&Renderer::new(&s)),
    ))?;
    for line in warnings(&s, &shown(path, "<stdin>")) {
        say(&format!("{line}\n"))?;
    }
    Ok(())
}

/// The scene's warnings (see `microray::warning`), a line each, for the file `name`.
fn warnings<S: Scalar>(scene: &HostScene<'_, S>, name: &str) -> Vec<String> {
    let mut lines = Vec::new();
    scene.warnings(|w| lines.push(format!("{name}: warning: {w}")));
    lines
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

/// Reads and parses a scene (`-`: standard input) into `scene`; the error is the full
/// `FILE:LINE:COL: error: ...` line. In place, not returned: the scene is 100 KB, and every
/// copy of it on the way out (the parser's, the `Result`'s) is stack that the process must
/// fault in, 0.1 ms a render.
#[inline(never)]
fn load<S: Scalar>(path: &Path, scene: &mut HostScene<'static, S>) -> Result<(), String> {
    let (text, dir) = read(path)?;
    load_text(&shown(path, "<stdin>"), &text, &dir, scene)
}

/// A scene file's text (`-`: standard input) and the folder its textures are found in.
fn read(path: &Path) -> Result<(Vec<u8>, PathBuf), String> {
    let name = shown(path, "<stdin>");
    if is_stdio(path) {
        let mut text = Vec::new();
        std::io::stdin()
            .lock()
            .read_to_end(&mut text)
            .map_err(|e| format!("{name}: error: cannot read: {e}"))?;
        Ok((text, PathBuf::from(".")))
    } else {
        let text = std::fs::read(path).map_err(|e| format!("{name}: error: cannot read: {e}"))?;
        Ok((text, path.parent().unwrap_or(Path::new(".")).to_path_buf()))
    }
}

/// Parses scene text read from `name` into `scene` (see [`load`]).
fn load_text<S: Scalar>(
    name: &str,
    text: &[u8],
    dir: &Path,
    scene: &mut HostScene<'static, S>,
) -> Result<(), String> {
    parse_scene_into(text, texture_files(dir), scene).map_err(|e| located(name, &e))
}

/// `NAME:LINE:COL: error: ...` for a scene's error.
fn located(name: &str, e: &microray::Error) -> String {
    match e.position {
        Some(p) => format!("{name}:{}:{}: error: {}", p.line, p.column, e.kind),
        None => format!("{name}: error: {}", e.kind),
    }
}

fn parse_size(text: &str) -> Result<(u16, u16), String> {
    let (w, h) = text
        .split_once('x')
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, found `{text}`"))?;
    let number = |v: &str| v.parse::<u16>().map_err(|e| format!("`{v}`: {e}"));
    Ok((number(w)?, number(h)?))
}

#[inline(never)]
fn compile<S: Scalar>(path: &Path, output: &Path, size: Option<(u16, u16)>) -> Result<(), Stop> {
    let mut scene = empty_scene::<S>();
    load(path, &mut scene)?;
    if let Some((width, height)) = size {
        scene
            .set_resolution(width, height)
            .map_err(|e| format!("{}: error: --size: {e}", shown(path, "<stdin>")))?;
    }
    let mut bytes = Vec::new();
    scene.write_compiled(&mut |piece| bytes.extend_from_slice(piece));
    write_whole(output, |out| {
        out.write_all(&bytes).map_err(|e| cannot_write(output, e))
    })?;
    note(&format!(
        "{}: {} bytes ({}) -> {}",
        shown(path, "<stdin>"),
        bytes.len(),
        S::NAME,
        shown(output, "<stdout>")
    ))
}

/// Writes a file (`-`: standard output) with `write`: a regular file is written beside its
/// name and put in place when whole ([`Staged`]), anything else as it is.
fn write_whole(
    output: &Path,
    write: impl FnOnce(&mut (dyn Write + Send)) -> Result<(), Stop>,
) -> Result<(), Stop> {
    if output::writes_in_place(output) {
        let mut out = output::stream(output).map_err(|e| cannot_write(output, e))?;
        write(&mut out)?;
        return out.flush().map_err(|e| cannot_write(output, e));
    }
    let staged = Staged::create(output).map_err(|e| cannot_write(output, e))?;
    let mut out = std::io::BufWriter::with_capacity(64 * 1024, staged.file());
    write(&mut out)?;
    out.flush().map_err(|e| cannot_write(output, e))?;
    drop(out);
    staged.commit().map_err(|e| cannot_write(output, e))
}

struct Options {
    format: Option<Format>,
    shading: Shading,
    quiet: bool,
    planned: bool,
    progressive: bool,
    depth: panel::Output,
    aa: Option<Antialias>,
    threads: usize,
}

/// The format of `output`: its extension's, which `--format` must agree with, else
/// `--format`'s, else PPM for standard output, a device or a pipe.
fn format_of(output: &Path, asked: Option<Format>) -> Result<Format, String> {
    let named = if is_stdio(output) {
        None
    } else {
        Format::of_name(output)
    };
    match (named, asked) {
        (Some(named), Some(asked)) if named != asked => Err(format!(
            "{}: error: the name says {} but --format says {}",
            output.display(),
            named.extension(),
            asked.extension()
        )),
        (Some(format), _) | (None, Some(format)) => Ok(format),
        (None, None) if output::writes_in_place(output) => Ok(Format::Ppm),
        (None, None) => Err(format!(
            "{}: error: unknown image format (name it .ppm or .png, or give --format)",
            output.display()
        )),
    }
}

#[inline(never)]
fn render<S: Scalar>(path: &Path, output: &Path, options: &Options) -> Result<(), Stop> {
    let quiet = options.quiet;
    let format = format_of(output, options.format)?;
    if is_stdio(output) && std::io::stdout().is_terminal() {
        return Err(Stop::Failed(
            "error: standard output is a terminal: send the image to a file or a pipe".into(),
        ));
    }
    if options.progressive && is_stdio(output) {
        return Err(Stop::Failed(
            "error: --progressive writes its previews beside the output: give a file name".into(),
        ));
    }
    if options.progressive && options.aa.is_some() {
        return Err(Stop::Failed(
            "error: --aa and --progressive cannot be combined (the progressive order traces \
             one ray a pixel)"
                .into(),
        ));
    }
    let mut scene = empty_scene::<S>();
    load(path, &mut scene)?;
    let name = shown(path, "<stdin>");
    if !quiet {
        for line in warnings(&scene, &name) {
            note(&line)?;
        }
    }
    let renderer = Renderer::new(&scene)
        .with_shading(options.shading)
        .with_plan(options.planned);
    let start = Instant::now();
    if options.progressive {
        render_progressive(&renderer, output, format, options.depth, &name)?;
    } else {
        render_rows(&renderer, output, format, options, start, &name)?;
    }
    if quiet {
        return Ok(());
    }
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
    let size = renderer.size();
    note(&format!(
        "{name}: {}x{} in {took} ({order}{}{threads}) -> {}",
        size.width,
        size.height,
        S::NAME,
        shown(output, "<stdout>")
    ))
}

/// The progressive order into a framebuffer, each preview written as it is done.
fn render_progressive<S: Scalar>(
    renderer: &HostRenderer<'_, S>,
    output: &Path,
    format: Format,
    depth: panel::Output,
    name: &str,
) -> Result<(), Stop> {
    let size = renderer.size();
    let mut image = Framebuffer::new(size);
    let mut row = vec![Default::default(); size.width as usize];
    for (pass, block) in microray::render::BLOCKS.iter().enumerate() {
        renderer
            .render_pass(&mut image, &mut row, pass)
            .map_err(|e| format!("{name}: error: {e}"))?;
        let target = if *block > 1 {
            let stem = output.file_stem().and_then(|s| s.to_str()).unwrap_or("out");
            output.with_file_name(format!("{stem}-{block}.{}", format.extension()))
        } else {
            output.to_path_buf()
        };
        if *block > 1 || pass + 1 == microray::render::BLOCKS.len() {
            if depth == panel::Output::Rgb888 {
                write_framebuffer(&image, format, &target)?;
            } else {
                // The next pass draws on the picture itself: the panel's view is a copy.
                let mut shown_image = image.clone();
                panel::converter(depth, size.width as usize).rows(shown_image.rgb_mut());
                write_framebuffer(&shown_image, format, &target)?;
            }
        }
    }
    Ok(())
}

/// Writes a whole framebuffer as an image file.
fn write_framebuffer(image: &Framebuffer, format: Format, output: &Path) -> Result<(), Stop> {
    use embedded_graphics::geometry::OriginDimensions;
    let size = image.size();
    let row_bytes = size.width as usize * 3;
    write_whole(output, |out| {
        let encoded = (|| {
            let mut file = Image::start(format, size, out)?;
            let mut encoder = file.encoder()?;
            for rows in image.rgb().chunks(row_bytes.max(1) * 64) {
                encoder.rows(rows)?;
            }
            encoder.finish()?;
            file.finish()
        })();
        encoded.map_err(|e| cannot_write(output, e))
    })
}

/// Renders on `options.threads` threads, each band of rows handed on as it is done: into a
/// PPM file at its place (`pwrite`), else through an encoder in row order. No image in
/// memory either way.
fn render_rows<S: Scalar>(
    renderer: &HostRenderer<'_, S>,
    output: &Path,
    format: Format,
    options: &Options,
    start: Instant,
    name: &str,
) -> Result<(), Stop> {
    let size = renderer.size();
    // Only renders that take more than a moment get a bar.
    let bar: std::sync::OnceLock<ProgressBar> = std::sync::OnceLock::new();
    let rows = AtomicU64::new(0);
    let total = u64::from(size.height);
    let quiet = options.quiet;
    let progress = |_| {
        let done = rows.fetch_add(1, Ordering::Relaxed) + 1;
        if quiet {
            return;
        }
        if bar.get().is_none() && start.elapsed() > Duration::from_millis(300) {
            let _ = bar.get_or_init(|| {
                let b = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
                let style = ProgressStyle::with_template("{bar:40} {pos}/{len} rows, {eta} left");
                b.set_style(style.unwrap_or_else(|_| ProgressStyle::default_bar()));
                b
            });
        }
        if let Some(b) = bar.get() {
            b.set_position(done);
        }
    };
    let width = size.width as usize;
    let depth = options.depth;
    let failed = |e: StreamError<std::io::Error>| -> Stop {
        match e {
            StreamError::Write(e) => cannot_write(output, e),
            StreamError::Render(e) => Stop::Failed(format!("{name}: error: {e}")),
        }
    };
    // Writing at an offset is a Unix call (Windows has one that moves the file's cursor).
    // Error diffusion takes the rows in order: through the encoder's path.
    if format == Format::Ppm
        && !output::writes_in_place(output)
        && cfg!(unix)
        && !depth.needs_order()
    {
        let staged = Staged::create(output).map_err(|e| cannot_write(output, e))?;
        let file = staged.file();
        let header = microray::host::ppm_header(size);
        write_at(file, header.as_bytes(), 0).map_err(|e| cannot_write(output, e))?;
        microray::host::render_streamed(
            renderer,
            options.threads,
            options.aa,
            progress,
            |top, pixels: &mut [u8]| {
                panel::to_panel(pixels, width, (0, top), depth);
                write_at(file, pixels, header.len() + top * width * 3)
            },
        )
        .map_err(failed)?;
        staged.commit().map_err(|e| cannot_write(output, e))?;
    } else {
        write_whole(output, |out| {
            let mut image = Image::start(format, size, out).map_err(|e| cannot_write(output, e))?;
            let mut encoder = image.encoder().map_err(|e| cannot_write(output, e))?;
            let mut converter = panel::converter(depth, width);
            microray::host::render_in_order(
                renderer,
                options.threads,
                options.aa,
                progress,
                |_, pixels: &mut [u8]| {
                    converter.rows(pixels);
                    encoder.rows(pixels)
                },
            )
            .map_err(failed)?;
            encoder.finish().map_err(|e| cannot_write(output, e))?;
            image.finish().map_err(|e| cannot_write(output, e))
        })?;
    }
    if let Some(b) = bar.get() {
        b.finish_and_clear();
    }
    Ok(())
}

fn cannot_write(output: &Path, e: std::io::Error) -> Stop {
    if is_stdio(output) {
        written_to("standard output", e)
    } else {
        Stop::Failed(format!("{}: error: cannot write: {e}", output.display()))
    }
}

/// Writes all of `bytes` at `offset` in `file`, whatever other threads write elsewhere.
#[cfg(unix)]
fn write_at(file: &std::fs::File, bytes: &[u8], offset: usize) -> std::io::Result<()> {
    std::os::unix::fs::FileExt::write_all_at(file, bytes, offset as u64)
}

/// Not called: streaming is for Unix (see `render_rows`).
#[cfg(not(unix))]
fn write_at(_file: &std::fs::File, _bytes: &[u8], _offset: usize) -> std::io::Result<()> {
    Err(std::io::Error::other("writing at an offset needs Unix"))
}
