//! Rendering with threads (`host::render_parallel`, the CLI's `--threads`): the image is the
//! one thread's, bit for bit, for every scene, number type, thread count and
//! anti-aliasing mode, and every row is reported once.

mod common;

use microray::Scalar;
use microray::host::{HostRenderer, HostScene, antialiased, render_parallel, texture_files};
use microray::parse::parse_scene;
use microray::render::{Antialias, Renderer, Samples};
use microray::scalar::I16F16;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

fn check<S: Scalar>(path: &Path) {
    let text = std::fs::read(path).unwrap();
    let Ok(mut scene) =
        parse_scene::<S, _, _, _, _, _>(&text, texture_files(path.parent().unwrap()))
    else {
        return;
    };
    let scene: &mut HostScene<'_, S> = &mut scene;
    // Small enough to run every scene in every type; tall enough for many bands.
    if scene.set_resolution(64, 60).is_err() {
        return;
    }
    let renderer: HostRenderer<'_, S> = Renderer::new(scene);
    let name = format!("{} in {}", path.display(), S::NAME);
    let one = common::image(&renderer);
    for threads in [1, 2, 3, 7] {
        let rows = AtomicUsize::new(0);
        let image = render_parallel(&renderer, threads, None, |_| {
            rows.fetch_add(1, Ordering::Relaxed);
        })
        .unwrap();
        assert!(image.rgb() == one.rgb(), "{name}: {threads} threads differ");
        assert_eq!(rows.load(Ordering::Relaxed), 60, "{name}: rows reported");
    }
    let adaptive = Antialias::Adaptive {
        samples: Samples::rotated(4).unwrap(),
        threshold: 8,
    };
    let alone = antialiased(&renderer, adaptive).unwrap();
    let together = render_parallel(&renderer, 3, Some(adaptive), |_| {}).unwrap();
    assert!(
        alone.rgb() == together.rgb(),
        "{name}: adaptive with threads differs"
    );
}

#[test]
fn threads_give_the_one_thread_image() {
    let files = common::all_scenes_with("stress");
    assert!(files.len() >= 20, "{} scenes", files.len());
    for path in &files {
        check::<f64>(path);
        check::<f32>(path);
        check::<I16F16>(path);
    }
}
