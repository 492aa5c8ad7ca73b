//! Range: scaling a scene at load by a power of two changes a floating-point image not at
//! all; a scene too large for Q16.16 is scaled into its range and still agrees with f64; what
//! cannot fit is a clear error.

mod common;

use microray::Scalar;
use microray::host::{Framebuffer, HostScene, texture_files};
use microray::parse::{choose_number_type, scene_extent};
use microray::parse::{parse_scene, parse_scene_with_scale};
use microray::print::print_scene;
use microray::range::{NumberType, Target};
use microray::render::{Renderer, render};
use microray::scalar::I16F16;
use std::path::{Path, PathBuf};

fn large() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/large.txt")
}

fn image<S: Scalar>(scene: &HostScene<'_, S>) -> Framebuffer {
    let mut image = Framebuffer::new(Renderer::new(scene).size());
    render(scene, &mut image).unwrap();
    image
}

fn scaled<S: Scalar>(path: &Path, scale: f64) -> HostScene<'static, S> {
    let text = std::fs::read(path).unwrap();
    parse_scene_with_scale(&text, texture_files(path.parent().unwrap()), scale)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn powers_of_two_leave_float_images_unchanged() {
    let mut scenes = common::project_scenes();
    if let Some(dir) = common::conformance_dir() {
        scenes.extend(common::scene_files(&dir));
    }
    for path in &scenes {
        let reference = image(&scaled::<f64>(path, 1.0));
        for scale in [0.125, 16.0] {
            assert_eq!(
                image(&scaled::<f64>(path, scale)),
                reference,
                "{} at {scale}",
                path.display()
            );
        }
        let reference = image(&scaled::<f32>(path, 1.0));
        assert_eq!(
            image(&scaled::<f32>(path, 0.25)),
            reference,
            "{} in f32",
            path.display()
        );
    }
}

#[test]
fn a_large_scene_is_scaled_into_fixed_point_range() {
    let text = std::fs::read(large()).unwrap();
    let extent = scene_extent(&text).unwrap();
    assert_eq!(extent.largest, 20000.0);
    // Emissivity 2e8 times 2^-14 is 12207, within Q16.16's shading budget of 16384.
    assert_eq!(extent.scale_for::<I16F16>(), 2f64.powi(-14));
    assert_eq!(extent.scale_for::<f32>(), 1.0);

    let fixed: HostScene<'_, I16F16> = parse_scene(&text, texture_files(Path::new("."))).unwrap();
    assert_eq!(fixed.scale(), 2f64.powi(-14));
    let exact: HostScene<'_, f64> = parse_scene(&text, texture_files(Path::new("."))).unwrap();
    let (a, b) = (image(&exact), image(&fixed));
    let n = a.rgb().len() / 3;
    let mut within_one = 0;
    for (p, q) in a.rgb().chunks(3).zip(b.rgb().chunks(3)) {
        within_one += usize::from(p.iter().zip(q).all(|(x, y)| x.abs_diff(*y) <= 1));
    }
    assert!(
        within_one as f64 >= 0.99 * n as f64,
        "{within_one} of {n} within ±1"
    );

    // The printer writes the scene's own units back, and they read back equal.
    let mut printed = String::new();
    print_scene(&fixed, &mut printed).unwrap();
    assert!(
        printed.contains("  center 8e3 3e3 -12000\n  radius 3e3\n"),
        "{printed}"
    );
    let again: HostScene<'_, I16F16> =
        parse_scene(printed.as_bytes(), texture_files(Path::new("."))).unwrap();
    assert_eq!(again, fixed);

    // Used as written, it does not fit Q16.16: a clear error, not a wrong image.
    let unscaled = parse_scene_with_scale::<I16F16, 8, 8, 2, 0, 320>(
        &text,
        texture_files(Path::new(".")),
        1.0,
    );
    assert_eq!(
        unscaled.unwrap_err().to_string(),
        "35:3: `radius` is beyond the range of i16f16, the number type of this build"
    );
}

#[test]
fn features_below_the_resolution_are_errors() {
    let text = b"camera c { pixeldim 8 6 worlddim 8 6 viewpoint 4 3 3 }
        material m { diffuse 1 1 1 }
        sphere grain { material m center 4 3 -5 radius 0.001 }";
    let e = parse_scene::<I16F16, 4, 4, 1, 0, 8>(text, texture_files(Path::new("."))).unwrap_err();
    assert_eq!(
        e.to_string(),
        "3:49: `radius` is too small for i16f16, the number type of this build (below its resolution once the scene is scaled to its range)"
    );
    assert!(parse_scene::<f32, 4, 4, 1, 0, 8>(text, texture_files(Path::new("."))).is_ok());
    assert_eq!(
        choose_number_type(text, Target::NoFpu).unwrap(),
        NumberType::F32
    );
}

#[test]
fn number_type_choice() {
    let text = std::fs::read(large()).unwrap();
    assert_eq!(
        choose_number_type(&text, Target::Host).unwrap(),
        NumberType::F64
    );
    assert_eq!(
        choose_number_type(&text, Target::SinglePrecisionFpu).unwrap(),
        NumberType::F32
    );
    assert_eq!(
        choose_number_type(&text, Target::NoFpu).unwrap(),
        NumberType::I16F16
    );
    for path in common::project_scenes() {
        let text = std::fs::read(&path).unwrap();
        assert_eq!(
            choose_number_type(&text, Target::NoFpu).unwrap(),
            NumberType::I16F16,
            "{}",
            path.display()
        );
    }
    let broken = choose_number_type(b"camera c {", Target::Host).unwrap_err();
    assert_eq!(
        broken.to_string(),
        "1:11: expected `}` to close the camera block opened at 1:10, found end of file"
    );
}
