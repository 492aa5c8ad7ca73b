//! The showcase on a 128x64 one-bit panel (an SSD1306 OLED's size), truncated and by each
//! dither method, side by side: the picture in the README (docs/one-bit.png).
//!
//! The scene is traced at 128x96 (its own 4:3) and the panel shows the middle 64 rows:
//! `render_area` traces only those, into the panel moved up 16 rows.
//!
//! ```sh
//! cargo run --release --example one_bit_panel -- docs/one-bit.png
//! ```

use embedded_graphics::mono_font::{MonoTextStyle, ascii::FONT_6X10};
use embedded_graphics::pixelcolor::{BinaryColor, Rgb888};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{PrimitiveStyle, Rectangle};
use embedded_graphics::text::{Baseline, Text};
use microray::dither::{Diffusion, Dither, Kernel, Method};
use microray::host::{Framebuffer, HostScene, texture_files};
use microray::parse::parse_scene;
use microray::render::Renderer;
use std::ops::ControlFlow;
use std::path::Path;

const WIDTH: u32 = 128;
const HEIGHT: u32 = 64;
/// Rows of the 4:3 picture above the panel's.
const TOP: i32 = 16;
/// Each panel pixel shown as a square of this side.
const ZOOM: u32 = 2;
/// Room for a label under each panel.
const LABEL: u32 = 14;

/// A one-bit panel in memory.
struct Oled {
    on: Vec<bool>,
}

impl Dimensions for Oled {
    fn bounding_box(&self) -> Rectangle {
        Rectangle::new(Point::zero(), Size::new(WIDTH, HEIGHT))
    }
}

impl DrawTarget for Oled {
    type Color = BinaryColor;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<BinaryColor>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Self::Error> {
        for Pixel(p, c) in pixels {
            if self.bounding_box().contains(p) {
                self.on[(p.y as u32 * WIDTH + p.x as u32) as usize] = c.is_on();
            }
        }
        Ok(())
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "one-bit.png".into());
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/showcase.txt");
    let text = std::fs::read(&path)?;
    let mut scene: HostScene<'_, f32> = parse_scene(&text, texture_files(path.parent().unwrap()))?;
    scene
        .set_resolution(WIDTH as u16, (HEIGHT * 3 / 2) as u16)
        .map_err(|e| e.to_string())?;
    let renderer = Renderer::new(&scene);
    // The panel's rows of the picture, in the picture's coordinates.
    let area = Rectangle::new(Point::new(0, TOP), Size::new(WIDTH, HEIGHT));
    let mut row = vec![Rgb888::BLACK; WIDTH as usize];

    let mut ways: Vec<(&str, Option<Method>)> = vec![("truncated", None)];
    ways.extend(Method::ALL.iter().map(|&(name, m)| (name, Some(m))));
    let columns = 4;
    let rows = ways.len().div_ceil(columns) as u32;
    let cell = Size::new(WIDTH * ZOOM + 8, HEIGHT * ZOOM + LABEL + 8);
    let mut sheet = Framebuffer::new(Size::new(cell.width * columns as u32, cell.height * rows));
    sheet.clear(Rgb888::new(40, 40, 48))?;
    let label = MonoTextStyle::new(&FONT_6X10, Rgb888::WHITE);

    for (i, (name, method)) in ways.into_iter().enumerate() {
        let mut oled = Oled {
            on: vec![false; (WIDTH * HEIGHT) as usize],
        };
        let mut memory =
            vec![0i16; Diffusion::<BinaryColor>::cells(Kernel::Atkinson, WIDTH as usize)];
        {
            // The panel seen from the picture: its row 0 is the picture's row TOP.
            let mut moved = oled.translated(Point::new(0, -TOP));
            let mut dither = match method {
                None => Dither::truncating(&mut moved),
                Some(Method::Ordered(m)) => Dither::ordered(&mut moved, m),
                Some(Method::Diffusion { kernel, serpentine }) => {
                    Dither::diffusing_area(&mut moved, area, kernel, serpentine, &mut memory)?
                }
            };
            renderer.render_area(&mut dither, area, &mut row, |_| ControlFlow::Continue(()))?;
        }
        let origin = Point::new(
            (i % columns) as i32 * cell.width as i32 + 4,
            (i / columns) as i32 * cell.height as i32 + 4,
        );
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                let lit = oled.on[(y * WIDTH + x) as usize];
                // An OLED's blue-white on black.
                let color = if lit {
                    Rgb888::new(200, 230, 255)
                } else {
                    Rgb888::BLACK
                };
                let square = Rectangle::new(
                    origin + Point::new((x * ZOOM) as i32, (y * ZOOM) as i32),
                    Size::new(ZOOM, ZOOM),
                );
                square
                    .into_styled(PrimitiveStyle::with_fill(color))
                    .draw(&mut sheet)?;
            }
        }
        let under = origin + Point::new(0, (HEIGHT * ZOOM) as i32 + 2);
        Text::with_baseline(name, under, label, Baseline::Top).draw(&mut sheet)?;
    }
    std::fs::write(&out, sheet.to_png()?)?;
    println!("{out}: {}x{}", sheet.size().width, sheet.size().height);
    Ok(())
}
