//! A scene sized for the scene it holds (the crate docs' "Sizing a scene"): the capacities
//! it needs and not one more, a row buffer in the panel's own colour type, and the render
//! is the same as with room to spare; one object more is a capacity error, not a panic.

use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use microray::error::{Collection, ErrorKind};
use microray::parse::{no_textures, parse_scene_into};
use microray::render::Renderer;
use microray::scalar::I16F16;
use microray::{Scalar, Scene};
use std::ops::ControlFlow;

mod common;

use common::Panel;

/// The project's smallest scene: a floor, a ball, one light (2 objects, 2 materials).
const MINIMAL: &[u8] = include_bytes!("../scenes/minimal.txt");

fn render<
    S: Scalar,
    const O: usize,
    const M: usize,
    const L: usize,
    const T: usize,
    const W: usize,
>(
    scene: &Scene<'_, S, O, M, L, T, W>,
) -> Vec<Rgb565> {
    let mut panel = Panel::<Rgb565>::new(320, 240);
    // The row buffer in the panel's colour type: two bytes a pixel.
    let mut row = [Rgb565::default(); W];
    let area = Rectangle::new(Point::zero(), Size::new(320, 240));
    Renderer::new(scene)
        .render_area(&mut panel, area, &mut row, |_| ControlFlow::Continue(()))
        .unwrap();
    panel.pixels
}

fn exact_and_roomy<S: Scalar>() {
    // Exactly what the scene needs: 2 objects, 2 materials, 1 light, no texture, 320 wide.
    let mut exact: Scene<'_, S, 2, 2, 1, 0, 320> = Scene::empty();
    parse_scene_into(MINIMAL, no_textures, &mut exact).unwrap();
    let mut roomy: Scene<'_, S, 32, 16, 8, 2, 1024> = Scene::empty();
    parse_scene_into(MINIMAL, no_textures, &mut roomy).unwrap();
    let (a, b) = (render(&exact), render(&roomy));
    assert_eq!(
        a,
        b,
        "{}: the exactly sized scene renders differently",
        S::NAME
    );
    // Not a blank image: the floor and the ball (below the horizon) are lit.
    let lit = a.iter().filter(|&&c| c != Rgb565::default()).count();
    assert!(lit > 320 * 240 / 4, "{}: only {lit} pixels lit", S::NAME);
    // The exactly sized scene is smaller than the roomy one by the slots it leaves out.
    assert!(
        core::mem::size_of_val(&exact) * 4 < core::mem::size_of_val(&roomy),
        "{}: {} against {} bytes",
        S::NAME,
        core::mem::size_of_val(&exact),
        core::mem::size_of_val(&roomy)
    );
}

#[test]
fn a_scene_sized_for_its_file_renders_as_one_with_room_to_spare() {
    exact_and_roomy::<f32>();
    exact_and_roomy::<I16F16>();
    exact_and_roomy::<f64>();
}

#[test]
fn one_object_too_many_is_a_capacity_error() {
    let mut small: Scene<'_, I16F16, 1, 2, 1, 0, 320> = Scene::empty();
    let error = parse_scene_into(MINIMAL, no_textures, &mut small).unwrap_err();
    assert!(
        matches!(
            error.kind,
            ErrorKind::CapacityExceeded {
                what: Collection::Objects,
                capacity: 1
            }
        ),
        "{error:?}"
    );
    // Where: the second object's block.
    assert_eq!(error.position.map(|p| p.line), Some(28), "{error:?}");
    // A row buffer narrower than the image is an error too.
    let mut scene: Scene<'_, I16F16, 2, 2, 1, 0, 320> = Scene::empty();
    parse_scene_into(MINIMAL, no_textures, &mut scene).unwrap();
    let mut panel = Panel::<Rgb888>::new(320, 240);
    let mut row = [Rgb888::default(); 100];
    let area = Rectangle::new(Point::zero(), Size::new(320, 240));
    assert!(
        Renderer::new(&scene)
            .render_area(&mut panel, area, &mut row, |_| ControlFlow::Continue(()))
            .is_err()
    );
}

/// The counts `Capacities::of_text` makes without the parser are what the parser loads, for
/// every scene of the project's and the course's.
#[test]
fn capacities_counted_from_the_text_are_what_the_parser_loads() {
    use microray::capacity::Capacities;
    use microray::host::{HostScene, texture_files};
    let scenes = common::all_scenes_with("stress");
    assert!(scenes.len() >= 8, "{scenes:?}");
    for path in scenes {
        let text = std::fs::read(&path).unwrap();
        let mut scene = Box::new(HostScene::<f64>::empty());
        parse_scene_into(&text, texture_files(path.parent().unwrap()), &mut scene)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let loaded = Capacities {
            objects: scene.objects().len(),
            materials: scene.materials().len(),
            lights: scene.lights().len(),
            textures: scene.textures().len(),
            max_width: scene.camera().width() as usize,
        };
        assert_eq!(Capacities::of_text(&text), loaded, "{}", path.display());
    }
}

/// A scene type sized in a `const` from the file it holds loads the file, and renders as a
/// scene with room to spare.
#[test]
fn a_scene_type_sized_from_its_text_in_a_const() {
    use microray::capacity::Capacities;
    const NEEDS: Capacities = Capacities::of_text(MINIMAL);
    type Minimal = Scene<
        'static,
        I16F16,
        { NEEDS.objects },
        { NEEDS.materials },
        { NEEDS.lights },
        { NEEDS.textures },
        { NEEDS.max_width },
    >;
    let mut exact = Minimal::empty();
    parse_scene_into(MINIMAL, no_textures, &mut exact).unwrap();
    let roomy: Scene<'_, I16F16> = microray::parse::parse_scene(MINIMAL, no_textures).unwrap();
    assert_eq!(render(&exact), render(&roomy));
    // One object fewer does not fit.
    let mut small: Scene<'_, I16F16, { NEEDS.objects - 1 }, 2, 1, 0, 320> = Scene::empty();
    assert!(parse_scene_into(MINIMAL, no_textures, &mut small).is_err());
}
