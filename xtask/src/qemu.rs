//! `cargo xtask qemu`: the firmware on emulated microcontrollers against the host.

use crate::profile;
use microray::Scalar;
use microray::host::{Framebuffer, HostScene, texture_files};
use microray::parse::parse_scene;
use microray::render::{Antialias, render};
use microray::scalar::I16F16;
use object::{Object, ObjectSection, ObjectSymbol};
use std::collections::BTreeMap;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[path = "../../firmware/src/static_scene.rs"]
mod static_scene;

#[path = "../../firmware/src/aa_modes.rs"]
mod aa_modes;
#[path = "../../firmware/src/basic_scene.rs"]
mod basic_scene;
pub(crate) use aa_modes::MODES as AA_MODES;

/// Options of `cargo xtask qemu`.
#[derive(Default)]
pub(crate) struct Options {
    /// Only these scenes (comma-separated); all when empty.
    pub(crate) only: String,
    /// Count instructions by function and stage as well, and write the report to
    /// `docs/profile-LABEL.md` (`--profile LABEL`).
    pub(crate) profile: Option<String>,
    /// Only the builds whose name starts with this (`mps2-an386-f32`, `microbit`, ...).
    pub(crate) build: Option<String>,
    /// Render each scene twice, with the render plan and without (`SCENE+noplan`).
    pub(crate) compare_plan: bool,
    /// Render each scene plainly and in the progressive order, counting the first pass
    /// (`SCENE+preview`) and the rest (`SCENE+progressive`) apart; the M4F board only.
    pub(crate) progressive: bool,
    /// Render each scene plainly and through `microray::dither::Rgb565Dither` into an
    /// Rgb565 target (`SCENE+dither`), to count what the dither costs.
    pub(crate) dither: bool,
    /// Render each scene plainly and anti-aliased with 4, 9 and 16 samples a pixel and
    /// adaptively (`SCENE+aa4`, `+aa9`, `+aa16`, `+adaptive`); the M4F board only.
    pub(crate) antialias: bool,
    /// Play each film (`scenes/` with an `animation`): every frame after the first in its
    /// region (`SCENE+iK`) and whole (`SCENE+fK`), both compared with the host's full frame.
    pub(crate) animations: bool,
    /// With `animations`: only each film's first frames (`MICRORAY_FW_FRAMES`).
    pub(crate) frames: Option<u16>,
    /// The minimal firmware: no optional microray feature, the `basic` scene only.
    pub(crate) minimal: bool,
    /// The optimisation level of the firmware build (`CARGO_PROFILE_RELEASE_OPT_LEVEL`),
    /// else the firmware's profile's.
    pub(crate) opt_level: Option<String>,
    /// The full build without the course's later kinds (the firmware's `full` alone): what
    /// the footprint tables measure.
    pub(crate) without_extensions: bool,
}

/// What a firmware build embeds and enables.
struct Variant<'a> {
    /// Scenes to embed (`MICRORAY_FW_ONLY`: comma-separated, `none`, or all when empty).
    only: &'a str,
    /// `compare` renders each scene with and without the render plan.
    plan: &'a str,
    /// Every microray feature (else the minimal build).
    full: bool,
    /// With `full`: the course's later kinds too (the firmware's `extensions`, a default
    /// feature); the footprint tables build `full` alone, the first assignments' language.
    extensions: bool,
    /// The firmware's `release-small` profile (opt-level z) instead of `release`.
    small: bool,
    /// The optimisation level (`""`: the firmware's profile's).
    opt_level: &'a str,
}

/// One firmware build: a machine and a number type.
pub(crate) struct Build {
    pub(crate) machine: &'static str,
    cpu: &'static str,
    target: &'static str,
    feature: &'static str,
    pub(crate) number: &'static str,
}

const BUILDS: [Build; 4] = [
    Build {
        machine: "mps2-an386",
        cpu: "cortex-m4",
        target: "thumbv7em-none-eabihf",
        feature: "mps2",
        number: "f32",
    },
    Build {
        machine: "mps2-an386",
        cpu: "cortex-m4",
        target: "thumbv7em-none-eabihf",
        feature: "mps2",
        number: "fixed",
    },
    Build {
        machine: "microbit",
        cpu: "cortex-m0",
        target: "thumbv6m-none-eabi",
        feature: "microbit",
        number: "fixed",
    },
    Build {
        machine: "microbit",
        cpu: "cortex-m0",
        target: "thumbv6m-none-eabi",
        feature: "microbit",
        number: "f32",
    },
];

/// What one frame cost and whether it matched.
pub(crate) struct Row {
    pub(crate) scene: String,
    pub(crate) machine: &'static str,
    pub(crate) number: &'static str,
    pub(crate) identical: Result<bool, String>,
    pub(crate) insns: u64,
    pub(crate) vdiv: u64,
    pub(crate) vsqrt: u64,
    pub(crate) stack: u64,
    /// The stack the renderer itself used (its frames below the harness's), if reported.
    pub(crate) renderer_stack: u64,
    /// Flash and static RAM of the build that rendered it.
    pub(crate) size: Size,
    /// For a film's frame rendered in its region, the region's pixels.
    pub(crate) region: Option<u64>,
}

impl Row {
    /// The number type as the host tracer names it (`i16f16` for the `fixed` builds).
    pub(crate) fn number_name(&self) -> &'static str {
        if self.number == "fixed" {
            "i16f16"
        } else {
            self.number
        }
    }
}

/// Flash and static RAM of a build, from its ELF sections.
#[derive(Clone, Copy)]
pub(crate) struct Size {
    pub(crate) flash: u64,
    pub(crate) ram: u64,
}

pub fn run(args: &[String]) -> Result<(), String> {
    let mut size = "160x120".to_string();
    let mut options = Options::default();
    let mut rest = args.iter();
    while let Some(arg) = rest.next() {
        match arg.as_str() {
            "--size" => size = rest.next().ok_or("--size takes WIDTHxHEIGHT")?.clone(),
            "--only" => options.only = rest.next().ok_or("--only takes SCENE[,SCENE...]")?.clone(),
            "--profile" => {
                options.profile = Some(rest.next().ok_or("--profile takes a LABEL")?.clone())
            }
            "--compare-plan" => options.compare_plan = true,
            "--progressive" => options.progressive = true,
            "--dither" => options.dither = true,
            "--antialias" => options.antialias = true,
            "--animations" => options.animations = true,
            "--frames" => {
                let n = rest.next().ok_or("--frames takes a number")?;
                options.frames = Some(n.parse().map_err(|_| "--frames takes a number")?);
            }
            "--minimal" => options.minimal = true,
            "--opt-levels" => return opt_levels(),
            // The RAM table alone (spec0 at 320x240, both machines), printed.
            "--ram" => {
                println!("{}", ram_by_part(&root()?, &[])?);
                return Ok(());
            }
            "--build" => {
                options.build = Some(rest.next().ok_or("--build takes MACHINE-NUMBER")?.clone())
            }
            other => return Err(format!("unknown argument {other}")),
        }
    }
    let (width, height) = size
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<u16>().ok()?, h.parse::<u16>().ok()?)))
        .ok_or("--size takes WIDTHxHEIGHT")?;
    let root = root()?;
    if options.animations && options.only.is_empty() {
        options.only = crate::animation::FILMS.join(",");
    }
    let mut measurement = measure(&root, width, height, &options)?;
    if options.animations {
        let table = crate::animation::table(&measurement.rows, width, height, options.frames);
        println!("{table}");
        if options.frames.is_none() && options.build.is_none() {
            let table = format!("{table}{}", crate::animation::flash(&root)?);
            crate::animation::write_table(&root, &table)?;
        }
        return measurement.check();
    }
    if options.dither {
        let table = format!(
            "{DITHER_HEADING}\n{}{}",
            panel_table(&measurement.rows, width, height),
            dither_table(&measurement.rows, width, height)
        );
        println!("{table}");
        if options.only.is_empty() && options.build.is_none() {
            // The narrative before the measured part is kept.
            let path = root.join("docs/dither.md");
            let text = std::fs::read_to_string(&path).unwrap_or_default();
            let kept = text
                .split(DITHER_HEADING)
                .next()
                .unwrap_or(&text)
                .trim_end();
            std::fs::write(&path, format!("{kept}\n\n{table}")).map_err(|e| e.to_string())?;
        }
        return measurement.check();
    }
    if options.antialias {
        let table = antialias_table(&measurement.rows, width, height);
        println!("{table}");
        return measurement.check();
    }
    if options.progressive {
        let table = progressive_table(&measurement.rows, width, height);
        println!("{table}");
        if options.only.is_empty() && options.build.is_none() {
            std::fs::write(root.join("docs/progressive.md"), &table).map_err(|e| e.to_string())?;
        }
        return measurement.check();
    }
    if options.build.is_none()
        && !options.minimal
        && !options.compare_plan
        && options.profile.is_none()
    {
        // The minimal firmware renders its one scene identically too.
        let minimal = measure(
            &root,
            width,
            height,
            &Options {
                only: "basic".into(),
                minimal: true,
                ..Options::default()
            },
        )?;
        for row in minimal.rows {
            measurement.rows.push(Row {
                scene: format!("{} (minimal build)", row.scene),
                ..row
            });
        }
    }
    let mut table = table(&measurement.rows, width, height);
    let complete = options.only.is_empty()
        && options.build.is_none()
        && options.profile.is_none()
        && !options.compare_plan
        && size == "160x120";
    if complete {
        table.push_str(&flash_by_part(
            &root,
            conformance_dir(&root).as_deref(),
            &size,
        )?);
        table.push_str(&ram_by_part(&root, &measurement.rows)?);
        if let Ok(levels) = std::fs::read_to_string(root.join("docs/opt-levels.md")) {
            table.push('\n');
            table.push_str(&levels);
        }
        table.push_str(&profile::comparison(&root));
    }
    println!("{table}");
    if complete {
        std::fs::create_dir_all(root.join("docs")).map_err(|e| e.to_string())?;
        std::fs::write(root.join("docs/firmware.md"), &table).map_err(|e| e.to_string())?;
    }
    measurement.check()
}

/// One scene at 320x240 on one build (`name`, as `--build` takes it), at an optimisation
/// level or the profile's; its frame checked. `spec0` in the firmware with the parser and
/// spec0 only, or (`minimal`) `basic` in the minimal firmware.
fn measure_frame(
    root: &Path,
    name: &str,
    opt_level: Option<&str>,
    scene: &str,
    minimal: bool,
) -> Result<Row, String> {
    let options = Options {
        only: scene.into(),
        build: Some(name.into()),
        opt_level: opt_level.map(str::to_string),
        minimal,
        // A footprint: the first assignments' language, as the flash table.
        without_extensions: true,
        ..Options::default()
    };
    let measured = measure(root, 320, 240, &options)?;
    measured.check()?;
    measured
        .rows
        .into_iter()
        .find(|r| r.scene == scene)
        .ok_or_else(|| format!("{scene} was not rendered"))
}

/// RAM by part for spec0 at 320x240 on both machines: the sizes the firmware reports
/// (`microray size NAME BYTES`) and the peaks of its stack while parsing and rendering.
fn ram_by_part(root: &Path, all: &[Row]) -> Result<String, String> {
    let mut columns = Vec::new();
    let mut deepest_scenes = Vec::new();
    for name in ["mps2-an386-f32", "microbit-fixed"] {
        let spec0 = measure_frame(root, name, None, "spec0", false)?;
        let console =
            std::fs::read_to_string(root.join("target/qemu").join(name).join("console.txt"))
                .map_err(|e| e.to_string())?;
        let mut values: HashMap<String, u64> = HashMap::new();
        for line in console.lines() {
            let words: Vec<&str> = line.split_whitespace().collect();
            match words.as_slice() {
                ["microray", "size", part, bytes] => {
                    values.insert((*part).to_string(), bytes.parse().unwrap_or(0));
                }
                ["microray", "scene", "spec0", rest @ ..] => {
                    for pair in rest.chunks(2) {
                        if let [key, value] = pair {
                            values.insert(format!("spec0 {key}"), value.parse().unwrap_or(0));
                        }
                    }
                }
                _ => {}
            }
        }
        values.insert("static".into(), spec0.size.ram);
        // The deepest trace chain: the scene whose renderer went deepest at 160x120.
        if let Some(deepest) = all
            .iter()
            .filter(|r| name == format!("{}-{}", r.machine, r.number))
            .max_by_key(|r| r.renderer_stack)
        {
            values.insert("deepest".into(), deepest.renderer_stack);
            deepest_scenes.push(format!("{} on {name}", deepest.scene));
        }
        values.insert("total".into(), spec0.size.ram + spec0.stack);
        // What playing a film keeps besides (the `animate` builds, docs/animation.md).
        for (key, bytes) in crate::animation::ram_of(root, name) {
            values.insert(key.into(), bytes);
        }
        columns.push((name, values));
    }
    let rows = [
        (
            "scene",
            "the scene (capacities: what the embedded scenes need)",
        ),
        ("object", "- one object slot"),
        ("material", "- one material slot"),
        ("light", "- one light slot"),
        ("texture", "- one texture slot"),
        ("renderer", "the renderer (render plan, tree, shader)"),
        (
            "row",
            "the row buffer (320 pixels in the output's 3-byte colour)",
        ),
        (
            "row-shading",
            "a row shaded together (its levels and lights)",
        ),
        (
            "spec0 renderer",
            "the renderer's own stack for spec0: row lists, row shading, its trace chain",
        ),
        (
            "deepest",
            "the renderer's own stack for the deepest trace chain of any scene (160x120)",
        ),
        ("spec0 parse", "peak stack while parsing spec0.txt"),
        ("spec0 render", "peak stack while rendering"),
        ("static", "static RAM (`.data + .bss`)"),
        ("total", "**static RAM + peak stack**"),
        (
            "film",
            "playing a film (`animate`, docs/animation.md): the film (`Animation<4>`)",
        ),
        (
            "region",
            "- the regions (a frame's `Region<8>`, the last frame's `LastFrame<8>`)",
        ),
    ];
    let mut out = String::from(
        "\n## RAM by part: spec0 at 320x240\n\n\
         Bytes, from `size_of` of each part in the firmware (its `full` build, as the flash table: the course's later kinds left out) and its painted stack (the peaks \
         include the scene and the harness's frames beneath the parser and the renderer; the \
         stack is painted again between parsing and rendering).\n\n| part |",
    );
    for (name, _) in &columns {
        let _ = write!(out, " {name} |");
    }
    out.push_str("\n|---|");
    out.push_str(&"---|".repeat(columns.len()));
    out.push('\n');
    for (key, label) in rows {
        let _ = write!(out, "| {label} |");
        for (_, values) in &columns {
            let _ = write!(out, " {} |", values.get(key).copied().unwrap_or(0));
        }
        out.push('\n');
    }
    let _ = writeln!(
        out,
        "\nThe deepest trace chains: {} (mirrors and glass nest a `trace` frame a level).",
        deepest_scenes.join(", ")
    );
    Ok(out)
}

/// The optimisation levels a firmware can be built at, against each other: flash and
/// instructions a pixel at 320x240 of the minimal build (its `basic` scene) and of the full
/// one with the parser and spec0, on both machines (`cargo xtask qemu --opt-levels`, which
/// writes `docs/opt-levels.md`; the complete run includes it in `docs/firmware.md`).
fn opt_levels() -> Result<(), String> {
    let root = root()?;
    let mut out = String::from(
        "## Optimisation level: flash against speed\n\n\
         Written by `cargo xtask qemu --opt-levels`: each firmware built at each level \
         (`CARGO_PROFILE_RELEASE_OPT_LEVEL`, `CARGO_PROFILE_RELEASE_SMALL_OPT_LEVEL`), flash in \
         bytes as above, and the instructions a pixel at 320x240 of the minimal build's `basic` \
         scene and of spec0 in the full build (their frames compared with the host's like every \
         other). The full firmware's profile (`release`) is at 3, the minimal firmware's \
         (`release-small`) at z.\n\n\
         | opt-level | M4F f32 minimal | its basic instr/px | M4F f32 full + parser + spec0 | \
         its spec0 instr/px | M0 I16F16 minimal | its basic instr/px | \
         M0 I16F16 full + parser + spec0 | its spec0 instr/px |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for level in ["3", "2", "s", "z"] {
        let _ = write!(out, "| {level} |");
        for build_name in ["mps2-an386-f32", "microbit-fixed"] {
            let basic = measure_frame(&root, build_name, Some(level), "basic", true)?;
            let spec0 = measure_frame(&root, build_name, Some(level), "spec0", false)?;
            let per_pixel = |row: &Row| row.insns as f64 / (320.0 * 240.0);
            let _ = write!(
                out,
                " {} | {:.0} | {} | {:.0} |",
                basic.size.flash,
                per_pixel(&basic),
                spec0.size.flash,
                per_pixel(&spec0)
            );
        }
        out.push('\n');
    }
    println!("{out}");
    std::fs::write(root.join("docs/opt-levels.md"), &out).map_err(|e| e.to_string())
}

/// The repository's root.
pub(crate) fn root() -> Result<PathBuf, String> {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .canonicalize()
        .map_err(|e| e.to_string())
}

/// Frames and builds measured in QEMU.
pub(crate) struct Measurement {
    pub(crate) rows: Vec<Row>,
}

impl Measurement {
    /// An error listing every frame that differs from the host's.
    pub(crate) fn check(&self) -> Result<(), String> {
        let failed: Vec<String> = self
            .rows
            .iter()
            .filter(|r| r.identical != Ok(true))
            .map(|r| {
                format!(
                    "{} on {} in {}: {:?}",
                    r.scene, r.machine, r.number, r.identical
                )
            })
            .collect();
        if failed.is_empty() {
            Ok(())
        } else {
            Err(format!(
                "frames differ from the host:\n{}",
                failed.join("\n")
            ))
        }
    }
}

/// Builds the firmware and the plugin, runs the builds `options` select in QEMU at `width`
/// x `height`, and compares every frame with the host's.
pub(crate) fn measure(
    root: &Path,
    width: u16,
    height: u16,
    options: &Options,
) -> Result<Measurement, String> {
    let conformance = conformance_dir(root);
    if conformance.is_none() {
        eprintln!(
            "warning: no course scenes (MICRORAY_CONFORMANCE, by default ../shared/conformance \
             beside the project, is not a directory): only the project's scenes are rendered"
        );
    }
    which("qemu-system-arm")
        .ok_or("qemu-system-arm is not installed (apt-get install qemu-system-arm)")?;
    let size = format!("{width}x{height}");
    let plugin = build_plugin(root)?;
    let scenes = scene_files(root, conformance.as_deref());
    let mut rows = Vec::new();
    let mut profiles = String::new();
    for build in &BUILDS {
        let name = format!("{}-{}", build.machine, build.number);
        // The progressive frame is kept in RAM: the micro:bit has no room for one.
        // The anti-aliased frames measure the M4F board (the M0's counts scale the same).
        if (options.progressive || options.antialias) && build.machine == "microbit" {
            continue;
        }
        if options
            .build
            .as_ref()
            .is_some_and(|only| !name.starts_with(only.as_str()))
        {
            continue;
        }
        let variant = Variant {
            opt_level: options.opt_level.as_deref().unwrap_or(""),
            only: &options.only,
            plan: if options.compare_plan {
                "compare"
            } else if options.progressive {
                "progressive"
            } else if options.dither {
                "dither"
            } else if options.antialias {
                "antialias"
            } else if options.animations {
                "animate"
            } else {
                ""
            },
            full: !options.minimal,
            extensions: !options.minimal && !options.without_extensions,
            // The minimal build is built for size (the firmware's `release-small` profile).
            small: options.minimal,
        };
        let frames = options.frames.map(|n| n.to_string()).unwrap_or_default();
        let elf = build_firmware(
            root,
            build,
            conformance.as_deref(),
            &size,
            &variant,
            &frames,
        )?;
        let (markers, size) = inspect(&elf)?;
        let out = root.join("target/qemu").join(&name);
        let _ = std::fs::remove_dir_all(&out);
        std::fs::create_dir_all(&out).map_err(|e| e.to_string())?;
        let started = Instant::now();
        let profiling = options.profile.is_some();
        let (console, log) = run_qemu(build, &elf, &plugin, markers, &out, profiling)?;
        eprintln!("{name}: ran in {:.1} s", started.elapsed().as_secs_f64());
        let frames = if options.animations {
            crate::animation::compare(build, &console, &log, &out, &scenes, width, height)?
        } else {
            compare(build, &console, &log, &out, &scenes, width, height)?
        };
        if profiling {
            let counts = profile::frame_counts(&log);
            let mut symbolizer = profile::Symbolizer::new(&elf)?;
            let pixels = f64::from(width) * f64::from(height);
            // The course's frames profiled, for their mean below.
            let mut profiled: Vec<(&HashMap<u64, u64>, &Row)> = Vec::new();
            for (index, row) in frames.iter().enumerate() {
                let Some(frame) = counts.get(&(index as u64)) else {
                    continue;
                };
                // Every frame of a wanted scene (`spec0`, `spec0+preview`, ...).
                let base = row.scene.split('+').next().unwrap_or(&row.scene);
                let wanted =
                    options.only.is_empty() || options.only.split(',').any(|scene| scene == base);
                if !wanted {
                    continue;
                }
                let title = format!(
                    "{} on {} in {} ({width}x{height})",
                    row.scene,
                    build.machine,
                    row.number_name()
                );
                let report = profile::Profile::of(&mut symbolizer, frame)
                    .report(&title, pixels, row.vdiv, row.vsqrt);
                profiles.push_str(&report);
                profiles.push('\n');
                if COURSE_SCENES.contains(&row.scene.as_str()) {
                    profiled.push((frame, row));
                }
            }
            if profiled.len() > 1 {
                profiles.push_str(&mean_profile(&mut symbolizer, &profiled, build, pixels));
            }
        }
        rows.extend(frames.into_iter().map(|r| Row { size, ..r }));
    }
    if let Some(label) = &options.profile {
        if profiles.is_empty() {
            return Err(format!(
                "--profile {label}: no frame of the scenes asked for ({}) was rendered (the \
                 course scenes come from MICRORAY_CONFORMANCE, by default ../shared/conformance \
                 beside the project)",
                if options.only.is_empty() {
                    "all"
                } else {
                    &options.only
                }
            ));
        }
        println!("{profiles}");
        let path = root.join("docs").join(format!("profile-{label}.md"));
        std::fs::write(&path, &profiles).map_err(|e| format!("{}: {e}", path.display()))?;
        eprintln!("profile written to {}", path.display());
    }
    Ok(Measurement { rows })
}

fn which(program: &str) -> Option<PathBuf> {
    std::env::var_os("PATH")?
        .to_str()?
        .split(':')
        .map(|d| Path::new(d).join(program))
        .find(|p| p.is_file())
}

pub(crate) fn conformance_dir(root: &Path) -> Option<PathBuf> {
    let dir = std::env::var_os("MICRORAY_CONFORMANCE")
        .map(PathBuf::from)
        .unwrap_or_else(|| "../shared/conformance".into());
    let dir = if dir.is_relative() {
        root.join(dir)
    } else {
        dir
    };
    dir.canonicalize().ok()
}

/// Scene name to file, in the firmware's order: course scenes, then the project's.
pub(crate) fn scene_files(root: &Path, conformance: Option<&Path>) -> BTreeMap<String, PathBuf> {
    let mut dirs: Vec<PathBuf> = conformance.map(Path::to_path_buf).into_iter().collect();
    dirs.push(root.join("scenes"));
    dirs.push(root.join("tests/scenes"));
    let mut found = BTreeMap::new();
    for path in txt_files(dirs) {
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default()
            .to_string();
        found.insert(name, path);
    }
    found
}

/// The `.txt` files under `dirs` and their subdirectories, the last directory's first.
pub(crate) fn txt_files(mut dirs: Vec<PathBuf>) -> Vec<PathBuf> {
    let mut found = Vec::new();
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "txt") {
                found.push(path);
            }
        }
    }
    found
}

pub(crate) fn cargo(args: &[&str], dir: &Path, envs: &[(&str, &str)]) -> Result<(), String> {
    checked(
        Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
            .args(args)
            .current_dir(dir)
            .envs(envs.iter().copied()),
    )
}

/// Runs `command`, an error naming it unless it succeeds.
pub(crate) fn checked(command: &mut Command) -> Result<(), String> {
    let status = command.status().map_err(|e| format!("{command:?}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{command:?} failed ({status})"))
    }
}

pub(crate) fn build_plugin(root: &Path) -> Result<PathBuf, String> {
    cargo(&["build", "--release", "-p", "icount"], root, &[])?;
    Ok(root.join("target/release/libicount.so"))
}

fn build_firmware(
    root: &Path,
    build: &Build,
    conformance: Option<&Path>,
    size: &str,
    variant: &Variant<'_>,
    frames: &str,
) -> Result<PathBuf, String> {
    let mut features = format!("{},{}", build.feature, build.number);
    if variant.plan == "animate" {
        features.push_str(",animate");
    }
    if variant.full && !variant.extensions {
        features.push_str(",full");
    }
    if variant.plan == "antialias" {
        features.push_str(",antialias");
    }
    let panels = if variant.plan == "dither" && variant.full {
        features.push_str(",panels");
        PANEL_SCENES.join(",")
    } else {
        String::new()
    };
    let (only, plan) = (variant.only, variant.plan);
    let dir = root.join("firmware");
    let conformance = conformance
        .map(|p| p.display().to_string())
        .unwrap_or_default();
    let mut envs = vec![
        ("MICRORAY_FW_SIZE", size),
        ("MICRORAY_FW_ONLY", only),
        ("MICRORAY_FW_PLAN", plan),
        ("MICRORAY_FW_FRAMES", frames),
        ("MICRORAY_FW_PANELS", panels.as_str()),
    ];
    if !conformance.is_empty() {
        envs.push(("MICRORAY_CONFORMANCE", conformance.as_str()));
    }
    let profile = if variant.small {
        "release-small"
    } else {
        "release"
    };
    if !variant.opt_level.is_empty() {
        envs.push(("CARGO_PROFILE_RELEASE_OPT_LEVEL", variant.opt_level));
        envs.push(("CARGO_PROFILE_RELEASE_SMALL_OPT_LEVEL", variant.opt_level));
    }
    let mut args = vec![
        "build",
        "--profile",
        profile,
        "--target",
        build.target,
        "--features",
        &features,
    ];
    if !variant.full || !variant.extensions {
        args.push("--no-default-features");
    }
    cargo(&args, &dir, &envs)?;
    // One artefact per target: copy it before the next build of the same target replaces it.
    let elf = dir
        .join("target")
        .join(build.target)
        .join(profile)
        .join("microray-firmware");
    let copy = root.join("target/qemu").join(format!(
        "firmware-{}-{}{}.elf",
        build.machine,
        build.number,
        if variant.full { "" } else { "-minimal" }
    ));
    std::fs::create_dir_all(root.join("target/qemu")).map_err(|e| e.to_string())?;
    std::fs::copy(&elf, &copy).map_err(|e| format!("{}: {e}", elf.display()))?;
    Ok(copy)
}

/// The flash of the full firmware for `machine` and `number` embedding `only`, built for
/// `plan` (`MICRORAY_FW_PLAN`; `animate` adds the `animate` feature).
pub(crate) fn flash_of(
    root: &Path,
    machine: &str,
    number: &str,
    only: &str,
    plan: &str,
) -> Result<u64, String> {
    let build = BUILDS
        .iter()
        .find(|b| b.machine == machine && b.number == number)
        .ok_or(format!("no build {machine} {number}"))?;
    let variant = Variant {
        only,
        plan,
        full: true,
        extensions: true,
        small: false,
        opt_level: "",
    };
    let conformance = conformance_dir(root);
    let elf = build_firmware(root, build, conformance.as_deref(), "160x120", &variant, "")?;
    Ok(inspect(&elf)?.1.flash)
}

/// The markers' addresses (without the Thumb bit) and the flash and RAM the build takes.
fn inspect(elf: &Path) -> Result<([u64; 3], Size), String> {
    let bytes = std::fs::read(elf).map_err(|e| e.to_string())?;
    let file = object::File::parse(&*bytes).map_err(|e| e.to_string())?;
    let mut markers = [0u64; 3];
    for symbol in file.symbols() {
        let index = match symbol.name() {
            Ok("microray_count_start") => 0,
            Ok("microray_count_stop") => 1,
            Ok("microray_count_frame") => 2,
            _ => continue,
        };
        markers[index] = symbol.address() & !1;
    }
    if markers.contains(&0) {
        return Err(format!("{}: marker functions not found", elf.display()));
    }
    let mut size = Size { flash: 0, ram: 0 };
    for section in file.sections() {
        match section.name() {
            Ok(".vector_table" | ".text" | ".rodata") => size.flash += section.size(),
            Ok(".data") => {
                // Initial values live in flash, the variables in RAM.
                size.flash += section.size();
                size.ram += section.size();
            }
            Ok(".bss" | ".uninit") => size.ram += section.size(),
            _ => {}
        }
    }
    Ok((markers, size))
}

pub(crate) fn run_qemu(
    build: &Build,
    elf: &Path,
    plugin: &Path,
    markers: [u64; 3],
    out: &Path,
    profile: bool,
) -> Result<(String, String), String> {
    let log = out.join("icount.log");
    let plugin_arg = format!(
        "{},start={:#x},stop={:#x},frame={:#x},profile={}",
        plugin.display(),
        markers[0],
        markers[1],
        markers[2],
        if profile { "on" } else { "off" }
    );
    let mut child = Command::new("qemu-system-arm")
        .args(["-machine", build.machine, "-cpu", build.cpu, "-nographic"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .args(["-plugin", &plugin_arg, "-d", "plugin", "-D"])
        .arg(&log)
        .arg("-kernel")
        .arg(elf)
        .current_dir(out)
        // QEMU needs a standard input that stays open.
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())?;
    let deadline = Instant::now() + Duration::from_secs(600);
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            return Err(format!(
                "{} {}: QEMU did not finish in 600 s",
                build.machine, build.number
            ));
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let output = child.wait_with_output().map_err(|e| e.to_string())?;
    let console = String::from_utf8_lossy(&output.stdout).into_owned();
    // Kept for reading after the run.
    let _ = std::fs::write(out.join("console.txt"), &console);
    if !status.success() {
        return Err(format!(
            "{} {}: QEMU exited with {status}\n{console}{}",
            build.machine,
            build.number,
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    let log = std::fs::read_to_string(&log).map_err(|e| e.to_string())?;
    Ok((console, log))
}

/// A scene the firmware renders: a file, or one written in source.
pub(crate) enum Source<'a> {
    File(&'a Path),
    Static,
    Basic,
}

/// The host's render of a scene at the firmware's size, in `S`.
/// The host's frame of a scene at `width` x `height` in `S`, anti-aliased by `aa`.
pub(crate) fn host_render<S: Scalar>(
    source: &Source<'_>,
    width: u16,
    height: u16,
    aa: Option<Antialias>,
) -> Result<Vec<u8>, String> {
    let mut scene: HostScene<'static, S> = match source {
        Source::File(path) => {
            let text = std::fs::read(path).map_err(|e| e.to_string())?;
            parse_scene(
                &text,
                texture_files(path.parent().unwrap_or(Path::new("."))),
            )
            .map_err(|e| format!("{}: {e}", path.display()))?
        }
        Source::Static => microray::Scene::from_defs(
            &static_scene::CAMERA,
            &static_scene::MATERIALS,
            &static_scene::TEXTURES,
            &static_scene::LIGHTS,
            &static_scene::OBJECTS,
        )
        .map_err(|e| e.to_string())?,
        Source::Basic => {
            let mut scene = microray::Scene::empty();
            basic_scene::load(&mut scene).map_err(|e| e.to_string())?;
            scene
        }
    };
    scene
        .set_resolution(width, height)
        .map_err(|e| e.to_string())?;
    let mut image = Framebuffer::new(embedded_graphics::prelude::Size::new(
        u32::from(width),
        u32::from(height),
    ));
    if let Some(aa) = aa {
        let renderer: microray::host::HostRenderer<'_, S> = microray::render::Renderer::new(&scene);
        let image = microray::host::antialiased(&renderer, aa).map_err(|e| e.to_string())?;
        return Ok(image.rgb().to_vec());
    }
    render(&scene, &mut image).map_err(|e| e.to_string())?;
    Ok(image.rgb().to_vec())
}

/// Each frame's instructions, VDIVs and VSQRTs, in order, from the plugin's log.
pub(crate) fn frame_totals(log: &str) -> impl Iterator<Item = (u64, u64, u64)> + '_ {
    log.lines().filter_map(|line| {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["icount", "frame", _, "insns", i, "vdiv", d, "vsqrt", q] => {
                Some((i.parse().ok()?, d.parse().ok()?, q.parse().ok()?))
            }
            _ => None,
        }
    })
}

fn compare(
    build: &Build,
    console: &str,
    log: &str,
    out: &Path,
    scenes: &BTreeMap<String, PathBuf>,
    width: u16,
    height: u16,
) -> Result<Vec<Row>, String> {
    let mut frames = frame_totals(log);
    let mut rows = Vec::new();
    for line in console.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        let (name, stack, renderer_stack) = match words.as_slice() {
            ["microray", "scene", name, "stack", stack, rest @ ..] => {
                let renderer = rest
                    .chunks(2)
                    .find_map(|pair| match pair {
                        ["renderer", value] => value.parse().ok(),
                        _ => None,
                    })
                    .unwrap_or(0);
                (name.to_string(), stack.parse().unwrap_or(0), renderer)
            }
            ["microray", "scene", name, "skipped", ..] => {
                let why = line.split_once("skipped").map_or("", |(_, why)| why.trim());
                eprintln!("{} {}: {name} skipped {why}", build.machine, build.number);
                continue;
            }
            ["microray", "scene", name, ..] => {
                return Err(format!(
                    "{} {}: {name}: {line}",
                    build.machine, build.number
                ));
            }
            _ => continue,
        };
        let (insns, vdiv, vsqrt) = frames
            .next()
            .ok_or(format!("no instruction count for {name}"))?;
        let dump =
            std::fs::read(out.join(format!("{name}.rgb"))).map_err(|e| format!("{name}: {e}"))?;
        // The frame without the plan must equal the host's render with it.
        let aa = AA_MODES
            .iter()
            .find(|(suffix, _)| name.ends_with(suffix))
            .map(|&(_, aa)| aa);
        let panel = name.split_once("+panel-");
        let scene = ["+noplan", "+preview", "+progressive", "+dither", "+rgb565"]
            .iter()
            .chain(AA_MODES.iter().map(|(suffix, _)| suffix))
            .find_map(|suffix| name.strip_suffix(suffix))
            .or(panel.map(|(scene, _)| scene))
            .unwrap_or(&name);
        let source = if scene == static_scene::NAME {
            Source::Static
        } else if scene == basic_scene::NAME {
            Source::Basic
        } else {
            Source::File(
                scenes
                    .get(scene)
                    .ok_or(format!("{name}: no such scene on the host"))?,
            )
        };
        let host = match build.number {
            "f32" => host_render::<f32>(&source, width, height, aa),
            _ => host_render::<I16F16>(&source, width, height, aa),
        };
        // The dithered frame is the host's frame through the same dither, expanded back.
        let host = if let Some((_, way)) = panel {
            let converted = panel_of(way).map(|(format, method)| {
                host.map(|mut h| {
                    microray::host::panel::whole(&mut h, usize::from(width), format, method);
                    h
                })
            });
            converted.unwrap_or_else(|| Err(format!("{name}: no such panel way")))
        } else if name.ends_with("+dither") {
            host.map(|h| rgb565(h, width, true))
        } else if name.ends_with("+rgb565") {
            host.map(|h| rgb565(h, width, false))
        } else {
            host
        };
        let identical = host.map(|h| h == dump);
        rows.push(Row {
            scene: name,
            machine: build.machine,
            number: build.number,
            identical,
            insns,
            vdiv,
            vsqrt,
            stack,
            renderer_stack,
            size: Size { flash: 0, ram: 0 },
            region: None,
        });
    }
    Ok(rows)
}

/// The minimal build's flash limit: a 16 KiB part with 1 KiB to spare.
const MINIMAL_LIMIT: u64 = 15 * 1024;
/// The full build's with the parser, built for size: a 64 KiB part with 1 KiB to spare.
const FULL_SMALL_LIMIT: u64 = 63 * 1024;

/// Where the room under the limits came from (bytes measured on the Cortex-M0, whose builds
/// were over them; each change leaves the pixels as they were).
const WHAT_MADE_ROOM: &str = "\nWhere the room came from (the Cortex-M0's builds, which were over \
these limits: minimal 16,040 bytes, full + parser + spec0 at `release-small` 67,068):\n\n\
- leading zeros counted with a 128-entry table (by byte pair) instead of 256 entries, the \
reciprocal square root's first guesses in 16 bits instead of 32, a render's area clipped in \
integers rather than by embedded-graphics' `Rectangle::intersection`: minimal -852, full \
-40 (its share of the tables, less what LTO inlined differently; no table at all, four \
halvings instead, took 240 bytes more off but cost the Cortex-M0 4 % of its instructions);\n\
- the parser fills each definition in place instead of building it from returned arrays \
(each array and each move was a `memcpy` call at opt-level z): full -1,192;\n\
- the decimal reader scans its grammar byte by byte instead of with nom's combinators: full \
-708;\n\
- built for size (`cfg(microray_small)`, docs/design.md), the row shading's rarer paths \
share one body: full -912.\n\n\
Tried and left: the names' UTF-8 decoded by hand in the compiled reader (+480: the strings \
returned by value cost more than `from_utf8`'s table); one generic light loop (+200 to \
+310); the parser's items passed by reference (+116).\n";

/// Flash of the parts: the minimal build (no optional feature, the `basic` scene in source),
/// the full build with the scenes written in source (no parser linked), and the full build
/// with the parser and one course scene file (spec0).
fn flash_by_part(root: &Path, conformance: Option<&Path>, size: &str) -> Result<String, String> {
    let spec0 = scene_files(root, conformance)
        .get("spec0")
        .and_then(|p| std::fs::metadata(p).ok())
        .map_or(0, |m| m.len());
    let mut out = String::from(
        "\n## Flash by part\n\n\
         - minimal: `--no-default-features`, no optional microray feature: planes and spheres, \
         point lights, ambient and diffuse light, the `basic` scene in Rust source compiled on \
         the host (`Scene::load_compiled`: no f64 arithmetic), no parser; built for size (the \
         firmware's `release-small` profile, opt-level z);\n\
         - full, scenes in source: every feature of the course's first assignments (the \
         firmware's `full`; the later kinds, projectors and surfaces of revolution, are its \
         `extensions` and are left out here as in every build of this table), the `static` scene (tiled plane, texture, \
         spotlight, glints) and `basic` in source, no parser linked;\n\
         - full + parser + spec0: every feature, the parser and one scene file (spec0, {spec0} \
         bytes of text), nothing else; with the `release` profile (opt-level 3, the speed \
         reported above) and with `release-small` (opt-level z: see the trade-off below);\n\
         - parser: the parser's and the decimal reader's parts of the full + parser build.\n\n\
         Bytes of `.vector_table + .text + .rodata + .data`, builds with LTO.\n\n\
         | machine | number | minimal | full, scenes in source | full + parser + spec0.txt | \
         the same, release-small | parser |\n\
         |---|---|---|---|---|---|---|\n",
    )
    .replace("{spec0}", &spec0.to_string());
    // Each build's flash by part: the minimal build and the full one with the parser, at
    // opt-level 3 and built for size.
    // A build's name, and its minimal, full + parser and full + parser release-small parts.
    type Parts = [u64; 8];
    let mut by_part: Vec<(String, Parts, Parts, Parts)> = Vec::new();
    let mut margins = String::new();
    for build in BUILDS.iter().filter(|b| {
        (b.machine, b.number) == ("mps2-an386", "f32")
            || (b.machine, b.number) == ("microbit", "fixed")
    }) {
        let flash = |only: &str, full: bool, small: bool| -> Result<(u64, [u64; 8]), String> {
            let variant = Variant {
                only,
                plan: "",
                full,
                extensions: false,
                small,
                opt_level: "",
            };
            let elf = build_firmware(root, build, conformance, size, &variant, "")?;
            Ok((inspect(&elf)?.1.flash, profile::flash_parts(&elf)?))
        };
        let (minimal, minimal_parts) = flash("basic", false, true)?;
        let (source_only, _) = flash("static,basic", true, false)?;
        let (with_parser, parser_parts) = flash("spec0", true, false)?;
        let (with_parser_small, small_parts) = flash("spec0", true, true)?;
        let number = if build.number == "fixed" {
            "I16F16"
        } else {
            build.number
        };
        by_part.push((
            format!("{} {number}", build.machine),
            minimal_parts,
            parser_parts,
            small_parts,
        ));
        let _ = writeln!(
            margins,
            "| {} | {number} | {minimal} | {} | {with_parser_small} | {} |",
            build.machine,
            MINIMAL_LIMIT as i64 - minimal as i64,
            FULL_SMALL_LIMIT as i64 - with_parser_small as i64,
        );
        let _ = writeln!(
            out,
            "| {} | {} | {minimal} | {source_only} | {with_parser} | {with_parser_small} | {} |",
            build.machine,
            if build.number == "fixed" {
                "i16f16"
            } else {
                build.number
            },
            parser_parts[2] + parser_parts[3],
        );
    }
    let _ = write!(
        out,
        "\nThe limits, with 1 KiB to spare on the parts they are for (16 KiB of flash for the \
         minimal build, 64 KiB for the full one with the parser built for size): minimal \
         ≤ {MINIMAL_LIMIT} bytes, full + parser + spec0 at `release-small` ≤ {FULL_SMALL_LIMIT}.\n\n\
         | machine | number | minimal | its margin | full + parser + spec0, release-small | its margin |\n\
         |---|---|---|---|---|---|\n{margins}"
    );
    out.push_str(
        "\nBy part (bytes; code by the innermost inlined function that belongs to a part, from \
         the DWARF inline records, so the renderer inlined into the harness's frame loop counts \
         for microray; data by symbol name):\n\n| part |",
    );
    for (build, _, _, _) in &by_part {
        let _ = write!(
            out,
            " {build} minimal | {build} full + parser + spec0 | the same, release-small |"
        );
    }
    out.push_str("\n|---|");
    out.push_str(&"---|---|---|".repeat(by_part.len()));
    out.push('\n');
    for (index, part) in profile::PARTS.iter().enumerate() {
        let _ = write!(out, "| {part} |");
        for (_, minimal, with_parser, small) in &by_part {
            let _ = write!(
                out,
                " {} | {} | {} |",
                minimal[index], with_parser[index], small[index]
            );
        }
        out.push('\n');
    }
    out.push_str(WHAT_MADE_ROOM);
    Ok(out)
}

fn table(rows: &[Row], width: u16, height: u16) -> String {
    let pixels = f64::from(width) * f64::from(height);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# microray on emulated microcontrollers\n\n\
         Written by `cargo xtask qemu`: every scene rendered at {width}x{height} by the firmware in QEMU 7.2 \
         (mps2-an386: Cortex-M4F; microbit: Cortex-M0), each frame compared byte for byte with the host's \
         render of the same scene and number type. Instructions are exact counts of the render \
         (parsing and writing rows out excluded) by the project's QEMU plugin; VDIV and VSQRT take 14 \
         cycles each on the M4F though they count as one instruction. Flash is `.vector_table + .text + \
         .rodata + .data`, static RAM `.data + .bss`, both for the whole firmware with every scene \
         embedded; peak stack is measured by painting the stack.\n"
    );
    let _ = writeln!(
        out,
        "| scene | machine | number | identical | instructions/frame | instructions/pixel | VDIV/pixel | VSQRT/pixel | flash | static RAM | peak stack |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let identical = match &r.identical {
            Ok(true) => "yes".to_string(),
            Ok(false) => "NO".to_string(),
            Err(e) => format!("error: {e}"),
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {:.0} | {:.2} | {:.2} | {} | {} | {} |",
            r.scene,
            r.machine,
            r.number_name(),
            identical,
            r.insns,
            r.insns as f64 / pixels,
            r.vdiv as f64 / pixels,
            r.vsqrt as f64 / pixels,
            r.size.flash,
            r.size.ram,
            r.stack
        );
    }
    out.push_str(&summary(rows, pixels));
    out
}

/// The stages of the geometric mean of the course's frames' instructions a pixel: each frame's
/// counts weighted by the mean over its own total, so that every frame counts by its shares
/// (as in the geometric mean) and the stages add up to the mean.
fn mean_profile(
    symbolizer: &mut profile::Symbolizer,
    frames: &[(&HashMap<u64, u64>, &Row)],
    build: &Build,
    pixels: f64,
) -> String {
    let n = frames.len() as f64;
    let mean = (frames
        .iter()
        .map(|(_, r)| (r.insns.max(1) as f64).ln())
        .sum::<f64>()
        / n)
        .exp();
    // Weighted counts in thousandths, so that the small frames keep their precision.
    let mut merged: HashMap<u64, u64> = HashMap::new();
    let (mut vdiv, mut vsqrt) = (0.0, 0.0);
    for (counts, row) in frames {
        let weight = mean / row.insns.max(1) as f64 / n;
        for (&address, &count) in *counts {
            *merged.entry(address).or_insert(0) += (count as f64 * weight * 1000.0).round() as u64;
        }
        vdiv += row.vdiv as f64 * weight;
        vsqrt += row.vsqrt as f64 * weight;
    }
    let names: Vec<&str> = frames.iter().map(|(_, r)| r.scene.as_str()).collect();
    let number = frames
        .first()
        .map_or(build.number, |(_, r)| r.number_name());
    let title = format!(
        "the geometric mean of {} course scenes on {} in {number} (each by its shares: {})",
        frames.len(),
        build.machine,
        names.join(", ")
    );
    let mut report = profile::Profile::of(symbolizer, &merged).report(
        &title,
        pixels * 1000.0,
        (vdiv * 1000.0).round() as u64,
        (vsqrt * 1000.0).round() as u64,
    );
    report.push('\n');
    report
}

/// The course's scenes of the summary: the 17 the firmware renders (the micro:bit's flash
/// holds 15 of them: not the textured planes' images).
pub(crate) const COURSE_SCENES: [&str; 17] = [
    "aademo",
    "fplane0",
    "fplane1",
    "fplane3",
    "fplane4",
    "shiny",
    "shiny3",
    "spec0",
    "spec1",
    "spec3",
    "spotlight",
    "texplane1",
    "texplane2",
    "tplane4",
    "translucent3",
    "translucent4",
    "translucent6",
];

/// Per machine and number type: the geometric mean of the instructions a pixel over the
/// course's scenes, and the heavy scenes of the project (the figures the speed work is
/// measured by).
fn summary(rows: &[Row], pixels: f64) -> String {
    let mut out = String::from(
        "\n## Per build: the course's geometric mean and the heavy scenes\n\n\
         Instructions a pixel; the geometric mean over the course's scenes in the table above \
         (17; 15 on the micro:bit, whose flash does not hold the textured planes' images).\n\n\
         | machine | number | course scenes | geometric mean | spec0 | showcase | vases | spec3 | many_spheres |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    let mut builds: Vec<(&str, &str)> = Vec::new();
    for r in rows {
        if !builds.contains(&(r.machine, r.number)) {
            builds.push((r.machine, r.number));
        }
    }
    for (machine, number) in builds {
        let of = |scene: &str| {
            rows.iter()
                .find(|r| r.machine == machine && r.number == number && r.scene == scene)
                .map(|r| r.insns as f64 / pixels)
        };
        let course: Vec<f64> = COURSE_SCENES.iter().filter_map(|s| of(s)).collect();
        if course.is_empty() {
            continue;
        }
        let mean = (course.iter().map(|v| v.ln()).sum::<f64>() / course.len() as f64).exp();
        let cell = |scene: &str| of(scene).map_or("-".to_string(), |v| format!("{v:.0}"));
        let number = if number == "fixed" { "i16f16" } else { number };
        let _ = writeln!(
            out,
            "| {machine} | {number} | {} | {mean:.0} | {} | {} | {} | {} | {} |",
            course.len(),
            cell("spec0"),
            cell("showcase"),
            cell("vases"),
            cell("spec3"),
            cell("many_spheres"),
        );
    }
    out
}

/// The progressive order against the plain one, per scene and number type: the
/// instructions until the first pass (8x8 blocks) is on the panel, as a share of the plain
/// frame's, and the whole progressive frame's over the plain one's.
fn progressive_table(rows: &[Row], width: u16, height: u16) -> String {
    let mut out = format!(
        "# The progressive order in QEMU\n\n\
         Written by `cargo xtask qemu --progressive`: every scene at {width}x{height} on the \
         MPS2 board (Cortex-M4F), rendered plainly and then progressively \
         (`Renderer::render_pass`: 8x8 blocks, 4x4, 2x2, every pixel) into a frame in RAM, \
         the writes to the frame not counted (as the plain frame's row output is not). \
         First preview: the instructions of the first pass (the whole picture in 8x8 \
         blocks), as a share of the plain frame's. Overhead: the whole progressive frame's \
         instructions over the plain frame's. The final progressive frame is compared byte \
         for byte with the host's plain render (identical).\n\n\
         | scene | number | plain instructions | first preview | share | progressive | overhead | identical |\n\
         |---|---|---|---|---|---|---|---|\n"
    );
    for plain in rows.iter().filter(|r| !r.scene.contains('+')) {
        let find = |suffix: &str| {
            rows.iter()
                .find(|r| r.scene == format!("{}{suffix}", plain.scene) && r.number == plain.number)
        };
        let (Some(preview), Some(rest)) = (find("+preview"), find("+progressive")) else {
            continue;
        };
        let total = preview.insns + rest.insns;
        let share = preview.insns as f64 / plain.insns.max(1) as f64;
        let overhead = total as f64 / plain.insns.max(1) as f64 - 1.0;
        let identical = matches!(rest.identical, Ok(true)) && matches!(plain.identical, Ok(true));
        out.push_str(&format!(
            "| {} | {} | {} | {} | 1/{:.0} | {} | {:+.2} % | {} |\n",
            plain.scene,
            plain.number_name(),
            plain.insns,
            preview.insns,
            1.0 / share.max(1e-9),
            total,
            100.0 * overhead,
            if identical { "yes" } else { "no" }
        ));
    }
    out
}

/// What anti-aliasing costs, per scene and number type: each mode's instructions against
/// the plain frame's.
pub(crate) fn antialias_table(rows: &[Row], width: u16, height: u16) -> String {
    let mut out = format!(
        "Instructions a pixel on the MPS2 board (Cortex-M4F) at {width}x{height} \
         (`cargo xtask qemu --antialias`), plain (`--aa 1`) and anti-aliased, and each as a \
         multiple of the plain frame's; every frame byte-identical to the host's.\n\n\
         | scene | number | plain | 4 | 9 | 16 | adaptive | identical |\n\
         |---|---|---|---|---|---|---|---|\n"
    );
    let pixels = f64::from(width) * f64::from(height);
    for plain in rows.iter().filter(|r| !r.scene.contains('+')) {
        let modes: Vec<&Row> = AA_MODES
            .iter()
            .filter_map(|(suffix, _)| {
                rows.iter().find(|r| {
                    r.scene == format!("{}{suffix}", plain.scene) && r.number == plain.number
                })
            })
            .collect();
        if modes.len() != AA_MODES.len() {
            continue;
        }
        let base = plain.insns.max(1) as f64;
        let cells: Vec<String> = modes
            .iter()
            .map(|r| {
                format!(
                    "{:.0} ({:.2}x)",
                    r.insns as f64 / pixels,
                    r.insns as f64 / base
                )
            })
            .collect();
        let identical = matches!(plain.identical, Ok(true))
            && modes.iter().all(|r| matches!(r.identical, Ok(true)));
        out.push_str(&format!(
            "| {} | {} | {:.0} | {} | {} |\n",
            plain.scene,
            plain.number_name(),
            base / pixels,
            cells.join(" | "),
            if identical { "yes" } else { "no" }
        ));
    }
    out
}

/// Where docs/dither.md's measured part starts (what is before it is kept).
const DITHER_HEADING: &str = "## In QEMU: what each method costs";

/// The scenes `cargo xtask qemu --dither` also renders into other panel formats by every
/// method (the firmware's `panels` feature): the costs hardly depend on the scene.
const PANEL_SCENES: [&str; 2] = ["spec0", "translucent3"];

/// `<format>-<method>` of a panel frame's name (`truncated` for no method).
fn panel_of(way: &str) -> Option<(microray::dither::Format, Option<microray::dither::Method>)> {
    use microray::dither::{Format, Method};
    let (format, method) = way.split_once('-')?;
    let format = Format::from_name(format)?;
    if method == "truncated" {
        return Some((format, None));
    }
    Some((format, Some(Method::from_name(method)?)))
}

/// A panel frame's machine, number type, format and method.
type PanelKey<'r> = (&'r str, &'r str, String, String);

/// What each panel format and method costs over truncating into the same format.
fn panel_table(rows: &[Row], width: u16, height: u16) -> String {
    let pixels = f64::from(width) * f64::from(height);
    let mut out = format!(
        "\n### Every panel format and method\n\n\
         The scenes {} again at {width}x{height}, each into a one-bit panel and an Rgb565 one \
         through `microray::dither::Dither`, truncated and by every method (the diffusions \
         left to right; their row memory on the stack). Instructions a pixel, mean over the \
         scenes; cost: over truncating into the same format. Every frame is compared byte for \
         byte with the host's frame converted by `microray::host::panel` (identical).\n\n\
         | machine | number | format | method | instr/px | cost over truncated | identical |\n\
         |---|---|---|---|---|---|---|\n",
        PANEL_SCENES.join(" and ")
    );
    // (machine, number, format, method) -> instruction counts, all identical
    let mut cells: BTreeMap<PanelKey<'_>, (Vec<f64>, bool)> = BTreeMap::new();
    let mut order = Vec::new();
    for row in rows {
        let Some((_, way)) = row.scene.split_once("+panel-") else {
            continue;
        };
        let Some((format, method)) = way.split_once('-') else {
            continue;
        };
        let key = (
            row.machine,
            row.number_name(),
            format.to_string(),
            method.to_string(),
        );
        if !cells.contains_key(&key) {
            order.push(key.clone());
        }
        let cell = cells.entry(key).or_insert((Vec::new(), true));
        cell.0.push(row.insns as f64 / pixels);
        cell.1 &= matches!(row.identical, Ok(true));
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    for key in &order {
        let (counts, identical) = &cells[key];
        let base = cells
            .get(&(key.0, key.1, key.2.clone(), "truncated".to_string()))
            .map(|(c, _)| mean(c))
            .unwrap_or(f64::NAN);
        let m = mean(counts);
        out.push_str(&format!(
            "| {} | {} | {} | {} | {m:.0} | {:+.1} | {} |\n",
            key.0,
            key.1,
            key.2,
            key.3,
            m - base,
            if *identical { "yes" } else { "no" }
        ));
    }
    out
}

/// RGB bytes (`width` pixels a row) as an Rgb565 panel shows them, expanded back:
/// truncated (`Rgb565Dither::truncating`) or dithered (`Rgb565Dither`, which is `bayer4`).
fn rgb565(mut rgb: Vec<u8>, width: u16, dither: bool) -> Vec<u8> {
    use microray::dither::{Format, Matrix, Method};
    let method = dither.then_some(Method::Ordered(Matrix::Bayer4));
    microray::host::panel::by_position(
        &mut rgb,
        usize::from(width),
        (0, 0),
        Format::Rgb565,
        method,
    );
    rgb
}

/// What the Rgb565 dither costs, per scene, machine and number type: instructions a pixel
/// of the plain frame and of the dithered one.
fn dither_table(rows: &[Row], width: u16, height: u16) -> String {
    let pixels = f64::from(width) * f64::from(height);
    let mut out = format!(
        "\n### The Rgb565 dither (`Rgb565Dither`), every scene\n\n\
         Written by `cargo xtask qemu --dither`: every scene at {width}x{height}, rendered \
         plainly (Rgb888 rows out), and into an Rgb565 target through \
         `microray::dither::Rgb565Dither`, once truncating (`Rgb565Dither::truncating`: what \
         a panel costs without a dither) and once dithering; one target type, so both frames \
         run the same code but the conversion. The Rgb565 frames' \
         colours are pulled (and dithered) while counting, their expansion and writes are \
         not. Cost: the dithered frame's instructions a pixel over the truncated one's (and \
         over the plain one's). Both Rgb565 frames are compared byte for byte with the \
         host's frame converted the same way (identical).\n\n\
         | scene | machine | number | plain instr/px | truncated | dithered | cost over truncated | over plain | identical |\n\
         |---|---|---|---|---|---|---|---|---|\n"
    );
    let mut costs: BTreeMap<(&str, &str), Vec<f64>> = BTreeMap::new();
    for plain in rows.iter().filter(|r| !r.scene.contains('+')) {
        let find = |suffix: &str| {
            rows.iter().find(|r| {
                r.scene == format!("{}{suffix}", plain.scene)
                    && r.number == plain.number
                    && r.machine == plain.machine
            })
        };
        let (Some(dither), Some(truncated)) = (find("+dither"), find("+rgb565")) else {
            continue;
        };
        let per_pixel = |r: &Row| r.insns as f64 / pixels;
        let (a, t, d) = (per_pixel(plain), per_pixel(truncated), per_pixel(dither));
        let identical =
            matches!(dither.identical, Ok(true)) && matches!(truncated.identical, Ok(true));
        costs
            .entry((plain.machine, plain.number_name()))
            .or_default()
            .push(d - t);
        out.push_str(&format!(
            "| {} | {} | {} | {a:.0} | {t:.0} | {d:.0} | {:+.1} | {:+.1} | {} |\n",
            plain.scene,
            plain.machine,
            plain.number_name(),
            d - t,
            d - a,
            if identical { "yes" } else { "no" }
        ));
    }
    out.push_str("\nMedian cost over the truncated frame, instructions a pixel:");
    for ((machine, number), mut list) in costs {
        list.sort_by(f64::total_cmp);
        let median = list.get(list.len() / 2).copied().unwrap_or(0.0);
        out.push_str(&format!(" {machine} {number} {median:+.1};"));
    }
    out.push('\n');
    out
}
