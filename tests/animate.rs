//! Moving pictures are exact: after random changes to random rooms (objects moved, resized,
//! given another material; materials changed; lights moved), tracing only the region the
//! changes can touch ([`microray::region`]) into the previous frame gives the full frame
//! of the new state, byte for byte, in `f64`, `f32` and Q16.16. And the region does leave
//! pixels out, or this would compare a full frame with itself.

#![cfg(feature = "animate")]

mod common;

use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use microray::host::Framebuffer;
use microray::object::{ObjectDef, RectDef};
use microray::region::Region;
use microray::render::{AaPixel, Antialias, Renderer, Samples};
use microray::scalar::I16F16;
use microray::{CameraDef, LightDef, MaterialDef, Scalar, Scene};
use proptest::prelude::*;
use std::ops::ControlFlow;

const NAMES: [&str; 4] = ["a", "b", "c", "d"];
const WIDTH: usize = 48;
const HEIGHT: usize = 36;

type Room<'a, S> = Scene<'a, S, 5, 4, 3, 0, WIDTH>;

/// An object as the test keeps it: kind, normal, point (a ball's centre), size, material.
#[derive(Clone, Copy, Debug)]
struct Thing {
    kind: u8,
    normal: [f64; 3],
    point: [f64; 3],
    size: f64,
    material: usize,
}

impl Thing {
    fn def(&self) -> ObjectDef<'static> {
        let (n, p, m) = (self.normal, self.point, NAMES[self.material]);
        match self.kind {
            0 => ObjectDef::plane("o", m, n, p),
            1 => {
                let rect = RectDef::new(n, p, [1.0, 0.0, 0.0], [1.5, 1.5]);
                ObjectDef::tiled_plane("o", m, rect, NAMES[(self.material + 1) % 4])
            }
            2 => {
                let rect = RectDef::new(n, p, [1.0, 0.0, 0.0], [self.size * 2.0, self.size]);
                ObjectDef::fplane("o", m, rect)
            }
            _ => ObjectDef::sphere("o", m, p, self.size),
        }
    }
}

/// A material: diffuse, ambient, specular (a mirror when above 0), transparency.
type Stuff = ([f64; 3], [f64; 3], f64, f64);

fn material_def(
    name: &'static str,
    &(diffuse, ambient, specular, transparency): &Stuff,
) -> MaterialDef<'static> {
    MaterialDef::new(name)
        .diffuse(diffuse)
        .ambient(ambient)
        .specular(specular)
        .transparency(transparency)
}

/// A light: spotlight or not, location, emissivity.
type Lamp = (bool, [f64; 3], [f64; 3]);

fn light_def(&(spot, at, emissivity): &Lamp) -> LightDef<'static> {
    if spot {
        LightDef::spot("l", at, emissivity, [at[0], 0.0, at[2] - 2.0], 40.0)
    } else {
        LightDef::point("l", at, emissivity)
    }
}

#[derive(Clone, Debug)]
enum Change {
    /// Object `.0` moved by `.1`.
    Move(usize, [f64; 3]),
    /// Object `.0` to size `.1`.
    Resize(usize, f64),
    /// Object `.0` shows material `.1`.
    Wear(usize, usize),
    /// Material `.0` becomes `.1`.
    Material(usize, Stuff),
    /// Light `.0` moves to `.1`.
    MoveLight(usize, [f64; 3]),
    /// Light `.0` shines with emissivity `.1`.
    Glow(usize, [f64; 3]),
    /// The eye moves to `.0`.
    Look([f64; 3]),
}

fn normal() -> impl Strategy<Value = [f64; 3]> {
    prop_oneof![
        Just([0.0, 1.0, 0.0]),
        Just([0.0, 0.0, 1.0]),
        Just([0.0, 1.0, 2.0]),
        Just([1.0, 0.5, 0.25]),
    ]
}

fn point() -> impl Strategy<Value = [f64; 3]> {
    [-6.0..6.0f64, -3.0..3.0f64, -9.0..-1.0f64]
}

fn thing() -> impl Strategy<Value = Thing> {
    // Mostly balls and panels: the bounded kinds whose changes leave pixels out.
    (0..6u8, normal(), point(), 0.4..1.6f64, 0..4usize).prop_map(
        |(kind, normal, point, size, material)| Thing {
            kind: kind.min(3),
            normal,
            point,
            size,
            material,
        },
    )
}

fn stuff() -> impl Strategy<Value = Stuff> {
    (
        [0.5..4.0f64, 0.5..4.0f64, 0.5..4.0f64],
        prop_oneof![Just([0.0; 3]), Just([0.5, 0.2, 0.1])],
        prop_oneof![3 => Just(0.0), 1 => 0.2..0.9f64],
        prop_oneof![3 => Just(0.0), 1 => 0.2..0.8f64],
    )
}

fn lamp() -> impl Strategy<Value = Lamp> {
    (
        any::<bool>(),
        [-6.0..10.0f64, 0.5..12.0f64, -6.0..4.0f64],
        [1.0..8.0f64, 1.0..8.0f64, 1.0..8.0f64],
    )
}

fn change() -> impl Strategy<Value = Change> {
    prop_oneof![
        6 => (0..5usize, [-1.5..1.5f64, -1.5..1.5f64, -1.5..1.5f64]).prop_map(|(i, d)| Change::Move(i, d)),
        2 => (0..5usize, 0.4..1.6f64).prop_map(|(i, s)| Change::Resize(i, s)),
        1 => (0..5usize, 0..4usize).prop_map(|(i, m)| Change::Wear(i, m)),
        1 => (0..4usize, stuff()).prop_map(|(i, s)| Change::Material(i, s)),
        1 => (0..3usize, [-6.0..10.0f64, 0.5..12.0f64, -6.0..4.0f64]).prop_map(|(i, at)| Change::MoveLight(i, at)),
        1 => (0..3usize, [0.0..12.0f64, 0.0..12.0f64, 0.0..12.0f64]).prop_map(|(i, e)| Change::Glow(i, e)),
        1 => [1.0..7.0f64, 1.0..5.0f64, 2.0..8.0f64].prop_map(Change::Look),
    ]
}

#[derive(Clone, Debug)]
struct Film {
    things: Vec<Thing>,
    stuffs: Vec<Stuff>,
    lamps: Vec<Lamp>,
    eye: [f64; 3],
    /// Frames, each a few changes.
    frames: Vec<Vec<Change>>,
}

fn film() -> impl Strategy<Value = Film> {
    (
        prop::collection::vec(thing(), 2..6),
        prop::collection::vec(stuff(), 4),
        prop::collection::vec(lamp(), 1..4),
        [1.0..7.0f64, 1.0..5.0f64, 2.0..8.0f64],
        prop::collection::vec(prop::collection::vec(change(), 1..3), 1..4),
    )
        .prop_map(|(things, stuffs, lamps, eye, frames)| Film {
            things,
            stuffs,
            lamps,
            eye,
            frames,
        })
}

/// A stage: a floor (plain or tiled) and a back wall, balls and panels over the floor, and
/// lights on both sides of the image plane: shadows on planes, and planes that hide parts
/// of them from a light.
fn stage() -> impl Strategy<Value = Film> {
    let floor = (any::<bool>(), -2.5..1.5f64).prop_map(|(tiled, y)| Thing {
        kind: if tiled { 1 } else { 0 },
        normal: [0.0, 1.0, 0.0],
        point: [0.0, y, 0.0],
        size: 1.0,
        material: 0,
    });
    let wall = (-14.0..-6.0f64).prop_map(|z| Thing {
        kind: 0,
        normal: [0.0, 0.0, 1.0],
        point: [0.0, 0.0, z],
        size: 1.0,
        material: 1,
    });
    let prop = (
        2..4u8,
        normal(),
        [-3.0..7.0f64, -0.5..4.0f64, -8.0..-1.0f64],
        0.4..1.6f64,
        0..4usize,
    )
        .prop_map(|(kind, normal, point, size, material)| Thing {
            kind,
            normal,
            point,
            size,
            material,
        });
    let moves = (2..5usize, [-1.5..1.5f64, -1.5..1.5f64, -1.5..1.5f64])
        .prop_map(|(i, d)| Change::Move(i, d));
    // The floor and the wall opaque: planes that can hide shadows.
    set((floor, wall), prop, moves, 2)
}

/// Films of two things that stay (the first `opaque` materials made opaque) and one to
/// three that move.
fn set(
    staying: (impl Strategy<Value = Thing>, impl Strategy<Value = Thing>),
    moving: impl Strategy<Value = Thing>,
    moves: impl Strategy<Value = Change>,
    opaque: usize,
) -> impl Strategy<Value = Film> {
    (
        staying,
        prop::collection::vec(moving, 1..4),
        prop::collection::vec(stuff(), 4),
        prop::collection::vec(lamp(), 1..4),
        [1.0..7.0f64, 1.0..5.0f64, 2.0..8.0f64],
        prop::collection::vec(prop::collection::vec(moves, 1..3), 1..4),
    )
        .prop_map(move |((a, b), more, mut stuffs, lamps, eye, frames)| {
            for stuff in stuffs.iter_mut().take(opaque) {
                stuff.3 = 0.0;
            }
            let mut things = vec![a, b];
            things.extend(more);
            Film {
                things,
                stuffs,
                lamps,
                eye,
                frames,
            }
        })
}

/// A gallery: a large panel (a mirror a quarter of the time) behind balls that move in
/// front of it, over a floor, and lights in front: balls' shadows on a panel, and a lone
/// flat mirror showing them.
fn gallery() -> impl Strategy<Value = Film> {
    let floor = (-2.5..0.0f64).prop_map(|y| Thing {
        kind: 0,
        normal: [0.0, 1.0, 0.0],
        point: [0.0, y, 0.0],
        size: 1.0,
        material: 0,
    });
    let panel = (
        prop_oneof![
            Just([0.0, 0.0, 1.0]),
            Just([1.0, 0.0, 1.0]),
            Just([0.0, 1.0, 2.0]),
            Just([1.0, 0.5, 0.25]),
        ],
        [-2.0..2.0f64, -1.0..1.0f64, -9.0..-6.0f64],
        2.5..4.0f64,
        1..4usize,
    )
        .prop_map(|(normal, point, size, material)| Thing {
            kind: 2,
            normal,
            point,
            size,
            material,
        });
    let ball = (
        [-1.0..6.0f64, 0.0..3.0f64, -5.0..-2.0f64],
        0.4..1.2f64,
        0..4usize,
    )
        .prop_map(|(point, size, material)| Thing {
            kind: 3,
            normal: [0.0, 1.0, 0.0],
            point,
            size,
            material,
        });
    let moves = (2..5usize, [-1.5..1.5f64, -1.0..1.0f64, -1.0..1.0f64])
        .prop_map(|(i, d)| Change::Move(i, d));
    // The floor opaque: a plane that can hide shadows.
    set((floor, panel), ball, moves, 1)
}

/// What the region left out, over a run: pixels not re-traced, and pixels in all.
#[derive(Default, Debug, Clone, Copy)]
struct Saved {
    left_out: u64,
    pixels: u64,
}

/// Plays `film` in `S`: every frame traced in its region only, into the previous frame,
/// compared with the full frame of the same state.
fn play<S: Scalar>(film: &Film) -> Result<Saved, TestCaseError> {
    play_with::<S>(film, None)
}

/// The film's scene, if `S` can hold it.
fn room<S: Scalar>(film: &Film) -> Option<Room<'static, S>> {
    let camera = CameraDef::new("c", [WIDTH as u32, HEIGHT as u32], [8.0, 6.0], film.eye);
    let materials: Vec<_> = film
        .stuffs
        .iter()
        .zip(NAMES)
        .map(|(s, name)| material_def(name, s))
        .collect();
    let lights: Vec<_> = film.lamps.iter().map(light_def).collect();
    let objects: Vec<_> = film.things.iter().map(Thing::def).collect();
    Room::<S>::from_defs(&camera, &materials, &[], &lights, &objects).ok()
}

/// [`play`], anti-aliased by `aa` when given.
fn play_with<S: Scalar>(film: &Film, aa: Option<Antialias>) -> Result<Saved, TestCaseError> {
    let Some(mut scene) = room::<S>(film) else {
        return Ok(Saved::default());
    };
    let (mut things, mut lamps) = (film.things.clone(), film.lamps.clone());
    let mut shown = frame(&Renderer::<S, 5>::new(&scene), aa);
    let mut saved = Saved::default();
    for changes in &film.frames {
        let border = u16::from(matches!(aa, Some(Antialias::Adaptive { .. })));
        let mut region =
            Region::<8>::new(Size::new(WIDTH as u32, HEIGHT as u32)).with_border(border);
        if aa.is_none() {
            region = region.with_one_ray_a_pixel();
        }
        let (mut olds, mut materials) = (Vec::new(), Vec::new());
        for change in changes {
            match *change {
                Change::Move(i, _) | Change::Resize(i, _) | Change::Wear(i, _)
                    if i < things.len() =>
                {
                    let mut thing = things[i];
                    match *change {
                        Change::Move(_, d) => {
                            thing.point = [0, 1, 2].map(|k| thing.point[k] + d[k]);
                        }
                        Change::Resize(_, s) => thing.size = s,
                        Change::Wear(_, m) => thing.material = m,
                        _ => {}
                    }
                    // A state the type cannot hold is skipped, as a scene file would be refused.
                    if let Ok(old) = scene.replace_object(i, &thing.def()) {
                        things[i] = thing;
                        olds.push((i, old));
                    }
                }
                Change::Material(i, s)
                    if i < NAMES.len()
                        && scene
                            .replace_material(i, &material_def(NAMES[i], &s))
                            .is_ok() =>
                {
                    materials.push(i);
                }
                Change::MoveLight(i, at) if i < lamps.len() => {
                    let lamp = (lamps[i].0, at, lamps[i].2);
                    if scene.replace_light(i, &light_def(&lamp)).is_ok() {
                        lamps[i] = lamp;
                        region.add_light_change();
                    }
                }
                Change::Glow(i, emissivity) if i < lamps.len() => {
                    let lamp = (lamps[i].0, lamps[i].1, emissivity);
                    if scene.replace_light(i, &light_def(&lamp)).is_ok() {
                        lamps[i] = lamp;
                        region.add_light_change();
                    }
                }
                Change::Look(eye) => {
                    let size = [WIDTH as u32, HEIGHT as u32];
                    let camera = CameraDef::new("c", size, [8.0, 6.0], eye);
                    if scene.replace_camera(&camera).is_ok() {
                        region.add_camera_change();
                    }
                }
                _ => {}
            }
        }
        // Every change made, the region of each.
        for &i in &materials {
            region.add_material_change(&scene, i);
        }
        for (i, old) in &olds {
            region.add_object_change(&scene, *i, old);
        }
        let renderer = Renderer::<S, 5>::new(&scene);
        for area in region.rectangles() {
            draw(&renderer, &mut shown, area, aa);
        }
        let full = frame(&renderer, aa);
        for (i, (p, q)) in shown.rgb().chunks(3).zip(full.rgb().chunks(3)).enumerate() {
            prop_assert_eq!(
                p,
                q,
                "{}: pixel ({}, {}) differs after {:?}",
                S::NAME,
                i % WIDTH,
                i / WIDTH,
                changes
            );
        }
        saved.pixels += (WIDTH * HEIGHT) as u64;
        saved.left_out += (WIDTH * HEIGHT) as u64 - u64::from(region.pixels());
    }
    Ok(saved)
}

/// Renders `area` into `target`, anti-aliased by `aa` when given.
fn draw<S: Scalar>(
    renderer: &Renderer<'_, S, 5>,
    target: &mut Framebuffer,
    area: Rectangle,
    aa: Option<Antialias>,
) {
    let go_on = |_| ControlFlow::Continue(());
    match aa {
        Some(aa) => {
            let mut buffer = [AaPixel::NEW; Antialias::buffer_len(WIDTH as u16)];
            renderer
                .render_antialiased(target, area, aa, &mut buffer, go_on)
                .unwrap();
        }
        None => {
            let mut row = vec![Default::default(); WIDTH];
            renderer.render_area(target, area, &mut row, go_on).unwrap();
        }
    };
}

/// The whole frame.
fn frame<S: Scalar>(renderer: &Renderer<'_, S, 5>, aa: Option<Antialias>) -> Framebuffer {
    let mut image = Framebuffer::new(renderer.size());
    draw(
        renderer,
        &mut image,
        Rectangle::new(Point::zero(), renderer.size()),
        aa,
    );
    image
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    #[test]
    fn incremental_frames_are_full_frames(film in film()) {
        play::<f64>(&film)?;
        play::<f32>(&film)?;
        play::<I16F16>(&film)?;
    }

    #[test]
    fn incremental_frames_on_a_stage_are_full_frames(film in stage()) {
        play::<f64>(&film)?;
        play::<f32>(&film)?;
        play::<I16F16>(&film)?;
    }

    #[test]
    fn incremental_frames_in_a_gallery_are_full_frames(film in gallery()) {
        play::<f64>(&film)?;
        play::<f32>(&film)?;
        play::<I16F16>(&film)?;
    }

    /// Anti-aliased: on a grid, and only on edges (whose pixels depend on their
    /// neighbours: the region's rectangles get a border of one pixel).
    #[test]
    fn antialiased_incremental_frames_are_full_frames(film in film()) {
        play_with::<f32>(&film, Some(Antialias::GRID_4))?;
        play_with::<I16F16>(&film, Some(Antialias::Adaptive { samples: Samples::rotated(4).unwrap(), threshold: 8 }))?;
    }
}

/// A stage's props moved by straight motions over a few frames, played through
/// [`Animation::show_next_frame`] (in order, then back to the start and on again: the
/// last frame's region serves as the next one's old states) and compared with full frames.
fn play_motions<S: Scalar>(film: &Film, by: &[(usize, [f64; 3])]) -> Result<(), TestCaseError> {
    use microray::animation::{Animation, LastFrame, MotionDef, Path, Target};
    let objects: Vec<_> = film.things.iter().map(Thing::def).collect();
    let Some(mut scene) = room::<S>(film) else {
        return Ok(());
    };
    let Ok(mut animation) = Animation::<'_, 4>::new("film", 5) else {
        return Ok(());
    };
    for &(i, d) in by.iter().filter(|(i, _)| *i < objects.len()) {
        let motion = MotionDef {
            name: "m",
            path: Path::Line { by: d },
        };
        let target = Target::Object {
            index: i as u16,
            def: objects[i],
        };
        prop_assert!(animation.add_motion(&motion, target).is_ok());
    }
    let mut shown = frame(&Renderer::<S, 5>::new(&scene), None);
    let mut last = LastFrame::<8>::new();
    for k in [1, 2, 3, 4, 0, 1, 2] {
        let mut region =
            Region::<8>::new(Size::new(WIDTH as u32, HEIGHT as u32)).with_one_ray_a_pixel();
        if animation
            .show_next_frame(k, &mut scene, &mut region, &mut last)
            .is_err()
        {
            // A state the type cannot hold: as a scene file would be refused.
            return Ok(());
        }
        let renderer = Renderer::<S, 5>::new(&scene);
        for area in region.rectangles() {
            draw(&renderer, &mut shown, area, None);
        }
        let full = frame(&renderer, None);
        prop_assert!(
            shown.rgb() == full.rgb(),
            "frame {k} differs in {}",
            S::NAME
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]
    #[test]
    fn films_played_frame_after_frame_are_full_frames(
        film in stage(),
        by in prop::collection::vec((2..5usize, [-2.0..2.0f64, -2.0..2.0f64, -2.0..2.0f64]), 1..4),
    ) {
        play_motions::<f64>(&film, &by)?;
        play_motions::<f32>(&film, &by)?;
        play_motions::<I16F16>(&film, &by)?;
    }
}

/// The region leaves pixels out of random films: a third of them at least (else the
/// property above would compare full frames with themselves).
#[test]
fn regions_leave_pixels_out() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::{Config, TestRng, TestRunner};
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::deterministic_rng(Default::default()),
    );
    let mut saved = Saved::default();
    for _ in 0..100 {
        let film = film().new_tree(&mut runner).unwrap().current();
        let s = play::<f32>(&film).unwrap();
        saved.left_out += s.left_out;
        saved.pixels += s.pixels;
    }
    let share = saved.left_out as f64 / saved.pixels as f64;
    eprintln!(
        "left out: {:.1} % of {} pixels",
        100.0 * share,
        saved.pixels
    );
    assert!(share > 1.0 / 3.0, "only {:.1} % left out", 100.0 * share);
}

mod language {
    use microray::host::{HostScene, texture_files};
    use microray::parse::{parse_animation, parse_scene};
    use microray::print::{print_animation, print_scene};
    use std::path::Path;

    const FILM: &str = "camera c { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 6 }
material white { diffuse 3 3 3 }
plane floor { material white normal 0 1 0 point 0 0 0 }
sphere ball { material white center 4 1 -4 radius 1 }
light sun { location 4 9 2 emissivity 6 6 6 }
";

    fn error(text: &str) -> String {
        match parse_animation::<4>(text.as_bytes()) {
            Err(e) => e.to_string(),
            Ok(a) => panic!("{text}: read as {a:?}"),
        }
    }

    #[test]
    fn errors_name_line_column_and_what_is_wrong() {
        // The film's blocks start on line 6.
        let cases = [
            (
                "animation a { frames 0 }",
                "6:15: `frames` must be between 1 and 65535",
            ),
            (
                "animation a { frames 2.5 }",
                "6:22: `frames` takes whole numbers, found `2.5`",
            ),
            (
                "animation a { frames 9 }\nanimation b { frames 9 }",
                "7:1: second `animation` block (a scene has at most one)",
            ),
            (
                "animation a { frames 9 }\nline l { target ghost by 1 0 0 }",
                "7:10: no object or light named `ghost` (a motion moves an object or light defined before it)",
            ),
            (
                "animation a { frames 9 }\nline l { target moon by 1 0 0 }\nsphere moon { material white center 0 0 0 radius 1 }",
                "7:10: no object or light named `moon` (a motion moves an object or light defined before it)",
            ),
            (
                "bounce b { target ball height 1 bounces 0 }",
                "6:33: `bounces` must be between 1 and 65535",
            ),
            (
                "orbit o { target ball center 0 0 0 direction 0 0 0 turns 1 }",
                "6:36: `direction` must not be the zero vector",
            ),
            ("line l { target ball }", "6:1: line is missing `by`"),
            (
                "line l { target ball by 1 0 0 speed 2 }",
                "6:31: unknown attribute `speed` in line (expected target, by or `}`)",
            ),
        ];
        for (tail, expected) in cases {
            assert_eq!(error(&format!("{FILM}{tail}")), expected, "{tail}");
        }
        // Motions need the block that gives the number of frames.
        let text = format!("{FILM}bounce b {{ target ball height 1 bounces 1 }}");
        assert_eq!(
            error(&text),
            "6:44: motions but no `animation` block (it gives the number of frames: `animation clip { frames 48 }`)"
        );
    }

    #[test]
    fn a_film_prints_and_reads_back_equal() {
        let text = format!(
            "{FILM}animation clip {{ frames 30 }}
line slide {{ target ball by 1.5 0 -0.25 }}
orbit round {{ target sun center 4 9 -2 direction 0 1 0 turns -0.75 }}
bounce hop {{ target ball height 2.5 bounces 3 }}"
        );
        let scene: HostScene<'static, f64> =
            parse_scene(text.as_bytes(), texture_files(Path::new("."))).unwrap();
        let animation = parse_animation::<4>(text.as_bytes()).unwrap().unwrap();
        let mut printed = String::new();
        print_scene(&scene, &mut printed).unwrap();
        print_animation(&animation, &mut printed).unwrap();
        let again = parse_animation::<4>(printed.as_bytes()).unwrap().unwrap();
        assert_eq!(again.frames(), 30);
        assert_eq!(again.motions().len(), 3);
        for (a, b) in animation.motions().iter().zip(again.motions()) {
            assert_eq!(
                (a.name(), a.path(), a.target()),
                (b.name(), b.path(), b.target())
            );
        }
        let mut twice = String::new();
        let scene_again: HostScene<'static, f64> =
            parse_scene(printed.as_bytes(), texture_files(Path::new("."))).unwrap();
        print_scene(&scene_again, &mut twice).unwrap();
        print_animation(&again, &mut twice).unwrap();
        assert_eq!(printed, twice);
    }

    /// The motion blocks change nothing of the scene itself: frame 0 is the scene as written.
    #[test]
    fn a_scene_with_motions_is_the_scene_without() {
        let with = format!(
            "{FILM}animation clip {{ frames 8 }}\nbounce hop {{ target ball height 2 bounces 1 }}"
        );
        let a: HostScene<'static, f64> =
            parse_scene(with.as_bytes(), texture_files(Path::new("."))).unwrap();
        let b: HostScene<'static, f64> =
            parse_scene(FILM.as_bytes(), texture_files(Path::new("."))).unwrap();
        assert!(a == b);
        assert!(parse_animation::<4>(FILM.as_bytes()).unwrap().is_none());
    }
}

/// The films in scenes/: every frame, traced in its region into the previous one, equals
/// the full frame, in every number type (at 96x72: the films' own sizes take longer).
mod films {
    use super::*;
    use microray::animation::LastFrame;
    use microray::host::{HostRenderer, HostScene, texture_files};
    use microray::parse::{parse_animation, parse_scene_into};
    use std::path::Path;

    /// How a film is played: each frame by itself, or through a [`LastFrame`], in order,
    /// or jumping about with a frame now and then shown by itself (and the [`LastFrame`]
    /// told to forget).
    #[derive(Clone, Copy, PartialEq)]
    enum Play {
        Alone,
        InOrder,
        Jumping,
    }

    fn play<S: Scalar>(path: &Path, how: Play) -> (u64, u64) {
        let text = std::fs::read(path).unwrap();
        let mut scene: Box<HostScene<'static, S>> = Box::new(HostScene::empty());
        parse_scene_into(&text, texture_files(path.parent().unwrap()), &mut scene).unwrap();
        scene.set_resolution(96, 72).unwrap();
        let animation = parse_animation::<8>(&text).unwrap().unwrap();
        let size = Size::new(96, 72);
        let mut shown = Framebuffer::new(size);
        let mut traced = 0u64;
        let mut last = LastFrame::<16>::new();
        let count = animation.frames();
        // Jumping: on by one, back by two now and then, and once past the end and back.
        let order = (0..count).map(|k| match how {
            Play::Jumping if k % 5 == 4 => k - 2,
            Play::Jumping if k == count / 2 => count - 1,
            _ => k,
        });
        for (i, frame) in order.enumerate() {
            let mut region = Region::<16>::new(size).with_one_ray_a_pixel();
            if i == 0 {
                region.add_whole();
            } else if how == Play::Alone || (how == Play::Jumping && i % 7 == 3) {
                animation
                    .show_frame(frame, &mut scene, &mut region)
                    .unwrap();
                last.forget();
            } else {
                animation
                    .show_next_frame(frame, &mut scene, &mut region, &mut last)
                    .unwrap();
            }
            let renderer: HostRenderer<'_, S> = Renderer::new(&*scene);
            let mut row = vec![Default::default(); 96];
            for area in region.rectangles() {
                renderer
                    .render_area(&mut shown, area, &mut row, |_| ControlFlow::Continue(()))
                    .unwrap();
            }
            traced += u64::from(region.pixels());
            let mut full = Framebuffer::new(size);
            renderer
                .render_area(
                    &mut full,
                    Rectangle::new(Point::zero(), size),
                    &mut row,
                    |_| ControlFlow::Continue(()),
                )
                .unwrap();
            assert!(
                shown.rgb() == full.rgb(),
                "{} in {}: frame {frame} differs",
                path.display(),
                S::NAME
            );
        }
        (traced, u64::from(animation.frames()) * 96 * 72)
    }

    #[test]
    fn every_frame_of_every_film_is_the_full_frame() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
        let mut films = 0;
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            let text = std::fs::read(&path).unwrap_or_default();
            if !text.windows(10).any(|w| w == b"animation ") {
                continue;
            }
            films += 1;
            play::<f64>(&path, Play::Alone);
            play::<f32>(&path, Play::Alone);
            play::<I16F16>(&path, Play::Alone);
            play::<f64>(&path, Play::InOrder);
            play::<f32>(&path, Play::Jumping);
            let (traced, all) = play::<I16F16>(&path, Play::InOrder);
            eprintln!(
                "{}: {:.1} % traced",
                path.display(),
                100.0 * traced as f64 / all as f64
            );
        }
        assert!(films >= 4, "only {films} films in scenes/");
    }
}
