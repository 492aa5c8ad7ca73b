//! The camera: image size, the world window on the image plane z = 0, and the eye.

use crate::error::{Attr, ErrorKind};
use crate::name::{Name, bounded};
use crate::ray::Ray;
use crate::scalar::{PixelSteps, RowRoots, Scalar, load_length, load_position};
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use crate::write;
#[cfg(feature = "print")]
use core::fmt;

/// The primary rays of one image row as a kind sees them when it prepares its test: every
/// one starts at `eye`, and the direction of the ray through pixel position `x` is
/// `(x - eye.x, dy, dz)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowOrigin<S> {
    /// Where every primary ray starts.
    pub eye: Vec3<S>,
    /// The rays' `y` component.
    pub dy: S,
    /// The rays' `z` component.
    pub dz: S,
    /// The scene's z rule (see [`closest_hit`](crate::hits::closest_hit)).
    pub z_limit: S,
    /// The rays' `x` component, column by column.
    pub columns: RowColumns<S>,
}

/// The `x` component of the directions of a row's primary rays, column by column (the
/// whole row, whichever columns are rendered): what a kind needs to find the run of
/// columns whose rays can meet it (see [`RowTest::AtAcross`](crate::object::RowTest)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowColumns<S> {
    world: S,
    /// The last column (the window's `world` lies over `n` steps between pixels).
    n: u16,
    /// `Multiply`: `world / n`, as the row's positions have it. `Exact`: `floor(world /
    /// n)` in the type's steps.
    step: S,
    /// `Exact`: `world - step n` in the type's steps (below `n`), or `u32::MAX` where
    /// `dir_x` divides as `mul_ratio` does.
    remainder: u32,
    eye_x: S,
    #[cfg(feature = "antialias")]
    shift_x: S,
    count: u16,
}

impl<S: Scalar> RowColumns<S> {
    /// No columns (a row whose rays are not known by column).
    pub(crate) fn none() -> Self {
        Self {
            world: S::ZERO,
            n: 0,
            step: S::ZERO,
            remainder: u32::MAX,
            eye_x: S::ZERO,
            #[cfg(feature = "antialias")]
            shift_x: S::ZERO,
            count: 0,
        }
    }

    /// How many columns the row has.
    pub fn count(&self) -> u16 {
        self.count
    }

    /// The `x` of the direction of the ray through `column`, bit for bit as
    /// [`RowRays`] makes it. Not for `f64`, whose rays are normalised.
    pub fn dir_x(&self, column: u16) -> S {
        let x = match S::PIXEL_STEPS {
            PixelSteps::Exact => self.exact_position(column),
            PixelSteps::Course => self.world.mul_ratio(column, self.n),
            PixelSteps::Multiply => self.step * S::from_i32(i32::from(column)),
        };
        #[cfg(feature = "antialias")]
        let x = x + self.shift_x;
        x - self.eye_x
    }
}

impl<S: Scalar> RowColumns<S> {
    /// `Exact`: `world column / n` as `mul_ratio` truncates it, from `world = step n +
    /// remainder`: `step column + floor(remainder column / n)`, a product and a quotient
    /// of 32 bits (`column` at most `n`: the sum is at most `world`), where `mul_ratio`
    /// divides 48 bits by a divisor it prepares each time (on the Cortex-M0 a
    /// rectangle's row test asked it about 18 times a row, 7 % of aademo).
    #[inline(never)]
    fn exact_position(&self, column: u16) -> S {
        let n = u32::from(self.n);
        let column = u32::from(column);
        let step = signed_raw(self.step);
        if self.remainder >= n || column > n || step < 0 {
            return self.world.mul_ratio(column as u16, self.n);
        }
        // step n + remainder = world below 2^31, column <= n: within 32 bits.
        let whole = (step as u32).wrapping_mul(column);
        let part = self.remainder.wrapping_mul(column) / n;
        S::from_raw(u64::from(whole.wrapping_add(part)))
    }

    /// `Exact`: [`RowColumns`]'s `step` and `remainder` for a window `world` over `n`
    /// steps (a remainder of `u32::MAX` where `dir_x` is left to `mul_ratio`).
    #[inline(never)]
    fn exact_steps(world: S, n: u16) -> (S, u32) {
        let raw = signed_raw(world);
        if n == 0 || raw <= 0 || raw >= 1 << 31 {
            return (S::ZERO, u32::MAX);
        }
        let (raw, n) = (raw as u32, u32::from(n));
        (S::from_raw(u64::from(raw / n)), raw % n)
    }
}

#[cfg(all(feature = "plan", feature = "batch"))]
impl<S: Scalar> RowOrigin<S> {
    /// `dy^2 + dz^2` in `f64`: a ray's length squared is `a^2` more, `a` its `x`.
    pub(crate) fn dy_dz_squared(&self) -> f64 {
        let (dy, dz) = (self.dy.to_f64(), self.dz.to_f64());
        dy * dy + dz * dz
    }
}

/// Neighbouring pixels' rays must differ in direction by at least this many steps of the
/// number type's [`Scalar::UNIT_STEP`]; below that the rounding of the rays merges rows (a
/// window 0.006 high over 120 rows, seen from 6 away, is 0.5 steps apart in Q16.16).
pub const MIN_PIXEL_STEPS: u32 = 16;

/// The primary rays of one image row, left to right: `Some` ray per pixel, `None` where
/// the eye lies on the pixel's point (no direction).
#[derive(Clone, Debug)]
pub struct RowRays<S> {
    eye: Vec3<S>,
    dy: S,
    dz: S,
    /// What the rays' lengths share (see [`Scalar::row_squares`]).
    squares: u64,
    /// The roots of the lengths so far (see [`Scalar::row_length`]).
    roots: RowRoots,
    x: Positions<S>,
    /// Added to every position along the row (anti-aliasing's sub-pixel samples).
    #[cfg(feature = "antialias")]
    shift_x: S,
    left: u16,
}

impl<S: Scalar> RowRays<S> {
    /// The columns (first and last) of the next `count` rays: the stride apart.
    #[cfg(all(feature = "plan", not(microray_small)))]
    pub(crate) fn next_columns(&self, count: usize) -> [u16; 2] {
        let steps = u16::try_from(count.saturating_sub(1)).unwrap_or(u16::MAX);
        let first = self.x.i;
        [
            first,
            first.saturating_add(steps.saturating_mul(self.x.stride)),
        ]
    }

    /// What every ray of the row shares, for the kinds' row tests (see
    /// [`crate::object::RowTest`]): the eye and the direction's `y` and `z`. Only the types
    /// that do not normalise primary rays keep `y` and `z` along a row.
    pub fn origin(&self, z_limit: S) -> RowOrigin<S> {
        RowOrigin {
            eye: self.eye,
            dy: self.dy,
            dz: self.dz,
            z_limit,
            // Built for size, no kind reads them (flash).
            columns: if cfg!(microray_small) {
                RowColumns::none()
            } else {
                self.columns()
            },
        }
    }

    /// The row's columns, for [`origin`](Self::origin).
    fn columns(&self) -> RowColumns<S> {
        let (step, remainder) = match S::PIXEL_STEPS {
            PixelSteps::Exact => RowColumns::exact_steps(self.x.world, self.x.n),
            _ => (self.x.step, u32::MAX),
        };
        RowColumns {
            world: self.x.world,
            n: self.x.n,
            step,
            remainder,
            eye_x: self.eye.x,
            #[cfg(feature = "antialias")]
            shift_x: self.shift_x,
            count: self.x.n.saturating_add(1),
        }
    }

    /// The world `x` of the row's pixels, less the eye's, from the first to the last
    /// column (shifted, for anti-aliasing's samples), in `f64`.
    #[cfg(all(feature = "batch", feature = "plan"))]
    pub(crate) fn span_from_eye(&self, width: S) -> [f64; 2] {
        #[cfg(feature = "antialias")]
        let shift = self.shift_x.to_f64();
        #[cfg(not(feature = "antialias"))]
        let shift = 0.0;
        let eye_x = self.eye.x.to_f64();
        [shift - eye_x, width.to_f64() + shift - eye_x]
    }
}

impl<S: Scalar> Iterator for RowRays<S> {
    type Item = Option<Ray<S>>;

    // Always in line: the row's loop then works out what is the same along the row once.
    #[inline(always)]
    fn next(&mut self) -> Option<Self::Item> {
        if self.left == 0 {
            return None;
        }
        self.left -= 1;
        let x = self.x.next_position();
        #[cfg(feature = "antialias")]
        let x = x + self.shift_x;
        let dir = Vec3::new(x - self.eye.x, self.dy, self.dz);
        if S::COURSE_ORDER {
            Some(
                dir.unit()
                    .map(|unit| Ray::with_length(self.eye, unit, S::ONE)),
            )
        } else {
            // The length is needed for the distance travelled wherever the ray hits.
            let len = S::row_length(dir.x, self.dy, self.dz, self.squares, &mut self.roots);
            Some((len > S::ZERO).then(|| Ray::with_length(self.eye, dir, len)))
        }
    }
}

#[cfg(feature = "batch")]
impl<S: Scalar> RowRays<S> {
    /// The next `out.len()` rays into `out` (`None` past the row's end), as as many calls
    /// of [`next`](Iterator::next) give them, bit for bit. In `f64` a batch's divisions
    /// and square roots are done side by side (`src/lanes.rs`).
    #[inline]
    pub fn next_batch(&mut self, out: &mut [Option<Ray<S>>]) {
        self.next_batch_with(out, |slot, ray| *slot = ray);
    }

    /// [`next_batch`](Self::next_batch) with each ray handed to `put` with its slot of
    /// `out`, so that a caller keeping more than the ray writes it where it stays.
    #[inline(always)]
    pub(crate) fn next_batch_with<T>(
        &mut self,
        out: &mut [T],
        mut put: impl FnMut(&mut T, Option<Ray<S>>),
    ) {
        const BATCH: usize = crate::lanes::BATCH;
        let course_f64 = S::CODE == f64::CODE && matches!(S::PIXEL_STEPS, PixelSteps::Course);
        if !course_f64 || out.len() != BATCH || usize::from(self.left) < BATCH {
            for slot in out.iter_mut() {
                put(slot, self.next().flatten());
            }
            return;
        }
        let mut i = [0u16; BATCH];
        for i in &mut i {
            *i = self.x.i;
            self.x.i = self.x.i.saturating_add(self.x.stride);
        }
        self.left -= BATCH as u16;
        #[cfg(feature = "antialias")]
        let shift = self.shift_x.to_f64();
        // The positions are not below +0 (the window is above 0), so adding +0 changes none.
        #[cfg(not(feature = "antialias"))]
        let shift = 0.0;
        let dx = crate::lanes::row_offsets(
            self.x.world.to_f64(),
            &i,
            self.x.n,
            shift,
            self.eye.x.to_f64(),
        );
        let [x, y, z, length] =
            crate::lanes::unit_directions(&dx, self.dy.to_f64(), self.dz.to_f64());
        let units = x.into_iter().zip(y).zip(z).zip(length);
        let eye = self.eye;
        for (slot, (((x, y), z), length)) in out.iter_mut().zip(units) {
            if length > 0.0 {
                let unit = Vec3::new(S::from_f64(x), S::from_f64(y), S::from_f64(z));
                put(slot, Some(Ray::with_length(eye, unit, S::ONE)));
            } else {
                put(slot, None);
            }
        }
    }
}

/// A value of a [`PixelSteps::Exact`] type in its steps: the raw word, sign-extended.
fn signed_raw<S: Scalar>(value: S) -> i64 {
    let unused = 64 - 8 * S::RAW_BYTES.clamp(1, 8) as u32;
    (value.to_raw() << unused) as i64 >> unused
}

/// The positions `world * i / n` along one axis for `i = first, first + stride, ...`, as
/// the number type's [`PixelSteps`] finds them (the same values whatever the stride).
#[derive(Clone, Debug)]
struct Positions<S> {
    world: S,
    n: u16,
    i: u16,
    stride: u16,
    /// `Multiply`: `world / n`. `Exact`: `floor(world stride / n)` in the type's steps.
    step: S,
    /// `Exact`: the next position, the type's smallest step, and the remainders (in
    /// those steps) of the position and of the step, below `n`.
    value: S,
    bump: S,
    remainder: u32,
    remainder_step: u32,
}

impl<S: Scalar> Positions<S> {
    fn new(world: S, n: u16, first: u16, stride: u16) -> Self {
        let stride = stride.max(1);
        let mut positions = Self {
            world,
            n,
            i: first,
            stride,
            step: S::ZERO,
            value: S::ZERO,
            bump: S::ZERO,
            remainder: 0,
            remainder_step: 0,
        };
        match S::PIXEL_STEPS {
            PixelSteps::Course => {}
            PixelSteps::Multiply => positions.step = world / S::from_i32(i32::from(n.max(1))),
            PixelSteps::Exact => {
                // In steps of the type's resolution every value is an integer below 2^31,
                // so these products (below 2^47) and differences are exact in i64.
                let n = n.max(1);
                positions.step = world.mul_ratio(stride, n);
                positions.value = world.mul_ratio(first, n);
                positions.bump = S::from_raw(1);
                // Within 0..n for every window the loaders accept; clamped there for any
                // other, so that the sums in `next_position` cannot overflow.
                let remainder = |count: u16, value: S| {
                    let exact =
                        signed_raw(world) * i64::from(count) - signed_raw(value) * i64::from(n);
                    exact.clamp(0, i64::from(n) - 1) as u32
                };
                positions.remainder_step = remainder(stride, positions.step);
                positions.remainder = remainder(first, positions.value);
            }
        }
        positions
    }

    /// The position at `i`, then on to `i + 1`.
    #[inline]
    fn next_position(&mut self) -> S {
        let i = self.i;
        self.i = self.i.saturating_add(self.stride);
        match S::PIXEL_STEPS {
            PixelSteps::Course => self.world.mul_ratio(i, self.n),
            PixelSteps::Multiply => self.step * S::from_i32(i32::from(i)),
            PixelSteps::Exact => {
                let value = self.value;
                self.value = self.value + self.step;
                self.remainder += self.remainder_step;
                if self.remainder >= u32::from(self.n) {
                    self.remainder -= u32::from(self.n);
                    self.value = self.value + self.bump;
                }
                value
            }
        }
    }
}

/// A camera as written in a scene (or in Rust source): plain `f64` data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraDef<'a> {
    /// The camera's name.
    pub name: &'a str,
    /// Image size in pixels (width, height); each at least 2.
    pub pixeldim: [u32; 2],
    /// Size of the world window on the image plane; each above 0.
    pub worlddim: [f64; 2],
    /// The eye, where primary rays start.
    pub viewpoint: [f64; 3],
}

impl<'a> CameraDef<'a> {
    /// A camera definition.
    pub const fn new(
        name: &'a str,
        pixeldim: [u32; 2],
        worlddim: [f64; 2],
        viewpoint: [f64; 3],
    ) -> Self {
        Self {
            name,
            pixeldim,
            worlddim,
            viewpoint,
        }
    }
}

/// The scene's camera, checked: at least 2 by 2 pixels, a positive world window.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera<S> {
    pub(crate) name: Name,
    pub(crate) width: u16,
    pub(crate) height: u16,
    pub(crate) world: [S; 2],
    pub(crate) viewpoint: Vec3<S>,
}

impl<S: Scalar> Camera<S> {
    /// Checks a definition; `max_width` is the widest row the build renders.
    pub(crate) fn build(
        def: &CameraDef<'_>,
        max_width: usize,
        scale: f64,
    ) -> Result<Self, ErrorKind> {
        let [width, height] = def.pixeldim;
        if width < 2 || height < 2 {
            return Err(ErrorKind::PixeldimTooSmall);
        }
        if usize::try_from(width).map_or(true, |w| w > max_width) || width > u32::from(u16::MAX) {
            let max = u32::try_from(max_width)
                .unwrap_or(u32::MAX)
                .min(u32::from(u16::MAX));
            return Err(ErrorKind::ImageTooWide { width, max });
        }
        let height = u16::try_from(height).map_err(|_| ErrorKind::ImageTooTall { height })?;
        let width = u16::try_from(width).map_err(|_| ErrorKind::ImageTooWide {
            width,
            max: u32::from(u16::MAX),
        })?;
        let world = [
            load_length::<S>(def.worlddim[0], scale, Attr::Worlddim)?,
            load_length::<S>(def.worlddim[1], scale, Attr::Worlddim)?,
        ];
        let viewpoint = load_position(def.viewpoint, scale, Attr::Viewpoint)?;
        let camera = Self {
            name: bounded(def.name)?,
            width,
            height,
            world,
            viewpoint,
        };
        camera.check_pixel_angle()?;
        Ok(camera)
    }

    /// The angle between neighbouring pixels' rays, at the window's corner farthest from
    /// the eye (where it is smallest), must be at least [`MIN_PIXEL_STEPS`] steps of the type.
    fn check_pixel_angle(&self) -> Result<(), ErrorKind> {
        let eye = self.viewpoint.to_f64();
        let [w, h] = [self.world[0].to_f64(), self.world[1].to_f64()];
        let farthest = [(0.0, 0.0), (w, 0.0), (0.0, h), (w, h)]
            .iter()
            .map(|&(x, y)| (Vec3::new(x, y, 0.0) - eye).length())
            .fold(0.0, f64::max);
        let gaps = |pixels: u16| f64::from(pixels.saturating_sub(1).max(1));
        let pitch = (w / gaps(self.width)).min(h / gaps(self.height));
        if pitch / farthest >= f64::from(MIN_PIXEL_STEPS) * S::UNIT_STEP {
            Ok(())
        } else {
            Err(ErrorKind::PixelsTooFine {
                number_type: S::NAME,
                steps: MIN_PIXEL_STEPS,
            })
        }
    }

    /// A stand-in until the scene's camera is set: 2 by 2 pixels, a unit window.
    pub(crate) const PLACEHOLDER: Self = Self {
        name: Name::new(),
        width: 2,
        height: 2,
        world: [S::ONE, S::ONE],
        viewpoint: Vec3::new(S::ZERO, S::ZERO, S::ONE),
    };

    /// The same camera with another image size (the world window stays: the same picture at
    /// another resolution).
    pub(crate) fn with_pixels(
        &self,
        width: u16,
        height: u16,
        max_width: usize,
    ) -> Result<Self, ErrorKind> {
        if width < 2 || height < 2 {
            return Err(ErrorKind::PixeldimTooSmall);
        }
        if usize::from(width) > max_width {
            let max = u32::try_from(max_width).unwrap_or(u32::MAX);
            return Err(ErrorKind::ImageTooWide {
                width: u32::from(width),
                max,
            });
        }
        let camera = Self {
            width,
            height,
            ..self.clone()
        };
        camera.check_pixel_angle()?;
        Ok(camera)
    }

    /// The camera's name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Image width in pixels.
    pub fn width(&self) -> u16 {
        self.width
    }
    /// Image height in pixels.
    pub fn height(&self) -> u16 {
        self.height
    }
    /// Image row `row` (0 the top, as a display counts) as the camera counts it (0 the
    /// bottom, as the course's pixel loop does).
    #[inline]
    pub fn row_from_top(&self, row: u16) -> u16 {
        self.height.saturating_sub(1).saturating_sub(row)
    }
    /// The world window's size on the image plane.
    pub fn world(&self) -> [S; 2] {
        self.world
    }
    /// The eye.
    pub fn viewpoint(&self) -> Vec3<S> {
        self.viewpoint
    }

    /// The primary ray through pixel `(x, y)`, `y = 0` the bottom row: from the viewpoint to
    /// `(worlddim.x * x / (pixeldim.x - 1), worlddim.y * y / (pixeldim.y - 1), 0)`. `None`
    /// when the viewpoint lies on that point (no direction). The same ray as
    /// [`row_rays`](Self::row_rays) gives for the pixel.
    #[inline]
    pub fn primary_ray(&self, x: u16, y: u16) -> Option<Ray<S>> {
        self.row_rays(y, x).next().flatten()
    }

    /// The primary rays of row `y` (`y = 0` the bottom) from column `first` rightwards.
    /// In `f64` each is normalised, as the course does; the other types leave the direction
    /// from the eye to the pixel as it is (see [`Ray`]).
    pub fn row_rays(&self, y: u16, first: u16) -> RowRays<S> {
        self.row_rays_every(y, first, 1)
    }

    /// The primary rays of row `y` at columns `first`, `first + stride`, ...: the same rays
    /// as [`row_rays`](Self::row_rays) gives for those pixels, bit for bit, without
    /// computing the ones between (the progressive order's sparse passes).
    pub fn row_rays_every(&self, y: u16, first: u16, stride: u16) -> RowRays<S> {
        let [world_x, world_y] = self.world;
        let height = self.height.saturating_sub(1);
        let on_screen_y = world_y.mul_ratio(y, height);
        let stride = stride.max(1);
        let dy = on_screen_y - self.viewpoint.y;
        let dz = S::ZERO - self.viewpoint.z;
        RowRays {
            eye: self.viewpoint,
            dy,
            dz,
            squares: S::row_squares(dy, dz),
            roots: RowRoots::default(),
            x: Positions::new(world_x, self.width.saturating_sub(1), first, stride),
            #[cfg(feature = "antialias")]
            shift_x: S::ZERO,
            left: self.width.saturating_sub(first).div_ceil(stride),
        }
    }

    /// The rays of [`row_rays`](Self::row_rays) with every point on the image plane moved
    /// by `shift` (world units, `x` and `y`): one sub-pixel sample of each pixel of the row
    /// (see [`crate::render::Samples`]). A zero shift gives the row's rays bit for bit.
    #[cfg(feature = "antialias")]
    pub fn shifted_row_rays(&self, y: u16, first: u16, shift: [S; 2]) -> RowRays<S> {
        let mut rays = self.row_rays(y, first);
        rays.dy = rays.dy + shift[1];
        rays.squares = S::row_squares(rays.dy, rays.dz);
        rays.shift_x = shift[0];
        rays
    }

    /// The pixel pitch on the image plane, `worlddim / (pixeldim - 1)` along `x` and `y`.
    #[cfg(feature = "antialias")]
    pub fn pitch(&self) -> [S; 2] {
        let [world_x, world_y] = self.world;
        [
            world_x.mul_ratio(1, self.width.saturating_sub(1)),
            world_y.mul_ratio(1, self.height.saturating_sub(1)),
        ]
    }

    /// Writes the camera block.
    #[cfg(feature = "print")]
    pub fn print(&self, out: &mut dyn fmt::Write, scale: f64) -> fmt::Result {
        write::header(out, "camera", &self.name)?;
        writeln!(out, "  {} {} {}", Attr::Pixeldim, self.width, self.height)?;
        write::numbers(out, Attr::Worlddim, &self.world, scale)?;
        write::vector(out, Attr::Viewpoint, self.viewpoint, scale)?;
        write::footer(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scalar::I16F16;
    use proptest::prelude::*;

    proptest! {
        /// A column's position from the window's step and remainder equals `mul_ratio`'s
        /// for every column of the row, any window and width (and beyond the row, or for a
        /// window not above zero, it is `mul_ratio`'s own).
        #[test]
        fn exact_positions_equal_the_ratios(world: i32, n in 1u16.., column: u16, small in 1i32..1 << 20) {
            for world in [world, small, i32::MAX, 1] {
                let world = I16F16::from_bits(world);
                let (step, remainder) = RowColumns::exact_steps(world, n);
                let columns = RowColumns { world, n, step, remainder, ..RowColumns::none() };
                for c in [column % n.saturating_add(1), n, 0, column] {
                    prop_assert_eq!(columns.exact_position(c), world.mul_ratio(c, n), "{:?} {} {}", world, n, c);
                }
                prop_assert_eq!(remainder < u32::from(n), world.to_bits() > 0);
            }
        }
    }

    #[cfg(feature = "batch")]
    #[test]
    fn batches_are_the_rays_one_by_one() {
        use crate::lanes::BATCH;
        let bits = |ray: Option<Ray<f64>>| {
            ray.map(|r| [r.base, r.dir].map(|v| [v.x, v.y, v.z].map(f64::to_bits)))
        };
        let cameras = [
            ([640, 480], [8.0, 6.0], [4.0, 3.0, 3.0]),
            ([37, 5], [0.3, 2.0], [-1.5, 0.25, 7.0]),
            // The eye on the image plane: one pixel has no direction.
            ([21, 21], [2.0, 2.0], [1.0, 1.0, 0.0]),
        ];
        let mut no_direction = false;
        for (pixeldim, worlddim, viewpoint) in cameras {
            let def = CameraDef::new("c", pixeldim, worlddim, viewpoint);
            let camera = Camera::<f64>::build(&def, 1024, 1.0).unwrap();
            for (y, first, stride) in [(0, 0, 1), (3, 5, 1), (4, 1, 2), (2, 0, 3), (10, 0, 1)] {
                #[cfg(feature = "antialias")]
                let shifted = camera.shifted_row_rays(y, first, [0.01, -0.02]);
                #[cfg(not(feature = "antialias"))]
                let shifted = camera.row_rays_every(y, first, stride);
                for rays in [camera.row_rays_every(y, first, stride), shifted] {
                    let one_by_one: Vec<_> = rays.clone().map(bits).collect();
                    let mut batched = Vec::new();
                    let mut rays = rays;
                    for size in [BATCH, 3, BATCH, BATCH, 1].iter().cycle().take(200) {
                        let mut out = [None; BATCH];
                        rays.next_batch(&mut out[..*size]);
                        batched.extend(out[..*size].iter().map(|r| bits(*r)));
                    }
                    assert!(batched[one_by_one.len()..].iter().all(Option::is_none));
                    assert_eq!(batched[..one_by_one.len()], one_by_one[..]);
                    no_direction |= one_by_one.contains(&None);
                }
            }
        }
        assert!(no_direction);
    }

    #[test]
    fn exact_steps_are_the_course_positions() {
        // Stepping (integer and remainder parts, in the type's steps) gives world * i / n as
        // the course computes each, for widths and windows of every size, any first pixel
        // and any stride (the progressive order's).
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..2000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let world = I16F16::from_raw(seed % (1 << 31));
            let n = 1 + (seed >> 32) as u16 % 1024;
            let first = (seed >> 48) as u16 % n;
            let stride = 1 + (seed >> 40) as u16 % 8;
            let mut positions = Positions::new(world, n, first, stride);
            for i in (first..n.min(first + 64 * stride)).step_by(usize::from(stride)) {
                assert_eq!(
                    positions.next_position(),
                    world.mul_ratio(i, n),
                    "world {world:?} i {i} n {n} stride {stride}"
                );
            }
        }
    }
}
