//! `cargo xtask pgo`: the std tracer built with profile-guided optimisation.
//!
//! 1. builds `microray` instrumented (`-Cprofile-generate`) in `target/pgo/generate`;
//! 2. renders every training scene once with it, one thread, f64: the course's scenes
//!    (`MICRORAY_CONFORMANCE` and the `course-extensions` beside it) when they are there,
//!    else the project's `scenes/`;
//! 3. merges the counts with `llvm-profdata` (rustup's `llvm-tools` component), each
//!    scene weighted by the inverse of its total count, so that every scene counts alike
//!    (unweighted, the slowest scenes would decide the layout of code they share with the
//!    others: tplane4 was 1.4 % slower than without a profile);
//! 4. builds `microray` with the profile (`-Cprofile-use`) in `target/pgo/use`;
//! 5. renders every training scene with the new binary and with the plain release build,
//!    and fails unless every image is the same byte for byte (the compiler may lay out and
//!    inline code differently, never round differently; this checks it).
//!
//! The profile is not kept in the repository: it belongs to one compiler and one state of
//! the code, and takes about a minute to make. Cargo has no stable way to give
//! `-Cprofile-use` to the workspace's own crates alone with a path relative to the
//! workspace, so the plain `cargo build --release` stays without it.

use crate::qemu;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Builds the profile-guided binary and returns its path.
pub fn build(root: &Path) -> Result<PathBuf, String> {
    let profdata_tool = llvm_profdata()?;
    let pgo = root.join("target/pgo");
    let raw = pgo.join("raw");
    let generate = format!("-Cprofile-generate={}", raw.display());
    let instrumented = build_microray(root, &pgo.join("generate"), &generate)?;
    // Emptied after the build: its own instrumented programs (build scripts, proc macros)
    // wrote counts there too.
    let _ = std::fs::remove_dir_all(&raw);
    std::fs::create_dir_all(&raw).map_err(|e| e.to_string())?;
    let scenes = training_scenes(root);
    if scenes.is_empty() {
        return Err("no training scenes found".into());
    }
    let out = std::env::temp_dir().join(format!("microray-pgo-{}.ppm", std::process::id()));
    let mut weighted = Vec::new();
    for (index, scene) in scenes.iter().enumerate() {
        let counts = raw.join(format!("{index}.profraw"));
        render(
            &instrumented,
            scene,
            &out,
            &[("LLVM_PROFILE_FILE", counts.as_os_str())],
        )?;
        let total = total_count(&profdata_tool, &counts)?;
        // Every scene's counts scaled to about 4e9 in all (a weight is a whole number).
        let weight = 4_000_000_000 / total.max(1) + 1;
        weighted.push(format!("--weighted-input={weight},{}", counts.display()));
    }
    let profile = pgo.join("microray.profdata");
    qemu::checked(
        Command::new(&profdata_tool)
            .args(["merge", "-sparse", "-o"])
            .arg(&profile)
            .args(&weighted),
    )?;
    let use_profile = format!("-Cprofile-use={}", profile.display());
    let binary = build_microray(root, &pgo.join("use"), &use_profile)?;
    qemu::cargo(&["build", "--release", "--bin", "microray"], root, &[])?;
    let plain = root.join("target/release/microray");
    let other = std::env::temp_dir().join(format!("microray-pgo-{}-plain.ppm", std::process::id()));
    for scene in &scenes {
        render(&binary, scene, &out, &[])?;
        render(&plain, scene, &other, &[])?;
        let (a, b) = (std::fs::read(&out), std::fs::read(&other));
        if a.map_err(|e| e.to_string())? != b.map_err(|e| e.to_string())? {
            return Err(format!(
                "{}: the profile-guided build's image differs from the release build's",
                scene.display()
            ));
        }
    }
    let _ = std::fs::remove_file(&out);
    let _ = std::fs::remove_file(&other);
    eprintln!(
        "pgo: {} scenes, images identical to the release build's; {}",
        scenes.len(),
        binary.display()
    );
    Ok(binary)
}

/// `cargo xtask pgo`.
pub fn run(args: &[String]) -> Result<(), String> {
    if !args.is_empty() {
        return Err("usage: cargo xtask pgo".into());
    }
    let binary = build(&qemu::root()?)?;
    println!("{}", binary.display());
    Ok(())
}

/// The course's scenes and its later ones, or the project's own.
fn training_scenes(root: &Path) -> Vec<PathBuf> {
    let mut dirs = Vec::new();
    if let Some(conformance) = qemu::conformance_dir(root) {
        if let Some(extensions) = conformance
            .parent()
            .map(|p| p.join("course-extensions"))
            .filter(|p| p.is_dir())
        {
            dirs.push(extensions);
        }
        dirs.push(conformance);
    }
    if dirs.is_empty() {
        dirs.push(root.join("scenes"));
    }
    // Sorted: the same counts file for the same scene from run to run.
    let mut scenes = qemu::txt_files(dirs);
    scenes.sort();
    scenes
}

/// `binary render SCENE -o OUT -q --threads 1`.
fn render(
    binary: &Path,
    scene: &Path,
    out: &Path,
    envs: &[(&str, &std::ffi::OsStr)],
) -> Result<(), String> {
    let command = &mut render_command(binary, scene, out, Some("1"));
    qemu::checked(command.arg("-q").envs(envs.iter().copied()))
}

/// `binary render SCENE -o OUT [--threads THREADS]`, the whole-process run the bench
/// times too (`None` for a build without `--threads`, which had one thread only). Add `-q`
/// for no report.
pub(crate) fn render_command(
    binary: &Path,
    scene: &Path,
    out: &Path,
    threads: Option<&str>,
) -> Command {
    let mut command = Command::new(binary);
    command.arg("render").arg(scene).arg("-o").arg(out);
    if let Some(threads) = threads {
        command.args(["--threads", threads]);
    }
    command
}

/// `cargo build --release --bin microray` of the tree at `root` into `target_dir` with
/// `rustflags`; the binary.
pub(crate) fn build_microray(
    root: &Path,
    target_dir: &Path,
    rustflags: &str,
) -> Result<PathBuf, String> {
    let dir = target_dir.to_string_lossy();
    let args = [
        "build",
        "--release",
        "--bin",
        "microray",
        "--target-dir",
        &dir,
    ];
    qemu::cargo(&args, root, &[("RUSTFLAGS", rustflags)])?;
    Ok(target_dir.join("release/microray"))
}

/// The sum of a raw profile's counts (`llvm-profdata show`'s "Total count").
fn total_count(tool: &Path, raw: &Path) -> Result<u64, String> {
    let out = Command::new(tool)
        .arg("show")
        .arg(raw)
        .output()
        .map_err(|e| e.to_string())?;
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .find_map(|l| l.trim().strip_prefix("Total count:"))
        .and_then(|n| n.trim().parse().ok())
        .ok_or_else(|| format!("llvm-profdata show {}: no total count", raw.display()))
}

/// rustup's `llvm-profdata` for the toolchain that builds the tracer (the profile's format
/// must be the compiler's own), installing the `llvm-tools` component when it is missing.
fn llvm_profdata() -> Result<PathBuf, String> {
    let rustc = |args: &[&str]| -> Result<String, String> {
        let out = Command::new("rustc")
            .args(args)
            .output()
            .map_err(|e| e.to_string())?;
        Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
    };
    let sysroot = rustc(&["--print", "sysroot"])?;
    let host = rustc(&["-vV"])?
        .lines()
        .find_map(|l| l.strip_prefix("host: ").map(str::to_string))
        .ok_or("rustc -vV: no host")?;
    let tool = Path::new(&sysroot).join(format!("lib/rustlib/{host}/bin/llvm-profdata"));
    if !tool.exists() {
        let status = Command::new("rustup")
            .args(["component", "add", "llvm-tools"])
            .status()
            .map_err(|e| format!("llvm-profdata is missing and rustup could not run: {e}"))?;
        if !status.success() || !tool.exists() {
            return Err(format!(
                "{} is missing: `rustup component add llvm-tools` installs it",
                tool.display()
            ));
        }
    }
    Ok(tool)
}
