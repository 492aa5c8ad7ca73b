//! microray on an emulated microcontroller (QEMU mps2-an386 or microbit).
//!
//! Renders every embedded scene through the `DrawTarget` path into a target that writes each
//! row to a file over semihosting (`<scene>.rgb` in QEMU's working directory), and reports on
//! the semihosting console how deep the stack went. The render of each frame is bracketed by
//! calls to marker functions (`microray_count_start`, `_stop`, `_frame`) at which the
//! project's QEMU plugin reads its instruction counter; writing a row stops the count.
#![no_std]
#![no_main]

// The minimal build loads it compiled by build.rs, and uses only its name.
#[cfg(feature = "antialias")]
mod aa_modes;
#[cfg_attr(not(feature = "full"), allow(dead_code))]
mod basic_scene;
#[cfg(feature = "panels")]
mod panels;
#[cfg(feature = "full")]
mod static_scene;

use console::Part::{N, T};
use core::ops::ControlFlow;
use core::sync::atomic::{AtomicUsize, Ordering};
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, syscall};
use embedded_graphics::pixelcolor::{PixelColor, Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::Point;
use embedded_graphics::prelude::{DrawTarget, OriginDimensions, Pixel, PointsIter, Size};
use embedded_graphics::primitives::Rectangle;
use microray::Scene;
#[cfg(feature = "full")]
use microray::error::TextureError;
#[cfg(feature = "full")]
use microray::parse::parse_scene_into;
use microray::render::Renderer;
#[cfg(not(feature = "full"))]
use microray::texture::no_textures;

#[cfg(feature = "f32")]
type Number = f32;
#[cfg(feature = "fixed")]
type Number = microray::scalar::I16F16;

// Without `full` there are no scene files (no parser to read them).
#[cfg_attr(not(feature = "full"), allow(dead_code))]
mod scenes {
    pub struct SceneFile {
        pub name: &'static str,
        pub text: &'static str,
        pub textures: &'static [(&'static str, &'static [u8])],
    }
    include!(concat!(env!("OUT_DIR"), "/scenes.rs"));
}
#[cfg(feature = "animate")]
use scenes::ANIMATE;
#[cfg(feature = "full")]
use scenes::RUN_STATIC;
#[cfg(feature = "full")]
use scenes::SCENES;
use scenes::{
    ANTIALIAS, COMPARE_PLAN, DITHER, HEIGHT, LIGHTS, MATERIALS, OBJECTS, PROGRESSIVE, RUN_BASIC,
    SKIPPED, TEXTURES, WIDTH,
};

/// Capacities that hold every embedded scene and no more (build.rs counts them, and leaves
/// out scenes with more objects than the machine has room for); files up to 800 pixels wide
/// load (they are rendered at `WIDTH` x `HEIGHT`).
type FirmwareScene = Scene<'static, Number, OBJECTS, MATERIALS, LIGHTS, TEXTURES, 800>;

// The markers: the QEMU plugin reads its counters when execution reaches their addresses.
// Inline assembly is a side effect the compiler keeps, and a different number of NOPs keeps
// the three from being merged into one address.

/// Counting starts (or resumes after a row was written).
#[unsafe(no_mangle)]
#[inline(never)]
pub extern "C" fn microray_count_start() {
    cortex_m::asm::nop();
}

/// Counting pauses.
#[unsafe(no_mangle)]
#[inline(never)]
pub extern "C" fn microray_count_stop() {
    cortex_m::asm::nop();
    cortex_m::asm::nop();
}

/// A frame is complete: the plugin reports its count.
#[unsafe(no_mangle)]
#[inline(never)]
pub extern "C" fn microray_count_frame() {
    cortex_m::asm::nop();
    cortex_m::asm::nop();
    cortex_m::asm::nop();
}

/// A colour as the three bytes the output file takes: the row buffer in the output's own
/// format (an `Rgb888` takes four bytes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Rgb([u8; 3]);

impl PixelColor for Rgb {
    type Raw = ();
}

impl From<Rgb888> for Rgb {
    fn from(c: Rgb888) -> Self {
        Self([c.r(), c.g(), c.b()])
    }
}

/// Pixels written to the output file at a time: the write buffer is small, the
/// semihosting calls few.
const CHUNK: usize = 32;

/// A draw target that writes each row, as RGB bytes, to a semihosting file; as patches
/// (see [`RowFile::patches`]), each row after its place.
struct RowFile {
    handle: usize,
    /// Rows as patches (only films draw parts of the picture: no field elsewhere).
    #[cfg(feature = "animate")]
    patches: bool,
}

impl OriginDimensions for RowFile {
    fn size(&self) -> Size {
        Size::new(u32::from(WIDTH), u32::from(HEIGHT))
    }
}

impl DrawTarget for RowFile {
    type Color = Rgb;
    type Error = ();

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb>>>(&mut self, _: I) -> Result<(), ()> {
        // The renderer sends whole rows; single pixels would mean a bug.
        Err(())
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), ()> {
        microray_count_stop();
        let mut bytes = [0u8; 3 * CHUNK];
        let (mut n, mut total) = (0, 0);
        let mut result = Ok(());
        #[cfg(feature = "animate")]
        if self.patches {
            let place = [area.top_left.x, area.top_left.y, area.size.width as i32];
            for (i, v) in place.into_iter().enumerate() {
                bytes[2 * i..2 * i + 2].copy_from_slice(&(v as u16).to_le_bytes());
            }
            result = self.write(&bytes[..6]);
        }
        for c in colors {
            bytes[n..n + 3].copy_from_slice(&c.0);
            n += 3;
            if n == bytes.len() {
                result = result.and(self.write(&bytes[..n]));
                total += n;
                n = 0;
            }
        }
        result = result.and(self.write(&bytes[..n]));
        total += n;
        microray_count_start();
        if total == 3 * area.size.width as usize {
            result
        } else {
            Err(())
        }
    }
}

impl Drop for RowFile {
    fn drop(&mut self) {
        unsafe { syscall!(CLOSE, self.handle) };
    }
}

impl RowFile {
    /// Opens `<name><suffix>.rgb` for writing (the name cut to 40 bytes, the suffix to 16):
    /// every frame's file is opened here.
    fn create(name: &str, suffix: &str) -> Result<Self, &'static str> {
        let name = &name.as_bytes()[..name.len().min(40)];
        let suffix = &suffix.as_bytes()[..suffix.len().min(40)];
        // Not an array: it would be cleared first.
        let mut path = microray::heapless::Vec::<u8, 96>::new();
        for part in [name, suffix, b".rgb", b"\0"] {
            let _ = path.extend_from_slice(part);
        }
        // Mode 5 is "wb"; the length excludes the terminating NUL.
        let handle = unsafe { syscall!(OPEN, path.as_ptr(), 5, path.len() - 1) };
        if handle == usize::MAX {
            return Err("cannot open the output file");
        }
        Ok(Self {
            handle,
            #[cfg(feature = "animate")]
            patches: false,
        })
    }

    /// The same file written as patches: each row after its `x`, `y` and width (16 bits
    /// each, little-endian), for frames that draw only parts of the picture.
    #[cfg(feature = "animate")]
    fn patches(mut self) -> Self {
        self.patches = true;
        self
    }

    fn write(&self, bytes: &[u8]) -> Result<(), ()> {
        // SYS_WRITE returns the number of bytes not written.
        let left = unsafe { syscall!(WRITE, self.handle, bytes.as_ptr(), bytes.len()) };
        if left == 0 { Ok(()) } else { Err(()) }
    }
}

/// Renders a scene into `<name>.rgb`, and with `MICRORAY_FW_PLAN=compare` a second time
/// without the render plan into `<name>+noplan.rgb`. (The minimal build's one scene is
/// compiled at the firmware's size: it renders with [`render_scene`].)
#[cfg(feature = "full")]
fn render_to_file(name: &str, scene: &mut FirmwareScene) -> Result<(), &'static str> {
    scene
        .set_resolution(WIDTH, HEIGHT)
        .map_err(|_| "resolution")?;
    render_scene(name, scene)
}

/// [`render_to_file`] for a scene already at `WIDTH` x `HEIGHT`.
fn render_scene(name: &str, scene: &FirmwareScene) -> Result<(), &'static str> {
    render_frame(name, "", scene, true)?;
    if COMPARE_PLAN {
        report_frame(name, "", Ok(()));
        stack::paint();
        render_frame(name, "+noplan", scene, false)?;
    }
    if PROGRESSIVE {
        report_frame(name, "", Ok(()));
        stack::paint();
        render_progressive(name, scene)?;
    }
    if DITHER {
        report_frame(name, "", Ok(()));
        stack::paint();
        #[cfg(feature = "panels")]
        if scenes::PANEL_SCENES.contains(&name) {
            panels::render_all(name, scene)?;
        }
        render_rgb565(name, scene, false)?;
        report_frame(name, "+rgb565", Ok(()));
        stack::paint();
        render_rgb565(name, scene, true)?;
    }
    #[cfg(feature = "antialias")]
    if ANTIALIAS {
        let mut previous = "";
        for (suffix, aa) in antialiasing::MODES {
            report_frame(name, previous, Ok(()));
            stack::paint();
            antialiasing::render(name, suffix, scene, aa)?;
            previous = suffix;
        }
    }
    Ok(())
}

/// The anti-aliased frames of `MICRORAY_FW_PLAN=antialias`.
#[cfg(feature = "antialias")]
mod antialiasing {
    use super::*;
    pub use crate::aa_modes::MODES;
    use microray::render::{AaPixel, Antialias};

    /// Renders a scene anti-aliased by `aa` into `<name><suffix>.rgb`.
    #[inline(never)]
    pub fn render(
        name: &str,
        suffix: &str,
        scene: &FirmwareScene,
        aa: Antialias,
    ) -> Result<(), &'static str> {
        let file = RowFile::create(name, suffix)?;
        let mut target = file;
        let mut buffer = [AaPixel::NEW; Antialias::buffer_len(WIDTH)];
        let all = Rectangle::new(
            Point::zero(),
            Size::new(u32::from(WIDTH), u32::from(HEIGHT)),
        );
        RENDER_BASE.store(stack::depth(), Ordering::Relaxed);
        microray_count_start();
        let result =
            Renderer::new(scene).render_antialiased(&mut target, all, aa, &mut buffer, |_| {
                ControlFlow::Continue(())
            });
        microray_count_stop();
        microray_count_frame();
        result.map(|_| ()).map_err(|_| "render failed")
    }
}

/// The films of `MICRORAY_FW_PLAN=animate`.
#[cfg(feature = "animate")]
mod animating {
    use super::*;
    use microray::animation::{Animation, LastFrame};
    use microray::parse::parse_animation;
    use microray::region::Region;

    /// The most motions a film has.
    const MOTIONS: usize = 4;

    /// The most rectangles a frame's region keeps apart.
    pub const AREAS: usize = 8;

    /// Plays the film of `file` (already loaded into `scene` and rendered at the firmware's
    /// size as frame 0): each later frame `k` is rendered in its region into
    /// `<name>+i<k>.rgb` (patches), then whole into `<name>+f<k>.rgb`, each counted and
    /// reported (frame 0's report first), with a line `microray frame K region PIXELS` or
    /// `microray frame K full` after each.
    #[inline(never)]
    pub fn play(file: &scenes::SceneFile, scene: &mut FirmwareScene) -> Result<(), &'static str> {
        let animation: Option<Animation<'static, MOTIONS>> =
            parse_animation(file.text.as_bytes()).map_err(|_| "the film does not load")?;
        // What playing keeps in RAM besides the scene: the film and a frame's region.
        for (what, bytes) in [
            (
                "animation",
                core::mem::size_of::<Animation<'static, MOTIONS>>(),
            ),
            // A frame's region, and the last frame's the film keeps.
            (
                "region",
                core::mem::size_of::<Region<AREAS>>() + core::mem::size_of::<LastFrame<AREAS>>(),
            ),
        ] {
            console::line(&[T("microray size "), T(what), T(" "), N(bytes)]);
        }
        report_frame(file.name, "", Ok(()));
        console::line(&[T("microray frame 0 full")]);
        let Some(animation) = animation else {
            return Ok(());
        };
        let frames = match scenes::FRAMES {
            0 => animation.frames(),
            n => n.min(animation.frames()),
        };
        // The moving objects' last region, so each frame works out only its new one.
        let mut last = LastFrame::<AREAS>::new();
        for k in 1..frames {
            stack::paint();
            let pixels = incremental(file.name, k, &animation, scene, &mut last)?;
            let name = suffix(b'i', k);
            report_frame(file.name, core::str::from_utf8(&name).unwrap_or(""), Ok(()));
            console::line(&[
                T("microray frame "),
                N(k.into()),
                T(" region "),
                N(pixels as usize),
            ]);
            stack::paint();
            full(file.name, k, scene)?;
            let name = suffix(b'f', k);
            report_frame(file.name, core::str::from_utf8(&name).unwrap_or(""), Ok(()));
            console::line(&[T("microray frame "), N(k.into()), T(" full")]);
        }
        Ok(())
    }

    /// The suffix of frame `k`'s file: `+i7`, `+f7`.
    fn suffix(kind: u8, k: u16) -> microray::heapless::Vec<u8, 8> {
        let mut text = microray::heapless::Vec::new();
        let _ = text.extend_from_slice(&[b'+', kind]);
        let mut digits = [0u8; 5];
        let mut n = k;
        let mut len = 0;
        loop {
            digits[len] = b'0' + (n % 10) as u8;
            len += 1;
            n /= 10;
            if n == 0 {
                break;
            }
        }
        for &d in digits[..len].iter().rev() {
            let _ = text.push(d);
        }
        text
    }

    /// Frame `k` in its region: the scene moved, the region worked out, the plan rebuilt
    /// and the region's rectangles rendered, all counted. Returns the region's pixels.
    #[inline(never)]
    fn incremental(
        name: &str,
        k: u16,
        animation: &Animation<'static, MOTIONS>,
        scene: &mut FirmwareScene,
        last: &mut LastFrame<AREAS>,
    ) -> Result<u32, &'static str> {
        let suffix = suffix(b'i', k);
        let out = RowFile::create(name, core::str::from_utf8(&suffix).unwrap_or("+i"))?;
        let mut patches = out.patches();
        let mut row = [Rgb::default(); WIDTH as usize];
        RENDER_BASE.store(stack::depth(), Ordering::Relaxed);
        microray_count_start();
        let mut region = Region::<AREAS>::new(Size::new(u32::from(WIDTH), u32::from(HEIGHT)))
            .with_one_ray_a_pixel();
        let moved = animation.show_next_frame(k, scene, &mut region, last);
        let renderer = Renderer::new(&*scene);
        let mut result = moved.map_err(|_| "a frame does not load");
        for area in region.rectangles() {
            let drawn =
                renderer.render_area(&mut patches, area, &mut row, |_| ControlFlow::Continue(()));
            if drawn.is_err() {
                result = Err("render failed");
            }
        }
        microray_count_stop();
        microray_count_frame();
        result.map(|()| region.pixels())
    }

    /// Frame `k` whole (the scene already moved): the plan built and every row rendered.
    #[inline(never)]
    fn full(name: &str, k: u16, scene: &FirmwareScene) -> Result<(), &'static str> {
        let suffix = suffix(b'f', k);
        render_frame(
            name,
            core::str::from_utf8(&suffix).unwrap_or("+f"),
            scene,
            true,
        )
    }
}

/// A draw target that writes each row of a panel (Rgb565, or any format with the `panels`
/// feature), expanded back to RGB bytes, to a semihosting file. The colours are pulled (and
/// so dithered) while counting; only the expansion and the writes are not counted.
struct PanelFile<C> {
    out: RowFile,
    expand: fn(C) -> Rgb888,
}

impl<C> OriginDimensions for PanelFile<C> {
    fn size(&self) -> Size {
        Size::new(u32::from(WIDTH), u32::from(HEIGHT))
    }
}

impl<C: PixelColor> DrawTarget for PanelFile<C> {
    type Color = C;
    type Error = ();

    fn draw_iter<I: IntoIterator<Item = Pixel<C>>>(&mut self, _: I) -> Result<(), ()> {
        Err(())
    }

    fn fill_contiguous<I: IntoIterator<Item = C>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), ()> {
        let mut pulled = [None; CHUNK];
        let (mut n, mut total) = (0, 0);
        let mut result = Ok(());
        let (out, expand) = (&self.out, self.expand);
        let flush = |pulled: &[Option<C>]| {
            microray_count_stop();
            let mut bytes = [0u8; 3 * CHUNK];
            for (i, c) in pulled.iter().flatten().enumerate() {
                let c = expand(*c);
                bytes[3 * i..3 * i + 3].copy_from_slice(&[c.r(), c.g(), c.b()]);
            }
            let written = out.write(&bytes[..3 * pulled.len()]);
            microray_count_start();
            written
        };
        for c in colors {
            pulled[n] = Some(c);
            n += 1;
            if n == CHUNK {
                result = result.and(flush(&pulled));
                total += n;
                n = 0;
            }
        }
        result = result.and(flush(&pulled[..n]));
        total += n;
        if total == area.size.width as usize {
            result
        } else {
            Err(())
        }
    }
}

/// Renders a scene into an Rgb565 target through `Rgb565Dither`, dithering into
/// `<name>+dither.rgb` or truncating into `<name>+rgb565.rgb`.
#[inline(never)]
fn render_rgb565(name: &str, scene: &FirmwareScene, dither: bool) -> Result<(), &'static str> {
    let suffix = if dither { "+dither" } else { "+rgb565" };
    let file = RowFile::create(name, suffix)?;
    let mut panel = PanelFile::<Rgb565> {
        out: file,
        expand: Rgb888::from,
    };
    let all = Rectangle::new(
        Point::zero(),
        Size::new(u32::from(WIDTH), u32::from(HEIGHT)),
    );
    let renderer = Renderer::new(scene);
    // One target type for both frames, so that both run the same code but the conversion.
    let mut converting = if dither {
        microray::dither::Rgb565Dither::new(&mut panel)
    } else {
        microray::dither::Rgb565Dither::truncating(&mut panel)
    };
    let mut row = [Rgb888::BLACK; WIDTH as usize];
    microray_count_start();
    let result = renderer.render_area(
        &mut converting,
        all,
        &mut row,
        |_| ControlFlow::Continue(()),
    );
    microray_count_stop();
    microray_count_frame();
    result.map(|_| ()).map_err(|_| "render failed")
}

/// A frame in RAM for the progressive order's blocks (a panel takes them directly); its
/// writes are not counted, as the plain frame's row output is not.
struct Frame<'f> {
    pixels: &'f mut [Rgb],
}

impl OriginDimensions for Frame<'_> {
    fn size(&self) -> Size {
        Size::new(u32::from(WIDTH), u32::from(HEIGHT))
    }
}

impl DrawTarget for Frame<'_> {
    type Color = Rgb;
    type Error = ();

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb>>>(&mut self, pixels: I) -> Result<(), ()> {
        // The pixels are shaded before the call (the renderer's row buffer): only the
        // output is here, not counted, as the other calls' is not.
        microray_count_stop();
        for Pixel(p, c) in pixels {
            if let Some(slot) = self
                .pixels
                .get_mut(p.y as usize * WIDTH as usize + p.x as usize)
            {
                *slot = c;
            }
        }
        microray_count_start();
        Ok(())
    }

    fn fill_solid(&mut self, area: &Rectangle, color: Rgb) -> Result<(), ()> {
        microray_count_stop();
        for p in area.points() {
            if let Some(slot) = self
                .pixels
                .get_mut(p.y as usize * WIDTH as usize + p.x as usize)
            {
                *slot = color;
            }
        }
        microray_count_start();
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), ()> {
        microray_count_stop();
        for (p, c) in area.points().zip(colors) {
            if let Some(slot) = self
                .pixels
                .get_mut(p.y as usize * WIDTH as usize + p.x as usize)
            {
                *slot = c;
            }
        }
        microray_count_start();
        Ok(())
    }
}

/// Renders a scene in the progressive order into a frame in RAM: the first pass counted as
/// `<name>+preview`, the other three as `<name>+progressive`; the final frame goes to both
/// files.
#[inline(never)]
fn render_progressive(name: &str, scene: &FirmwareScene) -> Result<(), &'static str> {
    let mut pixels = [Rgb::default(); WIDTH as usize * HEIGHT as usize];
    let mut frame = Frame {
        pixels: &mut pixels,
    };
    let mut row = [Rgb::default(); WIDTH as usize];
    let renderer = Renderer::new(scene);
    microray_count_start();
    let first = renderer.render_pass(&mut frame, &mut row, 0);
    microray_count_stop();
    microray_count_frame();
    report_frame(name, "+preview", first.map_err(|_| "render failed"));
    microray_count_start();
    let mut rest = Ok(());
    for pass in 1..microray::render::BLOCKS.len() {
        rest = rest.and(renderer.render_pass(&mut frame, &mut row, pass));
    }
    microray_count_stop();
    microray_count_frame();
    for suffix in ["+preview", "+progressive"] {
        let file = RowFile::create(name, suffix)?;
        let out = file;
        for line in pixels.chunks(CHUNK) {
            let mut bytes = [0u8; 3 * CHUNK];
            for (i, c) in line.iter().enumerate() {
                bytes[3 * i..3 * i + 3].copy_from_slice(&c.0);
            }
            out.write(&bytes[..3 * line.len()])
                .map_err(|()| "cannot write the output file")?;
        }
    }
    rest.map_err(|_| "render failed")
}

#[inline(never)]
fn render_frame(
    name: &str,
    suffix: &str,
    scene: &FirmwareScene,
    planned: bool,
) -> Result<(), &'static str> {
    let file = RowFile::create(name, suffix)?;
    let mut target = file;
    let mut row = [Rgb::default(); WIDTH as usize];
    let all = Rectangle::new(
        Point::zero(),
        Size::new(u32::from(WIDTH), u32::from(HEIGHT)),
    );
    RENDER_BASE.store(stack::depth(), Ordering::Relaxed);
    microray_count_start();
    // One renderer in this frame, changed in place (its copies sit under the render's calls).
    let mut renderer = Renderer::new(scene);
    renderer.set_plan(planned);
    let result = renderer.render_area(&mut target, all, &mut row, |_| ControlFlow::Continue(()));
    microray_count_stop();
    microray_count_frame();
    result.map(|_| ()).map_err(|_| "render failed")
}

/// Reports the last frame of a scene: `+noplan` is the frame without the plan.
fn report(name: &str, result: Result<(), &str>) {
    let suffix = if COMPARE_PLAN {
        "+noplan"
    } else if PROGRESSIVE {
        "+progressive"
    } else if DITHER {
        "+dither"
    } else if ANTIALIAS {
        "+adaptive"
    } else {
        ""
    };
    report_frame(name, suffix, result);
}

/// The peak stack of parsing the last scene file (0 for scenes in source): the stack is
/// painted again before rendering, so that each is measured alone.
static PARSE_PEAK: AtomicUsize = AtomicUsize::new(0);

/// The stack already in use when the renderer is called (the scene, the harness's frames,
/// the row buffer and the output's), so that the renderer's own share shows.
static RENDER_BASE: AtomicUsize = AtomicUsize::new(0);

#[inline(never)]
fn report_frame(name: &str, suffix: &str, result: Result<(), &str>) {
    let render = stack::peak();
    let parse = PARSE_PEAK.load(Ordering::Relaxed);
    PARSE_PEAK.store(0, Ordering::Relaxed);
    match result {
        Ok(()) => console::line(&[
            T("microray scene "),
            T(name),
            T(suffix),
            T(" stack "),
            N(render.max(parse)),
            T(" parse "),
            N(parse),
            T(" render "),
            N(render),
            T(" renderer "),
            N(render.saturating_sub(RENDER_BASE.load(Ordering::Relaxed))),
        ]),
        Err(why) => console::line(&[
            T("microray scene "),
            T(name),
            T(suffix),
            T(" error "),
            T(why),
        ]),
    }
}

/// The RAM of the parts a render keeps on the stack, and of one slot of each of the
/// scene's capacities, for the xtask's table (spec0's RAM: the full build).
#[cfg(feature = "full")]
#[inline(never)]
fn report_sizes() {
    use core::mem::size_of;
    use microray::{Light, Material, Object, Texture, shade::RowShading};
    let sizes = [
        ("scene", size_of::<FirmwareScene>()),
        ("renderer", size_of::<Renderer<'static, Number, OBJECTS>>()),
        ("row", size_of::<[Rgb; WIDTH as usize]>()),
        ("output", size_of::<RowFile>()),
        ("row-shading", size_of::<RowShading<'static, Number>>()),
        ("object", size_of::<Object<Number>>()),
        ("material", size_of::<Material<Number>>()),
        ("light", size_of::<Light<Number>>()),
        ("texture", size_of::<Texture<'static>>()),
    ];
    console::line(&[T("microray sizes")]);
    for (name, bytes) in sizes {
        console::line(&[T("microray size "), T(name), T(" "), N(bytes)]);
    }
}

/// Parses one embedded scene file into the one scene there is (out of line, so that the
/// parser's frames are gone before the render starts).
#[cfg(feature = "full")]
#[inline(never)]
fn load_file(file: &scenes::SceneFile, scene: &mut FirmwareScene) -> Result<(), &'static str> {
    let textures = |filename: &str| {
        file.textures
            .iter()
            .find(|(written, _)| *written == filename)
            .map(|(_, bytes)| *bytes)
            .ok_or(TextureError::NotFound)
    };
    parse_scene_into(file.text.as_bytes(), textures, scene).map_err(|e| {
        // Line and column only: the error's text needs the formatter, which the firmware
        // does not link (`microray render` on the host says the rest).
        let at = e
            .position
            .unwrap_or(microray::Position { line: 0, column: 0 });
        console::line(&[
            T("microray scene "),
            T(file.name),
            T(" load error at "),
            N(at.line as usize),
            T(":"),
            N(at.column as usize),
        ]);
        "scene does not load"
    })
}

/// Builds and renders the scene written in Rust source with every feature.
#[cfg(feature = "full")]
#[inline(never)]
fn run_static(scene: &mut FirmwareScene) -> Result<(), &'static str> {
    scene
        .load_defs(
            &static_scene::CAMERA,
            &static_scene::MATERIALS,
            &static_scene::TEXTURES,
            &static_scene::LIGHTS,
            &static_scene::OBJECTS,
        )
        .map_err(|_| "static scene does not load")?;
    render_to_file(static_scene::NAME, scene)
}

/// The scene written in Rust source that needs no optional feature, compiled by build.rs
/// for this number type and image size.
#[cfg(not(feature = "full"))]
static BASIC: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/basic.mray"));

/// Loads and renders the compiled `basic` scene: no parser, no f64 arithmetic, and no
/// change of resolution (it was compiled at the firmware's). The minimal build's way.
#[cfg(not(feature = "full"))]
#[inline(never)]
fn run_basic(scene: &mut FirmwareScene) -> Result<(), &'static str> {
    scene
        .load_compiled(BASIC, no_textures)
        .map_err(|_| "basic scene does not load")?;
    render_scene(basic_scene::NAME, scene)
}

/// Builds and renders the `basic` scene from its definitions (the full build has the f64
/// loader anyway, for scene files: a second way to load would only cost flash).
#[cfg(feature = "full")]
#[inline(never)]
fn run_basic(scene: &mut FirmwareScene) -> Result<(), &'static str> {
    basic_scene::load(scene).map_err(|_| "basic scene does not load")?;
    render_to_file(basic_scene::NAME, scene)
}

#[entry]
fn main() -> ! {
    // The one scene, built in place for each file in turn.
    let mut scene = FirmwareScene::empty();
    #[cfg(feature = "full")]
    {
        for file in SCENES {
            stack::paint();
            let result = load_file(file, &mut scene).and_then(|()| {
                PARSE_PEAK.store(stack::peak(), Ordering::Relaxed);
                stack::paint();
                render_to_file(file.name, &mut scene)
            });
            // A film reports each of its frames.
            #[cfg(feature = "animate")]
            if ANIMATE {
                if let Err(why) = result.and_then(|()| animating::play(file, &mut scene)) {
                    report_frame(file.name, "", Err(why));
                }
                continue;
            }
            report(file.name, result);
        }
        if RUN_STATIC {
            stack::paint();
            let result = run_static(&mut scene);
            report(static_scene::NAME, result);
        }
    }
    if RUN_BASIC {
        stack::paint();
        let result = run_basic(&mut scene);
        report(basic_scene::NAME, result);
    }
    #[cfg(feature = "full")]
    report_sizes();
    for (name, why) in SKIPPED {
        console::line(&[
            T("microray scene "),
            T(name),
            T(" skipped ("),
            T(why),
            T(")"),
        ]);
    }
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::wfi();
    }
}

/// The semihosting console, without `core::fmt` (its formatter and float printing are most
/// of a small firmware's flash).
mod console {
    use cortex_m_semihosting::hio;

    /// A piece of a console line.
    pub enum Part<'a> {
        /// Text as it is.
        T(&'a str),
        /// A number, in decimal.
        N(usize),
    }

    /// Writes `parts` and a newline to the console.
    #[inline(never)]
    pub fn line(parts: &[Part<'_>]) {
        for part in parts {
            match part {
                Part::T(text) => write(text.as_bytes()),
                Part::N(n) => {
                    let mut digits = [0u8; 10];
                    write(decimal(*n, &mut digits));
                }
            }
        }
        write(b"\n");
    }

    fn write(bytes: &[u8]) {
        if let Ok(mut out) = hio::hstdout() {
            let _ = out.write_all(bytes);
        }
    }

    /// `n` in decimal, in `digits`: by subtracting powers of ten (the Cortex-M0 has no
    /// divide instruction, and a division routine costs flash).
    fn decimal(n: usize, digits: &mut [u8; 10]) -> &[u8] {
        const POWERS: [u32; 10] = [
            1_000_000_000,
            100_000_000,
            10_000_000,
            1_000_000,
            100_000,
            10_000,
            1_000,
            100,
            10,
            1,
        ];
        let mut n = n as u32;
        let mut len = 0;
        for (i, power) in POWERS.into_iter().enumerate() {
            let mut digit = 0u8;
            while n >= power {
                n -= power;
                digit += 1;
            }
            if digit > 0 || len > 0 || i == POWERS.len() - 1 {
                digits[len] = b'0' + digit;
                len += 1;
            }
        }
        &digits[..len]
    }

    /// A panic ends QEMU with a failure, without formatting the message.
    #[panic_handler]
    fn panic(_: &core::panic::PanicInfo) -> ! {
        line(&[Part::T("microray panic")]);
        cortex_m_semihosting::debug::exit(cortex_m_semihosting::debug::EXIT_FAILURE);
        loop {
            cortex_m::asm::wfi();
        }
    }
}

/// Peak stack: the free stack is filled with a pattern, and the lowest word that no longer
/// holds it shows how deep the stack went.
mod stack {
    const PATTERN: u32 = 0x5AFE_C0DE;

    unsafe extern "C" {
        /// End of `.bss`: the stack may grow down to here (cortex-m-rt).
        static __sheap: u32;
        /// Top of RAM, where the stack starts (cortex-m-rt).
        static _stack_start: u32;
    }

    fn bounds() -> (usize, usize) {
        let bottom = core::ptr::addr_of!(__sheap) as usize;
        let top = core::ptr::addr_of!(_stack_start) as usize;
        (bottom, top)
    }

    /// Fills the free stack below the current frame (with a margin) with the pattern.
    #[inline(never)]
    pub fn paint() {
        let (bottom, _) = bounds();
        let here = cortex_m::register::msp::read() as usize - 64;
        let mut p = bottom;
        while p < here {
            unsafe { core::ptr::write_volatile(p as *mut u32, PATTERN) };
            p += 4;
        }
    }

    /// Bytes of stack in use now.
    #[inline(always)]
    pub fn depth() -> usize {
        let (_, top) = bounds();
        top - cortex_m::register::msp::read() as usize
    }

    /// Bytes of stack used since the last paint.
    pub fn peak() -> usize {
        let (bottom, top) = bounds();
        let mut p = bottom;
        while p < top && unsafe { core::ptr::read_volatile(p as *const u32) } == PATTERN {
            p += 4;
        }
        top - p
    }
}
