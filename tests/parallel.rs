//! Rendering with threads (`host::render_parallel`, the CLI's `--threads`): the image is the
//! one thread's, bit for bit, for every scene, number type, thread count and
//! anti-aliasing mode, and every row is reported once.

mod common;

use microray::Scalar;
use microray::host::{
    HostRenderer, HostScene, antialiased, render_parallel, render_streamed, texture_files,
};
use microray::parse::parse_scene;
use microray::render::{Antialias, Renderer, Samples};
use microray::scalar::I16F16;
use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

fn check<S: Scalar>(path: &Path) {
    let text = std::fs::read(path).unwrap();
    let parsed: Result<HostScene<'_, S>, _> =
        parse_scene(&text, texture_files(path.parent().unwrap()));
    let Ok(mut scene) = parsed else {
        return;
    };
    let scene = &mut scene;
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
        // Streamed: every row handed on once, the same pixels.
        let streamed = Mutex::new((vec![0u8; one.rgb().len()], [0u8; 60]));
        render_streamed(
            &renderer,
            threads,
            None,
            |_| {},
            |top, pixels| {
                let mut guard = streamed.lock().unwrap();
                let (image, seen) = &mut *guard;
                image[top * 64 * 3..][..pixels.len()].copy_from_slice(pixels);
                seen[top..top + pixels.len() / (64 * 3)]
                    .iter_mut()
                    .for_each(|n| *n += 1);
                Ok::<(), ()>(())
            },
        )
        .unwrap();
        let (image, seen) = streamed.into_inner().unwrap();
        assert!(
            image == one.rgb(),
            "{name}: {threads} threads streamed differ"
        );
        assert!(
            seen.iter().all(|&n| n == 1),
            "{name}: rows handed on {seen:?}"
        );
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
    let streamed = Mutex::new(vec![0u8; one.rgb().len()]);
    render_streamed(
        &renderer,
        2,
        Some(adaptive),
        |_| {},
        |top, pixels| {
            streamed.lock().unwrap()[top * 64 * 3..][..pixels.len()].copy_from_slice(pixels);
            Ok::<(), ()>(())
        },
    )
    .unwrap();
    assert!(
        alone.rgb() == streamed.into_inner().unwrap(),
        "{name}: adaptive streamed differs"
    );
}

/// A failing writer (here, of the rows after the 16th) stops the render with its error,
/// on any thread count.
#[test]
fn a_failed_write_is_the_error() {
    let text = b"camera c { pixeldim 16 40 worlddim 8 6 viewpoint 4 3 3 }";
    let mut scene = HostScene::<f64>::empty();
    microray::parse::parse_scene_into(text, microray::parse::no_textures, &mut scene).unwrap();
    let renderer = HostRenderer::new(&scene);
    for threads in [1, 2] {
        let result = render_streamed(
            &renderer,
            threads,
            None,
            |_| {},
            |top, pixels| {
                if top + pixels.len() / (16 * 3) > 16 {
                    Err(top)
                } else {
                    Ok(())
                }
            },
        );
        assert!(
            matches!(result, Err(microray::host::StreamError::Write(top)) if top < 40),
            "{threads} threads: {result:?}"
        );
    }
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
