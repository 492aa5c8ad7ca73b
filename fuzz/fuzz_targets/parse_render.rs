//! Any bytes parsed and, when they make a scene, rendered at 8x6 in every number type:
//! never a panic (overflow checks are on in fuzz builds), whatever the geometry.
#![no_main]

use core::convert::Infallible;
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use libfuzzer_sys::fuzz_target;
use microray::error::TextureError;
use microray::parse::parse_scene;
use microray::render::render;
use microray::scalar::I16F16;
use microray::{Scalar, Scene};

fn texture(_: &str) -> Result<&'static [u8], TextureError> {
    Ok(b"P6 2 1 255 \x10\x20\x30\x40\x50\x60")
}

/// A display that only counts what it is sent.
struct Sink(usize);

impl OriginDimensions for Sink {
    fn size(&self) -> Size {
        Size::new(8, 6)
    }
}

impl DrawTarget for Sink {
    type Color = Rgb888;
    type Error = Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, pixels: I) -> Result<(), Infallible> {
        self.0 += pixels.into_iter().count();
        Ok(())
    }
}

fn check<S: Scalar>(data: &[u8]) {
    let Ok(mut scene) = parse_scene::<S, 16, 8, 4, 2, 256>(data, texture) else {
        return;
    };
    if scene.set_resolution(8, 6).is_err() {
        return;
    }
    let scene: &Scene<'_, S, 16, 8, 4, 2, 256> = &scene;
    let mut sink = Sink(0);
    let _ = render(scene, &mut sink);
    assert_eq!(sink.0, 48);
}

fuzz_target!(|data: &[u8]| {
    check::<f64>(data);
    check::<f32>(data);
    check::<I16F16>(data);
});
