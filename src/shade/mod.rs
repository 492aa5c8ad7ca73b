//! The course's shading: ambient, diffuse with linear fall-off, shadows through transparent
//! objects, Blinn-Phong glints, mirror reflection and transparency, recursively.
//!
//! The order of operations follows the course's pseudo-code literally, because the reference
//! images are reproduced bit for bit only that way:
//! ```text
//! trace(base, dir, total, left_from):
//!   if total > 32: black
//!   closest hit (obj, t) skipping left_from; none: black
//!   c = ambient(obj) + sum over lights of illuminate(light, obj, hit, base)
//!   total += t;  c = c / total
//!   if specular != 0:     c += specular * trace(hit, reflect(dir, n), total, obj)
//!   if transparency != 0: c = (1 - tr) * c + filter (x) trace(hit, dir, total, obj)
//! ```
//!
//! The distance bound alone does not bound the recursion (a ray can bounce in a corner with
//! tiny steps), so [`MAX_DEPTH`] does: at most `MAX_DEPTH + 1` nested `trace` frames, each
//! with two recursive calls at most. The illumination runs in its own function so its locals
//! are not part of every recursive frame.
//!
//! # Negligible rays
//!
//! Two calls a hit make a tree of up to 2^16 rays a pixel where every surface both mirrors
//! and lets light through, though most of them may count for nothing: with `transparency
//! 1e-6`, what a ray through adds is multiplied by a filter of at most 1e-6. So each ray
//! carries a bound on its weight in its pixel: the product of the strongest channels of
//! the filters it passed through is at most `2^-h`, `h` the sum of their whole halvings (a
//! material's `filter_halvings`, worked out in f64 at load: the same in every number type).
//! A ray through a filter whose bound falls below 2^-16 (`h` above [`NEGLIGIBLE_HALVINGS`])
//! is not traced: it adds black. Mirror rays are always traced and keep the bound they
//! came with: a mirror alone makes a chain, not a tree, and with `specular` at most 1 the
//! bound still holds (a mirror above 1 amplifies what lies beyond it, and the bound is off
//! by that factor). What a skipped ray leaves out of its pixel is below 2^-16 of what it
//! would have seen, so below 1/256 of a level wherever that is below 1 (where the picture
//! saturates). The cost is the number of paths worth about 2^-16 of their pixel or more:
//! one mirror chain for a barely transparent mirror (issue 36: a 2^16 tree before); the
//! check is one integer addition and comparison a ray through glass, none for a mirror
//! ray. The course's scenes have no such rays: their images are the same bit for bit.

use crate::bvh::Tree;
use crate::hits::{
    Among, any_hit_among, any_hit_remembering, closest_hit_among, closest_hit_in_row,
};
use crate::light::Light;
use crate::material::Material;
use crate::object::{Hit, Object, Palette, RowEntry, Surface, TexPlane};
use crate::plan::Stages;
use crate::ray::Ray;
use crate::scalar::Scalar;
use crate::vec3::Vec3;
use core::sync::atomic::AtomicU16;

#[cfg(feature = "batch")]
mod batch;
#[cfg(feature = "batch")]
mod blockers;
mod row;
#[cfg(feature = "batch")]
pub use batch::BATCH;
#[cfg(feature = "batch")]
pub(crate) use blockers::LightBlockers;
pub(crate) use row::RowShadows;
pub use row::{ROW_LEVELS, ROW_LIGHTS, RowShading};

pub use crate::ray::MAX_DISTANCE;

/// Reflection and transmission rays nest at most this deep; the primary ray is depth 0.
/// The course's own scenes reach depth 12 (spec3, in the corner of two mirrors); the bound
/// protects a microcontroller's stack from scenes whose rays take tiny steps.
pub const MAX_DEPTH: u8 = 16;

/// A ray bounded by `2^-h` with `h` above this weighs less than 2^-16 of its pixel and is
/// not traced (see the module's docs).
pub const NEGLIGIBLE_HALVINGS: u8 = 16;

/// Lights whose last blocker is remembered (see [`ShadowCache`]).
pub const CACHED_LIGHTS: usize = 8;

/// The object that blocked each light's last shadow ray through a tree, which the next one
/// tests first (the classic shadow cache: neighbouring pixels in a shadow are mostly in the
/// same object's). Exact: a hit by any object answers an any-hit test, and a tree walk
/// reaches every object a ray can hit. One per render; a thread rendering rows keeps its
/// own. Relaxed atomics rather than `Cell`s, so that a renderer can be shared between
/// threads: on the microcontrollers they compile to the same loads and stores.
#[derive(Debug)]
pub struct ShadowCache {
    last: [AtomicU16; CACHED_LIGHTS],
}

impl Default for ShadowCache {
    fn default() -> Self {
        Self {
            last: core::array::from_fn(|_| AtomicU16::new(crate::hits::NONE_REMEMBERED)),
        }
    }
}

impl ShadowCache {
    /// Nothing remembered.
    pub fn new() -> Self {
        Self::default()
    }
}

/// What shading needs from a scene: its objects, lights and surface look-ups.
#[derive(Clone, Copy, Debug)]
pub struct Shader<'s, S: Scalar> {
    objects: &'s [Object<S>],
    lights: &'s [Light<S>],
    palette: Palette<'s, S>,
    max_distance: S,
    z_limit: S,
    stages: Stages,
    among: Among<'s, S>,
    shadow_cache: Option<&'s ShadowCache>,
    /// Each light's list of the objects that can block it (see `blockers`). Held by
    /// value: borrowed from the renderer, its loads were not hoisted past the shadow
    /// cache's atomic stores (translucent3 +3 %, fplane3 +2 %). The per-pixel calls
    /// (`Renderer::radiance`) copy it with the shader, beside their row list's work.
    #[cfg(feature = "batch")]
    blockers: Option<blockers::LightBlockers>,
}

impl<'s, S: Scalar> Shader<'s, S> {
    /// A shader over a scene's parts, with every stage on and every object tested.
    pub fn new(objects: &'s [Object<S>], lights: &'s [Light<S>], palette: Palette<'s, S>) -> Self {
        Self {
            objects,
            lights,
            palette,
            max_distance: palette.limits.distance,
            z_limit: palette.limits.z,
            stages: Stages::ALL,
            among: Among::All,
            shadow_cache: None,
            #[cfg(feature = "batch")]
            blockers: None,
        }
    }

    /// The same shader remembering each light's last blocker in `cache` (see
    /// [`ShadowCache`]); the pixels are the same with it and without.
    pub fn with_shadow_cache<'c>(self, cache: &'c ShadowCache) -> Shader<'c, S>
    where
        's: 'c,
    {
        Shader {
            shadow_cache: Some(cache),
            ..self
        }
    }

    /// The shadow cache's slot of `light` (one of the shader's lights), if there is one.
    fn remembered(&self, light: &Light<S>) -> Option<&AtomicU16> {
        self.shadow_cache
            .and_then(|cache| cache.last.get(self.light_number(light)))
    }

    /// The place of `light` (one of the shader's lights) in their list, from its address:
    /// the light loops pass references into `lights`, and threading an index through them
    /// costs every scene registers (measured).
    fn light_number(&self, light: &Light<S>) -> usize {
        let offset =
            (light as *const Light<S> as usize).wrapping_sub(self.lights.as_ptr() as usize);
        offset / core::mem::size_of::<Light<S>>().max(1)
    }

    /// The same shader running only `stages` and testing rays only against `among` (a
    /// render plan's; see [`crate::plan`]).
    pub fn planned(self, stages: Stages, among: Among<'s, S>) -> Self {
        Self {
            stages,
            among,
            ..self
        }
    }

    /// The same shader testing each light's shadow rays only against `blockers`' list for
    /// it, where it has one (found from the objects `among` holds: see `blockers`).
    #[cfg(feature = "batch")]
    pub(crate) fn with_blockers(self, blockers: Option<LightBlockers>) -> Self {
        Self { blockers, ..self }
    }

    /// What `light`'s shadow rays are tested against.
    #[inline(always)]
    pub(crate) fn shadows_of(&self, light: &Light<S>) -> Shadows<'_, S> {
        // (Written as one record changed in place: built in two arms, shiny3 +1.4 %.)
        #[cfg_attr(not(feature = "batch"), allow(unused_mut))]
        let mut shadows = Shadows {
            among: self.among,
            #[cfg(feature = "batch")]
            clearing: None,
        };
        #[cfg(feature = "batch")]
        if let Some(blockers) = self.blockers.as_ref() {
            let n = self.light_number(light);
            if let Some(list) = blockers.of(n) {
                shadows.among = Among::Only(list);
            }
            shadows.clearing = blockers.clearing(n);
        }
        let _ = light;
        shadows
    }

    /// The colour seen along a primary ray.
    pub fn primary(&self, ray: &Ray<S>) -> Vec3<S> {
        self.primary_among(ray, self.among)
    }

    /// The colour seen along a primary ray that can only hit the objects `among` (its
    /// row's list); the rays it spawns test every object the shader tests.
    pub fn primary_among(&self, ray: &Ray<S>, among: Among<'_, S>) -> Vec3<S> {
        // Nothing travelled yet: no bound to check.
        let found = closest_hit_among(self.objects, &among, ray, None, S::UNBOUNDED, self.z_limit);
        match found {
            Some((index, t)) => self.shade(ray, index, t, S::ZERO, Path::PRIMARY),
            None => Vec3::ZERO,
        }
    }

    /// [`primary_among`](Self::primary_among) for a primary ray of a row whose objects'
    /// tests were prepared (see [`crate::object::RowTest`]).
    pub fn primary_in_row(&self, ray: &Ray<S>, row: &[RowEntry<S>]) -> Vec3<S> {
        match closest_hit_in_row(self.objects, row, self.tree(), ray, self.z_limit) {
            Some((index, t)) => self.shade(ray, index, t, S::ZERO, Path::PRIMARY),
            None => Vec3::ZERO,
        }
    }

    /// [`first_object_among`](Self::first_object_among) for a primary ray of a row whose
    /// objects' tests were prepared.
    pub fn first_object_in_row(&self, ray: &Ray<S>, row: &[RowEntry<S>]) -> Option<usize> {
        closest_hit_in_row(self.objects, row, self.tree(), ray, self.z_limit)
            .map(|(index, _)| index)
    }

    /// The tree the shader's objects are in, if they are.
    pub(crate) fn tree(&self) -> Option<&Tree<'s, S>> {
        match &self.among {
            Among::Tree(tree) => Some(tree),
            _ => None,
        }
    }

    /// The scene's objects.
    pub fn objects(&self) -> &'s [Object<S>] {
        self.objects
    }

    /// The scene's z limit (see [`crate::hits::closest_hit`]).
    pub fn z_limit(&self) -> S {
        self.z_limit
    }

    /// The index of the object a primary ray sees first, if any (the object-id view).
    pub fn first_object(&self, ray: &Ray<S>) -> Option<usize> {
        self.first_object_among(ray, self.among)
    }

    /// [`first_object`](Self::first_object) among the objects of a row's list.
    pub fn first_object_among(&self, ray: &Ray<S>, among: Among<'_, S>) -> Option<usize> {
        closest_hit_among(self.objects, &among, ray, None, S::UNBOUNDED, self.z_limit)
            .map(|(index, _)| index)
    }

    /// The course's `trace`: `total` is the distance travelled so far, `left_from` the object
    /// the ray leaves.
    pub fn trace(&self, ray: &Ray<S>, total: S, left_from: Option<usize>, depth: u8) -> Vec3<S> {
        self.trace_path(ray, total, left_from, Path { depth, halvings: 0 })
    }

    /// [`trace`](Self::trace) for a ray at `path` in its pixel's tree (see [`Path`]).
    pub(crate) fn trace_path(
        &self,
        ray: &Ray<S>,
        total: S,
        left_from: Option<usize>,
        path: Path,
    ) -> Vec3<S> {
        self.trace_among(ray, &self.among, total, left_from, path)
    }

    fn trace_among(
        &self,
        ray: &Ray<S>,
        among: &Among<'_, S>,
        total: S,
        left_from: Option<usize>,
        path: Path,
    ) -> Vec3<S> {
        #[cfg(all(test, feature = "std"))]
        tests::TRACED.with(|traced| traced.set(traced.get() + 1));
        if total > self.max_distance || path.depth > MAX_DEPTH {
            return Vec3::ZERO;
        }
        let found = closest_hit_among(
            self.objects,
            among,
            ray,
            left_from,
            S::UNBOUNDED,
            self.z_limit,
        );
        match found {
            Some((index, t)) => self.shade(ray, index, t, total, path),
            None => Vec3::ZERO,
        }
    }

    /// The colour where `ray`, having come `total` so far, meets object `index` at `t`:
    /// the object's own light, then what its mirror and its transparency let through
    /// (`path`: the ray's place in its pixel's tree).
    #[inline(never)]
    fn shade(&self, ray: &Ray<S>, index: usize, t: S, total: S, path: Path) -> Vec3<S> {
        let Some(object) = self.objects.get(index) else {
            return Vec3::ZERO;
        };
        // Written here by the look-up and borrowed where it is, not moved.
        let mut found = None;
        object.surface_into(&self.palette, ray, t, &mut found);
        let Some(surface) = found.as_ref() else {
            return Vec3::ZERO;
        };
        let (c, onward) = self.own_light(ray, surface, index, t, total, path);
        self.beyond(c, ray, &surface.hit, surface.material, &onward)
    }

    /// The surface's own light where `ray`, having come `total` so far, meets it (object
    /// `index`) at `t`, divided by the distance travelled; and what the rays leaving it
    /// need.
    #[inline(always)]
    fn own_light(
        &self,
        ray: &Ray<S>,
        surface: &Surface<'_, S>,
        index: usize,
        t: S,
        total: S,
        path: Path,
    ) -> (Vec3<S>, Onward<S>) {
        let onward = onward(ray, index, t, total, path);
        let c = if S::COURSE_ORDER {
            self.local(surface, index, ray.base) / onward.total
        } else {
            self.local_divided(surface, index, ray, onward.total)
        };
        (c, onward)
    }

    /// `c`, the surface's own light, plus what its mirror and its transparency let through
    /// from `hit` on (the rays leaving the object, as `onward` says).
    #[inline(always)]
    fn beyond(
        &self,
        mut c: Vec3<S>,
        ray: &Ray<S>,
        hit: &Hit<S>,
        material: &Material<S>,
        onward: &Onward<S>,
    ) -> Vec3<S> {
        if self.mirrors(material) {
            let reflected = mirror_ray(ray, hit, onward);
            c = with_mirror(
                c,
                self.follow(&reflected, onward, onward.path.mirrored()),
                material,
            );
        }
        self.through(c, ray, hit, material, onward)
    }

    /// `c` as seen through the surface's transparency, with what lies behind it.
    #[inline(always)]
    fn through(
        &self,
        c: Vec3<S>,
        ray: &Ray<S>,
        hit: &Hit<S>,
        material: &Material<S>,
        onward: &Onward<S>,
    ) -> Vec3<S> {
        if self.transmits(material) {
            let behind = match onward.path.leaving(material.filter_halvings) {
                Some(path) => self.follow(&through_ray(ray, hit, onward), onward, path),
                None => Vec3::ZERO,
            };
            return with_behind(c, behind, material);
        }
        c
    }

    /// Whether a surface of `material` reflects (`cfg!`: a build without the feature has
    /// no such materials, they fail to load, and the compiler drops the code).
    #[inline(always)]
    fn mirrors(&self, material: &Material<S>) -> bool {
        self.any_mirrors() && material.reflects()
    }

    /// Whether the render traces mirror rays at all.
    #[inline(always)]
    fn any_mirrors(&self) -> bool {
        cfg!(feature = "reflection") && self.stages.reflection
    }

    /// Whether a surface of `material` lets light through.
    #[inline(always)]
    fn transmits(&self, material: &Material<S>) -> bool {
        self.any_transmits() && material.transparency != S::ZERO
    }

    /// Whether the render traces rays through transparent surfaces at all.
    #[inline(always)]
    fn any_transmits(&self) -> bool {
        cfg!(feature = "transparency") && self.stages.transparency
    }

    /// The colour along a ray leaving a hit at `path`, as `onward` says.
    #[inline(always)]
    fn follow(&self, ray: &Ray<S>, onward: &Onward<S>, path: Path) -> Vec3<S> {
        self.trace_path(ray, onward.total, Some(onward.index), path)
    }

    /// Ambient plus every light's contribution, before the division by distance: the
    /// course's order of operations.
    #[inline(never)]
    fn local(&self, surface: &Surface<'_, S>, index: usize, eye: Vec3<S>) -> Vec3<S> {
        let mut c = surface.ambient;
        if !self.stages.illumination {
            return c;
        }
        let filtered = self.filters_shadows();
        for light in self.lights {
            let shadows = self.shadows_of(light);
            c = c + self.illuminate(
                light,
                &shadows,
                index,
                surface,
                &eye,
                filtered,
                LightKind::Any,
            );
        }
        c
    }

    /// Which copy of [`illuminate`](Self::illuminate) `light` takes: a point light (no cone,
    /// no slide) needs less of the hit and the material, and less again in a render without
    /// glints.
    #[cfg(feature = "batch")]
    #[inline(always)]
    fn light_kind(&self, light: &Light<S>, filtered: bool) -> LightKind {
        match (
            light.spot.is_none() && light.slide().is_none(),
            self.stages.glints,
        ) {
            // Only where shadows are filtered (translucent3's pane): a copy less elsewhere.
            (true, false) if filtered && self.shadows_of(light).only_rect() => {
                LightKind::PlainBehindOne
            }
            (true, false) => LightKind::Plain,
            (true, true) => LightKind::PointWithGlints,
            (false, _) => LightKind::Any,
        }
    }

    /// Whether shadow rays pass through transparent objects, taking their filters.
    #[inline(always)]
    fn filters_shadows(&self) -> bool {
        cfg!(feature = "transparency") && self.stages.shadows && self.stages.filtered_shadows
    }

    /// One light's diffuse and glint at a hit; black when the light is behind the surface,
    /// outside a spotlight's cone, or blocked by an opaque object. `filtered` is
    /// [`filters_shadows`](Self::filters_shadows), passed in so that a caller can have a
    /// copy without the walk through transparent objects where the scene has none, and
    /// `kind` says which of the spotlight's, the projector's and the glint's branches it
    /// needs (see [`LightKind`]), for copies without the others (always inlined: called out
    /// of line, it would wait for each light's long chain of square root and divisions
    /// before the next lane's could start).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn illuminate(
        &self,
        light: &Light<S>,
        shadows: &Shadows<'_, S>,
        index: usize,
        surface: &Surface<'_, S>,
        eye: &Vec3<S>,
        filtered: bool,
        kind: LightKind,
    ) -> Vec3<S> {
        let point = kind != LightKind::Any;
        let hit = &surface.hit;
        let to_light = light.location - hit.point;
        let distance = to_light.length();
        if !(distance > S::ZERO) {
            return Vec3::ZERO;
        }
        let l = to_light / distance;
        let cos = l.dot(hit.normal);
        if !(cos > S::ZERO) {
            return Vec3::ZERO;
        }
        if point {
            // (The spotlight's and the projector's branches left out.)
        } else if let Some(spot) = light.spot.as_ref().filter(|_| cfg!(feature = "spotlight")) {
            // unit(hit - location) is exactly -l.
            if !((-l).dot(spot.axis) > spot.cos_theta) {
                return Vec3::ZERO;
            }
        }
        // A projector sends the texel of its slide that the way to the hit crosses (the
        // course's order: emissivity times texel, then times the diffuse colour).
        let slide = if point { None } else { light.slide() };
        let texel = match slide {
            None => None,
            Some(slide) => match self.slide_texel(light, slide, -l, distance) {
                Some(texel) => Some(texel),
                None => return Vec3::ZERO,
            },
        };
        // The colours are read after the shadow test (through references, so that they are
        // not loaded before it and kept across its calls).
        let mut filter = None;
        if filtered {
            // Cleared: the walk would meet nothing, and its filter would be ones (a product
            // by one is exact; a filter left out would be a branch more).
            let through = if shadows.clear(hit.point, l, distance, index, kind) {
                Vec3::new(S::ONE, S::ONE, S::ONE)
            } else {
                let among = &shadows.among;
                let Some(through) = self.shadow_filter(among, hit.point, l, distance, index) else {
                    return Vec3::ZERO;
                };
                through
            };
            filter = Some(through);
        } else if self.stages.shadows && !shadows.clear(hit.point, l, distance, index, kind) {
            // Nothing is transparent: the first blocker decides, whichever it is (unless the
            // clearing shows that no object can block: see `blockers`).
            let shadow = Ray::with_length(hit.point, l, S::ONE);
            let z = self.z_limit;
            let last = self.remembered(light);
            let among = &shadows.among;
            if any_hit_remembering(self.objects, among, &shadow, index, distance, z, last) {
                return Vec3::ZERO;
            }
        }
        let (emissivity, glint_emissivity) = match texel {
            None => (light.diffuse_emissivity, light.emissivity),
            Some(texel) => (
                light.diffuse_emissivity.mul_each(texel),
                light.emissivity.mul_each(texel),
            ),
        };
        let mut lit = surface.diffuse.mul_each(emissivity);
        if let Some(filter) = filter {
            lit = lit.mul_each(filter);
        }
        let mut c = lit * cos / distance;
        let material = surface.material;
        let shininess = material.shininess;
        let glints = !kind.plain() && self.stages.glints;
        if cfg!(feature = "glint") && glints && shininess != S::ZERO {
            let halfway = (*eye - hit.point).unit().and_then(|v| (v + l).unit());
            if let Some(h) = halfway {
                let glint = glint_emissivity.mul_each(material.specular);
                c = c + glint * h.dot(hit.normal).pow_positive(shininess);
            }
        }
        c
    }

    /// Ambient plus every light's contribution, divided by the distance travelled, without
    /// the course's square roots and with one division per light that shines: with `L` the
    /// way to the light and `d = |L|`, the course's `cos / d` is `(L . n) / (L . L)`, and the
    /// shadow ray runs along `L` itself to `t = 1`; the division by the distance travelled
    /// joins it, `(L . n) / ((L . L) total)`, and the ambient term takes `1 / total` from
    /// the same reciprocal. The quotients are formed in the type's wide numbers (see
    /// [`Scalar::Wide`]).
    #[inline(always)]
    fn local_divided(
        &self,
        surface: &Surface<'_, S>,
        index: usize,
        ray: &Ray<S>,
        total: S,
    ) -> Vec3<S> {
        let Some(total) = total.to_wide() else {
            return Vec3::ZERO;
        };
        let mut c = Vec3::ZERO;
        // `1 / total`, from the first light that shines here.
        let mut per_total = None;
        if self.stages.illumination {
            for light in self.lights {
                if let Some(per) =
                    self.illuminate_divided(light, index, ray, surface, total, &mut c)
                {
                    per_total.get_or_insert(per);
                }
            }
        }
        with_ambient(c, surface.ambient, per_total, total)
    }

    /// Adds one light's diffuse and glint at a hit, divided by the distance travelled
    /// (`total`), to `c`, and returns `1 / total`; `None` when the light is behind the
    /// surface, outside a spotlight's cone, or blocked by an opaque object.
    #[inline(never)]
    fn illuminate_divided(
        &self,
        light: &Light<S>,
        index: usize,
        ray: &Ray<S>,
        surface: &Surface<'_, S>,
        total: S::Wide,
        c: &mut Vec3<S>,
    ) -> Option<S::Wide> {
        let hit = &surface.hit;
        let to_light = light.location - hit.point;
        // cos > 0 and d > 0.
        let cos_d = S::positive_dot_unit(to_light, hit.normal)?;
        let d_squared = S::positive_dot(to_light, to_light)?;
        if cfg!(feature = "spotlight") && light.spot.is_some() && !in_cone(light, to_light) {
            return None;
        }
        let mut lit = surface.diffuse.mul_each(light.diffuse_emissivity);
        if self.filters_shadows() {
            let among = &self.among;
            lit = lit.mul_each(self.shadow_filter(among, hit.point, to_light, S::ONE, index)?);
        } else if self.stages.shadows && self.blocked(hit.point, to_light, index, light) {
            return None;
        }
        // A projector: the texel of its slide that the way to the hit crosses, or no light.
        // After the shadow test, out of the way of its loop (one load and a branch for
        // other lights).
        let texel = match light.slide() {
            None => None,
            Some(slide) => Some(self.slide_texel(light, slide, -to_light, S::ONE)?),
        };
        if let Some(texel) = texel {
            lit = lit.mul_each(texel);
        }
        let per_total = S::wide_mul(d_squared, add_diffuse(lit, cos_d, d_squared, total, c));
        let material = surface.material;
        if cfg!(feature = "glint") && self.stages.glints && material.shininess != S::ZERO {
            *c = *c
                + glint(
                    light, texel, material, hit.normal, ray.dir, to_light, per_total,
                );
        }
        Some(per_total)
    }

    /// The texel of a projector's slide where the way from the light along `towards`
    /// crosses it before `reach`, if it does: a projector lights only what lies behind its
    /// slide.
    #[inline(never)]
    fn slide_texel(
        &self,
        light: &Light<S>,
        slide: &TexPlane<S>,
        towards: Vec3<S>,
        reach: S,
    ) -> Option<Vec3<S>> {
        let way = Ray::new(light.location, towards);
        let t = slide.rect.nearest(&way, reach)?;
        Some(slide.texel_at(&self.palette, way.at(t)))
    }

    /// Whether an object (but the one at `index`) is in the way from `from` to `from + l`,
    /// within the z rule: the shadow test when nothing is transparent.
    #[inline(always)]
    fn blocked(&self, from: Vec3<S>, l: Vec3<S>, index: usize, light: &Light<S>) -> bool {
        let shadow = Ray::new(from, l);
        let z = self.z_limit;
        match self.among {
            // Only tree walks are worth remembering a blocker for (and trees come only from
            // a render plan).
            Among::Tree(_) if cfg!(feature = "plan") => {
                self.blocked_remembering(&shadow, index, light)
            }
            _ => any_hit_among(self.objects, &self.among, &shadow, index, S::ONE, z),
        }
    }

    /// [`blocked`](Self::blocked) through a tree, with the light's shadow cache.
    #[inline(never)]
    fn blocked_remembering(&self, shadow: &Ray<S>, index: usize, light: &Light<S>) -> bool {
        let last = self.remembered(light);
        let z = self.z_limit;
        any_hit_remembering(self.objects, &self.among, shadow, index, S::ONE, z, last)
    }

    /// Walks from `from` towards a light `distance` away along `l`: `None` when an opaque
    /// object is in the way, else the product of the transparent objects' filters.
    /// Always inlined: its callers (the lights' loops, the batch's copy of them, a row's
    /// filtered level) pass it vectors by value, which a call would send through memory.
    /// With two callers the compiler left it out of line in the firmware, and the
    /// showcase cost 3 % more on the Cortex-M4F in `f32`.
    #[inline(always)]
    fn shadow_filter(
        &self,
        among: &Among<'_, S>,
        from: Vec3<S>,
        l: Vec3<S>,
        distance: S,
        left: usize,
    ) -> Option<Vec3<S>> {
        let filter = Vec3::new(S::ONE, S::ONE, S::ONE);
        // One object that can block (a light's list, see `blockers`): one test, the walk's
        // first step; its second would skip that object and find nothing.
        #[cfg(feature = "batch")]
        if let (true, Among::Only([only])) = (S::COURSE_ORDER, among) {
            let only = usize::from(*only);
            if only == left {
                return Some(filter);
            }
            let object = self.objects.get(only)?;
            let ray = Ray::with_length(from, l, S::ONE);
            let Some(t) = object.hits(&ray, distance) else {
                return Some(filter);
            };
            let point = ray.at(t);
            // The z rule as the searches apply it.
            if !(point.z <= self.z_limit) {
                return Some(filter);
            }
            return self.filtered_through(object, point, filter);
        }
        self.shadow_walk(among, from, l, distance, left, filter, self.walk_steps())
    }

    /// The most steps a walk through transparent objects takes (it only guards against a
    /// scene that would make the walk revisit objects forever).
    #[inline(always)]
    fn walk_steps(&self) -> usize {
        self.objects.len().saturating_mul(2).saturating_add(1)
    }

    /// `filter` times the filter of `object`'s material at `point`, where a walk through
    /// transparent objects meets it; `None` where it is opaque (or has no material).
    #[inline(always)]
    fn filtered_through(
        &self,
        object: &Object<S>,
        point: Vec3<S>,
        filter: Vec3<S>,
    ) -> Option<Vec3<S>> {
        let material = self.palette.material(object.material_at(point))?;
        if material.transparency == S::ZERO {
            return None;
        }
        Some(filter.mul_each(material.filter))
    }

    /// [`shadow_filter`](Self::shadow_filter)'s walk from `from` (on the object at `left`)
    /// with `distance` to go and the filters so far in `filter`, for at most `steps` more
    /// steps (a walk whose first step was taken elsewhere goes on with one step less).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn shadow_walk(
        &self,
        among: &Among<'_, S>,
        from: Vec3<S>,
        l: Vec3<S>,
        distance: S,
        left: usize,
        mut filter: Vec3<S>,
        steps: usize,
    ) -> Option<Vec3<S>> {
        let mut base = from;
        let mut skip = left;
        let mut remaining = distance;
        // Each step moves forward along the ray (see `walk_steps`).
        for _ in 0..steps {
            // The course's shadow rays are unit rays; the others run along `L` itself.
            let ray = if S::COURSE_ORDER {
                Ray::with_length(base, l, S::ONE)
            } else {
                Ray::new(base, l)
            };
            let found = closest_hit_among(
                self.objects,
                among,
                &ray,
                Some(skip),
                remaining,
                self.z_limit,
            );
            let Some((index, t)) = found else {
                return Some(filter);
            };
            let object = self.objects.get(index)?;
            let point = ray.at(t);
            filter = self.filtered_through(object, point, filter)?;
            base = point;
            skip = index;
            remaining = remaining - t;
        }
        None
    }
}

/// Whether the way from a spotlight to a hit, `-to_light`, lies within its cone.
#[inline(never)]
fn in_cone<S: Scalar>(light: &Light<S>, to_light: Vec3<S>) -> bool {
    light
        .spot
        .as_ref()
        .is_none_or(|spot| S::within_cone(-to_light, spot.axis, spot.cos_theta))
}

/// [`in_cone`] for the way from a spotlight whose `x` has its key ([`Scalar::order_key`])
/// within `cone`, a row's span of it beyond which the way is certainly outside (see
/// `row::cone_span`): a key outside is of a value beyond the span's ends. Out of line as
/// `in_cone` (the light loops that call it keep their registers). Not built for size.
#[cfg(not(microray_small))]
#[inline(never)]
fn in_cone_within<S: Scalar>(light: &Light<S>, to_light: Vec3<S>, cone: [i16; 2]) -> bool {
    let key = (-to_light.x).order_key();
    if key < cone[0] || key > cone[1] {
        return false;
    }
    // A call of its own: the test's registers are saved only where it is made.
    in_cone(light, to_light)
}

/// A light's Blinn-Phong glint at a hit seen along `dir`, times `k` (the division by the
/// distance travelled): `emissivity specular (h . n)^shininess`, the power kept as a wide
/// number until the end (Q16.16's absolute step times a bright light is visible); a
/// projector's emissivity times its slide's `texel`.
#[inline(never)]
fn glint<S: Scalar>(
    light: &Light<S>,
    texel: Option<Vec3<S>>,
    material: &Material<S>,
    normal: Vec3<S>,
    dir: Vec3<S>,
    to_light: Vec3<S>,
    k: S::Wide,
) -> Vec3<S> {
    let halfway = to_light
        .unit()
        .and_then(|l| (-dir).unit().and_then(|v| (v + l).unit()));
    // Below the material's floor the power is certainly nothing: not computed (`powf` is
    // most of a glint).
    let power = halfway
        .map(|h| h.dot(normal))
        .filter(|&x| !(x < material.glint_floor))
        .and_then(|x| x.pow_wide(material.shininess));
    match power {
        Some(power) => {
            // `cfg!`: without projectors there is never a texel, and no code for one.
            let emissivity = match texel {
                Some(texel) if cfg!(feature = "projector") => light.emissivity.mul_each(texel),
                _ => light.emissivity,
            };
            scaled(
                emissivity.mul_each(material.specular),
                S::wide_mul(power, k),
            )
        }
        None => Vec3::ZERO,
    }
}

/// `c` plus the ambient light divided by the distance travelled: `per_total` is `1 / total`
/// from the first light that shone, if one did.
#[inline(always)]
fn with_ambient<S: Scalar>(
    c: Vec3<S>,
    ambient: Vec3<S>,
    per_total: Option<S::Wide>,
    total: S::Wide,
) -> Vec3<S> {
    if ambient.is_zero() {
        return c;
    }
    let k = match per_total {
        Some(k) => k,
        None => reciprocal::<S>(total),
    };
    c + scaled(ambient, k)
}

/// What the rays leaving object `index`, met at `t` by `ray` after `total`, need.
#[inline(always)]
fn onward<S: Scalar>(ray: &Ray<S>, index: usize, t: S, total: S, path: Path) -> Onward<S> {
    // The distance travelled: `t` for the unit rays of f64, `t |dir|` otherwise.
    let (len, travelled) = if S::COURSE_ORDER {
        (S::ONE, t)
    } else {
        let len = ray.length();
        (len, t * len)
    };
    Onward {
        index,
        len,
        total: total + travelled,
        path,
    }
}

/// The mirror ray leaving `hit` for a ray along `ray`.
#[inline(always)]
fn mirror_ray<S: Scalar>(ray: &Ray<S>, hit: &Hit<S>, onward: &Onward<S>) -> Ray<S> {
    Ray::with_length(hit.point, reflect(ray.dir, hit.normal), onward.len)
}

/// The ray going on through a transparent surface at `hit`.
#[inline(always)]
fn through_ray<S: Scalar>(ray: &Ray<S>, hit: &Hit<S>, onward: &Onward<S>) -> Ray<S> {
    Ray::with_length(hit.point, ray.dir, onward.len)
}

/// `c` plus what the mirror shows, `seen`.
#[inline(always)]
fn with_mirror<S: Scalar>(c: Vec3<S>, seen: Vec3<S>, material: &Material<S>) -> Vec3<S> {
    c + seen.mul_each(material.specular)
}

/// `c` seen through the surface's transparency, with what lies `behind` it.
#[inline(always)]
fn with_behind<S: Scalar>(c: Vec3<S>, behind: Vec3<S>, material: &Material<S>) -> Vec3<S> {
    c * (S::ONE - material.transparency) + material.filter.mul_each(behind)
}

/// What a light's shadow rays are tested against: the objects that can block it, and the
/// cones and sides that clear lanes before their test (see `blockers`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shadows<'a, S> {
    among: Among<'a, S>,
    #[cfg(feature = "batch")]
    clearing: Option<&'a blockers::Clearing>,
}

impl<S: Scalar> Shadows<'_, S> {
    /// Whether the cones and sides show that no object blocks the unit way `l` (`distance` long) to
    /// the light from `point`, a hit on object `own`.
    /// (`kind`: a light whose clearing is one finite plane's alone has a copy of its own.)
    #[inline(always)]
    fn clear(&self, point: Vec3<S>, l: Vec3<S>, distance: S, own: usize, kind: LightKind) -> bool {
        #[cfg(feature = "batch")]
        if let (true, Some(clearing)) = (S::COURSE_ORDER, self.clearing) {
            let (point, l, distance) = (point.to_f64(), l.to_f64(), distance.to_f64());
            return if kind == LightKind::PlainBehindOne {
                clearing.clear_only_rect(point, l, distance, own)
            } else {
                clearing.clear(point, l, distance, own)
            };
        }
        let _ = (point, l, distance, own, kind);
        false
    }

    /// Whether the clearing is one finite plane's alone.
    #[cfg(feature = "batch")]
    fn only_rect(&self) -> bool {
        self.clearing.is_some_and(|clearing| clearing.only_rect())
    }
}

/// The branches a light's copy of [`Shader::illuminate`] keeps: each copy is compiled
/// for one kind, so that the common ones carry no code for the others (the glint's code
/// in the point lights' copy cost the scenes without glints their registers: +1.4 to
/// +3.5 % instructions).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LightKind {
    /// A point light in a render without glints.
    Plain,
    /// [`Plain`](Self::Plain), whose shadows only one finite plane can cast (see
    /// `blockers`): its clearing's test alone (translucent3).
    #[cfg(feature = "batch")]
    PlainBehindOne,
    /// A point light in a render with glints.
    #[cfg(feature = "batch")]
    PointWithGlints,
    /// Any light: a spotlight's cone, a projector's slide, glints.
    Any,
}

impl LightKind {
    /// A point light in a render without glints.
    #[inline(always)]
    fn plain(self) -> bool {
        #[cfg(feature = "batch")]
        if self == LightKind::PlainBehindOne {
            return true;
        }
        self == LightKind::Plain
    }
}

/// What the rays leaving a hit need: the object they leave, the length of their
/// directions, the distance travelled and how deep they nest.
#[derive(Clone, Copy, Debug)]
struct Onward<S> {
    index: usize,
    len: S,
    total: S,
    /// The place in its pixel's tree of the ray that met the hit.
    path: Path,
}

/// Where a ray is in its pixel's tree: how deep, and a bound on its weight in the pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Path {
    /// Mirror and glass bounces so far: 0 for a primary ray.
    depth: u8,
    /// The ray weighs at most `2^-halvings` in its pixel (see the module's docs).
    halvings: u8,
}

impl Path {
    /// A primary ray's.
    pub(crate) const PRIMARY: Path = Path {
        depth: 0,
        halvings: 0,
    };

    /// The path of a mirror ray leaving a hit: one bounce deeper, the same bound (mirrors
    /// make no tree of rays, so their weight is left out of the bound).
    #[inline(always)]
    fn mirrored(self) -> Path {
        Path {
            depth: self.depth.saturating_add(1),
            halvings: self.halvings,
        }
    }

    /// The path of a ray leaving a hit through a filter of `halvings` (see [`Material`]);
    /// `None` if the ray is negligible (it weighs less than 2^-16 of its pixel): it is not
    /// traced and adds black.
    #[inline(always)]
    fn leaving(self, halvings: u8) -> Option<Path> {
        let bound = self.halvings.saturating_add(halvings);
        (bound <= NEGLIGIBLE_HALVINGS).then_some(Path {
            depth: self.depth.saturating_add(1),
            halvings: bound,
        })
    }
}

/// Adds the diffuse light `lit` of a light that shines on a hit, times `cos_d / (d_squared
/// total)` (`L . n` over `L . L` and the distance travelled), to `c`, and returns that
/// reciprocal `r = 1 / (d_squared total)`: `d_squared r` is `1 / total`, for the glint and
/// the ambient light (one reciprocal for all three), where they need it.
#[inline(always)]
fn add_diffuse<S: Scalar>(
    lit: Vec3<S>,
    cos_d: S::Wide,
    d_squared: S::Wide,
    total: S::Wide,
    c: &mut Vec3<S>,
) -> S::Wide {
    let r = S::wide_recip(S::wide_mul(d_squared, total));
    *c = *c + scaled(lit, S::wide_mul(cos_d, r));
    r
}

/// `1 / total` where no light shone (out of line: the division is not worth speculating).
#[cold]
#[inline(never)]
fn reciprocal<S: Scalar>(total: S::Wide) -> S::Wide {
    S::wide_recip(total)
}

/// Each component times a wide number.
#[inline]
fn scaled<S: Scalar>(v: Vec3<S>, k: S::Wide) -> Vec3<S> {
    S::scale3(v, k)
}

/// `dir - 2 (dir . n) n`.
#[inline]
pub fn reflect<S: Scalar>(dir: Vec3<S>, n: Vec3<S>) -> Vec3<S> {
    S::reflect(dir, n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::CameraDef;
    use crate::light::LightDef;
    use crate::material::MaterialDef;
    use crate::object::ObjectDef;
    use crate::scene::Scene;

    const CAMERA: CameraDef<'static> = CameraDef::new("c", [8, 6], [8.0, 6.0], [0.0, 4.0, 4.0]);
    const FLOOR: ObjectDef<'static> = ObjectDef::plane("floor", "grey", [0.0, 1.0, 0.0], [0.0; 3]);

    /// The colour seen from (0, 4, 4) looking at the origin, under one light.
    fn look_at(
        light: LightDef<'_>,
        materials: &[MaterialDef<'_>],
        objects: &[ObjectDef<'_>],
    ) -> Vec3<f64> {
        let scene: Scene<'_, f64> =
            Scene::from_defs(&CAMERA, materials, &[], &[light], objects).unwrap();
        let shader = Shader::new(scene.objects(), scene.lights(), scene.palette());
        let eye = Vec3::new(0.0, 4.0, 4.0);
        shader.primary(&Ray::new(eye, (-eye).unit().unwrap()))
    }

    /// [`look_at`] a grey floor (diffuse 2) and `extra` objects.
    fn look(
        light: LightDef<'_>,
        materials: &[MaterialDef<'_>],
        extra: &[ObjectDef<'_>],
    ) -> Vec3<f64> {
        let mut all = vec![MaterialDef::new("grey").diffuse([2.0; 3])];
        all.extend_from_slice(materials);
        let mut objects = vec![FLOOR];
        objects.extend_from_slice(extra);
        look_at(light, &all, &objects)
    }

    const OVERHEAD: LightDef<'static> = LightDef::point("l", [0.0, 4.0, 0.0], [1.0, 1.0, 1.0]);

    #[cfg(feature = "std")]
    std::thread_local! {
        /// `trace` calls on this thread (a test's own count: tests run on threads of their
        /// own).
        pub(super) static TRACED: core::cell::Cell<u32> = const { core::cell::Cell::new(0) };
    }

    /// Rays traced for one primary ray between four glass mirrors of `transparency`, two
    /// below it and two above, 1/2 apart: every hit sends a mirror ray and a ray through,
    /// each of which meets another of the planes, so without a bound the tree has every
    /// path to depth 16 (65,535 rays).
    #[cfg(feature = "std")]
    fn rays_between_mirrors(transparency: f64) -> (u32, Vec3<f64>) {
        let glass = [MaterialDef::new("m")
            .ambient([0.2; 3])
            .diffuse([1.0, 0.8, 0.6])
            .specular(0.93)
            .transparency(transparency)];
        let up = [0.0, 1.0, 0.0];
        let down = [0.0, -1.0, 0.0];
        let planes = [
            ObjectDef::plane("floor", "m", up, [0.0, 0.0, 0.0]),
            ObjectDef::plane("ceiling", "m", down, [0.0, 1.0, 0.0]),
            ObjectDef::plane("cellar", "m", up, [0.0, -0.5, 0.0]),
            ObjectDef::plane("attic", "m", down, [0.0, 1.5, 0.0]),
        ];
        let light = LightDef::point("l", [0.0, 0.5, -2.0], [1.0, 1.0, 1.0]);
        let scene: Scene<'_, f64> =
            Scene::from_defs(&CAMERA, &glass, &[], &[light], &planes).unwrap();
        let shader = Shader::new(scene.objects(), scene.lights(), scene.palette());
        let ray = Ray::new(
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::new(0.0, -1.0, -1.0).unit().unwrap(),
        );
        TRACED.with(|traced| traced.set(0));
        let c = shader.primary(&ray);
        (TRACED.with(|traced| traced.get()), c)
    }

    #[test]
    #[cfg(feature = "std")]
    fn negligible_rays_are_not_traced() {
        // Issue 36: `transparency 1e-6` made every hit's ray through worth 1e-6 of the
        // pixel, and each of them made two more. Now a ray worth less than 2^-16 of its pixel
        // is not traced: the mirror chain alone is (one ray a bounce to depth 16).
        let (barely, seen) = rays_between_mirrors(1e-6);
        let (opaque, opaque_seen) = rays_between_mirrors(0.0);
        assert!(
            barely <= opaque,
            "{barely} rays against {opaque} for opaque mirrors"
        );
        // One call a bounce, the last finding it has gone too deep.
        assert!((1..=MAX_DEPTH as u32 + 1).contains(&opaque), "{opaque}");
        // The untraced rays add black: each hit's own light is kept at (1 - 1e-6), so the
        // colour is the opaque mirrors' to within 17 such factors.
        let lost = (opaque_seen - seen).mul_each(Vec3::new(
            1.0 / opaque_seen.x,
            1.0 / opaque_seen.y,
            1.0 / opaque_seen.z,
        ));
        assert!(
            (-lost).max_component() < 0.0 && lost.max_component() < 17e-6,
            "{lost:?}"
        );
        // A filter of 1/100 is traced: one ray through, then its own mirror chain (its
        // rays through, 1e-4 of the pixel, are traced once more, and theirs are not).
        let (clear, _) = rays_between_mirrors(0.01);
        assert!(clear > 4 * opaque, "{clear} rays against {opaque}");
    }

    #[test]
    fn diffuse_falls_off_linearly_and_divides_by_distance_travelled() {
        // cos = 1, light distance 4: 2 * 1 / 4 = 0.5; divided by the ray's length 4 sqrt 2.
        let c = look(OVERHEAD, &[], &[]);
        let expected = 0.5 / (4.0 * core::f64::consts::SQRT_2);
        assert!(
            (c.x - expected).abs() < 1e-15 && c.x == c.y && c.y == c.z,
            "{c:?}"
        );
    }

    #[test]
    fn opaque_objects_block_and_transparent_ones_filter() {
        let ball = ObjectDef::sphere("ball", "glass", [0.0, 2.0, 0.0], 0.5);
        let opaque = MaterialDef::new("glass").diffuse([1.0, 0.5, 0.0]);
        assert_eq!(look(OVERHEAD, &[opaque], &[ball]), Vec3::ZERO);
        // Filter (0.5 / 1) * (1, 0.5, 0), once: the walk continues from the ball's near
        // side and skips the ball.
        let clear = opaque.transparency(0.5);
        let c = look(OVERHEAD, &[clear], &[ball]);
        let lit = look(OVERHEAD, &[], &[]);
        assert!(
            (c.x - lit.x * 0.5).abs() < 1e-15 && (c.y - lit.y * 0.25).abs() < 1e-15 && c.z == 0.0,
            "{c:?}"
        );
    }

    #[test]
    fn spotlight_cone_is_strict() {
        // Aimed straight down at the origin: the hit is on the axis.
        let on_axis = LightDef::spot("s", [0.0, 4.0, 0.0], [1.0; 3], [0.0, 0.0, 0.0], 10.0);
        assert_eq!(look(on_axis, &[], &[]), look(OVERHEAD, &[], &[]));
        // Aimed 45 degrees away with a 40 degree cone: dark; with a 50 degree cone: lit.
        let away = LightDef::spot("s", [0.0, 4.0, 0.0], [1.0; 3], [4.0, 0.0, 0.0], 40.0);
        assert_eq!(look(away, &[], &[]), Vec3::ZERO);
        let wide = LightDef::spot("s", [0.0, 4.0, 0.0], [1.0; 3], [4.0, 0.0, 0.0], 50.0);
        assert_eq!(look(wide, &[], &[]), look(OVERHEAD, &[], &[]));
    }

    #[test]
    fn glints_are_blinn_phong_and_never_nan() {
        let shiny = [MaterialDef::new("shiny")
            .diffuse([2.0; 3])
            .specular(0.0)
            .shininess(2.0)];
        // A floor of the shiny material: h = unit(unit(eye - hit) + l) with l = (0,1,0),
        // unit(eye - hit) = (0, s, s), s = 1/sqrt 2: h . n = (s + 1) / |(0, s + 1, s)|.
        let floor = ObjectDef::plane("f", "shiny", [0.0, 1.0, 0.0], [0.0; 3]);
        let plain = look(OVERHEAD, &[], &[]);
        // Specular 0 means the glint term is zero even with shininess.
        assert_eq!(look_at(OVERHEAD, &shiny, &[floor]), plain);
        let with_glint = [shiny[0].specular(0.5)];
        let c = look_at(OVERHEAD, &with_glint, &[floor]);
        let s = core::f64::consts::FRAC_1_SQRT_2;
        let hn = (s + 1.0) / ((s + 1.0) * (s + 1.0) + s * s).sqrt();
        // Glint 1 * 0.5 * (h . n)^2 joins the diffuse before the division by the distance;
        // the mirror ray leaves upwards and meets nothing.
        let expected = (plain.x * 4.0 * 2f64.sqrt() + 0.5 * hn * hn) / (4.0 * 2f64.sqrt());
        assert!((c.x - expected).abs() < 1e-15, "{c:?} vs {expected}");
        assert!(!c.x.is_nan());
    }

    #[test]
    fn reflection_formula() {
        let d = Vec3::new(1.0, -1.0, 0.0);
        assert_eq!(
            reflect(d, Vec3::new(0.0, 1.0, 0.0)),
            Vec3::new(1.0, 1.0, 0.0)
        );
    }
}
