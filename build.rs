//! Sets `cfg(microray_conformance)` when `MICRORAY_CONFORMANCE` names the course's scenes
//! (the tests that need them are ignored otherwise, with the reason).
//!
//! Sets `cfg(microray_small)` when the crate is built for the least flash (`opt-level` `z`,
//! as the firmware's `release-small` profile; `s` still weighs speed), or when
//! `MICRORAY_SMALL` is set (so that the host's tests can check that shape): where speed and
//! flash pull apart, the library then takes the smaller shape (see docs/design.md, "Built
//! for size"). The same pixels either way.
//!
//! Links the `microray` binary as a static PIE on Linux with glibc, when the static
//! archives are installed (they come with the C compiler's `libc6-dev`).
//!
//! Why: a dynamically linked Rust binary spends about 0.23 ms of every run loading
//! `libgcc_s` and `libm` and relocating (measured on the course's scenes: a render is 11
//! to 50 ms), and a static PIE keeps the address randomisation that `-no-pie` would lose.
//!
//! How: `-C target-feature=+crt-static` would do it, but it can only be set for a whole
//! build, where it stops proc macros (clap's derive) and `cdylib`s from building. So the
//! binary alone gets `-static-pie` at link time. Rust's link line still asks for
//! `-lgcc_s -lc -lm ...` in dynamic mode, so a directory searched before the system's holds
//! only static libraries under those names (one-line linker scripts naming the archives):
//! `libgcc_s.a` is the static unwinder (`libgcc_eh.a` and `libgcc.a`, what `crt-static`
//! links), the others are glibc's own.
//!
//! Nothing changes elsewhere (other systems, cross builds, a build without the archives,
//! or `MICRORAY_DYNAMIC=1`): the binary is then linked as usual.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// glibc's libraries that Rust's link line names.
const GLIBC: [&str; 6] = ["c", "m", "pthread", "dl", "rt", "util"];

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-env-changed=MICRORAY_DYNAMIC");
    // The tests that need the course's scenes are ignored, with the reason shown by
    // `cargo test`, when the variable that points at them is unset.
    println!("cargo::rerun-if-env-changed=MICRORAY_CONFORMANCE");
    println!("cargo::rustc-check-cfg=cfg(microray_conformance)");
    if env::var_os("MICRORAY_CONFORMANCE").is_some() {
        println!("cargo::rustc-cfg=microray_conformance");
    }
    println!("cargo::rerun-if-env-changed=MICRORAY_SMALL");
    println!("cargo::rustc-check-cfg=cfg(microray_small)");
    if matches!(env::var("OPT_LEVEL").as_deref(), Ok("z"))
        || env::var_os("MICRORAY_SMALL").is_some_and(|v| !v.is_empty())
    {
        println!("cargo::rustc-cfg=microray_small");
    }
    if let Some(dir) = static_libs() {
        println!("cargo::rustc-link-arg-bins=-L{}", dir.display());
        println!("cargo::rustc-link-arg-bins=-static-pie");
        // For tests/cli.rs, which checks the binary that came out.
        println!("cargo::rustc-env=MICRORAY_STATIC_PIE=1");
    }
}

/// The directory of static archives for the binary's link, or `None` to link as usual.
fn static_libs() -> Option<PathBuf> {
    let var = |name: &str| env::var(name).unwrap_or_default();
    let wanted = var("CARGO_CFG_TARGET_OS") == "linux"
        && var("CARGO_CFG_TARGET_ENV") == "gnu"
        && var("TARGET") == var("HOST")
        && env::var_os("CARGO_FEATURE_STD").is_some()
        && env::var_os("MICRORAY_DYNAMIC").is_none()
        && !var("CARGO_CFG_TARGET_FEATURE")
            .split(',')
            .any(|f| f == "crt-static");
    if !wanted {
        return None;
    }
    let dir = PathBuf::from(env::var_os("OUT_DIR")?).join("static-libs");
    fs::create_dir_all(&dir).ok()?;
    for lib in GLIBC {
        let name = format!("lib{lib}.a");
        static_library(&dir, &name, &[archive(&name)?])?;
    }
    let unwinder = [archive("libgcc_eh.a")?, archive("libgcc.a")?];
    static_library(&dir, "libgcc_s.a", &unwinder)?;
    Some(dir)
}

/// Where the C compiler finds `name`, if it is installed.
fn archive(name: &str) -> Option<PathBuf> {
    let cc = env::var("CC").unwrap_or_else(|_| "cc".into());
    let out = Command::new(cc)
        .arg(format!("-print-file-name={name}"))
        .output()
        .ok()?;
    let path = PathBuf::from(String::from_utf8(out.stdout).ok()?.trim());
    // An answer without a directory means not found.
    (path.is_absolute() && path.exists()).then_some(path)
}

/// Writes `dir/name`, a linker script that stands for `archives`.
fn static_library(dir: &Path, name: &str, archives: &[PathBuf]) -> Option<()> {
    let paths: Vec<String> = archives.iter().map(|a| a.display().to_string()).collect();
    fs::write(dir.join(name), format!("INPUT({})\n", paths.join(" "))).ok()
}
