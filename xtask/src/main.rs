//! The project's tasks.
//!
//! - `cargo xtask qemu [--size WxH] [--only SCENE,...] [--build PREFIX] [--profile]
//!   [--compare-plan]`: builds the firmware for the emulated Cortex-M4F (mps2-an386) and
//!   Cortex-M0 (microbit) in f32 and I16F16, and the instruction-counting QEMU plugin; runs
//!   every scene on both machines; compares each frame byte for byte with the host's render
//!   of the same scene, number type and size; prints the table (and, for a complete run,
//!   writes it to `docs/firmware.md`). `--compare-plan` renders each scene a second time
//!   without the render plan (`SCENE+noplan`). Exits non-zero on any difference or failure.
//! - `cargo xtask bench [--quick]`: run time against error (`docs/benchmarks.md`).
//! - `cargo xtask host-bench [--runs N]`: the bench's whole-process tables alone (the std
//!   tracer against the course's figures, directly and through the build), printed.
//! - `cargo xtask host-profile [--binary PATH] [--out FILE]`: the std tracer's time per
//!   function (perf) on spec0 and tplane4.
//! - `cargo xtask pgo`: the std tracer built with profile-guided optimisation, trained on
//!   the course's scenes (`target/pgo/use/release/microray`; see `xtask/src/pgo.rs`).

mod animation;
mod bench;
mod host_profile;
mod pgo;
mod pico;
mod profile;
mod qemu;

use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("qemu") => qemu::run(&args[1..]),
        Some("bench") => bench::run(&args[1..]),
        Some("host-bench") => bench::host_run(&args[1..]),
        Some("host-profile") => host_profile::run(&args[1..]),
        Some("pgo") => pgo::run(&args[1..]),
        Some("pico") => pico::run(&args[1..]),
        _ => Err(
            "usage: cargo xtask qemu [--size WIDTHxHEIGHT] [--only SCENE,...] \
                  [--build PREFIX] [--profile] [--compare-plan] | cargo xtask bench [--quick] | cargo xtask host-bench [--runs N] \
                  | cargo xtask host-profile \
                  [--binary PATH] [--out FILE] [--title TEXT] [--runs N] | cargo xtask pgo \
                  | cargo xtask pico [--only SCENE,...]"
                .to_string(),
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("xtask: {message}");
            ExitCode::FAILURE
        }
    }
}
