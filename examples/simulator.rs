//! Renders a scene into embedded-graphics-simulator's `SimulatorDisplay`: the same no_std
//! path firmware uses with a real panel, here with an `Rgb565` display as on most small LCDs.
//!
//! ```sh
//! cargo run --release --example simulator -- scenes/showcase.txt showcase-sim.png
//! cargo run --release --example simulator --features sdl -- scenes/showcase.txt   # a window
//! cargo run --release --example simulator -- --progressive scenes/vases.txt vases.png
//! ```
//!
//! Without the `sdl` feature it writes a PNG (no SDL needed). With it, it opens a window and
//! shows each row as it arrives. With `--progressive` the picture comes in four passes (8x8
//! blocks, 4x4, 2x2, every pixel: `Renderer::render_pass`), the same image at the end; the
//! window shows each pass, and the PNG mode writes each preview too (`vases-8.png`, ...).

use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use embedded_graphics_simulator::SimulatorDisplay;
use microray::host::{HostRenderer, HostScene, texture_files};
use microray::parse::parse_scene;
use microray::render::{BLOCKS, Renderer};
use std::ops::ControlFlow;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let all: Vec<String> = std::env::args().skip(1).collect();
    let progressive = all.iter().any(|a| a == "--progressive");
    let mut args = all.into_iter().filter(|a| a != "--progressive");
    let scene_path = args.next().unwrap_or_else(|| "scenes/showcase.txt".into());
    let scene_path = Path::new(&scene_path);
    let text = std::fs::read(scene_path)?;
    let scene: HostScene<'_, f32> = parse_scene(
        &text,
        texture_files(scene_path.parent().unwrap_or(Path::new("."))),
    )
    .map_err(|e| format!("{}:{e}", scene_path.display()))?;
    let renderer = Renderer::new(&scene);
    let size = renderer.size();
    let mut display = SimulatorDisplay::<Rgb565>::new(size);
    let mut row = vec![Rgb565::BLACK; size.width as usize];
    show(&renderer, &mut display, &mut row, args.next(), progressive)
}

/// Writes the finished image to a PNG.
#[cfg(not(feature = "sdl"))]
fn show(
    renderer: &HostRenderer<'_, f32>,
    display: &mut SimulatorDisplay<Rgb565>,
    row: &mut [Rgb565],
    output: Option<String>,
    progressive: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    use embedded_graphics_simulator::OutputSettings;
    let output = output.unwrap_or_else(|| "simulator.png".into());
    if progressive {
        for (pass, block) in BLOCKS.iter().enumerate() {
            renderer.render_pass(display, row, pass)?;
            if *block > 1 {
                let preview = output.replace(".png", &format!("-{block}.png"));
                display
                    .to_rgb_output_image(&OutputSettings::default())
                    .save_png(&preview)?;
                println!("wrote {preview}");
            }
        }
    } else {
        let all = Rectangle::new(Point::zero(), renderer.size());
        renderer.render_area(display, all, row, |_| ControlFlow::Continue(()))?;
    }
    display
        .to_rgb_output_image(&OutputSettings::default())
        .save_png(&output)?;
    println!("wrote {output}");
    Ok(())
}

/// Opens a window and updates it after every row.
#[cfg(feature = "sdl")]
fn show(
    renderer: &HostRenderer<'_, f32>,
    display: &mut SimulatorDisplay<Rgb565>,
    row: &mut [Rgb565],
    _output: Option<String>,
    progressive: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    use embedded_graphics_simulator::{OutputSettingsBuilder, SimulatorEvent, Window};
    let mut window = Window::new("microray", &OutputSettingsBuilder::new().build());
    let size = renderer.size();
    let rows = if progressive { 0 } else { size.height as i32 };
    for pass in (0..BLOCKS.len()).filter(|_| progressive) {
        renderer.render_pass(display, row, pass)?;
        window.update(display);
        if window.events().any(|e| e == SimulatorEvent::Quit) {
            return Ok(());
        }
    }
    for y in 0..rows {
        let line = Rectangle::new(Point::new(0, y), Size::new(size.width, 1));
        renderer.render_area(display, line, row, |_| ControlFlow::Continue(()))?;
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
