//! Panel colours: the tracer's 8-bit channels to the few bits of a panel, truncated or
//! dithered.
//!
//! - [`Rgb565Dither`] (always built): Rgb565 panels, truncated or with a 4x4 Bayer dither.
//! - With the `dither` feature, `Dither` takes any `PanelColor` format: one-bit
//!   (`BinaryColor`: SSD1306 and SH1106 OLEDs, Sharp memory LCDs), grey (`Gray2`, `Gray4`,
//!   `Gray8`: e-paper), and `Rgb332`, `Rgb444` (defined here), `Rgb555`, `Rgb565`, `Rgb666`.
//!   Grey is BT.601 luma (`color`). The methods:
//!
//! | `Method` | memory | drawing order | |
//! |---|---|---|---|
//! | `bayer2`, `bayer4`, `bayer8` | none | any | a regular cross-hatch |
//! | `blue-noise` | none (1 KiB table in flash) | any | no pattern, fine grain |
//! | `floyd-steinberg` | 2 rows of errors | rows, top to bottom | the closest local means |
//! | `atkinson` | 3 rows of errors | rows, top to bottom | crisp, loses 1/4 of each error |
//!
//! Error diffusion's memory is the caller's (`Diffusion::cells`); ordered methods work in
//! the progressive order and in an animation's patches, error diffusion refuses them
//! (`DitherError::OutOfOrder`). Everything is integer arithmetic: host and firmware
//! frames agree bit for bit. docs/dither.md in the repository measures each method
//! against truncation on the course's scenes, and prices them in instructions a pixel.

#[cfg(feature = "dither")]
pub mod blue_noise;
#[cfg(feature = "dither")]
pub mod color;
#[cfg(feature = "dither")]
pub mod diffusion;
#[cfg(feature = "dither")]
pub mod ordered;
mod rgb565;
#[cfg(feature = "dither")]
pub mod target;

#[cfg(feature = "dither")]
pub use color::{PanelColor, Rgb332, Rgb444, shown, truncate};
#[cfg(feature = "dither")]
pub use diffusion::{Diffusion, Kernel, SetupError};
#[cfg(feature = "dither")]
pub use ordered::{Matrix, dither_ordered};
pub use rgb565::{Rgb565Dither, dither_rgb565, truncate_rgb565};
#[cfg(feature = "dither")]
pub use target::{Dither, DitherError};

/// A way to reach a panel's colours.
#[cfg(feature = "dither")]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// By a threshold matrix, per pixel.
    Ordered(Matrix),
    /// By spreading errors along rows (serpentine: odd rows right to left).
    Diffusion {
        /// The kernel.
        kernel: Kernel,
        /// Odd rows right to left.
        serpentine: bool,
    },
}

#[cfg(feature = "dither")]
impl Method {
    /// Every method, by its command-line name.
    pub const ALL: [(&'static str, Method); 6] = [
        ("bayer2", Method::Ordered(Matrix::Bayer2)),
        ("bayer4", Method::Ordered(Matrix::Bayer4)),
        ("bayer8", Method::Ordered(Matrix::Bayer8)),
        ("blue-noise", Method::Ordered(Matrix::BlueNoise)),
        (
            "floyd-steinberg",
            Method::Diffusion {
                kernel: Kernel::FloydSteinberg,
                serpentine: false,
            },
        ),
        (
            "atkinson",
            Method::Diffusion {
                kernel: Kernel::Atkinson,
                serpentine: false,
            },
        ),
    ];

    /// The method of this name (`bayer2` ... `atkinson`; a diffusion's name followed by
    /// `-serpentine` for that order).
    pub fn from_name(name: &str) -> Option<Method> {
        let (base, serpentine) = match name.strip_suffix("-serpentine") {
            Some(base) => (base, true),
            None => (name, false),
        };
        let (_, method) = Method::ALL.iter().find(|(n, _)| *n == base)?;
        match (*method, serpentine) {
            (m, false) => Some(m),
            (Method::Diffusion { kernel, .. }, true) => Some(Method::Diffusion {
                kernel,
                serpentine: true,
            }),
            (Method::Ordered(_), true) => None,
        }
    }

    /// The method's name, as [`from_name`](Self::from_name) reads it.
    pub fn name(self) -> &'static str {
        match self {
            Method::Ordered(Matrix::Bayer2) => "bayer2",
            Method::Ordered(Matrix::Bayer4) => "bayer4",
            Method::Ordered(Matrix::Bayer8) => "bayer8",
            Method::Ordered(Matrix::BlueNoise) => "blue-noise",
            Method::Diffusion {
                kernel: Kernel::FloydSteinberg,
                serpentine: false,
            } => "floyd-steinberg",
            Method::Diffusion {
                kernel: Kernel::FloydSteinberg,
                serpentine: true,
            } => "floyd-steinberg-serpentine",
            Method::Diffusion {
                kernel: Kernel::Atkinson,
                serpentine: false,
            } => "atkinson",
            Method::Diffusion {
                kernel: Kernel::Atkinson,
                serpentine: true,
            } => "atkinson-serpentine",
        }
    }
}

/// The panel formats by name, for choosing one at run time.
#[cfg(feature = "dither")]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// One bit (`BinaryColor`).
    Binary,
    /// Four greys.
    Gray2,
    /// Sixteen greys.
    Gray4,
    /// 256 greys.
    Gray8,
    /// 3-3-2 bits.
    Rgb332,
    /// 4-4-4 bits.
    Rgb444,
    /// 5-5-5 bits.
    Rgb555,
    /// 5-6-5 bits.
    Rgb565,
    /// 6-6-6 bits.
    Rgb666,
}

#[cfg(feature = "dither")]
impl Format {
    /// Every format, by its command-line name.
    pub const ALL: [(&'static str, Format); 9] = [
        ("binary", Format::Binary),
        ("gray2", Format::Gray2),
        ("gray4", Format::Gray4),
        ("gray8", Format::Gray8),
        ("rgb332", Format::Rgb332),
        ("rgb444", Format::Rgb444),
        ("rgb555", Format::Rgb555),
        ("rgb565", Format::Rgb565),
        ("rgb666", Format::Rgb666),
    ];

    /// The format of this name.
    pub fn from_name(name: &str) -> Option<Format> {
        Format::ALL
            .iter()
            .find(|(n, _)| *n == name)
            .map(|&(_, f)| f)
    }

    /// The format's name.
    pub fn name(self) -> &'static str {
        Format::ALL
            .iter()
            .find(|(_, f)| *f == self)
            .map_or("", |&(n, _)| n)
    }

    /// The method with the lowest mean error over the course's scenes for this format
    /// (docs/dither.md; tests/dither.rs checks the choice against its own table).
    pub fn best_method(self) -> Method {
        let diffusion = |serpentine| Method::Diffusion {
            kernel: Kernel::FloydSteinberg,
            serpentine,
        };
        match self {
            Format::Binary | Format::Gray2 | Format::Gray4 | Format::Rgb332 | Format::Rgb444 => {
                Method::Ordered(Matrix::Bayer4)
            }
            Format::Rgb555 | Format::Rgb565 => diffusion(false),
            Format::Gray8 | Format::Rgb666 => diffusion(true),
        }
    }

    /// The ordered method with the lowest mean error (for an animation's patches, which
    /// error diffusion cannot dither).
    pub fn best_ordered(self) -> Method {
        Method::Ordered(match self {
            Format::Rgb555 | Format::Rgb565 => Matrix::Bayer8,
            Format::Rgb666 => Matrix::Bayer2,
            _ => Matrix::Bayer4,
        })
    }
}
