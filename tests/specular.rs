//! `specular r g b`, the later course scenes' per-channel mirror reflectivity (and glint
//! weight): channels are independent, so each channel of a render with `specular r g b`
//! is that channel of the render with `specular r`, `g` or `b` for every channel; one number
//! is the same for all three; bad counts are errors that say so.

mod common;

use microray::error::ErrorKind;
use microray::host::{Framebuffer, HostScene};
use microray::parse::{no_textures, parse_scene};
use microray::print::print_scene;
use microray::render::Renderer;
use microray::scalar::I16F16;
use microray::{Scalar, Vec3};

/// A mirror floor with glints, a ball it reflects, two lights.
fn scene(specular: &str) -> String {
    format!(
        "camera c {{ pixeldim 48 36 worlddim 8 6 viewpoint 4 3 6 }}
         material floor {{ diffuse 1 1 1 ambient 0.5 0.5 0.5 specular {specular} shininess 20 }}
         material ball {{ diffuse 5 3 1 ambient 1 0.5 0.2 }}
         light a {{ location 2 8 2 emissivity 6 6 6 }}
         light b {{ location 7 5 -1 emissivity 3 4 5 }}
         plane floor {{ material floor normal 0 1 0 point 0 0 0 }}
         sphere ball {{ material ball center 4 2 -5 radius 1.5 }}"
    )
}

fn render<S: Scalar>(text: &str) -> Framebuffer {
    let scene: HostScene<'_, S> = parse_scene(text.as_bytes(), no_textures).unwrap();
    common::image(&Renderer::new(&scene))
}

fn channels_are_independent<S: Scalar>() {
    let mixed = render::<S>(&scene("0.8 0.3 0"));
    let per = [
        render::<S>(&scene("0.8")),
        render::<S>(&scene("0.3")),
        render::<S>(&scene("0")),
    ];
    for (channel, single) in per.iter().enumerate() {
        let of = |image: &Framebuffer| -> Vec<u8> {
            image
                .rgb()
                .iter()
                .skip(channel)
                .step_by(3)
                .copied()
                .collect()
        };
        assert_eq!(of(&mixed), of(single), "{} channel {channel}", S::NAME);
    }
    // And the mirror does show: the red channel differs from a floor without it.
    let none = render::<S>(&scene("0"));
    assert_ne!(mixed.rgb(), none.rgb(), "{}", S::NAME);
}

#[test]
fn each_channel_is_the_render_with_that_channels_specular() {
    channels_are_independent::<f64>();
    channels_are_independent::<f32>();
    channels_are_independent::<I16F16>();
}

#[test]
fn one_number_is_every_channel_and_three_print_back() {
    let read = |s: &str| -> HostScene<'_, f64> { parse_scene(s.as_bytes(), no_textures).unwrap() };
    let one = read(&scene("0.5"));
    assert_eq!(one, read(&scene("0.5 0.5 0.5")));
    assert_eq!(one.materials()[0].specular, Vec3::new(0.5, 0.5, 0.5));
    let three = read(&scene("0.25 0.5 1"));
    assert_eq!(three.materials()[0].specular, Vec3::new(0.25, 0.5, 1.0));
    for scene in [one, three] {
        let mut text = String::new();
        print_scene(&scene, &mut text).unwrap();
        assert_eq!(read(&text), scene, "{text}");
    }
    let mut text = String::new();
    print_scene(&read(&scene("0.5")), &mut text).unwrap();
    assert!(text.contains("  specular 0.5\n"), "{text}");
}

#[test]
fn two_or_four_numbers_and_negative_channels_are_errors() {
    let error =
        |s: &str| parse_scene::<f64, 8, 4, 4, 0, 64>(s.as_bytes(), no_textures).unwrap_err();
    let two = error(&scene("0.5 0.5"));
    assert_eq!(
        two.kind.to_string(),
        "`specular` takes 1 or 3 numbers, found 2 before `shininess`"
    );
    let four = error(&scene("0.5 0.5 0.5 0.5"));
    assert_eq!(
        four.kind.to_string(),
        "extra value: `specular` takes 1 or 3 numbers"
    );
    // At the fourth number.
    let text = scene("0.5 0.5 0.5 0.5");
    let line = text.lines().nth(1).unwrap();
    let column = line.find("specular ").unwrap() + "specular 0.5 0.5 0.5 ".len() + 1;
    let at = four.position.unwrap();
    assert_eq!((at.line, at.column as usize), (2, column));
    assert!(matches!(
        error(&scene("0.5 -0.1 0.5")).kind,
        ErrorKind::OutOfRange { .. }
    ));
}
