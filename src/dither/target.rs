//! [`Dither`]: an `Rgb888` draw target in front of a panel of any [`PanelColor`] format.

use super::color::{PanelColor, truncate};
use super::diffusion::{Diffusion, Kernel, SetupError};
use super::ordered::{Matrix, dither_ordered};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::{Dimensions, DrawTarget, Pixel, Point, PointsIter, Size};
use embedded_graphics::primitives::Rectangle;

/// What went wrong in drawing through a [`Dither`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DitherError<E> {
    /// The panel failed.
    Target(E),
    /// An error diffusion takes whole rows, top to bottom, inside its area; this pixel came
    /// while row `expected_row` was unfinished (the progressive order and patches draw
    /// out of order: dither them with an ordered method).
    OutOfOrder {
        /// The row being filled.
        expected_row: i32,
        /// The pixel that came.
        got: Point,
    },
}

impl<E: core::fmt::Debug> core::fmt::Display for DitherError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            DitherError::Target(e) => write!(f, "the display failed: {e:?}"),
            DitherError::OutOfOrder { expected_row, got } => write!(
                f,
                "error diffusion takes whole rows top to bottom: pixel ({}, {}) came while row \
                 {expected_row} was unfinished (use an ordered dither for the progressive \
                 order or partial redraws)",
                got.x, got.y
            ),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for DitherError<E> {}

#[derive(Debug)]
enum How<'m, C> {
    Truncate,
    Ordered(Matrix),
    Diffuse {
        diffusion: Diffusion<C, &'m mut [i16]>,
        /// Pixels of the current row received so far.
        filled: usize,
    },
}

/// An `Rgb888` target in front of a panel: each pixel truncated, dithered by its position
/// (ordered: any drawing order), or error-diffused row by row.
///
/// The renderer draws into it as into any target. An error diffusion expects every pixel of
/// its area once, row after row from the top (the plain and anti-aliased renders do so);
/// after the area's last row it starts again at the top, and [`reset`](Self::reset) starts
/// it over at any time. A pixel out of that order is an error, not a wrong picture.
///
/// ```
/// use embedded_graphics::{mock_display::MockDisplay, pixelcolor::BinaryColor, prelude::*};
/// use embedded_graphics::primitives::Rectangle;
/// use microray::dither::{Diffusion, Dither, Kernel};
/// use microray::{parse::{no_textures, parse_scene}, render::render, Scene};
///
/// let text = b"camera c { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 4 }
///              material grey { ambient 1 1 1 diffuse 3 3 3 }
///              plane floor { material grey normal 0 1 0 point 0 0 0 }
///              light sun { location 4 5 -2 emissivity 4 4 4 }";
/// let scene: Scene<f32, 2, 1, 1, 0, 64> = parse_scene(text, no_textures)?;
/// // A 64x64 panel showing the 64x48 picture: the diffusion covers the picture's area.
/// let mut panel: MockDisplay<BinaryColor> = MockDisplay::new();
/// let area = Rectangle::new(Point::zero(), Size::new(64, 48));
/// let mut rows = [0i16; Diffusion::<BinaryColor>::cells(Kernel::FloydSteinberg, 64)];
/// let mut dither =
///     Dither::diffusing_area(&mut panel, area, Kernel::FloydSteinberg, false, &mut rows)?;
/// render(&scene, &mut dither)?;
/// assert_eq!(panel.get_pixel(Point::new(10, 47)), Some(BinaryColor::On)); // the lit floor
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Dither<'t, 'm, T: DrawTarget> {
    inner: &'t mut T,
    how: How<'m, T::Color>,
    area: Rectangle,
}

impl<'t, 'm, T> Dither<'t, 'm, T>
where
    T: DrawTarget,
    T::Color: PanelColor,
{
    /// Each channel cut to its top bits ([`truncate`]): the picture without a dither.
    pub fn truncating(inner: &'t mut T) -> Self {
        let area = inner.bounding_box();
        Dither {
            inner,
            how: How::Truncate,
            area,
        }
    }

    /// An ordered dither by `matrix` ([`dither_ordered`]).
    pub fn ordered(inner: &'t mut T, matrix: Matrix) -> Self {
        let area = inner.bounding_box();
        Dither {
            inner,
            how: How::Ordered(matrix),
            area,
        }
    }

    /// An error diffusion over the panel's whole area, its rows in `memory` (at least
    /// [`Diffusion::cells`] for the panel's width).
    pub fn diffusing(
        inner: &'t mut T,
        kernel: Kernel,
        serpentine: bool,
        memory: &'m mut [i16],
    ) -> Result<Self, SetupError> {
        let area = inner.bounding_box();
        Self::diffusing_area(inner, area, kernel, serpentine, memory)
    }

    /// An error diffusion over `area` only (a partial render's rectangle).
    pub fn diffusing_area(
        inner: &'t mut T,
        area: Rectangle,
        kernel: Kernel,
        serpentine: bool,
        memory: &'m mut [i16],
    ) -> Result<Self, SetupError> {
        let width = area.size.width as usize;
        let diffusion = Diffusion::new(kernel, serpentine, width, memory)?;
        Ok(Dither {
            inner,
            how: How::Diffuse {
                diffusion,
                filled: 0,
            },
            area,
        })
    }

    /// Starts an error diffusion over at its area's top, no errors carried.
    pub fn reset(&mut self) {
        if let How::Diffuse { diffusion, filled } = &mut self.how {
            diffusion.reset();
            *filled = 0;
        }
    }

    /// One pixel into the diffusion; the row goes out when it is full.
    fn diffuse(
        inner: &mut T,
        area: Rectangle,
        diffusion: &mut Diffusion<T::Color, &mut [i16]>,
        filled: &mut usize,
        Pixel(p, c): Pixel<Rgb888>,
    ) -> Result<(), DitherError<T::Error>> {
        if !area.contains(p) {
            // Outside the area: the panel would clip it anyway.
            return Ok(());
        }
        let row = area.top_left.y.saturating_add(diffusion.rows_done() as i32);
        if p.y != row {
            return Err(DitherError::OutOfOrder {
                expected_row: row,
                got: p,
            });
        }
        diffusion.set(p.x.wrapping_sub(area.top_left.x) as usize, c);
        *filled += 1;
        Self::row_out(inner, area, diffusion, filled)
    }

    /// The current row quantized and sent, once all its pixels are in.
    fn row_out(
        inner: &mut T,
        area: Rectangle,
        diffusion: &mut Diffusion<T::Color, &mut [i16]>,
        filled: &mut usize,
    ) -> Result<(), DitherError<T::Error>> {
        if *filled < diffusion.width() {
            return Ok(());
        }
        let row = area.top_left.y.saturating_add(diffusion.rows_done() as i32);
        diffusion.finish_row();
        let line = Rectangle::new(
            Point::new(area.top_left.x, row),
            Size::new(area.size.width, 1),
        );
        let sent = inner.fill_contiguous(&line, diffusion.levels());
        diffusion.next_row();
        *filled = 0;
        if diffusion.rows_done() >= area.size.height as usize {
            diffusion.reset();
        }
        sent.map_err(DitherError::Target)
    }

    /// Pixels in any order through the method.
    fn pass<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), DitherError<T::Error>> {
        let area = self.area;
        match &mut self.how {
            How::Truncate => self
                .inner
                .draw_iter(pixels.into_iter().map(|Pixel(p, c)| Pixel(p, truncate(c))))
                .map_err(DitherError::Target),
            How::Ordered(m) => {
                let m = *m;
                self.inner
                    .draw_iter(
                        pixels
                            .into_iter()
                            .map(|Pixel(p, c)| Pixel(p, dither_ordered(c, p, m))),
                    )
                    .map_err(DitherError::Target)
            }
            How::Diffuse { diffusion, filled } => {
                for pixel in pixels {
                    Self::diffuse(self.inner, area, diffusion, filled, pixel)?;
                }
                Ok(())
            }
        }
    }
}

impl<T: DrawTarget> Dimensions for Dither<'_, '_, T> {
    fn bounding_box(&self) -> Rectangle {
        self.inner.bounding_box()
    }
}

impl<T> DrawTarget for Dither<'_, '_, T>
where
    T: DrawTarget,
    T::Color: PanelColor,
{
    type Color = Rgb888;
    type Error = DitherError<T::Error>;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Self::Error> {
        self.pass(pixels)
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Self::Error> {
        if let How::Diffuse { diffusion, filled } = &mut self.how {
            // A whole row of the area, the one expected (the renderer's case): at once.
            let row = self.area.top_left.y + diffusion.rows_done() as i32;
            if area.size.height == 1
                && area.top_left == Point::new(self.area.top_left.x, row)
                && area.size.width == self.area.size.width
                && *filled == 0
            {
                *filled = diffusion.set_row(colors);
                return Self::row_out(self.inner, self.area, diffusion, filled);
            }
        }
        match &self.how {
            How::Truncate => self
                .inner
                .fill_contiguous(area, colors.into_iter().map(truncate))
                .map_err(DitherError::Target),
            How::Ordered(m) => {
                let m = *m;
                let pixels = area
                    .points()
                    .zip(colors)
                    .map(|(p, c)| dither_ordered(c, p, m));
                self.inner
                    .fill_contiguous(area, pixels)
                    .map_err(DitherError::Target)
            }
            How::Diffuse { .. } => {
                let pixels = area.points().zip(colors).map(|(p, c)| Pixel(p, c));
                self.pass(pixels)
            }
        }
    }

    fn fill_solid(&mut self, area: &Rectangle, color: Rgb888) -> Result<(), Self::Error> {
        match &self.how {
            How::Truncate => self
                .inner
                .fill_solid(area, truncate(color))
                .map_err(DitherError::Target),
            _ => self.fill_contiguous(area, core::iter::repeat(color)),
        }
    }
}
