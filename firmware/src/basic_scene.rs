//! The smallest scene in Rust source: planes and spheres, ambient and diffuse light, point
//! lights. It needs none of microray's optional features, so it is the scene of the minimal
//! firmware build (`--no-default-features`): build.rs compiles it (`Scene::write_compiled`)
//! and the minimal build loads that (`Scene::load_compiled`), with neither the loader's f64
//! arithmetic nor the parser; the full build loads these definitions. The host side of
//! `cargo xtask qemu` renders it from the definitions to compare.

use microray::{CameraDef, Error, LightDef, MaterialDef, ObjectDef, Scalar, Scene};

pub const NAME: &str = "basic";

pub const CAMERA: CameraDef<'static> =
    CameraDef::new("eye", [320, 240], [8.0, 6.0], [4.0, 3.0, 6.0]);

pub const MATERIALS: [MaterialDef<'static>; 3] = [
    MaterialDef::new("sand")
        .ambient([1.0, 0.9, 0.7])
        .diffuse([6.0, 5.4, 4.2]),
    MaterialDef::new("sky")
        .ambient([0.6, 0.8, 1.2])
        .diffuse([1.0, 1.5, 2.5]),
    MaterialDef::new("clay")
        .ambient([1.2, 0.4, 0.3])
        .diffuse([7.0, 2.5, 1.5]),
];

pub const LIGHTS: [LightDef<'static>; 2] = [
    LightDef::point("sun", [1.0, 9.0, 3.0], [14.0, 13.0, 12.0]),
    LightDef::point("fill", [8.0, 4.0, 2.0], [4.0, 4.0, 5.0]),
];

pub const OBJECTS: [ObjectDef<'static>; 4] = [
    ObjectDef::plane("ground", "sand", [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]),
    ObjectDef::plane("backdrop", "sky", [0.0, 0.0, 1.0], [0.0, 0.0, -12.0]),
    ObjectDef::sphere("big", "clay", [4.5, 1.5, -6.0], 1.5),
    ObjectDef::sphere("small", "clay", [2.0, 0.7, -4.5], 0.7),
];

/// Loads the scene from these definitions (the full build, and build.rs for the minimal).
pub fn load<
    S: Scalar,
    const O: usize,
    const M: usize,
    const L: usize,
    const T: usize,
    const W: usize,
>(
    scene: &mut Scene<'static, S, O, M, L, T, W>,
) -> Result<(), Error> {
    scene.load_defs(&CAMERA, &MATERIALS, &[], &LIGHTS, &OBJECTS)
}
