//! Warnings about ill-posed scenes: configurations that load and render, but whose picture
//! is decided by rounding rather than by the scene.
//!
//! Where two surfaces coincide, which of them a ray meets is a tie that the last bit of a
//! product decides (two identical planes shade an eighth of a picture differently from one
//! plane, in f64 itself); a light exactly on a surface lights it from a side that rounding
//! picks; a surface through the eye is met at `t = 0` or not at all; an eye inside a sphere
//! starts every ray inside it. The number types round differently, so such a scene's
//! pictures in f32 and I16F16 can differ grossly from f64's, and from each other. These are
//! warnings, not errors: the scene is still rendered.
//!
//! "Exactly" means within 2^-20 of the size of the numbers involved (about one part in a
//! million): what a decimal written for an exact position (`0.1`, a computed coordinate
//! printed to 17 digits) leaves, and far below anything a scene means by "near".
//!
//! ```
//! use microray::{parse::{no_textures, parse_scene}, Scene, warning::Warning};
//!
//! let text = b"camera c { pixeldim 8 6 worlddim 8 6 viewpoint 4 3 3 }
//!     material m { diffuse 1 1 1 }
//!     light lamp { location 0 0 0 emissivity 1 1 1 }
//!     plane floor { material m normal 0 1 0 point 0 0 0 }";
//! let scene: Scene<f64, 4, 4, 2, 0, 8> = parse_scene(text, no_textures)?;
//! let mut found = Vec::new();
//! scene.warnings(|w| found.push(w.to_string()));
//! assert_eq!(found, ["light `lamp` is on the surface of plane `floor`: which side it lights is decided by rounding"]);
//! # Ok::<(), microray::Error>(())
//! ```

use crate::error::Entity;
use crate::light::Light;
use crate::object::{Object, Shape};
use crate::scalar::Scalar;
use crate::vec3::Vec3;
use core::fmt;

/// Distances below this fraction of the numbers involved count as zero.
pub const TOLERANCE: f64 = 1.0 / 1_048_576.0;

/// An ill-posed configuration of a scene (see the module's docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Warning<'s> {
    /// What is wrong.
    pub kind: WarningKind,
    /// The objects and lights involved: kind and name, the first always there.
    pub first: (Entity, &'s str),
    /// The second party of a pair (two objects, a light and an object).
    pub second: Option<(Entity, &'s str)>,
}

/// What a [`Warning`] is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WarningKind {
    /// Two objects' surfaces coincide where both are.
    CoincidentSurfaces,
    /// A light lies on an object's surface.
    LightOnSurface,
    /// A light is at the eye.
    LightAtEye,
    /// An object's surface passes through the eye.
    SurfaceThroughEye,
    /// The eye is inside an object (a sphere, or a surface of revolution's inside).
    EyeInside,
}

impl fmt::Display for Warning<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (kind, name) = self.first;
        write!(f, "{kind} `{name}`")?;
        let second = self.second.unwrap_or((kind, name));
        let (other_kind, other) = second;
        match self.kind {
            WarningKind::CoincidentSurfaces => write!(
                f,
                " and {other_kind} `{other}` coincide: which one a ray meets is decided by rounding"
            ),
            WarningKind::LightOnSurface => write!(
                f,
                " is on the surface of {other_kind} `{other}`: which side it lights is decided by rounding"
            ),
            WarningKind::LightAtEye => f.write_str(
                " is at the eye: its glints and the shadows it casts are decided by rounding",
            ),
            WarningKind::SurfaceThroughEye => f.write_str(
                " passes through the eye: whether a ray meets it at the start is decided by rounding",
            ),
            WarningKind::EyeInside => {
                f.write_str(" has the eye inside it: every ray starts inside its surface")
            }
        }
    }
}

/// Calls `each` with every warning about a scene's camera `eye`, `lights` and `objects`
/// (what [`Scene::warnings`](crate::Scene::warnings) does).
pub fn warnings<'s, S: Scalar>(
    eye: Vec3<S>,
    lights: &'s [Light<S>],
    objects: &'s [Object<S>],
    mut each: impl FnMut(Warning<'s>),
) {
    let eye = eye.to_f64();
    let object = |o: &'s Object<S>| (o.kind(), o.name());
    for (i, a) in objects.iter().enumerate() {
        let shape = Surface::of(a.shape());
        if shape.near(eye) {
            each(Warning {
                kind: WarningKind::SurfaceThroughEye,
                first: object(a),
                second: None,
            });
        } else if shape.encloses(eye) {
            each(Warning {
                kind: WarningKind::EyeInside,
                first: object(a),
                second: None,
            });
        }
        for b in objects.iter().skip(i + 1) {
            if shape.coincides(&Surface::of(b.shape())) {
                each(Warning {
                    kind: WarningKind::CoincidentSurfaces,
                    first: object(a),
                    second: Some(object(b)),
                });
            }
        }
    }
    for light in lights {
        let location = light.location.to_f64();
        let named = (light_kind(light), light.name());
        if near(location, eye, 0.0) {
            each(Warning {
                kind: WarningKind::LightAtEye,
                first: named,
                second: None,
            });
        }
        for o in objects {
            if Surface::of(o.shape()).near(location) {
                each(Warning {
                    kind: WarningKind::LightOnSurface,
                    first: named,
                    second: Some(object(o)),
                });
            }
        }
    }
}

fn light_kind<S: Scalar>(light: &Light<S>) -> Entity {
    if light.slide().is_some() {
        Entity::Projector
    } else if light.spot.is_some() {
        Entity::Spotlight
    } else {
        Entity::Light
    }
}

/// Whether two points are the same, to [`TOLERANCE`] of their size and of `size`.
fn near(a: Vec3<f64>, b: Vec3<f64>, size: f64) -> bool {
    (a - b).length() <= TOLERANCE * magnitude(&[a, b]).max(size.abs())
}

/// The largest coordinate of some points.
fn magnitude(points: &[Vec3<f64>]) -> f64 {
    points
        .iter()
        .fold(0.0, |m, p| m.max(p.x.abs()).max(p.y.abs()).max(p.z.abs()))
}

/// An object's surface in f64, for the tests above.
enum Surface {
    /// A plane `n . x = offset` (`n` unit), with the rectangle on it if it is finite:
    /// corner, unit axes and size.
    Plane {
        normal: Vec3<f64>,
        point: Vec3<f64>,
        rect: Option<(Vec3<f64>, Vec3<f64>, [f64; 2])>,
    },
    Sphere {
        center: Vec3<f64>,
        radius: f64,
    },
    /// A surface of revolution: profile, foot, unit axis, height, scale.
    RevSurf {
        surfer: u8,
        base: Vec3<f64>,
        axis: Vec3<f64>,
        height: f64,
        scale: f64,
    },
}

impl Surface {
    fn of<S: Scalar>(shape: &Shape<S>) -> Self {
        let rect = |r: &crate::object::Rect<S>| Surface::Plane {
            normal: r.plane.unit_normal.to_f64(),
            point: r.plane.point.to_f64(),
            rect: Some((
                r.u.to_f64(),
                r.v.to_f64(),
                [r.dimensions[0].to_f64(), r.dimensions[1].to_f64()],
            )),
        };
        match shape {
            Shape::Plane(p) => Surface::Plane {
                normal: p.unit_normal.to_f64(),
                point: p.point.to_f64(),
                rect: None,
            },
            Shape::Sphere(s) => Surface::Sphere {
                center: s.center.to_f64(),
                radius: s.radius.to_f64(),
            },
            Shape::FPlane(r) => rect(r),
            Shape::TiledPlane(t) => Surface::Plane {
                normal: t.rect.plane.unit_normal.to_f64(),
                point: t.rect.plane.point.to_f64(),
                rect: None,
            },
            Shape::TexPlane(t) => rect(&t.rect),
            Shape::RevSurf(r) => Surface::RevSurf {
                surfer: r.surfer as u8,
                base: r.base.to_f64(),
                axis: r.axis.to_f64(),
                height: r.height.to_f64(),
                scale: r.scale.to_f64(),
            },
        }
    }

    /// Whether `p` is on the surface, to [`TOLERANCE`].
    fn near(&self, p: Vec3<f64>) -> bool {
        match *self {
            Surface::Plane {
                normal,
                point,
                rect,
            } => {
                let size = rect.map_or(0.0, |(_, _, [w, h])| w.max(h));
                let tolerance = TOLERANCE * magnitude(&[p, point]).max(size);
                let off = (p - point).dot(normal);
                if off.abs() > tolerance {
                    return false;
                }
                rect.is_none_or(|(u, v, [w, h])| {
                    let (x, y) = ((p - point).dot(u), (p - point).dot(v));
                    x >= -tolerance && x <= w + tolerance && y >= -tolerance && y <= h + tolerance
                })
            }
            Surface::Sphere { center, radius } => {
                let tolerance = TOLERANCE * magnitude(&[p, center]).max(radius);
                ((p - center).length() - radius).abs() <= tolerance
            }
            Surface::RevSurf { .. } => {
                let Some((h, rho, r, height, tolerance)) = self.cylindrical(p) else {
                    return false;
                };
                (-tolerance..=height + tolerance).contains(&h) && (rho - r).abs() <= tolerance
            }
        }
    }

    /// Whether `p` is inside a closed surface (a sphere) or within a surface of
    /// revolution's profile between its ends.
    fn encloses(&self, p: Vec3<f64>) -> bool {
        match *self {
            Surface::Sphere { center, radius } => (p - center).length() < radius,
            Surface::RevSurf { .. } => self
                .cylindrical(p)
                .is_some_and(|(h, rho, r, height, _)| h > 0.0 && h < height && rho < r),
            Surface::Plane { .. } => false,
        }
    }

    /// A surface of revolution's height, distance from the axis and radius at `p`, its
    /// height and the tolerance there.
    fn cylindrical(&self, p: Vec3<f64>) -> Option<(f64, f64, f64, f64, f64)> {
        let Surface::RevSurf {
            surfer,
            base,
            axis,
            height,
            scale,
        } = *self
        else {
            return None;
        };
        let w = p - base;
        let h = w.dot(axis);
        let rho = (w - axis * h).length();
        let x = h.clamp(0.0, height) / scale;
        let r = scale
            * match surfer {
                1 => (4.0 - 2.0 * x / 3.0).max(0.0),
                2 => 1.0 + libm::cos(x) / 2.0,
                _ => 1.0 + libm::sin(x) / 2.0,
            };
        let tolerance = TOLERANCE * magnitude(&[p, base]).max(height);
        Some((h, rho, r, height, tolerance))
    }

    /// Whether two surfaces coincide where both are (to [`TOLERANCE`]).
    fn coincides(&self, other: &Surface) -> bool {
        match (self, other) {
            (
                Surface::Sphere { center, radius },
                Surface::Sphere {
                    center: c,
                    radius: r,
                },
            ) => {
                near(*center, *c, radius.max(*r))
                    && (radius - r).abs() <= TOLERANCE * radius.max(*r)
            }
            (
                Surface::Plane {
                    normal,
                    point,
                    rect,
                },
                Surface::Plane {
                    normal: n,
                    point: q,
                    rect: other_rect,
                },
            ) => {
                let size = |r: &Option<(_, _, [f64; 2])>| r.map_or(0.0, |(_, _, [w, h])| w.max(h));
                let tolerance = TOLERANCE
                    * magnitude(&[*point, *q])
                        .max(size(rect))
                        .max(size(other_rect));
                normal.cross(*n).length() <= TOLERANCE
                    && (*q - *point).dot(*normal).abs() <= tolerance
                    && overlap(*point, *rect, *q, *other_rect)
            }
            (
                Surface::RevSurf {
                    surfer,
                    base,
                    axis,
                    height,
                    ..
                },
                Surface::RevSurf {
                    surfer: s,
                    base: b,
                    axis: a,
                    height: h,
                    ..
                },
            ) => {
                surfer == s && near(*base, *b, height.max(*h)) && (*axis - *a).length() <= TOLERANCE
            }
            _ => false,
        }
    }
}

/// Whether two rectangles (or infinite planes, `None`) on one plane overlap, by the
/// second's corners against the first's extent along its axes.
fn overlap(
    point: Vec3<f64>,
    rect: Option<(Vec3<f64>, Vec3<f64>, [f64; 2])>,
    other_point: Vec3<f64>,
    other: Option<(Vec3<f64>, Vec3<f64>, [f64; 2])>,
) -> bool {
    let (Some((u, v, [w, h])), Some((ou, ov, [ow, oh]))) = (rect, other) else {
        return true;
    };
    let corners = [
        other_point,
        other_point + ou * ow,
        other_point + ov * oh,
        other_point + ou * ow + ov * oh,
    ];
    let along = |axis: Vec3<f64>| {
        corners
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), &c| {
                let x = (c - point).dot(axis);
                (low.min(x), high.max(x))
            })
    };
    let ((x0, x1), (y0, y1)) = (along(u), along(v));
    x0 < w && x1 > 0.0 && y0 < h && y1 > 0.0
}
