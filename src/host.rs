//! Host (`std`) support: texture files next to a scene file, and an RGB framebuffer that
//! writes PPM and PNG.

use crate::error::TextureError;
use core::convert::Infallible;
use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use embedded_graphics::prelude::{DrawTarget, OriginDimensions, Pixel, Point, Size};
use std::path::{Path, PathBuf};

/// A texture resolver that reads files relative to `scene_dir`, the scene file's folder.
///
/// Each file is read once and kept for the rest of the process (the scene borrows the bytes
/// for `'static`), which suits a command-line run; a long-running program that reloads
/// scenes should supply its own resolver.
pub fn texture_files(scene_dir: &Path) -> impl FnMut(&str) -> Result<&'static [u8], TextureError> {
    let dir: PathBuf = scene_dir.to_path_buf();
    move |filename: &str| match std::fs::read(dir.join(filename)) {
        Ok(bytes) => Ok(Box::leak(bytes.into_boxed_slice())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(TextureError::NotFound),
        Err(_) => Err(TextureError::Unreadable),
    }
}

/// Objects a [`HostScene`] holds.
pub const HOST_OBJECTS: usize = 256;

/// The scene type the host tracer uses: room for large scenes and wide images.
pub type HostScene<'t, S> = crate::Scene<'t, S, HOST_OBJECTS, 64, 32, 16, 8192>;

/// The renderer of a [`HostScene`].
pub type HostRenderer<'s, S> = crate::render::Renderer<'s, S, HOST_OBJECTS>;

/// An RGB image in memory, rows top first: the host tracer's draw target.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Framebuffer {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Framebuffer {
    /// A black image.
    pub fn new(size: Size) -> Self {
        let bytes = size.width as usize * size.height as usize * 3;
        Self {
            width: size.width,
            height: size.height,
            rgb: vec![0; bytes],
        }
    }

    /// The pixels, three bytes each, rows top first.
    pub fn rgb(&self) -> &[u8] {
        &self.rgb
    }

    /// Binary PPM: `P6\n{w} {h} 255\n` and the pixels.
    pub fn to_ppm(&self) -> Vec<u8> {
        let mut out = format!("P6\n{} {} 255\n", self.width, self.height).into_bytes();
        out.extend_from_slice(&self.rgb);
        out
    }

    /// PNG, 8-bit RGB.
    #[cfg(feature = "std")]
    pub fn to_png(&self) -> Result<Vec<u8>, png::EncodingError> {
        let mut out = Vec::new();
        let mut encoder = png::Encoder::new(&mut out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(&self.rgb)?;
        writer.finish()?;
        Ok(out)
    }
}

impl OriginDimensions for Framebuffer {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl DrawTarget for Framebuffer {
    type Color = Rgb888;
    type Error = Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Infallible> {
        for Pixel(point, color) in pixels {
            let (Ok(x), Ok(y)) = (u32::try_from(point.x), u32::try_from(point.y)) else {
                continue;
            };
            if x < self.width && y < self.height {
                let at = (y as usize * self.width as usize + x as usize) * 3;
                if let Some(slot) = self.rgb.get_mut(at..at + 3) {
                    slot.copy_from_slice(&[color.r(), color.g(), color.b()]);
                }
            }
        }
        Ok(())
    }
}

/// Reads a binary PPM into a framebuffer (for comparing with reference images).
pub fn read_ppm(bytes: &[u8]) -> Option<Framebuffer> {
    let (width, height, pixels) = crate::texture::decode_ppm(bytes).ok()?;
    Some(Framebuffer {
        width: u32::from(width),
        height: u32::from(height),
        rgb: pixels.to_vec(),
    })
}

/// How an image differs from a reference, pixel by pixel: the error measures of the parity
/// tests and the benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Difference {
    /// Pixels compared.
    pub pixels: usize,
    /// Pixels equal in every channel.
    pub identical: usize,
    /// Pixels no channel of which is off by more than 1.
    pub within_one: usize,
    /// The largest channel difference.
    pub largest: u8,
    /// The sum of squared channel differences.
    pub squared: f64,
}

impl Difference {
    /// Compares two RGB images (three bytes a pixel) of the same size, leaving out the
    /// pixels for which `skip(index)` holds.
    pub fn between(reference: &[u8], other: &[u8], skip: impl Fn(usize) -> bool) -> Self {
        let mut d = Self::default();
        for (i, (a, b)) in reference.chunks(3).zip(other.chunks(3)).enumerate() {
            if skip(i) {
                continue;
            }
            let worst = a
                .iter()
                .zip(b)
                .map(|(x, y)| x.abs_diff(*y))
                .max()
                .unwrap_or(0);
            d.pixels += 1;
            d.identical += usize::from(worst == 0);
            d.within_one += usize::from(worst <= 1);
            d.largest = d.largest.max(worst);
            d.squared += a
                .iter()
                .zip(b)
                .map(|(x, y)| f64::from(x.abs_diff(*y)).powi(2))
                .sum::<f64>();
        }
        d
    }

    /// Identical pixels, in percent.
    pub fn identical_percent(&self) -> f64 {
        100.0 * self.identical as f64 / self.pixels.max(1) as f64
    }

    /// Pixels within ±1 in every channel, in percent.
    pub fn within_one_percent(&self) -> f64 {
        100.0 * self.within_one as f64 / self.pixels.max(1) as f64
    }

    /// Peak signal-to-noise ratio in dB over all channels (infinite for identical images).
    pub fn psnr(&self) -> f64 {
        let mse = self.squared / (3 * self.pixels.max(1)) as f64;
        if mse == 0.0 {
            f64::INFINITY
        } else {
            10.0 * (255.0f64 * 255.0 / mse).log10()
        }
    }
}

/// The object each pixel sees, rows top first (the object-id view).
pub fn object_ids<S: crate::Scalar, const OBJECTS: usize>(
    renderer: &crate::render::Renderer<'_, S, OBJECTS>,
) -> Vec<Option<usize>> {
    let size = renderer.size();
    let (width, height) = (
        u16::try_from(size.width).unwrap_or(0),
        u16::try_from(size.height).unwrap_or(0),
    );
    (0..height)
        .flat_map(|row| (0..width).map(move |x| renderer.object_at(x, row)))
        .collect()
}

/// The whole image anti-aliased by `aa` (see [`crate::render::Antialias`]).
pub fn antialiased<S: crate::Scalar, const OBJECTS: usize>(
    renderer: &crate::render::Renderer<'_, S, OBJECTS>,
    aa: crate::render::Antialias,
) -> Result<Framebuffer, crate::render::RenderError<Infallible>> {
    let size = renderer.size();
    let mut image = Framebuffer::new(size);
    let width = u16::try_from(size.width).unwrap_or(u16::MAX);
    let mut buffer = vec![crate::render::AaPixel::NEW; crate::render::Antialias::buffer_len(width)];
    let all = embedded_graphics::primitives::Rectangle::new(Point::zero(), size);
    renderer.render_antialiased(&mut image, all, aa, &mut buffer, |_| {
        core::ops::ControlFlow::Continue(())
    })?;
    Ok(image)
}
