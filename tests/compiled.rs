//! Compiled scenes: every course and project scene, compiled in each number type and loaded
//! back, is the same scene and renders the same image; malformed bytes are errors that name
//! the byte, never a panic.

mod common;

use microray::error::{CompiledError, ErrorKind};
use microray::host::{Framebuffer, HostScene, texture_files};
use microray::parse::{no_textures, parse_scene};
use microray::render::Renderer;
use microray::scalar::I16F16;
use microray::{Scalar, Scene};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

fn scenes() -> Vec<PathBuf> {
    let mut scenes = common::project_scenes();
    if let Some(dir) = common::conformance_dir() {
        scenes.extend(common::scene_files(&dir));
    }
    scenes
}

fn compile<S: Scalar>(scene: &HostScene<'_, S>) -> Vec<u8> {
    let mut bytes = Vec::new();
    scene.write_compiled(&mut |piece| bytes.extend_from_slice(piece));
    bytes
}

fn image<S: Scalar>(scene: &HostScene<'_, S>) -> Framebuffer {
    common::image(&Renderer::new(scene))
}

fn same_scene_and_image<S: Scalar>(path: &Path) {
    let text = std::fs::read(path).unwrap();
    let textures = || texture_files(path.parent().unwrap());
    let scene: HostScene<'static, S> = parse_scene(&text, textures()).unwrap();
    let bytes = compile(&scene);
    let mut loaded: Box<HostScene<'static, S>> = Box::new(Scene::empty());
    loaded
        .load_compiled(&bytes, textures())
        .unwrap_or_else(|e| panic!("{} ({}): {e}", path.display(), S::NAME));
    assert_eq!(*loaded, scene, "{} ({})", path.display(), S::NAME);
    // Equal values; the same image shows the kinds' tables were installed alike too.
    assert!(
        image(&loaded).rgb() == image(&scene).rgb(),
        "{} ({}): images differ",
        path.display(),
        S::NAME
    );
    // Compiling the loaded scene gives the same bytes.
    assert_eq!(compile(&loaded), bytes, "{} ({})", path.display(), S::NAME);
}

#[test]
fn every_scene_compiles_and_loads_back_in_every_number_type() {
    let files = scenes();
    assert!(files.len() >= 7, "{} scenes", files.len());
    for path in &files {
        same_scene_and_image::<f64>(path);
        same_scene_and_image::<f32>(path);
        same_scene_and_image::<I16F16>(path);
    }
}

type Small = Scene<'static, f32, 4, 4, 2, 0, 64>;

const SCENE: &[u8] = b"camera c { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 4 }
    material red { diffuse 4 0 0 }
    material blue { diffuse 0 0 4 }
    light sun { location 4 8 2 emissivity 5 5 5 }
    plane floor { material blue normal 0 1 0 point 0 0 0 }
    sphere ball { material red center 4 3 -6 radius 2 }";

fn small_bytes() -> Vec<u8> {
    let scene: HostScene<'_, f32> = parse_scene(SCENE, no_textures).unwrap();
    compile(&scene)
}

fn load_small(bytes: &[u8]) -> Result<Box<Small>, ErrorKind> {
    let mut scene = Box::new(Small::empty());
    scene
        .load_compiled(bytes, no_textures)
        .map_err(|e| e.kind)?;
    Ok(scene)
}

#[test]
fn every_truncation_and_trailing_byte_is_an_error() {
    let bytes = small_bytes();
    assert!(load_small(&bytes).is_ok());
    for len in 0..bytes.len() {
        let error = load_small(&bytes[..len]).unwrap_err();
        assert!(
            matches!(
                error,
                ErrorKind::Compiled {
                    problem: CompiledError::Truncated | CompiledError::NotCompiled,
                    ..
                }
            ),
            "{len}: {error:?}"
        );
    }
    let mut longer = bytes.clone();
    longer.push(0);
    assert_eq!(
        load_small(&longer).unwrap_err(),
        ErrorKind::Compiled {
            offset: bytes.len() as u32,
            problem: CompiledError::Trailing
        }
    );
}

#[test]
fn header_number_type_index_and_kind_are_checked() {
    let bytes = small_bytes();
    let not = |b: &mut Vec<u8>| b[0] = b'x';
    let mut changed = bytes.clone();
    not(&mut changed);
    assert!(matches!(
        load_small(&changed).unwrap_err(),
        ErrorKind::Compiled {
            offset: 0,
            problem: CompiledError::NotCompiled
        }
    ));
    // f32 bytes into an I16F16 scene.
    let mut fixed: Box<Scene<'static, I16F16, 4, 4, 2, 0, 64>> = Box::new(Scene::empty());
    assert_eq!(
        fixed.load_compiled(&bytes, no_textures).unwrap_err().kind,
        ErrorKind::Compiled {
            offset: 5,
            problem: CompiledError::OtherNumberType { found: 2 }
        }
    );
    // The last object is the sphere: name `ball`, material index, kind, 5 numbers.
    let sphere = bytes.len() - (1 + 4 + 2 + 1 + 5 * 4);
    let material = sphere + 5;
    let mut changed = bytes.clone();
    changed[material] = 2;
    assert_eq!(
        load_small(&changed).unwrap_err(),
        ErrorKind::Compiled {
            offset: material as u32,
            problem: CompiledError::BadIndex
        }
    );
    let mut changed = bytes.clone();
    changed[material + 2] = 9;
    assert_eq!(
        load_small(&changed).unwrap_err(),
        ErrorKind::Compiled {
            offset: material as u32 + 2,
            problem: CompiledError::BadValue
        }
    );
    // A world window that is not positive (the loaders reject it; stepping along it would
    // not be defined): after the header (14 bytes), the limits (8) and the camera's name
    // (2), width and height (4).
    let world = 14 + 8 + 2 + 4;
    for bad in [-1.0f32, 0.0, f32::NAN] {
        let mut changed = bytes.clone();
        changed[world..world + 4].copy_from_slice(&bad.to_le_bytes());
        assert_eq!(
            load_small(&changed).unwrap_err(),
            ErrorKind::Compiled {
                offset: world as u32,
                problem: CompiledError::BadValue
            }
        );
    }
    // A scene too small for what the bytes hold.
    let mut narrow: Box<Scene<'static, f32, 1, 4, 2, 0, 64>> = Box::new(Scene::empty());
    assert!(matches!(
        narrow.load_compiled(&bytes, no_textures).unwrap_err().kind,
        ErrorKind::CapacityExceeded { .. }
    ));
    let mut thin: Box<Scene<'static, f32, 4, 4, 2, 0, 32>> = Box::new(Scene::empty());
    assert!(matches!(
        thin.load_compiled(&bytes, no_textures).unwrap_err().kind,
        ErrorKind::ImageTooWide { width: 64, max: 32 }
    ));
}

#[test]
fn every_single_byte_change_loads_or_is_an_error() {
    // No byte value anywhere makes the reader or a render of what it read panic.
    let bytes = small_bytes();
    let mut loaded = 0;
    for i in 0..bytes.len() {
        for value in [0u8, 1, 2, 5, 0x7f, 0x80, 0xff] {
            let mut changed = bytes.clone();
            changed[i] = value;
            if let Ok(scene) = load_small(&changed) {
                loaded += 1;
                let renderer = Renderer::new(&*scene);
                let size = renderer.size();
                let mut image = Framebuffer::new(size);
                let mut row = vec![Default::default(); size.width as usize];
                let all = embedded_graphics::primitives::Rectangle::new(Default::default(), size);
                let _ =
                    renderer.render_area(&mut image, all, &mut row, |_| ControlFlow::Continue(()));
            }
        }
    }
    assert!(loaded > 0);
}
