//! Regression tests for the defects the random-scene differential suite found (issue 36),
//! each built from its reproducer in `tests/scenes/defects/`.

mod common;

use microray::host::{HostRenderer, HostScene};
use microray::parse::{no_textures, parse_scene};
use microray::render::Renderer;
use microray::scalar::I16F16;
use microray::{Scalar, Vec3};
use std::path::Path;

fn defect(name: &str) -> Vec<u8> {
    std::fs::read(Path::new("tests/scenes/defects").join(name)).unwrap()
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
