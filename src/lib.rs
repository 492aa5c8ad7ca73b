//! # microray
//!
//! A `no_std` ray tracer for microcontroller displays. It reads the scene files of a classic
//! university course ray tracer, keeps the C design's objects with `hits`/`printer` function
//! pointers (in safe Rust: a `'static` table of `fn` pointers per object kind), and computes
//! in any [`Scalar`] number type from one source. The library allocates nothing: every list is
//! a [`heapless::Vec`](https://docs.rs/heapless/0.9/heapless/type.Vec.html) whose capacity is part of the [`Scene`] type, and running out of room is
//! an [`Error`], never a panic.
//!
//! ```
//! use microray::{parse::parse_scene, print::print_scene, Scene};
//!
//! let text = b"
//!     camera cam { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 3 }
//!     material white { diffuse 3 3 3 ambient 1 1 1 }
//!     plane floor { material white normal 0 1 0 point 0 0 0 }
//!     light top { location 4 10 0 emissivity 5 5 5 }
//! ";
//! let scene: Scene<f32> = parse_scene(text, microray::parse::no_textures)?;
//! assert_eq!(scene.objects().len(), 1);
//!
//! let mut out = heapless::String::<512>::new();
//! print_scene(&scene, &mut out).map_err(|_| "printer ran out of room")?;
//! assert!(out.starts_with("camera cam\n{\n  pixeldim 64 48\n"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Features
//! | feature | default | what it adds |
//! |---|---|---|
//! | `std` | yes | the `microray` command-line tracer, file-based texture loading and an RGB framebuffer writing PPM/PNG (`host`); implies `full` and `batch` |
//! | `batch` | in `std` | a planned row's pixels shaded 16 at a time, stage by stage (`shade::BATCH`): the same pixels, faster on out-of-order processors; on a microcontroller only more stack |
//! | `full` | yes | all of the below |
//! | `plan` | in `full` | the render plan ([`plan`]): skipped stages, per-row object lists and row tests, rows shaded together, the bounding-volume tree ([`bvh`]) and the shadow cache; without it every pixel takes the general path (the same pixels, slower, in less flash) |
//! | `parser` | in `full` | the scene-file parser (`parse`); without it, scenes are built from `*Def` values in Rust source |
//! | `print` | in `full` | scene text out (`print`, each object's `printer`) |
//! | `fplane`, `tiled-plane` | in `full` | the finite and the tiled plane |
//! | `texture` | in `full` | textures and the textured plane |
//! | `spotlight` | in `full` | spotlights |
//! | `reflection`, `transparency`, `glint` | in `full` | mirror rays (`specular`), transmission and filtered shadows (`transparency`), Blinn-Phong glints (`shininess`; needs `reflection`) |
//! | `projector`, `revsurf` | in `full` | projectors (lights that shine a texture) and surfaces of revolution |
//! | `antialias` | in `full` | anti-aliasing at fixed sample positions (`render::Antialias`): a grid of samples per pixel, or only on edges |
//! | `animate` | in `full` | moving pictures: objects, lights and materials replaced between frames ([`Scene::replace_object`] and its kin) and the screen region each change can touch ([`region`]), so a frame re-traces only that, byte for byte the full frame |
//! | `geometry-f32` | no | the render plan's bounds and a moving picture's region worked out in `f32`, not `f64` ([`scalar::geometry`]): for a single-precision float unit (Cortex-M4F), where `f64` is software; the same images |
//! | `warnings` | in `full` | warnings about ill-posed scenes ([`Scene::warnings`], [`warning`]): coincident surfaces, a light on a surface or at the eye, a surface through the eye, the eye inside an object |
//! | `dither` | in `std` | dithering into any panel format (`dither::Dither`): one-bit, grey and Rgb332 to Rgb666 panels, ordered (Bayer, blue noise) or error-diffused (Floyd-Steinberg, Atkinson); Rgb565's Bayer dither ([`dither::Rgb565Dither`]) is there without it |
//! | `sdl` | no | `examples/simulator.rs` opens an SDL window |
//!
//! Without default features the crate is `#![no_std]`, has no `alloc`, and builds for
//! `thumbv6m-none-eabi`, `thumbv7em-none-eabihf` and `riscv32imc-unknown-none-elf`. What is
//! always there: planes, spheres, point lights, ambient and diffuse light. A
//! scene that needs a feature the build left out fails to load with
//! [`ErrorKind::NotCompiledIn`], which names the feature (and, from the parser, the line and
//! column that asks for it).
//!
//! ## On a microcontroller
//! In the firmware's `Cargo.toml`, without the default features (which bring `std`), and
//! with those the scene needs:
//!
//! ```toml
//! microray = { version = "0.1", default-features = false, features = ["parser", "plan"] }
//! ```
//!
//! A scene's capacities are part of its type and cost RAM slot by slot:
//! [`capacity::Capacities::of_text`] counts them from the scene's text in a `const`, and
//! [`Scene`]'s docs ("Sizing a scene") give each slot's bytes on a 32-bit Cortex-M. Render
//! with [`render::Renderer::render_area`] into the panel with a row buffer in the panel's own
//! colour type:
//!
//! ```
//! use core::ops::ControlFlow;
//! use microray::capacity::Capacities;
//! use microray::embedded_graphics::{pixelcolor::Rgb565, prelude::*, primitives::Rectangle};
//! use microray::{parse::{no_textures, parse_scene_into}, render::Renderer, Scene};
//!
//! const SCENE: &[u8] = b"
//!     camera eye { pixeldim 160 120 worlddim 8 6 viewpoint 4 3 3 }
//!     material white { diffuse 3 3 3 ambient 1 1 1 }
//!     light top { location 4 10 0 emissivity 5 5 5 }
//!     plane floor { material white normal 0 1 0 point 0 0 0 }
//! ";
//! const NEEDS: Capacities = Capacities::of_text(SCENE);
//! type Sized = Scene<'static, f32, { NEEDS.objects }, { NEEDS.materials }, { NEEDS.lights },
//!     { NEEDS.textures }, { NEEDS.max_width }>;
//!
//! fn draw<D: DrawTarget<Color = Rgb565>>(panel: &mut D) -> Result<(), &'static str> {
//!     let mut scene = Sized::empty();
//!     parse_scene_into(SCENE, no_textures, &mut scene).map_err(|_| "bad scene")?;
//!     let renderer = Renderer::new(&scene);
//!     let mut row = [Rgb565::BLACK; NEEDS.max_width];
//!     let area = Rectangle::new(Point::zero(), renderer.size());
//!     renderer
//!         .render_area(panel, area, &mut row, |_| ControlFlow::Continue(()))
//!         .map_err(|_| "panel failed")?;
//!     Ok(())
//! }
//! # let mut panel = embedded_graphics::mock_display::MockDisplay::<Rgb565>::new();
//! # panel.set_allow_out_of_bounds_drawing(true);
//! # panel.set_allow_overdraw(true);
//! # draw(&mut panel).unwrap();
//! ```
//!
//! The crates the API uses are re-exported
//! ([`embedded_graphics`](https://docs.rs/embedded-graphics/0.8),
//! [`heapless`](https://docs.rs/heapless/0.9), [`fixed`](https://docs.rs/fixed/1)) so that
//! firmware names the versions microray was built with. The repository's
//! `firmware/` renders every scene this way in QEMU, `firmware/quickstart` is this example
//! as a crate built for `thumbv6m-none-eabi`, and `firmware/pico` runs on a Raspberry Pi
//! Pico with an ST7789 panel.
//!
//! ## Layout
//! One concept per module: [`scalar`], [`vec3`], [`ray`], [`camera`], [`material`], [`light`],
//! [`texture`], [`object`] (one file per kind), [`scene`], `parse`, `print`, [`plan`] (what a
//! scene needs, per-row object lists), [`shade`] (the course's illumination), [`render`] (rows
//! into a `DrawTarget`), `region` (what a change to the scene can touch), [`error`].
#![cfg_attr(not(feature = "std"), no_std)]
#![deny(unsafe_code)]
#![deny(missing_docs)]
#![warn(missing_debug_implementations, rust_2018_idioms, unreachable_pub)]
// `!(t > 0)` is deliberate: a NaN must count as a miss, which `t <= 0` would not do.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// The library must not panic on any input: these lints keep panicking shortcuts out of it.
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented,
        clippy::indexing_slicing
    )
)]

#[cfg(feature = "animate")]
pub mod animation;
pub mod bvh;
pub mod camera;
pub mod capacity;
pub mod compiled;
#[cfg(any(feature = "parser", feature = "print"))]
pub mod decimal;
pub mod dither;
pub mod error;
pub mod hits;
mod interval;
#[cfg(feature = "batch")]
mod lanes;
pub mod light;
pub mod material;
pub mod name;
pub mod object;
#[cfg(feature = "parser")]
pub mod parse;
pub mod plan;
#[cfg(feature = "print")]
pub mod print;
pub mod range;
pub mod ray;
#[cfg(feature = "animate")]
pub mod region;
pub mod render;
pub mod scalar;
pub mod scene;
pub mod shade;
pub mod texture;
pub use scalar::vec3;
#[cfg(feature = "warnings")]
pub mod warning;
#[cfg(feature = "print")]
pub mod write;

#[cfg(feature = "std")]
pub mod host;

// The crates whose types the public API takes and returns, re-exported so that a program
// names the versions microray was built with (`microray::embedded_graphics::pixelcolor::Rgb565`).
pub use embedded_graphics;
pub use fixed;
pub use heapless;

pub use camera::{Camera, CameraDef};
pub use error::{Error, ErrorKind, Position};
pub use light::{Light, LightDef, SlideDef};
pub use material::{Material, MaterialDef};
pub use object::{Hit, Object, ObjectDef, ObjectVTable, RectDef, TextureMode};
pub use ray::Ray;
pub use scalar::Scalar;
pub use scene::Scene;
pub use texture::{Texture, TextureDef};
pub use vec3::Vec3;
