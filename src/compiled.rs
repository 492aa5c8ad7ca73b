//! Compiled scenes: a scene as it is once loaded, its values bit for bit in the number type,
//! written on the host ([`Scene::write_compiled`](crate::Scene::write_compiled), `microray
//! compile`) and read by firmware ([`Scene::load_compiled`](crate::Scene::load_compiled)).
//!
//! Loading a scene from text or from `*Def` values takes `f64` arithmetic (scaling, unit
//! normals, the camera's checks), which a Cortex-M has only in software; a compiled scene
//! needs none of it, nor the parser: the minimal firmware reads its scene this way. The
//! bytes are checked as they are read (their layout, the number type, every index and kind),
//! and a problem is an [`ErrorKind::Compiled`] naming the byte; the values themselves are
//! taken as the host loaded them.
//!
//! The layout (little-endian; a number is `RAW_BYTES` of [`Scalar::to_raw`], a text is a
//! length byte and UTF-8): `mray`, the version, the number type's [`Scalar::CODE`], the
//! scale (`f64` bits), the z rule's limit, the camera, then materials, textures (name and file name), lights
//! and objects, each list after its `u16` count.

use crate::camera::Camera;
use crate::error::{ErrorKind, Feature};
use crate::light::{Light, Spot};
use crate::material::{Material, MaterialId};
use crate::name::bounded;
use crate::object::plane::plane_object;
use crate::object::{
    Object, Plane, Rect, RevSurf, Shape, Sphere, Surfer, TexPlane, TextureMode, TiledPlane,
};
use crate::scalar::Scalar;
use crate::vec3::Vec3;

pub use crate::error::CompiledError;

/// The first bytes of a compiled scene.
pub const MAGIC: [u8; 4] = *b"mray";
/// The layout's version, after the magic bytes.
pub const VERSION: u8 = 2;

/// Writes the bytes of a compiled scene to a sink.
pub(crate) struct Writer<'w> {
    sink: &'w mut dyn FnMut(&[u8]),
}

impl<'w> Writer<'w> {
    pub(crate) fn new(sink: &'w mut dyn FnMut(&[u8])) -> Self {
        Self { sink }
    }
    pub(crate) fn bytes(&mut self, bytes: &[u8]) {
        (self.sink)(bytes);
    }
    pub(crate) fn byte(&mut self, value: u8) {
        self.bytes(&[value]);
    }
    pub(crate) fn u16(&mut self, value: u16) {
        self.bytes(&value.to_le_bytes());
    }
    /// A list's length (lists are bounded by `u16` capacities at load).
    pub(crate) fn count(&mut self, len: usize) {
        self.u16(u16::try_from(len).unwrap_or(u16::MAX));
    }
    pub(crate) fn f64(&mut self, value: f64) {
        self.bytes(&value.to_bits().to_le_bytes());
    }
    pub(crate) fn number<S: Scalar>(&mut self, value: S) {
        let raw = value.to_raw().to_le_bytes();
        self.bytes(raw.get(..S::RAW_BYTES).unwrap_or(&raw));
    }
    pub(crate) fn vec3<S: Scalar>(&mut self, v: Vec3<S>) {
        self.number(v.x);
        self.number(v.y);
        self.number(v.z);
    }
    /// Names and file names are bounded to 128 bytes at load, so a length byte holds them.
    pub(crate) fn text(&mut self, text: &str) {
        let len = text.len().min(usize::from(u8::MAX));
        self.byte(len as u8);
        self.bytes(text.as_bytes().get(..len).unwrap_or_default());
    }
}

/// Reads a compiled scene, checking as it goes.
pub(crate) struct Reader<'b> {
    bytes: &'b [u8],
    at: usize,
    /// Where a number ran past the end (numbers are not checked one by one: see `number`).
    truncated_at: Option<usize>,
}

impl<'b> Reader<'b> {
    pub(crate) fn new(bytes: &'b [u8]) -> Self {
        Self {
            bytes,
            at: 0,
            truncated_at: None,
        }
    }
    /// A problem with the value that starts at byte `at`.
    fn error_at(at: usize, problem: CompiledError) -> ErrorKind {
        ErrorKind::Compiled {
            offset: u32::try_from(at).unwrap_or(u32::MAX),
            problem,
        }
    }
    fn error(&self, problem: CompiledError) -> ErrorKind {
        Self::error_at(self.at, problem)
    }
    fn take(&mut self, n: usize) -> Result<&'b [u8], ErrorKind> {
        let end = self.at.checked_add(n);
        let bytes = end
            .and_then(|end| self.bytes.get(self.at..end))
            .ok_or(self.error(CompiledError::Truncated))?;
        self.at += n;
        Ok(bytes)
    }
    fn array<const N: usize>(&mut self) -> Result<[u8; N], ErrorKind> {
        let mut out = [0; N];
        out.copy_from_slice(self.take(N)?);
        Ok(out)
    }
    pub(crate) fn byte(&mut self) -> Result<u8, ErrorKind> {
        Ok(self.array::<1>()?[0])
    }
    pub(crate) fn u16(&mut self) -> Result<u16, ErrorKind> {
        Ok(u16::from_le_bytes(self.array()?))
    }
    pub(crate) fn f64(&mut self) -> Result<f64, ErrorKind> {
        Ok(f64::from_bits(u64::from_le_bytes(self.array()?)))
    }
    /// A number. Past the end it reads as zero and the reader remembers where, which
    /// [`checked`](Self::checked) reports: scenes are mostly numbers, and one check at the
    /// end instead of one at each saves flash. (No value is used before that check. Not
    /// through `take`, whose error, built and dropped here, costs 60 B of a Cortex-M0's.)
    pub(crate) fn number<S: Scalar>(&mut self) -> S {
        let mut raw = [0; 8];
        let end = self.at.checked_add(S::RAW_BYTES);
        match end.and_then(|end| self.bytes.get(self.at..end)) {
            Some(bytes) => {
                if let Some(low) = raw.get_mut(..bytes.len()) {
                    low.copy_from_slice(bytes);
                }
                self.at += S::RAW_BYTES;
            }
            None => {
                self.truncated_at.get_or_insert(self.at);
                self.at = self.bytes.len();
            }
        }
        S::from_raw(u64::from_le_bytes(raw))
    }
    pub(crate) fn vec3<S: Scalar>(&mut self) -> Vec3<S> {
        Vec3::new(self.number(), self.number(), self.number())
    }
    /// The outcome of reading a whole scene: a number past the end comes first, as the
    /// first problem in the bytes (later checks saw its zeros).
    pub(crate) fn checked(&self, result: Result<(), ErrorKind>) -> Result<(), ErrorKind> {
        match self.truncated_at {
            Some(at) => Err(Self::error_at(at, CompiledError::Truncated)),
            None => result,
        }
    }
    pub(crate) fn text(&mut self) -> Result<&'b str, ErrorKind> {
        let len = self.byte()?;
        let bytes = self.take(usize::from(len))?;
        core::str::from_utf8(bytes).map_err(|_| ErrorKind::NotUtf8)
    }
    /// An index into a list of `len` entries.
    pub(crate) fn index(&mut self, len: usize) -> Result<u16, ErrorKind> {
        let at = self.at;
        let index = self.u16()?;
        if usize::from(index) < len {
            Ok(index)
        } else {
            Err(Self::error_at(at, CompiledError::BadIndex))
        }
    }
    /// One of `0..limit`.
    fn choice(&mut self, limit: u8) -> Result<u8, ErrorKind> {
        let at = self.at;
        let value = self.byte()?;
        if value < limit {
            Ok(value)
        } else {
            Err(Self::error_at(at, CompiledError::BadValue))
        }
    }
    fn flag(&mut self) -> Result<bool, ErrorKind> {
        Ok(self.choice(2)? == 1)
    }
    /// The header: magic, version, number type; then the scale.
    pub(crate) fn header<S: Scalar>(&mut self) -> Result<f64, ErrorKind> {
        if self.take(MAGIC.len()).ok() != Some(&MAGIC[..]) || self.byte().ok() != Some(VERSION) {
            return Err(ErrorKind::Compiled {
                offset: 0,
                problem: CompiledError::NotCompiled,
            });
        }
        let at = self.at;
        let code = self.byte()?;
        if code != S::CODE {
            return Err(Self::error_at(
                at,
                CompiledError::OtherNumberType { found: code },
            ));
        }
        self.f64()
    }
    /// Checks that nothing follows the last object.
    pub(crate) fn finish(&self) -> Result<(), ErrorKind> {
        if self.at == self.bytes.len() {
            Ok(())
        } else {
            Err(self.error(CompiledError::Trailing))
        }
    }
}

pub(crate) fn write_header<S: Scalar>(out: &mut Writer<'_>, scale: f64) {
    out.bytes(&MAGIC);
    out.byte(VERSION);
    out.byte(S::CODE);
    out.f64(scale);
}

pub(crate) fn write_camera<S: Scalar>(out: &mut Writer<'_>, camera: &Camera<S>) {
    out.text(&camera.name);
    out.u16(camera.width);
    out.u16(camera.height);
    out.number(camera.world[0]);
    out.number(camera.world[1]);
    out.vec3(camera.viewpoint);
}

/// A camera, checked against the row buffer as [`Camera::with_pixels`] checks (the pixel
/// angle was checked for this number type when the scene was compiled).
pub(crate) fn read_camera<S: Scalar>(
    input: &mut Reader<'_>,
    max_width: usize,
) -> Result<Camera<S>, ErrorKind> {
    let name = bounded(input.text()?)?;
    let (width, height) = (input.u16()?, input.u16()?);
    if width < 2 || height < 2 {
        return Err(ErrorKind::PixeldimTooSmall);
    }
    if usize::from(width) > max_width {
        return Err(ErrorKind::ImageTooWide {
            width: u32::from(width),
            max: u32::try_from(max_width).unwrap_or(u32::MAX),
        });
    }
    let at = input.at;
    let world: [S; 2] = [input.number(), input.number()];
    // NaN fails this too.
    if !world.iter().all(|&w| w > S::ZERO) {
        return Err(Reader::error_at(at, CompiledError::BadValue));
    }
    Ok(Camera {
        name,
        width,
        height,
        world,
        viewpoint: input.vec3(),
    })
}

pub(crate) fn write_material<S: Scalar>(out: &mut Writer<'_>, m: &Material<S>) {
    out.text(m.name());
    out.vec3(m.ambient);
    out.vec3(m.diffuse);
    out.vec3(m.specular);
    out.number(m.shininess);
    out.number(m.transparency);
    out.vec3(m.filter);
}

pub(crate) fn read_material<S: Scalar>(input: &mut Reader<'_>) -> Result<Material<S>, ErrorKind> {
    let name = bounded(input.text()?)?;
    let ambient = input.vec3();
    let diffuse = input.vec3();
    let specular = input.vec3();
    let shininess = input.number();
    let transparency = input.number();
    let filter = input.vec3();
    Ok(Material::from_parts(
        name,
        [ambient, diffuse, specular, filter],
        shininess,
        transparency,
    ))
}

pub(crate) fn write_light<S: Scalar>(out: &mut Writer<'_>, light: &Light<S>) {
    out.text(light.name());
    out.vec3(light.location);
    out.vec3(light.emissivity);
    out.vec3(light.diffuse_emissivity);
    match &light.spot {
        None => out.byte(0),
        Some(spot) => {
            out.byte(1);
            out.vec3(spot.point);
            out.number(spot.theta);
            out.vec3(spot.axis);
            out.number(spot.cos_theta);
        }
    }
    match light.slide() {
        None => out.byte(0),
        Some(slide) => {
            out.byte(1);
            write_slide(out, slide);
        }
    }
}

fn write_slide<S: Scalar>(out: &mut Writer<'_>, t: &TexPlane<S>) {
    write_rect(out, &t.rect);
    out.u16(t.texture);
    out.byte(t.mode as u8);
}

/// A texplane's or projector's textured rectangle, its texture index checked.
fn read_slide<S: Scalar>(
    input: &mut Reader<'_>,
    textures: usize,
) -> Result<TexPlane<S>, ErrorKind> {
    Ok(TexPlane {
        rect: read_rect(input)?,
        texture: input.index(textures)?,
        mode: match input.choice(2)? {
            0 => TextureMode::Fit,
            _ => TextureMode::Tile,
        },
    })
}

pub(crate) fn read_light<S: Scalar>(
    input: &mut Reader<'_>,
    textures: usize,
) -> Result<Light<S>, ErrorKind> {
    let name = bounded(input.text()?)?;
    let (location, emissivity, diffuse_emissivity) = (input.vec3(), input.vec3(), input.vec3());
    let spot = if input.flag()? {
        Feature::Spotlight.require(None)?;
        Some(Spot {
            point: input.vec3(),
            theta: input.number(),
            axis: input.vec3(),
            cos_theta: input.number(),
        })
    } else {
        None
    };
    let projector = input.flag()?;
    if projector {
        Feature::Projector.require(None)?;
    }
    #[cfg(feature = "projector")]
    let slide = if projector {
        Some(read_slide(input, textures)?)
    } else {
        None
    };
    #[cfg(not(feature = "projector"))]
    let _ = textures;
    Ok(Light {
        name,
        location,
        emissivity,
        diffuse_emissivity,
        spot,
        #[cfg(feature = "projector")]
        slide,
    })
}

/// The kinds' tags in a compiled scene.
const PLANE: u8 = 0;
const SPHERE: u8 = 1;
const FPLANE: u8 = 2;
const TILED_PLANE: u8 = 3;
const TEX_PLANE: u8 = 4;
const REV_SURF: u8 = 5;

fn write_plane<S: Scalar>(out: &mut Writer<'_>, p: &Plane<S>) {
    out.vec3(p.normal);
    out.vec3(p.point);
    out.vec3(p.unit_normal);
    out.number(p.n_dot_point);
    out.byte(p.axis.unwrap_or(u8::MAX));
}

fn read_plane<S: Scalar>(input: &mut Reader<'_>) -> Result<Plane<S>, ErrorKind> {
    let (normal, point, unit_normal, n_dot_point) =
        (input.vec3(), input.vec3(), input.vec3(), input.number());
    let at = input.at;
    let axis = match input.byte()? {
        u8::MAX => None,
        axis if usize::from(axis) < Plane::<S>::AXIS_VTABLES.len() => Some(axis),
        _ => return Err(Reader::error_at(at, CompiledError::BadValue)),
    };
    Ok(Plane {
        normal,
        point,
        unit_normal,
        n_dot_point,
        axis,
    })
}

fn write_rect<S: Scalar>(out: &mut Writer<'_>, r: &Rect<S>) {
    write_plane(out, &r.plane);
    out.vec3(r.xdir);
    out.number(r.dimensions[0]);
    out.number(r.dimensions[1]);
    out.vec3(r.u);
    out.vec3(r.v);
}

fn read_rect<S: Scalar>(input: &mut Reader<'_>) -> Result<Rect<S>, ErrorKind> {
    Ok(Rect::new(
        read_plane(input)?,
        input.vec3(),
        [input.number(), input.number()],
        input.vec3(),
        input.vec3(),
    ))
}

pub(crate) fn write_object<S: Scalar>(out: &mut Writer<'_>, object: &Object<S>) {
    out.text(object.name());
    out.u16(object.material());
    match object.shape() {
        Shape::Plane(p) => {
            out.byte(PLANE);
            write_plane(out, p);
        }
        Shape::Sphere(s) => {
            out.byte(SPHERE);
            out.vec3(s.center);
            out.number(s.radius);
            out.number(s.radius_squared);
        }
        Shape::FPlane(r) => {
            out.byte(FPLANE);
            write_rect(out, r);
        }
        Shape::TiledPlane(t) => {
            out.byte(TILED_PLANE);
            write_rect(out, &t.rect);
            out.u16(t.altmaterial);
            for (odd, offset) in t.offset {
                out.byte(u8::from(odd));
                out.number(offset);
            }
            out.f64(t.written_dimensions[0]);
            out.f64(t.written_dimensions[1]);
        }
        Shape::TexPlane(t) => {
            out.byte(TEX_PLANE);
            write_slide(out, t);
        }
        Shape::RevSurf(r) => {
            out.byte(REV_SURF);
            out.byte(r.surfer as u8 - 1);
            for v in [r.base, r.direction, r.axis] {
                out.vec3(v);
            }
            for n in [r.height, r.scale, r.unscale, r.reach, r.steepest] {
                out.number(n);
            }
            out.vec3(r.center);
            out.number(r.bound);
        }
    }
}

/// An object, its material and texture indices checked against the lists so far, with its
/// kind's table installed as the kind's `*_init` installs it. Each kind is read after its
/// feature check, so a build without the feature leaves the kind's code out.
pub(crate) fn read_object<S: Scalar>(
    input: &mut Reader<'_>,
    materials: usize,
    textures: usize,
) -> Result<Object<S>, ErrorKind> {
    let name = input.text()?;
    let material: MaterialId = input.index(materials)?;
    let at = input.at;
    match input.byte()? {
        PLANE => plane_object(name, material, read_plane(input)?),
        SPHERE => {
            let sphere = Sphere {
                center: input.vec3(),
                radius: input.number(),
                radius_squared: input.number(),
            };
            Object::init(&Sphere::VTABLE, name, material, Shape::Sphere(sphere))
        }
        FPLANE => {
            Feature::FPlane.require(None)?;
            let rect = read_rect(input)?;
            Object::init(rect.fplane_vtable(), name, material, Shape::FPlane(rect))
        }
        TILED_PLANE => {
            Feature::TiledPlane.require(None)?;
            let tiled = TiledPlane {
                rect: read_rect(input)?,
                altmaterial: input.index(materials)?,
                offset: [
                    (input.flag()?, input.number()),
                    (input.flag()?, input.number()),
                ],
                written_dimensions: [input.f64()?, input.f64()?],
            };
            Object::init(
                &TiledPlane::VTABLE,
                name,
                material,
                Shape::TiledPlane(tiled),
            )
        }
        TEX_PLANE => {
            Feature::Texture.require(None)?;
            let textured = read_slide(input, textures)?;
            Object::init(&TexPlane::VTABLE, name, material, Shape::TexPlane(textured))
        }
        REV_SURF => {
            Feature::RevSurf.require(None)?;
            let surfer = match input.choice(3)? {
                0 => Surfer::Cone,
                1 => Surfer::Waist,
                _ => Surfer::Vase,
            };
            let surface = RevSurf {
                surfer,
                base: input.vec3(),
                direction: input.vec3(),
                axis: input.vec3(),
                height: input.number(),
                scale: input.number(),
                unscale: input.number(),
                reach: input.number(),
                steepest: input.number(),
                center: input.vec3(),
                bound: input.number(),
            };
            Object::init(&RevSurf::VTABLE, name, material, Shape::RevSurf(surface))
        }
        _ => Err(Reader::error_at(at, CompiledError::BadValue)),
    }
}
