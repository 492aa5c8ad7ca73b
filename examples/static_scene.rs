//! A scene written in Rust source, without the parser: what firmware that embeds its scene
//! does. Every definition is a `const`, so it lives in flash; `Scene::from_defs` checks it
//! and computes the per-object invariants once, at start-up.
//!
//! ```sh
//! cargo run --release --example static_scene -- static.png
//! ```

use microray::host::Framebuffer;
use microray::object::{RectDef, TextureMode};
use microray::render::render;
use microray::scene::TinyScene;
use microray::{CameraDef, LightDef, MaterialDef, ObjectDef, Scene, TextureDef};

const CAMERA: CameraDef<'static> = CameraDef::new("eye", [320, 240], [8.0, 6.0], [4.0, 3.0, 6.0]);

const MATERIALS: [MaterialDef<'static>; 4] = [
    MaterialDef::new("paper")
        .ambient([2.0, 2.0, 2.0])
        .diffuse([7.0, 7.0, 7.0]),
    MaterialDef::new("ink")
        .ambient([0.4, 0.4, 0.6])
        .diffuse([1.5, 1.5, 2.5]),
    MaterialDef::new("gold")
        .ambient([1.5, 1.1, 0.3])
        .diffuse([6.0, 4.5, 1.0])
        .specular(0.3)
        .shininess(80.0),
    MaterialDef::new("frame")
        .ambient([3.0, 3.0, 3.0])
        .diffuse([9.0, 9.0, 9.0]),
];

/// The project's test card, embedded at build time as firmware would.
const CARD: &[u8] = include_bytes!("../scenes/images/card.ppm");
const TEXTURES: [TextureDef<'static, 'static>; 1] = [TextureDef {
    name: "card",
    filename: "images/card.ppm",
    ppm: CARD,
}];

const LIGHTS: [LightDef<'static>; 2] = [
    LightDef::point("key", [1.0, 8.0, 2.0], [12.0, 12.0, 11.0]),
    LightDef::spot(
        "spot",
        [7.0, 7.0, -2.0],
        [8.0, 6.0, 3.0],
        [5.0, 0.0, -7.0],
        20.0,
    ),
];

const OBJECTS: [ObjectDef<'static>; 4] = [
    ObjectDef::tiled_plane(
        "floor",
        "paper",
        RectDef::new(
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0],
        ),
        "ink",
    ),
    ObjectDef::sphere("ball", "gold", [5.0, 1.5, -7.0], 1.5),
    ObjectDef::sphere("pebble", "gold", [2.2, 0.6, -5.0], 0.6),
    ObjectDef::texplane(
        "picture",
        "frame",
        RectDef::new(
            [0.0, 0.0, 1.0],
            [0.5, 1.0, -10.0],
            [1.0, 0.0, 0.0],
            [4.0, 4.0],
        ),
        "card",
        TextureMode::Fit,
    ),
];

/// Capacities sized to this scene: 4 objects, 4 materials, 2 lights, 1 texture, rows of 320.
type StaticScene = TinyScene<'static, f32>;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene: StaticScene = Scene::from_defs(&CAMERA, &MATERIALS, &TEXTURES, &LIGHTS, &OBJECTS)?;
    println!(
        "scene: {} bytes of RAM in f32",
        core::mem::size_of::<StaticScene>()
    );
    let mut image = Framebuffer::new(embedded_graphics::prelude::Size::new(320, 240));
    render(&scene, &mut image)?;
    let output = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "static.png".into());
    std::fs::write(&output, image.to_png()?)?;
    println!("wrote {output}");
    Ok(())
}
