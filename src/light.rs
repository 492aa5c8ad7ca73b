//! Lights: point lights, spotlights and projectors.

use crate::error::{Attr, ErrorKind, Feature, Range};
use crate::name::{Name, bounded};
use crate::object::{RectDef, TexPlane, TextureMode};
use crate::scalar::{Scalar, load, load_position};
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use crate::write;
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

/// A projector's slide as written: a rectangle laid out as a `texplane`'s, the texture
/// it shows and how.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlideDef<'a> {
    /// The rectangle.
    pub rect: RectDef,
    /// The name of the texture (a `texture` block, or an image file).
    pub texname: &'a str,
    /// How the texture is laid on the rectangle.
    pub mode: TextureMode,
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
    /// The slide, for a projector.
    pub slide: Option<SlideDef<'a>>,
}

impl<'a> LightDef<'a> {
    /// A point light.
    pub const fn point(name: &'a str, location: [f64; 3], emissivity: [f64; 3]) -> Self {
        Self {
            name,
            location,
            emissivity,
            spot: None,
            slide: None,
        }
    }

    /// A projector: a light at `location` that reaches only what it sees through the
    /// slide, each point in the colour of the slide's texel there (times `emissivity`).
    ///
    /// ```
    /// use microray::{LightDef, RectDef, TextureMode};
    ///
    /// // proj1's: a 4 x 3 slide 2 units in front of the lamp, the image stretched over it.
    /// let slide = RectDef::new([0.0, 0.0, 1.0], [2.0, 1.5, 0.0], [1.0, 0.0, 0.0], [4.0, 3.0]);
    /// let front = LightDef::projector("front", [4.0, 3.0, 2.0], [6.0; 3], slide, "mike", TextureMode::Fit);
    /// assert!(front.slide.is_some());
    /// ```
    pub const fn projector(
        name: &'a str,
        location: [f64; 3],
        emissivity: [f64; 3],
        rect: RectDef,
        texname: &'a str,
        mode: TextureMode,
    ) -> Self {
        Self {
            name,
            location,
            emissivity,
            spot: None,
            slide: Some(SlideDef {
                rect,
                texname,
                mode,
            }),
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
            slide: None,
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
    pub(crate) name: Name,
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
    /// The slide, for a projector: a textured rectangle the light shines through (a
    /// `texplane` that is not an object). Only with the `projector` feature: a build
    /// without it keeps its lights small.
    #[cfg(feature = "projector")]
    pub slide: Option<TexPlane<S>>,
}

impl<S: Scalar> Light<S> {
    /// Checks a definition, with the scene's scale; `find_texture` gives a projector's
    /// texture by name.
    pub(crate) fn build(
        def: &LightDef<'_>,
        scale: f64,
        find_texture: impl Fn(&str) -> Option<u16>,
    ) -> Result<Self, ErrorKind> {
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
                let cos_theta = cos_degrees(theta.to_f64());
                Some(Spot {
                    point,
                    theta,
                    axis: axis.cast(),
                    cos_theta: S::from_f64(cos_theta),
                })
            }
        };
        #[cfg(not(feature = "projector"))]
        let _ = find_texture;
        #[cfg(not(feature = "projector"))]
        if def.slide.is_some() {
            return Err(ErrorKind::NotCompiledIn {
                feature: Feature::Projector,
                attr: None,
            });
        }
        #[cfg(feature = "projector")]
        let slide = match &def.slide {
            None => None,
            Some(slide) => {
                let texture =
                    find_texture(slide.texname).ok_or_else(|| ErrorKind::UndefinedTexture {
                        name: crate::error::Snippet::new(slide.texname.as_bytes()),
                    })?;
                Some(TexPlane {
                    rect: crate::object::Rect::build(&slide.rect, scale)?,
                    texture,
                    mode: slide.mode,
                })
            }
        };
        Ok(Self {
            name: bounded(def.name)?,
            location,
            emissivity,
            diffuse_emissivity,
            spot,
            #[cfg(feature = "projector")]
            slide,
        })
    }

    /// The projector's slide, if the light is a projector.
    #[inline(always)]
    pub fn slide(&self) -> Option<&TexPlane<S>> {
        #[cfg(feature = "projector")]
        return self.slide.as_ref();
        #[cfg(not(feature = "projector"))]
        None
    }

    /// The light's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Writes the light, spotlight or projector block; `textures` are the scene's (for a
    /// projector's texture name).
    #[cfg(feature = "print")]
    pub fn print(
        &self,
        out: &mut dyn fmt::Write,
        scale: f64,
        textures: &[crate::texture::Texture<'_>],
    ) -> fmt::Result {
        let keyword = if self.slide().is_some() {
            "projector"
        } else if self.spot.is_some() {
            "spotlight"
        } else {
            "light"
        };
        write::header(out, keyword, &self.name)?;
        write::vector(out, Attr::Location, self.location, scale)?;
        write::vector(out, Attr::Emissivity, self.emissivity, scale)?;
        if let Some(spot) = &self.spot {
            write::vector(out, Attr::Point, spot.point, scale)?;
            write::numbers(out, Attr::Theta, &[spot.theta], 1.0)?;
        }
        if let Some(slide) = self.slide() {
            slide.rect.print_attributes(out, scale)?;
            let name = textures
                .get(usize::from(slide.texture))
                .map_or("", |t| t.name());
            write::word(out, Attr::Texname, name)?;
            writeln!(out, "  {} {}", Attr::Mode, slide.mode as u8)?;
        }
        write::footer(out)
    }
}

/// `libm::cos(degrees * pi / 180)` for `0 <= degrees <= 180`, bit for bit: musl's `cos`
/// with only the argument reduction this range needs (`rem_pio2` for `|x| <= 5 pi / 4`).
/// `libm::cos` brings the reduction of any argument, 6.8 KB of flash on the Cortex-M4F, for
/// a step taken once per spotlight at load.
fn cos_degrees(degrees: f64) -> f64 {
    const INV_PIO2: f64 = core::f64::consts::FRAC_2_PI;
    const PIO2_1: f64 = f64::from_bits(0x3ff9_21fb_5440_0000);
    const PIO2_1T: f64 = f64::from_bits(0x3dd0_b461_1a62_6331);
    const PIO2_2: f64 = f64::from_bits(0x3dd0_b461_1a60_0000);
    const PIO2_2T: f64 = f64::from_bits(0x3ba3_198a_2e03_7073);
    const PIO2_3: f64 = f64::from_bits(0x3ba3_198a_2e00_0000);
    const PIO2_3T: f64 = f64::from_bits(0x397b_839a_2520_49c1);
    const TO_INT: f64 = 1.5 / f64::EPSILON;
    let x = degrees * (core::f64::consts::PI / 180.0);
    let ix = (x.to_bits() >> 32) as u32 & 0x7fff_ffff;
    if ix <= 0x3fe9_21fb {
        return kernel_cos(x, 0.0);
    }
    let (n, y0, y1) = if ix & 0xf_ffff == 0x9_21fb {
        // Near pi/2 or pi: musl's "medium" reduction, in up to three rounds.
        let f_n = (x * INV_PIO2 + TO_INT) - TO_INT;
        let mut r = x - f_n * PIO2_1;
        let mut w = f_n * PIO2_1T;
        let mut y0 = r - w;
        let exponent = |v: f64| (v.to_bits() >> 52) as i32 & 0x7ff;
        let ex = (ix >> 20) as i32;
        for (part, tail, gap) in [(PIO2_2, PIO2_2T, 16), (PIO2_3, PIO2_3T, 49)] {
            if ex - exponent(y0) <= gap {
                break;
            }
            let t = r;
            w = f_n * part;
            r = t - w;
            w = f_n * tail - ((t - r) - w);
            y0 = r - w;
        }
        (f_n as i32, y0, (r - y0) - w)
    } else if ix <= 0x4002_d97c {
        let z = x - PIO2_1;
        let y0 = z - PIO2_1T;
        (1, y0, (z - y0) - PIO2_1T)
    } else {
        let z = x - 2.0 * PIO2_1;
        let y0 = z - 2.0 * PIO2_1T;
        (2, y0, (z - y0) - 2.0 * PIO2_1T)
    };
    match n & 3 {
        0 => kernel_cos(y0, y1),
        1 => -kernel_sin(y0, y1),
        2 => -kernel_cos(y0, y1),
        _ => kernel_sin(y0, y1),
    }
}

/// musl's `__cos(x, y)`: the cosine of `x + y` for `|x + y| <= pi / 4`.
fn kernel_cos(x: f64, y: f64) -> f64 {
    const C: [f64; 6] = [
        f64::from_bits(0x3fa5_5555_5555_554c),
        f64::from_bits(0xbf56_c16c_16c1_5177),
        f64::from_bits(0x3efa_01a0_19cb_1590),
        f64::from_bits(0xbe92_7e4f_809c_52ad),
        f64::from_bits(0x3e21_ee9e_bdb4_b1c4),
        f64::from_bits(0xbda8_fae9_be88_38d4),
    ];
    let z = x * x;
    let w = z * z;
    let r = z * (C[0] + z * (C[1] + z * C[2])) + w * w * (C[3] + z * (C[4] + z * C[5]));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + (z * r - x * y))
}

/// musl's `__sin(x, y, 1)`: the sine of `x + y` for `|x + y| <= pi / 4`.
fn kernel_sin(x: f64, y: f64) -> f64 {
    const S: [f64; 6] = [
        f64::from_bits(0xbfc5_5555_5555_5549),
        f64::from_bits(0x3f81_1111_1110_f8a6),
        f64::from_bits(0xbf2a_01a0_19c1_61d5),
        f64::from_bits(0x3ec7_1de3_57b1_fe7d),
        f64::from_bits(0xbe5a_e5e6_8a2b_9ceb),
        f64::from_bits(0x3de5_d93a_5acf_d57c),
    ];
    let z = x * x;
    let w = z * z;
    let r = S[1] + z * (S[2] + z * S[3]) + z * w * (S[4] + z * S[5]);
    let v = z * x;
    x - ((z * (0.5 * y - v * r) - y) - v * S[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spotlight_axis_and_cone() {
        let def = LightDef::spot("s", [0.0, 4.0, 0.0], [1.0; 3], [0.0, 0.0, 0.0], 60.0);
        let light = Light::<f64>::build(&def, 1.0, |_| None).unwrap();
        let spot = light.spot.unwrap();
        assert_eq!(spot.axis, Vec3::new(0.0, -1.0, 0.0));
        assert!((spot.cos_theta - 0.5).abs() < 1e-15);
    }

    #[test]
    fn cos_degrees_is_libm_cos() {
        // Every thousandth of a degree, its neighbours, and the angles near 90 and 180 that
        // take the three-round reduction: bit for bit.
        let check = |d: f64| {
            let libm = libm::cos(d * (core::f64::consts::PI / 180.0));
            assert_eq!(cos_degrees(d).to_bits(), libm.to_bits(), "{d}");
        };
        for i in 0..=180_000 {
            let d = f64::from(i) / 1000.0;
            check(d);
            check(f64::from_bits(d.to_bits().saturating_sub(1)));
            if d < 180.0 {
                check(f64::from_bits(d.to_bits() + 1));
            }
        }
        for centre in [90.0f64, 180.0] {
            let bits = centre.to_bits();
            for k in 0..20_000 {
                check(f64::from_bits(bits - k));
                if centre < 180.0 {
                    check(f64::from_bits(bits + k));
                }
            }
        }
    }

    #[test]
    fn spotlight_aimed_at_itself_is_an_error() {
        let def = LightDef::spot("s", [1.0; 3], [1.0; 3], [1.0; 3], 10.0);
        assert_eq!(
            Light::<f32>::build(&def, 1.0, |_| None),
            Err(ErrorKind::ZeroVector { attr: Attr::Point })
        );
        let wide = LightDef::spot("s", [1.0; 3], [1.0; 3], [0.0; 3], 181.0);
        assert_eq!(
            Light::<f32>::build(&wide, 1.0, |_| None),
            Err(ErrorKind::OutOfRange {
                attr: Attr::Theta,
                range: Range::HalfTurn
            })
        );
    }
}
