//! Host (`std`) support: texture files next to a scene file, and an RGB framebuffer that
//! writes PPM and PNG.

use crate::error::TextureError;
use core::convert::Infallible;
use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use embedded_graphics::prelude::{DrawTarget, OriginDimensions, Pixel, Point, Size};
use std::path::{Path, PathBuf};

pub mod panel;
#[cfg(all(test, feature = "animate", feature = "antialias"))]
mod umbra_tests;

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

/// Binary PPM's header for an image of `size`: `P6\n{w} {h} 255\n`, the pixels follow
/// (what [`Framebuffer::write_ppm`] writes first, and a streamed PPM too).
pub fn ppm_header(size: Size) -> String {
    format!("P6\n{} {} 255\n", size.width, size.height)
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

    /// The pixels to change in place, three bytes each, rows top first.
    pub fn rgb_mut(&mut self) -> &mut [u8] {
        &mut self.rgb
    }

    /// Binary PPM: `P6\n{w} {h} 255\n` and the pixels.
    pub fn to_ppm(&self) -> Vec<u8> {
        let mut out = ppm_header(self.size()).into_bytes();
        out.extend_from_slice(&self.rgb);
        out
    }

    /// [`to_ppm`](Self::to_ppm) written to `out` without a copy of the pixels (the header,
    /// then the framebuffer itself: its bytes are the PPM's).
    pub fn write_ppm(&self, mut out: impl std::io::Write) -> std::io::Result<()> {
        out.write_all(ppm_header(self.size()).as_bytes())?;
        out.write_all(&self.rgb)?;
        out.flush()
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

impl Framebuffer {
    /// The whole image as one band (the band's drawing serves both).
    fn band(&mut self) -> Band<'_> {
        Band {
            size: Size::new(self.width, self.height),
            top: 0,
            rows: self.height as usize,
            pixels: &mut self.rgb,
        }
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
        let pixels = pixels.into_iter().map(|Pixel(p, c)| Pixel(p, c.into()));
        self.band().draw_iter(pixels)
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(
        &mut self,
        area: &embedded_graphics::primitives::Rectangle,
        colors: I,
    ) -> Result<(), Infallible> {
        let colors = colors.into_iter().map(RgbBytes::from);
        self.band().fill_contiguous(area, colors)
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

/// Rows a thread renders at a time: few enough that rows of different cost even out
/// between threads, many enough that the adaptive anti-aliasing's extra rows (the one above
/// and the one below each band) stay a small share.
const BAND_ROWS: usize = 8;

/// Rows at the end of the image that only the calling thread renders (see
/// [`Bands::take`]): about the time a helper thread takes to exit.
const CALLER_ROWS: usize = 1;

/// Bytes one thread of [`render_streamed`] gathers before handing them on: it gets every
/// band, so they go out together, a few calls (system calls, for a file) for the image
/// instead of one a band.
const STREAM_BYTES: usize = 64 * 1024;

/// The whole image rendered by `threads` threads (at least 1), each taking the next band of
/// rows from a shared queue until none is left: the same pixels as one thread, since every
/// row depends on the scene alone (an area of the image renders the image's pixels there).
/// `aa` anti-aliases (see [`crate::render::Antialias`]); `on_row` runs after each row, on
/// the thread that drew it. With more than one thread, the calling thread renders bands
/// too, and each new thread is pinned (on Linux) to a core other than the calling thread's
/// when there are at least as many cores.
///
/// The library's row API is all it needs: a firmware author with two cores (an RP2040)
/// splits rows the same way, each core rendering its own areas into the panel.
pub fn render_parallel<S: crate::Scalar, const OBJECTS: usize>(
    renderer: &crate::render::Renderer<'_, S, OBJECTS>,
    threads: usize,
    aa: Option<crate::render::Antialias>,
    on_row: impl Fn(crate::render::RowDone) + Sync,
) -> Result<Framebuffer, crate::render::RenderError<Infallible>> {
    let size = renderer.size();
    let mut image = Framebuffer::new(size);
    let never_written = |_: usize, _: &mut [u8]| Ok::<(), Infallible>(());
    match render_bands(
        renderer,
        threads,
        aa,
        on_row,
        Some(&mut image.rgb),
        never_written,
        || {},
    ) {
        Ok(()) => Ok(image),
        Err(StreamError::Render(e)) => Err(e),
        Err(StreamError::Write(never)) => match never {},
    }
}

/// The image of [`render_parallel`], handed on as it is made instead of kept:
/// `write(first_row, pixels)` gets whole rows, three bytes a pixel, from a buffer that each
/// thread owns and reuses (64 KB with one thread, eight rows with more), and may change
/// them (a panel's colour depth). The calls come from the rendering threads in no fixed
/// order; each row comes once.
///
/// No image in memory: the host tracer writes a PPM this way with `pwrite`, which saves
/// faulting in a framebuffer (225 page faults for 640x480, and the copy: 1 to 4 % of the
/// render) and lets an image of any size render in a few hundred kilobytes.
///
/// ```
/// use microray::host::{render_streamed, HostRenderer, HostScene};
/// use microray::parse::{no_textures, parse_scene_into};
/// use std::sync::Mutex;
///
/// let mut scene = HostScene::<f64>::empty();
/// parse_scene_into(b"camera c { pixeldim 8 6 worlddim 8 6 viewpoint 4 3 3 }", no_textures, &mut scene)?;
/// let renderer = HostRenderer::new(&scene);
/// let image = Mutex::new(vec![1u8; 8 * 6 * 3]);
/// render_streamed(&renderer, 2, None, |_| {}, |row, pixels| {
///     let mut image = image.lock().map_err(|_| "poisoned")?;
///     image[row * 8 * 3..][..pixels.len()].copy_from_slice(pixels);
///     Ok::<(), &str>(())
/// })?;
/// assert!(image.lock().unwrap().iter().all(|&c| c == 0)); // no object: black
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn render_streamed<S: crate::Scalar, const OBJECTS: usize, E: Send>(
    renderer: &crate::render::Renderer<'_, S, OBJECTS>,
    threads: usize,
    aa: Option<crate::render::Antialias>,
    on_row: impl Fn(crate::render::RowDone) + Sync,
    write: impl Fn(usize, &mut [u8]) -> Result<(), E> + Sync,
) -> Result<(), StreamError<E>> {
    render_bands(renderer, threads, aa, on_row, None, write, || {})
}

/// The image of [`render_streamed`], handed to `write` in order, top row first, one call
/// at a time: for an encoder that takes rows in order (PNG, a pipe). A thread whose rows
/// come before others' waits until theirs are written, so what is held at any time is a
/// few bands a thread (64 KB with one thread), however tall the image.
///
/// ```
/// use microray::host::{render_in_order, HostRenderer, HostScene};
/// use microray::parse::{no_textures, parse_scene_into};
///
/// let mut scene = HostScene::<f64>::empty();
/// parse_scene_into(b"camera c { pixeldim 8 60 worlddim 8 6 viewpoint 4 3 3 }", no_textures, &mut scene)?;
/// let mut rows = Vec::new();
/// render_in_order(&HostRenderer::new(&scene), 2, None, |_| {}, |top, pixels| {
///     rows.push((top, pixels.len() / (8 * 3)));
///     Ok::<(), std::io::Error>(())
/// })?;
/// // Every row once, in order.
/// let mut next = 0;
/// for (top, count) in rows {
///     assert_eq!(top, next);
///     next += count;
/// }
/// assert_eq!(next, 60);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn render_in_order<S: crate::Scalar, const OBJECTS: usize, E: Send>(
    renderer: &crate::render::Renderer<'_, S, OBJECTS>,
    threads: usize,
    aa: Option<crate::render::Antialias>,
    on_row: impl Fn(crate::render::RowDone) + Sync,
    write: impl FnMut(usize, &mut [u8]) -> Result<(), E> + Send,
) -> Result<(), StreamError<E>> {
    let turns = Turns {
        state: std::sync::Mutex::new(Turn {
            next: 0,
            failed: false,
            write,
        }),
        changed: std::sync::Condvar::new(),
    };
    let row_bytes = renderer.size().width as usize * 3;
    render_bands(
        renderer,
        threads,
        aa,
        on_row,
        None,
        |top, pixels: &mut [u8]| turns.write(top, pixels, row_bytes),
        || turns.fail(),
    )
}

/// Whose rows [`render_in_order`] writes next.
struct Turns<W> {
    state: std::sync::Mutex<Turn<W>>,
    changed: std::sync::Condvar,
}

struct Turn<W> {
    /// The first row not yet written.
    next: usize,
    /// A thread failed: the rows after its own will never come.
    failed: bool,
    write: W,
}

impl<W> Turns<W> {
    /// Writes rows from `top` on once every row before them is written. After a failure
    /// elsewhere, writes nothing (that thread's error is the one reported).
    fn write<E>(&self, top: usize, pixels: &mut [u8], row_bytes: usize) -> Result<(), E>
    where
        W: FnMut(usize, &mut [u8]) -> Result<(), E>,
    {
        let Ok(mut turn) = self.state.lock() else {
            return Ok(());
        };
        while turn.next != top && !turn.failed {
            turn = match self.changed.wait(turn) {
                Ok(turn) => turn,
                Err(_) => return Ok(()),
            };
        }
        if turn.failed {
            return Ok(());
        }
        let written = (turn.write)(top, pixels);
        match written {
            Ok(()) => turn.next += pixels.len() / row_bytes.max(1),
            Err(_) => turn.failed = true,
        }
        self.changed.notify_all();
        written
    }

    /// A thread stopped short: no thread waits for its rows.
    fn fail(&self) {
        if let Ok(mut turn) = self.state.lock() {
            turn.failed = true;
        }
        self.changed.notify_all();
    }
}

/// Why [`render_streamed`] stopped short.
#[derive(Debug)]
pub enum StreamError<E> {
    /// The rendering failed.
    Render(crate::render::RenderError<Infallible>),
    /// Handing pixels on failed.
    Write(E),
}

impl<E: core::fmt::Display> core::fmt::Display for StreamError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            StreamError::Render(e) => write!(f, "{e}"),
            StreamError::Write(e) => write!(f, "{e}"),
        }
    }
}

impl<E: core::fmt::Debug + core::fmt::Display> core::error::Error for StreamError<E> {}

/// Renders the image on `threads` threads into `image` (a framebuffer's pixels) or, with
/// `None`, into each thread's own buffer, handed to `write` when full or no longer followed
/// by the band taken next. A thread that fails calls `on_fail` (before its error is
/// returned), so that no other waits for its rows.
fn render_bands<S: crate::Scalar, const OBJECTS: usize, E: Send>(
    renderer: &crate::render::Renderer<'_, S, OBJECTS>,
    threads: usize,
    aa: Option<crate::render::Antialias>,
    on_row: impl Fn(crate::render::RowDone) + Sync,
    image: Option<&mut [u8]>,
    write: impl Fn(usize, &mut [u8]) -> Result<(), E> + Sync,
    on_fail: impl Fn() + Sync,
) -> Result<(), StreamError<E>> {
    use crate::render::{AaPixel, Antialias};
    use core::ops::ControlFlow;
    use embedded_graphics::primitives::Rectangle;
    let size = renderer.size();
    let (width, height) = (size.width as usize, size.height as usize);
    let row_bytes = width * 3;
    if row_bytes == 0 || height == 0 {
        return Ok(());
    }
    let threads = threads.clamp(1, height.div_ceil(BAND_ROWS));
    let queue = std::sync::Mutex::new(Bands {
        top: 0,
        height,
        row_bytes,
        rest: image,
        // The adaptive anti-aliasing renders a row above and below each band: bands of a
        // fixed size keep that share small.
        shrink: threads > 1 && !matches!(aa, Some(Antialias::Adaptive { .. })),
        threads,
    });
    let next_band = |caller: bool| queue.lock().ok().and_then(|mut bands| bands.take(caller));
    // Threads take turns at the queue, so one thread's bands seldom follow each other: a
    // band's room is enough (and a fifth of the pages to fault in).
    let own_rows = match threads {
        1 => (STREAM_BYTES / row_bytes).max(BAND_ROWS),
        _ => BAND_ROWS,
    };
    let work_until_done = |caller: bool| -> Result<(), StreamError<E>> {
        let mut row = vec![RgbBytes::BLACK; width];
        let mut aa_buffer = match aa {
            Some(_) => vec![AaPixel::NEW; Antialias::buffer_len(size.width as u16)],
            None => Vec::new(),
        };
        // The thread's own rows not yet handed on: the first, and how many.
        let mut own: Vec<u8> = Vec::new();
        let (mut own_top, mut own_held) = (0, 0);
        while let Some((top, rows, place)) = next_band(caller) {
            let pixels = match place {
                Some(pixels) => pixels,
                None => {
                    if own_held > 0 && (own_top + own_held != top || own_held + rows > own_rows) {
                        let held = own.get_mut(..own_held * row_bytes).unwrap_or_default();
                        write(own_top, held).map_err(StreamError::Write)?;
                        own_held = 0;
                    }
                    if own_held == 0 {
                        own_top = top;
                        own.resize(own_rows.min(height) * row_bytes, 0);
                    }
                    let at = own_held * row_bytes;
                    own_held += rows;
                    own.get_mut(at..at + rows * row_bytes).unwrap_or_default()
                }
            };
            let mut band = Band {
                size,
                top,
                rows,
                pixels,
            };
            let area = Rectangle::new(
                Point::new(0, top as i32),
                Size::new(size.width, rows as u32),
            );
            let report = |done| {
                on_row(done);
                ControlFlow::Continue(())
            };
            match aa {
                Some(aa) => {
                    renderer.render_antialiased(&mut band, area, aa, &mut aa_buffer, report)
                }
                None => renderer.render_area(&mut band, area, &mut row, report),
            }
            .map_err(StreamError::Render)?;
        }
        if let Some(held) = own
            .get_mut(..own_held * row_bytes)
            .filter(|h| !h.is_empty())
        {
            write(own_top, held).map_err(StreamError::Write)?;
        }
        Ok(())
    };
    let work = |caller: bool| {
        let done = work_until_done(caller);
        if done.is_err() {
            on_fail();
        }
        done
    };
    if threads == 1 {
        return work(true);
    }
    // The calling thread renders too, and each helper moves to a core of its own (when
    // there is a core for each) as soon as it starts: a new thread is queued on the core of
    // the thread that made it, where it would wait 1 to 3 ms (measured) for the scheduler
    // to move one of the two. Yielding once a helper lets it start and move at once.
    let cores = cores::others(threads - 1);
    std::thread::scope(|scope| {
        let helpers: Vec<_> = (1..threads)
            .map(|k| {
                let core = cores.get(k - 1).copied();
                scope.spawn(move || {
                    if let Some(core) = core {
                        cores::move_to(core);
                    }
                    work(false)
                })
            })
            .collect();
        for _ in &helpers {
            std::thread::yield_now();
        }
        let mut result = work(true);
        for helper in helpers {
            match helper.join() {
                Ok(done) => result = result.and(done),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        }
        result
    })
}

/// Where the render threads run.
#[cfg(target_os = "linux")]
mod cores {
    use nix::sched::{CpuSet, sched_getaffinity, sched_getcpu, sched_setaffinity};
    use nix::unistd::Pid;

    /// The cores this thread may run on, but for the one it is on, if there are at least
    /// `helpers` of them (otherwise none: the threads share cores, and the scheduler
    /// places them).
    pub(super) fn others(helpers: usize) -> Vec<usize> {
        let this_thread = Pid::from_raw(0);
        let (Ok(allowed), Ok(here)) = (sched_getaffinity(this_thread), sched_getcpu()) else {
            return Vec::new();
        };
        let others: Vec<usize> = (0..CpuSet::count())
            .filter(|&core| core != here && allowed.is_set(core).unwrap_or(false))
            .collect();
        if others.len() >= helpers {
            others
        } else {
            Vec::new()
        }
    }

    /// Moves this thread to `core` for good.
    pub(super) fn move_to(core: usize) {
        let mut set = CpuSet::new();
        if set.set(core).is_ok() {
            // A thread that cannot move still renders, on a core it shares.
            let _ = sched_setaffinity(Pid::from_raw(0), &set);
        }
    }
}

/// Where the render threads run: where the scheduler puts them.
#[cfg(not(target_os = "linux"))]
mod cores {
    pub(super) fn others(_helpers: usize) -> Vec<usize> {
        Vec::new()
    }

    pub(super) fn move_to(_core: usize) {}
}

/// The rows not yet rendered, handed out a band at a time.
struct Bands<'p> {
    /// The first row not handed out.
    top: usize,
    height: usize,
    row_bytes: usize,
    /// The framebuffer's pixels from `top` on, if there is a framebuffer.
    rest: Option<&'p mut [u8]>,
    /// Whether the last bands are smaller, so that the threads finish together: a band of
    /// `BAND_ROWS` taken last by one thread while the others have nothing left is a
    /// sixtieth of a 480-row image that only one core works on.
    shrink: bool,
    threads: usize,
}

impl<'p> Bands<'p> {
    /// The next band for the calling thread (`caller`) or a helper: its first row, its
    /// rows and, with a framebuffer, its pixels. The last [`CALLER_ROWS`] are the calling
    /// thread's, so that a helper ends, and its thread exits, while the calling thread
    /// renders them, not while it waits to join.
    fn take(&mut self, caller: bool) -> Option<(usize, usize, Option<&'p mut [u8]>)> {
        let left = self.height.checked_sub(self.top).filter(|&n| n > 0)?;
        if self.shrink && !caller && left <= CALLER_ROWS {
            return None;
        }
        let rows = if self.shrink {
            (left / (4 * self.threads)).clamp(1, BAND_ROWS)
        } else {
            BAND_ROWS.min(left)
        };
        let top = self.top;
        self.top += rows;
        let pixels = match self.rest.take() {
            Some(rest) => {
                let (band, rest) = rest.split_at_mut((rows * self.row_bytes).min(rest.len()));
                self.rest = Some(rest);
                Some(band)
            }
            None => None,
        };
        Some((top, rows, pixels))
    }
}

/// A band of rows of a [`Framebuffer`], drawn into in the image's coordinates (pixels
/// outside it are dropped).
struct Band<'a> {
    size: Size,
    top: usize,
    rows: usize,
    pixels: &'a mut [u8],
}

impl Band<'_> {
    /// The bytes of pixel `(x, y)` of the image, if it lies in the band.
    fn at(&mut self, x: i32, y: i32) -> Option<&mut [u8]> {
        let (x, y) = (usize::try_from(x).ok()?, usize::try_from(y).ok()?);
        let width = self.size.width as usize;
        if x >= width || y < self.top || y >= self.top + self.rows {
            return None;
        }
        let at = ((y - self.top) * width + x) * 3;
        self.pixels.get_mut(at..at + 3)
    }
}

impl OriginDimensions for Band<'_> {
    fn size(&self) -> Size {
        self.size
    }
}

/// A pixel's bytes as the image holds them: the band's colour, so that the renderer's rows
/// are copied in as they are (through an [`Rgb888`], each pixel was packed into a word and
/// taken apart again: 10 instructions a pixel).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct RgbBytes([u8; 3]);

impl RgbBytes {
    const BLACK: Self = Self([0; 3]);
}

impl embedded_graphics::pixelcolor::PixelColor for RgbBytes {
    type Raw = ();
}

impl From<Rgb888> for RgbBytes {
    #[inline]
    fn from(c: Rgb888) -> Self {
        Self([c.r(), c.g(), c.b()])
    }
}

impl DrawTarget for Band<'_> {
    type Color = RgbBytes;
    type Error = Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<RgbBytes>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Infallible> {
        for Pixel(p, RgbBytes(c)) in pixels {
            if let Some(slot) = self.at(p.x, p.y) {
                slot.copy_from_slice(&c);
            }
        }
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = RgbBytes>>(
        &mut self,
        area: &embedded_graphics::primitives::Rectangle,
        colors: I,
    ) -> Result<(), Infallible> {
        // The renderer's rows: one slice, no per-pixel look-up.
        let start = area.top_left;
        let inside = area.size.height == 1
            && start.x >= 0
            && (start.x as u32).saturating_add(area.size.width) <= self.size.width;
        match self.at(start.x, start.y) {
            Some(_) if inside => {
                let width = self.size.width as usize;
                let at = ((start.y as usize - self.top) * width + start.x as usize) * 3;
                let end = at + area.size.width as usize * 3;
                if let Some(run) = self.pixels.get_mut(at..end) {
                    for (slot, RgbBytes(c)) in run.chunks_exact_mut(3).zip(colors) {
                        slot.copy_from_slice(&c);
                    }
                }
                Ok(())
            }
            _ => self.draw_iter(
                embedded_graphics::prelude::PointsIter::points(area)
                    .zip(colors)
                    .map(|(p, c)| Pixel(p, c)),
            ),
        }
    }
}
