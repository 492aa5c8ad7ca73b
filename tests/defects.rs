//! Regression tests for the defects the random-scene differential suite found (issue 36),
//! each built from its reproducer in `tests/defects/`.

mod common;

use microray::host::{HostRenderer, HostScene};
use microray::parse::{no_textures, parse_scene};
use microray::render::Renderer;
use microray::scalar::I16F16;
use microray::{Scalar, Vec3};
use std::path::Path;

fn defect(name: &str) -> Vec<u8> {
    std::fs::read(Path::new("tests/defects").join(name)).unwrap()
}

fn load<S: Scalar>(text: &[u8]) -> HostScene<'static, S> {
    parse_scene(text, no_textures).unwrap()
}

/// The scene with its two objects in the other order.
fn swapped(text: &[u8]) -> Vec<u8> {
    let text = std::str::from_utf8(text).unwrap();
    let (sphere, revsurf) = (
        text.find("sphere ").unwrap(),
        text.find("revsurf ").unwrap(),
    );
    let mut out = String::from(&text[..sphere]);
    out.push_str(&text[revsurf..]);
    out.push('\n');
    out.push_str(&text[sphere..revsurf]);
    out.into_bytes()
}

/// How many pixels of two images differ.
fn differing(a: &[u8], b: &[u8]) -> usize {
    assert_eq!(a.len(), b.len());
    a.chunks(3).zip(b.chunks(3)).filter(|(p, q)| p != q).count()
}

fn rgb<S: Scalar>(text: &[u8], planned: bool) -> Vec<u8> {
    let scene = load::<S>(text);
    let renderer: HostRenderer<'_, S> = Renderer::new(&scene).with_plan(planned);
    common::image(&renderer).rgb().to_vec()
}

/// `G(t) = rho^2 - r(h)^2` of the reproducer's vase (`surfer 3`, scale 1) in f64, and
/// whether the point is between the vase's ends.
fn vase_g(base: Vec3<f64>, dir: Vec3<f64>, t: f64) -> (f64, bool) {
    let foot = Vec3::new(-3.77691, 6.66345, -14.3007);
    let d: Vec3<f64> = Vec3::new(0.20246161207867736, -0.275, 0.94);
    let axis = d * (1.0 / d.dot(d).sqrt());
    let p = base + dir * t - foot;
    let h = p.dot(axis);
    let off = p - axis * h;
    let r = 1.0 + 0.5 * h.sin();
    (off.dot(off) - r * r, (0.0..=23.4).contains(&h))
}

#[test]
fn a_surface_of_revolution_finds_its_nearest_crossing_whatever_is_tested_first() {
    let text = defect("revsurf_far_root.txt");
    let other = swapped(&text);
    for planned in [true, false] {
        let f64s = differing(&rgb::<f64>(&text, planned), &rgb::<f64>(&other, planned));
        let f32s = differing(&rgb::<f32>(&text, planned), &rgb::<f32>(&other, planned));
        let i16f16s = differing(
            &rgb::<I16F16>(&text, planned),
            &rgb::<I16F16>(&other, planned),
        );
        assert_eq!((f64s, f32s, i16f16s), (0, 0, 0), "planned: {planned}");
    }
    assert_eq!(
        differing(&rgb::<f64>(&text, true), &rgb::<f64>(&text, false)),
        0
    );

    // Every primary ray: the crossing found without a limit is the one found below the
    // sphere's distance, and it is the first sign change of G (scanned in steps of 1e-3).
    let scene = load::<f64>(&text);
    let (sphere, vase) = (&scene.objects()[0], &scene.objects()[1]);
    let camera = scene.camera();
    let mut checked = 0;
    for y in 0..camera.height() {
        for x in 0..camera.width() {
            let ray = camera.primary_ray(x, y).unwrap();
            let free = vase.hits(&ray, f64::INFINITY);
            if let Some(limit) = sphere.hits(&ray, f64::INFINITY) {
                assert_eq!(
                    vase.hits(&ray, limit),
                    free.filter(|&t| t < limit),
                    "({x}, {y})"
                );
            }
            let Some(found) = free else { continue };
            let steps = (found / 1e-3) as usize;
            let start = vase_g(ray.base, ray.dir, 0.0).0 > 0.0;
            let earlier = (1..steps.saturating_sub(1))
                .map(|i| i as f64 * 1e-3)
                .find(|&t| {
                    let (g, between_ends) = vase_g(ray.base, ray.dir, t);
                    between_ends && (g > 0.0) != start
                });
            assert_eq!(
                earlier, None,
                "({x}, {y}): found {found}, G changes sign before"
            );
            checked += 1;
        }
    }
    // The pixel of the report whose ray crosses three times in the first bracket.
    let ray = camera.primary_ray(17, 53).unwrap();
    let t = vase.hits(&ray, f64::INFINITY).unwrap();
    assert!((t - 5.856).abs() < 0.01, "{t}");
    assert!(checked > 400, "{checked}");
}

/// The warnings of a scene, as text.
fn warnings(text: &[u8]) -> Vec<String> {
    let scene = load::<f64>(text);
    let mut found = Vec::new();
    scene.warnings(|w| found.push(w.to_string()));
    found
}

#[test]
fn ill_posed_scenes_are_flagged_and_well_posed_ones_are_not() {
    // Issue 36, item 3: two identical planes shade 384 of 3,072 pixels differently from
    // one plane in f64 itself. The picture is rounding's choice: a warning says so.
    let one = b"camera c { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 6 }
        material grey { ambient 0.2 0.2 0.2 diffuse 2 2 2 }
        material red { ambient 0.3 0 0 diffuse 3 0 0 }
        light lamp { location 2 5 2 emissivity 4 4 4 }
        plane floor { material grey normal 0 1 0 point 0 0 0 }"
        .to_vec();
    let mut two = one.clone();
    two.extend_from_slice(b" plane again { material red normal 0 2 0 point 5 0 -3 }");
    let (single, double) = (rgb::<f64>(&one, true), rgb::<f64>(&two, true));
    assert!(
        differing(&single, &double) > 0,
        "the tie must show to need a warning"
    );
    assert_eq!(warnings(&one), Vec::<String>::new());
    assert_eq!(
        warnings(&two),
        ["plane `floor` and plane `again` coincide: which one a ray meets is decided by rounding"]
    );
    // Each other kind, from the configurations the random scenes met.
    let mut all = one.clone();
    all.extend_from_slice(
        b" light on_floor { location 1 0 -2 emissivity 1 1 1 }
           light at_eye { location 4 3 6 emissivity 1 1 1 }
           plane through_eye { material grey normal 1 0 0 point 4 0 0 }
           sphere around_eye { material grey center 4 3 5.5 radius 1 }
           sphere twin { material red center 4 3 5.5 radius 1 }",
    );
    let found = warnings(&all);
    for expected in [
        "plane `through_eye` passes through the eye",
        "sphere `around_eye` has the eye inside it",
        "sphere `around_eye` and sphere `twin` coincide",
        "light `on_floor` is on the surface of plane `floor`",
        "light `at_eye` is at the eye",
        "light `at_eye` is on the surface of plane `through_eye`",
    ] {
        assert!(
            found.iter().any(|w| w.starts_with(expected)),
            "{expected}: {found:#?}"
        );
    }
    assert_eq!(found.len(), 7, "{found:#?}");
    // Near is not on: a light 1e-3 above the floor, a plane 1e-3 from the eye.
    let mut near = one.clone();
    near.extend_from_slice(
        b" light above { location 1 0.001 -2 emissivity 1 1 1 }
           plane beside { material grey normal 1 0 0 point 4.001 0 0 }",
    );
    assert_eq!(warnings(&near), Vec::<String>::new());
}

#[test]
fn no_project_stress_or_course_scene_is_flagged() {
    for path in common::all_scenes_with("stress") {
        let text = std::fs::read(&path).unwrap();
        let scene: HostScene<'static, f64> =
            parse_scene(&text, microray::host::texture_files(path.parent().unwrap())).unwrap();
        let mut found = Vec::new();
        scene.warnings(|w| found.push(w.to_string()));
        assert!(found.is_empty(), "{}: {found:?}", path.display());
    }
}

/// Why I16F16 refuses a scene.
fn refusal(text: &[u8]) -> microray::Error {
    match parse_scene::<I16F16, 64, 64, 32, 16, 8192>(text, no_textures) {
        Err(e) => e,
        Ok(_) => panic!("i16f16 accepted {}", String::from_utf8_lossy(text)),
    }
}

#[test]
fn a_length_too_small_after_scaling_names_the_far_value() {
    // Issue 36, item 5: I16F16 said "`worlddim` must be greater than 0" where a far value
    // forced the scene to be scaled until the window rounded to nothing.
    let text = b"camera c { pixeldim 64 48 worlddim 61.29 29.47 viewpoint 30 15 10 }
        material m { diffuse 1 1 1 }
        sphere far { material m center 30 15 -1e12 radius 5 }";
    let error = refusal(text);
    assert!(
        matches!(
            error.kind,
            microray::ErrorKind::ScaledBelowResolution {
                attr: microray::error::Attr::Worlddim,
                largest_at: microray::error::Attr::Center,
                largest: 1_000_000_000_005,
                range_log2: 13,
                scaled_log2: 27,
                ..
            }
        ),
        "{error:?}"
    );
    assert!(
        error
            .to_string()
            .starts_with("1:27: the scene reaches 1000000000005 from the origin (its `center`)"),
        "{error}"
    );
    // f32 and f64 hold it.
    assert!(parse_scene::<f32, 64, 64, 32, 16, 8192>(text, no_textures).is_ok());
    // A positive length that rounds to zero is too small, not "not positive".
    let tiny = b"camera c { pixeldim 8 6 worlddim 8 6 viewpoint 4 3 3 }
        material m { diffuse 1 1 1 }
        sphere dot { material m center 4 3 -1 radius 0.000001 }";
    let error = refusal(tiny);
    assert!(
        matches!(error.kind, microray::ErrorKind::TooSmallForType { .. }),
        "{error:?}"
    );
}

/// The share of pixels with a channel more than 16 levels off.
fn grossly_off(a: &[u8], b: &[u8]) -> f64 {
    let off = a
        .chunks(3)
        .zip(b.chunks(3))
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > 16))
        .count();
    off as f64 / (a.len() / 3) as f64
}

#[test]
fn i16f16_renders_well_posed_scenes_within_the_usual_bounds() {
    // Issue 36, item 4: directions written at 1e-5 scale (65 % of pixels off before), and a
    // transparency I16F16 rounded to zero (an opaque plane that hid the glints behind it).
    for name in ["i16f16_tiny_normal.txt", "i16f16_barely_transparent.txt"] {
        let text = defect(name);
        let reference = rgb::<f64>(&text, true);
        let fixed = rgb::<I16F16>(&text, true);
        let off = grossly_off(&reference, &fixed);
        assert!(off <= 0.02, "{name}: {:.1} % off", off * 100.0);
        assert!(warnings(&text).is_empty(), "{name}: {:?}", warnings(&text));
    }
    // The direction is scaled by a power of two, not rounded: f64 makes the same unit normal
    // of it as of the same normal written 1024 times larger, bit for bit.
    let small = load::<f64>(&defect("i16f16_tiny_normal.txt"));
    let scaled_up = String::from_utf8(defect("i16f16_tiny_normal.txt"))
        .unwrap()
        .replace(
            "normal 0.00000893 0.0000786 0.0000612",
            "normal 0.00914432 0.0804864 0.0626688",
        );
    let large = load::<f64>(scaled_up.as_bytes());
    match (small.objects()[2].shape(), large.objects()[2].shape()) {
        (microray::object::Shape::TiledPlane(a), microray::object::Shape::TiledPlane(b)) => {
            assert_eq!(a.rect.plane.unit_normal, b.rect.plane.unit_normal);
        }
        _ => panic!("object 2 is the tiled plane"),
    }
}
