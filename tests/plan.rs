//! The render plan changes no pixel: for every conformance and project scene and every number
//! type, the planned render equals the render without a plan (every stage on, every ray
//! tested against every object), in colours and in the object-id view. And the plan does
//! skip work, or this would compare a path with itself.

mod common;

use microray::Scalar;
use microray::host::{Framebuffer, HostRenderer, HostScene, texture_files};
use microray::parse::parse_scene;
use microray::plan::Stages;
use microray::render::{Renderer, Shading};
use microray::scalar::I16F16;
use std::path::{Path, PathBuf};

fn scenes() -> Vec<PathBuf> {
    let mut scenes = common::project_scenes();
    scenes.extend(common::scene_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes"),
    ));
    if let Some(dir) = common::conformance_dir() {
        scenes.extend(common::scene_files(&dir));
    }
    scenes
}

fn load<S: Scalar>(path: &Path) -> HostScene<'static, S> {
    let text = std::fs::read(path).unwrap();
    parse_scene(&text, texture_files(path.parent().unwrap()))
        .unwrap_or_else(|e| panic!("{} in {}: {e}", path.display(), S::NAME))
}

use common::image;

/// What a scene's plan skips, summed over the scenes of one run.
#[derive(Default, Debug)]
struct Skipped {
    /// (object, row) pairs whose primary-ray tests the row lists leave out.
    culled_object_rows: u64,
    /// Stages switched off, over all scenes.
    stages_off: usize,
    /// Scenes whose shadow rays use the any-hit test.
    any_hit_shadows: usize,
    /// Rows shaded together (see `Renderer::shades_row_together`).
    rows_together: u64,
}

fn identical_with_and_without_plan<S: Scalar>() -> Skipped {
    let mut skipped = Skipped::default();
    for path in scenes() {
        let scene = load::<S>(&path);
        let planned: HostRenderer<'_, S> = Renderer::new(&scene);
        let unplanned = planned.clone().with_plan(false);
        for shading in [Shading::Color, Shading::Ids] {
            let differing = differing_pixels(
                &image(&planned.clone().with_shading(shading)),
                &image(&unplanned.clone().with_shading(shading)),
            );
            assert_eq!(
                differing,
                0,
                "{} in {} ({shading:?}): {differing} pixels differ with the plan",
                path.display(),
                S::NAME
            );
        }
        let plan = planned.plan();
        let height = scene.camera().height();
        skipped.culled_object_rows += plan
            .spans()
            .iter()
            .map(|s| u64::from(height - s.rows(height)))
            .sum::<u64>();
        let stages = plan.stages();
        let all = Stages::ALL;
        skipped.stages_off += [
            stages.illumination != all.illumination,
            stages.shadows != all.shadows,
            stages.reflection != all.reflection,
            stages.transparency != all.transparency,
            stages.glints != all.glints,
        ]
        .into_iter()
        .filter(|&off| off)
        .count();
        skipped.any_hit_shadows += usize::from(stages.shadows && !stages.filtered_shadows);
        skipped.rows_together += (0..height)
            .filter(|&row| planned.shades_row_together(row))
            .count() as u64;
    }
    eprintln!("{}: {skipped:?}", S::NAME);
    assert!(
        skipped.culled_object_rows > 0 && skipped.stages_off > 0 && skipped.any_hit_shadows > 0,
        "the plan skipped nothing: the comparison would be vacuous ({skipped:?})"
    );
    skipped
}

#[test]
fn f64_plan_changes_no_pixel() {
    let skipped = identical_with_and_without_plan::<f64>();
    // Normalised primary rays differ in every coordinate: no row is shaded together.
    assert_eq!(skipped.rows_together, 0);
}

#[test]
fn f32_plan_changes_no_pixel() {
    let skipped = identical_with_and_without_plan::<f32>();
    // The floors and walls of the scenes: the comparison covers rows shaded together.
    assert!(skipped.rows_together > 100, "{skipped:?}");
}

#[test]
fn i16f16_plan_changes_no_pixel() {
    let skipped = identical_with_and_without_plan::<I16F16>();
    assert!(skipped.rows_together > 100, "{skipped:?}");
}

/// The many-spheres scene is where row culling pays: each row's list holds only a few of
/// its hundred spheres.
#[test]
fn rows_of_many_spheres_hold_few_spheres() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/many_spheres.txt");
    let scene = load::<f32>(&path);
    let renderer: HostRenderer<'_, f32> = Renderer::new(&scene);
    let plan = renderer.plan();
    let height = scene.camera().height();
    let most = (0..height)
        .map(|y| plan.objects_in_row(y).len())
        .max()
        .unwrap();
    assert_eq!(plan.kept().len(), 101);
    // A sphere 0.5 across at distance 7.5 to 9 covers about 13 of 240 rows plus margins;
    // rows cross at most two rows of ten spheres, plus the floor.
    assert!(most <= 21, "a row holds {most} objects");
}

mod random_geometry {
    //! Row spans hold every row whose primary rays hit the object, for random cameras (eyes
    //! in front of, on and behind the image plane) and random objects of every bounded and
    //! unbounded kind, in every number type.
    use microray::object::{ObjectDef, RectDef};
    use microray::render::Renderer;
    use microray::scalar::I16F16;
    use microray::{CameraDef, MaterialDef, Scalar, Scene};
    use proptest::prelude::*;

    fn coordinate(range: std::ops::Range<f64>) -> impl Strategy<Value = f64> {
        // Whole quarters as often as not: axis-aligned and tangent cases are the edge cases.
        prop_oneof![range.clone(), range.prop_map(|v| (v * 4.0).round() / 4.0)]
    }

    fn vector(extent: f64) -> impl Strategy<Value = [f64; 3]> {
        [
            coordinate(-extent..extent),
            coordinate(-extent..extent),
            coordinate(-extent..extent),
        ]
    }

    fn direction() -> impl Strategy<Value = [f64; 3]> {
        prop_oneof![
            Just([0.0, 1.0, 0.0]),
            Just([0.0, 0.0, 1.0]),
            Just([0.0, -1.0, 1.0]),
            Just([1.0, 0.0, 0.0]),
            vector(1.0),
        ]
        .prop_filter("a direction", |v| {
            v.iter().map(|c| c * c).sum::<f64>() > 1e-3
        })
    }

    fn object() -> impl Strategy<Value = ObjectDef<'static>> {
        let rect = (
            direction(),
            vector(8.0),
            direction(),
            0.1..6.0f64,
            0.1..6.0f64,
        )
            .prop_map(|(n, p, x, w, h)| RectDef::new(n, p, x, [w, h]));
        prop_oneof![
            (vector(10.0), 0.05..4.0f64).prop_map(|(c, r)| ObjectDef::sphere("o", "m", c, r)),
            (direction(), vector(8.0)).prop_map(|(n, p)| ObjectDef::plane("o", "m", n, p)),
            rect.prop_map(|r| ObjectDef::fplane("o", "m", r)),
        ]
    }

    fn camera() -> impl Strategy<Value = [f64; 3]> {
        (
            coordinate(-4.0..12.0),
            coordinate(-4.0..10.0),
            prop_oneof![coordinate(0.5..10.0), coordinate(-6.0..0.5)],
        )
            .prop_map(|(x, y, z)| [x, y, z])
    }

    fn check<S: Scalar>(eye: [f64; 3], object: &ObjectDef<'_>) -> Result<(), TestCaseError> {
        let camera = CameraDef::new("c", [64, 48], [8.0, 6.0], eye);
        let materials = [MaterialDef::new("m").ambient([1.0; 3])];
        let Ok(scene) = Scene::<'_, S, 2, 1, 1, 0, 64>::from_defs(
            &camera,
            &materials,
            &[],
            &[],
            core::slice::from_ref(object),
        ) else {
            // Rejected for this type (a rectangle's xdir along its normal, ...).
            return Ok(());
        };
        let renderer = Renderer::new(&scene);
        let plan = renderer.plan();
        let unplanned = renderer.clone().with_plan(false);
        for row in 0..48u16 {
            let y = 47 - row;
            let seen = (0..64).any(|x| unplanned.object_at(x, row) == Some(0));
            let listed = plan.objects_in_row(y).contains(&0);
            prop_assert!(
                !seen || listed,
                "{}: row {y} sees the object but its list leaves it out (spans {:?})",
                S::NAME,
                plan.spans()
            );
        }
        // Columns likewise: rows are shaded in segments by them.
        for x in 0..64u16 {
            let seen = (0..48).any(|row| unplanned.object_at(x, row) == Some(0));
            let listed = plan.columns().first().is_some_and(|span| span.contains(x));
            prop_assert!(
                !seen || listed,
                "{}: column {x} sees the object but its span leaves it out ({:?})",
                S::NAME,
                plan.columns()
            );
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        #[test]
        fn spans_hold_every_row_and_column_that_sees_the_object(eye in camera(), object in object()) {
            check::<f64>(eye, &object)?;
            check::<f32>(eye, &object)?;
            check::<I16F16>(eye, &object)?;
        }
    }
}

mod random_rooms {
    //! Rooms of planes (floors, walls, slopes, checkerboards, sometimes a ball) under one to
    //! four lights (spotlights among them), with mirrors and glints: rows shaded together
    //! (see `Renderer::shades_row_together`) give the pixels of the render without a plan,
    //! in the types that shade rows together.
    use super::image;
    use microray::object::{ObjectDef, RectDef, TextureMode};
    use microray::render::Renderer;
    use microray::scalar::I16F16;
    use microray::{CameraDef, LightDef, MaterialDef, Scalar, Scene, TextureDef};
    use proptest::prelude::*;

    const NAMES: [&str; 4] = ["a", "b", "c", "d"];

    fn normal() -> impl Strategy<Value = [f64; 3]> {
        prop_oneof![
            Just([0.0, 1.0, 0.0]),
            Just([0.0, 0.0, 1.0]),
            Just([0.0, -1.0, 0.0]),
            Just([0.0, 1.0, 2.0]),
            Just([0.0, -1.0, 1.0]),
            Just([1.0, 0.0, 0.0]),
            Just([1.0, 0.5, 0.25]),
        ]
    }

    fn point() -> impl Strategy<Value = [f64; 3]> {
        [-6.0..6.0f64, -3.0..3.0f64, -9.0..-1.0f64]
    }

    fn object() -> impl Strategy<Value = (u8, [f64; 3], [f64; 3], usize)> {
        (0..9u8, normal(), point(), 0..4usize)
    }

    /// Diffuse, ambient, specular, shininess and transparency.
    type Material = ([f64; 3], [f64; 3], f64, f64, f64);

    fn material() -> impl Strategy<Value = Material> {
        (
            [0.0..4.0f64, 0.0..4.0f64, 0.0..4.0f64],
            prop_oneof![Just([0.0; 3]), Just([1.0; 3]), Just([0.5, 0.2, 0.1])],
            prop_oneof![Just(0.0), 0.2..0.9f64],
            prop_oneof![Just(0.0), 2.0..40.0f64],
            // Transparent in one case of three: shadow rays walk through, taking filters.
            prop_oneof![Just(0.0), Just(0.0), 0.2..0.8f64],
        )
    }

    /// A point light (0), a spotlight (1) or a projector (2).
    fn light() -> impl Strategy<Value = (u8, [f64; 3], [f64; 3], f64)> {
        (
            0..3u8,
            [-6.0..10.0f64, 0.5..12.0f64, -6.0..4.0f64],
            [1.0..8.0f64, 1.0..8.0f64, 1.0..8.0f64],
            10.0..80.0f64,
        )
    }

    type Room = (
        Vec<(u8, [f64; 3], [f64; 3], usize)>,
        Vec<Material>,
        Vec<(u8, [f64; 3], [f64; 3], f64)>,
        [f64; 3],
    );

    /// The projectors' slide: a 4x3 binary PPM of twelve colours.
    fn slide_ppm() -> Vec<u8> {
        let mut ppm = b"P6\n4 3\n255\n".to_vec();
        for i in 0..12u8 {
            ppm.extend([40 + i * 17, 250 - i * 19, 90 + i * 13]);
        }
        ppm
    }

    fn room() -> impl Strategy<Value = Room> {
        (
            prop::collection::vec(object(), 1..4),
            prop::collection::vec(material(), 4),
            prop::collection::vec(light(), 1..5),
            [1.0..7.0f64, 1.0..5.0f64, 2.0..8.0f64],
        )
    }

    fn check<S: Scalar>(room: &Room) -> Result<u64, TestCaseError> {
        let (objects, materials, lights, eye) = room;
        let materials: Vec<_> = materials
            .iter()
            .zip(NAMES)
            .map(
                |(&(diffuse, ambient, specular, shininess, transparency), name)| {
                    MaterialDef::new(name)
                        .diffuse(diffuse)
                        .ambient(ambient)
                        .specular(specular)
                        .shininess(shininess)
                        .transparency(transparency)
                },
            )
            .collect();
        let objects: Vec<_> = objects
            .iter()
            .map(|&(kind, n, p, m)| match kind {
                // Mostly plain planes: the kind rows are shaded together for.
                0..=4 => ObjectDef::plane("o", NAMES[m], n, p),
                5 | 6 => {
                    let rect = RectDef::new(n, p, [1.0, 0.0, 0.0], [1.5, 1.5]);
                    ObjectDef::tiled_plane("o", NAMES[m], rect, NAMES[(m + 1) % 4])
                }
                // A panel: rows with one are shaded in segments (its column span).
                7 => {
                    let rect = RectDef::new(n, p, [1.0, 0.0, 0.0], [2.5, 1.5]);
                    ObjectDef::fplane("o", NAMES[m], rect)
                }
                _ => ObjectDef::sphere("o", NAMES[m], p, 1.0),
            })
            .collect();
        let lights: Vec<_> = lights
            .iter()
            .map(|&(kind, at, emissivity, theta)| match kind {
                1 => LightDef::spot("l", at, emissivity, [at[0], 0.0, at[2] - 2.0], theta),
                // A slide a little below and ahead of the light, facing along z: it lights
                // what lies beyond it, its texels from the slide's image.
                2 => {
                    let corner = [at[0] - 1.0, at[1] - 1.5, at[2] - 1.0];
                    let rect = RectDef::new([0.0, 0.0, 1.0], corner, [1.0, 0.0, 0.0], [2.0, 1.5]);
                    LightDef::projector("l", at, emissivity, rect, "slide", TextureMode::Fit)
                }
                _ => LightDef::point("l", at, emissivity),
            })
            .collect();
        let ppm = slide_ppm();
        let textures = [TextureDef {
            name: "slide",
            filename: "slide.ppm",
            ppm: &ppm,
        }];
        let camera = CameraDef::new("c", [48, 36], [8.0, 6.0], *eye);
        let Ok(scene) = Scene::<'_, S, 4, 4, 4, 1, 48>::from_defs(
            &camera, &materials, &textures, &lights, &objects,
        ) else {
            // Rejected for this type (a tiled plane's xdir along its normal, ...).
            return Ok(0);
        };
        let planned: Renderer<'_, S, 4> = Renderer::new(&scene);
        let unplanned = planned.clone().with_plan(false);
        let together = (0..36)
            .filter(|&row| planned.shades_row_together(row))
            .count();
        let (a, b) = (image(&planned), image(&unplanned));
        for (i, (p, q)) in a.rgb().chunks(3).zip(b.rgb().chunks(3)).enumerate() {
            prop_assert_eq!(p, q, "{}: pixel ({}, {}) differs", S::NAME, i % 48, i / 48);
        }
        Ok(together as u64)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        #[test]
        fn rows_shaded_together_change_no_pixel(room in room()) {
            check::<f32>(&room)?;
            check::<I16F16>(&room)?;
        }

        /// Rooms whose materials differ in their colours only (one finish: specular and
        /// shininess), so that their checkerboards' rows are shaded together too (the
        /// tiles' colours found by each pixel), where random finishes almost never agree.
        #[test]
        fn checkerboard_rows_change_no_pixel(room in room()) {
            let room = one_finish(room);
            check::<f32>(&room)?;
            check::<I16F16>(&room)?;
        }

        /// In `f64` the planned render drops the planes no shadow ray to a light can cross
        /// and clears lanes by the planes' sides and the balls' cones
        /// (`src/shade/blockers.rs`): the same pixels.
        #[test]
        fn f64_blockers_change_no_pixel(room in room()) {
            check::<f64>(&room)?;
        }
    }

    /// `room` with every material's specular and shininess those of the first.
    fn one_finish(mut room: Room) -> Room {
        let (_, _, specular, shininess, _) = room.1[0];
        for material in &mut room.1 {
            (material.2, material.3) = (specular, shininess);
        }
        room
    }

    /// Rooms with a checkerboard floor are shaded together: a red and grey board (one
    /// finish, as shiny3's), a wall, a ball and its shadow, two lights (one a spotlight),
    /// and the same again behind a transparent pane (the showcase's: shadow rays take its
    /// filter).
    #[test]
    fn checkerboard_rooms_are_shaded_together() {
        let mut room: Room = (
            vec![
                (5, [0.0, 1.0, 0.0], [0.0, -1.0, -4.0], 0),
                (0, [0.0, 0.0, 1.0], [0.0, 0.0, -9.0], 2),
                (8, [0.0, 1.0, 0.0], [1.0, 0.0, -5.0], 3),
            ],
            vec![
                ([3.0, 0.0, 0.0], [0.5, 0.2, 0.1], 0.3, 0.0, 0.0),
                ([2.0; 3], [0.0; 3], 0.3, 0.0, 0.0),
                ([1.0; 3], [1.0; 3], 0.0, 0.0, 0.0),
                ([0.0, 1.0, 0.25], [0.0; 3], 0.0, 0.0, 0.6),
            ],
            vec![
                (0, [2.0, 8.0, 0.0], [4.0; 3], 0.0),
                (1, [-3.0, 6.0, -2.0], [3.0; 3], 40.0),
            ],
            [4.0, 3.0, 4.0],
        );
        // Built for size, only plain planes' rows are shaded together.
        let rows = if cfg!(microray_small) { 0 } else { 36 };
        assert_eq!(check::<f32>(&room).unwrap(), rows);
        assert_eq!(check::<I16F16>(&room).unwrap(), rows);
        room.0[2].0 = 7;
        assert_eq!(check::<f32>(&room).unwrap(), rows);
        assert_eq!(check::<I16F16>(&room).unwrap(), rows);
    }

    /// The rooms above do exercise rows shaded together (else the property is vacuous).
    #[test]
    fn rooms_are_shaded_together() {
        let room: Room = (
            vec![
                (0, [0.0, 1.0, 0.0], [0.0, -1.0, -4.0], 0),
                (1, [0.0, 0.0, 1.0], [0.0, 0.0, -6.0], 1),
            ],
            vec![
                ([2.0; 3], [1.0; 3], 0.5, 0.0, 0.0),
                ([1.0, 3.0, 1.0], [0.0; 3], 0.0, 10.0, 0.0),
                ([1.0; 3], [0.0; 3], 0.0, 0.0, 0.0),
                ([1.0; 3], [0.0; 3], 0.0, 0.0, 0.0),
            ],
            vec![(0, [2.0, 8.0, 0.0], [4.0; 3], 0.0)],
            [4.0, 3.0, 4.0],
        );
        assert_eq!(check::<f32>(&room).unwrap(), 36);
        assert_eq!(check::<I16F16>(&room).unwrap(), 36);
    }

    /// So are rooms lit by a projector (as the vases' scene): a floor, a wall, a ball and
    /// a glass ball, a projector throwing its slide over them and a point light; each
    /// pixel finds its texel on the slide. Without the slide's look-up in the rows, the
    /// pixels it lights would differ.
    #[test]
    fn projected_rooms_are_shaded_together() {
        let room: Room = (
            vec![
                (0, [0.0, 1.0, 0.0], [0.0, -1.0, -4.0], 0),
                (0, [0.0, 0.0, 1.0], [0.0, 0.0, -8.0], 1),
                (8, [0.0, 1.0, 0.0], [0.5, 0.0, -5.0], 2),
                (8, [0.0, 1.0, 0.0], [-2.0, 0.5, -6.0], 3),
            ],
            vec![
                ([2.0; 3], [0.2; 3], 0.0, 0.0, 0.0),
                ([1.5; 3], [0.0; 3], 0.0, 20.0, 0.0),
                ([3.0, 2.0, 1.0], [0.0; 3], 0.0, 0.0, 0.0),
                ([0.5, 1.0, 2.0], [0.0; 3], 0.0, 0.0, 0.5),
            ],
            vec![
                (2, [0.0, 4.0, 2.0], [40.0; 3], 0.0),
                (0, [3.0, 8.0, 0.0], [4.0; 3], 0.0),
            ],
            [0.0, 1.0, 6.0],
        );
        // Built for size, rows lit by a projector are shaded pixel by pixel.
        let rows = if cfg!(microray_small) { 0 } else { 36 };
        assert_eq!(check::<f32>(&room).unwrap(), rows);
        assert_eq!(check::<I16F16>(&room).unwrap(), rows);
    }

    /// So are rooms whose shadow rays pass through a transparent panel (as the course's
    /// translucent scenes): a wall, a green pane before it, two lights.
    #[test]
    fn translucent_rooms_are_shaded_together() {
        let room: Room = (
            vec![
                (0, [0.0, 0.0, 1.0], [0.0, 0.0, -8.0], 0),
                (7, [0.0, 0.0, 1.0], [-1.0, -0.5, -5.0], 1),
            ],
            vec![
                ([2.0; 3], [0.0; 3], 0.0, 0.0, 0.0),
                ([0.0, 1.0, 0.25], [0.0; 3], 0.0, 0.0, 0.6),
                ([1.0; 3], [0.0; 3], 0.0, 0.0, 0.0),
                ([1.0; 3], [0.0; 3], 0.0, 0.0, 0.0),
            ],
            vec![
                (0, [-4.0, 3.0, 3.0], [5.0; 3], 0.0),
                (0, [4.0, 3.0, 3.0], [5.0; 3], 0.0),
            ],
            [0.0, 0.0, 8.0],
        );
        // Built for size, rows whose shadow rays take filters are shaded pixel by pixel.
        let rows = if cfg!(microray_small) { 0 } else { 36 };
        assert_eq!(check::<f32>(&room).unwrap(), rows);
        assert_eq!(check::<I16F16>(&room).unwrap(), rows);
        // A glass ball between the wall and the pane, before the pane in the scene's list:
        // a walk's first step must take the ball, the nearer, though the pane's prepared
        // test comes after it (and hits too).
        let mut room = room;
        room.0.insert(1, (8, [0.0, 1.0, 0.0], [0.5, 0.5, -6.5], 2));
        room.1[2] = ([1.0, 0.5, 0.0], [0.0; 3], 0.0, 0.0, 0.5);
        assert_eq!(check::<f32>(&room).unwrap(), rows);
        assert_eq!(check::<I16F16>(&room).unwrap(), rows);
    }
}

/// The side tests of the lights' blockers (`src/shade/blockers.rs`) on a scene made for
/// them: four infinite planes, three leaning, a mirror, hit points in shadow and in light,
/// and a light 1e-10 from a plane. `f64` only (the side test's only type); the scene is not
/// among the parity scenes, which it would fail on purpose (a light that close to a plane
/// is on either side of it in `f32` and Q16.16).
#[test]
fn side_tests_change_no_pixel() {
    assert_eq!(blockers_scene_differs("leaning_planes.txt"), 0);
}

/// The lights' cones and sides (`src/shade/blockers.rs`) on balls and planes made for them:
/// a ball resting on the floor, one floating near a light, a wall no shadow ray crosses.
#[test]
fn cones_change_no_pixel() {
    assert_eq!(blockers_scene_differs("balls_on_a_floor.txt"), 0);
}

/// The pixels of a scene of `tests/blockers` that differ between its `f64` renders with
/// and without the plan (planned `f64` colour rows are shaded in batches,
/// `render::shade_batches`, where the blockers are used).
fn blockers_scene_differs(file: &str) -> usize {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/blockers")
        .join(file);
    let scene = load::<f64>(&path);
    let planned: HostRenderer<'_, f64> = Renderer::new(&scene);
    let unplanned = planned.clone().with_plan(false);
    differing_pixels(&image(&planned), &image(&unplanned))
}

/// Pixels where two images of one size differ.
fn differing_pixels(a: &Framebuffer, b: &Framebuffer) -> usize {
    a.rgb()
        .chunks(3)
        .zip(b.rgb().chunks(3))
        .filter(|(p, q)| p != q)
        .count()
}
