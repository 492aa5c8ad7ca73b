//! The random-scene differential suite: seeded random valid scenes (`differential/generator.rs`)
//! through every pair of paths that must agree.
//!
//! In f64, byte for byte: the render plan against none (also anti-aliased on a grid and
//! adaptively, and dithered to RGB565), one thread against three, the progressive order
//! against the plain one, and the printed scene read back (and printed again: the same
//! text). Against f64, f32 and I16F16 either refuse the scene with a range error (never
//! another) or render it with no more than 2 % of its pixels off by more than 16 levels in
//! a channel, unless the scene has a warning (`Scene::warnings`: its picture is rounding's).
//!
//! `cargo test --test differential` runs [`SCENES`] scenes from seed 0;
//! `MICRORAY_DIFFERENTIAL_SCENES=N` and `MICRORAY_DIFFERENTIAL_FIRST=K` run seeds `K..K+N`
//! (the long run in `docs/differential.md`), printing a summary;
//! `MICRORAY_DIFFERENTIAL_DUMP=DIR` writes each failing scene to `DIR/SEED/scene.txt`.

mod common;
#[path = "differential/generator.rs"]
mod generator;

use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use microray::dither::Rgb565Dither;
use microray::error::TextureError;
use microray::host::{Framebuffer, HostRenderer, HostScene, antialiased, render_parallel};
use microray::parse::parse_scene;
use microray::print::print_scene;
use microray::render::{Antialias, Renderer};
use microray::scalar::I16F16;
use microray::{Error, ErrorKind, Scalar};
use std::ops::ControlFlow;

/// Scenes a plain `cargo test` runs.
const SCENES: u64 = 300;

/// At most this share of pixels may be off by more than [`LEVELS`] in f32 or I16F16.
const OFF_SHARE: f64 = 0.02;
const LEVELS: u8 = 16;

fn load<'g, S: Scalar>(
    text: &[u8],
    scene: &'g generator::Generated,
) -> Result<HostScene<'g, S>, Error> {
    parse_scene(text, |name: &str| {
        scene.texture(name).ok_or(TextureError::NotFound)
    })
}

fn draw<D>(renderer: &HostRenderer<'_, f64>, target: &mut D)
where
    D: DrawTarget,
    D::Color: From<Rgb888> + Default,
    D::Error: std::fmt::Debug,
{
    let size = renderer.size();
    let mut row = vec![D::Color::default(); size.width as usize];
    renderer
        .render_area(
            target,
            Rectangle::new(Point::zero(), size),
            &mut row,
            |_| ControlFlow::Continue(()),
        )
        .unwrap();
}

fn plain<S: Scalar>(scene: &HostScene<'_, S>, planned: bool) -> Vec<u8> {
    let renderer: HostRenderer<'_, S> = Renderer::new(scene).with_plan(planned);
    common::image(&renderer).rgb().to_vec()
}

/// How a scene fared, for the summary of a long run.
#[derive(Default, Debug)]
struct Tally {
    scenes: u64,
    warned: u64,
    refused: [u64; 2],
    compared: [u64; 2],
    /// Scenes without a warning over the bound, and the worst share among them.
    over: [u64; 2],
    worst: [f64; 2],
    /// Scenes with a warning over the bound (allowed).
    warned_over: [u64; 2],
}

/// Every check of one scene; failures are pushed as text.
fn check(seed: u64, tally: &mut Tally, failures: &mut Vec<String>) {
    let generated = generator::scene(seed);
    let text = generated.text.as_bytes();
    let mut fail = |what: String| {
        dump(seed, &generated);
        failures.push(format!("seed {seed}: {what}"));
    };
    let scene = match load::<f64>(text, &generated) {
        Ok(scene) => scene,
        Err(e) => {
            return fail(format!(
                "f64 refuses a valid scene: {e}\n{}",
                generated.text
            ));
        }
    };
    tally.scenes += 1;
    let mut warned = false;
    scene.warnings(|w| {
        warned = true;
        if std::env::var("MICRORAY_DIFFERENTIAL_VERBOSE").is_ok() {
            eprintln!("seed {seed}: warning: {w}");
        }
    });
    tally.warned += u64::from(warned);

    // The plan against none, plain, anti-aliased and dithered.
    let reference = plain(&scene, true);
    if plain(&scene, false) != reference {
        fail("--no-plan differs".into());
    }
    let planned: HostRenderer<'_, f64> = Renderer::new(&scene);
    let unplanned: HostRenderer<'_, f64> = Renderer::new(&scene).with_plan(false);
    for aa in [Antialias::GRID_4, Antialias::ADAPTIVE] {
        let (a, b) = (
            antialiased(&planned, aa).unwrap(),
            antialiased(&unplanned, aa).unwrap(),
        );
        if a.rgb() != b.rgb() {
            fail(format!("--no-plan differs anti-aliased ({aa:?})"));
        }
    }
    let size = planned.size();
    let mut dithered = [
        common::Panel::<Rgb565>::new(size.width, size.height),
        common::Panel::<Rgb565>::new(size.width, size.height),
    ];
    draw(&planned, &mut Rgb565Dither::new(&mut dithered[0]));
    draw(&unplanned, &mut Rgb565Dither::new(&mut dithered[1]));
    if dithered[0].pixels != dithered[1].pixels {
        fail("--no-plan differs dithered".into());
    }

    // Threads and the progressive order.
    let threaded = render_parallel(&planned, 3, None, |_| {}).unwrap();
    if threaded.rgb() != reference.as_slice() {
        fail("three threads differ from one".into());
    }
    let mut progressive = Framebuffer::new(size);
    let mut row = vec![Rgb888::BLACK; size.width as usize];
    planned
        .render_progressive(&mut progressive, &mut row, |_| ControlFlow::Continue(()))
        .unwrap();
    if progressive.rgb() != reference.as_slice() {
        fail("the progressive order differs".into());
    }

    // The print round trip.
    let mut printed = String::new();
    print_scene(&scene, &mut printed).unwrap();
    match load::<f64>(printed.as_bytes(), &generated) {
        Err(e) => fail(format!(
            "the printed scene does not read back: {e}\n{printed}"
        )),
        Ok(again) => {
            let mut twice = String::new();
            print_scene(&again, &mut twice).unwrap();
            if twice != printed {
                fail("printing the read-back scene gives other text".into());
            }
            if plain(&again, true) != reference {
                fail("the printed scene renders differently".into());
            }
        }
    }

    // The other number types against f64.
    for (k, other) in [
        typed::<f32>(text, &generated),
        typed::<I16F16>(text, &generated),
    ]
    .into_iter()
    .enumerate()
    {
        let name = ["f32", "i16f16"][k];
        match other {
            Err(e) if clean_refusal(&e.kind) => tally.refused[k] += 1,
            Err(e) => fail(format!("{name} refuses with a non-range error: {e}")),
            Ok(image) => {
                tally.compared[k] += 1;
                let share = off_share(&reference, &image);
                if share > OFF_SHARE {
                    if warned {
                        tally.warned_over[k] += 1;
                        if std::env::var("MICRORAY_DIFFERENTIAL_VERBOSE").is_ok() {
                            eprintln!(
                                "seed {seed}: warned and over: {name} {:.1} %",
                                share * 100.0
                            );
                        }
                    } else {
                        tally.over[k] += 1;
                        fail(format!(
                            "{name}: {:.1} % of pixels off by more than {LEVELS} (nasty: {:?})\n{}",
                            share * 100.0,
                            generated.nasty,
                            generated.text
                        ));
                    }
                }
                if !warned {
                    tally.worst[k] = tally.worst[k].max(share);
                }
            }
        }
    }
}

/// Writes a failing scene and its textures to `MICRORAY_DIFFERENTIAL_DUMP/SEED/`, if set,
/// for `microray render` and `microray check`.
fn dump(seed: u64, generated: &generator::Generated) {
    let Ok(dir) = std::env::var("MICRORAY_DIFFERENTIAL_DUMP") else {
        return;
    };
    let dir = std::path::Path::new(&dir).join(seed.to_string());
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("scene.txt"), &generated.text).unwrap();
    for (file, bytes) in &generated.textures {
        std::fs::write(dir.join(file), bytes).unwrap();
    }
}

fn typed<S: Scalar>(text: &[u8], generated: &generator::Generated) -> Result<Vec<u8>, Error> {
    Ok(plain(&load::<S>(text, generated)?, true))
}

/// The refusals a number type may give a valid scene: its range and resolution.
fn clean_refusal(kind: &ErrorKind) -> bool {
    matches!(
        kind,
        ErrorKind::BeyondRange { .. }
            | ErrorKind::TooSmallForType { .. }
            | ErrorKind::ScaledBelowResolution { .. }
            | ErrorKind::PixelsTooFine { .. }
    )
}

/// The share of pixels whose largest channel difference exceeds [`LEVELS`].
fn off_share(a: &[u8], b: &[u8]) -> f64 {
    let off = a
        .chunks(3)
        .zip(b.chunks(3))
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > LEVELS))
        .count();
    off as f64 / (a.len() / 3) as f64
}

fn env(name: &str) -> Option<u64> {
    std::env::var(name).ok().map(|v| v.parse().unwrap())
}

#[test]
fn random_scenes_agree_across_paths_and_types() {
    let first = env("MICRORAY_DIFFERENTIAL_FIRST").unwrap_or(0);
    let count = env("MICRORAY_DIFFERENTIAL_SCENES").unwrap_or(SCENES);
    let mut tally = Tally::default();
    let mut failures = Vec::new();
    for seed in first..first + count {
        check(seed, &mut tally, &mut failures);
    }
    eprintln!("seeds {first}..{}: {tally:?}", first + count);
    assert_eq!(tally.scenes, count, "{}", failures.join("\n\n"));
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n\n")
    );
    // Not vacuous: most scenes load in every type, and the nasty cases and warnings occur.
    if count >= 100 {
        assert!(tally.compared[0] * 10 >= count * 9, "{tally:?}");
        assert!(tally.compared[1] * 2 >= count, "{tally:?}");
        assert!(tally.warned * 50 >= count, "{tally:?}");
    }
}

#[test]
fn the_generator_covers_every_kind_and_nasty_case() {
    let mut text = String::new();
    let mut nasty = std::collections::BTreeSet::new();
    for seed in 0..SCENES {
        let g = generator::scene(seed);
        text.push_str(&g.text);
        nasty.extend(g.nasty);
    }
    for keyword in [
        "\nplane ",
        "\nsphere ",
        "\nfplane ",
        "\ntiled_plane ",
        "\ntexplane ",
        "\nrevsurf ",
        "\nlight ",
        "\nspotlight ",
        "\nprojector ",
        "\ntexture ",
        "  specular ",
        "  shininess ",
        "  transparency ",
    ] {
        assert!(text.contains(keyword), "no {keyword:?} in {SCENES} scenes");
    }
    assert_eq!(nasty.len(), 14, "{nasty:?}");
}
