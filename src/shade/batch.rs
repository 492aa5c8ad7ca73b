//! A row's primary rays shaded [`BATCH`] at a time, stage by stage (feature `batch`, part
//! of `std`).
//!
//! A pixel's colour is one long chain of dependent divisions and square roots (the ray's
//! direction, its hit, the way to each light, the division by the distance travelled, then
//! the same again for a mirror's ray), and one pixel's shading is more instructions than an
//! out-of-order processor looks ahead: traced pixel by pixel, each chain mostly waits for
//! itself. Stage by stage over a batch (every pixel's surface, then every pixel's own light,
//! then all the mirror rays, then all the rays through transparent surfaces) the chains of
//! neighbouring pixels run side by side. Each pixel gets the same operations in the same
//! order as [`Shader::shade`], so the same colour, bit for bit (tests/plan.rs: the planned
//! rows are the batched ones, the unplanned traced ray by ray, in every number type; the shadow
//! cache only changes which object a shadow ray tries first). A microcontroller executes in
//! order and would only gain memory traffic: the firmware leaves the feature out.

use super::{
    LightKind, MAX_DEPTH, Onward, Path, Shader, mirror_ray, through_ray, with_behind, with_mirror,
};
use crate::camera::RowRays;
use crate::hits::{Among, BatchRay, closest_hit_among, closest_hits_in_row, closest_in_list};
use crate::light::Light;
use crate::material::Material;
use crate::object::plane::plane_surface;
use crate::object::tiled_plane::tiled_plane_surface;
use crate::object::{Hit, RowEntry, Shape, Surface};
use crate::ray::Ray;
use crate::scalar::Scalar;
use crate::vec3::Vec3;

pub use crate::lanes::BATCH;

/// Below this many rays, a batch of mirror or transparency rays is traced ray by ray: the
/// stages' loops over the whole batch would cost more than the overlap brings.
const SPARSE: usize = 3;

/// One ray of a batch and where it stands.
#[derive(Clone, Copy)]
struct Lane<S> {
    ray: Ray<S>,
    /// The object the ray leaves (none for a primary ray).
    left: Option<usize>,
    /// The distance travelled before the ray.
    total: S,
    /// Its place in its pixel's tree.
    path: Path,
    /// The object it meets first and where.
    hit: Option<(usize, S)>,
}

impl<S: Scalar> Shader<'_, S> {
    /// The colours seen along the next `count` (up to [`BATCH`]) primary rays of a row
    /// whose objects' tests are prepared: [`primary_in_row`](Self::primary_in_row) for
    /// each, into `out`. Every entry of `out` is written (black past `count`), so the
    /// caller need not clear it between batches.
    pub fn primary_batch_in_row(
        &self,
        rays: &mut RowRays<S>,
        count: usize,
        row: &[RowEntry<S>],
        out: &mut [Vec3<S>; BATCH],
    ) {
        // Each lane written where it stays, its ray straight from the camera (through an
        // array of rays it was copied once more).
        let mut lanes = [None; BATCH];
        if let Some(lanes) = lanes.get_mut(..count) {
            rays.next_batch_with(lanes, |lane, ray| {
                *lane = ray.map(|ray| Lane {
                    ray,
                    left: None,
                    total: S::ZERO,
                    path: Path::PRIMARY,
                    hit: None,
                });
            });
        }
        let tree = self.tree();
        if !closest_hits_in_row(self.objects, row, tree, &mut lanes, self.z_limit) {
            // Nothing met (the sky of a scene): black, as the stages would leave it.
            *out = [Vec3::ZERO; BATCH];
            return;
        }
        self.shade_lanes(&lanes, out);
    }

    /// [`trace`](Self::trace) for each lane.
    fn trace_lanes(&self, lanes: &mut [Option<Lane<S>>; BATCH], out: &mut [Vec3<S>; BATCH]) {
        if lanes.iter().flatten().count() < SPARSE {
            for (c, lane) in out.iter_mut().zip(lanes.iter()) {
                *c = lane.map_or(Vec3::ZERO, |l| {
                    self.trace_path(&l.ray, l.total, l.left, l.path)
                });
            }
            return;
        }
        // A row's list (the common set) walked here, in line, rather than through
        // `closest_hit_among`'s call.
        let search = |lane: &Lane<S>| match self.among {
            Among::Only(list) => closest_in_list(
                self.objects,
                list,
                &lane.ray,
                lane.left,
                S::UNBOUNDED,
                self.z_limit,
            ),
            _ => closest_hit_among(
                self.objects,
                &self.among,
                &lane.ray,
                lane.left,
                S::UNBOUNDED,
                self.z_limit,
            ),
        };
        for slot in lanes.iter_mut() {
            let Some(lane) = slot else { continue };
            if lane.total > self.max_distance || lane.path.depth > MAX_DEPTH {
                *slot = None;
                continue;
            }
            lane.hit = search(lane);
        }
        self.shade_lanes(lanes, out);
    }

    /// [`shade`](Self::shade) for each lane that meets an object; black for the others.
    fn shade_lanes(&self, lanes: &[Option<Lane<S>>; BATCH], out: &mut [Vec3<S>; BATCH]) {
        // Every surface, then every own light: the chains of the batch side by side. The
        // surfaces are written where they stay (they are large to move).
        let mut surfaces: [Option<Surface<'_, S>>; BATCH] = [None; BATCH];
        // Each shaded lane's ray, surface and onward record in one place, so that the
        // stages' loops ask one question a lane.
        let mut shades: [Option<Shade<'_, '_, S>>; BATCH] = [None; BATCH];
        for ((surface, shade), lane) in surfaces.iter_mut().zip(&mut shades).zip(lanes) {
            let Some((lane, (index, t))) = lane.as_ref().and_then(|l| Some((l, l.hit?))) else {
                continue;
            };
            if let Some(object) = self.objects.get(index) {
                // Written where it stays (see `ObjectVTable::surface`); a plain plane's
                // look-up called directly (every plane's table holds it), so that it is
                // inlined.
                if object.surface_is_uniform() {
                    plane_surface(object, &self.palette, &lane.ray, t, surface);
                } else if matches!(object.shape(), Shape::TiledPlane(_)) {
                    // The tiled plane's table holds this one too.
                    tiled_plane_surface(object, &self.palette, &lane.ray, t, surface);
                } else {
                    object.surface_into(&self.palette, &lane.ray, t, surface);
                }
                // In the same loop: its own would test the same options again.
                if let Some(surface) = surface.as_ref() {
                    *shade = Some(Shade {
                        ray: &lane.ray,
                        surface,
                        onward: super::onward(&lane.ray, index, t, lane.total, lane.path),
                    });
                }
            }
        }
        self.own_lights(&shades, out);
        // Then what the mirrors show, then what lies behind transparent surfaces, in the
        // order `beyond` adds them.
        // (Each stage asked first, so that a render without it does not even clear its
        // lanes.)
        if self.any_mirrors() {
            let mirrors = |s: &Self, m: &Material<S>| s.mirrors(m);
            let path = |p: Path, _: &Material<S>| Some(p.mirrored());
            self.leaving(&shades, out, mirrors, path, mirror_ray, with_mirror);
        }
        if self.any_transmits() {
            let through = |s: &Self, m: &Material<S>| s.transmits(m);
            let path = |p: Path, m: &Material<S>| p.leaving(m.filter_halvings);
            self.leaving(&shades, out, through, path, through_ray, with_behind);
        }
    }

    /// Each shaded lane's own light into `out` (black for the others): as
    /// [`own_light`](Self::own_light), with the lights in the outer loop in `f64` so that
    /// the lanes' shadow rays to one light run side by side (each lane adds its lights in
    /// the same order as [`local`](Self::local)).
    #[inline(always)]
    fn own_lights(&self, shaded: &Shaded<'_, '_, S>, out: &mut [Vec3<S>; BATCH]) {
        for c in out.iter_mut() {
            *c = Vec3::ZERO;
        }
        if !S::COURSE_ORDER {
            for (c, shade) in lit(out, shaded) {
                let (surface, onward) = (shade.surface, &shade.onward);
                *c = self.local_divided(surface, onward.index, shade.ray, onward.total);
            }
            return;
        }
        if !self.stages.illumination || self.lights.is_empty() {
            for (c, shade) in lit(out, shaded) {
                *c = shade.surface.ambient / shade.onward.total;
            }
            return;
        }
        // Two copies of the loop, the common one without the walk through transparent
        // objects (it would take registers from the loop).
        if self.filters_shadows() {
            self.add_lights(shaded, out, true);
        } else {
            self.add_lights(shaded, out, false);
        }
    }

    /// Adds every light's diffuse and glint to each shaded lane's colour in `out`, the
    /// lights in the outer loop (see [`own_lights`](Self::own_lights)).
    #[inline(always)]
    fn add_lights(&self, shaded: &Shaded<'_, '_, S>, out: &mut [Vec3<S>; BATCH], filtered: bool) {
        // Each light's place known where its loop is written, so that no lane asks.
        match self.lights {
            [] => {}
            [only] => self.add_light_copy(only, shaded, out, [true, true], filtered),
            [first, middle @ .., last] => {
                self.add_light_copy(first, shaded, out, [true, false], filtered);
                for light in middle {
                    self.add_light_copy(light, shaded, out, [false, false], filtered);
                }
                self.add_light_copy(last, shaded, out, [false, true], filtered);
            }
        }
    }

    /// [`add_light`](Self::add_light) for the light that is first and/or last or neither
    /// (`[first, last]`), in a copy for the light's [`LightKind`]: point lights without
    /// glints, the common case, with the fewest values to keep; point lights with glints;
    /// any other light.
    #[inline(always)]
    fn add_light_copy(
        &self,
        light: &Light<S>,
        shaded: &Shaded<'_, '_, S>,
        out: &mut [Vec3<S>; BATCH],
        [first, last]: [bool; 2],
        filtered: bool,
    ) {
        let ends = Ends { first, last };
        // Each kind a constant where its copy is written, in arms of its own (through one
        // closure called from three arms, the compiler made one copy taking the kind at run
        // time: +9 to +30 % instructions).
        // (`add_light` works out the light's shadows again: the record kept from here to
        // there cost fplane3 +2 % in registers.)
        match self.light_kind(light, filtered) {
            LightKind::Plain => {
                self.add_light(light, shaded, out, ends, filtered, LightKind::Plain);
            }
            LightKind::PlainBehindOne => {
                let kind = LightKind::PlainBehindOne;
                self.add_light(light, shaded, out, ends, true, kind);
            }
            LightKind::PointWithGlints => {
                let kind = LightKind::PointWithGlints;
                self.add_light(light, shaded, out, ends, filtered, kind);
            }
            LightKind::Any => {
                self.add_light(light, shaded, out, ends, filtered, LightKind::Any);
            }
        }
    }

    /// Adds one light's diffuse and glint to each shaded lane's colour in `out` (see
    /// [`illuminate`](Self::illuminate) for `filtered` and `kind`): to the ambient colour
    /// for the first light, and divided by the distance travelled after the last, the same
    /// operations as loops of their own in one pass over the lanes.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn add_light(
        &self,
        light: &Light<S>,
        shaded: &Shaded<'_, '_, S>,
        out: &mut [Vec3<S>; BATCH],
        ends: Ends,
        filtered: bool,
        kind: LightKind,
    ) {
        let shadows = self.shadows_of(light);
        for (c, shade) in lit(out, shaded) {
            let (surface, onward) = (shade.surface, &shade.onward);
            let shine = self.illuminate(
                light,
                &shadows,
                onward.index,
                surface,
                &shade.ray.base,
                filtered,
                kind,
            );
            ends.add(c, surface.ambient, shine, onward.total);
        }
    }

    /// Traces the rays leaving the shaded hits whose material `leaves` says so (`path`
    /// gives their place in the pixel's tree, `None` for a negligible ray, which adds black
    /// untraced; `ray` makes them) and adds what they see to their colours in `out` (as
    /// `add` says).
    #[inline(always)]
    fn leaving(
        &self,
        shaded: &Shaded<'_, '_, S>,
        out: &mut [Vec3<S>; BATCH],
        leaves: impl Fn(&Self, &Material<S>) -> bool,
        path: impl Fn(Path, &Material<S>) -> Option<Path>,
        ray: impl Fn(&Ray<S>, &Hit<S>, &Onward<S>) -> Ray<S>,
        add: impl Fn(Vec3<S>, Vec3<S>, &Material<S>) -> Vec3<S>,
    ) {
        let mut next = [None; BATCH];
        let (mut any, mut traced) = (false, false);
        for (next, shade) in next.iter_mut().zip(shaded) {
            if let Some(shade) = shade
                && leaves(self, shade.surface.material)
            {
                any = true;
                if let Some(path) = path(shade.onward.path, shade.surface.material) {
                    let leaving = ray(shade.ray, &shade.surface.hit, &shade.onward);
                    *next = Some(follow(leaving, &shade.onward, path));
                    traced = true;
                }
            }
        }
        if !any {
            return;
        }
        let mut seen = [Vec3::ZERO; BATCH];
        if traced {
            self.trace_lanes(&mut next, &mut seen);
        }
        // The same test as above (`trace_lanes` drops the lanes it stops: they add black).
        for ((c, seen), shade) in out.iter_mut().zip(&seen).zip(shaded) {
            if let Some(shade) = shade
                && leaves(self, shade.surface.material)
            {
                *c = add(*c, *seen, shade.surface.material);
            }
        }
    }
}

impl Ends {
    /// Adds a light's `shine` to the colour so far `c` (to `ambient` for the first light),
    /// divided by the distance travelled after the last. The colour so far is read after
    /// the light's shadow test, not kept across it.
    #[inline(always)]
    fn add<S: Scalar>(self, c: &mut Vec3<S>, ambient: Vec3<S>, shine: Vec3<S>, total: S) {
        let before = if self.first { ambient } else { *c };
        let sum = before + shine;
        *c = if self.last { sum / total } else { sum };
    }
}

/// Where a light stands in the order the lights are added.
#[derive(Clone, Copy)]
struct Ends {
    /// The first: its light is added to the ambient colour.
    first: bool,
    /// The last: the sum is then divided by the distance travelled.
    last: bool,
}

/// A shaded lane: its ray, the surface it met and what the rays leaving it need.
#[derive(Clone, Copy)]
struct Shade<'a, 's, S> {
    ray: &'a Ray<S>,
    surface: &'a Surface<'s, S>,
    onward: Onward<S>,
}

/// A batch's shaded lanes (`None` for the others).
type Shaded<'a, 's, S> = [Option<Shade<'a, 's, S>>; BATCH];

/// The colours of the lanes that met a surface, with what shading them needs.
#[inline(always)]
fn lit<'a, 's, S: Scalar>(
    out: &'a mut [Vec3<S>; BATCH],
    shaded: &'a Shaded<'a, 's, S>,
) -> impl Iterator<Item = (&'a mut Vec3<S>, &'a Shade<'a, 's, S>)> {
    out.iter_mut()
        .zip(shaded)
        .filter_map(|(c, shade)| Some((c, shade.as_ref()?)))
}

/// The lane of a ray at `path` leaving a hit, as `onward` says (as [`Shader::follow`]).
fn follow<S: Scalar>(ray: Ray<S>, onward: &Onward<S>, path: Path) -> Lane<S> {
    Lane {
        ray,
        left: Some(onward.index),
        total: onward.total,
        path,
        hit: None,
    }
}

impl<S> BatchRay<S> for Lane<S> {
    #[inline(always)]
    fn ray(&self) -> &Ray<S> {
        &self.ray
    }
    #[inline(always)]
    fn set_hit(&mut self, hit: Option<(usize, S)>) {
        self.hit = hit;
    }
}
