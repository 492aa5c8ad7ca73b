//! A picture's RGB bytes as a panel shows them: truncated or dithered into a
//! [`Format`], expanded back to 8 bits a channel (`microray render --color/--dither`, and
//! the firmware frames' checks).

use crate::dither::{
    Diffusion, Format, Matrix, Method, PanelColor, Rgb332, Rgb444, dither_ordered, shown, truncate,
};
use embedded_graphics::pixelcolor::{
    BinaryColor, Gray2, Gray4, Gray8, Rgb555, Rgb565, Rgb666, Rgb888, RgbColor,
};
use embedded_graphics::prelude::Point;

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

/// [`by_position`] for the format `C`.
fn each_pixel<C: PanelColor>(
    rgb: &mut [u8],
    width: usize,
    (left, top): (usize, usize),
    matrix: Option<Matrix>,
) {
    for (i, c) in rgb.chunks_exact_mut(3).enumerate() {
        let p = Point::new((left + i % width) as i32, (top + i / width) as i32);
        let &mut [r, g, b] = c else { continue };
        let color = Rgb888::new(r, g, b);
        let panel: C = match matrix {
            Some(m) => dither_ordered(color, p, m),
            None => truncate(color),
        };
        write(c, panel);
    }
}

/// Rows of a picture (`width` pixels each from column `origin.0`, row `origin.1` the
/// first, three bytes a pixel), in place, truncated (`method` `None`) or by an ordered
/// method: rows in any order. Error diffusion needs [`PanelRows`]; here it leaves the
/// bytes as they are.
pub fn by_position(
    rgb: &mut [u8],
    width: usize,
    origin: (usize, usize),
    format: Format,
    method: Option<Method>,
) {
    if width == 0 {
        return;
    }
    let matrix = match method {
        None => None,
        Some(Method::Ordered(m)) => Some(m),
        // The callers send such rows through `Converter` instead.
        Some(Method::Diffusion { .. }) => return,
    };
    with_format!(format, C => each_pixel::<C>(rgb, width, origin, matrix))
}

/// Converts the next rows of a picture, in place.
type RowsFn = Box<dyn FnMut(&mut [u8]) + Send>;

/// A picture's rows converted in order, top to bottom from the first (what error
/// diffusion needs; any method works).
///
/// ```
/// use microray::dither::{Format, Method};
/// use microray::host::panel::PanelRows;
///
/// let mut rgb = vec![100u8; 3 * 8 * 2]; // two rows of 8 grey pixels
/// let mut rows = PanelRows::new(Format::Binary, Method::from_name("atkinson"), 8);
/// rows.rows(&mut rgb);
/// assert!(rgb.iter().all(|&v| v == 0 || v == 255));
/// ```
pub struct PanelRows {
    convert: RowsFn,
}

impl core::fmt::Debug for PanelRows {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("PanelRows")
    }
}

impl PanelRows {
    /// A conversion into `format` by `method` (`None`: truncation) of a picture `width`
    /// pixels wide.
    pub fn new(format: Format, method: Option<Method>, width: usize) -> PanelRows {
        let convert: RowsFn = match method {
            Some(Method::Diffusion { kernel, serpentine }) => {
                with_format!(format, C => diffusing::<C>(kernel, serpentine, width))
            }
            _ => {
                let mut top = 0;
                Box::new(move |rows: &mut [u8]| {
                    by_position(rows, width, (0, top), format, method);
                    top += rows.len() / (3 * width.max(1));
                })
            }
        };
        PanelRows { convert }
    }

    /// The next rows of the picture, in place.
    pub fn rows(&mut self, rgb: &mut [u8]) {
        (self.convert)(rgb)
    }
}

/// A whole picture (`width` pixels a row) converted in place.
pub fn whole(rgb: &mut [u8], width: usize, format: Format, method: Option<Method>) {
    PanelRows::new(format, method, width).rows(rgb)
}

fn diffusing<C: PanelColor + Send + 'static>(
    kernel: crate::dither::Kernel,
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
                if let &[r, g, b] = c {
                    diffusion.set(x, Rgb888::new(r, g, b));
                }
            }
            diffusion.finish_row();
            for (c, level) in row.chunks_exact_mut(3).zip(diffusion.levels()) {
                write(c, level);
            }
            diffusion.next_row();
        }
    })
}
