//! The README's firmware quick start (`firmware/quickstart`, built for thumbv6m-none-eabi
//! by CI) draws the picture the library draws with room to spare, into an Rgb565 panel.

// Its `#![no_std]` is for a crate root; its error fields are for firmware to read.
#[allow(unused_attributes, dead_code)]
#[path = "../firmware/quickstart/src/lib.rs"]
mod quickstart;

mod common;

use common::Panel;

use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use microray::parse::{no_textures, parse_scene};
use microray::render::Renderer;
use std::ops::ControlFlow;

#[test]
fn the_quick_start_draws_what_the_library_draws() {
    let roomy: microray::Scene<'_, f32> = parse_scene(quickstart::SCENE, no_textures).unwrap();
    let size = Renderer::new(&roomy).size();
    let blank = || Panel::filled(size, Rgb565::new(1, 2, 3));
    let mut expected = blank();
    let mut row = vec![Rgb565::BLACK; size.width as usize];
    let all = Rectangle::new(Point::zero(), size);
    Renderer::new(&roomy)
        .render_area(&mut expected, all, &mut row, |_| ControlFlow::Continue(()))
        .unwrap();

    let mut scene = quickstart::MyScene::empty();
    let mut panel = blank();
    quickstart::draw(&mut scene, &mut panel).unwrap();
    assert!(panel.pixels == expected.pixels);
    assert!(panel.pixels.iter().any(|&p| p != Rgb565::BLACK));
}
