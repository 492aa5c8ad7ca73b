//! Lights: point lights and spotlights.

use crate::error::{Attr, ErrorKind, Feature, Range};
use crate::name::{Name, bounded};
#[cfg(feature = "print")]
use crate::print;
use crate::scalar::{Scalar, load, load_position};
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use core::fmt;

/// The cone of a spotlight as written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotDef {
    /// A point the cone's axis passes through.
    pub point: [f64; 3],
    /// Half-angle of the cone in degrees, 0 to 180.
    pub theta: f64,
}

/// A light as written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightDef<'a> {
    /// The light's name.
    pub name: &'a str,
    /// Where it is.
    pub location: [f64; 3],
    /// What it emits (r, g, b).
    pub emissivity: [f64; 3],
    /// The cone, for a spotlight.
    pub spot: Option<SpotDef>,
}

impl<'a> LightDef<'a> {
    /// A point light.
    pub const fn point(name: &'a str, location: [f64; 3], emissivity: [f64; 3]) -> Self {
        Self {
            name,
            location,
            emissivity,
            spot: None,
        }
    }

    /// A spotlight aimed at `point` with half-angle `theta` degrees.
    pub const fn spot(
        name: &'a str,
        location: [f64; 3],
        emissivity: [f64; 3],
        point: [f64; 3],
        theta: f64,
    ) -> Self {
        Self {
            name,
            location,
            emissivity,
            spot: Some(SpotDef { point, theta }),
        }
    }
}

/// A spotlight's cone, with its axis and `cos(theta)` precomputed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot<S> {
    /// The point written in the scene.
    pub point: Vec3<S>,
    /// The half-angle written in the scene, in degrees.
    pub theta: S,
    /// `unit(point - location)`.
    pub axis: Vec3<S>,
    /// `cos(theta)`: a hit is lit when the direction to it is within the cone.
    pub cos_theta: S,
}

/// A checked light.
#[derive(Clone, Debug, PartialEq)]
pub struct Light<S> {
    name: Name,
    /// Where it is.
    pub location: Vec3<S>,
    /// What it emits, times the scene's scale: the glint term.
    pub emissivity: Vec3<S>,
    /// What it emits, times the square of the scene's scale: the diffuse term, which is
    /// divided by the distance to the light as well as by the distance travelled. Equal to
    /// `emissivity` in an unscaled scene.
    pub diffuse_emissivity: Vec3<S>,
    /// The cone, for a spotlight.
    pub spot: Option<Spot<S>>,
}

impl<S: Scalar> Light<S> {
    /// Checks a definition.
    /// Checks a definition, with the scene's scale.
    pub(crate) fn build(def: &LightDef<'_>, scale: f64) -> Result<Self, ErrorKind> {
        let location = load_position::<S>(def.location, scale, Attr::Location)?;
        let emissivity = load_position::<S>(def.emissivity, scale, Attr::Emissivity)?;
        let diffuse_emissivity =
            load_position::<S>(def.emissivity, scale * scale, Attr::Emissivity)?;
        let spot = match def.spot {
            None => None,
            Some(cone) => {
                Feature::Spotlight.require(None)?;
                let point = load_position::<S>(cone.point, scale, Attr::Point)?;
                let theta = load::<S>(cone.theta, Attr::Theta)?;
                if !(0.0..=180.0).contains(&cone.theta) {
                    return Err(ErrorKind::OutOfRange {
                        attr: Attr::Theta,
                        range: Range::HalfTurn,
                    });
                }
                let axis = (point.to_f64() - location.to_f64())
                    .unit_f64()
                    .ok_or(ErrorKind::ZeroVector { attr: Attr::Point })?;
                let cos_theta = libm::cos(theta.to_f64() * (core::f64::consts::PI / 180.0));
                Some(Spot {
                    point,
                    theta,
                    axis: axis.cast(),
                    cos_theta: S::from_f64(cos_theta),
                })
            }
        };
        Ok(Self {
            name: bounded(def.name)?,
            location,
            emissivity,
            diffuse_emissivity,
            spot,
        })
    }

    /// The light's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Writes the light or spotlight block.
    #[cfg(feature = "print")]
    pub fn print(&self, out: &mut dyn fmt::Write, scale: f64) -> fmt::Result {
        let keyword = if self.spot.is_some() {
            "spotlight"
        } else {
            "light"
        };
        print::header(out, keyword, &self.name)?;
        print::vector(out, Attr::Location, self.location, scale)?;
        print::vector(out, Attr::Emissivity, self.emissivity, scale)?;
        if let Some(spot) = &self.spot {
            print::vector(out, Attr::Point, spot.point, scale)?;
            print::numbers(out, Attr::Theta, &[spot.theta], 1.0)?;
        }
        print::footer(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spotlight_axis_and_cone() {
        let def = LightDef::spot("s", [0.0, 4.0, 0.0], [1.0; 3], [0.0, 0.0, 0.0], 60.0);
        let light = Light::<f64>::build(&def, 1.0).unwrap();
        let spot = light.spot.unwrap();
        assert_eq!(spot.axis, Vec3::new(0.0, -1.0, 0.0));
        assert!((spot.cos_theta - 0.5).abs() < 1e-15);
    }

    #[test]
    fn spotlight_aimed_at_itself_is_an_error() {
        let def = LightDef::spot("s", [1.0; 3], [1.0; 3], [1.0; 3], 10.0);
        assert_eq!(
            Light::<f32>::build(&def, 1.0),
            Err(ErrorKind::ZeroVector { attr: Attr::Point })
        );
        let wide = LightDef::spot("s", [1.0; 3], [1.0; 3], [0.0; 3], 181.0);
        assert_eq!(
            Light::<f32>::build(&wide, 1.0),
            Err(ErrorKind::OutOfRange {
                attr: Attr::Theta,
                range: Range::HalfTurn
            })
        );
    }
}
