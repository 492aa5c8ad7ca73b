//! The Raspberry Pi Pico's split of the rows between its two cores (firmware/pico/src/
//! split.rs, compiled here as it is there), run on the host with a thread as core 1, as the
//! emulator cannot run the Pico's core 1: every row reaches the panel once, each core's rows
//! in order, core 1's through the queue of four, and the panel ends with the one-core image.

#![cfg(feature = "std")]

#[allow(dead_code)]
#[path = "../firmware/pico/src/split.rs"]
mod split;

use core::convert::Infallible;
use core::ops::ControlFlow;
use embedded_graphics::Pixel;
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use embedded_graphics::prelude::{DrawTarget, OriginDimensions, Point, Size};
use embedded_graphics::primitives::Rectangle;
use microray::host::{HostRenderer, HostScene, texture_files};
use microray::parse::parse_scene;
use microray::scalar::I16F16;
use std::path::Path;

/// The Pico's image: its panel's width, and the 4:3 scene's height (firmware/pico/src/main.rs).
const PANEL: u16 = 240;
const HEIGHT: u16 = 180;

/// The panel as the split draws on it: the rows in the order they came, each with its pixels.
struct Panel {
    rows: Vec<(u16, Vec<Rgb565>)>,
}

impl OriginDimensions for Panel {
    fn size(&self) -> Size {
        Size::new(u32::from(PANEL), u32::from(HEIGHT))
    }
}

impl DrawTarget for Panel {
    type Color = Rgb565;
    type Error = Infallible;

    fn fill_contiguous<I>(&mut self, area: &Rectangle, colors: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Rgb565>,
    {
        assert_eq!(
            area.size,
            Size::new(u32::from(PANEL), 1),
            "not a whole row: {area:?}"
        );
        assert_eq!(area.top_left.x, 0);
        let y = u16::try_from(area.top_left.y).unwrap();
        self.rows.push((y, colors.into_iter().collect()));
        Ok(())
    }

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(&mut self, _: I) -> Result<(), Infallible> {
        panic!("the split draws whole rows only");
    }
}

/// The queue is one static, as on the Pico: one test at a time uses it.
static QUEUE: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn scene(name: &str) -> HostScene<'static, I16F16> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let text = std::fs::read(&path).unwrap();
    let mut scene: HostScene<'static, I16F16> =
        parse_scene(&text, texture_files(path.parent().unwrap())).unwrap();
    scene.set_resolution(PANEL, HEIGHT).unwrap();
    scene
}

/// The rows one core draws, in order.
fn one_core(renderer: &HostRenderer<'_, I16F16>) -> Vec<Vec<Rgb565>> {
    let mut panel = Panel { rows: Vec::new() };
    let mut row = [Rgb565::BLACK; PANEL as usize];
    let image = Rectangle::new(Point::zero(), Size::new(PANEL.into(), HEIGHT.into()));
    renderer
        .render_area(&mut panel, image, &mut row, |_| ControlFlow::Continue(()))
        .unwrap();
    assert_every_row_once_in_order(&panel);
    panel.rows.into_iter().map(|(_, pixels)| pixels).collect()
}

fn assert_every_row_once_in_order(panel: &Panel) {
    let ys: Vec<u16> = panel.rows.iter().map(|(y, _)| *y).collect();
    assert_eq!(ys, (0..HEIGHT).collect::<Vec<_>>());
}

/// Runs the split with core 1 starting `late` (after core 0 has rendered its rows, so that
/// core 0 waits for all of core 1's through the full queue) or at once, and checks the panel.
fn two_cores(late: bool) {
    let _queue = QUEUE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let scene = scene("showcase.txt");
    let expected = one_core(&HostRenderer::new(&scene));
    let mut panel = Panel { rows: Vec::new() };
    std::thread::scope(|scope| {
        // Core 1, with a renderer of its own as on the Pico.
        scope.spawn(|| {
            if late {
                std::thread::sleep(std::time::Duration::from_secs(2));
            }
            split::odd_rows(&HostRenderer::new(&scene))
        });
        split::even_rows(&HostRenderer::new(&scene), &mut panel, 2);
    });
    let order: Vec<u16> = panel.rows.iter().map(|(y, _)| *y).collect();
    if late {
        // Core 0 had sent all its rows before core 1 began (else this run tested nothing
        // of the wait).
        assert!(
            order
                .iter()
                .take(usize::from(HEIGHT / 2))
                .all(|y| y % 2 == 0),
            "{order:?}"
        );
    }
    // Every row once.
    let mut ys = order.clone();
    ys.sort_unstable();
    assert_eq!(ys, (0..HEIGHT).collect::<Vec<_>>(), "rows sent: {order:?}");
    // Each core's rows in order: core 0's even ones as it renders them, core 1's odd ones as
    // the queue hands them over.
    for parity in [0, 1] {
        let own: Vec<u16> = order.iter().copied().filter(|y| y % 2 == parity).collect();
        assert!(
            own.windows(2).all(|w| w[0] < w[1]),
            "rows of parity {parity}: {own:?}"
        );
    }
    // The queue is empty, and the panel holds the one-core image.
    assert!(critical_section::with(|cs| split::READY
        .borrow_ref(cs)
        .is_empty()));
    for (y, pixels) in &panel.rows {
        assert!(
            pixels == &expected[usize::from(*y)],
            "row {y} differs from one core's"
        );
    }
}

#[test]
fn two_cores_at_once_send_every_row_once_and_the_one_core_image() {
    two_cores(false);
}

#[test]
fn core_0_waits_for_a_late_core_1_through_the_queue() {
    two_cores(true);
}

#[test]
fn one_core_alone_renders_every_row_in_order() {
    // Core 1 not started: core 0 renders all the rows itself (step 1).
    let _queue = QUEUE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let scene = scene("stage.txt");
    let expected = one_core(&HostRenderer::new(&scene));
    let mut panel = Panel { rows: Vec::new() };
    split::even_rows(&HostRenderer::new(&scene), &mut panel, 1);
    assert_every_row_once_in_order(&panel);
    let pixels: Vec<Vec<Rgb565>> = panel.rows.into_iter().map(|(_, p)| p).collect();
    assert!(pixels == expected);
}
