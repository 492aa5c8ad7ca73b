//! Materials: plain data that objects refer to by index.

use crate::error::{Attr, ErrorKind, Feature, Range};
use crate::name::{Name, bounded};
use crate::scalar::{Scalar, load, load_position, load3};
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use crate::write;
#[cfg(feature = "print")]
use core::fmt;

/// Index of a material in its scene.
pub type MaterialId = u16;

/// A material as written; attributes left out are zero, as in the course.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialDef<'a> {
    /// The name objects refer to it by.
    pub name: &'a str,
    /// Ambient reflectivity (r, g, b).
    pub ambient: [f64; 3],
    /// Diffuse reflectivity (r, g, b).
    pub diffuse: [f64; 3],
    /// Mirror reflectivity (r, g, b), each 0 or more: `specular k` in a file is `k k k`.
    pub specular: [f64; 3],
    /// Glint exponent (Blinn-Phong), 0 for no glint.
    pub shininess: f64,
    /// Fraction of light passed through, 0 to 1.
    pub transparency: f64,
}

impl<'a> MaterialDef<'a> {
    /// A black material; set its attributes with the builder methods.
    pub const fn new(name: &'a str) -> Self {
        Self {
            name,
            ambient: [0.0; 3],
            diffuse: [0.0; 3],
            specular: [0.0; 3],
            shininess: 0.0,
            transparency: 0.0,
        }
    }
    /// With an ambient colour.
    pub const fn ambient(mut self, rgb: [f64; 3]) -> Self {
        self.ambient = rgb;
        self
    }
    /// With a diffuse colour.
    pub const fn diffuse(mut self, rgb: [f64; 3]) -> Self {
        self.diffuse = rgb;
        self
    }
    /// With a mirror reflectivity, the same for every channel.
    pub const fn specular(mut self, k: f64) -> Self {
        self.specular = [k; 3];
        self
    }
    /// With a mirror reflectivity per channel (`specular r g b`).
    pub const fn specular_rgb(mut self, rgb: [f64; 3]) -> Self {
        self.specular = rgb;
        self
    }
    /// With a glint exponent.
    pub const fn shininess(mut self, k: f64) -> Self {
        self.shininess = k;
        self
    }
    /// With a transparency.
    pub const fn transparency(mut self, k: f64) -> Self {
        self.transparency = k;
        self
    }
}

/// A checked material, with the transmission filter precomputed.
#[derive(Clone, Debug, PartialEq)]
pub struct Material<S> {
    pub(crate) name: Name,
    /// Ambient reflectivity.
    pub ambient: Vec3<S>,
    /// Diffuse reflectivity.
    pub diffuse: Vec3<S>,
    /// Mirror reflectivity, per channel (also the weight of glints).
    pub specular: Vec3<S>,
    /// Glint exponent.
    pub shininess: S,
    /// Fraction of light passed through.
    pub transparency: S,
    /// What light passing through is multiplied by: `(tr / max(diffuse)) * diffuse`.
    pub filter: Vec3<S>,
    /// `specular` is not zero: kept so that a batch asks once, not per channel.
    pub(crate) reflects: bool,
    /// How many times the strongest channel of `filter` can be halved and stay at or above
    /// it: a transmitted ray weighs at most `2^-filter_halvings` of what reaches its hit.
    pub(crate) filter_halvings: u8,
    /// Below this `h . n` a glint is nothing ([`Scalar::glint_floor`] of `shininess`).
    pub(crate) glint_floor: S,
}

/// The largest `h` (up to 255) with every channel of `coefficient` at most `2^-h`: a ray
/// through it weighs at most `2^-h` of the ray that met the surface. From the stored
/// values, so a compiled or printed scene agrees. In the type itself (no `f64` in a
/// firmware's set-up): the halving bounds are exact down to the type's smallest positive
/// value, and below it a bound is zero, which every positive value exceeds as it does
/// the exact one (tested against `f64` for every type).
pub(crate) fn halvings<S: Scalar>(coefficient: Vec3<S>) -> u8 {
    let strongest = coefficient.max_component();
    let half = S::ONE / S::TWO;
    let mut bound = half;
    let mut h = 0;
    while !(strongest > bound) && h < u8::MAX {
        bound = bound * half;
        h += 1;
    }
    h
}

/// `loaded`, or [`Scalar::STEP`] (2^-16, one step of I16F16) if the type rounded a
/// positive `written` to zero.
fn nonzero<S: Scalar>(loaded: S, written: f64) -> S {
    if loaded == S::ZERO && written > 0.0 {
        S::STEP
    } else {
        loaded
    }
}

impl<S: Scalar> Material<S> {
    /// Checks a definition.
    /// Checks a definition. Ambient is multiplied by the scene's scale, as the course divides
    /// it by the distance travelled.
    pub(crate) fn build(def: &MaterialDef<'_>, scale: f64) -> Result<Self, ErrorKind> {
        let ambient = load_position::<S>(def.ambient, scale, Attr::Ambient)?;
        let diffuse = load3::<S>(def.diffuse, Attr::Diffuse)?;
        let specular = load3::<S>(def.specular, Attr::Specular)?;
        // Zero and not zero shade differently (no glint, opaque): a value the type rounds
        // to zero is kept at its smallest step.
        let shininess = nonzero(load::<S>(def.shininess, Attr::Shininess)?, def.shininess);
        let transparency = nonzero(
            load::<S>(def.transparency, Attr::Transparency)?,
            def.transparency,
        );
        if def.specular.iter().any(|&k| k < 0.0) {
            return Err(ErrorKind::OutOfRange {
                attr: Attr::Specular,
                range: Range::NonNegative,
            });
        }
        if def.shininess < 0.0 {
            return Err(ErrorKind::OutOfRange {
                attr: Attr::Shininess,
                range: Range::NonNegative,
            });
        }
        if !(0.0..=1.0).contains(&def.transparency) {
            return Err(ErrorKind::OutOfRange {
                attr: Attr::Transparency,
                range: Range::ZeroToOne,
            });
        }
        if def.specular != [0.0; 3] {
            Feature::Reflection.require(Some(Attr::Specular))?;
        }
        if def.shininess != 0.0 {
            Feature::Glint.require(Some(Attr::Shininess))?;
        }
        if def.transparency != 0.0 {
            Feature::Transparency.require(Some(Attr::Transparency))?;
        }
        // Computed from the stored values so that a printed and re-read scene is equal.
        let diffuse64 = diffuse.to_f64();
        let strongest = diffuse64.max_component();
        let tr = transparency.to_f64();
        let filter = if tr == 0.0 {
            Vec3::ZERO
        } else if strongest > 0.0 {
            let filter = diffuse64 * (tr / strongest);
            load3([filter.x, filter.y, filter.z], Attr::Diffuse)?
        } else {
            return Err(ErrorKind::TransparentWithoutDiffuse);
        };
        Ok(Self::from_parts(
            bounded(def.name)?,
            [ambient, diffuse, specular, filter],
            shininess,
            transparency,
        ))
    }

    /// A material from its stored values (`[ambient, diffuse, specular, filter]`), with
    /// what is derived from them: whether it reflects, and its filter's halvings. Loaded
    /// and compiled scenes both make theirs here.
    pub(crate) fn from_parts(
        name: Name,
        [ambient, diffuse, specular, filter]: [Vec3<S>; 4],
        shininess: S,
        transparency: S,
    ) -> Self {
        Self {
            name,
            ambient,
            diffuse,
            specular,
            shininess,
            transparency,
            filter,
            reflects: specular != Vec3::ZERO,
            filter_halvings: halvings(filter),
            // Without glints, nothing reads it (and `f32`'s `exp2f` stays out of the flash).
            glint_floor: if cfg!(feature = "glint") {
                S::glint_floor(shininess)
            } else {
                S::ZERO
            },
        }
    }

    /// The material's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Whether it is a mirror (`specular` is not zero).
    #[inline]
    pub fn reflects(&self) -> bool {
        self.reflects
    }

    /// Writes the material block; zero attributes other than the colours are left out.
    #[cfg(feature = "print")]
    pub fn print(&self, out: &mut dyn fmt::Write, scale: f64) -> fmt::Result {
        write::header(out, "material", &self.name)?;
        write::vector(out, Attr::Ambient, self.ambient, scale)?;
        write::vector(out, Attr::Diffuse, self.diffuse, 1.0)?;
        // One number when the channels agree, as the course's first scenes write it.
        let k = self.specular;
        if k.x != k.y || k.x != k.z {
            write::vector(out, Attr::Specular, k, 1.0)?;
        } else if k.x != S::ZERO {
            write::numbers(out, Attr::Specular, &[k.x], 1.0)?;
        }
        for (attr, value) in [
            (Attr::Shininess, self.shininess),
            (Attr::Transparency, self.transparency),
        ] {
            if value != S::ZERO {
                write::numbers(out, attr, &[value], 1.0)?;
            }
        }
        write::footer(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scalar::I16F16;

    /// [`halvings`] as it was first written, in `f64` from the stored values.
    fn halvings_in_f64<S: Scalar>(coefficient: Vec3<S>) -> u8 {
        let strongest = coefficient.to_f64().max_component();
        let mut bound = 0.5;
        let mut h = 0;
        while !(strongest > bound) && h < u8::MAX {
            bound *= 0.5;
            h += 1;
        }
        h
    }

    fn halvings_agree<S: Scalar>(values: &[f64]) {
        for &a in values {
            for &b in &[0.0, a * 0.5, a] {
                let v = Vec3::new(S::from_f64(b), S::from_f64(a), S::from_f64(b * 0.25));
                assert_eq!(halvings(v), halvings_in_f64(v), "{} {}", S::NAME, a);
            }
        }
    }

    #[test]
    fn halvings_in_the_type_are_those_in_f64() {
        // Powers of two and their neighbours from 2 down past every type's smallest value.
        let mut values = vec![0.0, -0.5, 1.0, 2.0, 0.3, 0.7];
        let mut p = 2.0f64;
        while p > 1e-320 {
            values.extend([p, p * (1.0 + 1e-9), p * (1.0 - 1e-9), p * 0.75]);
            p *= 0.5;
        }
        halvings_agree::<f64>(&values);
        halvings_agree::<f32>(&values);
        halvings_agree::<I16F16>(&values);
    }

    #[test]
    fn filter_is_transparency_over_strongest_diffuse() {
        let m = Material::<f64>::build(
            &MaterialDef::new("g")
                .diffuse([0.0, 8.0, 2.0])
                .transparency(0.6),
            1.0,
        )
        .unwrap();
        assert_eq!(m.filter, Vec3::new(0.0, 0.6, 0.15));
    }

    #[test]
    fn reflects_says_whether_any_channel_mirrors() {
        let build = |rgb| Material::<f64>::build(&MaterialDef::new("m").specular_rgb(rgb), 1.0);
        assert!(!build([0.0; 3]).unwrap().reflects());
        for rgb in [[0.5, 0.0, 0.0], [0.0, 0.25, 0.0], [0.0, 0.0, 1.0]] {
            assert!(build(rgb).unwrap().reflects(), "{rgb:?}");
        }
        // The flag follows the stored value: a specular that Q16.16 rounds to zero does
        // not mirror.
        let tiny = Material::<I16F16>::build(&MaterialDef::new("m").specular(1e-9), 1.0).unwrap();
        assert_eq!(tiny.specular, Vec3::ZERO);
        assert!(!tiny.reflects());
    }

    #[test]
    fn ranges_are_checked() {
        let bad = [
            (MaterialDef::new("a").transparency(1.5), Attr::Transparency),
            (MaterialDef::new("a").shininess(-1.0), Attr::Shininess),
            (MaterialDef::new("a").specular(-0.1), Attr::Specular),
        ];
        for (def, attr) in bad {
            assert_eq!(
                Material::<f32>::build(&def, 1.0).unwrap_err().attribute(),
                Some(attr)
            );
        }
        assert_eq!(
            Material::<f32>::build(&MaterialDef::new("a").transparency(0.5), 1.0),
            Err(ErrorKind::TransparentWithoutDiffuse)
        );
        assert_eq!(
            Material::<f32>::build(&MaterialDef::new("a").ambient([f64::NAN, 0.0, 0.0]), 1.0),
            Err(ErrorKind::NonFiniteValue {
                attr: Attr::Ambient
            })
        );
    }
}
