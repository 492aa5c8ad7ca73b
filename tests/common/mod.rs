//! Helpers shared by the integration tests.
#![allow(dead_code)]

use embedded_graphics::prelude::{DrawTarget, OriginDimensions, Pixel, PixelColor, Size};
use microray::Scalar;
use microray::host::{Framebuffer, HostScene};
use microray::object::Shape;
use microray::render::Renderer;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

/// The course's conformance folder from `MICRORAY_CONFORMANCE`: `None` (and a note) when the
/// variable is unset; a failure when it is set and the folder is missing.
pub fn conformance_dir() -> Option<PathBuf> {
    let Some(dir) = std::env::var_os("MICRORAY_CONFORMANCE") else {
        eprintln!("skipped: MICRORAY_CONFORMANCE is not set (CI sets it to ../shared/conformance)");
        return None;
    };
    let dir = PathBuf::from(dir);
    assert!(
        dir.is_dir(),
        "MICRORAY_CONFORMANCE={} is not a folder",
        dir.display()
    );
    Some(dir)
}

/// The course's conformance folder, for the tests that are ignored without it (see
/// `build.rs`): a failure when it is missing.
pub fn required_conformance_dir() -> PathBuf {
    conformance_dir().expect("MICRORAY_CONFORMANCE was set when the tests were built, not now")
}

/// The course's later scenes, for the tests that are ignored without the course's scenes.
pub fn required_course_extensions_dir() -> PathBuf {
    course_extensions_dir().expect(
        "no course-extensions folder next to MICRORAY_CONFORMANCE's (or MICRORAY_COURSE_EXTENSIONS)",
    )
}

/// The course's later scenes: `MICRORAY_COURSE_EXTENSIONS`, else `course-extensions` next to
/// the conformance folder, if it is there.
pub fn course_extensions_dir() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("MICRORAY_COURSE_EXTENSIONS") {
        return Some(dir.into());
    }
    let conformance = conformance_dir()?;
    let dir = conformance.parent()?.join("course-extensions");
    dir.is_dir().then_some(dir)
}

/// Every `*.txt` under `dir`, sorted.
pub fn scene_files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "txt") {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

/// The project's own scenes.
pub fn project_scenes() -> Vec<PathBuf> {
    scene_files(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes"))
}

/// The project's scenes, those in `tests/<folder>`, and the course's (conformance and
/// later scenes) where they are found.
pub fn all_scenes_with(folder: &str) -> Vec<PathBuf> {
    let mut all = project_scenes();
    all.extend(scene_files(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests")
            .join(folder),
    ));
    if let Some(dir) = conformance_dir() {
        all.extend(scene_files(&dir));
    }
    if let Some(dir) = course_extensions_dir() {
        all.extend(scene_files(&dir));
    }
    all
}

/// Pixels (top row first) whose primary ray meets a rectangle exactly on its edge, or a
/// textured rectangle exactly on an edge between two texels (in f64, within 1e-9 of the
/// size): ties in exact arithmetic, which any rounding decides.
pub fn ties(scene: &HostScene<'_, f64>) -> Vec<bool> {
    let camera = scene.camera();
    let mut ties = Vec::new();
    for row in 0..camera.height() {
        for x in 0..camera.width() {
            let Some(ray) = camera.primary_ray(x, camera.height() - 1 - row) else {
                ties.push(false);
                continue;
            };
            let on_edge = scene.objects().iter().any(|object| {
                let rect = match object.shape() {
                    Shape::FPlane(rect) => rect,
                    Shape::TexPlane(textured) => &textured.rect,
                    _ => return false,
                };
                let Some(hit) = rect.plane.intersect(&ray) else {
                    return false;
                };
                let [qx, qy] = rect.local(hit.point);
                let [w, h] = rect.dimensions;
                let tol = 1e-9 * w.max(h);
                let inside = |q: f64, size: f64| q >= -tol && q <= size + tol;
                let edge = |q: f64, size: f64| q.abs() <= tol || (q - size).abs() <= tol;
                let on_rect_edge = (edge(qx, w) && inside(qy, h)) || (edge(qy, h) && inside(qx, w));
                on_rect_edge
                    || (inside(qx, w) && inside(qy, h) && on_texel_edge(scene, object, qx, qy))
            });
            ties.push(on_edge);
        }
    }
    ties
}

/// Whether local coordinates `(qx, qy)` of a textured rectangle lie on an edge between two
/// texels (in f64, within 1e-9 of a texel).
pub fn on_texel_edge(
    scene: &HostScene<'_, f64>,
    object: &microray::Object<f64>,
    qx: f64,
    qy: f64,
) -> bool {
    let Shape::TexPlane(textured) = object.shape() else {
        return false;
    };
    let Some(texture) = scene.textures().get(usize::from(textured.texture)) else {
        return false;
    };
    let camera = scene.camera();
    let [w, h] = textured.rect.dimensions;
    let (across, up) = match textured.mode {
        microray::object::TextureMode::Fit => (
            qx / w * f64::from(texture.width()),
            qy / h * f64::from(texture.height()),
        ),
        microray::object::TextureMode::Tile => (
            qx / camera.world()[0] * f64::from(camera.width()),
            qy / camera.world()[1] * f64::from(camera.height()),
        ),
    };
    let near_whole = |v: f64| (v - v.round()).abs() <= 1e-9 * v.abs().max(1.0);
    near_whole(across) || near_whole(up)
}

/// The render through rows (`render_area`, where rows are shaded together).
pub fn image<S: Scalar, const OBJECTS: usize>(renderer: &Renderer<'_, S, OBJECTS>) -> Framebuffer {
    let size = renderer.size();
    let mut image = Framebuffer::new(size);
    let mut row = vec![Default::default(); size.width as usize];
    let all = embedded_graphics::primitives::Rectangle::new(Default::default(), size);
    renderer
        .render_area(&mut image, all, &mut row, |_| ControlFlow::Continue(()))
        .unwrap();
    image
}

/// A panel that keeps what it is sent, in its own colour type.
pub struct Panel<C> {
    pub size: Size,
    pub pixels: Vec<C>,
}

impl<C: PixelColor + Default> Panel<C> {
    pub fn new(width: u32, height: u32) -> Self {
        Self::filled(Size::new(width, height), C::default())
    }

    /// A panel whose every pixel starts as `color` (to see which pixels were drawn).
    pub fn filled(size: Size, color: C) -> Self {
        Self {
            size,
            pixels: vec![color; (size.width * size.height) as usize],
        }
    }
}

impl<C: PixelColor> OriginDimensions for Panel<C> {
    fn size(&self) -> Size {
        self.size
    }
}

impl<C: PixelColor> DrawTarget for Panel<C> {
    type Color = C;
    type Error = std::convert::Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<C>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), std::convert::Infallible> {
        for Pixel(p, c) in pixels {
            let i = p.y as usize * self.size.width as usize + p.x as usize;
            self.pixels[i] = c;
        }
        Ok(())
    }
}

/// Rows of `width` pixels diffused by hand, with the library's `Diffusion` alone: what the
/// `Dither` target and the command line must give.
pub fn diffused_by_hand<C: microray::dither::PanelColor>(
    pixels: &[embedded_graphics::pixelcolor::Rgb888],
    width: usize,
    kernel: microray::dither::Kernel,
    serpentine: bool,
) -> Vec<C> {
    let mut memory = vec![0i16; microray::dither::Diffusion::<C>::cells(kernel, width)];
    let mut d =
        microray::dither::Diffusion::<C, _>::new(kernel, serpentine, width, &mut memory).unwrap();
    let mut out = Vec::new();
    for row in pixels.chunks(width) {
        for (x, &c) in row.iter().enumerate() {
            d.set(x, c);
        }
        d.finish_row();
        out.extend(d.levels());
        d.next_row();
    }
    out
}
