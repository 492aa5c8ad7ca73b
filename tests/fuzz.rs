//! A bounded byte fuzz that `cargo test` runs: 100,000 mutations of the project's own scenes
//! (bytes flipped, inserted, deleted, blocks spliced), each parsed in every number type and,
//! when it loads, rendered at 8x6 (a film's first frames too, each in its region). Nothing
//! may panic (overflow checks are on in tests).
//! The open-ended fuzzers are in `fuzz/` (`cargo +nightly fuzz run parse`).

use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use microray::Scalar;
use microray::Scene;
use microray::error::TextureError;
use microray::parse::{parse_animation, parse_scene};
use microray::region::Region;
use microray::render::Renderer;
use microray::render::render;
use microray::scalar::I16F16;
use proptest::prelude::*;
use std::convert::Infallible;
use std::ops::ControlFlow;
use std::path::Path;
use std::sync::OnceLock;

fn seeds() -> &'static Vec<Vec<u8>> {
    static SEEDS: OnceLock<Vec<Vec<u8>>> = OnceLock::new();
    SEEDS.get_or_init(|| {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut seeds = Vec::new();
        for dir in ["scenes", "tests/stress", "tests/scenes"] {
            for entry in std::fs::read_dir(root.join(dir)).unwrap() {
                let path = entry.unwrap().path();
                if path.extension().is_some_and(|e| e == "txt") {
                    seeds.push(std::fs::read(path).unwrap());
                }
            }
        }
        seeds.sort();
        seeds
    })
}

fn texture(_: &str) -> Result<&'static [u8], TextureError> {
    Ok(b"P6 2 1 255 \x10\x20\x30\x40\x50\x60")
}

struct Sink(usize);

impl OriginDimensions for Sink {
    fn size(&self) -> Size {
        Size::new(8, 6)
    }
}

impl DrawTarget for Sink {
    type Color = Rgb888;
    type Error = Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Infallible> {
        self.0 += pixels.into_iter().count();
        Ok(())
    }
}

/// Parses, and renders what loads; returns whether it loaded.
fn run<S: Scalar>(bytes: &[u8]) -> bool {
    let Ok(mut scene) = parse_scene::<S, 128, 16, 8, 2, 1024>(bytes, texture) else {
        return false;
    };
    if scene.set_resolution(8, 6).is_ok() {
        let mut sink = Sink(0);
        let _ = render(&scene, &mut sink);
        assert_eq!(sink.0, 48);
        play(bytes, &mut scene);
    }
    true
}

/// A film's first frames, each rendered in its region: every pixel of the region drawn.
fn play<S: Scalar>(bytes: &[u8], scene: &mut Scene<'_, S, 128, 16, 8, 2, 1024>) {
    let Ok(Some(animation)) = parse_animation::<4>(bytes) else {
        return;
    };
    for frame in 1..animation.frames().min(3) {
        let mut region = Region::<4>::new(Size::new(8, 6));
        let moved = animation.show_frame(frame, scene, &mut region);
        let renderer = Renderer::new(&*scene);
        let mut sink = Sink(0);
        let mut row = [Rgb888::BLACK; 8];
        for area in region.rectangles() {
            let _ = renderer.render_area(&mut sink, area, &mut row, |_| ControlFlow::Continue(()));
        }
        if moved.is_ok() {
            assert_eq!(sink.0 as u32, region.pixels());
        }
    }
}

#[derive(Clone, Debug)]
enum Edit {
    Flip(usize, u8),
    Insert(usize, u8),
    Delete(usize, usize),
    Splice(usize, usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    // Bytes the language is made of, so edits make near-valid scenes.
    let byte = prop_oneof![
        any::<u8>(),
        prop::sample::select(b"0123456789.-+e{} \n#".to_vec()),
    ];
    prop_oneof![
        (any::<usize>(), byte.clone()).prop_map(|(at, b)| Edit::Flip(at, b)),
        (any::<usize>(), byte).prop_map(|(at, b)| Edit::Insert(at, b)),
        (any::<usize>(), 1usize..40).prop_map(|(at, n)| Edit::Delete(at, n)),
        (any::<usize>(), any::<usize>(), 1usize..200).prop_map(|(a, b, n)| Edit::Splice(a, b, n)),
    ]
}

fn mutate(seed: &[u8], edits: &[Edit]) -> Vec<u8> {
    let mut bytes = seed.to_vec();
    for e in edits {
        let len = bytes.len().max(1);
        match *e {
            Edit::Flip(at, b) if !bytes.is_empty() => bytes[at % len] = b,
            Edit::Insert(at, b) => bytes.insert(at % (bytes.len() + 1), b),
            Edit::Delete(at, n) if !bytes.is_empty() => {
                let start = at % len;
                let end = (start + n).min(bytes.len());
                bytes.drain(start..end);
            }
            Edit::Splice(from, to, n) if !bytes.is_empty() => {
                // A run of the scene copied elsewhere in it: duplicated blocks and attributes.
                let start = from % len;
                let run: Vec<u8> = bytes[start..(start + n).min(bytes.len())].to_vec();
                let at = to % (bytes.len() + 1);
                bytes.splice(at..at, run);
            }
            _ => {}
        }
    }
    bytes
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 100_000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenes_never_panic(seed in any::<prop::sample::Index>(), edits in prop::collection::vec(edit(), 1..4)) {
        let seeds = seeds();
        let bytes = mutate(seeds[seed.index(seeds.len())].as_slice(), &edits);
        run::<f64>(&bytes);
        run::<f32>(&bytes);
        run::<I16F16>(&bytes);
    }
}

/// The fuzz is not vacuous: a fair share of mutants still load and render.
#[test]
fn many_mutants_still_load() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strategy = (
        any::<prop::sample::Index>(),
        prop::collection::vec(edit(), 1..4),
    );
    let seeds = seeds();
    let loaded = (0..2000)
        .filter(|_| {
            let (seed, edits) = strategy.new_tree(&mut runner).unwrap().current();
            run::<f32>(&mutate(seeds[seed.index(seeds.len())].as_slice(), &edits))
        })
        .count();
    eprintln!("{loaded} of 2000 mutants load");
    assert!(loaded >= 100, "only {loaded} of 2000 mutants load");
}
