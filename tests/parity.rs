//! Parity: every number type, rendered through the no_std path into a `SimulatorDisplay`,
//! against the std tracer's f64 image of the same scene. Prints a table of the error of
//! each type and asserts the bounds of the number-types issue.

mod common;

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use embedded_graphics::prelude::*;
use embedded_graphics_simulator::SimulatorDisplay;
use microray::Scalar;
use microray::host::{Difference, Framebuffer, HostScene, object_ids, texture_files};
use microray::parse::parse_scene;
use microray::render::{Renderer, render};
use microray::scalar::I16F16;
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

struct Image {
    width: usize,
    rgb: Vec<[u8; 3]>,
    ids: Vec<Option<usize>>,
    /// Pixels whose primary ray meets a rectangle's plane exactly on the rectangle's edge,
    /// or a textured rectangle exactly on an edge between two texels (within 1e-9 of the
    /// size, in f64): in exact arithmetic a tie, so any rounding decides. fplane0, fplane4,
    /// spec1 and spec3 put a rectangle's edge on the centres of a whole pixel column (world
    /// x = 0 is pixel column 0); texplane1 and texplane2 put texel edges on two columns
    /// (213 and 426 of 640: a third of the wall, where a texel edge lies).
    ties: Vec<bool>,
}

fn load<S: Scalar>(path: &Path) -> HostScene<'static, S> {
    let text = std::fs::read(path).unwrap();
    parse_scene(&text, texture_files(path.parent().unwrap()))
        .unwrap_or_else(|e| panic!("{} in {}: {e}", path.display(), S::NAME))
}

/// The std tracer: f64 into the host framebuffer.
fn reference(path: &Path) -> Image {
    let scene = load::<f64>(path);
    let renderer = Renderer::new(&scene);
    let mut image = Framebuffer::new(renderer.size());
    render(&scene, &mut image).unwrap();
    let rgb = image.rgb().chunks(3).map(|p| [p[0], p[1], p[2]]).collect();
    let ties = common::ties(&scene);
    Image {
        width: renderer.size().width as usize,
        rgb,
        ids: object_ids(&renderer),
        ties,
    }
}

/// The no_std path: `S` into embedded-graphics-simulator's display.
fn no_std<S: Scalar>(path: &Path) -> Image {
    let scene = load::<S>(path);
    let renderer = Renderer::new(&scene);
    let size = renderer.size();
    let mut display = SimulatorDisplay::<Rgb888>::new(size);
    render(&scene, &mut display).unwrap();
    let mut rgb = Vec::new();
    for y in 0..size.height as i32 {
        for x in 0..size.width as i32 {
            let c = display.get_pixel(Point::new(x, y));
            rgb.push([c.r(), c.g(), c.b()]);
        }
    }
    Image {
        width: size.width as usize,
        rgb,
        ids: object_ids(&renderer),
        ties: Vec::new(),
    }
}

#[derive(Debug)]
struct Stats {
    identical: f64,
    within_one: f64,
    max_difference: u8,
    psnr: f64,
    id_mismatches: usize,
    appeared: BTreeSet<usize>,
    vanished: BTreeSet<usize>,
    /// Pixels that see the same object but are off by more than 1 in a channel where the f64
    /// image is smooth: the difference exceeds the channel's contrast in the f64 image's 5x5
    /// neighbourhood (+1). Differences on shadow, texel and highlight edges (also seen in
    /// mirrors) stay within the contrast that is there; silhouettes count as id mismatches.
    off_edge: usize,
    /// Pixels left out of the statistics above: exact ties (see [`Image::ties`]).
    ties: usize,
}

fn difference(a: [u8; 3], b: [u8; 3]) -> u8 {
    (0..3).map(|i| a[i].abs_diff(b[i])).max().unwrap()
}

/// Whether `colour` differs from the reference at pixel `i`, channel by channel, by no more
/// than the reference's contrast in the 5x5 neighbourhood (+1): an edge moved by up to two
/// pixels.
fn within_local_contrast(reference: &Image, i: usize, colour: [u8; 3]) -> bool {
    let (w, h) = (
        reference.width as isize,
        (reference.rgb.len() / reference.width) as isize,
    );
    let (x, y) = (
        (i % reference.width) as isize,
        (i / reference.width) as isize,
    );
    let (mut low, mut high) = ([255u8; 3], [0u8; 3]);
    for dy in -2..=2 {
        for dx in -2..=2 {
            let (nx, ny) = (x + dx, y + dy);
            if nx >= 0 && ny >= 0 && nx < w && ny < h {
                let c = reference.rgb[(ny * w + nx) as usize];
                for k in 0..3 {
                    low[k] = low[k].min(c[k]);
                    high[k] = high[k].max(c[k]);
                }
            }
        }
    }
    let own = reference.rgb[i];
    (0..3).all(|k| own[k].abs_diff(colour[k]) <= (high[k] - low[k]).saturating_add(1))
}

fn compare(reference: &Image, other: &Image) -> Stats {
    assert_eq!(reference.rgb.len(), other.rgb.len());
    let bytes = |image: &Image| image.rgb.iter().flatten().copied().collect::<Vec<u8>>();
    let pixels = Difference::between(&bytes(reference), &bytes(other), |i| reference.ties[i]);
    let mut off_edge = 0;
    let mut id_mismatches = 0;
    for i in (0..reference.rgb.len()).filter(|&i| !reference.ties[i]) {
        let other_object = reference.ids[i] != other.ids[i];
        id_mismatches += usize::from(other_object);
        // A pixel that sees another object is on a silhouette: the id statistics judge it
        // (no object appears or vanishes, few such pixels), not the neighbourhood's contrast
        // (a grazing hit on a sphere's rim is darker than anything around it).
        if !other_object
            && difference(reference.rgb[i], other.rgb[i]) > 1
            && !within_local_contrast(reference, i, other.rgb[i])
        {
            off_edge += 1;
        }
    }
    let seen = |image: &Image| image.ids.iter().flatten().copied().collect::<BTreeSet<_>>();
    let (before, after) = (seen(reference), seen(other));
    Stats {
        identical: pixels.identical_percent(),
        within_one: pixels.within_one_percent(),
        max_difference: pixels.largest,
        psnr: pixels.psnr(),
        id_mismatches,
        appeared: after.difference(&before).copied().collect(),
        vanished: before.difference(&after).copied().collect(),
        off_edge,
        ties: reference.ties.iter().filter(|&&t| t).count(),
    }
}

fn scenes() -> Vec<PathBuf> {
    let mut all = common::project_scenes();
    all.extend(common::scene_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes"),
    ));
    if let Some(dir) = common::conformance_dir() {
        all.extend(common::scene_files(&dir));
    }
    if let Some(dir) = common::course_extensions_dir() {
        all.extend(common::scene_files(&dir));
    }
    all
}

#[test]
fn every_number_type_against_the_f64_std_tracer() {
    let mut table = String::from(
        "| scene | type | identical % | within ±1 % | max diff | PSNR dB | id mismatches | off-edge | exact ties left out |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut failures = Vec::new();
    for path in scenes() {
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        let f64_image = reference(&path);
        for (number, image) in [
            ("f32", no_std::<f32>(&path)),
            ("i16f16", no_std::<I16F16>(&path)),
        ] {
            let s = compare(&f64_image, &image);
            writeln!(
                table,
                "| {name} | {number} | {:.3} | {:.3} | {} | {:.1} | {} | {} | {} |",
                s.identical,
                s.within_one,
                s.max_difference,
                s.psnr,
                s.id_mismatches,
                s.off_edge,
                s.ties
            )
            .unwrap();
            // Silhouettes may move by rounding, on at most 1 pixel in 2,000.
            let few_silhouette_moves = s.id_mismatches as f64 <= image.rgb.len() as f64 / 2000.0;
            let ok = few_silhouette_moves
                && match number {
                    // Where a channel is off by more than 2 the difference is an edge that sits
                    // on a pixel centre (texel edges in texplane1/2, the x = 0 edge and tile edges
                    // seen in the mirrors of spec1/3 and shiny3, texel edges thrown by proj3's
                    // slide and seen in texplane5, revsurfa's silhouette): allowed, but only on
                    // edges.
                    "f32" => {
                        let edge_scenes = [
                            "texplane1",
                            "texplane2",
                            "spec1",
                            "spec3",
                            "shiny3",
                            "proj3",
                            "texplane5",
                            "revsurfa",
                        ];
                        s.identical >= 99.9
                            && (s.max_difference <= 2
                                || (edge_scenes.contains(&name.as_str()) && s.off_edge == 0))
                    }
                    // At most 1 pixel in 100,000 off in a smooth region: spec3's twelve mirror
                    // bounces leave one pixel 4 levels off (measured).
                    _ => {
                        s.within_one >= 99.0
                            && s.psnr >= 40.0
                            && s.appeared.is_empty()
                            && s.vanished.is_empty()
                            && s.off_edge as f64 <= image.rgb.len() as f64 / 100_000.0
                    }
                };
            if !ok {
                failures.push(format!("{name} {number}: {s:?}"));
            }
        }
    }
    eprintln!("{table}");
    assert!(
        failures.is_empty(),
        "outside the bounds:\n{}",
        failures.join("\n")
    );
}
