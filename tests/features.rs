//! Cargo features: a scene that needs something a build left out is a load error that names
//! the cargo feature and where the scene asks for it; with the feature, the same scene
//! loads. The test runs in whatever configuration it is built with: `cargo test` checks the
//! full build, and CI also runs it without the optional features:
//! `cargo test --no-default-features --features parser --test features`.
#![cfg(feature = "parser")]

use microray::error::{ErrorKind, Feature};
use microray::parse::parse_scene;
use microray::{Error, Scene};

const CAMERA: &str = "camera c { pixeldim 8 6 worlddim 8 6 viewpoint 4 3 3 }\n";

/// Loads `body` after a camera and a plain material `m`; every texture file is a 1x1 PPM.
fn load(body: &str) -> Result<Scene<'static, f32, 4, 4, 2, 1, 8>, Error> {
    let text = format!("{CAMERA}material m {{ diffuse 1 1 1 }}\n{body}");
    parse_scene(text.as_bytes(), |_| Ok(&b"P6 1 1 255 \x80\x80\x80"[..]))
}

/// Each optional part, a scene using it, and where the error is (line, column).
const NEEDS: [(Feature, &str, (u32, u32)); 10] = [
    (
        Feature::FPlane,
        "fplane f { material m normal 0 0 1 point 0 0 -5 xdir 1 0 0 dimensions 2 2 }",
        (3, 1),
    ),
    (
        Feature::TiledPlane,
        "tiled_plane t { material m normal 0 1 0 point 0 0 0 xdir 1 0 0 dimensions 1 1 altmaterial m }",
        (3, 1),
    ),
    (Feature::Texture, "texture p { filename p.ppm }", (3, 1)),
    (
        Feature::Spotlight,
        "spotlight s { location 4 5 0 emissivity 1 1 1 point 4 0 -5 theta 20 }",
        (3, 1),
    ),
    (
        Feature::Reflection,
        "material mirror { diffuse 1 1 1\n  specular 0.5 }",
        (4, 3),
    ),
    (
        Feature::Transparency,
        "material glass { diffuse 1 1 1\n  transparency 0.5 }",
        (4, 3),
    ),
    (
        Feature::Glint,
        "material shiny { diffuse 1 1 1\n  shininess 20 }",
        (4, 3),
    ),
    (
        Feature::Texture,
        "texture p { filename p.ppm }\ntexplane w { material m normal 0 0 1 point 0 0 -5 xdir 1 0 0 dimensions 2 2 texname p mode 0 }",
        (3, 1),
    ),
    (
        Feature::Projector,
        "projector p { emissivity 1 1 1 location 4 3 2 normal 0 0 1 point 2 1 0 xdir 1 0 0 dimensions 4 3 texname p.ppm mode 0 }",
        (3, 1),
    ),
    (
        Feature::RevSurf,
        "revsurf v { material m surfer 1 base 4 0 -4 direction 0 1 0 height 6 }",
        (3, 1),
    ),
];

#[test]
fn scenes_load_exactly_when_the_build_has_what_they_need() {
    for (feature, body, (line, column)) in NEEDS {
        let result = load(body);
        if feature.enabled() {
            assert!(result.is_ok(), "{}: {:?}", feature.name(), result.err());
        } else {
            let error = result.map(|_| ()).unwrap_err();
            assert!(
                matches!(error.kind, ErrorKind::NotCompiledIn { feature: f, .. } if f == feature),
                "{}: {error:?}",
                feature.name()
            );
            let position = error.position.unwrap();
            assert_eq!(
                (position.line, position.column),
                (line, column),
                "{}: {error}",
                feature.name()
            );
            let message = error.to_string();
            assert!(
                message.contains(&format!("cargo feature `{}`", feature.name())),
                "{message}"
            );
        }
    }
}

/// What every build reads: planes, spheres, point lights, ambient and diffuse light.
#[test]
fn the_minimal_language_always_loads() {
    let scene = load(
        "material red { ambient 0.2 0 0 diffuse 3 0 0 }
         plane floor { material m normal 0 1 0 point 0 0 0 }
         sphere ball { material red center 4 1 -5 radius 1 }
         light sun { location 4 9 0 emissivity 5 5 5 }",
    )
    .unwrap();
    assert_eq!(scene.objects().len(), 2);
}

/// The message a minimal build gives, in full: what is missing and which feature adds it.
#[test]
fn not_compiled_in_message() {
    let kind = ErrorKind::NotCompiledIn {
        feature: Feature::TiledPlane,
        attr: None,
    };
    assert_eq!(
        kind.to_string(),
        "this build of microray leaves out tiled planes (`tiled_plane`) (cargo feature `tiled-plane`)"
    );
}
