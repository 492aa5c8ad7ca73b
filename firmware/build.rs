//! Chooses the machine's memory layout and embeds the scenes (course scenes from
//! `MICRORAY_CONFORMANCE`, default `../../shared/conformance`, and the project's own) with
//! their textures, as `include_str!`/`include_bytes!` of their files; compiles the `basic`
//! scene in source for the firmware's number type and image size (`basic.mray`).

// The scene's definitions; its name is the firmware's business.
#[allow(dead_code)]
#[path = "src/basic_scene.rs"]
mod basic_scene;
// What the Pico's build script shares.
#[path = "scene_files.rs"]
mod scene_files;

use microray::capacity::Capacities;
use std::env;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

fn main() {
    let out = PathBuf::from(env::var("OUT_DIR").unwrap());
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").unwrap());
    let microbit = env::var_os("CARGO_FEATURE_MICROBIT").is_some();
    // Without the `full` feature there is no parser: no scene files.
    let parser = env::var_os("CARGO_FEATURE_FULL").is_some();
    let memory = if microbit {
        // nRF51822: 256 KiB flash, 16 KiB RAM.
        "MEMORY { FLASH : ORIGIN = 0x00000000, LENGTH = 256K\n RAM : ORIGIN = 0x20000000, LENGTH = 16K }\n"
    } else {
        // MPS2 AN386: 4 MiB SSRAM1 for code, 4 MiB SSRAM2/3 for data.
        "MEMORY { FLASH : ORIGIN = 0x00000000, LENGTH = 4M\n RAM : ORIGIN = 0x20000000, LENGTH = 4M }\n"
    };
    fs::write(out.join("memory.x"), memory).unwrap();
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=MICRORAY_CONFORMANCE");
    println!("cargo:rerun-if-env-changed=MICRORAY_FW_SIZE");
    println!("cargo:rerun-if-env-changed=MICRORAY_FW_ONLY");
    println!("cargo:rerun-if-env-changed=MICRORAY_FW_PLAN");
    println!("cargo:rerun-if-env-changed=MICRORAY_FW_FRAMES");
    // With `animate`: play only each film's first frames (all when unset or 0).
    let frames: u16 = env::var("MICRORAY_FW_FRAMES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    // `compare`: each scene is rendered twice, with the render plan and without.
    let compare_plan = env::var("MICRORAY_FW_PLAN").is_ok_and(|v| v == "compare");
    // `progressive`: each scene is rendered plainly, then in the progressive order into a
    // frame in RAM, counting the first pass and the rest apart (the M4F board only).
    let progressive = env::var("MICRORAY_FW_PLAN").is_ok_and(|v| v == "progressive");
    // `dither`: each scene is rendered plainly, then into an Rgb565 target through
    // `microray::dither::Rgb565Dither` (written back as 8-bit channels).
    let dither = env::var("MICRORAY_FW_PLAN").is_ok_and(|v| v == "dither");
    // With the `panels` feature, the scenes (comma-separated) that are also rendered through
    // `microray::dither::Dither` into other panel formats, by every method.
    println!("cargo:rerun-if-env-changed=MICRORAY_FW_PANELS");
    let panel_scenes: Vec<String> = env::var("MICRORAY_FW_PANELS")
        .unwrap_or_default()
        .split(',')
        .filter(|s| !s.is_empty())
        .map(|s| format!("{s:?}"))
        .collect();
    let panel_scenes = panel_scenes.join(", ");
    // `antialias`: each scene is rendered plainly, then anti-aliased with 4, 9 and 16
    // samples a pixel and adaptively (needs the firmware's `antialias` feature).
    let antialias = env::var("MICRORAY_FW_PLAN").is_ok_and(|v| v == "antialias");
    assert!(
        !antialias || env::var_os("CARGO_FEATURE_ANTIALIAS").is_some(),
        "MICRORAY_FW_PLAN=antialias needs the firmware's `antialias` feature"
    );
    // `animate`: each scene with an `animation` plays it, every frame after the first
    // rendered in its region and then whole (needs the firmware's `animate` feature).
    let animate = env::var("MICRORAY_FW_PLAN").is_ok_and(|v| v == "animate");
    assert!(
        !animate || env::var_os("CARGO_FEATURE_ANIMATE").is_some(),
        "MICRORAY_FW_PLAN=animate needs the firmware's `animate` feature"
    );
    // Objects a scene holds: the micro:bit's 16 KiB of RAM has room for a few; the MPS2
    // board's 4 MiB for the project's scene of a hundred spheres.
    let objects: usize = if microbit { 6 } else { 128 };
    // A comma-separated list of scene names to embed, files and the scenes in source (`static`,
    // `basic`) alike (all when unset; `none`: none).
    let only: Option<Vec<String>> = env::var("MICRORAY_FW_ONLY")
        .ok()
        .filter(|s| !s.is_empty())
        .map(|s| s.split(',').map(str::to_string).collect());

    let size = env::var("MICRORAY_FW_SIZE").unwrap_or_else(|_| "160x120".into());
    let (width, height) = size
        .split_once('x')
        .expect("MICRORAY_FW_SIZE is WIDTHxHEIGHT");

    let (width, height): (u16, u16) = (width.parse().unwrap(), height.parse().unwrap());
    println!("cargo:rerun-if-changed=src/basic_scene.rs");
    let basic = if env::var_os("CARGO_FEATURE_FIXED").is_some() {
        compile_basic::<microray::scalar::I16F16>(width, height)
    } else {
        compile_basic::<f32>(width, height)
    };
    fs::write(out.join("basic.mray"), basic).unwrap();

    let conformance = env::var_os("MICRORAY_CONFORMANCE")
        .map(PathBuf::from)
        .unwrap_or_else(|| manifest.join("../../shared/conformance"));
    let conformance = if conformance.is_relative() {
        manifest.join("..").join(conformance)
    } else {
        conformance
    };
    let mut files = Vec::new();
    collect(&conformance, &mut files);
    collect(&manifest.join("../scenes"), &mut files);
    collect(&manifest.join("../tests/scenes"), &mut files);

    // The micro:bit's 256 KiB of flash cannot hold the course's photographs (192 and 432 KiB).
    let texture_budget = if microbit { 16 * 1024 } else { usize::MAX };
    // The scenes in source run unless `MICRORAY_FW_ONLY` leaves them out (`static` needs the
    // full build's features).
    let wanted = |name: &str| {
        only.as_ref()
            .is_none_or(|names| names.iter().any(|n| n == name))
    };
    let run_static = parser && wanted("static");
    let run_basic = wanted("basic");
    // The scene's capacities: what the embedded scenes need (the scenes in source: `basic`
    // has 4 objects, 3 materials and 2 lights; `static` 4, 4, 2 and a texture), so that its
    // RAM is what a firmware author sizing a scene would give it.
    let in_source = [
        (run_basic, in_source(4, 3, 2, 0)),
        (run_static, in_source(4, 4, 2, 1)),
    ];
    let mut capacity = Capacities::ZERO;
    for (_, needs) in in_source.iter().filter(|(runs, _)| *runs) {
        capacity = capacity.max(*needs);
    }

    let mut table = String::from("pub const SCENES: &[SceneFile] = &[\n");
    let mut skipped = String::from("pub const SKIPPED: &[(&str, &str)] = &[\n");
    for path in files {
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        if !parser || only.as_ref().is_some_and(|names| !names.contains(&name)) {
            continue;
        }
        let text = fs::read_to_string(&path).unwrap();
        let textures = scene_files::texture_files(&text, path.parent().unwrap());
        let bytes: usize = textures
            .iter()
            .map(|(_, p)| fs::metadata(p).map(|m| m.len() as usize).unwrap_or(0))
            .sum();
        if bytes > texture_budget {
            let why = format!("its textures ({bytes} bytes) do not fit this machine's flash");
            writeln!(skipped, "    ({name:?}, {why:?}),").unwrap();
            continue;
        }
        // A film's motion blocks need the `animate` feature to load: the other builds
        // leave a film out, as a build leaves out a scene whose kinds it lacks, or, when
        // `MICRORAY_FW_ONLY` names it (the flash of `cargo xtask qemu --animations`, without
        // the feature), render its scene without them (frame 0), from a copy in OUT_DIR.
        let film = text
            .lines()
            .any(|l| l.split_whitespace().next() == Some("animation"));
        let still = film && env::var_os("CARGO_FEATURE_ANIMATE").is_none();
        let named = only.as_ref().is_some_and(|names| names.contains(&name));
        if still && !named {
            let why = "a film: it needs the firmware's `animate` feature (`cargo xtask qemu --animations`)";
            writeln!(skipped, "    ({name:?}, {why:?}),").unwrap();
            continue;
        }
        let (embedded, text) = if still {
            let still = without_motions(&text);
            let out = PathBuf::from(env::var("OUT_DIR").unwrap()).join(format!("{name}.txt"));
            fs::write(&out, &still).unwrap();
            (out, still)
        } else {
            (path.clone(), text)
        };
        // The library's count, as a firmware author's `const` would make it.
        let needs = Capacities::of_text(text.as_bytes());
        let count = needs.objects;
        if count > objects {
            let why = format!("its {count} objects do not fit this machine's RAM ({objects})");
            writeln!(skipped, "    ({name:?}, {why:?}),").unwrap();
            continue;
        }
        capacity = capacity.max(needs);
        println!("cargo:rerun-if-changed={}", path.display());
        write!(
            table,
            "    SceneFile {{ name: {name:?}, text: include_str!({:?}), textures: &[",
            embedded.display().to_string()
        )
        .unwrap();
        for (written, file) in &textures {
            write!(
                table,
                "({written:?}, include_bytes!({:?})), ",
                file.display().to_string()
            )
            .unwrap();
        }
        table.push_str("] },\n");
    }
    table.push_str("];\n");
    skipped.push_str("];\n");
    let Capacities {
        objects,
        materials,
        lights,
        textures,
        ..
    } = capacity;
    let generated = format!(
        "pub const WIDTH: u16 = {width};\npub const HEIGHT: u16 = {height};\n\
         pub const OBJECTS: usize = {objects};\npub const MATERIALS: usize = {materials};\n\
         pub const LIGHTS: usize = {lights};\npub const TEXTURES: usize = {textures};\n\
         pub const COMPARE_PLAN: bool = {compare_plan};\n\
         pub const PROGRESSIVE: bool = {progressive};\n\
         pub const DITHER: bool = {dither};\n\
         #[allow(dead_code)] pub const PANEL_SCENES: &[&str] = &[{panel_scenes}];\n\
         pub const ANTIALIAS: bool = {antialias};\n\
         #[allow(dead_code)] pub const ANIMATE: bool = {animate};\n\
         #[allow(dead_code)] pub const FRAMES: u16 = {frames};\n\
         pub const RUN_STATIC: bool = {run_static};\npub const RUN_BASIC: bool = {run_basic};\n\
         {table}{skipped}"
    );
    fs::write(out.join("scenes.rs"), generated).unwrap();
}

/// The `basic` scene loaded as the firmware would load it, at the firmware's image size,
/// as a compiled scene.
fn compile_basic<S: microray::Scalar>(width: u16, height: u16) -> Vec<u8> {
    let mut scene: Box<microray::Scene<'static, S>> = Box::new(microray::Scene::empty());
    basic_scene::load(&mut scene).unwrap();
    scene.set_resolution(width, height).unwrap();
    let mut bytes = Vec::new();
    scene.write_compiled(&mut |piece| bytes.extend_from_slice(piece));
    bytes
}

fn collect(dir: &Path, files: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let mut found: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).collect();
    found.sort();
    for path in found {
        if path.is_dir() {
            collect(&path, files);
        } else if path.extension().is_some_and(|e| e == "txt") {
            files.push(path.canonicalize().unwrap());
        }
    }
}

/// The capacities of a scene in source (its width is the firmware's).
const fn in_source(objects: usize, materials: usize, lights: usize, textures: usize) -> Capacities {
    Capacities {
        objects,
        materials,
        lights,
        textures,
        max_width: 0,
    }
}

/// A film's text without its motion blocks (`animation`, `line`, `orbit`, `bounce`: each
/// from its keyword's line to the brace that closes it, comments skipped).
fn without_motions(text: &str) -> String {
    const MOTIONS: [&str; 4] = ["animation", "line", "orbit", "bounce"];
    let mut out = String::new();
    let mut depth = 0usize;
    let mut skipping = false;
    for line in text.lines() {
        let code = line.split('#').next().unwrap_or("");
        if depth == 0 && !skipping {
            skipping = code
                .split_whitespace()
                .next()
                .is_some_and(|word| MOTIONS.contains(&word));
        }
        let opens = code.matches('{').count();
        let closes = code.matches('}').count();
        if !skipping {
            out.push_str(line);
            out.push('\n');
        }
        depth = (depth + opens).saturating_sub(closes);
        if skipping && depth == 0 && closes > 0 {
            skipping = false;
        }
    }
    out
}
