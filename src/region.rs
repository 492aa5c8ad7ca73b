//! The part of the screen a change to the scene can touch, worked out before tracing, so
//! that a moving picture re-traces only that and stays byte for byte the full frame.
//!
//! A pixel's colour depends on its primary rays' first hits, the shadow rays from those
//! hits to each light, and, where a hit is on a mirror or a transparent object, the rays
//! that go on from there. So when object `O` changes (moves, changes size or material), a
//! pixel can change only if
//! - one of its primary rays can reach `O` before or after: `O`'s outline both times,
//!   bounded as the render plan bounds an object's rows and columns;
//! - its primary hit `P` lies where a shadow ray from `P` to some light `L` can cross `O`
//!   before or after: the points `L + s (V - L)`, `s >= 1`, `V` in a polytope holding `O`
//!   ([`crate::plan`]'s shadow polytope, widened for rounding). On an infinite plane those
//!   points lie in the hull of the polytope's projection from `L` onto the plane; a bounded
//!   object is taken whole (its outline) where its bounding sphere can meet that cone;
//!   less, for an opaque ball's shadow on a flat receiver, the pixels in its certain umbra
//!   both before and after (their shadow rays to `L` cross the ball both times, in any
//!   number type: `L` adds nothing there either time);
//! - its primary hit is on a mirror or a transparent object: their outlines, whole.
//!
//! A light that changes can change anything it lights: the whole frame, as does a camera
//! that changes. Every bound is conservative (worked out in `f64`, or in `f32` with the
//! `geometry-f32` feature, from the number type's own values, with the plan's margins);
//! `tests/animate.rs` compares incremental frames with full ones in every number type.
//!
//! The region is a short list of disjoint screen rectangles whose capacity is part of the
//! type, as with every list in microray: a rectangle that overlaps one already there adds
//! only its parts outside it, and when the list is full, a part is merged with the
//! rectangle whose union with it grows least, so the region always holds every pixel asked
//! for and traces none twice. Beside them it keeps an outline of each thing added (up to
//! 16; more merge into boxes): a box, and for the hull of a set of points (a ball's
//! octagon, a shadow's polygon) the lines along the box's diagonals that cut its corners
//! off (an ellipse's octagon is 1.055 times its area, its box 1.27). Only the rectangles'
//! pixels within some outline are traced, row by row: in `bounce` that is 17 % fewer.
//!
//! ```
//! use microray::embedded_graphics::prelude::*;
//! use microray::embedded_graphics::primitives::Rectangle;
//! use microray::region::Region;
//!
//! let square = |x, y, side| Rectangle::new(Point::new(x, y), Size::new(side, side));
//! let mut region = Region::<8>::new(Size::new(100, 80));
//! region.add(square(10, 10, 20));
//! region.add(square(25, 25, 10)); // overlaps the first: only its 75 new pixels are added
//! region.add(square(90, 70, 30)); // clipped to the screen
//! assert_eq!(region.pixels(), 20 * 20 + 75 + 10 * 10);
//!
//! // Room for two rectangles: the overlapping ones are filed as their bounding box, and
//! // its rows are traced only where the squares are (in three rectangles).
//! let mut small = Region::<2>::new(Size::new(100, 80));
//! small.add(square(10, 10, 20));
//! small.add(square(25, 25, 10));
//! assert_eq!(small.pixels(), 20 * 20 + 75);
//! assert_eq!(small.rectangles().count(), 3);
//! ```

use crate::camera::Camera;
use crate::light::Light;
use crate::material::Material;
use crate::object::{Object, Plane, Shape};
use crate::plan::{self, OnPlane, ScreenBox};
use crate::scalar::Scalar;
use crate::scalar::geometry::{self, Geo};
use crate::scene::Scene;
use crate::vec3::Vec3;
use core::num::NonZeroU8;
use embedded_graphics::prelude::{Point, Size};
use embedded_graphics::primitives::Rectangle;
use heapless::Vec;

/// Screen rectangles holding every pixel some changes can touch (see the module's docs);
/// at most `N`, disjoint, or the whole frame.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Region<const N: usize> {
    width: u16,
    height: u16,
    /// Pixels added around every rectangle (see [`with_border`](Self::with_border)).
    border: u16,
    /// Whether each pixel is one ray through its own point (see
    /// [`with_one_ray_a_pixel`](Self::with_one_ray_a_pixel)).
    one_ray: bool,
    whole: bool,
    areas: Vec<Area, N>,
    /// What was added, each piece a box maybe with its corners cut: the areas' pixels
    /// outside all of them are not traced. When the list is full, two merge into their
    /// box.
    outlines: Vec<Outline, OUTLINES>,
    /// The certain umbras of moving balls, each on a receiver from a light, as each state
    /// added casts it: an outline of that shadow leaves out the pixels within every state's
    /// umbra (blocked before and after, that light adds nothing there either time).
    umbras: Vec<Umbra, UMBRAS>,
    /// How many states of each ball with an umbra were added (its slot, the count): an
    /// umbra is left out only where it holds exactly two, before and after.
    balls: Vec<(u8, u8), UMBRAS>,
}

/// The most outlines a region keeps: a moving ball's outline and its shadows from two
/// lights, before and after, for two balls and more (more merge into boxes).
const OUTLINES: usize = 16;

/// The most umbras a region keeps (more are not kept: their shadows' outlines are traced
/// whole).
const UMBRAS: usize = 4;

/// Which shadow an umbra is: the ball's slot, the light's and the receiver's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct UmbraKey {
    ball: u8,
    light: u8,
    receiver: u8,
}

impl UmbraKey {
    /// The key of ball `ball`'s shadow from light `light` on object `receiver`, where each
    /// slot fits a byte.
    fn new(ball: usize, light: usize, receiver: usize) -> Option<Self> {
        Some(Self {
            ball: u8::try_from(ball).ok()?,
            light: u8::try_from(light).ok()?,
            receiver: u8::try_from(receiver).ok()?,
        })
    }
}

/// A shadow's certain umbra in each state added (see [`Region::add_umbra`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Umbra {
    key: UmbraKey,
    /// Each state's pixels in its umbra for certain; `None`: a state without one.
    states: [Option<Octagon>; 2],
    /// How many states were added (more than two: none is left out).
    count: u8,
}

impl Umbra {
    /// The columns of row `y` in every state's umbra, when exactly two states were added
    /// (a state's shadow outline added with no umbra spoils it; a shadow of one state only
    /// changes every pixel it holds).
    fn columns(&self, y: u16) -> Option<(i32, i32)> {
        let [Some(a), Some(b)] = &self.states else {
            return None;
        };
        if self.count != 2 {
            return None;
        }
        let ((a0, a1), (b0, b1)) = (a.columns(y)?, b.columns(y)?);
        let (first, last) = (a0.max(b0), a1.min(b1));
        (first <= last).then_some((first, last))
    }
}

/// A box of pixels, and lines that cut its corners.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Outline {
    area: Area,
    cut: Option<Corners>,
    /// The shadow it holds, whose umbra it leaves out: that umbra's place in the region's
    /// list, from 1.
    umbra: Option<NonZeroU8>,
}

impl Outline {
    /// Whether it holds every pixel of its box.
    fn is_box(&self) -> bool {
        self.cut.is_none() && self.umbra.is_none()
    }
}

/// A box of pixels, and lines that cut its corners: an umbra's pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Octagon {
    area: Area,
    cut: Corners,
}

impl Octagon {
    /// The pixels within `bounds` (`y = 0` the top) for certain, `border` pixels in from
    /// them, on a screen `width` by `height`; `None` when there are none.
    fn within(
        ([a, b], bounds): plan::OctagonBounds,
        border: u16,
        width: u16,
        height: u16,
    ) -> Option<Self> {
        let [x0, x1, y0, y1, s0, s1, d0, d1] = bounds;
        let inward = Geo::from(border);
        // Clamped to the screen; a bound past it on the far side leaves nothing.
        let low = |v: Geo, most: u16| {
            let v = geometry::ceil(v + inward);
            (v <= Geo::from(most)).then(|| v.max(0.0) as u16)
        };
        let high = |v: Geo, most: u16| {
            let v = geometry::floor(v - inward);
            (v >= 0.0).then(|| v.min(Geo::from(most)) as u16)
        };
        let (right, bottom) = (width.checked_sub(1)?, height.checked_sub(1)?);
        let area = Area {
            left: low(x0, right)?,
            right: high(x1, right)?,
            top: low(y0, bottom)?,
            bottom: high(y1, bottom)?,
        };
        if area.left > area.right || area.top > area.bottom {
            return None;
        }
        let cut = Corners::within(([a, b], [s0, s1, d0, d1]), border, area)?;
        Some(Self { area, cut })
    }

    /// The columns of row `y` within it, `None` when there are none.
    pub(crate) fn columns(&self, y: u16) -> Option<(i32, i32)> {
        let o = self.area;
        if y < o.top || y > o.bottom {
            return None;
        }
        let (from, to) = self.cut.columns(o, y);
        let (first, last) = (from.max(i32::from(o.left)), to.min(i32::from(o.right)));
        (first <= last).then_some((first, last))
    }
}

/// Four lines about a convex set of pixels, as an outline keeps them, from its box's top
/// left corner `(left, top)`, `h` rows high: pixel `(x, y)` of the box is within them when
/// `sum[0] <= a (x - left) + b (y - top) <= sum[1]` and
/// `difference[0] <= a (x - left) - b (y - top) + b h <= difference[1]` (both from 0 to
/// `a w + b h`, `w` the box's width less one, which fits u16: 20 bytes an outline). With
/// `a` and `b` the box's height and width, the lines run along its diagonals, and an
/// ellipse's octagon is 1.055 times its area where its box is 1.27.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Corners {
    /// Not zero (so that an outline without a cut takes no more room).
    a: NonZeroU8,
    b: u8,
    sum: [u16; 2],
    difference: [u16; 2],
}

/// The least pixels of a box, a point of its hull, worth a cut: a cut keeps about 85 % of a
/// box, and a point's projection in software `f64` cost about four pixels' tracing on the
/// Cortex-M4F in `f32` (an estimate, before the geometry was `f32` there; every hull of the
/// films in `scenes/` passes).
const CUT_PRICE: u32 = 24;

/// A cut's weights over a box: as bytes (`a` not zero) and as numbers, the largest
/// `a x + b y` in the box (from its top left), and where `a x + b y` and `a x - b y` start
/// (at its top left, and its bottom left).
struct Frame {
    bytes: (NonZeroU8, u8),
    weights: (i32, i32),
    most: u16,
    sum_from: Geo,
    difference_from: Geo,
}

impl Frame {
    /// `None` where a weight does not fit a byte (or `a` is zero), or the box is too large.
    fn of([a, b]: [i32; 2], area: Area) -> Option<Self> {
        let bytes = (
            NonZeroU8::try_from(u8::try_from(a).ok()?).ok()?,
            u8::try_from(b).ok()?,
        );
        let (a, b) = (i32::from(bytes.0.get()), i32::from(bytes.1));
        let (w, h) = (
            i32::from(area.right - area.left),
            i32::from(area.bottom - area.top),
        );
        let (left, top) = (i32::from(area.left), i32::from(area.top));
        Some(Self {
            bytes,
            weights: (a, b),
            most: u16::try_from(a * w + b * h).ok()?,
            // Below 2^19: exact in `f32` too.
            sum_from: (a * left + b * top) as Geo,
            difference_from: (a * left - b * top - b * h) as Geo,
        })
    }
}

impl Corners {
    /// Weights for a box `width` by `height` pixels: the lines along its diagonals (any
    /// positive ones hold the pixels; up to 16, so that an outline keeps them in a byte and
    /// `a x + b y` over a box up to 2047 pixels wide and high in 16 bits).
    fn weights(width: u16, height: u16) -> [i32; 2] {
        let longer = width.max(height).max(1);
        let scaled =
            |side: u16| ((i32::from(side) * 16 + i32::from(longer) / 2) / i32::from(longer)).max(1);
        [scaled(height), scaled(width)]
    }

    /// The cut with weights `[a, b]` and bounds (`a x + b y` low and high, then
    /// `a x - b y`, `y = 0` the top) rounded out, `border` pixels further out along both
    /// axes, from the top left of `area`; `None` where the box is too large to keep it.
    fn of(([a, b], bounds): plan::CutBounds, border: u16, area: Area) -> Option<Self> {
        let frame = Frame::of([a, b], area)?;
        let ((a_byte, b_byte), (a, b)) = (frame.bytes, frame.weights);
        let (sum_from, difference_from) = (frame.sum_from, frame.difference_from);
        // Whole numbers after the floor and ceiling, so every subtraction whose result can
        // fall within 0 to `most` is exact (in `f32` too: its operands lie below 2^19); every
        // pixel of the box lies from 0 to `most`: clamped, each bound still holds it (the
        // roundings of farther ones keep their order).
        let out = ((a + b) * i32::from(border)) as Geo;
        let kept = |v: Geo| v.clamp(0.0, Geo::from(frame.most)) as u16;
        let [sum_low, sum_high, low_difference, high_difference] = bounds;
        Some(Self {
            a: a_byte,
            b: b_byte,
            sum: [
                kept(geometry::floor(sum_low) - out - sum_from),
                kept(geometry::ceil(sum_high) + out - sum_from),
            ],
            difference: [
                kept(geometry::floor(low_difference) - out - difference_from),
                kept(geometry::ceil(high_difference) + out - difference_from),
            ],
        })
    }

    /// The pixels of `area` within the lines for certain, `border` pixels in from them
    /// (rounded in); `None` where none is, or the box is too large to keep them.
    fn within(([a, b], bounds): plan::CutBounds, border: u16, area: Area) -> Option<Self> {
        let frame = Frame::of([a, b], area)?;
        let ((a_byte, b_byte), (a, b)) = (frame.bytes, frame.weights);
        let (sum_from, difference_from) = (frame.sum_from, frame.difference_from);
        let most = Geo::from(frame.most);
        let inward = ((a + b) * i32::from(border)) as Geo;
        let [sum_low, sum_high, low_difference, high_difference] = bounds;
        // Clamped into `0..=most`, which every pixel of the box is in; a bound that keeps
        // them all out keeps the octagon out.
        let pair = |lo: Geo, hi: Geo, from: Geo| {
            let (lo, hi) = (
                geometry::ceil(lo) + inward - from,
                geometry::floor(hi) - inward - from,
            );
            (lo <= hi && hi >= 0.0 && lo <= most).then(|| [lo.max(0.0) as u16, hi.min(most) as u16])
        };
        Some(Self {
            a: a_byte,
            b: b_byte,
            sum: pair(sum_low, sum_high, sum_from)?,
            difference: pair(low_difference, high_difference, difference_from)?,
        })
    }

    /// The columns of row `y` of `area` (its box) within the lines: `(first, last)`,
    /// empty when `first > last`.
    fn columns(&self, area: Area, y: u16) -> (i32, i32) {
        let (a, b) = (i32::from(self.a.get()), i32::from(self.b));
        let by = b * (i32::from(y) - i32::from(area.top));
        let bh = b * i32::from(area.bottom - area.top);
        // `a > 0`: exact floors and ceilings of quotients of numbers below 2^18.
        let floor = |n: i32| n.div_euclid(a.max(1));
        let ceil = |n: i32| -(-n).div_euclid(a.max(1));
        let [s0, s1] = self.sum.map(i32::from);
        let [d0, d1] = self.difference.map(i32::from);
        let left = i32::from(area.left);
        (
            left + ceil(s0 - by).max(ceil(d0 + by - bh)),
            left + floor(s1 - by).min(floor(d1 + by - bh)),
        )
    }
}

/// Joins the run of columns `first..=last` to `runs`, with those it overlaps or touches;
/// with the list full, with the nearest too (the gap between is traced, no pixel lost).
fn add_run<const N: usize>(runs: &mut Vec<(i32, i32), N>, mut first: i32, mut last: i32) {
    loop {
        runs.retain(|&(a, b)| {
            let apart = a > last.saturating_add(1) || b < first.saturating_sub(1);
            if !apart {
                first = first.min(a);
                last = last.max(b);
            }
            apart
        });
        if runs.push((first, last)).is_ok() {
            return;
        }
        let gap = |&(a, b): &(i32, i32)| a.saturating_sub(last).max(first.saturating_sub(b));
        let Some(nearest) = (0..runs.len()).min_by_key(|&i| runs.get(i).map(gap)) else {
            return;
        };
        let (a, b) = runs.swap_remove(nearest);
        (first, last) = (first.min(a), last.max(b));
    }
}

/// Parts of added rectangles waiting to be filed.
const PENDING: usize = 16;

/// The most steps one rectangle's filing takes before the region becomes the whole frame.
const STEPS: usize = 4096;

/// A rectangle of pixels, both ends included.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Area {
    left: u16,
    top: u16,
    right: u16,
    bottom: u16,
}

impl Area {
    fn overlaps(&self, other: &Area) -> bool {
        self.left <= other.right
            && other.left <= self.right
            && self.top <= other.bottom
            && other.top <= self.bottom
    }

    /// The parts of `self` outside `other` (which it overlaps): the rows above and below
    /// it, then the columns left and right of it in its rows.
    fn less(&self, other: &Area) -> Vec<Area, 4> {
        let mut parts = Vec::new();
        let (top, bottom) = (self.top.max(other.top), self.bottom.min(other.bottom));
        // None can fail: four at most. Overlap makes `top <= bottom` and the columns meet.
        if self.top < other.top {
            let _ = parts.push(Area {
                bottom: other.top - 1,
                ..*self
            });
        }
        if self.bottom > other.bottom {
            let _ = parts.push(Area {
                top: other.bottom + 1,
                ..*self
            });
        }
        if self.left < other.left {
            let _ = parts.push(Area {
                top,
                bottom,
                right: other.left - 1,
                ..*self
            });
        }
        if self.right > other.right {
            let _ = parts.push(Area {
                top,
                bottom,
                left: other.right + 1,
                ..*self
            });
        }
        parts
    }

    fn contains(&self, other: &Area) -> bool {
        self.left <= other.left
            && self.top <= other.top
            && other.right <= self.right
            && other.bottom <= self.bottom
    }

    fn union(&self, other: &Area) -> Area {
        Area {
            left: self.left.min(other.left),
            top: self.top.min(other.top),
            right: self.right.max(other.right),
            bottom: self.bottom.max(other.bottom),
        }
    }

    fn pixels(&self) -> u32 {
        (u32::from(self.right - self.left) + 1) * (u32::from(self.bottom - self.top) + 1)
    }

    fn rectangle(&self) -> Rectangle {
        Rectangle::new(
            Point::new(i32::from(self.left), i32::from(self.top)),
            Size::new(
                u32::from(self.right - self.left) + 1,
                u32::from(self.bottom - self.top) + 1,
            ),
        )
    }
}

impl<const N: usize> Region<N> {
    /// An empty region of a screen of `size` pixels (each side at most 65535).
    pub fn new(size: Size) -> Self {
        let side = |v: u32| u16::try_from(v).unwrap_or(u16::MAX);
        Self {
            width: side(size.width),
            height: side(size.height),
            border: 0,
            one_ray: false,
            whole: false,
            areas: Vec::new(),
            outlines: Vec::new(),
            umbras: Vec::new(),
            balls: Vec::new(),
        }
    }

    /// The same region, with `pixels` added around every rectangle added from now on:
    /// 1 for [`Antialias::Adaptive`](crate::render::Antialias), which supersamples a pixel
    /// by what its neighbours show.
    pub fn with_border(self, pixels: u16) -> Self {
        Self {
            border: pixels,
            ..self
        }
    }

    /// The same region, for frames traced with one ray a pixel, through the pixel's own
    /// point (no anti-aliasing): outlines are then not widened by the half pixel within
    /// which an anti-aliased pixel's samples lie (in `bounce`, 9 % fewer pixels). A region
    /// without it holds what every mode can touch but
    /// [`Antialias::Adaptive`](crate::render::Antialias), which needs
    /// [`with_border(1)`](Self::with_border).
    pub fn with_one_ray_a_pixel(self) -> Self {
        Self {
            one_ray: true,
            ..self
        }
    }

    /// Empty, of the same screen, border and sampling as `other`.
    pub(crate) fn reset_like<const M: usize>(&mut self, other: &Region<M>) {
        (self.width, self.height, self.border) = (other.width, other.height, other.border);
        self.one_ray = other.one_ray;
        self.clear();
    }

    /// Whether `self` is of the same screen, border and sampling as `other` (its
    /// rectangles can be added to it as they are).
    pub(crate) fn fits<const M: usize>(&self, other: &Region<M>) -> bool {
        (self.width, self.height, self.border, self.one_ray)
            == (other.width, other.height, other.border, other.one_ray)
    }

    /// Adds every pixel of `other`, a region of the same screen, border and sampling.
    pub(crate) fn add_region<const M: usize>(&mut self, other: &Region<M>) {
        if other.whole {
            return self.add_whole();
        }
        for &area in &other.areas {
            self.push(area);
        }
        for umbra in &other.umbras {
            for state in 0..usize::from(umbra.count) {
                let shape = umbra.states.get(state).copied().flatten();
                self.add_umbra(umbra.key, shape);
            }
        }
        for &outline in &other.outlines {
            // Its umbra's place in this list.
            let key = |place: NonZeroU8| other.umbras.get(usize::from(place.get() - 1));
            let umbra = outline
                .umbra
                .and_then(key)
                .and_then(|u| self.umbra_place(u.key));
            self.keep(Outline { umbra, ..outline });
        }
        for &(ball, states) in &other.balls {
            for _ in 0..states {
                self.count_state(ball);
            }
        }
    }

    /// Nothing again (the next frame's region).
    pub fn clear(&mut self) {
        self.whole = false;
        self.areas.clear();
        self.outlines.clear();
        self.umbras.clear();
        self.balls.clear();
    }

    /// Whether no pixel is in the region.
    pub fn is_empty(&self) -> bool {
        !self.whole && self.areas.is_empty()
    }

    /// Whether the region is the whole frame.
    pub fn is_whole(&self) -> bool {
        self.whole
    }

    /// The whole frame.
    pub fn add_whole(&mut self) {
        self.whole = true;
        self.areas.clear();
        self.outlines.clear();
        self.umbras.clear();
        self.balls.clear();
    }

    /// Adds a rectangle (widened by the border, clipped to the screen).
    pub fn add(&mut self, rectangle: Rectangle) {
        self.add_cut(rectangle, None, None);
    }

    /// Adds the pixels of a rectangle (widened by the border, clipped to the screen)
    /// within `cut`, less those of `umbra` (when it holds that shadow).
    fn add_cut(
        &mut self,
        rectangle: Rectangle,
        cut: Option<plan::CutBounds>,
        umbra: Option<UmbraKey>,
    ) {
        let Some(bottom_right) = rectangle.bottom_right() else {
            return;
        };
        let (right, bottom) = (self.width.saturating_sub(1), self.height.saturating_sub(1));
        let (top_left, border) = (rectangle.top_left, i64::from(self.border));
        let (low, high) = (
            (
                i64::from(top_left.x) - border,
                i64::from(top_left.y) - border,
            ),
            (
                i64::from(bottom_right.x) + border,
                i64::from(bottom_right.y) + border,
            ),
        );
        if self.width == 0
            || self.height == 0
            || high.0 < 0
            || high.1 < 0
            || low.0 > i64::from(right)
            || low.1 > i64::from(bottom)
        {
            return;
        }
        let clamp =
            |v: i64, limit: u16| u16::try_from(v.clamp(0, i64::from(limit))).unwrap_or(limit);
        let area = Area {
            left: clamp(low.0, right),
            top: clamp(low.1, bottom),
            right: clamp(high.0, right),
            bottom: clamp(high.1, bottom),
        };
        self.push(area);
        let cut = cut.and_then(|c| Corners::of(c, self.border, area));
        let umbra = umbra.and_then(|key| self.umbra_place(key));
        self.keep(Outline { area, cut, umbra });
    }

    /// Keeps an outline of what was added; with the list full, the two whose box grows
    /// least become that box.
    fn keep(&mut self, outline: Outline) {
        if self.whole
            || self
                .outlines
                .iter()
                .any(|o| o.is_box() && o.area.contains(&outline.area))
        {
            return;
        }
        let Err(left_over) = self.outlines.push(outline) else {
            return;
        };
        let grows = |o: &Outline| o.area.union(&left_over.area).pixels() - o.area.pixels();
        let closest = (0..self.outlines.len()).min_by_key(|&i| self.outlines.get(i).map(grows));
        if let Some(o) = closest.and_then(|i| self.outlines.get_mut(i)) {
            *o = Outline {
                area: o.area.union(&left_over.area),
                cut: None,
                umbra: None,
            };
        }
    }

    /// The columns of row `y` within `area` that some outline holds, as disjoint runs.
    fn runs_in_row(&self, area: Area, y: u16) -> Vec<(i32, i32), OUTLINES> {
        let mut runs = Vec::<(i32, i32), OUTLINES>::new();
        for outline in &self.outlines {
            let o = outline.area;
            if y < o.top || y > o.bottom {
                continue;
            }
            let (mut first, mut last) = (
                i32::from(o.left.max(area.left)),
                i32::from(o.right.min(area.right)),
            );
            if let Some(cut) = &outline.cut {
                let (from, to) = cut.columns(o, y);
                first = first.max(from);
                last = last.min(to);
            }
            if first > last {
                continue;
            }
            let hole = outline.umbra.and_then(|place| self.umbra_columns(place, y));
            match hole {
                Some((from, to)) if from <= last && to >= first => {
                    if first < from {
                        add_run(&mut runs, first, from - 1);
                    }
                    if to < last {
                        add_run(&mut runs, to + 1, last);
                    }
                }
                _ => add_run(&mut runs, first, last),
            }
        }
        runs
    }

    /// The columns of row `y` that the umbra at `place` leaves out of its shadow's
    /// outlines.
    fn umbra_columns(&self, place: NonZeroU8, y: u16) -> Option<(i32, i32)> {
        let umbra = self.umbras.get(usize::from(place.get() - 1))?;
        let states = self.balls.iter().find(|b| b.0 == umbra.key.ball)?.1;
        (states == 2).then(|| umbra.columns(y)).flatten()
    }

    /// The place of the umbra `key` in the list, from 1 (`None`: not filed).
    fn umbra_place(&self, key: UmbraKey) -> Option<NonZeroU8> {
        let index = self.umbras.iter().position(|u| u.key == key)?;
        NonZeroU8::new(u8::try_from(index).ok()?.checked_add(1)?)
    }

    /// Files a state of the umbra `key` (`None`: the state's shadow has none).
    fn add_umbra(&mut self, key: UmbraKey, state: Option<Octagon>) {
        if let Some(umbra) = self.umbras.iter_mut().find(|u| u.key == key) {
            if let Some(slot) = umbra.states.get_mut(usize::from(umbra.count)) {
                *slot = state;
            }
            umbra.count = umbra.count.saturating_add(1);
        } else {
            // No room: not filed, and its shadow's outlines are traced whole.
            let _ = self.umbras.push(Umbra {
                key,
                states: [state, None],
                count: 1,
            });
        }
    }

    /// Counts a state of the ball in slot `ball` (with no room, not counted: its umbras
    /// leave nothing out).
    fn count_state(&mut self, ball: u8) {
        match self.balls.iter_mut().find(|b| b.0 == ball) {
            Some(b) => b.1 = b.1.saturating_add(1),
            None => {
                let _ = self.balls.push((ball, 1));
            }
        }
    }

    /// The rectangles to trace for `area`: all of it where a box added holds it, else
    /// the runs of its rows, each as tall as the rows below it that have the same runs.
    fn pieces(&self, area: Area) -> impl Iterator<Item = Rectangle> + '_ {
        let whole = self.outlines.is_empty()
            || self
                .outlines
                .iter()
                .any(|o| o.is_box() && o.area.contains(&area));
        // The next row to start from (past the bottom: done), the runs being given out.
        let mut next = if whole {
            u32::from(area.bottom) + 1
        } else {
            u32::from(area.top)
        };
        let (mut runs, mut given, mut top, mut bottom) =
            (Vec::<(i32, i32), OUTLINES>::new(), 0, 0, 0);
        let rows = core::iter::from_fn(move || {
            loop {
                if let Some(&(first, last)) = runs.get(given) {
                    given += 1;
                    // Within `area`'s columns, which fit u16.
                    let column = |v: i32| u16::try_from(v).unwrap_or(u16::MAX);
                    let piece = Area {
                        left: column(first),
                        top,
                        right: column(last),
                        bottom,
                    };
                    return Some(piece.rectangle());
                }
                let y = u16::try_from(next).ok().filter(|&y| y <= area.bottom)?;
                runs = self.runs_in_row(area, y);
                (given, top, bottom) = (0, y, y);
                while bottom < area.bottom && self.runs_in_row(area, bottom + 1) == runs {
                    bottom += 1;
                }
                next = u32::from(bottom) + 1;
            }
        });
        whole.then_some(area.rectangle()).into_iter().chain(rows)
    }

    /// The rectangles to trace, disjoint: the region's boxes, or where what was added
    /// has cut corners, the runs of pixels of its rows within it; the whole frame as one.
    pub fn rectangles(&self) -> impl Iterator<Item = Rectangle> + '_ {
        let whole = Area {
            left: 0,
            top: 0,
            right: self.width.saturating_sub(1),
            bottom: self.height.saturating_sub(1),
        };
        let nonempty = self.width > 0 && self.height > 0;
        let all = (self.whole && nonempty).then_some(whole);
        all.into_iter().map(|a| a.rectangle()).chain(
            self.areas
                .iter()
                .copied()
                .filter(|_| !self.whole)
                .flat_map(|a| self.pieces(a)),
        )
    }

    /// How many pixels the region holds.
    pub fn pixels(&self) -> u32 {
        self.rectangles()
            .map(|r| r.size.width.saturating_mul(r.size.height))
            .sum()
    }

    /// Adds a rectangle of pixels: the parts of it outside those there are added as they
    /// are (up to four each); when the list is full, a part is merged with the rectangle
    /// whose union with it is smallest.
    fn push(&mut self, area: Area) {
        // Each part, and whether it came from a merge: a merged rectangle absorbs those it
        // overlaps (splitting it again could undo the merge forever).
        let mut pending = Vec::<(Area, bool), PENDING>::new();
        let _ = pending.push((area, false));
        // Every step files a part, splits one off an overlap or merges two: a few hundred
        // at most for the list's capacity; past the bound, the whole frame.
        for _ in 0..STEPS {
            if self.whole {
                return;
            }
            let Some((a, merged)) = pending.pop() else {
                return;
            };
            if let Some(b) = self.areas.iter().copied().find(|b| b.overlaps(&a)) {
                let parts = a.less(&b);
                if !merged && pending.len() + parts.len() <= PENDING {
                    pending.extend(parts.into_iter().map(|p| (p, false)));
                } else {
                    self.areas.retain(|x| *x != b);
                    let _ = pending.push((a.union(&b), true));
                }
                continue;
            }
            let Err(left_over) = self.areas.push(a) else {
                continue;
            };
            let grows = |x: &Area| x.union(&left_over).pixels() - x.pixels();
            let closest = (0..self.areas.len()).min_by_key(|&i| self.areas.get(i).map(grows));
            match closest {
                Some(i) => {
                    let _ = pending.push((left_over.union(&self.areas.swap_remove(i)), true));
                }
                // No room at all (`N` is 0): only the whole frame holds it.
                None => return self.add_whole(),
            }
        }
        self.add_whole();
    }

    /// Adds a box of the plan's rows (`y = 0` the bottom) and columns.
    fn add_box(&mut self, screen: ScreenBox) {
        self.add_box_cut(screen, None, None);
    }

    /// How far from its own point a pixel's rays can pass, in pixels.
    fn spread(&self) -> Geo {
        if self.one_ray { 0.0 } else { 0.5 }
    }

    /// Adds the pixels whose primary rays can reach the hull of `points` (seen by
    /// `camera`), within `within`.
    fn add_hull<S: Scalar>(&mut self, camera: &Camera<S>, points: &[Vec3<Geo>], within: ScreenBox) {
        self.add_hull_less(camera, points, within, None);
    }

    /// [`add_hull`](Self::add_hull), less the pixels of `umbra`.
    fn add_hull_less<S: Scalar>(
        &mut self,
        camera: &Camera<S>,
        points: &[Vec3<Geo>],
        within: ScreenBox,
        umbra: Option<UmbraKey>,
    ) {
        let side = |span: plan::RowSpan| span.last.saturating_sub(span.first).saturating_add(1);
        let weights = |screen: &ScreenBox| {
            let screen = meet(*screen, within);
            let (width, height) = (side(screen.columns), side(screen.rows));
            let pixels = u32::from(width) * u32::from(height);
            let price = u32::try_from(points.len())
                .unwrap_or(u32::MAX)
                .saturating_mul(CUT_PRICE);
            (pixels >= price).then(|| Corners::weights(width, height))
        };
        let (screen, cut) = plan::outline_cut(camera, points, self.spread(), weights);
        self.add_box_cut(meet(screen, within), cut, umbra);
    }

    /// [`add_box`](Self::add_box), the pixels within `cut`, less those of `umbra`.
    fn add_box_cut(
        &mut self,
        screen: ScreenBox,
        cut: Option<plan::CutBounds>,
        umbra: Option<UmbraKey>,
    ) {
        let (rows, columns) = (screen.rows, screen.columns);
        let top_row = self.height.saturating_sub(1);
        if rows.first > rows.last || columns.first > columns.last || rows.first > top_row {
            return;
        }
        let last = rows.last.min(top_row);
        let right = columns.last.min(self.width.saturating_sub(1));
        self.add_cut(
            Rectangle::with_corners(
                Point::new(i32::from(columns.first), i32::from(top_row - last)),
                Point::new(i32::from(right), i32::from(top_row - rows.first)),
            ),
            cut,
            umbra,
        );
    }

    /// Adds what a change of object `index` can touch: `old` is the object as it was (what
    /// [`Scene::replace_object`] returned), the scene holds it as it is now. Call it after
    /// every change of the frame is made: it reads the other objects as they are now.
    pub fn add_object_change<'a, S: Scalar + 'a>(
        &mut self,
        scene: impl Into<Parts<'a, S>>,
        index: usize,
        old: &Object<S>,
    ) {
        let scene = scene.into();
        let Some(new) = scene.objects.get(index) else {
            return self.add_whole();
        };
        self.add_object_state(&scene, old, index);
        self.add_object_state(&scene, new, index);
        self.add_seen_beyond(&scene, |i| i == index);
    }

    /// Adds what a change of material `index` can touch: every object that shows it, as
    /// [`add_object_change`](Self::add_object_change) does (a transparent material also
    /// filters shadows).
    pub fn add_material_change<'a, S: Scalar + 'a>(
        &mut self,
        scene: impl Into<Parts<'a, S>>,
        index: usize,
    ) {
        let shows = |object: &&Object<S>| {
            plan::materials_of(object)
                .into_iter()
                .flatten()
                .any(|m| usize::from(m) == index)
        };
        let scene = scene.into();
        for (slot, object) in scene.objects.iter().enumerate() {
            if shows(&object) {
                self.add_object_state(&scene, object, slot);
            }
        }
        self.add_seen_beyond(&scene, |i| scene.objects.get(i).is_some_and(|o| shows(&o)));
    }

    /// Adds what a change of a light can touch: everything it may light, which is taken as
    /// the whole frame.
    pub fn add_light_change(&mut self) {
        self.add_whole();
    }

    /// Adds what a change of the camera touches: the whole frame.
    pub fn add_camera_change(&mut self) {
        self.add_whole();
    }

    /// `object` (in the scene's slot `slot`, or about to be)'s outline and where its
    /// shadows can fall, from every light; with a lone flat mirror (see
    /// [`add_seen_beyond`](Self::add_seen_beyond)), where it shows them.
    pub(crate) fn add_object_state<S: Scalar>(
        &mut self,
        scene: &Parts<'_, S>,
        object: &Object<S>,
        slot: usize,
    ) {
        let mirror = lone_mirror(scene, slot);
        let footprint = plan::footprint(scene.camera, object);
        let mut octagon = [Vec3::ZERO; 8];
        if plan::outline_octagon(scene.camera, object, &mut octagon) {
            self.add_hull(scene.camera, &octagon, footprint);
        } else {
            self.add_box(footprint);
        }
        if let Some(mirror) = &mirror {
            match bounds(object) {
                Some(held) => self.add_reflected(scene, mirror, &box_corners(held)),
                None => self.add_box(mirror.screen),
            }
        }
        // Its shadows' umbras, known by its slot (one that does not fit a byte has none).
        let ball = u8::try_from(slot).ok();
        if let Some(ball) = ball {
            self.count_state(ball);
        }
        let mut vertices = [Vec3::ZERO; 8];
        for (light_slot, light) in scene.lights.iter().enumerate() {
            if self.whole {
                return;
            }
            let l = light.location.to_geo();
            let Some(octagon) = plan::widened_vertices(
                object,
                l,
                plan::resolution(scene.camera),
                plan::region_angle(scene.camera),
                true,
                &mut vertices,
            ) else {
                // Not bounded (an infinite plane), or a panel in line with the light.
                return self.add_whole();
            };
            let cone = Cone {
                vertices: &vertices,
                octagon,
                ball: bounding_sphere(&vertices, octagon),
            };
            // Not the object itself: its own pixels are in its outline.
            for (index, receiver) in scene.objects.iter().enumerate() {
                if index != slot {
                    let key = ball.and_then(|_| UmbraKey::new(slot, light_slot, index));
                    let caster = key.map(|key| (key, object));
                    self.add_shadow_on(scene, mirror.as_ref(), l, &cone, receiver, caster);
                }
            }
        }
    }

    /// Where the shadow of the polytope `cone.vertices` from a light at `l` can fall on
    /// `receiver`, and where `mirror` shows that; on a flat receiver, less the certain
    /// umbra of `caster` (its key, the object) before and after.
    fn add_shadow_on<S: Scalar>(
        &mut self,
        scene: &Parts<'_, S>,
        mirror: Option<&Mirror>,
        l: Vec3<Geo>,
        cone: &Cone<'_>,
        receiver: &Object<S>,
        caster: Option<(UmbraKey, &Object<S>)>,
    ) {
        let camera = scene.camera;
        let vertices = cone.vertices;
        if let (Some(panel), true) = (
            panel_polygon(receiver, plan::resolution(camera)),
            cone.octagon,
        ) {
            // A panel in the shadow of a ball: the panel less what lies outside the
            // pyramid of the ball's octagon (bounded where the cone runs along the panel).
            let polygon = panel.in_pyramid(l, vertices).in_light(scene, l, receiver);
            if polygon.len > 0 {
                let mut corners = [Vec3::ZERO; POLYGON];
                let corners = polygon.corners(&mut corners);
                self.add_hull(camera, corners, ScreenBox::ALL);
                if let Some(mirror) = mirror {
                    self.add_reflected(scene, mirror, corners);
                }
            }
            return;
        }
        if let Some((plane, bounded)) = flat(receiver) {
            // A panel's shadow is its plane's, within the panel's outline.
            let within = if bounded {
                plan::footprint(camera, receiver)
            } else {
                ScreenBox::ALL
            };
            let mut points = [Vec3::ZERO; 8];
            let everywhere = match plan::shadow_on_plane(l, vertices, plane, &mut points) {
                OnPlane::Nowhere => return,
                OnPlane::Anywhere => true,
                OnPlane::Within => {
                    let Some(polygon) = Polygon::in_plane(plane, &points) else {
                        return self.add_plane(scene, mirror, receiver, plane, bounded);
                    };
                    let polygon = polygon.in_light(scene, l, receiver);
                    if polygon.len == 0 {
                        return;
                    }
                    if let Some((key, object)) = caster {
                        let umbra = self.umbra_on(scene, object, l, plane);
                        self.add_umbra(key, umbra);
                    }
                    let mut corners = [Vec3::ZERO; POLYGON];
                    let corners = polygon.corners(&mut corners);
                    self.add_hull_less(camera, corners, within, caster.map(|(key, _)| key));
                    if let Some(mirror) = mirror {
                        self.add_reflected(scene, mirror, corners);
                    }
                    false
                }
            };
            if everywhere {
                self.add_plane(scene, mirror, receiver, plane, bounded);
            }
            return;
        }
        let reach = match bounds(receiver) {
            Some((low, high)) => {
                let center = (low + high) * 0.5;
                let radius = (high - low).length() * 0.5;
                let margin = 2e-3 * (radius + center.length()) + 256.0 * plan::resolution(camera);
                Some((center, radius + margin))
            }
            None => None,
        };
        if reach.is_none_or(|reach| may_meet(l, cone.ball, reach)) {
            self.add_box(plan::footprint(camera, receiver));
            if let Some(mirror) = mirror {
                match bounds(receiver) {
                    Some(held) => self.add_reflected(scene, mirror, &box_corners(held)),
                    None => self.add_box(mirror.screen),
                }
            }
        }
    }

    /// The pixels whose primary rays meet `plane` in the umbra of `object` from the light
    /// at `l` for certain (where `object` is an opaque ball). Not inlined: its corners are
    /// on the stack only while it runs (the micro:bit's region frames peak near its RAM).
    #[inline(never)]
    pub(crate) fn umbra_on<S: Scalar>(
        &self,
        scene: &Parts<'_, S>,
        object: &Object<S>,
        l: Vec3<Geo>,
        plane: &Plane<S>,
    ) -> Option<Octagon> {
        if !opaque(scene, object) {
            return None;
        }
        let mut corners = [Vec3::ZERO; plan::UMBRA_CORNERS];
        let margins = (
            plan::resolution(scene.camera),
            plan::region_angle(scene.camera),
        );
        if !plan::certain_umbra(object, l, margins, scene.z_limit, plane, &mut corners) {
            return None;
        }
        let bounds = plan::inscribed_cut(scene.camera, &corners, self.spread(), |w, h| {
            Corners::weights(w, h)
        })?;
        Octagon::within(bounds, self.border, self.width, self.height)
    }

    /// Adds a ball's outline alone, as [`add_object_state`](Self::add_object_state) adds it
    /// (for tests that leave the ball's own pixels out); `false` where it has none.
    #[cfg(test)]
    pub(crate) fn add_outline_of<S: Scalar>(
        &mut self,
        camera: &Camera<S>,
        object: &Object<S>,
    ) -> bool {
        let mut octagon = [Vec3::ZERO; 8];
        if !plan::outline_octagon(camera, object, &mut octagon) {
            return false;
        }
        self.add_hull(camera, &octagon, plan::footprint(camera, object));
        true
    }

    /// All of a flat receiver (an infinite plane's rows, a panel's outline), and all of
    /// the mirror.
    fn add_plane<S: Scalar>(
        &mut self,
        scene: &Parts<'_, S>,
        mirror: Option<&Mirror>,
        receiver: &Object<S>,
        plane: &Plane<S>,
        bounded: bool,
    ) {
        self.add_box(if bounded {
            plan::footprint(scene.camera, receiver)
        } else {
            plan::plane_footprint(scene.camera, plane)
        });
        if let Some(mirror) = mirror {
            self.add_box(mirror.screen);
        }
    }

    /// Where `mirror` can show a point of the hull of `points`: the primary rays that meet
    /// the mirror image of that hull, within the mirror's outline.
    fn add_reflected<S: Scalar>(
        &mut self,
        scene: &Parts<'_, S>,
        mirror: &Mirror,
        points: &[Vec3<Geo>],
    ) {
        let mut images = [Vec3::ZERO; POLYGON];
        for (image, &p) in images.iter_mut().zip(points) {
            *image = p - mirror.normal * (2.0 * (mirror.normal.dot(p) - mirror.offset));
        }
        let images = images.get(..points.len()).unwrap_or(&[]);
        self.add_hull(scene.camera, images, mirror.screen);
    }

    /// The outlines of every mirror and transparent object: what their pixels show comes
    /// from rays that may meet anything. The exception is a lone flat mirror: the only
    /// object whose rays go on besides the changed one, flat, its materials opaque, the
    /// same for every changed object (`changed` says which slots changed). The rays it
    /// reflects meet no mirror or glass but the changed object, so only where it shows the
    /// change can change, which [`add_object_state`](Self::add_object_state) adds for each
    /// state. The changed objects themselves are left out: call it after their states are
    /// added, which hold their outlines as they are.
    pub(crate) fn add_seen_beyond<S: Scalar>(
        &mut self,
        scene: &Parts<'_, S>,
        changed: impl Fn(usize) -> bool,
    ) {
        let slots = 0..scene.objects.len();
        if slots
            .filter(|&i| changed(i))
            .all(|i| lone_mirror(scene, i).is_some())
        {
            return;
        }
        for (slot, object) in scene.objects.iter().enumerate() {
            if !changed(slot) && goes_on(scene, object) {
                self.add_box(plan::footprint(scene.camera, object));
            }
        }
    }
}

/// Whether rays that meet `object` can go on (it shows a mirror or a transparent
/// material).
fn goes_on<S: Scalar>(scene: &Parts<'_, S>, object: &Object<S>) -> bool {
    let onward = |m: u16| {
        scene.materials.get(usize::from(m)).is_some_and(|m| {
            (cfg!(feature = "reflection") && m.reflects())
                || (cfg!(feature = "transparency") && m.transparency != S::ZERO)
        })
    };
    plan::materials_of(object).into_iter().flatten().any(onward)
}

/// Whether every material `object` shows is opaque.
fn opaque<S: Scalar>(scene: &Parts<'_, S>, object: &Object<S>) -> bool {
    plan::materials_of(object).into_iter().flatten().all(|m| {
        scene
            .materials
            .get(usize::from(m))
            .is_some_and(|m| m.transparency == S::ZERO)
    })
}

/// A flat mirror whose reflections a region follows: its plane (`normal . P = offset`,
/// the normal a unit in the geometry's type) and its outline.
struct Mirror {
    normal: Vec3<Geo>,
    offset: Geo,
    screen: ScreenBox,
}

/// The scene's lone flat mirror for a change of the object in slot `changed`: the only
/// object but that one whose rays go on, flat, its materials opaque (a ray it reflects
/// meets no mirror and no glass but the changed object, so it shows each other point of
/// the scene along one path).
fn lone_mirror<S: Scalar>(scene: &Parts<'_, S>, changed: usize) -> Option<Mirror> {
    let mut onward_objects = scene
        .objects
        .iter()
        .enumerate()
        .filter(|&(i, object)| i != changed && goes_on(scene, object));
    let (_, object) = onward_objects.next()?;
    if onward_objects.next().is_some() {
        return None;
    }
    let opaque = opaque(scene, object);
    let (plane, _) = flat(object)?;
    let n = plane.unit_normal.to_geo();
    let length = n.length();
    if !(opaque && length > 0.5 && length.is_finite()) {
        return None;
    }
    let normal = n * (1.0 / length);
    Some(Mirror {
        normal,
        offset: normal.dot(plane.point.to_geo()),
        screen: plan::footprint(scene.camera, object),
    })
}

/// The polytope of a shadow: its vertices, whether they are a ball's octagon (a flat
/// polygon whose pyramid from the light holds the shadow), and a ball holding them.
struct Cone<'v> {
    vertices: &'v [Vec3<Geo>; 8],
    octagon: bool,
    ball: (Vec3<Geo>, Geo),
}

/// A panel's rectangle as a polygon in its plane, widened by 2e-3 of its reach and 256
/// steps of `resolution` (see [`plan::resolution`]) along its sides (as the plan widens
/// objects).
fn panel_polygon<S: Scalar>(object: &Object<S>, resolution: Geo) -> Option<Polygon> {
    let rect = match object.shape() {
        Shape::FPlane(rect) => rect,
        Shape::TexPlane(textured) => &textured.rect,
        _ => return None,
    };
    let [p, across, up] = rect.corner_and_sides_geo();
    let reach = norm_1(p) + norm_1(across) + norm_1(up);
    let margin = 2e-3 * reach + 256.0 * resolution;
    let out = |v: Vec3<Geo>| {
        let length = v.length();
        if length > 0.0 && length.is_finite() {
            v * (margin / length)
        } else {
            Vec3::ZERO
        }
    };
    let (a, b) = (out(across), out(up));
    let (low, high) = (p - a - b, p + across + up + a + b);
    let corners = [low, p + across + a - b, high, p + up + b - a];
    let mut points = [low; 8];
    for (point, corner) in points.iter_mut().zip(corners) {
        *point = corner;
    }
    Polygon::in_plane(&rect.plane, &points)
}

/// The plane of a flat object, and whether the object is bounded (a panel).
fn flat<S: Scalar>(object: &Object<S>) -> Option<(&Plane<S>, bool)> {
    match object.shape() {
        Shape::Plane(plane) => Some((plane, false)),
        Shape::TiledPlane(tiles) => Some((&tiles.rect.plane, false)),
        Shape::FPlane(rect) => Some((&rect.plane, true)),
        Shape::TexPlane(textured) => Some((&textured.rect.plane, true)),
        Shape::Sphere(_) | Shape::RevSurf(_) => None,
    }
}

/// The box [`crate::bvh::bounds`] gives `object`, in the geometry's type (`f32`'s
/// rounding of a corner is far inside the margins every use adds).
fn bounds<S: Scalar>(object: &Object<S>) -> Option<(Vec3<Geo>, Vec3<Geo>)> {
    crate::bvh::bounds(object).map(|(low, high)| (geometry::narrow(low), geometry::narrow(high)))
}

/// The corners of the box from `low` to `high`.
fn box_corners((low, high): (Vec3<Geo>, Vec3<Geo>)) -> [Vec3<Geo>; 8] {
    core::array::from_fn(|i| {
        let pick = |bit: usize, a: Geo, b: Geo| if i & bit == 0 { a } else { b };
        Vec3::new(
            pick(1, low.x, high.x),
            pick(2, low.y, high.y),
            pick(4, low.z, high.z),
        )
    })
}

/// The screen box both hold.
fn meet(a: ScreenBox, b: ScreenBox) -> ScreenBox {
    let both = |a: plan::RowSpan, b: plan::RowSpan| plan::RowSpan {
        first: a.first.max(b.first),
        last: a.last.min(b.last),
    };
    ScreenBox {
        rows: both(a.rows, b.rows),
        columns: both(a.columns, b.columns),
    }
}

/// What a region reads of a scene (any [`Scene`] gives it with `&scene` or `.into()`).
#[derive(Clone, Copy, Debug)]
pub struct Parts<'a, S: Scalar> {
    /// The camera.
    pub camera: &'a Camera<S>,
    /// The materials.
    pub materials: &'a [Material<S>],
    /// The lights.
    pub lights: &'a [Light<S>],
    /// The objects.
    pub objects: &'a [Object<S>],
    /// The z rule's limit (see [`Scene::z_limit`]).
    pub z_limit: Geo,
}

impl<
    'a,
    S: Scalar,
    const OBJECTS: usize,
    const MATERIALS: usize,
    const LIGHTS: usize,
    const TEXTURES: usize,
    const MAX_WIDTH: usize,
> From<&'a Scene<'_, S, OBJECTS, MATERIALS, LIGHTS, TEXTURES, MAX_WIDTH>> for Parts<'a, S>
{
    fn from(scene: &'a Scene<'_, S, OBJECTS, MATERIALS, LIGHTS, TEXTURES, MAX_WIDTH>) -> Self {
        Self {
            camera: scene.camera(),
            materials: scene.materials(),
            lights: scene.lights(),
            objects: scene.objects(),
            z_limit: scene.z_limit().to_geo(),
        }
    }
}

/// The most corners a shadow's polygon keeps.
const POLYGON: usize = 16;

/// A convex polygon in a plane, counter-clockwise in the plane's coordinates `(x, y)`:
/// `origin + x u + y v`.
#[derive(Clone, Copy)]
struct Polygon {
    origin: Vec3<Geo>,
    u: Vec3<Geo>,
    v: Vec3<Geo>,
    points: [[Geo; 2]; POLYGON],
    len: usize,
}

impl Polygon {
    /// The hull of `points`, which lie on `plane`; `None` for a plane the basis fails on.
    fn in_plane<S: Scalar>(plane: &Plane<S>, points: &[Vec3<Geo>; 8]) -> Option<Self> {
        let n = plane.unit_normal.to_geo();
        let origin = n * plane.n_dot_point.to_geo();
        // The axis least along the normal gives the plane's first direction.
        let (ax, ay, az) = (geometry::abs(n.x), geometry::abs(n.y), geometry::abs(n.z));
        let axis = if ax <= ay && ax <= az {
            Vec3::new(1.0, 0.0, 0.0)
        } else if ay <= az {
            Vec3::new(0.0, 1.0, 0.0)
        } else {
            Vec3::new(0.0, 0.0, 1.0)
        };
        let u = n.cross(axis);
        let length = u.length();
        if !(length > 0.0) {
            return None;
        }
        let u = u * (1.0 / length);
        let v = n.cross(u);
        let mut flat = [[0.0; 2]; 8];
        for (f, p) in flat.iter_mut().zip(points) {
            let d = *p - origin;
            *f = [d.dot(u), d.dot(v)];
        }
        let mut polygon = Self {
            origin,
            u,
            v,
            points: [[0.0; 2]; POLYGON],
            len: 0,
        };
        polygon.set_hull(&mut flat);
        Some(polygon)
    }

    /// The polygon less the points that an opaque infinite plane of the scene hides from
    /// the light at `l`: a shadow ray from there crosses that plane first, whatever else
    /// is in its way (the light on one side, the point clearly on the other, the crossing
    /// clearly within the z rule).
    fn in_light<S: Scalar>(self, scene: &Parts<'_, S>, l: Vec3<Geo>, receiver: &Object<S>) -> Self {
        let mut polygon = self;
        for object in scene.objects {
            let Some(plane) = object.infinite_plane() else {
                continue;
            };
            if core::ptr::eq(object, receiver) || !opaque(scene, object) {
                continue;
            }
            let n = plane.unit_normal.to_geo();
            let offset = plane.n_dot_point.to_geo();
            let reach = polygon.reach().max(norm_1(l)) + 1.0;
            let margin = 2e-3 * reach + 256.0 * plan::resolution(scene.camera);
            let above = n.dot(l) - offset;
            if !(geometry::abs(above) > margin) {
                continue;
            }
            let (side, height) = (if above > 0.0 { 1.0 } else { -1.0 }, geometry::abs(above));
            // Kept: near or on the light's side of the plane (`d(P) >= -margin`, `d` the
            // distance on the light's side)...
            if polygon.holds(n * side, margin - side * offset) {
                continue;
            }
            let lit = polygon.clipped(n * side, margin - side * offset);
            // ... or where the crossing `C = (h P - d(P) L) / (h - d(P))` may break the z
            // rule: `h (P.z - zl) - d(P) (L.z - zl) > -margin (h + |L.z - zl| + 1)`.
            let lz = l.z - scene.z_limit;
            let a = Vec3::new(0.0, 0.0, height) - n * (side * lz);
            let b = -height * scene.z_limit
                + side * offset * lz
                + margin * (height + geometry::abs(lz) + 1.0);
            let near = polygon.clipped(a, b);
            // Mostly one of them is empty (no hull to take).
            polygon = match (lit.len, near.len) {
                (_, 0) => lit,
                (0, _) => near,
                _ => lit.union(&near).unwrap_or(polygon),
            };
        }
        polygon
    }

    /// The part in the pyramid of the points `l + s (V - l)`, `s >= 1`, `V` in the convex
    /// octagon `octagon` (its corners in order round it).
    fn in_pyramid(self, l: Vec3<Geo>, octagon: &[Vec3<Geo>; 8]) -> Self {
        let middle = octagon.iter().fold(Vec3::ZERO, |s, &v| s + v) * 0.125;
        let axis = middle - l;
        // Beyond the octagon's plane: `axis . (P - l) >= |axis|^2`.
        let mut polygon = self.clipped(axis, -axis.dot(l) - axis.dot(axis));
        for (i, &v) in octagon.iter().enumerate() {
            let next = octagon.get((i + 1) % 8).copied().unwrap_or(v);
            // The side through `l`, `v` and `next`, facing the middle.
            let mut side = (v - l).cross(next - l);
            if side.dot(axis) < 0.0 {
                side = -side;
            }
            polygon = polygon.clipped(side, -side.dot(l));
        }
        polygon
    }

    /// Whether every corner has `a . P + b >= 0` (clipping would change nothing).
    fn holds(&self, a: Vec3<Geo>, b: Geo) -> bool {
        let (a2, b2) = ([a.dot(self.u), a.dot(self.v)], a.dot(self.origin) + b);
        let corners = self.points.get(..self.len).unwrap_or(&[]);
        corners
            .iter()
            .all(|p| a2[0] * p[0] + a2[1] * p[1] + b2 >= 0.0)
    }

    /// The part where `a . P + b >= 0` (Sutherland and Hodgman's step).
    fn clipped(&self, a: Vec3<Geo>, b: Geo) -> Self {
        let (a2, b2) = ([a.dot(self.u), a.dot(self.v)], a.dot(self.origin) + b);
        let f = |p: [Geo; 2]| a2[0] * p[0] + a2[1] * p[1] + b2;
        let mut out = Self { len: 0, ..*self };
        let corners = self.points.get(..self.len).unwrap_or(&[]);
        for (i, &p) in corners.iter().enumerate() {
            let q = corners.get((i + 1) % self.len).copied().unwrap_or(p);
            let (fp, fq) = (f(p), f(q));
            if fp >= 0.0 {
                out.push(p);
            }
            if (fp >= 0.0) != (fq >= 0.0) {
                let t = fp / (fp - fq);
                out.push([p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t]);
            }
        }
        out
    }

    /// The hull of both (in the same plane); `None` when the corners do not fit. Out of
    /// line: its 32 corners would sit in the plane clip's frame (the micro:bit's stack).
    #[inline(never)]
    fn union(&self, other: &Self) -> Option<Self> {
        let mut all = [[0.0; 2]; 2 * POLYGON];
        let count = self.len + other.len;
        let mut slots = all.iter_mut();
        for (slot, p) in (&mut slots).zip(self.points.iter().take(self.len)) {
            *slot = *p;
        }
        for (slot, p) in slots.zip(other.points.iter().take(other.len)) {
            *slot = *p;
        }
        let mut union = Self { len: 0, ..*self };
        union.set_hull(all.get_mut(..count)?);
        (union.len <= POLYGON).then_some(union)
    }

    /// Adds a corner (dropped past the capacity: callers keep below it).
    fn push(&mut self, p: [Geo; 2]) {
        if let Some(slot) = self.points.get_mut(self.len) {
            *slot = p;
            self.len += 1;
        }
    }

    /// Sets the corners to the convex hull of `points` (Andrew's monotone chain; the
    /// points are sorted in place).
    fn set_hull(&mut self, points: &mut [[Geo; 2]]) {
        sort_points(points);
        self.len = 0;
        let turn = |o: [Geo; 2], a: [Geo; 2], b: [Geo; 2]| {
            (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
        };
        // Lower chain left to right, then upper chain right to left.
        for pass in 0..2 {
            let start = self.len;
            let ordered: &mut dyn Iterator<Item = &[Geo; 2]> = if pass == 0 {
                &mut points.iter()
            } else {
                &mut points.iter().rev()
            };
            for &p in ordered {
                while self.len >= start + 2 {
                    let (Some(&o), Some(&a)) =
                        (self.points.get(self.len - 2), self.points.get(self.len - 1))
                    else {
                        break;
                    };
                    if turn(o, a, p) > 0.0 {
                        break;
                    }
                    self.len -= 1;
                }
                self.push(p);
            }
            // The last of each chain is the first of the other.
            self.len = self.len.saturating_sub(1);
        }
        // All the points one: that point.
        if let (0, Some(&p)) = (self.len, points.first()) {
            self.push(p);
        }
    }

    /// At least the largest `|p|_1` of the corners (a larger margin keeps more: safe).
    fn reach(&self) -> Geo {
        // `|origin + x u + y v|_1 <= |origin|_1 + |x| |u|_1 + |y| |v|_1`: no corner built.
        let (u, v) = (norm_1(self.u), norm_1(self.v));
        let corners = self.points.get(..self.len).unwrap_or(&[]);
        let farthest = corners
            .iter()
            .map(|p| geometry::abs(p[0]) * u + geometry::abs(p[1]) * v)
            .fold(0.0, Geo::max);
        norm_1(self.origin) + farthest
    }

    /// The corners in space, into `out`.
    fn corners<'o>(&self, out: &'o mut [Vec3<Geo>; POLYGON]) -> &'o [Vec3<Geo>] {
        for (o, p) in out.iter_mut().zip(self.points.iter().take(self.len)) {
            *o = self.origin + self.u * p[0] + self.v * p[1];
        }
        out.get(..self.len).unwrap_or(&[])
    }
}

/// Sorts points by `x`, then `y` (`total_cmp`): an insertion sort, for the few dozen
/// corners a hull is made of. The library's `sort_unstable_by` took 11.8 KB of the
/// micro:bit's film firmware; points that compare equal are the same bits, so any sort
/// leaves the same order.
fn sort_points(points: &mut [[Geo; 2]]) {
    let out_of_order =
        |a: &[Geo; 2], b: &[Geo; 2]| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])).is_gt();
    for i in 1..points.len() {
        let mut j = i;
        while let (Some(a), Some(b)) = (points.get(j.wrapping_sub(1)), points.get(j)) {
            if !out_of_order(a, b) {
                break;
            }
            points.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// `|v|_1`.
fn norm_1(v: Vec3<Geo>) -> Geo {
    geometry::abs(v.x) + geometry::abs(v.y) + geometry::abs(v.z)
}

/// A sphere holding `points`: their mean and the farthest one's distance from it (for a
/// regular `octagon`, every corner's: one root, widened by a millionth for its rounding).
fn bounding_sphere(points: &[Vec3<Geo>; 8], octagon: bool) -> (Vec3<Geo>, Geo) {
    let sum = points.iter().fold(Vec3::ZERO, |s, &p| s + p);
    let center = sum * 0.125;
    if octagon {
        let corner = points.first().map_or(0.0, |&p| (p - center).length());
        return (center, corner * (1.0 + geometry::allowance(1e-6, 1e-5)));
    }
    let radius = points
        .iter()
        .map(|&p| (p - center).length())
        .fold(0.0, Geo::max);
    (center, radius)
}

/// Whether a point `P` of the ball `receiver` can see a light at `l` across the ball
/// `object`: whether `receiver` meets the cone of the rays from `l` through `object`,
/// beyond the nearest point of `object`.
fn may_meet(l: Vec3<Geo>, object: (Vec3<Geo>, Geo), receiver: (Vec3<Geo>, Geo)) -> bool {
    let (a, b) = (object.0 - l, receiver.0 - l);
    let (da, db) = (a.length(), b.length());
    let (ra, rb) = (object.1, receiver.1);
    // The light inside either ball: no cone to go by.
    if !(da > ra && db > rb) {
        return true;
    }
    // All of the receiver nearer the light than any of the object.
    if db + rb < da - ra {
        return false;
    }
    // The angle between the centres against the sum of the half-angles both subtend.
    let (sa, sb) = (ra / da, rb / db);
    let (ca, cb) = (geometry::sqrt(1.0 - sa * sa), geometry::sqrt(1.0 - sb * sb));
    let cos_sum = ca * cb - sa * sb;
    let cos_between = a.dot(b) / (da * db);
    !(cos_between < cos_sum - geometry::allowance(1e-9, 1e-5))
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_graphics::prelude::PointsIter;
    use proptest::prelude::*;

    /// The hull's insertion sort leaves points in the order the library's sort does, with
    /// repeated points, both zeros and values of every size.
    #[test]
    fn points_sorted_as_the_library_sorts_them() {
        let mut seed = 7u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for n in 0..40 {
            let mut points: std::vec::Vec<[Geo; 2]> = (0..n)
                .map(|_| {
                    let mut c = || match next() % 5 {
                        0 => 0.0,
                        1 => -0.0,
                        2 => (next() % 4) as Geo,
                        _ => (next() % 2_000) as Geo / 7.0 - 150.0,
                    };
                    [c(), c()]
                })
                .collect();
            let mut sorted = points.clone();
            sorted.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
            sort_points(&mut points);
            let bits = |v: &[[Geo; 2]]| {
                v.iter()
                    .map(|p| p.map(Geo::to_bits))
                    .collect::<std::vec::Vec<_>>()
            };
            assert_eq!(bits(&points), bits(&sorted));
        }
    }

    fn rectangle() -> impl Strategy<Value = Rectangle> {
        (-10..70i32, -10..50i32, 0..40u32, 0..30u32)
            .prop_map(|(x, y, w, h)| Rectangle::new(Point::new(x, y), Size::new(w, h)))
    }

    fn check<const N: usize>(added: &[Rectangle], border: u16) -> Result<(), TestCaseError> {
        let size = Size::new(64, 48);
        let mut region = Region::<N>::new(size).with_border(border);
        for &r in added {
            region.add(r);
        }
        let mut count = [[0u8; 64]; 48];
        for r in region.rectangles() {
            for p in r.points() {
                prop_assert!(
                    p.x >= 0 && p.y >= 0 && p.x < 64 && p.y < 48,
                    "{p:?} off screen"
                );
                count[p.y as usize][p.x as usize] += 1;
            }
        }
        let traced: u32 = count.iter().flatten().map(|&c| u32::from(c)).sum();
        prop_assert_eq!(traced, region.pixels());
        for (y, row) in count.iter().enumerate() {
            for (x, &c) in row.iter().enumerate() {
                prop_assert!(c <= 1, "({x}, {y}) traced {c} times");
                let b = i32::from(border);
                let asked = added.iter().any(|r| {
                    let grown = Rectangle::new(
                        r.top_left - Point::new(b, b),
                        r.size + Size::new(2 * u32::from(border), 2 * u32::from(border)),
                    );
                    !r.is_zero_sized() && grown.contains(Point::new(x as i32, y as i32))
                });
                prop_assert!(!asked || c == 1, "({x}, {y}) asked for, not in the region");
            }
        }
        Ok(())
    }

    proptest! {
        /// Every pixel asked for is in the region once, whatever the capacity.
        #[test]
        fn every_pixel_once(added in prop::collection::vec(rectangle(), 0..12), border in 0..3u16) {
            check::<1>(&added, border)?;
            check::<3>(&added, border)?;
            check::<16>(&added, border)?;
        }
    }

    proptest! {
        /// The pixels about the image of every point of a hull are in the region (its
        /// corners' cut keeps its box's margins: half a pixel on each side).
        #[test]
        fn a_hull_keeps_the_pixels_about_its_points(
            eye in eye(),
            points in hull_points(1),
            mix in prop::collection::vec(prop::collection::vec(0.0..1.0f64, 9), 40),
            border in 0..2u16,
        ) {
            const W: u16 = 64;
            const H: u16 = 48;
            let region = hull_region(eye, &points, Region::new(Size::new(64, 48)).with_border(border));
            let traced = traced(&region);
            prop_assert!(traced.iter().flatten().all(|&c| c <= 1));
            for weights in &mix {
                let total: f64 = weights.iter().take(points.len()).sum();
                prop_assume!(total > 1e-3);
                let q = points
                    .iter()
                    .zip(weights)
                    .fold(Vec3::ZERO, |q, (&p, &w)| q + p * (w / total));
                let [x, y] = pixel(eye, q);
                // The pixels on the screen whose anti-aliased samples can lie on it (within
                // half a pixel), and those within the border of them (a pixel off the
                // screen changes no neighbour's supersampling: it is not there).
                let on_screen = |px: f64, py: f64| {
                    (0.0..f64::from(W)).contains(&px) && (0.0..f64::from(H)).contains(&py)
                };
                let [x0, x1] = [libm::ceil(x - 0.5), libm::floor(x + 0.5)];
                let [y0, y1] = [libm::ceil(y - 0.5), libm::floor(y + 0.5)];
                let b = i32::from(border);
                for (cx, cy) in [(x0, y0), (x1, y1), (x0, y1), (x1, y0)] {
                    if !on_screen(cx, cy) {
                        continue;
                    }
                    for (dx, dy) in (-b..=b).flat_map(|dx| (-b..=b).map(move |dy| (dx, dy))) {
                        let (px, py) = (cx + f64::from(dx), cy + f64::from(dy));
                        if on_screen(px, py) {
                            prop_assert_eq!(
                                traced[py as usize][px as usize], 1,
                                "pixel ({}, {}) of point ({}, {}) left out", px, py, x, y
                            );
                        }
                    }
                }
            }
        }
    }

    proptest! {
        /// The pixels about the image of every point of a ball are in its outline.
        #[test]
        fn a_ball_keeps_the_pixels_about_its_points(
            eye in eye(),
            center in (-6.0..14.0f64, -6.0..12.0f64, -30.0..-1.0f64),
            radius in 0.05..6.0f64,
            on in prop::collection::vec((-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), 40),
        ) {
            const W: u16 = 64;
            const H: u16 = 48;
            let c = Vec3::new(center.0, center.1, center.2);
            let Some(region) = ball_region(eye, c, radius, Region::new(Size::new(64, 48))) else {
                return Ok(());
            };
            let traced = traced(&region);
            for &(x, y, z) in &on {
                let d = Vec3::new(x, y, z);
                prop_assume!(d.length() > 1e-3);
                // A point on the ball, where a primary ray can reach it: before the eye
                // (a large ball near the eye reaches behind it).
                let q = c + d * (radius / d.length());
                if q.z >= eye.z {
                    continue;
                }
                let [x, y] = pixel(eye, q);
                // The pixels whose anti-aliased samples can lie on it.
                let [x0, x1] = [libm::ceil(x - 0.5), libm::floor(x + 0.5)];
                let [y0, y1] = [libm::ceil(y - 0.5), libm::floor(y + 0.5)];
                for (px, py) in [(x0, y0), (x1, y1), (x0, y1), (x1, y0)] {
                    if (0.0..f64::from(W)).contains(&px) && (0.0..f64::from(H)).contains(&py) {
                        prop_assert_eq!(
                            traced[py as usize][px as usize], 1,
                            "pixel ({}, {}) of point ({}, {}) left out", px, py, x, y
                        );
                    }
                }
            }
        }
    }

    /// A random eye before a 64 by 48 screen of 8 by 6 world units.
    fn eye() -> impl Strategy<Value = Vec3<f64>> {
        (0.0..8.0f64, 0.0..6.0f64, 2.0..12.0f64).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    /// `least` to 8 random points before the eye.
    fn hull_points(least: usize) -> impl Strategy<Value = std::vec::Vec<Vec3<f64>>> {
        prop::collection::vec((-6.0..14.0f64, -6.0..12.0f64, -30.0..1.5f64), least..9)
            .prop_map(|points| points.iter().map(|&(x, y, z)| Vec3::new(x, y, z)).collect())
    }

    /// The region of the hull of `points` on that screen seen from `eye`.
    fn hull_region(eye: Vec3<f64>, points: &[Vec3<f64>], region: Region<4>) -> Region<4> {
        use crate::camera::CameraDef;
        let def = CameraDef::new("c", [64, 48], [8.0, 6.0], [eye.x, eye.y, eye.z]);
        let scene: Scene<'_, f64, 1, 1, 1, 0, 64> =
            Scene::from_defs(&def, &[], &[], &[], &[]).unwrap();
        let points: std::vec::Vec<Vec3<Geo>> =
            points.iter().map(|&p| geometry::narrow(p)).collect();
        let mut region = region;
        region.add_hull(scene.camera(), &points, ScreenBox::ALL);
        region
    }

    /// The region of a ball's outline on that screen seen from `eye` (none where the eye
    /// is in or near it).
    fn ball_region(
        eye: Vec3<f64>,
        c: Vec3<f64>,
        radius: f64,
        region: Region<4>,
    ) -> Option<Region<4>> {
        use crate::camera::CameraDef;
        use crate::material::MaterialDef;
        use crate::object::ObjectDef;
        if (c - eye).length() <= radius * 1.01 {
            return None;
        }
        let def = CameraDef::new("c", [64, 48], [8.0, 6.0], [eye.x, eye.y, eye.z]);
        let ball = ObjectDef::sphere("b", "m", [c.x, c.y, c.z], radius);
        let scene: Scene<'_, f64, 1, 1, 1, 0, 64> =
            Scene::from_defs(&def, &[MaterialDef::new("m")], &[], &[], &[ball]).unwrap();
        let object = &scene.objects()[0];
        let mut octagon = [Vec3::ZERO; 8];
        assert!(plan::outline_octagon(scene.camera(), object, &mut octagon));
        let mut region = region;
        region.add_hull(
            scene.camera(),
            &octagon,
            plan::footprint(scene.camera(), object),
        );
        Some(region)
    }

    /// How often `region` traces each pixel of that screen.
    fn traced(region: &Region<4>) -> [[u8; 64]; 48] {
        let mut traced = [[0u8; 64]; 48];
        for r in region.rectangles() {
            for p in r.points() {
                traced[p.y as usize][p.x as usize] += 1;
            }
        }
        traced
    }

    /// Where the eye's ray through `q` meets that screen, in pixels.
    fn pixel(eye: Vec3<f64>, q: Vec3<f64>) -> [f64; 2] {
        let ahead = eye.z - q.z;
        let sx = eye.x + (q.x - eye.x) * eye.z / ahead;
        let sy = eye.y + (q.y - eye.y) * eye.z / ahead;
        [sx / (8.0 / 63.0), 47.0 - sy / (6.0 / 47.0)]
    }

    /// The direction of the one ray of pixel `(x, y)` of that screen: through its point.
    fn ray(eye: Vec3<f64>, x: u16, y: u16) -> Vec3<f64> {
        Vec3::new(
            f64::from(x) * 8.0 / 63.0,
            f64::from(47 - y) * 6.0 / 47.0,
            0.0,
        ) - eye
    }

    proptest! {
        /// With one ray a pixel, every pixel whose ray passes inside a hull is in the
        /// region, once.
        #[test]
        fn a_hull_keeps_the_pixels_whose_ray_meets_it(eye in eye(), points in hull_points(3)) {
            let one_ray = Region::new(Size::new(64, 48)).with_one_ray_a_pixel();
            let traced = traced(&hull_region(eye, &points, one_ray));
            prop_assert!(traced.iter().flatten().all(|&c| c <= 1));
            // Every point lies before the eye: a ray meets the hull where its screen
            // point lies in the hull of the points' screen points.
            let mut seen: std::vec::Vec<[f64; 2]> = points
                .iter()
                .map(|&q| {
                    let k = eye.z / (eye.z - q.z);
                    [eye.x + (q.x - eye.x) * k, eye.y + (q.y - eye.y) * k]
                })
                .collect();
            seen.sort_by(|a, b| a.partial_cmp(b).unwrap());
            let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
                (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
            };
            // Andrew's monotone chain, anticlockwise.
            let mut hull: std::vec::Vec<[f64; 2]> = std::vec::Vec::new();
            for pass in 0..2 {
                let start = hull.len();
                let order: std::vec::Vec<[f64; 2]> = if pass == 0 {
                    seen.clone()
                } else {
                    seen.iter().rev().copied().collect()
                };
                for p in order {
                    while hull.len() >= start + 2
                        && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
                    {
                        hull.pop();
                    }
                    hull.push(p);
                }
                hull.pop();
            }
            // Points in a line or one: no pixel's ray passes inside.
            if hull.len() < 3 {
                return Ok(());
            }
            for y in 0..48u16 {
                for x in 0..64u16 {
                    let d = ray(eye, x, y);
                    let p = [eye.x + d.x, eye.y + d.y];
                    // Inside every edge by more than rounding.
                    let inside = (0..hull.len()).all(|i| {
                        let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
                        let edge = libm::fabs(b[0] - a[0]) + libm::fabs(b[1] - a[1]);
                        cross(a, b, p) > 1e-9 * edge * (edge + 1.0)
                    });
                    if inside {
                        prop_assert_eq!(traced[y as usize][x as usize], 1, "pixel ({}, {}) left out", x, y);
                    }
                }
            }
        }
    }

    proptest! {
        /// With one ray a pixel, every pixel whose ray meets a ball is in its outline.
        #[test]
        fn a_ball_keeps_the_pixels_whose_ray_meets_it(
            eye in eye(),
            center in (-6.0..14.0f64, -6.0..12.0f64, -30.0..-1.0f64),
            radius in 0.05..6.0f64,
        ) {
            let c = Vec3::new(center.0, center.1, center.2);
            let one_ray = Region::new(Size::new(64, 48)).with_one_ray_a_pixel();
            let Some(region) = ball_region(eye, c, radius, one_ray) else {
                return Ok(());
            };
            let traced = traced(&region);
            for y in 0..48u16 {
                for x in 0..64u16 {
                    // The ray `e + t d`, `t > 0`, passes within the radius of the centre
                    // (less rounding), ahead of the eye.
                    let d = ray(eye, x, y);
                    let f = c - eye;
                    let t = f.dot(d) / d.dot(d);
                    let miss = (f - d * t).length();
                    if t > 0.0 && miss < radius * (1.0 - 1e-9) {
                        prop_assert_eq!(traced[y as usize][x as usize], 1, "pixel ({}, {}) left out", x, y);
                    }
                }
            }
        }
    }

    fn point() -> impl Strategy<Value = Vec3<f64>> {
        (-50.0..50.0f64, -50.0..50.0f64, -50.0..50.0f64).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    proptest! {
        /// A square about a point in a ball's shadow, clipped to the pyramid of the ball's
        /// octagon, still holds the point (on the shadow's edge too).
        #[test]
        fn a_panel_in_a_pyramid_keeps_the_shadow(
            l in point(),
            center in point(),
            r in 0.01..10.0f64,
            around in 0.0..1.0f64,
            s in prop_oneof![Just(1.0f64), 1.0..20.0f64],
            normal in point(),
            (half, x, y) in (0.01..20.0f64, -1.0..1.0f64, -1.0..1.0f64),
        ) {
            let mut octagon = [Vec3::ZERO; 8];
            let (c, light) = (geometry::narrow(center), geometry::narrow(l));
            prop_assume!(plan::cone_octagon(c, geometry::from_f64(r), light, &mut octagon));
            prop_assume!(normal.length() > 1e-3);
            // Where the geometry is `f32`, the ball shrunk by its rounding (every caller
            // widens it by at least 2.5e-4 of that reach), and a test of the clip's corners
            // with `f32`'s slack.
            let (r, slack) = if geometry::SINGLE {
                (r - 1e-4 * (center.length() + l.length() + r), 1e-6)
            } else {
                (r, 1e-9)
            };
            prop_assume!(r > 0.0);
            // A point on the circle where the cone touches the ball, seen beyond.
            let to = center - l;
            let d = to.length();
            let a = to * (1.0 / d);
            let u = a.cross(if libm::fabs(a.x) < 0.5 { Vec3::new(1.0, 0.0, 0.0) } else { Vec3::new(0.0, 1.0, 0.0) });
            let u = u * (1.0 / u.length());
            let w = a.cross(u);
            let phi = around * core::f64::consts::TAU;
            let touch = l + a * (d - r * r / d)
                + (u * libm::cos(phi) + w * libm::sin(phi)) * (r * libm::sqrt(d * d - r * r) / d);
            // Or, a tenth of the time, the ball's nearest point (where the pyramid begins).
            let q = if around < 0.1 { center - a * r } else { touch };
            let p = l + (q - l) * s;
            // A square in a random plane through it, the point anywhere in it.
            let n = normal * (1.0 / normal.length());
            let e1 = n.cross(if libm::fabs(n.x) < 0.5 { Vec3::new(1.0, 0.0, 0.0) } else { Vec3::new(0.0, 1.0, 0.0) });
            let e1 = e1 * (1.0 / e1.length());
            let e2 = n.cross(e1);
            let (origin, u, v) = (geometry::narrow(p), geometry::narrow(e1), geometry::narrow(e2));
            let mut square = Polygon { origin, u, v, points: [[0.0; 2]; POLYGON], len: 0 };
            for corner in [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]] {
                let at = |i: usize, by: f64| geometry::from_f64(half * (corner[i] - by));
                square.push([at(0, x), at(1, y)]);
            }
            let clipped = square.in_pyramid(light, &octagon);
            // The point (the plane's origin) inside every edge of what is left.
            let corners: std::vec::Vec<[f64; 2]> = clipped.points[..clipped.len]
                .iter()
                .map(|c| [geometry::to_f64(c[0]), geometry::to_f64(c[1])])
                .collect();
            prop_assert!(clipped.len >= 3, "{} corners left", clipped.len);
            for (i, &c) in corners.iter().enumerate() {
                let next = corners[(i + 1) % corners.len()];
                let edge = [next[0] - c[0], next[1] - c[1]];
                let cross = edge[0] * (0.0 - c[1]) - edge[1] * (0.0 - c[0]);
                let scale = (edge[0].abs() + edge[1].abs()) * (c[0].abs() + c[1].abs() + 1.0);
                prop_assert!(cross >= -slack * scale, "outside edge {i}: {cross}");
            }
        }
    }

    /// An umbra leaves its pixels out of its shadow's outline only when exactly two states
    /// of its ball were added, each with an umbra: where either has none, or a third state
    /// came, every pixel of the outline is traced.
    #[test]
    fn an_umbra_needs_both_states() {
        let key = UmbraKey::new(1, 0, 0).unwrap();
        let box_of = |left, top, right, bottom| Area {
            left,
            top,
            right,
            bottom,
        };
        let octagon = |area: Area| Octagon {
            area,
            cut: Corners {
                a: NonZeroU8::MIN,
                b: 1,
                sum: [0, u16::MAX],
                difference: [0, u16::MAX],
            },
        };
        let shadow = box_of(10, 10, 29, 19);
        // A state of the ball: counted, its shadow's outline, its umbra.
        let add = |region: &mut Region<4>, state: Option<Octagon>| {
            region.count_state(key.ball);
            region.add_umbra(key, state);
            region.push(shadow);
            region.keep(Outline {
                area: shadow,
                cut: None,
                umbra: region.umbra_place(key),
            });
        };
        let traced = |states: &[Option<Octagon>], split: bool| {
            let mut region = Region::<4>::new(Size::new(40, 30));
            let mut last = region.clone();
            for (i, &state) in states.iter().enumerate() {
                // With `split`, the first state as the last frame kept it.
                add(
                    if split && i == 0 {
                        &mut last
                    } else {
                        &mut region
                    },
                    state,
                );
            }
            region.add_region(&last);
            region.pixels()
        };
        let whole = shadow.pixels();
        let (a, b) = (
            octagon(box_of(12, 12, 25, 17)),
            octagon(box_of(14, 11, 27, 16)),
        );
        // Both states: the pixels in both umbras (columns 14-25 of rows 12-16) left out.
        let both = whole - 12 * 5;
        assert_eq!(traced(&[Some(a), Some(b)], false), both);
        assert_eq!(traced(&[Some(a), Some(b)], true), both);
        // A state without an umbra, one state only, or three: nothing left out.
        assert_eq!(traced(&[Some(a), None], true), whole);
        assert_eq!(traced(&[None, Some(b)], false), whole);
        assert_eq!(traced(&[Some(a)], false), whole);
        assert_eq!(traced(&[Some(a), Some(b), Some(a)], true), whole);
        // A third state whose shadow on this receiver has no outline (none filed): the
        // umbras of the other two say nothing about it.
        let mut region = Region::<4>::new(Size::new(40, 30));
        add(&mut region, Some(a));
        add(&mut region, Some(b));
        region.count_state(key.ball);
        assert_eq!(region.pixels(), whole);
    }

    /// An outline takes 20 bytes, cut or not, holding an umbra's shadow or not; an umbra 40.
    #[test]
    fn outlines_and_umbras_are_small() {
        assert_eq!(core::mem::size_of::<Outline>(), 20);
        assert_eq!(core::mem::size_of::<Umbra>(), 40);
    }

    #[test]
    fn no_room_is_the_whole_frame() {
        let mut region = Region::<0>::new(Size::new(8, 6));
        region.add(Rectangle::new(Point::new(1, 1), Size::new(2, 2)));
        assert!(region.is_whole());
        assert_eq!(region.pixels(), 48);
    }
}
