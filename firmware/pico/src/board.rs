//! The Pico's start-up, shared by the examples: the clocks at 125 MHz from the crystal, and
//! the pins; the peripherals the examples use next are handed back.

use rp_pico::hal::{self, pac};

/// What the start-up leaves for an example (each takes what it uses).
#[allow(dead_code)]
pub struct Board {
    pub pins: rp_pico::Pins,
    pub clocks: hal::clocks::ClocksManager,
    pub resets: pac::RESETS,
    pub timer: pac::TIMER,
    pub dma: pac::DMA,
    pub spi0: pac::SPI0,
    pub i2c0: pac::I2C0,
    pub psm: pac::PSM,
    pub ppb: pac::PPB,
    pub fifo: hal::sio::SioFifo,
}

/// Takes the peripherals and starts the clocks (a board without its crystal stops here).
pub fn start() -> Board {
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
    Board {
        pins,
        clocks,
        resets: pac.RESETS,
        timer: pac.TIMER,
        dma: pac.DMA,
        spi0: pac.SPI0,
        i2c0: pac.I2C0,
        psm: pac.PSM,
        ppb: pac.PPB,
        fifo: sio.fifo,
    }
}
