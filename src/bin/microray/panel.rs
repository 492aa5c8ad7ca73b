//! `--color FORMAT` and `--dither FORMAT[:METHOD]`: the picture as a panel of that format
//! shows it, expanded back to 8 bits a channel.

use microray::dither::{Format, Method};
use microray::host::panel::{PanelRows, by_position};

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

/// Rows that may come in any order (not error diffusion's, which go through
/// [`converter`]).
pub(crate) fn to_panel(rgb: &mut [u8], width: usize, origin: (usize, usize), output: Output) {
    if let Output::Panel { format, method } = output {
        by_position(rgb, width, origin, format, method);
    }
}

/// The conversion of a picture's rows in order, from the top.
pub(crate) fn converter(output: Output, width: usize) -> PanelRows {
    match output {
        Output::Panel { format, method } => PanelRows::new(format, method, width),
        Output::Rgb888 => PanelRows::new(Format::Rgb565, None, 0),
    }
}
