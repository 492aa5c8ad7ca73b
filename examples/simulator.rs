//! Renders a scene into embedded-graphics-simulator's `SimulatorDisplay`: the same no_std
//! path firmware uses with a real panel, here with an `Rgb565` display as on most small LCDs.
//!
//! ```sh
//! cargo run --release --example simulator -- scenes/showcase.txt showcase-sim.png
//! cargo run --release --example simulator --features sdl -- scenes/showcase.txt   # a window
//! cargo run --release --example simulator -- --progressive scenes/vases.txt vases.png
//! cargo run --release --example simulator -- --help
//! ```
//!
//! Without the `sdl` feature it writes a PNG (no SDL needed). With it, it opens a window and
//! shows each row as it arrives. With `--progressive` the picture comes in four passes (8x8
//! blocks, 4x4, 2x2, every pixel: `Renderer::render_pass`), the same image at the end; the
//! window shows each pass, and the PNG mode writes each preview too (`vases-8.png`, ...).

use clap::Parser;
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use embedded_graphics_simulator::SimulatorDisplay;
use microray::host::{HostRenderer, HostScene, texture_files};
use microray::parse::parse_scene;
use microray::render::{BLOCKS, Renderer};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Renders a scene into an Rgb565 simulator display, as firmware renders into a panel.
#[derive(Parser)]
#[command(name = "simulator")]
struct Args {
    /// The scene file.
    scene: PathBuf,
    /// The PNG to write (without the `sdl` feature; with it, a window opens instead).
    #[cfg_attr(not(feature = "sdl"), arg(required = true))]
    output: Option<PathBuf>,
    /// Render in four passes (8x8 blocks, 4x4, 2x2, every pixel), writing or showing each.
    #[arg(long)]
    progressive: bool,
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("{message}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> Result<(), String> {
    let name = args.scene.display();
    let text =
        std::fs::read(&args.scene).map_err(|e| format!("{name}: error: cannot read: {e}"))?;
    let dir = args.scene.parent().unwrap_or(Path::new("."));
    let scene: HostScene<'_, f32> =
        parse_scene(&text, texture_files(dir)).map_err(|e| match e.position {
            Some(p) => format!("{name}:{}:{}: error: {}", p.line, p.column, e.kind),
            None => format!("{name}: error: {}", e.kind),
        })?;
    let renderer = Renderer::new(&scene);
    let size = renderer.size();
    let mut display = SimulatorDisplay::<Rgb565>::new(size);
    let mut row = vec![Rgb565::BLACK; size.width as usize];
    show(
        &renderer,
        &mut display,
        &mut row,
        args.output.as_deref(),
        args.progressive,
    )
}

/// Writes the finished image to a PNG.
#[cfg(not(feature = "sdl"))]
fn show(
    renderer: &HostRenderer<'_, f32>,
    display: &mut SimulatorDisplay<Rgb565>,
    row: &mut [Rgb565],
    output: Option<&Path>,
    progressive: bool,
) -> Result<(), String> {
    use embedded_graphics_simulator::OutputSettings;
    // clap requires the output without the `sdl` feature.
    let output = output.ok_or("error: no output file")?;
    let save = |display: &SimulatorDisplay<Rgb565>, path: &Path| {
        display
            .to_rgb_output_image(&OutputSettings::default())
            .save_png(path)
            .map_err(|e| format!("{}: error: cannot write: {e}", path.display()))?;
        println!("wrote {}", path.display());
        Ok::<(), String>(())
    };
    if progressive {
        for (pass, block) in BLOCKS.iter().enumerate() {
            renderer
                .render_pass(display, row, pass)
                .map_err(|e| format!("error: {e}"))?;
            if *block > 1 {
                let stem = output.file_stem().unwrap_or_default().to_string_lossy();
                save(
                    display,
                    &output.with_file_name(format!("{stem}-{block}.png")),
                )?;
            }
        }
    } else {
        let all = Rectangle::new(Point::zero(), renderer.size());
        renderer
            .render_area(display, all, row, |_| ControlFlow::Continue(()))
            .map_err(|e| format!("error: {e}"))?;
    }
    save(display, output)
}

/// Opens a window and updates it after every row.
#[cfg(feature = "sdl")]
fn show(
    renderer: &HostRenderer<'_, f32>,
    display: &mut SimulatorDisplay<Rgb565>,
    row: &mut [Rgb565],
    _output: Option<&Path>,
    progressive: bool,
) -> Result<(), String> {
    use embedded_graphics_simulator::{OutputSettingsBuilder, SimulatorEvent, Window};
    let mut window = Window::new("microray", &OutputSettingsBuilder::new().build());
    let size = renderer.size();
    let rows = if progressive { 0 } else { size.height as i32 };
    for pass in (0..BLOCKS.len()).filter(|_| progressive) {
        renderer
            .render_pass(display, row, pass)
            .map_err(|e| format!("error: {e}"))?;
        window.update(display);
        if window.events().any(|e| e == SimulatorEvent::Quit) {
            return Ok(());
        }
    }
    for y in 0..rows {
        let line = Rectangle::new(Point::new(0, y), Size::new(size.width, 1));
        renderer
            .render_area(display, line, row, |_| ControlFlow::Continue(()))
            .map_err(|e| format!("error: {e}"))?;
        window.update(display);
        if window.events().any(|e| e == SimulatorEvent::Quit) {
            return Ok(());
        }
    }
    loop {
        window.update(display);
        if window.events().any(|e| e == SimulatorEvent::Quit) {
            return Ok(());
        }
        std::thread::sleep(std::time::Duration::from_millis(30));
    }
}
