//! Property tests of the parser: no input panics, and generated scenes round-trip.

use microray::host::HostScene;
use microray::parse::{no_textures, parse_scene};
use microray::print::print_scene;
use microray::{Scalar, Scene};
use proptest::prelude::*;

/// Words the scene language is made of, so random token streams reach deep into the parser.
const VOCABULARY: &[&str] = &[
    "camera",
    "material",
    "light",
    "spotlight",
    "plane",
    "sphere",
    "fplane",
    "tiled_plane",
    "texture",
    "texplane",
    "pixeldim",
    "worlddim",
    "viewpoint",
    "ambient",
    "diffuse",
    "specular",
    "shininess",
    "transparency",
    "location",
    "emissivity",
    "point",
    "theta",
    "normal",
    "center",
    "radius",
    "xdir",
    "dimensions",
    "altmaterial",
    "filename",
    "texname",
    "mode",
    "{",
    "}",
    "m",
    "0",
    "1",
    "-1",
    "2.5",
    "1e400",
    "nan",
    "#",
    "\n",
    "\0",
    "é",
    "1e-320",
];

fn token_soup() -> impl Strategy<Value = Vec<u8>> {
    let word = prop_oneof![
        4 => prop::sample::select(VOCABULARY).prop_map(|w| w.as_bytes().to_vec()),
        1 => any::<f64>().prop_map(|v| v.to_string().into_bytes()),
        1 => prop::collection::vec(any::<u8>(), 0..8),
    ];
    prop::collection::vec(word, 0..200).prop_map(|words| words.join(&b' '))
}

fn check_no_panic(bytes: &[u8]) {
    let _ = parse_scene::<f64, 32, 16, 8, 16, 1024>(bytes, no_textures);
    let _ = parse_scene::<f32, 2, 2, 1, 0, 16>(bytes, no_textures);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..4000)) {
        check_no_panic(&bytes);
    }

    #[test]
    fn random_token_streams_never_panic(bytes in token_soup()) {
        check_no_panic(&bytes);
    }

    #[test]
    fn errors_point_inside_the_input(bytes in token_soup()) {
        if let Err(e) = parse_scene::<f64, 32, 16, 8, 16, 1024>(&bytes, no_textures) {
            let p = e.position.unwrap();
            let lines = bytes.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
            prop_assert!(p.line >= 1 && p.line <= lines && p.column >= 1);
        }
    }
}

/// A finite number, written in one of several ways.
fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        (-1000i32..1000).prop_map(|v| v.to_string()),
        (-1e4f64..1e4).prop_map(|v| v.to_string()),
        any::<f64>()
            .prop_filter("finite", |v| v.is_finite())
            .prop_map(|v| format!("{v:e}")),
        ("[0-9]{1,25}", "[0-9]{0,25}", -40i32..40).prop_map(|(i, f, e)| format!("{i}.{f}e{e}")),
    ]
}

fn positive() -> impl Strategy<Value = String> {
    prop_oneof![
        (1u32..1000).prop_map(|v| v.to_string()),
        (1e-3f64..1e3).prop_map(|v| v.to_string())
    ]
}

/// A viewpoint within a thousand of the window: farther away, a window of 1e-3 would have
/// pixels closer in direction than f64 resolves (rejected, see the error tests).
fn viewpoint() -> impl Strategy<Value = String> {
    [-1e3f64..1e3, -1e3f64..1e3, -1e3f64..1e3].prop_map(|[a, b, c]| format!("{a} {b} {c}"))
}

fn vector() -> impl Strategy<Value = String> {
    (number(), number(), number()).prop_map(|(a, b, c)| format!("{a} {b} {c}"))
}

/// A scene that should load: every object of every kind with random numbers.
fn valid_scene() -> impl Strategy<Value = String> {
    (
        (2u32..2000, 2u32..2000, positive(), positive(), viewpoint()),
        (vector(), (number(), number()), positive(), positive(), 0.0f64..=1.0),
        (vector(), vector(), vector(), 0.0f64..180.0),
        (vector(), positive()),
        (positive(), positive()),
        prop::sample::select(vec!["0 0 1", "0 1 0", "1 2 3", "-6.93 0 4"]),
    )
        .prop_map(|(cam, mat, light, sphere, dims, normal)| {
            let (w, h, ww, wh, eye) = cam;
            let (amb, (d1, d2), spec, shin, tr) = mat;
            let (loc, emi, aim, theta) = light;
            format!(
                "camera c {{ pixeldim {w} {h} worlddim {ww} {wh} viewpoint {eye} }}\n\
                 material a {{ ambient {amb} diffuse 1 {d1} {d2} specular {spec} shininess {shin} transparency {tr} }}\n\
                 material b {{ diffuse {d2} {d1} 0 }}\n\
                 light l {{ location {loc} emissivity {emi} }}\n\
                 spotlight s {{ location {loc} emissivity {emi} point {aim} theta {theta} }}\n\
                 sphere o {{ material a center {center} radius {radius} }}\n\
                 plane p {{ material b normal {normal} point {center} }}\n\
                 fplane f {{ material a normal {normal} point {center} xdir 1 0 0 dimensions {w0} {w1} }}\n\
                 tiled_plane t {{ material a normal {normal} point {center} xdir 0 1 1 dimensions {w0} {w1} altmaterial b }}\n",
                center = sphere.0,
                radius = sphere.1,
                w0 = dims.0,
                w1 = dims.1,
            )
        })
}

fn print<S: Scalar>(scene: &HostScene<'_, S>) -> String {
    let mut out = String::new();
    print_scene(scene, &mut out).unwrap();
    out
}

fn round_trips<S: Scalar>(text: &str) -> Result<(), TestCaseError> {
    let Ok(scene) = parse_scene::<S, 256, 64, 32, 16, 8192>(text.as_bytes(), no_textures) else {
        // Random vectors can be degenerate (a spotlight aimed at itself, xdir along the
        // normal); those are checked by the error tests.
        return Ok(());
    };
    let printed = print(&scene);
    let again: HostScene<'_, S> = parse_scene(printed.as_bytes(), no_textures)
        .map_err(|e| TestCaseError::fail(format!("{e}\n{printed}")))?;
    prop_assert_eq!(&again, &scene);
    prop_assert_eq!(print(&again), printed);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    #[test]
    fn generated_scenes_round_trip(text in valid_scene()) {
        round_trips::<f64>(&text)?;
        round_trips::<f32>(&text)?;
    }

    #[test]
    fn most_generated_scenes_load(text in valid_scene()) {
        // The generator is meant to produce loadable scenes; a systematic rejection would
        // make the round-trip property vacuous.
        let loaded: Result<Scene<'_, f64>, _> = parse_scene(text.as_bytes(), no_textures);
        if let Err(e) = loaded {
            let allowed = matches!(
                e.kind,
                microray::ErrorKind::ZeroVector { .. }
                    | microray::ErrorKind::XdirParallelToNormal
                    | microray::ErrorKind::ImageTooWide { .. }
                    // Random values spanning 1e-300 to 1e300 exceed what even f64 resolves.
                    | microray::ErrorKind::TooSmallForType { .. }
                    | microray::ErrorKind::ScaledBelowResolution { .. }
                    | microray::ErrorKind::BeyondRange { .. }
                    // An eye 1e300 away from a window 1e-3 wide.
                    | microray::ErrorKind::PixelsTooFine { .. }
            );
            prop_assert!(allowed, "{}\n{}", e, text);
        }
    }
}

#[test]
fn the_round_trip_property_is_not_vacuous() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strategy = valid_scene();
    let total = 1000;
    let loaded = (0..total)
        .filter(|_| {
            let text = strategy.new_tree(&mut runner).unwrap().current();
            parse_scene::<f64, 256, 64, 32, 16, 8192>(text.as_bytes(), no_textures).is_ok()
        })
        .count();
    eprintln!("{loaded} of {total} generated scenes load");
    assert!(
        loaded * 2 >= total,
        "only {loaded} of {total} generated scenes load"
    );
}
