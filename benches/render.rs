//! Host run time of every number type on every scene (course scenes from
//! `MICRORAY_CONFORMANCE`, the project's `scenes/` and `tests/scenes/`), at the scene's own
//! size and at 320x240. The render only: parsing happens outside the measured loop.
//!
//! Benchmark ids are `SCENE/NUMBER/SIZE` (`spec0/f32/320x240`, `spec0/f64/native`), and
//! `SCENE/NUMBER/noplan` for 320x240 without the render plan, `SCENE/aa/MODE` for the
//! course's scenes anti-aliased (f64, 320x240); `cargo xtask bench` runs them
//! and collects the medians.

use criterion::{Criterion, criterion_group, criterion_main};

use microray::Scalar;
use microray::host::{Framebuffer, HostRenderer, HostScene, texture_files};
use microray::parse::parse_scene;
use microray::render::{AaPixel, Antialias, Renderer, render};
use microray::scalar::I16F16;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::time::Duration;

fn scene_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut dirs = vec![root.join("scenes"), root.join("tests/scenes")];
    if let Some(dir) = std::env::var_os("MICRORAY_CONFORMANCE") {
        dirs.push(root.join(dir));
    }
    let mut files = Vec::new();
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "txt") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

fn bench_type<S: Scalar>(c: &mut Criterion, path: &Path) {
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("?");
    let text = std::fs::read(path).expect("readable scene");
    let Ok(mut scene) = parse_scene::<S, 256, 64, 32, 16, 8192>(
        &text,
        texture_files(path.parent().unwrap_or(Path::new("."))),
    ) else {
        return;
    };
    for size in ["native", "320x240"] {
        if size != "native" && scene.set_resolution(320, 240).is_err() {
            continue;
        }
        let cam = scene.camera();
        let mut image = Framebuffer::new(embedded_graphics::prelude::Size::new(
            u32::from(cam.width()),
            u32::from(cam.height()),
        ));
        let scene: &HostScene<'_, S> = &scene;
        c.bench_function(&format!("{name}/{}/{size}", S::NAME), |b| {
            b.iter(|| render(scene, &mut image).expect("renders"));
        });
        if size == "320x240" && S::NAME == "f64" && is_course_scene(path) {
            bench_antialiasing(c, name, scene, &mut image);
        }
        if size == "320x240" {
            let unplanned: HostRenderer<'_, S> = Renderer::new(scene).with_plan(false);
            let all =
                embedded_graphics::primitives::Rectangle::new(Default::default(), unplanned.size());
            let mut row = vec![Default::default(); 320];
            c.bench_function(&format!("{name}/{}/noplan", S::NAME), |b| {
                b.iter(|| {
                    unplanned
                        .render_area(&mut image, all, &mut row, |_| ControlFlow::Continue(()))
                        .expect("renders")
                });
            });
        }
    }
}

/// Whether a scene is one of the course's (under `MICRORAY_CONFORMANCE`).
fn is_course_scene(path: &Path) -> bool {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    std::env::var_os("MICRORAY_CONFORMANCE").is_some_and(|dir| path.starts_with(root.join(dir)))
}

/// `SCENE/aa/MODE`: the scene anti-aliased as the firmware's anti-aliased frames are (4, 9
/// and 16 samples a pixel, and adaptively), at 320x240 in f64.
fn bench_antialiasing<S: Scalar>(
    c: &mut Criterion,
    name: &str,
    scene: &HostScene<'_, S>,
    image: &mut Framebuffer,
) {
    let renderer: HostRenderer<'_, S> = Renderer::new(scene);
    let all = embedded_graphics::primitives::Rectangle::new(Default::default(), renderer.size());
    let mut buffer = vec![AaPixel::NEW; Antialias::buffer_len(320)];
    // The firmware's modes (`cargo xtask qemu --antialias`).
    for (mode, aa) in Antialias::MEASURED {
        c.bench_function(&format!("{name}/aa/{mode}"), |b| {
            b.iter(|| {
                renderer
                    .render_antialiased(image, all, aa, &mut buffer, |_| ControlFlow::Continue(()))
                    .expect("renders")
            });
        });
    }
}

fn benches(c: &mut Criterion) {
    for path in scene_files() {
        bench_type::<f64>(c, &path);
        bench_type::<f32>(c, &path);
        bench_type::<I16F16>(c, &path);
    }
}

criterion_group! {
    name = render_benches;
    config = Criterion::default().sample_size(10).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(1));
    targets = benches
}
criterion_main!(render_benches);
