//! `--color FORMAT` and `--dither FORMAT[:METHOD]`: the picture as a panel of that format
//! shows it, expanded back to 8 bits a channel.

use embedded_graphics::pixelcolor::{
    BinaryColor, Gray2, Gray4, Gray8, Rgb555, Rgb565, Rgb666, Rgb888, RgbColor,
};
use embedded_graphics::prelude::Point;
use microray::dither::{
    Diffusion, Format, Matrix, Method, PanelColor, Rgb332, Rgb444, dither_ordered, shown, truncate,
};

/// The colours written: the tracer's, or a panel's.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Output {
    Rgb888,
    /// A panel's colours by `method`, or truncated.
    Panel {
        format: Format,
        method: Option<Method>,
    },
}

impl Output {
    /// Whether rows must be converted in order, top to bottom (error diffusion).
    pub(crate) fn needs_order(self) -> bool {
        matches!(
            self,
            Output::Panel {
                method: Some(Method::Diffusion { .. }),
                ..
            }
        )
    }
}

/// `--color`'s value: `rgb888` or a panel format.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Color {
    Rgb888,
    Panel(Format),
}

fn format_names() -> String {
    let names: Vec<&str> = Format::ALL.iter().map(|(n, _)| *n).collect();
    names.join(" ")
}

fn method_names() -> String {
    let names: Vec<&str> = Method::ALL.iter().map(|(n, _)| *n).collect();
    format!(
        "{} (floyd-steinberg and atkinson also with -serpentine)",
        names.join(" ")
    )
}

fn format_of(name: &str) -> Result<Format, String> {
    Format::from_name(name).ok_or_else(|| {
        format!(
            "`{name}`: unknown panel format; expected one of: {}",
            format_names()
        )
    })
}

pub(crate) fn parse_color(text: &str) -> Result<Color, String> {
    if text == "rgb888" {
        return Ok(Color::Rgb888);
    }
    format_of(text)
        .map(Color::Panel)
        .map_err(|e| format!("{e} rgb888"))
}

/// `--dither`'s value: a format and maybe a method.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) struct PanelDither {
    pub(crate) format: Format,
    pub(crate) method: Option<Method>,
}

pub(crate) fn parse_dither(text: &str) -> Result<PanelDither, String> {
    let (format, method) = match text.split_once(':') {
        Some((f, m)) => (f, Some(m)),
        None => (text, None),
    };
    let format = format_of(format)?;
    let method = match method {
        None => None,
        Some(name) => Some(Method::from_name(name).ok_or_else(|| {
            format!(
                "`{name}`: unknown dither method; expected one of: {}",
                method_names()
            )
        })?),
    };
    Ok(PanelDither { format, method })
}

/// Calls `$body` with `$c` the colour type of `$format`.
macro_rules! with_format {
    ($format:expr, $c:ident => $body:expr) => {
        match $format {
            Format::Binary => {
                type $c = BinaryColor;
                $body
            }
            Format::Gray2 => {
                type $c = Gray2;
                $body
            }
            Format::Gray4 => {
                type $c = Gray4;
                $body
            }
            Format::Gray8 => {
                type $c = Gray8;
                $body
            }
            Format::Rgb332 => {
                type $c = Rgb332;
                $body
            }
            Format::Rgb444 => {
                type $c = Rgb444;
                $body
            }
            Format::Rgb555 => {
                type $c = Rgb555;
                $body
            }
            Format::Rgb565 => {
                type $c = Rgb565;
                $body
            }
            Format::Rgb666 => {
                type $c = Rgb666;
                $body
            }
        }
    };
}

fn write<C: PanelColor>(bytes: &mut [u8], c: C) {
    let s = shown(c);
    bytes.copy_from_slice(&[s.r(), s.g(), s.b()]);
}

/// Rows of the picture (`width` pixels each from column `left`, `top` the first, three
/// bytes a pixel) truncated or dithered by position: any rows, in any order.
fn by_position<C: PanelColor>(
    rgb: &mut [u8],
    width: usize,
    (left, top): (usize, usize),
    matrix: Option<Matrix>,
) {
    for (i, c) in rgb.chunks_exact_mut(3).enumerate() {
        let p = Point::new((left + i % width) as i32, (top + i / width) as i32);
        let color = Rgb888::new(c[0], c[1], c[2]);
        let panel: C = match matrix {
            Some(m) => dither_ordered(color, p, m),
            None => truncate(color),
        };
        write(c, panel);
    }
}

/// The conversion of rows that may come in any order (not error diffusion): `None` when
/// `output` needs them in order.
pub(crate) fn to_panel(rgb: &mut [u8], width: usize, origin: (usize, usize), output: Output) {
    if width == 0 {
        return;
    }
    let Output::Panel { format, method } = output else {
        return;
    };
    let matrix = match method {
        None => None,
        Some(Method::Ordered(m)) => Some(m),
        // The callers send such rows through `Converter` instead.
        Some(Method::Diffusion { .. }) => return,
    };
    with_format!(format, C => by_position::<C>(rgb, width, origin, matrix))
}

/// Converts the next rows of a picture, in place.
type RowsFn = Box<dyn FnMut(&mut [u8]) + Send>;

/// A conversion with state: error diffusion takes whole rows of the whole picture, top to
/// bottom, from the first row on.
pub(crate) struct Converter {
    convert: RowsFn,
}

impl Converter {
    /// A conversion for `output` of a picture `width` pixels wide.
    pub(crate) fn new(output: Output, width: usize) -> Converter {
        let convert: RowsFn = match output {
            Output::Panel {
                format,
                method: Some(Method::Diffusion { kernel, serpentine }),
            } => with_format!(format, C => diffusing::<C>(kernel, serpentine, width)),
            _ => {
                let mut top = 0;
                Box::new(move |rows: &mut [u8]| {
                    to_panel(rows, width, (0, top), output);
                    top += rows.len() / (3 * width.max(1));
                })
            }
        };
        Converter { convert }
    }

    /// The next rows of the picture, in place.
    pub(crate) fn rows(&mut self, rgb: &mut [u8]) {
        (self.convert)(rgb)
    }
}

fn diffusing<C: PanelColor + Send + 'static>(
    kernel: microray::dither::Kernel,
    serpentine: bool,
    width: usize,
) -> RowsFn {
    let memory = vec![0i16; Diffusion::<C>::cells(kernel, width)];
    // The memory is exactly what `cells` asks for: `new` cannot fail.
    let Ok(mut diffusion) = Diffusion::<C, Vec<i16>>::new(kernel, serpentine, width, memory) else {
        return Box::new(|_: &mut [u8]| {});
    };
    Box::new(move |rgb: &mut [u8]| {
        for row in rgb.chunks_exact_mut(3 * width.max(1)) {
            for (x, c) in row.chunks_exact(3).enumerate() {
                diffusion.set(x, Rgb888::new(c[0], c[1], c[2]));
            }
            diffusion.finish_row();
            for (c, level) in row.chunks_exact_mut(3).zip(diffusion.levels()) {
                write(c, level);
            }
            diffusion.next_row();
        }
    })
}
