//! Range: how large a scene is, how it is scaled into a number type's range, and which
//! number type suits a scene on a target.
//!
//! Fixed point has a small range (Q16.16: ±32768), so a scene whose coordinates are larger
//! than the type's [`Scalar::MAX_EXTENT`] is scaled down at load by a power of two `s`:
//! positions, radii, sizes and the world window by `s`; and, so that the image is unchanged in
//! exact arithmetic, the course's distance-dependent terms with it: the distance bound 32 and
//! the z limit 0.01 by `s`, ambient by `s`, the light's diffuse emission by `s^2` (it is
//! divided by a distance, then the sum by the distance travelled) and its glint emission by
//! `s`. Powers of two are exact in floating point, so only fixed point loses anything (the
//! low bits of small features). A feature that falls below the type's
//! [`Scalar::MIN_FEATURE`] after scaling is a load error.
//!
//! The scale is the largest power of two, at most 1, with which coordinates stay within
//! [`Scalar::MAX_EXTENT`] and ambient, emissivity, `diffuse * emissivity` and squared sphere
//! radii (which scale by `s`, `s`, `s^2` and `s^2`) within [`Scalar::MAX_TERM`]:
//!
//! | type | `MAX_EXTENT` | `MAX_TERM` | smallest radius, side or window after scaling |
//! |---|---|---|---|
//! | `f64` | 3e150 | 1e300 | 1e-150 |
//! | `f32` | 2^30 (1.1e9) | 1e36 | 1e-18 |
//! | `I16F16` | 8192 | 16384 | 1/256 |
//!
//! The course's scenes (coordinates up to 20, ambient up to 2, diffuse times emissivity up to
//! 160) need no scaling in any type.

use crate::camera::CameraDef;
use crate::error::{Attr, ErrorKind};
use crate::light::LightDef;
use crate::material::MaterialDef;
use crate::object::{ObjectDef, RectDef, ShapeDef};
use crate::scalar::{I16F16, Scalar};

/// The size of a scene: the largest coordinate and the smallest length in it, and the
/// brightest values that scaling multiplies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extent {
    /// The largest absolute coordinate, a corner or rim included (radius and sizes added).
    pub largest: f64,
    /// The smallest radius, rectangle side or world-window side.
    pub smallest: f64,
    /// The largest ambient component.
    pub ambient: f64,
    /// The largest diffuse component.
    pub diffuse: f64,
    /// The largest emissivity component.
    pub emission: f64,
    /// The largest sphere radius (its square is kept).
    pub radius: f64,
    /// The attribute whose coordinate is [`largest`](Self::largest) (for errors that
    /// scaling causes).
    pub largest_at: Option<Attr>,
}

impl Extent {
    /// No scene at all.
    pub const EMPTY: Extent = Extent {
        largest: 0.0,
        smallest: f64::INFINITY,
        ambient: 0.0,
        diffuse: 0.0,
        emission: 0.0,
        radius: 0.0,
        largest_at: None,
    };

    fn brightest(values: [f64; 3]) -> f64 {
        values.iter().fold(0.0, |m: f64, v| m.max(libm::fabs(*v)))
    }

    /// Takes in a position `p` (attribute `attr`).
    fn place(&mut self, p: [f64; 3], attr: Attr) {
        self.point(p, attr, 0.0, attr);
    }

    /// Takes in a position `p` (attribute `attr`) and what reaches `reach` about it
    /// (attribute `reach_attr`: a radius, a rectangle's sides).
    fn point(&mut self, p: [f64; 3], attr: Attr, reach: f64, reach_attr: Attr) {
        for c in p {
            let far = libm::fabs(c) + reach;
            if far > self.largest {
                self.largest = far;
                self.largest_at = Some(if reach > libm::fabs(c) {
                    reach_attr
                } else {
                    attr
                });
            }
        }
    }

    fn length(&mut self, l: f64) {
        self.smallest = self.smallest.min(l);
    }

    /// Takes in a camera.
    pub(crate) fn camera(&mut self, c: &CameraDef<'_>) {
        self.place(c.viewpoint, Attr::Viewpoint);
        self.place([c.worlddim[0], c.worlddim[1], 0.0], Attr::Worlddim);
        c.worlddim.iter().for_each(|&w| self.length(w));
    }

    /// Takes in a light.
    pub(crate) fn light(&mut self, l: &LightDef<'_>) {
        self.place(l.location, Attr::Location);
        self.emission = self.emission.max(Self::brightest(l.emissivity));
        if let Some(spot) = &l.spot {
            self.place(spot.point, Attr::Point);
        }
        if let Some(slide) = &l.slide {
            self.rect(&slide.rect);
        }
    }

    /// Takes in a material.
    pub(crate) fn material(&mut self, m: &MaterialDef<'_>) {
        self.ambient = self.ambient.max(Self::brightest(m.ambient));
        self.diffuse = self.diffuse.max(Self::brightest(m.diffuse));
    }

    /// Takes in an object.
    pub(crate) fn object(&mut self, o: &ObjectDef<'_>) {
        match &o.shape {
            ShapeDef::Plane(p) => self.place(p.point, Attr::Point),
            ShapeDef::Sphere(s) => {
                self.point(s.center, Attr::Center, s.radius, Attr::Radius);
                self.length(s.radius);
                self.radius = self.radius.max(s.radius);
            }
            ShapeDef::RevSurf(r) => {
                let reach = 4.0 + libm::fabs(r.height);
                self.point(r.base, Attr::Base, reach, Attr::Height);
                self.length(r.height);
                self.radius = self.radius.max(reach);
            }
            ShapeDef::FPlane(r) | ShapeDef::TiledPlane(r, _) | ShapeDef::TexPlane(r, _, _) => {
                self.rect(r);
            }
        }
    }

    /// Takes in a rectangle: its corner, its reach and its sides.
    fn rect(&mut self, r: &RectDef) {
        self.point(
            r.point,
            Attr::Point,
            r.dimensions[0] + r.dimensions[1],
            Attr::Dimensions,
        );
        r.dimensions.iter().for_each(|&d| self.length(d));
    }

    /// The largest power of two, at most 1, that brings the scene within `S`'s range:
    /// coordinates up to [`Scalar::MAX_EXTENT`], and the scaled ambient (`* s`), diffuse
    /// light (`diffuse * emissivity * s^2`), glint emission (`emissivity * s`) and squared
    /// radii (`(r s)^2`) up to [`Scalar::MAX_TERM`].
    pub fn scale_for<S: Scalar>(&self) -> f64 {
        // Products are formed as (a s)(b s): no intermediate overflows.
        let fits = |s: f64| {
            self.largest * s <= S::MAX_EXTENT
                && self.ambient * s <= S::MAX_TERM
                && (self.diffuse * s) * (self.emission * s) <= S::MAX_TERM
                && self.emission * s <= S::MAX_TERM
                && (self.radius * s) * (self.radius * s) <= S::MAX_TERM
        };
        let mut scale = 1.0;
        // The smallest normal f64 is 2^-1022: a scene that needs more is refused at load, by
        // the value that does not fit.
        for _ in 0..1022 {
            if fits(scale) {
                break;
            }
            scale *= 0.5;
        }
        scale
    }

    /// `kind`, a load error in a scene scaled by `scale`, with its cause: a length below
    /// `S`'s resolution in a scene that was scaled down is the far coordinate's doing.
    pub(crate) fn explain<S: Scalar>(&self, kind: ErrorKind, scale: f64) -> ErrorKind {
        let (ErrorKind::TooSmallForType { attr, number_type }, Some(largest_at)) =
            (kind, self.largest_at)
        else {
            return kind;
        };
        if !(scale < 1.0) {
            return kind;
        }
        ErrorKind::ScaledBelowResolution {
            attr,
            number_type,
            largest_at,
            largest: whole(self.largest),
            range_log2: log2(S::MAX_EXTENT),
            scaled_log2: log2(1.0 / scale),
        }
    }

    /// Whether every length stays at or above `S`'s resolution once scaled.
    pub fn fits<S: Scalar>(&self) -> bool {
        self.smallest == f64::INFINITY || self.smallest * self.scale_for::<S>() >= S::MIN_FEATURE
    }
}

/// `x` rounded to a whole number, saturating (`as` saturates and maps NaN to 0).
fn whole(x: f64) -> u64 {
    libm::round(x) as u64
}

/// The largest `k` with `2^k <= x`, for `x` at least 1 (0 below).
fn log2(x: f64) -> u16 {
    u16::try_from(libm::ilogb(x)).unwrap_or(0)
}

/// The number types microray computes in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NumberType {
    /// `f64`: the reference.
    F64,
    /// `f32`: hardware on Cortex-M4F/M7.
    F32,
    /// Q16.16 fixed point: integer-only, for cores without a floating-point unit.
    I16F16,
}

impl NumberType {
    /// The name used on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            NumberType::F64 => f64::NAME,
            NumberType::F32 => f32::NAME,
            NumberType::I16F16 => I16F16::NAME,
        }
    }
}

/// What a build runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// A desktop or server processor: 64-bit floats in hardware.
    Host,
    /// A microcontroller with a single-precision FPU (Cortex-M4F, M7, ESP32-S3).
    SinglePrecisionFpu,
    /// A microcontroller without an FPU (Cortex-M0/M0+, RP2040, ESP32-C3).
    NoFpu,
}
