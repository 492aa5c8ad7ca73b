//! Any bytes into the compiled-scene reader, in every number type: an error or a scene,
//! never a panic; a scene that loads renders at its size (capped) without panicking, and
//! compiles back to the same bytes. Seed it with `microray compile --size 32x24` output
//! (its scene type holds images up to 64 pixels wide).
#![no_main]

use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use libfuzzer_sys::fuzz_target;
use microray::error::TextureError;
use microray::render::Renderer;
use microray::scalar::I16F16;
use microray::{Scalar, Scene};
use std::convert::Infallible;
use std::ops::ControlFlow;

/// Every texture file is a 2x1 binary PPM.
fn texture(_: &str) -> Result<&'static [u8], TextureError> {
    Ok(b"P6 2 1 255 \x10\x20\x30\x40\x50\x60")
}

struct Sink;
impl OriginDimensions for Sink {
    fn size(&self) -> Size {
        Size::new(64, 64)
    }
}
impl DrawTarget for Sink {
    type Color = Rgb888;
    type Error = Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, _: I) -> Result<(), Infallible> {
        Ok(())
    }
}

fn check<S: Scalar>(data: &[u8]) {
    let mut scene: Box<Scene<'static, S, 16, 8, 4, 2, 64>> = Box::new(Scene::empty());
    if scene.load_compiled(data, texture).is_err() {
        return;
    }
    let mut again = Vec::new();
    scene.write_compiled(&mut |piece| again.extend_from_slice(piece));
    assert_eq!(again, data, "a loaded scene compiles back to other bytes");
    let renderer = Renderer::new(&*scene);
    let mut row = [Rgb888::BLACK; 64];
    let area = embedded_graphics::primitives::Rectangle::new(Point::zero(), Size::new(64, 4));
    let _ = renderer.render_area(&mut Sink, area, &mut row, |_| ControlFlow::Continue(()));
}

fuzz_target!(|data: &[u8]| {
    check::<f64>(data);
    check::<f32>(data);
    check::<I16F16>(data);
});
