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

use crate::light::Light;
use crate::material::Material;
use crate::object::{Hit, Object, Palette, closest_hit};
use crate::ray::Ray;
use crate::scalar::Scalar;
use crate::vec3::Vec3;

/// Rays stop once the distance travelled from the eye exceeds this (the course's bound).
pub const MAX_DISTANCE: f64 = 32.0;

/// Reflection and transmission rays nest at most this deep; the primary ray is depth 0.
/// The course's own scenes stay within 13 (spec3, in the corner of two mirrors); the bound
/// protects a microcontroller's stack from scenes whose rays take tiny steps.
pub const MAX_DEPTH: u8 = 24;

/// What shading needs from a scene: its objects, lights and surface look-ups.
#[derive(Clone, Copy, Debug)]
pub struct Shader<'s, S: Scalar> {
    objects: &'s [Object<S>],
    lights: &'s [Light<S>],
    palette: Palette<'s, S>,
    max_distance: S,
}

impl<'s, S: Scalar> Shader<'s, S> {
    /// A shader over a scene's parts.
    pub fn new(objects: &'s [Object<S>], lights: &'s [Light<S>], palette: Palette<'s, S>) -> Self {
        Self { objects, lights, palette, max_distance: S::from_f64(MAX_DISTANCE) }
    }

    /// The colour seen along a primary ray.
    pub fn primary(&self, ray: &Ray<S>) -> Vec3<S> {
        self.trace(ray, S::ZERO, None, 0)
    }

    /// The course's `trace`: `total` is the distance travelled so far, `left_from` the object
    /// the ray leaves.
    pub fn trace(&self, ray: &Ray<S>, total: S, left_from: Option<usize>, depth: u8) -> Vec3<S> {
        if total > self.max_distance || depth > MAX_DEPTH {
            return Vec3::ZERO;
        }
        let Some((index, hit)) = closest_hit(self.objects, ray, left_from) else {
            return Vec3::ZERO;
        };
        let Some(object) = self.objects.get(index) else {
            return Vec3::ZERO;
        };
        let total = total + hit.t;
        let mut c = self.local(object, index, &hit, ray.base) / total;
        let specular = object.specular(&self.palette, &hit);
        if specular != S::ZERO {
            let reflected = Ray::new(hit.point, reflect(ray.dir, hit.normal));
            c = c + self.trace(&reflected, total, Some(index), depth + 1) * specular;
        }
        if let Some(material) = self.material_at(object, &hit) {
            let tr = material.transparency;
            if tr != S::ZERO {
                let through = Ray::new(hit.point, ray.dir);
                let behind = self.trace(&through, total, Some(index), depth + 1);
                c = c * (S::ONE - tr) + material.filter.mul_each(behind);
            }
        }
        c
    }

    fn material_at(&self, object: &Object<S>, hit: &Hit<S>) -> Option<&'s Material<S>> {
        self.palette.material(object.material_at(hit))
    }

    /// Ambient plus every light's contribution, before the division by distance.
    #[inline(never)]
    fn local(&self, object: &Object<S>, index: usize, hit: &Hit<S>, eye: Vec3<S>) -> Vec3<S> {
        let mut c = object.ambient(&self.palette, hit);
        if self.lights.is_empty() {
            return c;
        }
        let diffuse = object.diffuse(&self.palette, hit);
        let (specular, shininess) = self
            .material_at(object, hit)
            .map_or((S::ZERO, S::ZERO), |m| (m.specular, m.shininess));
        for light in self.lights {
            c = c + self.illuminate(light, index, hit, eye, diffuse, specular, shininess);
        }
        c
    }

    /// One light's diffuse and glint at a hit; black when the light is behind the surface,
    /// outside a spotlight's cone, or blocked by an opaque object.
    #[allow(clippy::too_many_arguments)]
    fn illuminate(
        &self,
        light: &Light<S>,
        index: usize,
        hit: &Hit<S>,
        eye: Vec3<S>,
        diffuse: Vec3<S>,
        specular: S,
        shininess: S,
    ) -> Vec3<S> {
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
        if let Some(spot) = &light.spot {
            // unit(hit - location) is exactly -l.
            if !((-l).dot(spot.axis) > spot.cos_theta) {
                return Vec3::ZERO;
            }
        }
        let Some(filter) = self.shadow_filter(hit.point, l, distance, index) else {
            return Vec3::ZERO;
        };
        let mut c = diffuse.mul_each(light.emissivity).mul_each(filter) * cos / distance;
        if shininess != S::ZERO {
            let halfway = (eye - hit.point).unit().and_then(|v| (v + l).unit());
            if let Some(h) = halfway {
                c = c + light.emissivity * specular * h.dot(hit.normal).powf(shininess);
            }
        }
        c
    }

    /// Walks from `from` towards a light `distance` away along `l`: `None` when an opaque
    /// object is in the way, else the product of the transparent objects' filters.
    fn shadow_filter(&self, from: Vec3<S>, l: Vec3<S>, distance: S, left: usize) -> Option<Vec3<S>> {
        let mut filter = Vec3::new(S::ONE, S::ONE, S::ONE);
        let mut base = from;
        let mut skip = left;
        let mut remaining = distance;
        // Each step moves forward along the ray; the count only guards against a scene
        // that would make the walk revisit objects forever.
        for _ in 0..=self.objects.len().saturating_mul(2) {
            let ray = Ray::new(base, l);
            let Some((index, hit)) = closest_hit(self.objects, &ray, Some(skip)) else {
                return Some(filter);
            };
            if !(hit.t < remaining) {
                return Some(filter);
            }
            let object = self.objects.get(index)?;
            let material = self.material_at(object, &hit)?;
            if material.transparency == S::ZERO {
                return None;
            }
            filter = filter.mul_each(material.filter);
            base = hit.point;
            skip = index;
            remaining = remaining - hit.t;
        }
        None
    }
}

/// `dir - 2 (dir . n) n`.
#[inline]
pub fn reflect<S: Scalar>(dir: Vec3<S>, n: Vec3<S>) -> Vec3<S> {
    dir - n * (S::TWO * dir.dot(n))
}
