//! Every course and project scene parses, and the printer round-trips it: parsing what the
//! printer wrote gives an equal scene, and printing that again gives identical text.

mod common;

use microray::Scalar;
use microray::host::{HostScene, texture_files};
use microray::parse::{no_textures, parse_scene};
use microray::print::print_scene;
use std::path::Path;

fn print<S: Scalar>(scene: &HostScene<'_, S>) -> String {
    let mut text = String::new();
    print_scene(scene, &mut text).unwrap();
    text
}

fn round_trip<S: Scalar>(path: &Path) {
    let text = std::fs::read(path).unwrap();
    let dir = path.parent().unwrap();
    let scene: HostScene<'_, S> = parse_scene(&text, texture_files(dir))
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let printed = print(&scene);
    let again: HostScene<'_, S> = parse_scene(printed.as_bytes(), texture_files(dir))
        .unwrap_or_else(|e| panic!("{} printed:\n{printed}\n{e}", path.display()));
    assert_eq!(
        again,
        scene,
        "{} ({}): re-read scene differs",
        path.display(),
        S::NAME
    );
    assert_eq!(
        print(&again),
        printed,
        "{} ({}): second print differs",
        path.display(),
        S::NAME
    );
}

#[test]
#[cfg_attr(
    not(microray_conformance),
    ignore = "needs the course's scenes: set MICRORAY_CONFORMANCE to their folder"
)]
fn conformance_scenes_parse_and_round_trip() {
    let dir = common::required_conformance_dir();
    let files = common::scene_files(&dir);
    assert!(
        files.len() >= 17,
        "expected the course's 17 scenes, found {}",
        files.len()
    );
    for path in &files {
        round_trip::<f64>(path);
        round_trip::<f32>(path);
    }
    eprintln!(
        "{} conformance scenes parsed and round-tripped in f64 and f32",
        files.len()
    );
}

#[test]
#[cfg_attr(
    not(microray_conformance),
    ignore = "needs the course's scenes: set MICRORAY_CONFORMANCE to their folder"
)]
fn later_course_scenes_parse_and_round_trip() {
    // Projectors, surfaces of revolution, `specular r g b`, `texname FILE`.
    let dir = common::required_course_extensions_dir();
    let files = common::scene_files(&dir);
    assert_eq!(files.len(), 5, "expected the course's 5 later scenes");
    for path in &files {
        round_trip::<f64>(path);
        round_trip::<f32>(path);
    }
}

#[test]
fn project_scenes_parse_and_round_trip() {
    let files = common::project_scenes();
    assert!(!files.is_empty());
    for path in &files {
        round_trip::<f64>(path);
        round_trip::<f32>(path);
    }
}

#[test]
fn printed_values_are_as_written_not_normalised() {
    let text = b"camera c { pixeldim 4 4 worlddim 1 1 viewpoint 0 0 1 }
        material m { diffuse 1 1 1 }
        plane p { material m normal 0 3 4 point 0 0 -1e-7 }";
    let scene: HostScene<'_, f64> = parse_scene(text, no_textures).unwrap();
    let printed = print(&scene);
    assert!(
        printed.contains("  normal 0 3 4\n  point 0 0 -1e-7\n"),
        "{printed}"
    );
}
