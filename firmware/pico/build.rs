//! Puts `memory.x` where cortex-m-rt's linker script finds it, and embeds the scene: the
//! file `MICRORAY_PICO_SCENE` names (default: the project's showcase) with the textures it
//! names, and the capacities its `Scene` type needs (`scene.rs` in `OUT_DIR`).

// The texture look-up the QEMU firmware's build script uses.
#[path = "../scene_files.rs"]
mod scene_files;

use microray::capacity::Capacities;
use std::fmt::Write as _;
use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var("OUT_DIR").unwrap());
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").unwrap());
    fs::write(out.join("memory.x"), include_bytes!("memory.x")).unwrap();
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-env-changed=MICRORAY_PICO_SCENE");
    // The OLED example's dither method (src/bin/oled.rs reads it with `option_env!`).
    println!("cargo:rerun-if-env-changed=MICRORAY_OLED_DITHER");

    let scene = env::var_os("MICRORAY_PICO_SCENE")
        .map(PathBuf::from)
        .unwrap_or_else(|| manifest.join("../../scenes/showcase.txt"));
    let scene = scene
        .canonicalize()
        .unwrap_or_else(|e| panic!("MICRORAY_PICO_SCENE {}: {e}", scene.display()));
    println!("cargo:rerun-if-changed={}", scene.display());
    let text = fs::read_to_string(&scene).unwrap();
    let textures = scene_files::texture_files(&text, scene.parent().unwrap());
    let Capacities {
        objects,
        materials,
        lights,
        textures: texture_slots,
        max_width,
    } = Capacities::of_text(text.as_bytes());
    let mut table = String::new();
    for (written, file) in &textures {
        println!("cargo:rerun-if-changed={}", file.display());
        write!(
            table,
            "({written:?}, include_bytes!({:?})), ",
            file.display().to_string()
        )
        .unwrap();
    }
    // The number type: Q16.16 unless the `f32` feature.
    let number = if env::var_os("CARGO_FEATURE_F32").is_some() {
        "f32"
    } else {
        "microray::scalar::I16F16"
    };
    // At least one slot of each: the type's capacities are its arrays' lengths.
    let generated = format!(
        "/// The embedded scene file.\npub const TEXT: &str = include_str!({:?});\n\
         /// The texture files it names, by the name it gives them.\n\
         pub const TEXTURES: &[(&str, &[u8])] = &[{table}];\n\
         /// What its `Scene` holds: objects, materials, lights, textures, the widest image.\n\
         pub type PicoScene = microray::Scene<'static, {number}, {}, {}, {}, {}, {}>;\n",
        scene.display().to_string(),
        objects.max(1),
        materials.max(1),
        lights.max(1),
        texture_slots.max(1),
        max_width.max(1),
    );
    fs::write(out.join("scene.rs"), generated).unwrap();
}
