//! Any bytes into the parser, in every number type: an error or a scene, never a panic; a
//! scene prints to text that reads back.
#![no_main]

use libfuzzer_sys::fuzz_target;
use microray::error::TextureError;
use microray::parse::parse_scene;
use microray::print::print_scene;
use microray::scalar::I16F16;
use microray::{Scalar, Scene};

/// Every texture file is a 2x1 binary PPM.
fn texture(_: &str) -> Result<&'static [u8], TextureError> {
    Ok(b"P6 2 1 255 \x10\x20\x30\x40\x50\x60")
}

fn check<S: Scalar>(data: &[u8]) {
    let Ok(scene) = parse_scene::<S, 16, 8, 4, 2, 256>(data, texture) else {
        return;
    };
    let mut text = heapless::String::<16384>::new();
    if print_scene(&scene, &mut text).is_ok() {
        let again: Result<Scene<'_, S, 16, 8, 4, 2, 256>, _> = parse_scene(text.as_bytes(), texture);
        assert!(again.is_ok(), "printed scene does not read back:\n{text}");
    }
}

fuzz_target!(|data: &[u8]| {
    check::<f64>(data);
    check::<f32>(data);
    check::<I16F16>(data);
});
