//! Frames through `microray::dither::Dither` into a one-bit and an Rgb565 panel, truncated
//! and by every method, `<scene>+panel-<format>-<method>.rgb` each (`cargo xtask qemu
//! --dither` prices each over truncation and checks it against the host's conversion).

use crate::{
    FirmwareScene, HEIGHT, PanelFile, RowFile, WIDTH, microray_count_frame, microray_count_start,
    microray_count_stop, report_frame, stack,
};
use core::ops::ControlFlow;
use embedded_graphics::pixelcolor::{BinaryColor, Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::{Point, Size};
use embedded_graphics::primitives::Rectangle;
use microray::dither::{Dither, Kernel, Matrix, PanelColor, shown};
use microray::render::Renderer;

/// How a frame reaches the panel.
#[derive(Clone, Copy)]
enum Way {
    Truncate,
    Ordered(Matrix),
    Diffuse(Kernel),
}

/// Each way, by the name the host reads back (`microray::dither::Method::from_name`).
const WAYS: [(&str, Way); 7] = [
    ("truncated", Way::Truncate),
    ("bayer2", Way::Ordered(Matrix::Bayer2)),
    ("bayer4", Way::Ordered(Matrix::Bayer4)),
    ("bayer8", Way::Ordered(Matrix::Bayer8)),
    ("blue-noise", Way::Ordered(Matrix::BlueNoise)),
    ("floyd-steinberg", Way::Diffuse(Kernel::FloydSteinberg)),
    ("atkinson", Way::Diffuse(Kernel::Atkinson)),
];

/// Row memory for the largest need: Atkinson's three rows of three channels.
const CELLS: usize = 3 * 3 * WIDTH as usize;

/// Every way into both formats, each frame reported as it ends.
pub(crate) fn render_all(name: &str, scene: &FirmwareScene) -> Result<(), &'static str> {
    for (way_name, way) in WAYS {
        render::<BinaryColor>(name, "binary", way_name, way, scene)?;
        render::<Rgb565>(name, "rgb565", way_name, way, scene)?;
    }
    Ok(())
}

/// `+panel-<format>-<way>`, in a buffer.
fn suffix<'b>(buffer: &'b mut [u8; 48], format: &str, way: &str) -> &'b str {
    let mut n = 0;
    for part in ["+panel-", format, "-", way] {
        for &b in part.as_bytes() {
            if let Some(slot) = buffer.get_mut(n) {
                *slot = b;
                n += 1;
            }
        }
    }
    core::str::from_utf8(&buffer[..n]).unwrap_or("+panel")
}

#[inline(never)]
fn render<C: PanelColor>(
    name: &str,
    format: &str,
    way_name: &str,
    way: Way,
    scene: &FirmwareScene,
) -> Result<(), &'static str> {
    let mut buffer = [0u8; 48];
    let suffix = suffix(&mut buffer, format, way_name);
    let mut panel = PanelFile::<C> {
        out: RowFile::create(name, suffix)?,
        expand: shown::<C>,
    };
    let all = Rectangle::new(
        Point::zero(),
        Size::new(u32::from(WIDTH), u32::from(HEIGHT)),
    );
    let mut memory = [0i16; CELLS];
    let renderer = Renderer::new(scene);
    let mut row = [Rgb888::BLACK; WIDTH as usize];
    microray_count_start();
    let result = {
        let dither = match way {
            Way::Truncate => Ok(Dither::truncating(&mut panel)),
            Way::Ordered(m) => Ok(Dither::ordered(&mut panel, m)),
            Way::Diffuse(k) => Dither::diffusing(&mut panel, k, false, &mut memory),
        };
        match dither {
            Ok(mut dither) => renderer
                .render_area(&mut dither, all, &mut row, |_| ControlFlow::Continue(()))
                .map(|_| ())
                .map_err(|_| "render failed"),
            Err(_) => Err("row memory"),
        }
    };
    microray_count_stop();
    microray_count_frame();
    report_frame(name, suffix, result);
    stack::paint();
    result
}
