//! Numerical stress: the scenes in `tests/stress/`, each rendered in every number type and
//! compared with f64, by the object each pixel sees and by pixels. Where a type cannot hold a
//! scene, the scene must be rejected at load with a range error, not rendered wrong. Prints
//! the table docs/number-types.md's stability section quotes, and asserts the bounds measured there.

mod common;

use microray::host::{Difference, Framebuffer, HostRenderer, HostScene, object_ids, texture_files};
use microray::parse::parse_scene;
use microray::render::{Renderer, render};
use microray::scalar::I16F16;
use microray::{ErrorKind, Scalar};
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn stress_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/stress")
}

struct Image {
    rgb: Vec<u8>,
    ids: Vec<Option<usize>>,
    /// Pixels that are ties in exact arithmetic (see `common::ties`; the f64 image's).
    ties: Vec<bool>,
}

fn load<S: Scalar>(path: &Path) -> Result<HostScene<'static, S>, microray::Error> {
    let text = std::fs::read(path).unwrap();
    parse_scene(&text, texture_files(path.parent().unwrap()))
}

fn image<S: Scalar>(scene: &HostScene<'_, S>) -> Image {
    let renderer: HostRenderer<'_, S> = Renderer::new(scene);
    let mut frame = Framebuffer::new(renderer.size());
    render(scene, &mut frame).unwrap();
    let rgb = frame.rgb().to_vec();
    for c in &rgb {
        // Nothing to check on a byte; the render returning at all is the no-panic check.
        let _ = c;
    }
    Image {
        rgb,
        ids: object_ids(&renderer),
        ties: Vec::new(),
    }
}

/// The f64 image, with its exact ties.
fn reference_image(scene: &HostScene<'_, f64>) -> Image {
    Image {
        ties: common::ties(scene),
        ..image(scene)
    }
}

/// How one type's image compares with the f64 image of the same scene.
#[derive(Debug)]
struct Comparison {
    identical: f64,
    within_one: f64,
    psnr: f64,
    /// Pixels that see another object, in percent.
    other_object: f64,
    appeared: BTreeSet<usize>,
    vanished: BTreeSet<usize>,
}

fn compare(reference: &Image, other: &Image) -> Comparison {
    let tie = |i: usize| reference.ties.get(i).copied().unwrap_or(false);
    let pixels = Difference::between(&reference.rgb, &other.rgb, tie);
    let counted = (0..reference.ids.len()).filter(|&i| !tie(i)).count();
    let mismatched = (0..reference.ids.len())
        .filter(|&i| !tie(i) && reference.ids[i] != other.ids[i])
        .count();
    let seen = |image: &Image| image.ids.iter().flatten().copied().collect::<BTreeSet<_>>();
    let (before, after) = (seen(reference), seen(other));
    Comparison {
        identical: pixels.identical_percent(),
        within_one: pixels.within_one_percent(),
        psnr: pixels.psnr(),
        other_object: 100.0 * mismatched as f64 / counted.max(1) as f64,
        appeared: after.difference(&before).copied().collect(),
        vanished: before.difference(&after).copied().collect(),
    }
}

/// What a type must achieve on a scene: at least this share of pixels within ±1 of f64, at
/// most this share seeing another object, no object appearing or vanishing. `None`: the
/// scene must be rejected at load with a range error.
type Bound = Option<(f64, f64)>;

/// The bounds, per scene, for f32 and for I16F16 (measured values in docs/number-types.md; the bounds
/// leave a margin below them).
const BOUNDS: [(&str, Bound, Bound); 12] = [
    ("far_1", Some((99.9, 0.05)), Some((99.0, 0.2))),
    ("far_100", Some((99.9, 0.05)), Some((99.0, 0.2))),
    ("far_1000", Some((99.9, 0.05)), None),
    ("huge_floor", Some((99.0, 0.1)), None),
    ("tiny_sphere", Some((99.9, 0.01)), Some((97.0, 1.0))),
    ("grazing", Some((99.0, 0.1)), None),
    ("parallel_planes", Some((99.0, 0.5)), Some((97.0, 3.0))),
    ("close_light", Some((99.9, 0.01)), Some((99.0, 0.2))),
    ("mirror_pair", Some((99.0, 0.1)), Some((95.0, 1.0))),
    ("revsurf_on_axis", Some((99.9, 0.05)), Some((99.9, 0.05))),
    ("projector_grazing", Some((99.9, 0.0)), Some((99.9, 0.0))),
    ("projector_behind", Some((99.8, 0.0)), Some((99.9, 0.0))),
];

fn check<S: Scalar>(
    name: &str,
    path: &Path,
    reference: &Image,
    bound: Bound,
    table: &mut String,
    failures: &mut Vec<String>,
) {
    match (load::<S>(path), bound) {
        (Ok(scene), Some((within_one, other_object))) => {
            let c = compare(reference, &image(&scene));
            writeln!(
                table,
                "| {name} | {} | scale {} | {:.3} | {:.3} | {:.1} | {:.3} |",
                S::NAME,
                scene.scale(),
                c.identical,
                c.within_one,
                c.psnr,
                c.other_object
            )
            .unwrap();
            if !(c.within_one >= within_one
                && c.other_object <= other_object
                && c.appeared.is_empty()
                && c.vanished.is_empty())
            {
                failures.push(format!("{name} in {}: {c:?}", S::NAME));
            }
        }
        (Ok(_), None) => failures.push(format!(
            "{name} in {}: loads, but the type cannot hold it",
            S::NAME
        )),
        (Err(e), None) => {
            writeln!(
                table,
                "| {name} | {} | rejected: {} | | | | |",
                S::NAME,
                e.kind
            )
            .unwrap();
            if !matches!(
                e.kind,
                ErrorKind::TooSmallForType { .. }
                    | ErrorKind::ScaledBelowResolution { .. }
                    | ErrorKind::BeyondRange { .. }
                    | ErrorKind::PixelsTooFine { .. }
            ) {
                failures.push(format!("{name} in {}: not a range error: {e}", S::NAME));
            }
        }
        (Err(e), Some(_)) => failures.push(format!("{name} in {}: {e}", S::NAME)),
    }
}

#[test]
fn every_type_on_every_stress_scene() {
    let mut table = String::from(
        "| scene | type | load | identical % | within ±1 % | PSNR dB | other object % |\n|---|---|---|---|---|---|---|\n",
    );
    let mut failures = Vec::new();
    for (name, f32_bound, fixed_bound) in BOUNDS {
        let path = stress_dir().join(format!("{name}.txt"));
        let reference = reference_image(&load::<f64>(&path).unwrap());
        check::<f32>(
            name,
            &path,
            &reference,
            f32_bound,
            &mut table,
            &mut failures,
        );
        check::<I16F16>(
            name,
            &path,
            &reference,
            fixed_bound,
            &mut table,
            &mut failures,
        );
    }
    eprintln!("{table}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The far scenes are one scene scaled about the eye (ambient by k, emissivity by k^2): in
/// f64 every pixel sees the same object at every scale, and the colours agree.
#[test]
fn far_scenes_are_one_scene_in_f64() {
    let base = image(&load::<f64>(&stress_dir().join("far_1.txt")).unwrap());
    for k in [100, 1000] {
        let far = image(&load::<f64>(&stress_dir().join(format!("far_{k}.txt"))).unwrap());
        let c = compare(&base, &far);
        assert_eq!(c.other_object, 0.0, "far_{k}: {c:?}");
        assert!(c.within_one >= 99.9, "far_{k}: {c:?}");
    }
}

/// Every stress scene is in the test above.
#[test]
fn every_stress_scene_has_bounds() {
    let mut files: Vec<String> = std::fs::read_dir(stress_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "txt"))
        .map(|p| p.file_stem().unwrap().to_str().unwrap().to_string())
        .collect();
    files.sort();
    let mut listed: Vec<String> = BOUNDS.iter().map(|b| b.0.to_string()).collect();
    listed.sort();
    assert_eq!(files, listed);
}
