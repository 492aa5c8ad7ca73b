//! `cargo xtask host-profile`: where the std tracer's time goes, per function.
//!
//! Runs `microray render SCENE -o OUT.ppm --threads 1` (f64) under `perf record` (cpu-clock
//! sampling: virtual machines rarely expose hardware counters) a number of times per scene
//! and prints, per scene, the functions with the largest share of the samples (self time,
//! the whole process: start, parsing, rendering and writing). With `--binary` it profiles
//! another build (an older commit's, for a before/after comparison); with `--out` it writes
//! the tables to a file as well.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::qemu;

/// The scenes the std tracer's issue asks a profile of.
const SCENES: [&str; 2] = ["spec0", "tplane4"];

/// Functions listed per scene.
const TOP: usize = 12;

pub fn run(args: &[String]) -> Result<(), String> {
    let mut binary = None;
    let mut out = None;
    let mut title = String::from("this build");
    let mut runs = 20usize;
    let mut rest = args.iter();
    while let Some(flag) = rest.next() {
        let mut value = || {
            rest.next()
                .cloned()
                .ok_or_else(|| format!("{flag} needs a value"))
        };
        match flag.as_str() {
            "--binary" => binary = Some(PathBuf::from(value()?)),
            "--out" => out = Some(PathBuf::from(value()?)),
            "--title" => title = value()?,
            "--runs" => runs = value()?.parse().map_err(|_| "--runs takes a count")?,
            _ => {
                return Err(
                    "usage: cargo xtask host-profile [--binary PATH] [--out FILE] \
                            [--title TEXT] [--runs N]"
                        .into(),
                );
            }
        }
    }
    let root = qemu::root()?;
    let binary = match binary {
        Some(binary) => binary,
        None => {
            qemu::cargo(&["build", "--release", "--bin", "microray"], &root, &[])?;
            root.join("target/release/microray")
        }
    };
    let report = report(&root, &binary, &title, runs)?;
    print!("{report}");
    if let Some(out) = out {
        std::fs::write(&out, &report).map_err(|e| format!("{}: {e}", out.display()))?;
    }
    Ok(())
}

/// The profile tables of [`SCENES`] for `binary`, headed `title`.
pub fn report(root: &Path, binary: &Path, title: &str, runs: usize) -> Result<String, String> {
    let conformance = qemu::conformance_dir(root);
    let scenes = qemu::scene_files(root, conformance.as_deref());
    let mut report = String::new();
    let _ = writeln!(
        report,
        "### Per function: {title}\n\n\
         `perf record -F 20000` (cpu-clock) over {runs} runs of `microray render SCENE -o \
         OUT.ppm --threads 1` (f64); self time as a share of the process's samples, and that \
         share of the median wall-clock time of as many runs without the profiler.\n"
    );
    for name in SCENES {
        let Some(path) = scenes.get(name) else {
            continue;
        };
        let (shares, ms) = profile(binary, path, runs)?;
        let _ = writeln!(report, "| {name}: function | share | ms |\n|---|---|---|");
        for (function, share) in shares.iter().take(TOP) {
            let _ = writeln!(
                report,
                "| `{function}` | {share:.1} % | {:.2} |",
                share / 100.0 * ms
            );
        }
        let rest: f64 = shares.iter().skip(TOP).map(|(_, s)| s).sum();
        let _ = writeln!(
            report,
            "| (everything else) | {rest:.1} % | {:.2} |\n| **the process** | | **{ms:.2}** |\n",
            rest / 100.0 * ms
        );
    }
    Ok(report)
}

/// Self-time shares by function, largest first, and the median wall-clock time of a run
/// without the profiler, in milliseconds (sampling 20,000 times a second slows the process
/// by a third on this kind of machine, so its own count would overstate every function).
fn profile(binary: &Path, scene: &Path, runs: usize) -> Result<(Vec<(String, f64)>, f64), String> {
    let dir = std::env::temp_dir().join(format!("microray-host-profile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let data = dir.join("perf.data");
    let image = dir.join("out.ppm");
    let script = format!(
        "for i in $(seq {runs}); do '{}' render '{}' -o '{}' -q --threads 1 || exit 1; done",
        binary.display(),
        scene.display(),
        image.display()
    );
    let status = Command::new("perf")
        .args(["record", "-q", "-F", "20000", "-e", "cpu-clock", "-o"])
        .arg(&data)
        .args(["--", "sh", "-c", &script])
        .status()
        .map_err(|e| format!("perf: {e} (install linux-perf)"))?;
    if !status.success() {
        return Err("perf record failed".into());
    }
    // The kernel names a process by its file's first 15 bytes.
    let comm: String = binary
        .file_name()
        .map(|n| n.to_string_lossy().chars().take(15).collect())
        .unwrap_or_default();
    let report = Command::new("perf")
        .args(["report", "--stdio", "--no-children", "--comm", &comm])
        .args(["--sort", "sym", "--percent-limit", "0", "-i"])
        .arg(&data)
        .output()
        .map_err(|e| e.to_string())?;
    let _ = std::fs::remove_file(&data);
    if !report.status.success() {
        return Err("perf report failed".into());
    }
    let text = String::from_utf8_lossy(&report.stdout);
    let mut shares: BTreeMap<String, f64> = BTreeMap::new();
    for line in text.lines() {
        // "    42.77%  [.] microray::shade::Shader<S>::local"
        let Some((share, rest)) = line.trim().split_once('%') else {
            continue;
        };
        let Ok(share) = share.trim().parse::<f64>() else {
            continue;
        };
        let function = rest
            .trim()
            .trim_start_matches("[.]")
            .trim_start_matches("[k]");
        let function = if rest.contains("[k]") {
            "(kernel: process start, page faults, writing)".to_string()
        } else {
            function.trim().to_string()
        };
        *shares.entry(function).or_default() += share;
    }
    let mut shares: Vec<(String, f64)> = shares.into_iter().collect();
    shares.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut times = Vec::new();
    for _ in 0..runs {
        let started = std::time::Instant::now();
        let status = Command::new(binary)
            .arg("render")
            .arg(scene)
            .arg("-o")
            .arg(&image)
            .args(["-q", "--threads", "1"])
            .status()
            .map_err(|e| e.to_string())?;
        if !status.success() {
            return Err(format!("microray render {} failed", scene.display()));
        }
        times.push(started.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    let _ = std::fs::remove_dir_all(&dir);
    Ok((shares, times.get(times.len() / 2).copied().unwrap_or(0.0)))
}
