//! A scene written in Rust source, without the parser: every definition is a `const` in
//! flash. Shared with the host side of `cargo xtask qemu`, which renders it to compare.

use microray::object::{RectDef, TextureMode};
use microray::{CameraDef, LightDef, MaterialDef, ObjectDef, TextureDef};

pub const NAME: &str = "static";

pub const CAMERA: CameraDef<'static> =
    CameraDef::new("eye", [320, 240], [8.0, 6.0], [4.0, 3.0, 6.0]);

pub const MATERIALS: [MaterialDef<'static>; 4] = [
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

pub const TEXTURES: [TextureDef<'static, 'static>; 1] = [TextureDef {
    name: "card",
    filename: "images/card.ppm",
    ppm: include_bytes!("../../scenes/images/card.ppm"),
}];

pub const LIGHTS: [LightDef<'static>; 2] = [
    LightDef::point("key", [1.0, 8.0, 2.0], [12.0, 12.0, 11.0]),
    LightDef::spot(
        "spot",
        [7.0, 7.0, -2.0],
        [8.0, 6.0, 3.0],
        [5.0, 0.0, -7.0],
        20.0,
    ),
];

pub const OBJECTS: [ObjectDef<'static>; 4] = [
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
