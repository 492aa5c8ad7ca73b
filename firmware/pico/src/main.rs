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
use microray::error::TextureError;
use microray::parse::parse_scene_into;
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
use rp_pico::hal::{self, clocks::Clock, gpio, pac, spi};

#[cfg(feature = "two-cores")]
mod split;
mod stream;
#[cfg(feature = "two-cores")]
mod two_cores;

use stream::Stream;

/// The scene, its textures and its `Scene` type (`PicoScene`), from the file build.rs
/// embeds: the project's showcase, or the one `MICRORAY_PICO_SCENE` names.
mod scene {
    include!(concat!(env!("OUT_DIR"), "/scene.rs"));
}
use scene::PicoScene;

/// The panel's size; the 4:3 scene is drawn 240 x 180 in its middle.
const PANEL: u16 = 240;
const HEIGHT: u16 = 180;
/// One row of the panel in its big-endian Rgb565.
const ROW_BYTES: usize = 2 * PANEL as usize;

#[entry]
fn main() -> ! {
    let mut pac = pac::Peripherals::take().unwrap();
    let mut watchdog = hal::Watchdog::new(pac.WATCHDOG);
    let clocks = hal::clocks::init_clocks_and_plls(
        rp_pico::XOSC_CRYSTAL_FREQ,
        pac.XOSC,
        pac.CLOCKS,
        pac.PLL_SYS,
        pac.PLL_USB,
        &mut pac.RESETS,
        &mut watchdog,
    )
    .ok()
    .unwrap();
    let sio = hal::Sio::new(pac.SIO);
    let pins = rp_pico::Pins::new(
        pac.IO_BANK0,
        pac.PADS_BANK0,
        sio.gpio_bank0,
        &mut pac.RESETS,
    );
    let mut timer = hal::Timer::new(pac.TIMER, &mut pac.RESETS, &clocks);

    // SPI0 at 62.5 MHz: SCK GP18, MOSI GP19; CS GP17, DC GP16, RST GP20, backlight GP21.
    let sck: gpio::Pin<_, gpio::FunctionSpi, gpio::PullNone> = pins.gpio18.reconfigure();
    let mosi: gpio::Pin<_, gpio::FunctionSpi, gpio::PullNone> = pins.gpio19.reconfigure();
    let spi = spi::Spi::<_, _, _, 8>::new(pac.SPI0, (mosi, sck)).init(
        &mut pac.RESETS,
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
    let dma = pac.DMA.split(&mut pac.RESETS);
    let top = (PANEL - HEIGHT) / 2;
    let mut panel = Stream::new(dma.ch0, spi, [first, second], dc, cs, top, HEIGHT);
    let textures = |name: &str| {
        scene::TEXTURES
            .iter()
            .find(|(written, _)| *written == name)
            .map(|(_, bytes)| *bytes)
            .ok_or(TextureError::NotFound)
    };
    if parse_scene_into(scene::TEXT.as_bytes(), textures, scene).is_err()
        || scene.set_resolution(PANEL, HEIGHT).is_err()
    {
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
        let mut fifo = sio.fifo;
        let mut multicore = Multicore::new(&mut pac.PSM, &mut pac.PPB, &mut fifo);
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
