//! Draws a scene file into an Rgb565 panel, as firmware does: no heap, no std, one row of
//! pixels in RAM, the scene sized from its own text at compile time.
#![no_std]

use core::ops::ControlFlow;
use microray::capacity::Capacities;
use microray::embedded_graphics::pixelcolor::Rgb565;
use microray::embedded_graphics::prelude::*;
use microray::embedded_graphics::primitives::Rectangle;
use microray::parse::{no_textures, parse_scene_into};
use microray::render::{RenderError, Renderer};
use microray::{Error, Scene};

/// The scene file, kept in flash.
pub const SCENE: &[u8] = include_bytes!("../../../scenes/minimal.txt");

/// What the scene needs: its objects, materials, lights, textures and width.
const NEEDS: Capacities = Capacities::of_text(SCENE);

/// A scene with room for exactly that, computing in `f32`.
pub type MyScene = Scene<
    'static,
    f32,
    { NEEDS.objects },
    { NEEDS.materials },
    { NEEDS.lights },
    { NEEDS.textures },
    { NEEDS.max_width },
>;

/// Why drawing stopped.
#[derive(Debug)]
pub enum DrawError<E> {
    /// The scene did not load (line, column and what was expected).
    Scene(Error),
    /// The panel failed.
    Panel(RenderError<E>),
}

/// Loads the scene into `scene` and draws it into `panel`, top row first.
pub fn draw<D>(scene: &mut MyScene, panel: &mut D) -> Result<(), DrawError<D::Error>>
where
    D: DrawTarget<Color = Rgb565>,
{
    parse_scene_into(SCENE, no_textures, scene).map_err(DrawError::Scene)?;
    let renderer = Renderer::new(scene);
    let mut row = [Rgb565::BLACK; NEEDS.max_width];
    let area = Rectangle::new(Point::zero(), renderer.size());
    renderer
        .render_area(panel, area, &mut row, |_| ControlFlow::Continue(()))
        .map_err(DrawError::Panel)?;
    Ok(())
}
