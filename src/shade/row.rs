//! Shading a row of primary rays that meet one plane at one `t`.
//!
//! Where a row's primary rays meet a plain plane whose normal has no x part (the floors and
//! walls of the course's scenes) they all meet it at the same `t` (see
//! [`RowTest::At`](crate::object::RowTest::At)), and their hit points differ only in `x`.
//! So do the rays of a segment of the row that lies in a rectangle's run of columns
//! ([`RowTest::AtAcross`](crate::object::RowTest::AtAcross)): there the rectangle, whose
//! surface look-up is its plane's, is the segment's plane (a textured one's colours are
//! then worked out by each pixel, the material's times its texel). So is a tiled plane
//! whose two materials differ in their colours only: each pixel finds its tile's.
//! Whatever reads only `y` and `z` is then the same at every pixel of the row, bit for bit:
//! the hit's `y` and `z`, the plane's surface look-up, each light's `L . n` (the normal has
//! no x part) and, in fixed point, whose sums of products are exact, the `y` and `z` share
//! of `|L|^2` ([`Scalar::positive_row_square`]), and the shadow test when every object a
//! shadow ray can meet ignores `x` too
//! ([`Object::hits_ignore_x`](crate::object::Object::hits_ignore_x)). [`RowShading`] works
//! those out once a row; each pixel computes the rest with the same operations as
//! [`Shader::primary_in_row`], so the pixels are the same:
//!
//! - when other objects of the row are tested ray by ray (a ball, a rectangle), each ray's
//!   closest hit is found first, and only the rays whose hit is the row's plane use the row;
//! - when an object that depends on `x` could block a light, each pixel tests that light's
//!   shadow ray itself; where shadow rays pass through transparent objects, it walks
//!   through them as [`Shader::shadow_filter`] does and takes their filters (rows with
//!   filters are shared only where every object that ignores `x` is an opaque plain plane,
//!   see `rows_take_filters`);
//! - where a light is a projector, each pixel finds its texel on the slide as
//!   `illuminate_divided` does, and its mirror rays go their own ways.
//!
//! Mirror rays off such a row differ only in `x` too (their base's and direction's `y` and
//! `z` are the row's), so when every object ignores `x`, all of them meet the same plane at
//! the same `t`, and the row's work repeats for them: up to [`ROW_LEVELS`] hits deep, then
//! each pixel's ray is traced alone. Not in `f64`, whose normalised primary rays differ in
//! every coordinate, nor with transparent objects (their filter walk and transmission
//! rays), a bounding-volume tree or more than [`ROW_LIGHTS`] lights.
//!
//! The row's fast case ([`RowShading::plain`]: every ray on the plane, every shadow
//! decided) costs spec0 about a third of the per-pixel path on a Cortex-M4F.

#[cfg(microray_small)]
use super::in_cone;
#[cfg(not(microray_small))]
use super::in_cone_within;
use super::{MAX_DEPTH, Onward, Path, Shader, add_diffuse, glint, reflect, with_ambient};
use crate::hits::{Among, closest_hit_among, closest_hit_in_row, object_blocks, row_plane_within};
use crate::light::Light;
#[cfg(not(microray_small))]
use crate::light::Spot;
use crate::material::MaterialId;
use crate::object::tiled_plane::TiledPlane;
use crate::object::{Hit, Object, RowEntry, RowOrigin, RowTest, Shape, Surface, TexPlane};
use crate::plan::ShadowBoxes;
use crate::ray::Ray;
use crate::scalar::Scalar;
#[cfg(not(microray_small))]
use crate::scalar::geometry::Geo;
use crate::vec3::Vec3;
use core::ops::ControlFlow;

mod shadows;
pub(crate) use shadows::RowShadows;

/// The most lights a [`RowShading`] holds (a scene with more shades each pixel alone).
pub const ROW_LIGHTS: usize = 4;

/// The most hits along a row's rays (the primary hit, then mirror hits) that a
/// [`RowShading`] prepares; deeper mirror rays are traced pixel by pixel. Two: the floor
/// and what its mirror shows, at about 190 bytes of stack a level.
pub const ROW_LEVELS: usize = 2;

/// A light that reaches a level's hits: what it contributes that is the same along the row.
#[derive(Clone, Copy, Debug)]
struct RowLight<'s, S: Scalar> {
    light: &'s Light<S>,
    /// Its place in the scene's list (for the render plan's shadow boxes).
    number: u8,
    /// `L . n`, above zero.
    cos_d: S::Wide,
    /// `L`'s `y` and `z`, the same at every hit of the level, and what their squares share
    /// ([`Scalar::row_squares`]).
    to_y: S,
    to_z: S,
    squares: u64,
    /// The surface's diffuse times the light's.
    lit: Vec3<S>,
    /// Whether each pixel tests its shadow ray (some object in the way may depend on `x`);
    /// else the light is known to reach the whole row.
    shadow_per_pixel: bool,
    /// A spotlight's span of the `x` of the way from it to a hit (`-L`, whose `y` and `z`
    /// are the row's), as the keys of its ends ([`Scalar::order_key`]: two bytes each, in
    /// the record's padding in Q16.16): beyond them the hit is certainly outside the cone
    /// (see [`cone_span`]). Not built for size (flash).
    #[cfg(not(microray_small))]
    cone: [i16; 2],
}

/// Where a level's mirror rays go.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mirror {
    /// To the next level's plane.
    Level,
    /// No mirror rays: the surface is no mirror.
    None,
    /// Nowhere: they meet nothing.
    Nothing,
    /// Each pixel's own way (traced alone).
    Trace,
}

/// The hits of a row's rays at one depth: one plain plane, one `t`.
#[derive(Clone, Debug)]
struct Level<'s, S: Scalar> {
    index: usize,
    t: S,
    /// The row's hit (`ray.at(t)`, as every kind's surface takes it, for the row's ray): its
    /// `y` and `z` are every pixel's.
    surface: Surface<'s, S>,
    /// The lights in front of the plane and not known to be blocked along the row.
    lights: heapless::Vec<RowLight<'s, S>, ROW_LIGHTS>,
    mirror: Mirror,
    /// Whether the lights add glints.
    glints: bool,
    /// Whether the surface has ambient light.
    ambient: bool,
    /// Whether the surface is transparent.
    transparent: bool,
    /// Whether some lights' shadow rays are tested by each pixel.
    shadows_per_pixel: bool,
    /// Whether the row decided only the objects that ignore `x` for its lights: each
    /// segment of the row learns from the shadow boxes which lights its pixels test.
    by_boxes: bool,
    /// A textured rectangle's texture or a tiled plane's tiles: each pixel finds its
    /// ambient and diffuse colours (the lights' `lit` is then not used).
    pattern: Option<Pattern<'s, S>>,
}

/// Where a level's colours change from pixel to pixel (the rest of its surface does not).
#[derive(Clone, Copy, Debug)]
enum Pattern<'s, S: Scalar> {
    /// A textured rectangle: the material's colours times the texel under the hit.
    Texture(&'s TexPlane<S>),
    /// A tiled plane whose two materials differ in their colours only (see
    /// `Shader::tiles_ambient`), and its material: the colours of the tile under the hit.
    /// (The materials are looked up by each pixel: held here, they made the levels of
    /// every row larger, and Q16.16's plane rows 1.3 % dearer on the Cortex-M4F.)
    Tiles(&'s TiledPlane<S>, MaterialId),
}

/// The rays of one row meeting one plain plane at one `t`, and their mirror rays the next
/// ones, with what is the same at each level's hits worked out once (see the module's
/// docs).
#[derive(Clone, Debug)]
pub struct RowShading<'s, S: Scalar> {
    levels: heapless::Vec<Level<'s, S>, ROW_LEVELS>,
    /// Whether some objects of the row are tested ray by ray (else every ray meets the first
    /// level's plane).
    tested: bool,
    /// Whether the first level's colours change from pixel to pixel (see `Level::pattern`).
    textured: bool,
    /// Whether the pixels that test a light's shadow ray walk through transparent objects,
    /// taking their filters (as [`Shader::shadow_filter`] walks).
    filtered: bool,
    /// Whether a light is a projector, whose light each pixel finds on its slide: the row
    /// has one level (the pixels' mirror rays go their own ways), is never plain, and takes
    /// the filtered copies of the level's body (`filtered` is set), which find the texels.
    projected: bool,
}

/// What a pixel's shadow ray towards a light finds.
#[derive(Clone, Copy, Debug)]
enum Reach<S> {
    /// An opaque object: no light.
    Blocked,
    /// Nothing: the light's whole colour (a filter of ones, whose products are exact).
    Clear,
    /// Transparent objects only: their filters' product.
    Through(Vec3<S>),
}

impl<S: Scalar> RowShading<'_, S> {
    /// Whether a light is a projector: each pixel finds its texel on the slide.
    pub fn projected(&self) -> bool {
        self.projected
    }

    /// Whether every ray of the row meets the row's plane (no object is tested ray by ray)
    /// and the row decides every shadow ray there: the row's fast case.
    pub fn plain(&self) -> bool {
        self.plain_unprojected() && !self.projected
    }

    /// [`plain`](Self::plain) for a row no projector lights.
    #[inline(always)]
    fn plain_unprojected(&self) -> bool {
        !self.tested
            && !self
                .levels
                .first()
                .is_some_and(|level| level.shadows_per_pixel)
            && !self.textured
    }
}

impl<S: Scalar> RowShading<'_, S> {
    /// Takes whether some objects are tested ray by ray in the segment of the row that
    /// starts at column `first` from `tests`, the row's tests with the entries that cannot
    /// be met there turned to misses, and runs of columns ([`RowTest::AtAcross`]) that the
    /// segment lies in or out of whole: the levels are the same along the whole row (they
    /// come from its planes at one `t`, which no segment changes).
    pub(crate) fn set_tested(&mut self, tests: &[RowEntry<S>], first: u16) {
        #[cfg(any(not(feature = "plan"), microray_small))]
        let _ = first;
        self.tested = tests.iter().any(|entry| match entry.test {
            RowTest::Miss | RowTest::At(_) => false,
            #[cfg(all(feature = "plan", not(microray_small)))]
            RowTest::AtAcross {
                first: from, last, ..
            } => from <= first && first <= last,
            _ => true,
        });
    }

    /// Sets which lights' shadow rays the pixels of row `y`, columns `first..=last`, test
    /// on the row's plane: those whose shadow boxes of objects that depend on `x` hold them
    /// (a row made with `by_boxes`; the others test every light that needs it). Out of
    /// line: once a segment, and in line it deepened the micro:bit's stack.
    #[inline(never)]
    pub(crate) fn set_segment(&mut self, boxes: &ShadowBoxes, y: u16, first: u16, last: u16) {
        let Some(level) = self.levels.first_mut() else {
            return;
        };
        if !level.by_boxes {
            return;
        }
        let own = level.index;
        let mut any = false;
        for lit in &mut level.lights {
            lit.shadow_per_pixel = boxes.may_block(usize::from(lit.number), own, y, first, last);
            any |= lit.shadow_per_pixel;
        }
        level.shadows_per_pixel = any;
    }

    /// Whether the row is [plain](Self::plain) and its one level neither mirrors, lets
    /// light through nor glints: each pixel's colour is its lights' diffuse light and the
    /// ambient, with no branch on those (a loop of its own: fplane0, aademo, spotlight).
    pub(crate) fn bare(&self) -> bool {
        match self.levels.as_slice() {
            [level] => {
                level.mirror == Mirror::None
                    && !level.transparent
                    && !level.glints
                    && level.pattern.is_none()
            }
            _ => false,
        }
    }

    /// The plane the row's primary rays meet at one `t` (those that meet nothing nearer).
    pub(crate) fn first_plane(&self) -> Option<usize> {
        self.levels.first().map(|level| level.index)
    }

    /// The object every ray of the row meets first, when no other object of the row is
    /// tested ray by ray.
    pub fn plane(&self) -> Option<usize> {
        if self.tested {
            None
        } else {
            self.levels.first().map(|level| level.index)
        }
    }
}

impl<'s, S: Scalar> Shader<'s, S> {
    /// The shading of a row whose prepared tests (`row`, for rays from `origin`) put a plain
    /// plane at one `t` for every ray (the rays that meet nothing nearer see it), or `None`
    /// for a row that is not like that (shade each pixel with
    /// [`primary_in_row`](Self::primary_in_row)).
    pub fn row_shading(
        &self,
        row: &[RowEntry<S>],
        origin: &RowOrigin<S>,
    ) -> Option<RowShading<'s, S>> {
        let mut shading = None;
        if self.shares_rows() {
            self.shared_row_shading(&mut shading, row, origin, false, None);
        }
        shading
    }

    /// Whether this shader's rows can be shaded together at all: not in `f64` (the
    /// course's order), not with a tree, at most [`ROW_LIGHTS`] lights, no projector built
    /// for size (its light changes with its slide's texel from pixel to pixel: each pixel
    /// finds it, see [`RowShading::projected`]), no shadows through transparent objects
    /// unless the row can take their filters. It holds or not for a whole render: a
    /// renderer asks once.
    pub(crate) fn shares_rows(&self) -> bool {
        let shadows = self.stages.illumination && self.stages.shadows;
        !S::COURSE_ORDER
            && self.tree().is_none()
            && self.lights.len() <= ROW_LIGHTS
            // Built for size, no projector's copy of the levels (flash).
            && !(cfg!(microray_small) && self.projects())
            && !(shadows && self.stages.filtered_shadows && !self.rows_take_filters())
    }

    /// Whether rows can be shaded together where shadow rays take transparent objects'
    /// filters: not built for size (flash), and every object that ignores `x` (those the
    /// row decides once for all its pixels) is an infinite plane, plain or tiled, of opaque
    /// materials. Where the row finds such a plane in the way, a pixel's walk ends at it
    /// too (whichever tile it meets); where it finds none, a pixel's walk meets only the
    /// objects that depend on `x`, which the pixels whose shadow boxes hold them walk
    /// through themselves.
    fn rows_take_filters(&self) -> bool {
        if cfg!(microray_small) || !cfg!(feature = "transparency") {
            return false;
        }
        let opaque = |id| {
            self.palette
                .material(id)
                .is_some_and(|m| m.transparency == S::ZERO)
        };
        let mut all_opaque = true;
        self.among.each(self.objects, |_, object| {
            let opaque_plane = match object.shape() {
                Shape::Plane(_) => opaque(object.material()),
                Shape::TiledPlane(tiled) => opaque(object.material()) && opaque(tiled.altmaterial),
                _ => false,
            };
            if object.hits_ignore_x() && !opaque_plane {
                all_opaque = false;
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        all_opaque
    }

    /// [`row_shading`](Self::row_shading) for a shader whose rows can be shared
    /// ([`shares_rows`](Self::shares_rows)), made in `slot`; `within`, for the columns
    /// `[first, last]` of the row only, where the runs of columns that hold them all are
    /// planes at one `t` (see [`row_plane_within`]). `slot` is `None` after where the row
    /// is not shaded together. In place: returned by value, the shading (several hundred
    /// bytes) was copied once a row, 3-7 instructions a pixel at 160 columns on the
    /// Cortex-M4F.
    pub(crate) fn shared_row_shading(
        &self,
        slot: &mut Option<RowShading<'s, S>>,
        row: &[RowEntry<S>],
        origin: &RowOrigin<S>,
        by_boxes: bool,
        within: Option<[u16; 2]>,
    ) {
        let Some((mut index, mut t, tested)) = row_plane_within(row, within) else {
            *slot = None;
            return;
        };
        let shadows = self.stages.illumination && self.stages.shadows;
        // A ray of the row in all but `x`, whose hits have the row's `y` and `z`.
        let mut ray = Ray::new(origin.eye, Vec3::new(S::ZERO, origin.dy, origin.dz));
        let all_ignore_x = self.all_ignore_x();
        let projected = self.projects();
        // Built in place, level by level (copies of levels and lights were most of the
        // stack this set-up took).
        let shading = slot.insert(RowShading {
            levels: heapless::Vec::new(),
            tested,
            textured: false,
            // A projector's rows take the filtered copies of the level's body, which find
            // each pixel's texel (with no transparent object a walk's filter is ones, which
            // change no product): no copies of their own (flash).
            filtered: shadows && self.filters_shadows() || projected,
            projected,
        });
        // The levels, until one ends the row's shading (`None`: the row is not shaded
        // together, and the half-made shading goes).
        let made = (|| loop {
            let object = self.objects.get(index)?;
            // A textured rectangle's run or a tiled plane: the primary rays' level only, its
            // colours found by each pixel (not built for size).
            let first = shading.levels.is_empty() && !cfg!(microray_small);
            // And whether either tile's material has ambient light.
            let (pattern, tiles_ambient) = match object.shape() {
                Shape::TexPlane(textured) if first => (Some(Pattern::Texture(textured)), false),
                Shape::TiledPlane(tiled) if first => match self.tiles_ambient(object, tiled) {
                    Some(ambient) => (Some(Pattern::Tiles(tiled, object.material())), ambient),
                    None => (None, false),
                },
                _ => (None, false),
            };
            if !object.surface_is_uniform() && pattern.is_none() {
                match shading.levels.last_mut() {
                    // The pixels' mirror rays go their own ways from here.
                    Some(Level { mirror, .. }) => *mirror = Mirror::Trace,
                    None => return None,
                }
                break Some(());
            }
            let surface = object.surface(&self.palette, &ray, t)?;
            let shadow_per_pixel = shadows && !(all_ignore_x || self.shadows_ignore_x(index));
            // The primary rays' plane: the render plan's shadow boxes tell each segment of
            // the row which lights its pixels test.
            let by_boxes = by_boxes && shadow_per_pixel && shading.levels.is_empty();
            let (point, normal) = (surface.hit.point, surface.hit.normal);
            let material = surface.material;
            let full = shading.levels.len() + 1 == ROW_LEVELS;
            // Cannot fail: a level is added only below the capacity.
            shading
                .levels
                .push(Level {
                    index,
                    t,
                    surface,
                    lights: heapless::Vec::new(),
                    mirror: Mirror::None,
                    glints: cfg!(feature = "glint")
                        && self.stages.glints
                        && material.shininess != S::ZERO,
                    ambient: !surface.material.ambient.is_zero() || tiles_ambient,
                    transparent: self.transmits(material),
                    shadows_per_pixel: shadow_per_pixel,
                    by_boxes,
                    pattern,
                })
                .ok()?;
            shading.textured |= pattern.is_some();
            let level = shading.levels.last_mut()?;
            self.row_lights(level, shadows, shadow_per_pixel, by_boxes);
            if !self.mirrors(material) {
                break Some(());
            }
            if full || !all_ignore_x || projected {
                level.mirror = Mirror::Trace;
                break Some(());
            }
            // The mirror rays: `y` and `z` of base and direction are the row's.
            ray = Ray::new(point, reflect(ray.dir, normal));
            let next = closest_hit_among(
                self.objects,
                &self.among,
                &ray,
                Some(index),
                S::UNBOUNDED,
                self.z_limit,
            );
            let Some((next_index, next_t)) = next else {
                level.mirror = Mirror::Nothing;
                break Some(());
            };
            level.mirror = Mirror::Level;
            (index, t) = (next_index, next_t);
        })();
        if made.is_none() {
            *slot = None;
        }
    }

    /// Adds to `level` the lights that can reach its surface along the row; shadow rays are
    /// tested once for the row, or by each pixel when `shadow_per_pixel`; `by_boxes`, the
    /// objects that ignore `x` are tested once for the row, and the others by each pixel.
    fn row_lights(
        &self,
        level: &mut Level<'s, S>,
        shadows: bool,
        shadow_per_pixel: bool,
        by_boxes: bool,
    ) {
        let (surface, index) = (&level.surface, level.index);
        let (point, normal) = (surface.hit.point, surface.hit.normal);
        if !self.stages.illumination {
            return;
        }
        let filtered = shadows && self.filters_shadows();
        for (number, light) in self.lights.iter().enumerate() {
            let to_light = light.location - point;
            let Some(cos_d) = S::positive_dot_unit(to_light, normal) else {
                continue;
            };
            if shadows && !shadow_per_pixel && self.blocked(point, to_light, index, light) {
                continue;
            }
            // Its place in the list, for the shadow boxes.
            let mut number = u8::try_from(number).unwrap_or(u8::MAX);
            if by_boxes && self.blocked_ignoring_x(point, to_light, index) {
                if !filtered {
                    continue;
                }
                // A pixel's walk may first pass through a transparent object that depends
                // on `x` and step on from it: it is left to each pixel, at every column (no
                // light has this number's boxes).
                number = u8::MAX;
            }
            let lit = surface.diffuse.mul_each(light.diffuse_emissivity);
            let (to_y, to_z) = (light.location.y - point.y, light.location.z - point.z);
            #[cfg(not(microray_small))]
            let cone = match light.spot.as_ref() {
                Some(spot) if cfg!(feature = "spotlight") => {
                    cone_span(spot, -to_y, -to_z).map(S::order_key)
                }
                _ => [i16::MIN, i16::MAX],
            };
            // Cannot fail: the row's shading is only made for at most `ROW_LIGHTS` lights.
            let _ = level.lights.push(RowLight {
                light,
                number,
                cos_d,
                to_y,
                to_z,
                squares: S::row_squares(to_y, to_z),
                lit,
                shadow_per_pixel,
                #[cfg(not(microray_small))]
                cone,
            });
        }
    }

    /// The colour seen along a primary ray of a row prepared by
    /// [`row_shading`](Self::row_shading) from the row's tests `tests`: what
    /// [`primary_in_row`](Self::primary_in_row) gives. `shadows` are the row's (or the
    /// segment's) shadow tests as [`prepare_row_shadows`](Self::prepare_row_shadows) leaves
    /// them (unprepared, each pixel tests its shadow rays against every object).
    #[inline]
    #[cfg_attr(not(feature = "antialias"), allow(dead_code))]
    pub(crate) fn shade_in_row(
        &self,
        row: &RowShading<'s, S>,
        shadows: &RowShadows<'s, S>,
        tests: &[RowEntry<S>],
        ray: &Ray<S>,
    ) -> Vec3<S> {
        if row.projected {
            self.shade_in_row_of::<true>(row, shadows, tests, ray)
        } else {
            self.shade_in_row_of::<false>(row, shadows, tests, ray)
        }
    }

    /// [`shade_in_row`](Self::shade_in_row) for a row that is lit by a projector or not
    /// (`PROJECTED`, as [`RowShading::projected`] says): a row's loop asks once, not for
    /// every pixel (spec0 and basic 1 to 2 % dearer on the Cortex-M4F).
    #[inline]
    pub(crate) fn shade_in_row_of<const PROJECTED: bool>(
        &self,
        row: &RowShading<'s, S>,
        shadows: &RowShadows<'s, S>,
        tests: &[RowEntry<S>],
        ray: &Ray<S>,
    ) -> Vec3<S> {
        if row.tested {
            self.shade_in_tested_row(row, shadows, tests, ray)
        } else if !PROJECTED && row.plain_unprojected() {
            self.shade_in_plain_row(row, ray)
        } else {
            self.shade_testing_shadows(row, shadows, ray)
        }
    }

    /// [`shade_in_row`](Self::shade_in_row) for a [plain](RowShading::plain) row.
    #[inline(always)]
    pub(crate) fn shade_in_plain_row(&self, row: &RowShading<'s, S>, ray: &Ray<S>) -> Vec3<S> {
        // The first level in line (every pixel has it), the deeper ones out of line.
        self.level(&row.levels, ray, S::ZERO, 0, None)
    }

    /// [`shade_in_plain_row`](Self::shade_in_plain_row) for a [bare](RowShading::bare) row.
    #[inline(always)]
    pub(crate) fn shade_in_bare_row(&self, row: &RowShading<'s, S>, ray: &Ray<S>) -> Vec3<S> {
        self.level_of::<false, false, true>(&row.levels, ray, S::ZERO, 0, None)
    }

    /// [`shade_in_row`](Self::shade_in_row) where each pixel tests some shadow rays.
    #[inline(never)]
    fn shade_testing_shadows(
        &self,
        row: &RowShading<'s, S>,
        shadows: &RowShadows<'s, S>,
        ray: &Ray<S>,
    ) -> Vec3<S> {
        let levels = &row.levels;
        if cfg!(microray_small) {
            // Built for size, the mirror rays' body serves these rows too.
            self.deeper_level(levels, ray, S::ZERO, 0, Some(shadows))
        } else if row.filtered {
            self.filtered_level(levels, ray, row.textured, shadows)
        } else if row.textured {
            self.textured_level(levels, ray, shadows)
        } else {
            self.level(levels, ray, S::ZERO, 0, Some(shadows))
        }
    }

    /// [`level`](Self::level) for a primary ray on a textured rectangle's run: a copy of
    /// its own, out of line, so that the planes' copy carries no texel look-up (in it, one
    /// cost spec0 17 % more on the Cortex-M4F in `f32`).
    #[inline(never)]
    fn textured_level(
        &self,
        levels: &[Level<'s, S>],
        ray: &Ray<S>,
        shadows: &RowShadows<'s, S>,
    ) -> Vec3<S> {
        self.level_of::<true, false, false>(levels, ray, S::ZERO, 0, Some(shadows))
    }

    /// [`level`](Self::level) for a primary ray whose shadow rays take transparent
    /// objects' filters, on a plane or a textured rectangle: copies of their own, out of
    /// line, apart from the others (sharing the textured one's function cost gallery 0.7 %
    /// more on the micro:bit).
    #[inline(never)]
    fn filtered_level(
        &self,
        levels: &[Level<'s, S>],
        ray: &Ray<S>,
        textured: bool,
        shadows: &RowShadows<'s, S>,
    ) -> Vec3<S> {
        if textured {
            self.level_of::<true, true, false>(levels, ray, S::ZERO, 0, Some(shadows))
        } else {
            self.level_of::<false, true, false>(levels, ray, S::ZERO, 0, Some(shadows))
        }
    }

    /// Whether a light is a projector.
    fn projects(&self) -> bool {
        self.lights.iter().any(|light| light.slide().is_some())
    }

    /// [`shade_in_row`](Self::shade_in_row) where an object tested ray by ray may be nearer
    /// than the row's plane.
    #[inline(never)]
    fn shade_in_tested_row(
        &self,
        row: &RowShading<'s, S>,
        shadows: &RowShadows<'s, S>,
        tests: &[RowEntry<S>],
        ray: &Ray<S>,
    ) -> Vec3<S> {
        let first = row.levels.first().map(|level| level.index);
        match closest_hit_in_row(self.objects, tests, None, ray, self.z_limit) {
            Some((index, _)) if Some(index) == first => {
                self.shade_testing_shadows(row, shadows, ray)
            }
            Some((index, t)) => self.shade(ray, index, t, S::ZERO, Path::PRIMARY),
            None => Vec3::ZERO,
        }
    }

    /// [`level`](Self::level) out of line, for the mirror rays (whose shadows the row
    /// decides: mirror levels are made only where every object ignores `x`, so they pass
    /// no `shadows`). Built for size, the rows whose pixels test shadow rays take this
    /// body too, with `shadows`, instead of a copy of their own (912 bytes of a Cortex-M0's
    /// flash; see docs/design.md, "Built for size").
    #[inline(never)]
    fn deeper_level(
        &self,
        levels: &[Level<'s, S>],
        ray: &Ray<S>,
        total: S,
        depth: u8,
        shadows: Option<&RowShadows<'s, S>>,
    ) -> Vec3<S> {
        self.level(levels, ray, total, depth, shadows)
    }

    /// [`shade`](Self::shade) for a ray of the row at the first of `levels`, having come
    /// `total` so far, at `depth`; `shadows` where the level may leave shadow rays to each
    /// pixel (with the tests prepared for them).
    #[inline(always)]
    fn level(
        &self,
        levels: &[Level<'s, S>],
        ray: &Ray<S>,
        total: S,
        depth: u8,
        shadows: Option<&RowShadows<'s, S>>,
    ) -> Vec3<S> {
        self.level_of::<false, false, false>(levels, ray, total, depth, shadows)
    }

    /// [`level`](Self::level), `TEXTURED` for a level on a textured rectangle (its
    /// colours found by each pixel), `FILTERED` where the pixels' shadow rays walk through
    /// transparent objects, `BARE` for a [bare](RowShading::bare) row's (constants, so that
    /// the planes' copies have no code for them).
    #[inline(always)]
    fn level_of<const TEXTURED: bool, const FILTERED: bool, const BARE: bool>(
        &self,
        levels: &[Level<'s, S>],
        ray: &Ray<S>,
        total: S,
        depth: u8,
        shadows: Option<&RowShadows<'s, S>>,
    ) -> Vec3<S> {
        let Some((level, deeper)) = levels.split_first() else {
            return Vec3::ZERO;
        };
        let surface = &level.surface;
        let material = surface.material;
        // `ray.at(level.t)`, its `y` and `z` the row's.
        let x = ray.base.x + ray.dir.x * level.t;
        let hit = Hit {
            t: level.t,
            point: Vec3::new(x, surface.hit.point.y, surface.hit.point.z),
            normal: surface.hit.normal,
        };
        let len = ray.length();
        let total = total + level.t * len;
        // What a pixel's shadow ray finds, where the pixels test them.
        let reach = |lit: &RowLight<'s, S>, to_light: Vec3<S>| {
            self.pixel_reach::<FILTERED>(lit, &hit, to_light, level.index, shadows)
        };
        let mut c = if TEXTURED && !cfg!(microray_small) {
            let colors = self.pattern_colors(level, &hit);
            self.local_in_row::<true, FILTERED, false>(level, &hit, ray, total, colors, reach)
        } else if shadows.is_some() || cfg!(microray_small) {
            // Built for size, one copy of the light loop, the test decided as it runs.
            let colors = (Vec3::ZERO, Vec3::ZERO);
            self.local_in_row::<false, FILTERED, false>(level, &hit, ray, total, colors, reach)
        } else {
            let colors = (Vec3::ZERO, Vec3::ZERO);
            self.local_in_row::<false, FILTERED, BARE>(level, &hit, ray, total, colors, |_, _| {
                Reach::Clear
            })
        };
        let onward = Onward {
            index: level.index,
            len,
            total,
            // A row's levels are its primary rays and their mirror rays: bound 1.
            path: Path { depth, halvings: 0 },
        };
        if !BARE && cfg!(feature = "reflection") && level.mirror != Mirror::None {
            let reflected = Ray::with_length(hit.point, reflect(ray.dir, hit.normal), len);
            let seen = match level.mirror {
                Mirror::Trace => self.follow(&reflected, &onward, onward.path.mirrored()),
                // Where `trace` stops, or finds nothing.
                _ if total > self.max_distance || depth + 1 > MAX_DEPTH => Vec3::ZERO,
                Mirror::Level => self.deeper_level(deeper, &reflected, total, depth + 1, None),
                _ => Vec3::ZERO,
            };
            c = c + seen.mul_each(material.specular);
        }
        if !BARE && cfg!(feature = "transparency") && level.transparent {
            c = self.through(c, ray, &hit, material, &onward);
        }
        c
    }

    /// What a pixel's shadow ray from `hit` (on the object at `index`) towards `lit` finds,
    /// when the pixels test shadow rays (with the segment's `shadows`) and this light's are
    /// left to them: `FILTERED`, the walk through transparent objects (as
    /// `illuminate_divided` walks), else the first blocker.
    #[inline(always)]
    fn pixel_reach<const FILTERED: bool>(
        &self,
        lit: &RowLight<'s, S>,
        hit: &Hit<S>,
        to_light: Vec3<S>,
        index: usize,
        shadows: Option<&RowShadows<'s, S>>,
    ) -> Reach<S> {
        let Some(shadows) = shadows.filter(|_| lit.shadow_per_pixel) else {
            return Reach::Clear;
        };
        if FILTERED && !cfg!(microray_small) {
            match self.filter_in_row(shadows, hit.point, to_light, index, lit) {
                Some(filter) => Reach::Through(filter),
                None => Reach::Blocked,
            }
        } else if self.blocked_in_row(shadows, hit.point, to_light, index, lit) {
            Reach::Blocked
        } else {
            Reach::Clear
        }
    }

    /// [`local_divided`](Self::local_divided) with a level's lights, `reach` telling what
    /// a light's shadow ray finds at this pixel (given the light and the way to it); on a
    /// `TEXTURED` level, `colors` are the pixel's diffuse and ambient colours (else not
    /// read); `BARE`, a [bare](RowShading::bare) row's level (no glints).
    #[inline(always)]
    fn local_in_row<const TEXTURED: bool, const FILTERED: bool, const BARE: bool>(
        &self,
        level: &Level<'s, S>,
        hit: &Hit<S>,
        ray: &Ray<S>,
        total: S,
        colors: (Vec3<S>, Vec3<S>),
        reach: impl Fn(&RowLight<'s, S>, Vec3<S>) -> Reach<S>,
    ) -> Vec3<S> {
        let Some(total) = total.to_wide() else {
            return Vec3::ZERO;
        };
        let material = level.surface.material;
        let mut c = Vec3::ZERO;
        let mut per_total = None;
        for lit in &level.lights {
            let light = lit.light;
            // `light.location - hit.point`, its `y` and `z` the row's.
            let to_light = Vec3::new(light.location.x - hit.point.x, lit.to_y, lit.to_z);
            let Some(d_squared) = S::positive_row_square(to_light, lit.squares) else {
                continue;
            };
            // Built for size, no spans (flash): each pixel tests the cone.
            #[cfg(microray_small)]
            let outside =
                cfg!(feature = "spotlight") && light.spot.is_some() && !in_cone(light, to_light);
            #[cfg(not(microray_small))]
            let outside = cfg!(feature = "spotlight")
                && light.spot.is_some()
                && !in_cone_within(light, to_light, lit.cone);
            if outside {
                continue;
            }
            let filter = match reach(lit, to_light) {
                Reach::Blocked => continue,
                Reach::Clear => None,
                Reach::Through(filter) => Some(filter),
            };
            let mut diffuse = if TEXTURED {
                colors.0.mul_each(light.diffuse_emissivity)
            } else {
                lit.lit
            };
            // After the colours, as `illuminate_divided` takes it.
            if let Some(filter) = filter {
                diffuse = diffuse.mul_each(filter);
            }
            // A projector's texel at this pixel (or no light), after the filter as there.
            // Only in the filtered copies, which every row lit by a projector takes.
            let texel = if FILTERED && light.slide().is_some() {
                match self.projected_texel(light, to_light) {
                    Some(texel) => Some(texel),
                    None => continue,
                }
            } else {
                None
            };
            if let Some(texel) = texel {
                diffuse = diffuse.mul_each(texel);
            }
            let r = add_diffuse(diffuse, lit.cos_d, d_squared, total, &mut c);
            let glints = !BARE && cfg!(feature = "glint") && level.glints;
            // `1 / total` (a wide product) only where a glint or the ambient light needs it, in
            // fixed point; the floats' product is one instruction, not worth the branch.
            if S::WIDE_RANGE || glints || (level.ambient && per_total.is_none()) {
                let per = S::wide_mul(d_squared, r);
                if glints {
                    // A constant `None` elsewhere, as before projectors came to rows (a
                    // variable's was stored for every pixel: spec0 +1 %).
                    let texel = if FILTERED { texel } else { None };
                    c = c + glint(light, texel, material, hit.normal, ray.dir, to_light, per);
                }
                per_total.get_or_insert(per);
            }
        }
        if !level.ambient {
            return c;
        }
        let ambient = if TEXTURED {
            colors.1
        } else {
            level.surface.ambient
        };
        with_ambient(c, ambient, per_total, total)
    }

    /// The texel of a projector's slide that lights a pixel of a row at `-to_light` from the
    /// light, as `illuminate_divided` finds it. Cold and out of line: the filtered loops
    /// keep their shape for the lights that are not projectors.
    #[cold]
    #[inline(never)]
    fn projected_texel(&self, light: &Light<S>, to_light: Vec3<S>) -> Option<Vec3<S>> {
        let slide = light.slide()?;
        self.slide_texel(light, slide, -to_light, S::ONE)
    }

    /// A pixel's diffuse and ambient colours on a level whose colours change from pixel to
    /// pixel, as the kind's surface look-up finds them at `hit`: a textured rectangle's
    /// material's times the texel, a tiled plane's tile's.
    #[inline(always)]
    fn pattern_colors(&self, level: &Level<'s, S>, hit: &Hit<S>) -> (Vec3<S>, Vec3<S>) {
        let material = level.surface.material;
        match level.pattern {
            Some(Pattern::Texture(textured)) => {
                let texel = textured.texel(&self.palette, hit);
                (
                    material.diffuse.mul_each(texel),
                    material.ambient.mul_each(texel),
                )
            }
            Some(Pattern::Tiles(tiled, base)) => {
                let id = if tiled.is_alternate(hit.point) {
                    tiled.altmaterial
                } else {
                    base
                };
                // Cannot fail: the row was made with both materials (`tiles_ambient`).
                let tile = self.palette.material(id).unwrap_or(material);
                (tile.diffuse, tile.ambient)
            }
            None => (material.diffuse, material.ambient),
        }
    }

    /// Whether either material of a tiled plane has ambient light, where its level can be
    /// shared (else `None`): its two materials differ in their colours only, not in what
    /// the level works out once from either (mirror, glint, exponent), and neither lets
    /// light through (a filter is made from the colours).
    fn tiles_ambient(&self, object: &Object<S>, tiled: &TiledPlane<S>) -> Option<bool> {
        let base = self.palette.material(object.material())?;
        let alternate = self.palette.material(tiled.altmaterial)?;
        (base.specular == alternate.specular
            && base.shininess == alternate.shininess
            && base.transparency == S::ZERO
            && alternate.transparency == S::ZERO)
            .then(|| !base.ambient.is_zero() || !alternate.ambient.is_zero())
    }

    /// Whether an object that ignores `x` (but the one at `index`) is in the way from
    /// `from` to `from + l`: [`blocked`](Self::blocked) among those objects only, whose
    /// answer is the same for every pixel of a row.
    fn blocked_ignoring_x(&self, from: Vec3<S>, l: Vec3<S>, index: usize) -> bool {
        let shadow = Ray::new(from, l);
        let mut blocked = false;
        self.among.each(self.objects, |i, object| {
            if i != index
                && object.hits_ignore_x()
                && object_blocks(object, &shadow, S::ONE, self.z_limit)
            {
                blocked = true;
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        blocked
    }

    /// Whether every object rays can meet ignores `x`.
    fn all_ignore_x(&self) -> bool {
        self.shadows_ignore_x(usize::MAX)
    }

    /// Whether every object a shadow ray can meet, but the one at `index`, ignores `x`.
    fn shadows_ignore_x(&self, index: usize) -> bool {
        if matches!(self.among, Among::Tree(_)) {
            return false;
        }
        let mut all = true;
        self.among.each(self.objects, |i, object| {
            if i == index || object.hits_ignore_x() {
                ControlFlow::Continue(())
            } else {
                all = false;
                ControlFlow::Break(())
            }
        });
        all
    }
}

/// The span of `x` beyond which the way `(x, y, z)` from a spotlight (its `y` and `z` a
/// row's, `y` and `z` here) certainly leaves the cone as [`Scalar::within_cone`] tests it:
/// outside, no pixel of the row needs the test; `[-MAX, MAX]` (every pixel tests) where the
/// span is not worth finding or not safely found.
///
/// With `a` the axis and `k` the cosine, the exact cosine of the way's angle to the axis is
/// `q(x) = (x a.x + c1) / sqrt(x^2 + c2)`, where `c1 = y a.y + z a.z` and `c2 = y^2 + z^2`.
/// The type's test is off from `q > k` by at most `e`: `f32`'s, a unit, a reciprocal, a
/// square root and two dot products, about `10 * 2^-24`; Q16.16's, `v . a` and `k |v|` each
/// truncated once, `2 * 2^-16` in `v . a - k |v|`, so `2^-15 / |v|` in `q`, with `|v|` at
/// least `sqrt(c2)`. Where `q(x)` is below `k - e` the test fails. With `k - e > 0` and
/// `a.x^2 < (k - e)^2` (the row's line is not within the cone's directions), `q(x)^2 >= (k -
/// e)^2` holds only between the roots of `(a.x^2 - (k - e)^2) x^2 + 2 a.x c1 x + c1^2 - (k -
/// e)^2 c2`, which bound the span. Worked out in the plan's geometry type, the roots only
/// where they are well conditioned (the discriminant a hundredth of its terms or more) and
/// the span widened by a thousandth of its size, far beyond the roundings of either; `e` is
/// taken four times over.
#[cfg(not(microray_small))]
fn cone_span<S: Scalar>(spot: &Spot<S>, y: S, z: S) -> [S; 2] {
    cone_span_with(spot, y, z, true)
}

/// [`cone_span`], without its margins where `margins` is false (the tests' check that they
/// are needed). In the geometry's type where that is the target's own or `f32`; else (the
/// Cortex-M0's software `f64`) in software `f32`, about half the cost: the margins are the
/// same ones the M4F's `f32` geometry takes (the micro:bit's spotlight 597 -> 527).
#[cfg(not(microray_small))]
fn cone_span_with<S: Scalar>(spot: &Spot<S>, y: S, z: S, margins: bool) -> [S; 2] {
    use crate::scalar::geometry;
    if geometry::IN_HARDWARE || geometry::SINGLE {
        let ways = [spot.cos_theta, y, z].map(S::to_geo);
        cone_span_in::<S, Geo>(spot.axis.to_geo(), ways, margins)
    } else {
        cone_span_single(spot, y, z, margins)
    }
}

/// [`cone_span_with`] in `f32`, whatever the geometry's type.
#[cfg(not(microray_small))]
fn cone_span_single<S: Scalar>(spot: &Spot<S>, y: S, z: S, margins: bool) -> [S; 2] {
    let single = |v: S| v.to_f64() as f32;
    let axis = Vec3::new(
        single(spot.axis.x),
        single(spot.axis.y),
        single(spot.axis.z),
    );
    cone_span_in::<S, f32>(axis, [spot.cos_theta, y, z].map(single), margins)
}

/// [`cone_span_with`] in the float type `F`, from the axis and the cone's cosine, `y` and
/// `z` in it.
#[cfg(not(microray_small))]
fn cone_span_in<S: Scalar, F: Scalar>(axis: Vec3<F>, [cos, y, z]: [F; 3], margins: bool) -> [S; 2] {
    let room = F::from_f64(if margins { 1.0 } else { 0.0 });
    let c2 = y * y + z * z;
    if !(c2 > F::from_f64(1e-6)) {
        return Crossing::Every.bounds();
    }
    let error =
        room * (F::from_f64(4.0 * 10.0 / 16_777_216.0) + F::from_f64(4.0 / 32_768.0) / c2.sqrt());
    crossing(axis, cos - error, [y, z], room).bounds()
}

/// Where the ways `(x, y, z)` of a row (see [`cone_span`]) can be within a cone.
#[cfg_attr(microray_small, allow(dead_code))]
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Crossing<S> {
    /// Anywhere: the span is not worth finding or not safely found.
    Every,
    /// Nowhere: the row never enters the cone.
    Never,
    /// Only with `x` in this span (its ends included).
    Within([S; 2]),
}

#[cfg_attr(microray_small, allow(dead_code))]
impl<S: Scalar> Crossing<S> {
    /// The span's ends, `[-MAX, MAX]` for every `x`, `[MAX, -MAX]` for none.
    pub(super) fn bounds(self) -> [S; 2] {
        let (low, high) = (S::from_f64(-f64::MAX), S::from_f64(f64::MAX));
        match self {
            Crossing::Every => [low, high],
            Crossing::Never => [high, low],
            Crossing::Within(span) => span,
        }
    }
}

/// Where a row's ways `(x, y, z)` can have the exact cosine of their angle to the unit
/// `axis` at `k` or above (see [`cone_span`]: `k` already less the error of the test the
/// span stands for), the roots' conditioning checked and the span widened by `room`
/// thousandths of its size.
#[cfg_attr(microray_small, allow(dead_code))]
pub(super) fn crossing<S: Scalar, F: Scalar>(
    a: Vec3<F>,
    k: F,
    [y, z]: [F; 2],
    room: F,
) -> Crossing<S> {
    let c1 = y * a.y + z * a.z;
    let c2 = y * y + z * z;
    if !(c2 > F::from_f64(1e-6)) {
        return Crossing::Every;
    }
    let a2 = a.x * a.x - k * k;
    if !(k > F::from_f64(0.0) && a2 < F::from_f64(-1e-3)) {
        return Crossing::Every;
    }
    let b = F::from_f64(2.0) * a.x * c1;
    let c = c1 * c1 - k * k * c2;
    let terms = b * b + F::from_f64(4.0) * (a2 * c).abs();
    let disc = b * b - F::from_f64(4.0) * a2 * c;
    if !(disc > F::from_f64(0.01) * terms) {
        // No root: the row never enters the cone (a2 < 0), unless the discriminant is
        // too near zero to tell.
        return if disc < -F::from_f64(0.01) * terms {
            Crossing::Never
        } else {
            Crossing::Every
        };
    }
    let root = disc.sqrt();
    // a2 < 0: the roots in increasing order.
    let (low, high) = (
        (-b + root) / (F::from_f64(2.0) * a2),
        (-b - root) / (F::from_f64(2.0) * a2),
    );
    let size = low.abs() + high.abs() + (b.abs() + root) / a2.abs();
    let widen = room * (F::from_f64(1e-3) * size + F::from_f64(4.0 / 65_536.0));
    let (low, high) = ((low - widen).to_f64(), (high + widen).to_f64());
    match (S::from_f64_checked(low), S::from_f64_checked(high)) {
        (Some(low), Some(high)) => Crossing::Within([low, high]),
        _ => Crossing::Every,
    }
}

/// The `x` where the way `(x, y, z)` has the exact cosine `k` to the unit axis `a`, in
/// `f64`: the tests' reference for the spans (none where no `x` has it).
#[cfg(all(test, not(microray_small)))]
pub(super) fn exact_edges(a: Vec3<f64>, k: f64, [y, z]: [f64; 2]) -> Vec<f64> {
    let c1 = y * a.y + z * a.z;
    let (qa, qb, qc) = (
        a.x * a.x - k * k,
        2.0 * a.x * c1,
        c1 * c1 - k * k * (y * y + z * z),
    );
    let disc = qb * qb - 4.0 * qa * qc;
    if !(disc > 0.0 && qa != 0.0) {
        return Vec::new();
    }
    let root = libm::sqrt(disc);
    vec![(-qb + root) / (2.0 * qa), (-qb - root) / (2.0 * qa)]
}

/// Points from 2^-30 to 2^-2 either side of `x`, apart and in proportion: where the tests
/// try a span's margins.
#[cfg(all(test, not(microray_small)))]
pub(super) fn about(x: f64) -> impl Iterator<Item = f64> {
    (2..=30).flat_map(move |e| {
        let d = libm::ldexp(1.0, -e);
        [x - d, x + d, x * (1.0 - d), x * (1.0 + d)]
    })
}

#[cfg(all(test, not(microray_small)))]
mod tests {
    use super::*;
    use crate::scalar::I16F16;
    use proptest::prelude::*;

    /// A spotlight aimed along `aim` with half-angle `theta` degrees.
    fn spot<S: Scalar>(aim: [f64; 3], theta: f64) -> Option<Spot<S>> {
        let len = libm::sqrt(aim.iter().map(|c| c * c).sum());
        (len > 1e-3).then(|| {
            let v =
                |c: [f64; 3]| Vec3::new(S::from_f64(c[0]), S::from_f64(c[1]), S::from_f64(c[2]));
            Spot {
                point: v(aim),
                theta: S::from_f64(theta),
                axis: v(aim.map(|c| c / len)),
                cos_theta: S::from_f64(libm::cos(theta.to_radians())),
            }
        })
    }

    /// The ways `(x, y, z)` whose `x` has a key outside the span's: how many, or the first
    /// that the type's own test puts inside the cone. The `x` are `xs` and, where the cone
    /// meets the row (in `f64`), points from 2^-30 to 2^-2 either side of where it does.
    fn check<S: Scalar>(
        spot: &Spot<S>,
        [y, z]: [f64; 2],
        xs: &[f64],
        margins: bool,
    ) -> Result<usize, String> {
        check_span(spot, [y, z], xs, margins, cone_span_with)?;
        // The Cortex-M0's way, in `f32` where the geometry is `f64`.
        check_span(spot, [y, z], xs, margins, cone_span_single)
    }

    fn check_span<S: Scalar>(
        spot: &Spot<S>,
        [y, z]: [f64; 2],
        xs: &[f64],
        margins: bool,
        cone_span: fn(&Spot<S>, S, S, bool) -> [S; 2],
    ) -> Result<usize, String> {
        let (y, z) = (S::from_f64(y), S::from_f64(z));
        let span = cone_span(spot, y, z, margins).map(S::order_key);
        // The exact crossings of the stored cone, in `f64`.
        let (a, k) = (spot.axis.to_f64(), spot.cos_theta.to_f64());
        let mut all = xs.to_vec();
        for root in exact_edges(a, k, [y.to_f64(), z.to_f64()]) {
            all.extend(about(root));
        }
        let mut outside = 0;
        for x in all {
            let x = S::from_f64(x);
            let key = x.order_key();
            if key < span[0] || key > span[1] {
                outside += 1;
                if S::within_cone(Vec3::new(x, y, z), spot.axis, spot.cos_theta) {
                    return Err(format!(
                        "{}: x {x:?} (key {key}) outside {span:?} is in the cone",
                        S::NAME
                    ));
                }
            }
        }
        Ok(outside)
    }

    proptest! {
        /// No way whose `x` lies beyond the span is inside the cone as `f32` and Q16.16 test
        /// it, for spotlights aimed anywhere with half-angles up to 80 degrees, rows at any
        /// height, and `x` near the cone's edges.
        #[test]
        fn ways_beyond_the_span_miss_the_cone(
            aim in prop::array::uniform3(-1.0f64..1.0),
            theta in 1.0f64..80.0,
            row in prop::array::uniform2(-20.0f64..20.0),
            xs in prop::collection::vec(-60.0f64..60.0, 16),
        ) {
            if let Some(spot) = spot::<f32>(aim, theta) {
                check(&spot, row, &xs, true).map_err(TestCaseError::fail)?;
            }
            if let Some(spot) = spot::<I16F16>(aim, theta) {
                check(&spot, row, &xs, true).map_err(TestCaseError::fail)?;
            }
        }
    }

    /// The spotlight scene's red light, down at the floor: most of a row lies beyond its
    /// span, and without the span's margins some way at the cone's edge is wrongly left out.
    #[test]
    fn the_span_leaves_out_most_of_a_row_and_needs_its_margins() {
        let red = spot::<f32>([4.0, -4.0, -3.0], 15.0).unwrap();
        let xs: Vec<f64> = (0..400).map(|i| f64::from(i) * 0.05 - 10.0).collect();
        // The floor 3 below the light, the row 2.5 in front of it.
        let outside = check(&red, [-4.0, -2.5], &xs, true).unwrap();
        assert!(outside > 300, "{outside}");
        let fixed = spot::<I16F16>([4.0, -4.0, -3.0], 15.0).unwrap();
        assert!(check(&fixed, [-4.0, -2.5], &xs, true).unwrap() > 300);
        let mut wrong = 0;
        for i in 0..200 {
            let row = [-4.0 + f64::from(i) * 1e-3, -2.5 + f64::from(i) * 7e-4];
            wrong += usize::from(check(&red, row, &xs, false).is_err());
            wrong += usize::from(check(&fixed, row, &xs, false).is_err());
        }
        assert!(wrong > 0, "no way was wrongly left out without the margins");
    }
}
