//! The two cores' split of the rows (feature `two-cores`), apart from the cores themselves so
//! that the host's tests can run it with a thread as core 1 (tests/pico_two_cores.rs): core
//! 1 renders the odd rows into [`READY`], core 0 the even rows and every write to the panel,
//! sending core 1's rows as they come. Each row is the one `Renderer::render_area` draws on
//! a one-row area, so the panel ends with the one-core image.

use core::cell::RefCell;
use core::convert::Infallible;
use core::ops::ControlFlow;
use critical_section::Mutex;
use embedded_graphics::Pixel;
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use embedded_graphics::prelude::{DrawTarget, OriginDimensions, Point, Size};
use embedded_graphics::primitives::Rectangle;
use heapless::Deque;
use microray::Scalar;
use microray::render::Renderer;

use crate::{HEIGHT, PANEL};

const WIDTH: usize = PANEL as usize;

/// A row of the image and its pixels.
pub type Row = (u16, [Rgb565; WIDTH]);

/// Rows core 1 has rendered and core 0 has not sent yet. The critical section is
/// rp2040-hal's on the Pico (interrupts off and a hardware spinlock, so it holds across both
/// cores), the standard library's mutex on the host.
pub static READY: Mutex<RefCell<Deque<Row, 4>>> = Mutex::new(RefCell::new(Deque::new()));

/// Core 0: the rows `0, step, 2 step, ...` into `panel`, and core 1's rows as they come;
/// returns when all `HEIGHT` rows are on the panel (with `step` 2, core 1 renders the odd
/// ones; with 1, core 0 renders them all).
pub fn even_rows<S: Scalar, D, const OBJECTS: usize>(
    renderer: &Renderer<'_, S, OBJECTS>,
    panel: &mut D,
    step: usize,
) where
    D: DrawTarget<Color = Rgb565>,
{
    let mut row = [Rgb565::BLACK; WIDTH];
    let mut sent = 0;
    for y in (0..HEIGHT).step_by(step) {
        let _ = renderer.render_area(panel, one_row(y), &mut row, |_| ControlFlow::Continue(()));
        sent += send_ready(panel);
    }
    if step == 2 {
        while sent < HEIGHT / 2 {
            sent += send_ready(panel);
        }
    }
}

/// Core 1: the odd rows, each into the queue (waiting while it is full).
pub fn odd_rows<S: Scalar, const OBJECTS: usize>(renderer: &Renderer<'_, S, OBJECTS>) {
    let mut target = RowTarget {
        y: 0,
        pixels: [Rgb565::BLACK; WIDTH],
    };
    let mut row = [Rgb565::BLACK; WIDTH];
    for y in (1..HEIGHT).step_by(2) {
        target.y = y;
        let _ = renderer.render_area(&mut target, one_row(y), &mut row, |_| {
            ControlFlow::Continue(())
        });
        let mut waiting = Some((y, target.pixels));
        while let Some(ready) = waiting.take() {
            critical_section::with(|cs| {
                waiting = READY.borrow_ref_mut(cs).push_back(ready).err();
            });
        }
    }
}

/// Sends the rows core 1 has queued to the panel; how many.
fn send_ready<D: DrawTarget<Color = Rgb565>>(panel: &mut D) -> u16 {
    let mut sent = 0;
    while let Some((y, pixels)) = critical_section::with(|cs| READY.borrow_ref_mut(cs).pop_front())
    {
        let _ = panel.fill_contiguous(&one_row(y), pixels);
        sent += 1;
    }
    sent
}

/// Row `y` of the image.
fn one_row(y: u16) -> Rectangle {
    Rectangle::new(Point::new(0, i32::from(y)), Size::new(u32::from(PANEL), 1))
}

/// Core 1's target: the pixels of row `y` of an image of the panel's width.
struct RowTarget {
    y: u16,
    pixels: [Rgb565; WIDTH],
}

impl OriginDimensions for RowTarget {
    fn size(&self) -> Size {
        Size::new(u32::from(PANEL), u32::from(HEIGHT))
    }
}

impl DrawTarget for RowTarget {
    type Color = Rgb565;
    type Error = Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Infallible> {
        for Pixel(point, color) in pixels {
            let x = usize::try_from(point.x).ok();
            let slot = x.and_then(|x| self.pixels.get_mut(x));
            if let Some(slot) = slot.filter(|_| point.y == i32::from(self.y)) {
                *slot = color;
            }
        }
        Ok(())
    }
}
