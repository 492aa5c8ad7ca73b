//! `cargo xtask bench [--quick]`: run time against error for every number type on every
//! scene, on the host (criterion) and on the emulated microcontrollers (exact instruction
//! counts), written to `docs/benchmarks.md` with a plot in `docs/benchmarks.svg`.

use crate::host_profile;
use crate::qemu::{self, Options, Row};
use microray::Scalar;
use microray::host::{
    Difference, Framebuffer, HostRenderer, HostScene, antialiased, object_ids, texture_files,
};
use microray::parse::parse_scene;
use microray::render::{Antialias, Renderer, Samples, render};
use microray::scalar::I16F16;
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

const NUMBERS: [&str; 3] = ["f64", "f32", "i16f16"];

/// Scenes rendered in QEMU with and without the render plan: the hundred spheres where row
/// culling pays, and scenes of a few objects where the stages matter more.
const PLAN_SCENES: &str = "many_spheres,spec0,glass,minimal,static,basic";

/// spec0 at 320x240, instructions per pixel of a straightforward generic tracer: the
/// baselines the number-types issue measured.
const BASELINES: [(&str, &str, f64, &str); 4] = [
    ("mps2-an386", "f32", 558.0, "generic tracer, f32"),
    (
        "mps2-an386",
        "fixed",
        4982.0,
        "I16F16 with the fixed crate's saturating ops",
    ),
    (
        "microbit",
        "fixed",
        21859.0,
        "I16F16 with the fixed crate's saturating ops; 7,511 hand-written",
    ),
    ("microbit", "f32", 14740.0, "soft-float f32"),
];

/// The error of one number type on one scene against f64.
struct Error {
    pixels: Difference,
    id_mismatches: usize,
}

pub fn run(args: &[String]) -> Result<(), String> {
    let quick = match args {
        [] => false,
        [flag] if flag == "--quick" => true,
        _ => return Err("usage: cargo xtask bench [--quick]".into()),
    };
    let root = qemu::root()?;
    let conformance = qemu::conformance_dir(&root);
    let scenes = qemu::scene_files(&root, conformance.as_deref());

    // Host run time: criterion, in one run so that ratios compare like with like.
    let conformance_text = conformance
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_default();
    let mut bench_args = vec!["bench", "--bench", "render", "--"];
    if quick {
        bench_args.extend(["--quick", "320x240|noplan|/aa/"]);
    }
    qemu::cargo(
        &bench_args,
        &root,
        &[("MICRORAY_CONFORMANCE", &conformance_text)],
    )?;
    let times = read_medians(&root.join("target/criterion"));

    // Error against f64, at 320x240 (the size timed in both modes).
    let mut errors = BTreeMap::new();
    for (name, path) in &scenes {
        let reference = host_image::<f64>(path)?;
        for number in ["f32", "i16f16"] {
            let other = if number == "f32" {
                host_image::<f32>(path)?
            } else {
                host_image::<I16F16>(path)?
            };
            let pixels = Difference::between(&reference.0, &other.0, |_| false);
            let id_mismatches = reference
                .1
                .iter()
                .zip(&other.1)
                .filter(|(a, b)| a != b)
                .count();
            errors.insert(
                (name.clone(), number),
                Error {
                    pixels,
                    id_mismatches,
                },
            );
        }
    }

    // Microcontrollers: spec0 at 320x240 against the baselines; every scene at 160x120 in
    // the full run.
    let baseline = qemu::measure(
        &root,
        320,
        240,
        &Options {
            only: "spec0".into(),
            ..Options::default()
        },
    )?;
    baseline.check()?;
    let plan = qemu::measure(
        &root,
        160,
        120,
        &Options {
            only: PLAN_SCENES.into(),
            compare_plan: true,
            ..Options::default()
        },
    )?;
    plan.check()?;
    let all = if quick {
        None
    } else {
        let all = qemu::measure(&root, 160, 120, &Options::default())?;
        all.check()?;
        // The Pico in rp2040js, every scene of its table (docs/pico.md).
        crate::pico::run(&[])?;
        Some(all)
    };

    // Anti-aliasing: quality against 64 samples (host, f64, 320x240) and cost in QEMU.
    let course: Vec<(String, PathBuf)> = scenes
        .iter()
        .filter(|(_, path)| {
            conformance
                .as_ref()
                .is_some_and(|dir| path.starts_with(dir))
        })
        .map(|(name, path)| (name.clone(), path.clone()))
        .collect();
    let mut quality = BTreeMap::new();
    for (name, path) in &course {
        quality.insert(name.clone(), aa_quality(path)?);
    }
    let names: Vec<&str> = course.iter().map(|(name, _)| name.as_str()).collect();
    let aa = qemu::measure(
        &root,
        160,
        120,
        &Options {
            only: names.join(","),
            antialias: true,
            ..Options::default()
        },
    )?;
    aa.check()?;

    let mut report = report(
        quick,
        &scenes,
        &times,
        &errors,
        &baseline.rows,
        &plan.rows,
        all.as_ref().map(|m| m.rows.as_slice()),
    );
    aa_report(&mut report, &times, &quality, &aa.rows);
    process_report(&mut report, &root, &scenes, if quick { 5 } else { 21 })?;
    println!("{report}");
    std::fs::create_dir_all(root.join("docs")).map_err(|e| e.to_string())?;
    std::fs::write(root.join("docs/benchmarks.md"), &report).map_err(|e| e.to_string())?;
    plot(&root.join("docs/benchmarks.svg"), &scenes, &times, &errors)?;
    eprintln!("wrote docs/benchmarks.md and docs/benchmarks.svg");
    Ok(())
}

/// The scenes of the std tracer's issue: whole-process times, one thread and all cores.
const PROCESS_SCENES: [&str; 6] = [
    "fplane3",
    "spec0",
    "spec3",
    "shiny3",
    "tplane4",
    "translucent3",
];

/// The course's C++ tracer on the same kind of 2-core machine, CPU seconds of the whole
/// process as the std tracer's issue gives them (the tracer is not in this repository, so
/// they cannot be measured here; spec3 has no figure, spec4's scene is not here).
const COURSE_SECONDS: [(&str, f64); 5] = [
    ("fplane3", 0.062),
    ("spec0", 0.037),
    ("shiny3", 0.065),
    ("tplane4", 0.034),
    ("translucent3", 0.049),
];

/// The commit whose `microray` the std tracer's issue timed beside the course's tracer (the
/// last before the issue's work began). Run alternating with the builds of this run, it
/// carries the issue's pair of figures onto them by ratio, a measure that holds however
/// fast the machine is that day (identical binaries have run up to 40 % apart here).
const ISSUE_COMMIT: &str = "0c1b966c676242123c371a4f1836d88833eb553b";

/// The issue's CPU seconds for `microray` at [`ISSUE_COMMIT`] (one thread, the same runs as
/// [`COURSE_SECONDS`]).
const ISSUE_MICRORAY_SECONDS: [(&str, f64); 5] = [
    ("fplane3", 0.033),
    ("spec0", 0.027),
    ("shiny3", 0.049),
    ("tplane4", 0.031),
    ("translucent3", 0.035),
];

/// `microray` as of [`ISSUE_COMMIT`]: its tree from `git archive` in
/// `target/issue-build/src`, built there with its own lock file (kept between runs).
fn issue_build(root: &Path) -> Result<PathBuf, String> {
    let dir = root.join("target/issue-build");
    let source = dir.join("src");
    let stamp = source.join(".microray-commit");
    if std::fs::read_to_string(&stamp).ok().as_deref() != Some(ISSUE_COMMIT) {
        let _ = std::fs::remove_dir_all(&source);
        std::fs::create_dir_all(&source).map_err(|e| e.to_string())?;
        let archive = Command::new("git")
            .arg("-C")
            .arg(root)
            .args(["archive", "--format=tar", ISSUE_COMMIT])
            .output()
            .map_err(|e| format!("git archive: {e}"))?;
        if !archive.status.success() {
            return Err(format!(
                "git archive {ISSUE_COMMIT} failed (a shallow clone?): {}",
                String::from_utf8_lossy(&archive.stderr).trim()
            ));
        }
        let tar = dir.join("src.tar");
        std::fs::write(&tar, &archive.stdout).map_err(|e| e.to_string())?;
        qemu::checked(
            Command::new("tar")
                .arg("-xf")
                .arg(&tar)
                .arg("-C")
                .arg(&source),
        )?;
        let _ = std::fs::remove_file(&tar);
        std::fs::write(&stamp, ISSUE_COMMIT).map_err(|e| e.to_string())?;
    }
    crate::pgo::build_microray(&source, &dir.join("target"), "")
}

/// The median of `values` (the upper one of an even count; 0 for none).
fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied().unwrap_or(0.0)
}

/// One build's whole-process runs of one scene: one thread's CPU and wall-clock seconds,
/// all cores' wall-clock seconds, and the render stage of each (as `microray` reports it).
#[derive(Clone, Default)]
struct Times {
    one_cpu: Vec<f64>,
    one_wall: Vec<f64>,
    all_wall: Vec<f64>,
    one_stage: Vec<f64>,
    all_stage: Vec<f64>,
    /// One thread's render stage with as many one-thread processes rendering the same
    /// scene beside it as there are other cores: how much slower a core renders when every
    /// core does (what the machine shares: caches, memory, and on a virtual machine the
    /// host's cores), over the same stage alone, run for run.
    crowded: Vec<f64>,
}

/// The render stages of `processes` one-thread runs of `binary` on `scene` started together
/// (each writing its own file next to `out`): each core busy with one.
fn crowded_stages(
    binary: &Path,
    scene: &Path,
    out: &Path,
    processes: usize,
) -> Result<Vec<f64>, String> {
    let children: Vec<_> = (0..processes)
        .map(|k| {
            let mut command = crate::pgo::render_command(
                binary,
                scene,
                &out.with_extension(format!("{k}.ppm")),
                Some("1"),
            );
            command
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::piped());
            command.spawn().map_err(|e| format!("{command:?}: {e}"))
        })
        .collect::<Result<_, _>>()?;
    let mut stages = Vec::with_capacity(processes);
    for (k, child) in children.into_iter().enumerate() {
        let output = child.wait_with_output().map_err(|e| e.to_string())?;
        let _ = std::fs::remove_file(out.with_extension(format!("{k}.ppm")));
        if !output.status.success() {
            return Err(format!("a crowded run of {} failed", scene.display()));
        }
        let report = String::from_utf8_lossy(&output.stderr);
        stages.push(
            stage_seconds(&report)
                .ok_or_else(|| format!("no render time in the report `{}`", report.trim()))?,
        );
    }
    Ok(stages)
}

/// The render stage's seconds in `microray`'s report (`... in 8.05 ms (...)`).
fn stage_seconds(report: &str) -> Option<f64> {
    let rest = report.split(" in ").nth(1)?;
    let mut words = rest.split_whitespace();
    let number: f64 = words.next()?.parse().ok()?;
    match words.next()? {
        "ms" => Some(number * 1e-3),
        "s" => Some(number),
        _ => None,
    }
}

/// [`timed_run`] of `binary render SCENE -o OUT --threads THREADS` without `-q`, and the
/// render stage's seconds that it reports (`... in 8.05 ms (...)`: from the renderer built
/// to the image written, the part of the process that the threads share).
fn timed_render(
    binary: &Path,
    scene: &Path,
    out: &Path,
    threads: &str,
) -> Result<(f64, f64, f64), String> {
    let mut command = crate::pgo::render_command(binary, scene, out, Some(threads));
    command
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped());
    let mut report = String::new();
    let (wall, cpu) = timed_child(&mut command, |child| {
        use std::io::Read;
        if let Some(mut stderr) = child.stderr.take() {
            let _ = stderr.read_to_string(&mut report);
        }
    })?;
    let stage = stage_seconds(&report).ok_or_else(|| {
        format!(
            "{command:?}: no render time in its report `{}`",
            report.trim()
        )
    })?;
    Ok((wall, cpu, stage))
}

/// The wall-clock and CPU seconds (user and system) of one run of `command`, with `during`
/// given the running child (to read its output).
fn timed_child(
    command: &mut Command,
    during: impl FnOnce(&mut std::process::Child),
) -> Result<(f64, f64), String> {
    use nix::sys::resource::{UsageWho, getrusage};
    let cpu = || -> Result<f64, String> {
        let usage = getrusage(UsageWho::RUSAGE_CHILDREN).map_err(|e| e.to_string())?;
        let seconds = |t: nix::sys::time::TimeVal| t.tv_sec() as f64 + t.tv_usec() as f64 * 1e-6;
        Ok(seconds(usage.user_time()) + seconds(usage.system_time()))
    };
    // The children's totals count a child once it has been waited for: the difference is
    // this run's.
    let cpu_before = cpu()?;
    let started = std::time::Instant::now();
    let mut child = command.spawn().map_err(|e| format!("{command:?}: {e}"))?;
    during(&mut child);
    let status = child.wait().map_err(|e| format!("{command:?}: {e}"))?;
    let wall = started.elapsed().as_secs_f64();
    if !status.success() {
        return Err(format!("{command:?} failed ({status})"));
    }
    Ok((wall, cpu()? - cpu_before))
}

/// The wall-clock and CPU seconds (user and system) of one run of `command`.
fn timed_run(command: &mut Command) -> Result<(f64, f64), String> {
    timed_child(command, |_| {})
}

/// What all cores can reach at best, from the release build's runs: the part of a
/// one-thread run outside the render stage stays on one core, so even a render stage split
/// perfectly leaves it whole; and with every core busy each renders slower than one alone.
fn ceiling_report(out: &mut String, times: &BTreeMap<&str, Times>, cores: usize, version: f64) {
    let _ = writeln!(
        out,
        "\nWhat {cores} cores can reach, from the release build's runs above (medians). Outside \
         the render stage: the one-thread run's wall-clock less its render stage (process \
         start and exit, reading the scene, planning), which no thread count splits. A \
         perfect split: that part plus the render stage over {cores}, against the whole \
         one-thread run. Every core busy: each round, {cores} one-thread runs of the scene \
         started together, their render stage over the lone run's of the same round (how \
         much slower a core renders while the others render too: shared caches and memory, \
         and on a virtual machine the host's cores). At that pace: a perfect split whose \
         threads each render that much slower. With only the process's own cost outside \
         the stage: the same, but with `microray --version`'s run ({:.2} ms: the process's \
         start and exit, and clap's parsing) in place of what is outside the stage, as if \
         reading the scene, planning and writing cost nothing.\n\n\
         | scene | one thread (ms) | outside the render stage (ms) | a perfect split | every \
         core busy: a core's render stage over a lone one | a perfect split at that pace | \
         the same, with only the process's own cost outside | measured |\n\
         |---|---|---|---|---|---|---|---|",
        version * 1e3
    );
    let n = cores as f64;
    for name in PROCESS_SCENES {
        let Some(t) = times.get(name) else {
            continue;
        };
        // Run for run (a one-thread run's own stage), then the medians. `whole` over the
        // part outside plus the stage shared by `n` cores, each at `pace`.
        let best = |whole: f64, outside: f64, stage: f64, pace: f64| {
            whole / (outside + stage * pace / n).max(1e-9)
        };
        let runs: Vec<(f64, f64, f64)> = t
            .one_wall
            .iter()
            .zip(&t.one_stage)
            .map(|(&one, &stage)| (one, (one - stage).max(0.0), stage))
            .collect();
        let outside: Vec<f64> = runs.iter().map(|&(_, outside, _)| outside).collect();
        let crowded = median(&t.crowded);
        let split = |pace: f64| -> Vec<f64> {
            runs.iter()
                .map(|&(one, outside, stage)| best(one, outside, stage, pace))
                .collect()
        };
        let bare: Vec<f64> = t
            .one_stage
            .iter()
            .map(|&stage| best(version + stage, version, stage, crowded))
            .collect();
        let (one, all) = (median(&t.one_wall), median(&t.all_wall));
        let _ = writeln!(
            out,
            "| {name} | {:.2} | {:.2} | {:.2}x | {crowded:.3} | {:.2}x | {:.2}x | {:.2}x |",
            one * 1e3,
            median(&outside) * 1e3,
            median(&split(1.0)),
            median(&split(crowded)),
            median(&bare),
            one / all.max(1e-9),
        );
    }
}

/// The builds' one-thread CPU times against the issue's build's, run for run (both in the
/// same round, so the pair saw the same machine), and the issue's figures carried by the
/// median of those ratios: this build's time as a multiple of the course's tracer's.
fn issue_report(
    out: &mut String,
    builds: &[(&str, PathBuf)],
    times: &[BTreeMap<&str, Times>],
    issue_cpu: &BTreeMap<&str, Vec<f64>>,
) {
    let _ = writeln!(
        out,
        "\nAgainst the build the issue timed ({}, its last commit before the issue's work), \
         run alternating with the builds above, one thread, CPU seconds. Ratio: the median, \
         over the runs, of a build's time over that build's in the same round. Carried onto \
         the issue's pair of figures (the course's tracer, microray then), the ratio gives a \
         build's time as a multiple of the course's tracer's, whatever the machine's speed \
         that day. The issue asks for 3x: a ratio at or below the last column.\n",
        &ISSUE_COMMIT[..7],
    );
    let mut header =
        "| scene | course's tracer (s) | microray then (s) | that build now (s) |".to_string();
    let mut rule = "|---|---|---|---|".to_string();
    for (title, _) in builds {
        let short = title
            .split(" (")
            .next()
            .unwrap_or(title)
            .trim_start_matches("The ");
        let _ = write!(header, " {short}: now (s) | ratio | against the course's |");
        rule.push_str("---|---|---|");
    }
    let _ = writeln!(out, "{header} ratio for 3x |\n{rule}---|");
    for name in PROCESS_SCENES {
        let figure = |table: &[(&str, f64)]| table.iter().find(|(n, _)| *n == name).map(|f| f.1);
        let (Some(course), Some(then), Some(old)) = (
            figure(&COURSE_SECONDS),
            figure(&ISSUE_MICRORAY_SECONDS),
            issue_cpu.get(name),
        ) else {
            continue;
        };
        let mut row = format!("| {name} | {course:.3} | {then:.3} | {:.4} |", median(old));
        for table in times {
            let Some(Times { one_cpu: cpu, .. }) = table.get(name) else {
                row.push_str(" — | — | — |");
                continue;
            };
            let pairs: Vec<f64> = cpu
                .iter()
                .zip(old)
                .map(|(new, old)| new / old.max(1e-9))
                .collect();
            let ratio = median(&pairs);
            let _ = write!(
                row,
                " {:.4} | {ratio:.3} | {:.2}x |",
                median(cpu),
                course / (then * ratio).max(1e-9)
            );
        }
        let _ = writeln!(out, "{row} {:.3} |", course / (3.0 * then));
    }
}

/// Whole-process medians of `microray render SCENE -o OUT.ppm` (f64), with one thread and
/// with every core, `runs` runs each, alternating, for the release build and, where
/// `llvm-tools` can be had, the profile-guided one (`cargo xtask pgo`): CPU seconds (the
/// issue's measure) and wall-clock seconds with one thread, wall-clock with all cores.
fn process_report(
    out: &mut String,
    root: &Path,
    scenes: &BTreeMap<String, PathBuf>,
    runs: usize,
) -> Result<(), String> {
    let binary = process_tables(out, root, scenes, runs)?;
    // Where the time goes, per function: this build, and the one before the std tracer's
    // batching (docs/host-profile-before.md, written by `cargo xtask host-profile`).
    match host_profile::report(root, &binary, "this build", runs) {
        Ok(now) => {
            let _ = write!(out, "\n{now}");
        }
        // Not every machine lets a user sample (perf missing, perf_event_paranoid).
        Err(e) => {
            let _ = writeln!(out, "\n(No per-function profile of this build: {e}.)");
        }
    }
    if let Ok(before) = std::fs::read_to_string(root.join("docs/host-profile-before.md")) {
        let _ = write!(out, "\n{before}");
    }
    // The steps between the two, measured as they were made.
    if let Ok(log) = std::fs::read_to_string(root.join("docs/host-speed-log.md")) {
        let _ = write!(out, "\n{log}");
    }
    Ok(())
}

/// `cargo xtask host-bench [--runs N]`: the whole-process tables of `cargo xtask bench`
/// alone (the release and profile-guided builds, one thread and all cores, and both against
/// the issue's build), printed, not written to `docs/`: a few minutes instead of the full
/// bench's twenty.
pub fn host_run(args: &[String]) -> Result<(), String> {
    let runs = match args {
        [] => 21,
        [flag, n] if flag == "--runs" => n
            .parse::<usize>()
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| format!("--runs takes a count above 0, not `{n}`"))?,
        _ => return Err("usage: cargo xtask host-bench [--runs N]".into()),
    };
    let root = qemu::root()?;
    let conformance = qemu::conformance_dir(&root);
    let scenes = qemu::scene_files(&root, conformance.as_deref());
    let mut out = String::new();
    process_tables(&mut out, &root, &scenes, runs)?;
    println!("{out}");
    Ok(())
}

/// The timing tables of [`process_report`]; returns the release build's binary.
fn process_tables(
    out: &mut String,
    root: &Path,
    scenes: &BTreeMap<String, PathBuf>,
    runs: usize,
) -> Result<PathBuf, String> {
    let mut builds = vec![(
        "The release build (`cargo build --release`)",
        root.join("target/release/microray"),
    )];
    let pgo_note = match crate::pgo::build(root) {
        Ok(binary) => {
            builds.push((
                "The profile-guided build (`cargo xtask pgo`: the same code, laid out by counts \
                 from the course's scenes; every image identical, checked)",
                binary,
            ));
            None
        }
        Err(e) => Some(e),
    };
    qemu::cargo(&["build", "--release", "--bin", "microray"], root, &[])?;
    let issue = issue_build(root);
    let output = std::env::temp_dir().join(format!("microray-bench-{}.ppm", std::process::id()));
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let _ = writeln!(
        out,
        "\n## Host: the whole process\n\n\
         `microray render SCENE -o OUT.ppm` in f64, medians of {runs} runs each (process \
         start, parsing, rendering and writing the PPM), with `--threads 1` and with all \
         {cores} cores (the default), every build and thread count alternating. One thread: \
         CPU seconds (user and system, the issue's measure) and wall-clock; all cores: \
         wall-clock, the speed-up over one thread's wall-clock, and the course's tracer's \
         time over it. The course's tracer: the issue's CPU seconds for it on the same kind \
         of machine (it is not in this repository). The render stage: the part of each run \
         that the threads share, from the renderer built to the image written, as \
         `microray` reports it (the builds run without `-q` for it); the process's start, \
         reading the scene and planning come before it, on one core whatever the threads."
    );
    if let Some(e) = pgo_note {
        let _ = writeln!(out, "\n(No profile-guided build in this run: {e}.)");
    }
    let thread_counts = ["1".to_string(), cores.to_string()];
    let mut times = vec![BTreeMap::<&str, Times>::new(); builds.len()];
    // The issue's build, one thread (it has no `--threads`: it had one thread only).
    let mut issue_cpu = BTreeMap::<&str, Vec<f64>>::new();
    // The process with nothing to render: start, clap's parsing, exit.
    let mut version_wall = Vec::with_capacity(runs);
    for _ in 0..runs {
        // Only the ceiling of all cores uses it.
        if cores > 1 {
            let (wall, _) = timed_run(
                Command::new(&builds[0].1)
                    .arg("--version")
                    .stdout(std::process::Stdio::null()),
            )?;
            version_wall.push(wall);
        }
        for name in PROCESS_SCENES {
            let Some(path) = scenes.get(name) else {
                continue;
            };
            if let Ok(binary) = &issue {
                let command = &mut crate::pgo::render_command(binary, path, &output, None);
                command.arg("-q");
                let (_, cpu) = timed_run(command)?;
                issue_cpu.entry(name).or_default().push(cpu);
            }
            for (build, (_, binary)) in builds.iter().enumerate() {
                for threads in &thread_counts {
                    let (wall, cpu, stage) = timed_render(binary, path, &output, threads)?;
                    let entry = times[build].entry(name).or_default();
                    if threads == "1" {
                        entry.one_cpu.push(cpu);
                        entry.one_wall.push(wall);
                        entry.one_stage.push(stage);
                    } else {
                        entry.all_wall.push(wall);
                        entry.all_stage.push(stage);
                    }
                }
                // How much slower one thread renders with every core busy, for the release
                // build: a process on each core, set beside this round's lone run.
                if build == 0 && cores > 1 {
                    let crowded = crowded_stages(binary, path, &output, cores)?;
                    let entry = times[build].entry(name).or_default();
                    if let Some(&alone) = entry.one_stage.last() {
                        let mean = crowded.iter().sum::<f64>() / crowded.len() as f64;
                        entry.crowded.push(mean / alone.max(1e-9));
                    }
                }
            }
        }
    }
    for ((title, _), table) in builds.iter().zip(&times) {
        let _ = writeln!(
            out,
            "\n{title}:\n\n\
             | scene | course's tracer (s) | one thread, CPU (s) | against the course's | \
             one thread, wall (s) | all cores, wall (s) | speed-up | all cores against the \
             course's | render stage, one thread (ms) | all cores (ms) | speed-up |\n\
             |---|---|---|---|---|---|---|---|---|---|---|"
        );
        for name in PROCESS_SCENES {
            let Some(t) = table.get(name) else {
                continue;
            };
            let (cpu, one, all) = (median(&t.one_cpu), median(&t.one_wall), median(&t.all_wall));
            let (one_stage, all_stage) = (median(&t.one_stage), median(&t.all_stage));
            let course = COURSE_SECONDS
                .iter()
                .find(|(n, _)| *n == name)
                .map(|&(_, s)| s);
            let times_faster = |c: f64, t: f64| format!("{:.2}x", c / t.max(1e-9));
            let (course_cell, ratio_cell, all_cell) = match course {
                Some(c) => (
                    format!("{c:.3}"),
                    times_faster(c, cpu),
                    times_faster(c, all),
                ),
                None => ("—".to_string(), "—".to_string(), "—".to_string()),
            };
            let _ = writeln!(
                out,
                "| {name} | {course_cell} | {cpu:.4} | {ratio_cell} | {one:.4} | {all:.4} | {} | \
                 {all_cell} | {:.2} | {:.2} | {} |",
                times_faster(one, all),
                one_stage * 1e3,
                all_stage * 1e3,
                times_faster(one_stage, all_stage),
            );
        }
    }
    if let Some(release) = times.first().filter(|_| cores > 1) {
        ceiling_report(out, release, cores, median(&version_wall));
    }
    match &issue {
        Ok(_) => issue_report(out, &builds, &times, &issue_cpu),
        Err(e) => {
            let _ = writeln!(out, "\n(No run of the issue's build: {e}.)");
        }
    }
    let _ = std::fs::remove_file(&output);
    Ok(builds.swap_remove(0).1)
}

/// The anti-aliasing modes of the host table, by benchmark name (`1`: the plain render; the
/// others the firmware's, as `benches/render.rs` names them).
fn aa_modes() -> Vec<(&'static str, Antialias)> {
    let mut modes = vec![("1", Antialias::Grid(Samples::ONE))];
    modes.extend(Antialias::MEASURED);
    modes
}

/// PSNR (dB) of each mode of [`aa_modes`] against 64 samples a pixel, f64 at 320x240.
fn aa_quality(path: &Path) -> Result<Vec<f64>, String> {
    let text = std::fs::read(path).map_err(|e| e.to_string())?;
    let mut scene: HostScene<'static, f64> = parse_scene(
        &text,
        texture_files(path.parent().unwrap_or(Path::new("."))),
    )
    .map_err(|e| format!("{}: {e}", path.display()))?;
    scene.set_resolution(320, 240).map_err(|e| e.to_string())?;
    let renderer: HostRenderer<'_, f64> = Renderer::new(&scene);
    let image = |aa| antialiased(&renderer, aa).map_err(|e| e.to_string());
    let reference = image(Antialias::Grid(
        Samples::rotated(64).unwrap_or(Samples::ONE),
    ))?;
    aa_modes()
        .iter()
        .map(|&(_, aa)| {
            Ok(Difference::between(reference.rgb(), image(aa)?.rgb(), |_| false).psnr())
        })
        .collect()
}

/// Anti-aliasing: host time and quality per course scene, and the QEMU table.
fn aa_report(
    out: &mut String,
    times: &BTreeMap<(String, String, String), f64>,
    quality: &BTreeMap<String, Vec<f64>>,
    qemu_rows: &[Row],
) {
    let _ = writeln!(
        out,
        "\n## Anti-aliasing\n\n\
         `microray render --aa N` and `--aa adaptive` (`render::Antialias`): fixed sample \
         positions on a rotated grid, so every frame is the same on every run and machine. \
         Host: milliseconds a frame of the course's scenes at 320x240 in f64 (criterion \
         medians of one run), the multiple of the plain frame's (`--aa 1`), and the PSNR \
         against a 64-sample render of the same scene (`tests/antialias.rs` checks that each \
         mode comes closer than one sample). Adaptive: 16 samples on the pixels whose plain \
         colour differs from a neighbour's by more than 8 levels in a channel, or that see \
         another object.\n"
    );
    let modes = aa_modes();
    let header: Vec<&str> = modes.iter().map(|(name, _)| *name).collect();
    let _ = writeln!(
        out,
        "| scene | {} |\n|---|{}",
        header.join(" | "),
        "---|".repeat(header.len())
    );
    for (name, psnr) in quality {
        let plain = ms(times, name, "f64", "320x240");
        let cells: Vec<String> = modes
            .iter()
            .zip(psnr)
            .map(|(&(mode, _), db)| {
                let t = if mode == "1" {
                    plain
                } else {
                    ms(times, name, "aa", mode)
                };
                match (t, plain) {
                    (Some(t), Some(p)) if p > 0.0 => {
                        format!("{t:.2} ms ({:.2}x), {db:.1} dB", t / p)
                    }
                    _ => format!("—, {db:.1} dB"),
                }
            })
            .collect();
        let _ = writeln!(out, "| {name} | {} |", cells.join(" | "));
    }
    let _ = writeln!(out, "\n{}", qemu::antialias_table(qemu_rows, 160, 120));
}

/// The host's render of a scene at 320x240 in `S`, and the object each pixel sees.
fn host_image<S: Scalar>(path: &Path) -> Result<(Vec<u8>, Vec<Option<usize>>), String> {
    let text = std::fs::read(path).map_err(|e| e.to_string())?;
    let mut scene: HostScene<'static, S> = parse_scene(
        &text,
        texture_files(path.parent().unwrap_or(Path::new("."))),
    )
    .map_err(|e| format!("{}: {e}", path.display()))?;
    scene.set_resolution(320, 240).map_err(|e| e.to_string())?;
    let mut image = Framebuffer::new(embedded_graphics::prelude::Size::new(320, 240));
    render(&scene, &mut image).map_err(|e| e.to_string())?;
    Ok((image.rgb().to_vec(), object_ids(&Renderer::new(&scene))))
}

/// Criterion's median (ns) of every benchmark, by `(scene, number, size)`.
fn read_medians(dir: &Path) -> BTreeMap<(String, String, String), f64> {
    let mut medians = BTreeMap::new();
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        // Directory names are the ids with `/` as `_`: SCENE_NUMBER_SIZE (scene names may
        // hold `_` too, so split from the right).
        let mut parts = name.rsplitn(3, '_');
        let (Some(size), Some(number), Some(scene)) = (parts.next(), parts.next(), parts.next())
        else {
            continue;
        };
        let file = entry.path().join("new/estimates.json");
        let Ok(text) = std::fs::read_to_string(&file) else {
            continue;
        };
        let Ok(json) = serde_json::from_str::<serde_json::Value>(&text) else {
            continue;
        };
        if let Some(ns) = json
            .pointer("/median/point_estimate")
            .and_then(serde_json::Value::as_f64)
        {
            medians.insert(
                (scene.to_string(), number.to_string(), size.to_string()),
                ns,
            );
        }
    }
    medians
}

fn command_line(program: &str, args: &[&str]) -> String {
    Command::new(program)
        .args(args)
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default()
}

fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!(
        "{cpu}, {cores} cores; {}; {}",
        command_line("rustc", &["--version"]),
        command_line("qemu-system-arm", &["--version"])
            .lines()
            .next()
            .unwrap_or("")
    )
}

fn ms(
    times: &BTreeMap<(String, String, String), f64>,
    scene: &str,
    number: &str,
    size: &str,
) -> Option<f64> {
    times
        .get(&(scene.to_string(), number.to_string(), size.to_string()))
        .map(|ns| ns / 1e6)
}

fn count(rows: Option<&[Row]>, scene: &str, machine: &str, number: &str, pixels: f64) -> String {
    let fixed = if number == "i16f16" { "fixed" } else { number };
    rows.and_then(|rows| {
        rows.iter()
            .find(|r| r.scene == scene && r.machine == machine && r.number == fixed)
    })
    .map_or("—".into(), |r| format!("{:.0}", r.insns as f64 / pixels))
}

fn report(
    quick: bool,
    scenes: &BTreeMap<String, PathBuf>,
    times: &BTreeMap<(String, String, String), f64>,
    errors: &BTreeMap<(String, &str), Error>,
    baseline: &[Row],
    plan: &[Row],
    all: Option<&[Row]>,
) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# Run time against error\n\n\
         Written by `cargo xtask bench{}` on {} on {}.\n\n\
         Host times are criterion's medians{}, all from one run, so the ratios between number \
         types compare like with like. Errors are against the f64 std tracer at 320x240: pixels \
         identical, pixels within ±1 in every channel, the largest channel difference, PSNR, and \
         pixels that see a different object. Microcontroller costs are exact instruction counts \
         in QEMU 7.2 (`cargo xtask qemu`); VDIV and VSQRT take 14 cycles each on the M4F although \
         they count as one instruction. The plot, [benchmarks.svg](benchmarks.svg), shows each \
         scene's host run time against its error.\n",
        if quick { " --quick" } else { "" },
        command_line("date", &["-u", "+%Y-%m-%d"]),
        machine(),
        if quick {
            " (criterion's quick mode: fewer samples)"
        } else {
            " (10 samples each)"
        },
    );
    let _ = writeln!(
        out,
        "## Microcontrollers: spec0 at 320x240 against the baselines\n"
    );
    let _ = writeln!(
        out,
        "| machine | number | instructions/pixel | baseline | ratio to the baseline | VDIV/pixel | VSQRT/pixel |\n|---|---|---|---|---|---|---|"
    );
    let pixels = 320.0 * 240.0;
    for (machine, number, base, what) in BASELINES {
        if let Some(r) = baseline
            .iter()
            .find(|r| r.machine == machine && r.number == number && r.scene == "spec0")
        {
            let per_pixel = r.insns as f64 / pixels;
            let _ = writeln!(
                out,
                "| {machine} | {} | {per_pixel:.0} | {base:.0} ({what}) | {:.2} | {:.2} | {:.2} |",
                if number == "fixed" { "i16f16" } else { number },
                per_pixel / base,
                r.vdiv as f64 / pixels,
                r.vsqrt as f64 / pixels
            );
        }
    }
    plan_report(&mut out, scenes, times, plan);
    let _ = writeln!(
        out,
        "\n## Every scene and number type\n\n\
         Host: milliseconds a frame at 320x240 and at the scene's own size (`native`), and the \
         ratio to f64 at 320x240. Microcontrollers: instructions per pixel at 160x120 (the full \
         run only).\n"
    );
    let _ = writeln!(
        out,
        "| scene | number | ms 320x240 | ratio to f64 | ms native | identical % | within ±1 % | max diff | PSNR dB | other object px | M4F instr/px | M0 instr/px |\n|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let small = 160.0 * 120.0;
    for name in scenes.keys() {
        let base = ms(times, name, "f64", "320x240");
        for number in NUMBERS {
            let t = ms(times, name, number, "320x240");
            let ratio = match (t, base) {
                (Some(t), Some(b)) if b > 0.0 => format!("{:.2}", t / b),
                _ => "—".into(),
            };
            let native =
                ms(times, name, number, "native").map_or("—".into(), |v| format!("{v:.2}"));
            let (identical, within, max, psnr, ids) = match errors.get(&(name.clone(), number)) {
                Some(e) => (
                    format!("{:.3}", e.pixels.identical_percent()),
                    format!("{:.3}", e.pixels.within_one_percent()),
                    e.pixels.largest.to_string(),
                    format!("{:.1}", e.pixels.psnr()),
                    e.id_mismatches.to_string(),
                ),
                None => (
                    "reference".into(),
                    String::new(),
                    String::new(),
                    String::new(),
                    String::new(),
                ),
            };
            let _ = writeln!(
                out,
                "| {name} | {number} | {} | {ratio} | {native} | {identical} | {within} | {max} | {psnr} | {ids} | {} | {} |",
                t.map_or("—".into(), |v| format!("{v:.2}")),
                if number == "f64" {
                    "—".into()
                } else {
                    count(all, name, "mps2-an386", number, small)
                },
                if number == "f64" {
                    "—".into()
                } else {
                    count(all, name, "microbit", number, small)
                },
            );
        }
    }
    out
}

/// The render plan's gain: host medians with and without it at 320x240 (one run), and exact
/// instruction counts in QEMU at 160x120.
fn plan_report(
    out: &mut String,
    scenes: &BTreeMap<String, PathBuf>,
    times: &BTreeMap<(String, String, String), f64>,
    rows: &[Row],
) {
    let _ = writeln!(
        out,
        "\n## The render plan\n\n\
         What skipping what a scene does not need gains (`microray render --no-plan` renders \
         without it; the images are identical, which `tests/plan.rs` checks for every scene and \
         number type, and QEMU checks for every frame below). Microcontrollers: instructions per \
         pixel at 160x120 with the plan and without, and the ratio; many_spheres does not fit \
         the micro:bit's RAM.\n"
    );
    let _ = writeln!(
        out,
        "| scene | machine | number | instr/px with plan | without | speed-up |\n|---|---|---|---|---|---|"
    );
    for r in rows.iter().filter(|r| !r.scene.ends_with("+noplan")) {
        let Some(without) = rows.iter().find(|o| {
            o.machine == r.machine
                && o.number == r.number
                && o.scene == format!("{}+noplan", r.scene)
        }) else {
            continue;
        };
        let pixels = 160.0 * 120.0;
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.0} | {:.0} | {:.2} |",
            r.scene,
            r.machine,
            r.number_name(),
            r.insns as f64 / pixels,
            without.insns as f64 / pixels,
            without.insns as f64 / r.insns.max(1) as f64
        );
    }
    let _ = writeln!(
        out,
        "\nHost: milliseconds a frame at 320x240 with the plan and without, and the speed-up \
         (criterion medians of one run).\n\n\
         | scene | f64 | f64 without | f64 speed-up | f32 | f32 without | f32 speed-up | i16f16 | i16f16 without | i16f16 speed-up |\n\
         |---|---|---|---|---|---|---|---|---|---|"
    );
    for name in scenes.keys() {
        let mut line = format!("| {name} |");
        for number in NUMBERS {
            let with = ms(times, name, number, "320x240");
            let without = ms(times, name, number, "noplan");
            let cell = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.2}"));
            let ratio = match (with, without) {
                (Some(a), Some(b)) if a > 0.0 => format!("{:.2}", b / a),
                _ => "—".into(),
            };
            let _ = write!(line, " {} | {} | {ratio} |", cell(with), cell(without));
        }
        let _ = writeln!(out, "{line}");
    }
}

/// Host time at 320x240 against the share of pixels that differ from f64, per scene.
fn plot(
    file: &Path,
    scenes: &BTreeMap<String, PathBuf>,
    times: &BTreeMap<(String, String, String), f64>,
    errors: &BTreeMap<(String, &str), Error>,
) -> Result<(), String> {
    let floor = 1e-3;
    let mut points: BTreeMap<&str, Vec<(f64, f64)>> = BTreeMap::new();
    for name in scenes.keys() {
        for number in NUMBERS {
            let Some(t) = ms(times, name, number, "320x240") else {
                continue;
            };
            let error = errors
                .get(&(name.clone(), number))
                .map_or(floor, |e| (100.0 - e.pixels.identical_percent()).max(floor));
            points.entry(number).or_default().push((error, t));
        }
    }
    let max_t = points.values().flatten().map(|p| p.1).fold(1.0, f64::max) * 1.5;
    let min_t = points.values().flatten().map(|p| p.1).fold(max_t, f64::min) / 1.5;
    let root = SVGBackend::new(file, (900, 560)).into_drawing_area();
    let e = |e: DrawingAreaErrorKind<std::io::Error>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Host run time against error, per scene (320x240)",
            ("sans-serif", 22),
        )
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(70)
        .build_cartesian_2d((floor * 0.7..100.0).log_scale(), (min_t..max_t).log_scale())
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("pixels not identical to f64, % (f64 itself drawn at 0.001)")
        .y_desc("milliseconds a frame")
        .draw()
        .map_err(e)?;
    let colors = [("f64", BLACK), ("f32", BLUE), ("i16f16", RED)];
    for (number, color) in colors {
        let Some(series) = points.get(number) else {
            continue;
        };
        chart
            .draw_series(
                series
                    .iter()
                    .map(|&(x, y)| Circle::new((x, y), 5, color.filled())),
            )
            .map_err(e)?
            .label(number)
            .legend(move |(x, y)| Circle::new((x, y), 5, color.filled()));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}
