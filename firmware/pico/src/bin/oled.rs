//! microray on a Raspberry Pi Pico with a 128x64 one-bit SSD1306 OLED on I2C0 (SDA GP4, SCL
//! GP5, 400 kHz, address 0x3C): the embedded scene (the showcase by default) traced at
//! 128x96 (its 4:3), the middle 64 rows dithered onto the panel by
//! `microray::dither::Dither` (the one-bit format's best method, `bayer4`, or the one
//! `MICRORAY_OLED_DITHER` names at build time), then sent by the `ssd1306` driver's
//! buffered mode. The on-board LED is lit while rendering and sending.
#![no_std]
#![no_main]

use core::ops::ControlFlow;
use embedded_graphics::pixelcolor::{BinaryColor, Rgb888, RgbColor};
use embedded_graphics::prelude::{DrawTargetExt, Point, Size};
use embedded_graphics::primitives::Rectangle;
use embedded_hal::digital::OutputPin;
use fugit::RateExtU32;
use microray::dither::{Diffusion, Dither, Format, Kernel, Method};
use microray::render::Renderer;
use panic_halt as _;
use rp_pico::entry;
use rp_pico::hal::{self, gpio};
use ssd1306::{I2CDisplayInterface, Ssd1306, prelude::*};

#[path = "../board.rs"]
mod board;

#[path = "../embedded.rs"]
mod embedded;
use embedded::PicoScene;

/// The panel.
const WIDTH: u16 = 128;
const HEIGHT: u16 = 64;
/// The picture is traced 4:3; the panel shows its rows from here.
const TOP: i32 = 16;

#[entry]
fn main() -> ! {
    let board::Board {
        pins,
        clocks,
        mut resets,
        i2c0,
        ..
    } = board::start();
    let mut led = pins.led.into_push_pull_output();

    let sda: gpio::Pin<_, gpio::FunctionI2C, gpio::PullUp> = pins.gpio4.reconfigure();
    let scl: gpio::Pin<_, gpio::FunctionI2C, gpio::PullUp> = pins.gpio5.reconfigure();
    let i2c = hal::I2C::i2c0(i2c0, sda, scl, 400.kHz(), &mut resets, &clocks.system_clock);
    let mut display = Ssd1306::new(
        I2CDisplayInterface::new(i2c),
        DisplaySize128x64,
        DisplayRotation::Rotate0,
    )
    .into_buffered_graphics_mode();
    if display.init().is_err() {
        halt();
    }

    let Some(scene) = cortex_m::singleton!(: PicoScene = PicoScene::empty()) else {
        halt();
    };
    if !embedded::load(scene, WIDTH, HEIGHT * 3 / 2) {
        halt();
    }

    let method = option_env!("MICRORAY_OLED_DITHER")
        .and_then(Method::from_name)
        .unwrap_or(Format::Binary.best_method());
    // Row memory for the hungriest method, Atkinson's three rows: 768 bytes.
    let mut rows = [0i16; Diffusion::<BinaryColor>::cells(Kernel::Atkinson, WIDTH as usize)];
    let mut row = [Rgb888::BLACK; WIDTH as usize];
    let renderer = Renderer::new(&*scene);
    led.set_high().unwrap();
    {
        // The dither sees the panel's coordinates: the picture's rows TOP.. move up to 0..
        let dither = match method {
            Method::Ordered(matrix) => Ok(Dither::ordered(&mut display, matrix)),
            Method::Diffusion { kernel, serpentine } => {
                Dither::diffusing(&mut display, kernel, serpentine, &mut rows)
            }
        };
        let Ok(mut dither) = dither else { halt() };
        let mut panel = dither.translated(Point::new(0, -TOP));
        let rows_shown = Rectangle::new(Point::new(0, TOP), Size::new(WIDTH.into(), HEIGHT.into()));
        let _ = renderer.render_area(&mut panel, rows_shown, &mut row, |_| {
            ControlFlow::Continue(())
        });
    }
    let _ = display.flush();
    led.set_low().unwrap();
    halt()
}

fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}
