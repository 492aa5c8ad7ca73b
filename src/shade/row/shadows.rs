//! A segment's shadow tests, prepared once: what each pixel of a row's first level tests
//! for the lights whose shadow rays it tests itself.
//!
//! A pixel of such a level sends its shadow ray from its hit, whose `y` and `z` are the
//! row's, along `L = light - hit`, whose `y` and `z` are the row's too. An object that
//! ignores `x` answers every pixel's ray as it answers the row's, so it is tested once: a
//! blocker blocks the light for the whole segment, else it is left out. A rectangle whose
//! normal has no x part (a panel standing across the row) meets every pixel's ray at the
//! same `t`, bit for bit (its plane test reads only `y` and `z`: the normal's zero x part
//! makes the x products zeros), and at a hit with the row's `y` and `z`; its test by each
//! pixel is then the hit's `x` (`base.x + dir.x t`, as `Ray::at` has it) and whether the
//! hit lies within ([`Rect::holds`]), where [`Rect::nearest`] makes a plane test, a
//! division among it, and reads the whole hit. A rectangle never met along the row's ray
//! (behind, beyond the light, parallel, or beyond the z rule) is left out. Any other
//! object is tested by each pixel as before. The answer is [`Shader::blocked`]'s, whatever
//! the order: a shadow ray is blocked when any object is in the way.
//!
//! Where shadow rays pass through transparent objects, taking their filters, the same tests
//! make the first step of each pixel's walk (the nearest object met, in the scene's order),
//! without the objects that ignore `x`: the row's planes (opaque, see `rows_take_filters`)
//! are left out where the row's ray meets none of them, and a light one of them blocks is
//! left to each pixel's whole walk. The walk goes on from the first object met as
//! [`Shader::shadow_filter`] does.

use super::{ROW_LIGHTS, RowLight, RowShading};
use crate::hits::object_blocks;
use crate::object::{Object, Rect, Shape};
use crate::plan::OCCLUDERS;
use crate::ray::Ray;
use crate::scalar::Scalar;
use crate::shade::Shader;
use crate::vec3::Vec3;
use core::ops::ControlFlow;

/// How each pixel of a segment tests one object that depends on `x`.
#[derive(Clone, Copy, Debug)]
pub(super) enum Occluder<'s, S: Scalar> {
    /// A rectangle whose normal has no x part, met by every pixel's ray at `t`, where the
    /// hit's `y` and `z` are these: whether the hit lies within.
    Across { rect: &'s Rect<S>, t: S, y: S, z: S },
    /// Each pixel's own test.
    Each(&'s Object<S>),
}

/// What each pixel of a segment tests for one light.
#[derive(Clone, Debug)]
pub(super) enum LightShadows<'s, S: Scalar> {
    /// Every object, as [`Shader::blocked`] tests them (or as a walk through transparent
    /// objects meets them): the light is decided by the row, more than [`OCCLUDERS`]
    /// objects depend on `x`, no rectangle stands across the row (the prepared tests would
    /// be each pixel's own), or, where shadow rays take filters, an object that ignores `x`
    /// is in the way.
    Each,
    /// An object that ignores `x` is in the way: no pixel sees the light.
    Blocked,
    /// These objects, in the scene's order (none: the light reaches every pixel).
    Tests(heapless::Vec<Occluder<'s, S>, OCCLUDERS, u8>),
}

/// The shadow tests of a segment of a row for the lights of its first level, by the
/// light's place in the scene's list (rows are shaded together with at most
/// [`ROW_LIGHTS`] lights; see the module's docs). Unprepared, every pixel tests each
/// light's shadow ray as [`Shader::blocked`] does.
#[derive(Clone, Debug)]
pub(crate) struct RowShadows<'s, S: Scalar> {
    lights: [LightShadows<'s, S>; SHADOW_LIGHTS],
}

/// How many lights' tests a [`RowShadows`] holds: none built for size (where none are
/// prepared, and the empty tests cost no flash to set up).
const SHADOW_LIGHTS: usize = if cfg!(microray_small) { 0 } else { ROW_LIGHTS };

impl<S: Scalar> RowShadows<'_, S> {
    /// No prepared tests. Each light's tag written on its own: a constant array was
    /// copied from flash whole for every segment (`memcpy`, spec1 1 % dearer).
    #[inline(always)]
    pub(crate) fn new() -> Self {
        Self {
            lights: core::array::from_fn(|_| LightShadows::Each),
        }
    }
}

impl<'s, S: Scalar> Shader<'s, S> {
    /// Prepares into `shadows` (unprepared) the shadow tests of a row's (or a segment's)
    /// first level for the lights its pixels test; none built for size (flash). Where the
    /// shadow rays take filters, the tests serve the first step of each pixel's walk (see
    /// [`filter_in_row`](Self::filter_in_row)). In place (no copy of the lists).
    pub(crate) fn prepare_row_shadows(
        &self,
        shadows: &mut RowShadows<'s, S>,
        row: &RowShading<'s, S>,
    ) {
        let Some(level) = row.levels.first() else {
            return;
        };
        // A walk's first step is spared the objects that ignore `x` too.
        if cfg!(microray_small) || !(row.filtered || self.any_across()) {
            return;
        }
        let point = level.surface.hit.point;
        for lit in level.lights.iter().filter(|lit| lit.shadow_per_pixel) {
            if let Some(tests) = shadows.lights.get_mut(usize::from(lit.number)) {
                self.light_shadows(tests, level.index, point, lit, row.filtered);
            }
        }
    }

    /// [`prepare_row_shadows`](Self::prepare_row_shadows) for one light, into `tests`,
    /// from the row's hit `point` on the object at `own`; `filtered`, for the first step of
    /// walks through transparent objects.
    fn light_shadows(
        &self,
        tests: &mut LightShadows<'s, S>,
        own: usize,
        point: Vec3<S>,
        lit: &RowLight<'s, S>,
        filtered: bool,
    ) {
        // The row's shadow ray: every pixel's in `y` and `z`.
        let to_light = Vec3::new(lit.light.location.x - point.x, lit.to_y, lit.to_z);
        let shadow = Ray::new(point, to_light);
        let z_limit = self.z_limit;
        *tests = LightShadows::Tests(heapless::Vec::new());
        let LightShadows::Tests(list) = tests else {
            return;
        };
        let mut decided = None;
        let mut across_any = false;
        let objects = self.objects;
        self.among.each(objects, |index, _| {
            // The scene's reference (the visit's lives only as long as the call).
            let Some(object) = objects.get(index).filter(|_| index != own) else {
                return ControlFlow::Continue(());
            };
            let test = if object.hits_ignore_x() {
                if object_blocks(object, &shadow, S::ONE, z_limit) {
                    // A walk may pass through transparent objects before it: each pixel's
                    // own (rows whose walks take filters have only opaque such planes,
                    // but the walk's later steps start elsewhere).
                    decided = Some(if filtered {
                        LightShadows::Each
                    } else {
                        LightShadows::Blocked
                    });
                    return ControlFlow::Break(());
                }
                return ControlFlow::Continue(());
            } else if let Some(rect) = across(object) {
                // The plane test of `Rect::nearest`, and its z rule.
                let Some(t) = rect.plane.nearest_by_axis(&shadow, S::ONE) else {
                    return ControlFlow::Continue(());
                };
                if !(shadow.base.z + shadow.dir.z * t <= z_limit) {
                    return ControlFlow::Continue(());
                }
                let hit = shadow.at(t);
                across_any = true;
                Occluder::Across {
                    rect,
                    t,
                    y: hit.y,
                    z: hit.z,
                }
            } else {
                Occluder::Each(object)
            };
            if list.push(test).is_err() {
                decided = Some(LightShadows::Each);
                return ControlFlow::Break(());
            }
            ControlFlow::Continue(())
        });
        if let Some(decided) = decided {
            *tests = decided;
        } else if !across_any && !list.is_empty() && !filtered {
            // No rectangle across the row: each pixel's own tests are as cheap.
            *tests = LightShadows::Each;
        }
    }

    /// Whether some object is a rectangle whose normal has no x part (else the prepared
    /// tests would be each pixel's own: a scan of the objects, not of each light's).
    fn any_across(&self) -> bool {
        let mut any = false;
        self.among.each(self.objects, |_, object| {
            any = across(object).is_some();
            if any {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        any
    }

    /// Whether the shadow ray from `point` along `to_light` (a pixel's, on the object at
    /// `index`) towards `lit` is blocked, with the segment's prepared `shadows`: the answer
    /// of [`blocked`](Self::blocked).
    #[inline(always)]
    pub(super) fn blocked_in_row(
        &self,
        shadows: &RowShadows<'s, S>,
        point: Vec3<S>,
        to_light: Vec3<S>,
        index: usize,
        lit: &RowLight<'s, S>,
    ) -> bool {
        // Built for size, nothing is prepared: no code for the prepared tests.
        if cfg!(microray_small) {
            return self.blocked(point, to_light, index, lit.light);
        }
        let list = match shadows.lights.get(usize::from(lit.number)) {
            Some(LightShadows::Tests(list)) => list,
            Some(LightShadows::Blocked) => return true,
            _ => return self.blocked(point, to_light, index, lit.light),
        };
        let shadow = Ray::new(point, to_light);
        list.iter().any(|occluder| match *occluder {
            // The hit as `ray.at(t)` has it.
            Occluder::Across { rect, t, y, z } => {
                rect.holds(Vec3::new(shadow.base.x + shadow.dir.x * t, y, z))
            }
            Occluder::Each(object) => object_blocks(object, &shadow, S::ONE, self.z_limit),
        })
    }

    /// The object an occluder tests, and its place in the scene's list: found where a
    /// pixel's walk meets it (not held in the occluder: an index beside it made every
    /// test of a row's shadow rays dearer, Q16.16 on the Cortex-M4F 1 %).
    fn occluder_object(&self, occluder: &Occluder<'s, S>) -> Option<(usize, &'s Object<S>)> {
        let objects = self.objects;
        match *occluder {
            Occluder::Across { rect, .. } => objects
                .iter()
                .enumerate()
                .find(|(_, object)| across(object).is_some_and(|r| core::ptr::eq(r, rect))),
            Occluder::Each(object) => objects
                .iter()
                .enumerate()
                .find(|(_, candidate)| core::ptr::eq(*candidate, object)),
        }
    }

    /// What the shadow ray from `point` along `to_light` (a pixel's, on the object at
    /// `index`) towards `lit` passes through, with the segment's prepared `shadows`: the
    /// answer of [`shadow_filter`](Self::shadow_filter), `None` where an opaque object is
    /// in the way, else the transparent objects' filters.
    ///
    /// Prepared, the walk's first step is the nearest hit among the light's tests, in the
    /// scene's order as the closest-hit search meets them (a later one must be nearer):
    /// the objects that ignore `x` meet none of the row's rays (else the light is left to
    /// the walk itself), and a rectangle standing across the row is met at its `t` where
    /// the hit lies within, `t` below the nearest so far as the plane test's own bound would
    /// have it (its quotient is the same). From a transparent object's hit the walk goes on
    /// as the general one, one step less to take.
    #[inline(always)]
    pub(super) fn filter_in_row(
        &self,
        shadows: &RowShadows<'s, S>,
        point: Vec3<S>,
        to_light: Vec3<S>,
        index: usize,
        lit: &RowLight<'s, S>,
    ) -> Option<Vec3<S>> {
        let list = match shadows.lights.get(usize::from(lit.number)) {
            Some(LightShadows::Tests(list)) if !cfg!(microray_small) => list,
            _ => return self.shadow_filter(&self.among, point, to_light, S::ONE, index),
        };
        let shadow = Ray::new(point, to_light);
        let mut nearest = None;
        let mut limit = S::ONE;
        for occluder in list {
            match *occluder {
                Occluder::Across { rect, t, y, z } => {
                    if t < limit && rect.holds(Vec3::new(shadow.base.x + shadow.dir.x * t, y, z)) {
                        (nearest, limit) = (Some(occluder), t);
                    }
                }
                Occluder::Each(object) => {
                    if let Some(t) = object.hits(&shadow, limit)
                        && shadow.base.z + shadow.dir.z * t <= self.z_limit
                    {
                        (nearest, limit) = (Some(occluder), t);
                    }
                }
            }
        }
        let ones = Vec3::new(S::ONE, S::ONE, S::ONE);
        let Some(found) = nearest else {
            return Some(ones);
        };
        // The object met and its place in the scene's list (the walk's next step skips it).
        let (found, object) = self.occluder_object(found)?;
        let at = shadow.at(limit);
        let filter = self.filtered_through(object, at, ones)?;
        // One step taken here.
        let steps = self.walk_steps().saturating_sub(1);
        self.shadow_walk(
            &self.among,
            at,
            to_light,
            S::ONE - limit,
            found,
            filter,
            steps,
        )
    }
}

/// The rectangle of a finite or textured plane whose normal has no x part.
fn across<S: Scalar>(object: &Object<S>) -> Option<&Rect<S>> {
    let rect = match object.shape() {
        Shape::FPlane(rect) => rect,
        Shape::TexPlane(textured) => &textured.rect,
        _ => return None,
    };
    (rect.plane.unit_normal.x == S::ZERO).then_some(rect)
}
