//! The scene: camera, materials, lights, textures and objects in bounded lists.
//!
//! Capacities are const generics with defaults, as in `heapless`: a firmware build sizes its
//! scene in the type (`Scene<'static, f32, 8, 4, 2, 0, 240>`), and adding past a capacity is
//! an [`ErrorKind::CapacityExceeded`], never a panic.

use crate::camera::{Camera, CameraDef};
use crate::compiled;
use crate::error::{Collection, Entity, Error, ErrorKind, Feature, Snippet, TextureError};
use crate::hits::closest_hit;
use crate::light::{Light, LightDef};
use crate::material::{Material, MaterialDef, MaterialId};
use crate::object::{Hit, Object, ObjectDef, Palette};
use crate::range::Extent;
use crate::ray::Ray;
use crate::scalar::Scalar;
use crate::texture::{Texture, TextureDef};
use heapless::Vec;

pub use crate::ray::Limits;

/// The default widest image: the renderer keeps one row of this many pixels.
pub const DEFAULT_MAX_WIDTH: usize = 1024;

/// A few objects on a small panel: 4 objects, 4 materials, 2 lights, 1 texture, 320 pixels
/// wide (a floor, a wall and two balls under a lamp and a spotlight). About 1.6 KiB of RAM
/// on a 32-bit Cortex-M in `f32` or `I16F16` (the slot sizes are in [`Scene`]'s docs; [`crate::capacity`] counts a scene file's).
pub type TinyScene<'t, S> = Scene<'t, S, 4, 4, 2, 1, 320>;

/// A room of things on a panel up to 480 pixels wide: 16 objects, 8 materials, 4 lights,
/// 4 textures. About 4.8 KiB of RAM on a 32-bit Cortex-M.
pub type SmallScene<'t, S> = Scene<'t, S, 16, 8, 4, 4, 480>;

/// Most hand-written scenes, up to 1024 pixels wide: 128 objects, 32 materials, 16 lights,
/// 16 textures. About 30 KiB of RAM on a 32-bit Cortex-M: for boards with RAM to spare, or
/// the host.
pub type LargeScene<'t, S> = Scene<'t, S, 128, 32, 16, 16, 1024>;

/// A checked scene, built in place: [`Scene::new`] with a camera, then `add_*` for each part,
/// checking each as it comes (no second copy of the scene is ever needed, which matters on a
/// microcontroller's stack). Or [`Scene::from_defs`], or the parser.
///
/// `'t` is the lifetime of texture bytes; the capacities are `OBJECTS`, `MATERIALS`,
/// `LIGHTS`, `TEXTURES` and the widest image `MAX_WIDTH`. Materials and textures must be
/// added before the objects that name them, as in the files.
///
/// # Sizing a scene
///
/// For a known scene file, give each capacity what the file defines and no more (count its
/// `material`, `light`/`spotlight`, `texture` and object blocks), and `MAX_WIDTH` the
/// panel's width: a scene is one fixed-size value, on the stack or in a `static`, and every
/// slot costs RAM whether it is used or not. On a 32-bit Cortex-M, in `f32` or `I16F16`
/// (measured by `cargo xtask qemu`, `docs/firmware.md` "RAM by part"):
///
/// | part | bytes |
/// |---|---|
/// | an object slot | 176 |
/// | a material slot | 92 |
/// | a light slot | 108 |
/// | a texture slot | 180 (the pixels stay where the bytes are: flash) |
/// | the rest of the scene (camera, scale) | about 90 |
/// | the [`Renderer`](crate::render::Renderer) (plan, tree, shader) | 288 for 4 objects, growing with `OBJECTS` |
/// | the row buffer | the width times the panel colour's size: 2 bytes for `Rgb565`, which the renderer converts to as it goes |
/// | the renderer's own stack | about 0.9 KiB for a floor and a wall (spec0), plus a trace frame (about 0.5 KiB on a Cortex-M0) per level of mirrors or glass the scene nests |
///
/// A slot too few is an [`ErrorKind::CapacityExceeded`] naming the collection (and, from the
/// parser, the line and column of the block that did not fit), never a panic; a row buffer
/// narrower than the image is a [`RenderError`](crate::render::RenderError). spec0 (a floor,
/// a wall, two materials, one light) at 320x240 on a Cortex-M0 in `I16F16` runs in under 6 KiB
/// of RAM this way, parser included:
///
/// ```
/// use microray::{parse::{no_textures, parse_scene_into}, render::Renderer, scalar::I16F16, Scene};
///
/// const SPEC0: &[u8] = b"
///     camera c { pixeldim 320 240 worlddim 8 6 viewpoint 4 3 3 }
///     material white { diffuse 3 3 3 ambient 1 1 1 specular 0.8 }
///     material green { diffuse 1 6 1 }
///     light center { location 4 10 0 emissivity 5 5 5 }
///     plane floor { material white normal 0 1 0 point 0 0 0 }
///     plane back { material green normal 0 0 1 point 0 0 -6 }
/// ";
/// // 2 objects, 2 materials, 1 light, no texture, 320 pixels wide.
/// type Spec0 = Scene<'static, I16F16, 2, 2, 1, 0, 320>;
/// let mut scene = Spec0::empty();
/// parse_scene_into(SPEC0, no_textures, &mut scene)?;
/// let renderer = Renderer::new(&scene);
/// assert_eq!(renderer.size().width, 320);
/// // One material too few does not fit, and says so.
/// let mut small: Scene<'static, I16F16, 2, 1, 1, 0, 320> = Scene::empty();
/// assert!(parse_scene_into(SPEC0, no_textures, &mut small).is_err());
/// # Ok::<(), microray::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Scene<
    't,
    S: Scalar,
    const OBJECTS: usize = 32,
    const MATERIALS: usize = 16,
    const LIGHTS: usize = 8,
    const TEXTURES: usize = 16,
    const MAX_WIDTH: usize = DEFAULT_MAX_WIDTH,
> {
    camera: Camera<S>,
    materials: Vec<Material<S>, MATERIALS>,
    lights: Vec<Light<S>, LIGHTS>,
    textures: Vec<Texture<'t>, TEXTURES>,
    objects: Vec<Object<S>, OBJECTS>,
    scale: f64,
    /// The limits in `S`, set with the scale (`None`: scale 1, not yet converted).
    limits: Option<Limits<S>>,
}

/// Adds to a bounded list, or says which list is full.
fn push<T, const N: usize>(
    list: &mut Vec<T, N>,
    item: T,
    what: Collection,
) -> Result<(), ErrorKind> {
    list.push(item).map_err(|_| capacity_error(what, N))
}

/// Puts `item` in place of entry `index` of a list and returns the entry it replaces.
#[cfg(feature = "animate")]
fn replace<T, const N: usize>(
    list: &mut Vec<T, N>,
    index: usize,
    item: T,
    what: Collection,
) -> Result<T, ErrorKind> {
    let slot = list.get_mut(index).ok_or_else(|| no_such(what, index))?;
    Ok(core::mem::replace(slot, item))
}

#[cfg(feature = "animate")]
fn no_such(what: Collection, index: usize) -> ErrorKind {
    ErrorKind::NoSuchIndex {
        what,
        index: u16::try_from(index).unwrap_or(u16::MAX),
    }
}

fn capacity_error(what: Collection, capacity: usize) -> ErrorKind {
    ErrorKind::CapacityExceeded {
        what,
        capacity: u16::try_from(capacity).unwrap_or(u16::MAX),
    }
}

impl<
    't,
    S: Scalar,
    const OBJECTS: usize,
    const MATERIALS: usize,
    const LIGHTS: usize,
    const TEXTURES: usize,
    const MAX_WIDTH: usize,
> Scene<'t, S, OBJECTS, MATERIALS, LIGHTS, TEXTURES, MAX_WIDTH>
{
    /// An empty scene with a camera. Every length is multiplied by `scale`, a power of two
    /// (see [`crate::range`]; [`Extent::scale_for`] chooses it, 1 uses the scene as written).
    pub fn new(camera: &CameraDef<'_>, scale: f64) -> Result<Self, ErrorKind> {
        let mut scene = Self::empty();
        scene.clear(scale);
        scene.set_camera(camera)?;
        Ok(scene)
    }

    /// An empty scene with a stand-in camera (2 by 2 pixels): the place to parse or load
    /// into ([`crate::parse::parse_scene_into`], [`Scene::load_defs`]) on a microcontroller,
    /// where the scene is built in place instead of returned.
    pub const fn empty() -> Self {
        Self {
            camera: Camera::PLACEHOLDER,
            materials: Vec::new(),
            lights: Vec::new(),
            textures: Vec::new(),
            objects: Vec::new(),
            scale: 1.0,
            limits: None,
        }
    }

    /// Empties the scene and sets the scale for what is added next; the camera becomes the
    /// stand-in until [`set_camera`](Self::set_camera).
    pub(crate) fn clear(&mut self, scale: f64) {
        self.clear_lists();
        self.scale = scale;
        self.limits = Some(Limits::at_scale(scale));
    }

    /// Empties the scene, keeping the scale.
    fn clear_lists(&mut self) {
        self.camera = Camera::PLACEHOLDER;
        self.materials.clear();
        self.lights.clear();
        self.textures.clear();
        self.objects.clear();
    }

    /// Replaces the camera.
    pub(crate) fn set_camera(&mut self, def: &CameraDef<'_>) -> Result<(), ErrorKind> {
        self.camera = Camera::build(def, MAX_WIDTH, self.scale)?;
        Ok(())
    }

    /// Adds a material; its name must be new.
    pub fn add_material(&mut self, def: &MaterialDef<'_>) -> Result<(), ErrorKind> {
        if self.find_material(def.name).is_some() {
            return Err(ErrorKind::DuplicateName {
                entity: Entity::Material,
                name: Snippet::new(def.name.as_bytes()),
            });
        }
        if self.materials.is_full() || u16::try_from(self.materials.len()).is_err() {
            return Err(capacity_error(Collection::Materials, MATERIALS));
        }
        let material = Material::build(def, self.scale)?;
        push(&mut self.materials, material, Collection::Materials)
    }

    /// Adds a light, spotlight or projector (after the texture a projector names).
    pub fn add_light(&mut self, def: &LightDef<'_>) -> Result<(), ErrorKind> {
        if self.lights.is_full() {
            return Err(capacity_error(Collection::Lights, LIGHTS));
        }
        let light = Light::build(def, self.scale, |n| self.find_texture(n))?;
        push(&mut self.lights, light, Collection::Lights)
    }

    /// Replaces object `index` (from 0, in definition order) with `def`, built as
    /// [`add_object`](Self::add_object) builds one, and returns the object it replaces: the
    /// old state a [`Region`](crate::region::Region) needs. On an error the scene is
    /// unchanged.
    #[cfg(feature = "animate")]
    pub fn replace_object(
        &mut self,
        index: usize,
        def: &ObjectDef<'_>,
    ) -> Result<Object<S>, ErrorKind> {
        let object = self.build_object(def)?;
        replace(&mut self.objects, index, object, Collection::Objects)
    }

    /// Replaces light `index` with `def` and returns the light it replaces (see
    /// [`replace_object`](Self::replace_object)).
    #[cfg(feature = "animate")]
    pub fn replace_light(
        &mut self,
        index: usize,
        def: &LightDef<'_>,
    ) -> Result<Light<S>, ErrorKind> {
        let light = Light::build(def, self.scale, |n| self.find_texture(n))?;
        replace(&mut self.lights, index, light, Collection::Lights)
    }

    /// Replaces the camera with `def` (its image no wider than the scene's rows hold) and
    /// returns the camera it replaces: a new view, which a
    /// [`Region::add_camera_change`](crate::region::Region::add_camera_change) takes as the
    /// whole frame. On an error the scene is unchanged.
    #[cfg(feature = "animate")]
    pub fn replace_camera(&mut self, def: &CameraDef<'_>) -> Result<Camera<S>, ErrorKind> {
        let camera = Camera::build(def, MAX_WIDTH, self.scale)?;
        Ok(core::mem::replace(&mut self.camera, camera))
    }

    /// Replaces material `index` with `def`, which must keep its name (objects name it),
    /// and returns the material it replaces.
    #[cfg(feature = "animate")]
    pub fn replace_material(
        &mut self,
        index: usize,
        def: &MaterialDef<'_>,
    ) -> Result<Material<S>, ErrorKind> {
        let material = Material::build(def, self.scale)?;
        let slot = self
            .materials
            .get_mut(index)
            .filter(|m| m.name() == def.name)
            .ok_or_else(|| no_such(Collection::Materials, index))?;
        Ok(core::mem::replace(slot, material))
    }

    /// Adds a texture, decoding its PPM bytes; its name must be new.
    pub fn add_texture(&mut self, def: &TextureDef<'_, 't>) -> Result<(), ErrorKind> {
        Feature::Texture.require(None)?;
        if self.find_texture(def.name).is_some() {
            return Err(ErrorKind::DuplicateName {
                entity: Entity::Texture,
                name: Snippet::new(def.name.as_bytes()),
            });
        }
        if self.textures.is_full() || u16::try_from(self.textures.len()).is_err() {
            return Err(capacity_error(Collection::Textures, TEXTURES));
        }
        let texture = Texture::build(def)?;
        push(&mut self.textures, texture, Collection::Textures)
    }

    /// Adds a texture whose PPM bytes `textures` finds by file name (the parser's way).
    pub(crate) fn add_texture_file(
        &mut self,
        name: &str,
        filename: &str,
        textures: &mut impl FnMut(&str) -> Result<&'t [u8], TextureError>,
    ) -> Result<(), ErrorKind> {
        let ppm = textures(filename).map_err(|error| ErrorKind::Texture {
            file: Snippet::new(filename.as_bytes()),
            error,
        })?;
        self.add_texture(&TextureDef {
            name,
            filename,
            ppm,
        })
    }

    /// Makes sure a texture named `texname` is there: the later course scenes name an image
    /// file directly (`texname FILE`), so a name that no texture block gave is read as a
    /// file, once, as if a `texture FILE { filename FILE }` block came first. A name that
    /// is neither is the undefined-texture error.
    #[cfg(feature = "parser")]
    pub(crate) fn add_texture_named(
        &mut self,
        texname: &str,
        textures: &mut impl FnMut(&str) -> Result<&'t [u8], TextureError>,
    ) -> Result<(), ErrorKind> {
        if !Feature::Texture.enabled() || self.find_texture(texname).is_some() {
            return Ok(());
        }
        self.add_texture_file(texname, texname, textures)
            .map_err(|e| match e {
                ErrorKind::Texture {
                    error: TextureError::NotFound,
                    ..
                } => ErrorKind::UndefinedTexture {
                    name: Snippet::new(texname.as_bytes()),
                },
                e => e,
            })
    }

    /// Adds an object; the materials and texture it names must already be there.
    pub fn add_object(&mut self, def: &ObjectDef<'_>) -> Result<(), ErrorKind> {
        // The render plan names objects by u16 index.
        if self.objects.is_full() || u16::try_from(self.objects.len()).is_err() {
            return Err(capacity_error(Collection::Objects, OBJECTS));
        }
        let object = self.build_object(def)?;
        push(&mut self.objects, object, Collection::Objects)
    }

    /// `def` built against this scene's materials, textures and scale: one copy of every
    /// kind's builder for adding and replacing (each closure type made its own, 14.7 KB on
    /// the Cortex-M0 with `animate`).
    #[inline(never)]
    fn build_object(&self, def: &ObjectDef<'_>) -> Result<Object<S>, ErrorKind> {
        Object::build(
            def,
            |n| self.find_material(n),
            |n| self.find_texture(n),
            self.scale,
        )
    }

    fn find_material(&self, name: &str) -> Option<MaterialId> {
        let index = self.materials.iter().position(|m| m.name() == name)?;
        MaterialId::try_from(index).ok()
    }

    pub(crate) fn find_texture(&self, name: &str) -> Option<u16> {
        let index = self.textures.iter().position(|t| t.name() == name)?;
        u16::try_from(index).ok()
    }

    /// A scene from definitions in Rust source, for firmware that embeds its scene without
    /// the parser, scaled into `S`'s range as the parser would. Errors carry no position.
    /// [`load_defs`](Self::load_defs) does the same in place.
    ///
    /// ```
    /// use microray::{CameraDef, LightDef, MaterialDef, ObjectDef, Scene};
    ///
    /// const CAMERA: CameraDef = CameraDef::new("cam", [160, 120], [8.0, 6.0], [4.0, 3.0, 4.0]);
    /// const MATERIALS: [MaterialDef; 1] = [MaterialDef::new("red").diffuse([4.0, 0.0, 0.0])];
    /// const LIGHTS: [LightDef; 1] = [LightDef::point("sun", [4.0, 8.0, 2.0], [5.0, 5.0, 5.0])];
    /// const OBJECTS: [ObjectDef; 1] = [ObjectDef::sphere("ball", "red", [4.0, 3.0, -6.0], 2.0)];
    ///
    /// let scene: Scene<f32, 4, 2, 1, 0, 160> =
    ///     Scene::from_defs(&CAMERA, &MATERIALS, &[], &LIGHTS, &OBJECTS)?;
    /// assert_eq!(scene.objects()[0].name(), "ball");
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn from_defs(
        camera: &CameraDef<'_>,
        materials: &[MaterialDef<'_>],
        textures: &[TextureDef<'_, 't>],
        lights: &[LightDef<'_>],
        objects: &[ObjectDef<'_>],
    ) -> Result<Self, Error> {
        let mut scene = Self::empty();
        scene.load_defs(camera, materials, textures, lights, objects)?;
        Ok(scene)
    }

    /// [`from_defs`](Self::from_defs) into this scene, emptied first: no second copy of the
    /// scene anywhere.
    pub fn load_defs(
        &mut self,
        camera: &CameraDef<'_>,
        materials: &[MaterialDef<'_>],
        textures: &[TextureDef<'_, 't>],
        lights: &[LightDef<'_>],
        objects: &[ObjectDef<'_>],
    ) -> Result<(), Error> {
        let mut extent = Extent::EMPTY;
        extent.camera(camera);
        materials.iter().for_each(|m| extent.material(m));
        lights.iter().for_each(|l| extent.light(l));
        objects.iter().for_each(|o| extent.object(o));
        let scale = extent.scale_for::<S>();
        self.clear(scale);
        let explain = |kind: ErrorKind| extent.explain::<S>(kind, scale);
        self.set_camera(camera).map_err(explain)?;
        for def in materials {
            self.add_material(def).map_err(explain)?;
        }
        for def in textures {
            self.add_texture(def).map_err(explain)?;
        }
        // After the textures: a projector names one.
        for def in lights {
            self.add_light(def).map_err(explain)?;
        }
        for def in objects {
            self.add_object(def).map_err(explain)?;
        }
        Ok(())
    }

    /// Writes the scene as a compiled scene ([`crate::compiled`]): its values as loaded,
    /// bit for bit, for [`load_compiled`](Self::load_compiled) on a machine that has neither
    /// the parser nor fast `f64`. The bytes go to `sink` in pieces.
    ///
    /// ```
    /// use microray::{parse::{no_textures, parse_scene_into}, Scene};
    ///
    /// let text = b"camera c { pixeldim 64 48 worlddim 8 6 viewpoint 4 3 4 }
    ///              material red { diffuse 4 0 0 }
    ///              sphere ball { material red center 4 3 -6 radius 2 }";
    /// let mut scene: Scene<f32, 4, 2, 1, 0, 64> = Scene::empty();
    /// parse_scene_into(text, no_textures, &mut scene)?;
    /// let mut bytes = Vec::new();
    /// scene.write_compiled(&mut |piece| bytes.extend_from_slice(piece));
    ///
    /// // On the microcontroller: no parser, no f64, the same scene.
    /// let mut loaded: Scene<f32, 4, 2, 1, 0, 64> = Scene::empty();
    /// loaded.load_compiled(&bytes, no_textures)?;
    /// assert_eq!(loaded, scene);
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn write_compiled(&self, sink: &mut dyn FnMut(&[u8])) {
        let mut out = compiled::Writer::new(sink);
        compiled::write_header::<S>(&mut out, self.scale);
        let limits = self.limits();
        out.number(limits.z);
        out.number(limits.distance);
        compiled::write_camera(&mut out, &self.camera);
        out.count(self.materials.len());
        for material in &self.materials {
            compiled::write_material(&mut out, material);
        }
        out.count(self.textures.len());
        for texture in &self.textures {
            out.text(texture.name());
            out.text(texture.filename());
        }
        out.count(self.lights.len());
        for light in &self.lights {
            compiled::write_light(&mut out, light);
        }
        out.count(self.objects.len());
        for object in &self.objects {
            compiled::write_object(&mut out, object);
        }
    }

    /// Loads a compiled scene into this scene, emptied first. `textures` finds each
    /// texture's PPM bytes by file name, as for the parser. The bytes are checked as they
    /// are read (see [`crate::compiled`]); no `f64` arithmetic is done.
    pub fn load_compiled(
        &mut self,
        bytes: &[u8],
        textures: impl FnMut(&str) -> Result<&'t [u8], TextureError>,
    ) -> Result<(), Error> {
        // One conversion to `Error` instead of one at each `?`: less flash.
        Ok(self.read_compiled(bytes, textures)?)
    }

    fn read_compiled(
        &mut self,
        bytes: &[u8],
        textures: impl FnMut(&str) -> Result<&'t [u8], TextureError>,
    ) -> Result<(), ErrorKind> {
        let mut input = compiled::Reader::new(bytes);
        let result = self.read_parts(&mut input, textures);
        input.checked(result)
    }

    fn read_parts(
        &mut self,
        input: &mut compiled::Reader<'_>,
        mut textures: impl FnMut(&str) -> Result<&'t [u8], TextureError>,
    ) -> Result<(), ErrorKind> {
        let scale = input.header::<S>()?;
        let limits = Limits {
            z: input.number(),
            distance: input.number(),
        };
        self.clear_lists();
        self.scale = scale;
        self.limits = Some(limits);
        self.camera = compiled::read_camera(input, MAX_WIDTH)?;
        for _ in 0..input.u16()? {
            let material = compiled::read_material(input)?;
            push(&mut self.materials, material, Collection::Materials)?;
        }
        let textures_in_scene = input.u16()?;
        if textures_in_scene > 0 {
            // Before reading them: without the feature, the loop is left out.
            Feature::Texture.require(None)?;
        }
        for _ in 0..textures_in_scene {
            let (name, filename) = (input.text()?, input.text()?);
            self.add_texture_file(name, filename, &mut textures)?;
        }
        for _ in 0..input.u16()? {
            let light = compiled::read_light(input, self.textures.len())?;
            push(&mut self.lights, light, Collection::Lights)?;
        }
        for _ in 0..input.u16()? {
            let object = compiled::read_object(input, self.materials.len(), self.textures.len())?;
            push(&mut self.objects, object, Collection::Objects)?;
        }
        input.finish()?;
        Ok(())
    }

    /// Renders the same picture at another resolution: the camera's `pixeldim` becomes
    /// `width` by `height`, its world window stays. Errors as for `pixeldim` in a file.
    pub fn set_resolution(&mut self, width: u16, height: u16) -> Result<(), ErrorKind> {
        self.camera = self.camera.with_pixels(width, height, MAX_WIDTH)?;
        Ok(())
    }

    /// The camera.
    pub fn camera(&self) -> &Camera<S> {
        &self.camera
    }
    /// The materials, in definition order.
    pub fn materials(&self) -> &[Material<S>] {
        &self.materials
    }
    /// The lights, in definition order.
    pub fn lights(&self) -> &[Light<S>] {
        &self.lights
    }
    /// The textures, in definition order.
    pub fn textures(&self) -> &[Texture<'t>] {
        &self.textures
    }
    /// The objects, in definition order.
    pub fn objects(&self) -> &[Object<S>] {
        &self.objects
    }

    /// What the objects' surface look-ups and printers need.
    pub fn palette(&self) -> Palette<'_, S> {
        Palette {
            materials: &self.materials,
            textures: &self.textures,
            camera: &self.camera,
            scale: self.scale,
            limits: self.limits(),
        }
    }

    /// The factor the scene's lengths were multiplied by at load: a power of two, 1 unless
    /// the scene was larger than the number type's [`Scalar::MAX_EXTENT`].
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// Hit points with `z` above this are in front of the image plane (0.01, scaled).
    pub fn z_limit(&self) -> S {
        self.limits().z
    }

    /// The lengths shading compares with, at the scene's scale.
    pub fn limits(&self) -> Limits<S> {
        self.limits.unwrap_or_else(Limits::unscaled)
    }

    /// Calls `each` with every [warning](crate::warning) about the scene: configurations
    /// whose picture rounding decides (coincident surfaces, a light on a surface or at the
    /// eye, a surface through the eye, the eye inside an object). The scene renders all the
    /// same; `microray check` prints them.
    #[cfg(feature = "warnings")]
    pub fn warnings<'s>(&'s self, each: impl FnMut(crate::warning::Warning<'s>)) {
        let eye = self.camera.viewpoint();
        crate::warning::warnings(eye, &self.lights, &self.objects, each);
    }

    /// The nearest hit with `t > 0` over all objects, skipping object `skip` (the one the
    /// ray leaves from); ties go to the object defined first.
    pub fn closest_hit(&self, ray: &Ray<S>, skip: Option<usize>) -> Option<(usize, Hit<S>)> {
        closest_hit(&self.objects, ray, skip, self.z_limit())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vec3::Vec3;

    const CAMERA: CameraDef<'static> = CameraDef::new("c", [64, 48], [8.0, 6.0], [4.0, 3.0, 3.0]);

    #[test]
    fn unscaled_limits_are_the_limits_at_scale_one() {
        fn same<S: Scalar>() {
            assert_eq!(
                Limits::<S>::unscaled(),
                Limits::<S>::at_scale(1.0),
                "{}",
                S::NAME
            );
        }
        same::<f64>();
        same::<f32>();
        same::<crate::scalar::I16F16>();
    }

    #[test]
    fn capacities_are_errors() {
        let mut b: Scene<'_, f32, 1, 1, 1, 0, 64> = Scene::new(&CAMERA, 1.0).unwrap();
        b.add_material(&MaterialDef::new("m")).unwrap();
        assert_eq!(
            b.add_material(&MaterialDef::new("n")),
            Err(ErrorKind::CapacityExceeded {
                what: Collection::Materials,
                capacity: 1
            })
        );
        b.add_light(&LightDef::point("l", [0.0; 3], [1.0; 3]))
            .unwrap();
        assert_eq!(
            b.add_light(&LightDef::point("l", [0.0; 3], [1.0; 3])),
            Err(ErrorKind::CapacityExceeded {
                what: Collection::Lights,
                capacity: 1
            })
        );
        b.add_object(&ObjectDef::sphere("s", "m", [0.0, 0.0, -5.0], 1.0))
            .unwrap();
        assert_eq!(
            b.add_object(&ObjectDef::sphere("s", "m", [0.0, 0.0, -5.0], 1.0)),
            Err(ErrorKind::CapacityExceeded {
                what: Collection::Objects,
                capacity: 1
            })
        );
    }

    #[test]
    fn image_wider_than_the_row_buffer() {
        assert_eq!(
            Scene::<'_, f32, 1, 1, 1, 0, 63>::new(&CAMERA, 1.0).map(|_| ()),
            Err(ErrorKind::ImageTooWide { width: 64, max: 63 })
        );
    }

    #[test]
    fn closest_hit_skips_and_prefers_the_first_on_ties() {
        let scene: Scene<'_, f64> = Scene::from_defs(
            &CAMERA,
            &[MaterialDef::new("m")],
            &[],
            &[],
            &[
                ObjectDef::plane("back", "m", [0.0, 0.0, 1.0], [0.0, 0.0, -8.0]),
                ObjectDef::plane("twin", "m", [0.0, 0.0, 1.0], [0.0, 0.0, -8.0]),
                ObjectDef::sphere("ball", "m", [0.0, 0.0, -5.0], 1.0),
            ],
        )
        .unwrap();
        let ray = Ray::new(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0));
        assert_eq!(scene.closest_hit(&ray, None).unwrap().0, 2);
        assert_eq!(scene.closest_hit(&ray, Some(2)).unwrap().0, 0);
        assert_eq!(scene.closest_hit(&ray, Some(0)).unwrap().0, 2);
        let away = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(scene.closest_hit(&away, None), None);
    }

    #[test]
    fn z_rule_applies_to_every_kind() {
        let scene: Scene<'_, f64> = Scene::from_defs(
            &CAMERA,
            &[MaterialDef::new("m")],
            &[],
            &[],
            &[
                // A wall facing the camera in front of the image plane, and one at z = 0.01.
                ObjectDef::plane("front", "m", [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]),
                ObjectDef::plane("edge", "m", [0.0, 0.0, 1.0], [9.0, 0.0, 0.01]),
                // A sphere poking through the image plane: its near side is at z = 1.
                ObjectDef::sphere("ball", "m", [20.0, 0.0, -1.0], 2.0),
            ],
        )
        .unwrap();
        let down = |x: f64| Ray::new(Vec3::new(x, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        // Through the front wall (z = 1, not a hit) to the edge wall (z = 0.01 exactly counts).
        assert_eq!(
            scene.closest_hit(&down(0.0), None).map(|(i, h)| (i, h.t)),
            Some((1, 4.99))
        );
        // The sphere's near root is in front of the image plane; its far root is not tried.
        assert_eq!(
            scene.closest_hit(&down(20.0), None).map(|(i, _)| i),
            Some(1)
        );
        assert!(scene.objects()[2].hit(&down(20.0)).is_some());
    }

    #[test]
    fn undefined_and_duplicate_names() {
        let mut b: Scene<'_, f64> = Scene::new(&CAMERA, 1.0).unwrap();
        b.add_material(&MaterialDef::new("m")).unwrap();
        assert!(matches!(
            b.add_material(&MaterialDef::new("m")),
            Err(ErrorKind::DuplicateName { .. })
        ));
        let err = b
            .add_object(&ObjectDef::sphere("s", "nope", [0.0; 3], 1.0))
            .unwrap_err();
        assert_eq!(
            err.to_string(),
            "undefined material `nope` (materials must be defined before the objects that use them)"
        );
    }
}
