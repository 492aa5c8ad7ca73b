//! The std tracer: a thin shell over the library.

use clap::{Parser, Subcommand};
use microray::host::{HostScene, texture_files};
use microray::parse::parse_scene;
use microray::print::print_scene;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

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
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Check { scene } => load(scene).map(|s| {
            let cam = s.camera();
            let spots = s.lights().iter().filter(|l| l.spot.is_some()).count();
            println!(
                "ok: {}: {}x{} pixels, {}, {}, {} ({} spot), {}",
                scene.display(),
                cam.width(),
                cam.height(),
                count(s.materials().len(), "material"),
                count(s.textures().len(), "texture"),
                count(s.lights().len(), "light"),
                spots,
                count(s.objects().len(), "object"),
            );
        }),
        Command::Print { scene } => load(scene).and_then(|s| {
            let mut text = String::new();
            print_scene(&s, &mut text)
                .map_err(|_| format!("{}: error: printing failed", scene.display()))?;
            print!("{text}");
            Ok(())
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("{message}");
            ExitCode::FAILURE
        }
    }
}

/// Reads and parses a scene; the error is the full `FILE:LINE:COL: error: ...` line.
fn load(path: &Path) -> Result<HostScene<'static, f64>, String> {
    let text =
        std::fs::read(path).map_err(|e| format!("{}: error: cannot read: {e}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    parse_scene(&text, texture_files(dir)).map_err(|e| match e.position {
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

fn count(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}
