//! microray on a Raspberry Pi Pico (RP2040, Cortex-M0+, no FPU) with a 240x240 ST7789 SPI
//! display: the project's showcase scene (or the one `MICRORAY_PICO_SCENE` names), embedded
//! at build time, rendered in Q16.16 fixed point straight to the panel, one row at a time:
//! one window for the image, each row sent by DMA while the next is traced (`stream.rs`; no
//! framebuffer). With the `progressive` feature, the whole picture first in 8x8 blocks, then
//! finer. The on-board LED lights while rendering. See README.md for wiring.
//!
//! With the `two-cores` feature both cores render: core 1 the odd rows, handed over in a
//! small queue, core 0 the even rows and every SPI write (the split `host::render_parallel`
//! makes on a PC, with the library's `render_area` on one-row areas).
#![no_std]
#![no_main]

#[cfg(not(feature = "two-cores"))]
use core::ops::ControlFlow;
#[cfg(not(feature = "two-cores"))]
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use embedded_graphics::prelude::DrawTarget;
#[cfg(not(feature = "two-cores"))]
use embedded_graphics::prelude::{Point, Size};
#[cfg(not(feature = "two-cores"))]
use embedded_graphics::primitives::Rectangle;
use embedded_hal::digital::OutputPin;
use embedded_hal_bus::spi::ExclusiveDevice;
use fugit::RateExtU32;
#[cfg(not(feature = "two-cores"))]
use microray::render::Renderer;
use mipidsi::Builder;
use mipidsi::interface::SpiInterface;
use mipidsi::models::ST7789;
use mipidsi::options::ColorInversion;
use panic_halt as _;
use rp_pico::entry;
use rp_pico::hal::dma::DMAExt;
#[cfg(feature = "two-cores")]
use rp_pico::hal::multicore::Multicore;
use rp_pico::hal::{self, clocks::Clock, gpio, spi};

mod board;
#[cfg(feature = "two-cores")]
mod split;
mod stream;
#[cfg(feature = "two-cores")]
mod two_cores;

use stream::Stream;

mod embedded;
use embedded::PicoScene;

/// The panel's size; the 4:3 scene is drawn 240 x 180 in its middle.
const PANEL: u16 = 240;
const HEIGHT: u16 = 180;
/// One row of the panel in its big-endian Rgb565.
const ROW_BYTES: usize = 2 * PANEL as usize;

#[entry]
fn main() -> ! {
    // Core 1's peripherals (`psm`, `ppb`, `fifo`) serve the two-core build only.
    #[cfg_attr(not(feature = "two-cores"), allow(unused_variables))]
    let board::Board {
        pins,
        clocks,
        mut resets,
        timer,
        dma,
        spi0,
        psm,
        ppb,
        fifo,
        ..
    } = board::start();
    let mut timer = hal::Timer::new(timer, &mut resets, &clocks);

    // SPI0 at 62.5 MHz: SCK GP18, MOSI GP19; CS GP17, DC GP16, RST GP20, backlight GP21.
    let sck: gpio::Pin<_, gpio::FunctionSpi, gpio::PullNone> = pins.gpio18.reconfigure();
    let mosi: gpio::Pin<_, gpio::FunctionSpi, gpio::PullNone> = pins.gpio19.reconfigure();
    let spi = spi::Spi::<_, _, _, 8>::new(spi0, (mosi, sck)).init(
        &mut resets,
        clocks.peripheral_clock.freq(),
        62_500_000u32.Hz(),
        embedded_hal::spi::MODE_3,
    );
    let mut cs = pins.gpio17.into_push_pull_output();
    let mut dc = pins.gpio16.into_push_pull_output();
    let reset = pins.gpio20.into_push_pull_output();
    let mut backlight = pins.gpio21.into_push_pull_output();
    let mut led = pins.led.into_push_pull_output();

    // The panel's set-up and clearing by the driver, over the bus and pins lent to it; the
    // image then goes out through `stream` (rows by DMA), which takes them back.
    let mut spi = spi;
    {
        let device = ExclusiveDevice::new_no_delay(&mut spi, &mut cs).unwrap();
        let mut buffer = [0u8; 512];
        let interface = SpiInterface::new(device, &mut dc, &mut buffer);
        let mut display = Builder::new(ST7789, interface)
            .display_size(PANEL, PANEL)
            .invert_colors(ColorInversion::Inverted)
            .reset_pin(reset)
            .init(&mut timer)
            .unwrap();
        display.clear(Rgb565::BLACK).unwrap();
    }
    backlight.set_high().unwrap();

    // The scene, built in place (in a static: with two cores, core 1 reads it too); a scene
    // that does not load shows a red panel.
    let (Some(scene), Some(first), Some(second)) = (
        cortex_m::singleton!(: PicoScene = PicoScene::empty()),
        cortex_m::singleton!(: [u8; ROW_BYTES] = [0; ROW_BYTES]),
        cortex_m::singleton!(: [u8; ROW_BYTES] = [0; ROW_BYTES]),
    ) else {
        loop {
            cortex_m::asm::wfi();
        }
    };
    let dma = dma.split(&mut resets);
    let top = (PANEL - HEIGHT) / 2;
    let mut panel = Stream::new(dma.ch0, spi, [first, second], dc, cs, top, HEIGHT);
    if !embedded::load(scene, PANEL, HEIGHT) {
        let _ = panel.clear(Rgb565::RED);
        panel.finish();
        loop {
            cortex_m::asm::wfi();
        }
    }

    led.set_high().unwrap();
    let scene: &'static PicoScene = scene;
    #[cfg(feature = "two-cores")]
    {
        let (mut psm, mut ppb, mut fifo) = (psm, ppb, fifo);
        let mut multicore = Multicore::new(&mut psm, &mut ppb, &mut fifo);
        two_cores::render(&mut multicore, scene, &mut panel);
    }
    #[cfg(not(feature = "two-cores"))]
    {
        let mut row = [Rgb565::from(Rgb888::BLACK); PANEL as usize];
        let renderer = Renderer::new(scene);
        if cfg!(feature = "progressive") {
            // The whole picture in 8x8 blocks after 1/64 of the work, then 4x4, 2x2 and
            // every pixel, each traced once; the panel ends with the image below. (A caller
            // that wants to do something between passes calls `render_pass` for passes 0
            // to 3 instead.)
            let _ =
                renderer.render_progressive(&mut panel, &mut row, |_| ControlFlow::Continue(()));
        } else {
            // Row by row, each row out by DMA while the next is traced.
            let image = Rectangle::new(Point::zero(), Size::new(PANEL.into(), HEIGHT.into()));
            let _ =
                renderer.render_area(&mut panel, image, &mut row, |_| ControlFlow::Continue(()));
        }
    }
    panel.finish();
    led.set_low().unwrap();

    loop {
        cortex_m::asm::wfi();
    }
}
