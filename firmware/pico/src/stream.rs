//! The image's rows streamed to the ST7789 by DMA: one window and one RAMWR for the whole
//! image, each row converted to the panel's big-endian Rgb565 in one of two buffers and sent
//! by a DMA channel while the next row is traced into the other. The CPU's share of the
//! output is the conversion and starting each transfer: no per-pixel driver calls.
//!
//! `Renderer::render_area` hands the image over as one `fill_contiguous` call per row, top
//! to bottom; anything else (another area, a row out of order) is written without DMA, after
//! the stream so far, through the same window commands.

use core::convert::Infallible;
use embedded_graphics::Pixel;
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::{DrawTarget, IntoStorage, OriginDimensions, Size};
use embedded_graphics::primitives::Rectangle;
use embedded_hal::digital::OutputPin;
use embedded_hal::spi::SpiBus;
use rp_pico::hal::dma::{SingleChannel, WriteTarget, single_buffer};

/// ST7789 commands: column and row address set, memory write.
const CASET: u8 = 0x2a;
const RASET: u8 = 0x2b;
const RAMWR: u8 = 0x2c;

/// A row on its way out: the transfer, or the channel and the bus when none is.
enum Link<CH: SingleChannel, SPI: WriteTarget<TransmittedWord = u8>, const B: usize> {
    Busy(single_buffer::Transfer<CH, &'static mut [u8; B], SPI>),
    Idle(CH, SPI, &'static mut [u8; B]),
    /// Only while one becomes the other.
    Moving,
}

/// The panel as a draw target for an image `B / 2` pixels wide at rows `top..` of the
/// panel: rows streamed by DMA (see the module's documentation).
pub struct Stream<CH, SPI, DC, CS, const B: usize>
where
    CH: SingleChannel,
    SPI: WriteTarget<TransmittedWord = u8> + SpiBus<u8>,
{
    link: Link<CH, SPI, B>,
    /// The buffer the next row is converted into.
    spare: Option<&'static mut [u8; B]>,
    dc: DC,
    cs: CS,
    /// The panel's row of the image's row 0, and the image's height.
    top: u16,
    height: u16,
    /// The image's row the stream expects next; `None` before the first and after a break.
    next: Option<u16>,
}

impl<CH, SPI, DC, CS, const B: usize> Stream<CH, SPI, DC, CS, B>
where
    CH: SingleChannel,
    SPI: WriteTarget<TransmittedWord = u8> + SpiBus<u8>,
    DC: OutputPin,
    CS: OutputPin,
{
    /// A stream over `spi` (the panel initialised, CS and DC as the driver left them),
    /// sending rows with DMA channel `channel` from the two buffers.
    pub fn new(
        channel: CH,
        spi: SPI,
        buffers: [&'static mut [u8; B]; 2],
        dc: DC,
        cs: CS,
        top: u16,
        height: u16,
    ) -> Self {
        let [first, second] = buffers;
        Self {
            link: Link::Idle(channel, spi, first),
            spare: Some(second),
            dc,
            cs,
            top,
            height,
            next: None,
        }
    }

    /// Waits for the row on its way out; the channel, the bus and that row's buffer.
    fn idle(&mut self) -> (CH, SPI, &'static mut [u8; B]) {
        match core::mem::replace(&mut self.link, Link::Moving) {
            Link::Busy(transfer) => {
                let (channel, buffer, spi) = transfer.wait();
                (channel, spi, buffer)
            }
            Link::Idle(channel, spi, buffer) => (channel, spi, buffer),
            // Never left so: every path puts one back.
            Link::Moving => loop {
                cortex_m::asm::wfi();
            },
        }
    }

    /// Sends `command` and its `data` with the bus idle, DC low for the command.
    fn command(&mut self, spi: &mut SPI, command: u8, data: &[u8]) {
        let _ = self.dc.set_low();
        let _ = spi.write(&[command]);
        let _ = spi.flush();
        let _ = self.dc.set_high();
        let _ = spi.write(data);
        let _ = spi.flush();
    }

    /// Opens a window of the panel's `x0..=x1`, `y0..=y1` for pixels.
    fn window(&mut self, spi: &mut SPI, [x0, y0, x1, y1]: [u16; 4]) {
        let _ = self.cs.set_low();
        let [a, b] = x0.to_be_bytes();
        let [c, d] = x1.to_be_bytes();
        self.command(spi, CASET, &[a, b, c, d]);
        let [a, b] = y0.to_be_bytes();
        let [c, d] = y1.to_be_bytes();
        self.command(spi, RASET, &[a, b, c, d]);
        self.command(spi, RAMWR, &[]);
    }

    /// Waits until the last row has left and the bus is idle, and deselects the panel.
    pub fn finish(&mut self) {
        let (channel, mut spi, buffer) = self.idle();
        let _ = spi.flush();
        let _ = self.cs.set_high();
        self.link = Link::Idle(channel, spi, buffer);
        self.next = None;
    }

    /// Row `y` of the image, as `pixels`: into the spare buffer, then out by DMA once the
    /// row before it has left.
    fn stream_row(&mut self, y: u16, pixels: impl Iterator<Item = Rgb565>) {
        let Some(row) = self.spare.take() else {
            return;
        };
        for (pair, pixel) in row.chunks_exact_mut(2).zip(pixels) {
            pair.copy_from_slice(&pixel.into_storage().to_be_bytes());
        }
        let (channel, mut spi, sent) = self.idle();
        self.spare = Some(sent);
        if self.next != Some(y) {
            // The first row, or the stream broken: a window for the rest of the image.
            let _ = spi.flush();
            let width = (B / 2) as u16;
            let bottom = self.top + self.height - 1;
            self.window(&mut spi, [0, self.top + y, width - 1, bottom]);
        }
        self.next = Some(y + 1);
        self.link = Link::Busy(single_buffer::Config::new(channel, row, spi).start());
    }

    /// `area` (image coordinates) filled with `colors` without DMA, the stream ended first.
    fn write_area(&mut self, area: &Rectangle, colors: impl Iterator<Item = Rgb565>) {
        let Some(bottom_right) = area.bottom_right() else {
            return;
        };
        self.finish();
        let (channel, mut spi, buffer) = self.idle();
        let corner = |x: i32, y: i32| {
            let x = u16::try_from(x).unwrap_or(0);
            let y = u16::try_from(y).unwrap_or(0) + self.top;
            (x, y)
        };
        let (x0, y0) = corner(area.top_left.x, area.top_left.y);
        let (x1, y1) = corner(bottom_right.x, bottom_right.y);
        self.window(&mut spi, [x0, y0, x1, y1]);
        for pixel in colors {
            let _ = spi.write(&pixel.into_storage().to_be_bytes());
        }
        let _ = spi.flush();
        let _ = self.cs.set_high();
        self.link = Link::Idle(channel, spi, buffer);
    }
}

impl<CH, SPI, DC, CS, const B: usize> OriginDimensions for Stream<CH, SPI, DC, CS, B>
where
    CH: SingleChannel,
    SPI: WriteTarget<TransmittedWord = u8> + SpiBus<u8>,
{
    fn size(&self) -> Size {
        Size::new((B / 2) as u32, u32::from(self.height))
    }
}

impl<CH, SPI, DC, CS, const B: usize> DrawTarget for Stream<CH, SPI, DC, CS, B>
where
    CH: SingleChannel,
    SPI: WriteTarget<TransmittedWord = u8> + SpiBus<u8>,
    DC: OutputPin,
    CS: OutputPin,
{
    type Color = Rgb565;
    type Error = Infallible;

    fn fill_contiguous<I>(&mut self, area: &Rectangle, colors: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Rgb565>,
    {
        let whole_row = area.top_left.x == 0
            && area.size == Size::new((B / 2) as u32, 1)
            && (0..i32::from(self.height)).contains(&area.top_left.y);
        match u16::try_from(area.top_left.y) {
            Ok(y) if whole_row => self.stream_row(y, colors.into_iter()),
            _ => self.write_area(area, colors.into_iter()),
        }
        Ok(())
    }

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Pixel<Rgb565>>,
    {
        for Pixel(point, color) in pixels {
            let area = Rectangle::new(point, Size::new(1, 1));
            self.write_area(&area, core::iter::once(color));
        }
        Ok(())
    }
}
