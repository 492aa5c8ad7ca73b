//! Objects, as in the C design: each carries a pointer to a table of functions (`hits`,
//! `printer`, and the surface look-ups), installed by its kind's constructor the way the
//! course's `plane_init` does `obj->hits = plane_hits`.
//!
//! The table is a `'static` [`ObjectVTable`] of plain `fn` pointers, so dispatch is one
//! indirect call, as in C, and needs no `unsafe`. A kind's data lives in [`Shape`]; the
//! constructor that installs a table also stores the matching data, so they cannot disagree.
//! The defaults are real functions like the C `object_print` and the no-hit function, and a
//! kind's printer calls the common [`object_print`] first.

#[cfg(all(feature = "plan", feature = "batch"))]
pub(crate) mod behind;
pub mod fplane;
pub mod plane;
pub mod revsurf;
pub mod sphere;
pub mod texplane;
pub mod tiled_plane;

use crate::camera::Camera;
pub use crate::camera::{RowColumns, RowOrigin};
use crate::error::{Attr, Entity, ErrorKind, Feature, Snippet};
use crate::material::{Material, MaterialId};
use crate::name::{Name, bounded};
use crate::ray::Ray;
use crate::scalar::Scalar;
use crate::texture::Texture;
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use crate::write;
#[cfg(feature = "print")]
use core::fmt;

pub use fplane::{Rect, RectDef};
pub use plane::{Plane, PlaneDef};
pub use revsurf::{RevSurf, RevSurfDef, Surfer};
pub use sphere::{Sphere, SphereDef};
pub use texplane::{TexPlane, TextureMode};
pub use tiled_plane::TiledPlane;

/// Where a ray meets a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit<S> {
    /// The ray parameter, always above zero.
    pub t: S,
    /// The hit point.
    pub point: Vec3<S>,
    /// The unit surface normal there.
    pub normal: Vec3<S>,
}

/// What the surface look-ups and printers need from the scene besides the object itself.
#[derive(Clone, Copy, Debug)]
pub struct Palette<'s, S> {
    /// The scene's materials, indexed by [`MaterialId`].
    pub materials: &'s [Material<S>],
    /// The scene's textures.
    pub textures: &'s [Texture<'s>],
    /// The camera (textures in [`TextureMode::Tile`] are laid out in its pixel units).
    pub camera: &'s Camera<S>,
    /// The factor the scene's lengths were multiplied by at load (a power of two; 1 unless
    /// the scene was too large for the number type).
    pub scale: f64,
    /// The scene's limits at that scale.
    pub limits: crate::ray::Limits<S>,
}

impl<'s, S: Scalar> Palette<'s, S> {
    /// A material by index.
    pub fn material(&self, id: MaterialId) -> Option<&'s Material<S>> {
        self.materials.get(usize::from(id))
    }
}

/// What shading needs of a surface at a hit: the hit record, the material in effect there,
/// and the ambient and diffuse reflectivity (the material's, times a texel on textured
/// planes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface<'s, S> {
    /// Where the ray meets the surface.
    pub hit: Hit<S>,
    /// The material in effect at the hit (mirror, glint and transparency come from it).
    pub material: &'s Material<S>,
    /// Ambient reflectivity.
    pub ambient: Vec3<S>,
    /// Diffuse reflectivity.
    pub diffuse: Vec3<S>,
}

/// The unit direction's `x` of a row's ray whose `x` is `a` (`m` its
/// [`dy_dz_squared`](RowOrigin::dy_dz_squared)); it grows with `a`.
#[cfg(all(feature = "plan", feature = "batch"))]
pub(crate) fn unit_x(a: f64, m: f64) -> f64 {
    a / crate::scalar::sqrt_f64(a * a + m)
}

/// What a kind works out once for the primary rays of a row, so that each pixel costs less
/// (see [`ObjectVTable::row_test`]). Exact: each pixel's answer is the one `hits` gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RowTest<S> {
    /// No ray of the row counts a hit (behind every ray, or in front of the image plane).
    Miss,
    /// Every ray of the row meets the object at this `t`, within the z rule (a plane
    /// parallel to the x axis: `N . dir` is the same along the row).
    At(S),
    /// Each ray is tested against the object's plane with `N.point - N.eye`, the part of
    /// the test that depends only on where the rays start, worked out once: this value
    /// (see [`Plane::distance_from`](plane::Plane::distance_from)). The plane kinds
    /// whose `hits` is their plane's (and a finite plane's bounds check after it).
    #[cfg(feature = "plan")]
    Plane(S),
    /// Only the rays whose (unit) direction's `x` lies in `lo..=hi` can meet the object
    /// (a sphere: the rays of a row that pass its widened outline); they are tested with the
    /// kind's `hits`, the others miss. `f64` on the host only (see `sphere_row_test`).
    #[cfg(all(feature = "plan", feature = "batch"))]
    Across {
        /// The least `dir.x` of a ray that can meet the object.
        lo: S,
        /// The greatest.
        hi: S,
    },
    /// [`Plane`](Self::Plane) for only the rays whose (unit) direction's `x` lies in
    /// `lo..=hi`; the others meet the plane behind another (see `behind`).
    #[cfg(all(feature = "plan", feature = "batch"))]
    PlaneAcross {
        /// As [`Plane`](Self::Plane)'s.
        distance: S,
        /// The least `dir.x` of a ray that can see the plane, rounded down (an `f32`: the
        /// test no larger than [`Across`](Self::Across)).
        lo: f32,
        /// The greatest, rounded up.
        hi: f32,
    },
    /// Every ray of the row whose direction's `x` lies in `lo..=hi` meets the object at
    /// `t` (within the z rule), and no other ray of the row meets it: a rectangle whose
    /// plane's normal has no x part (see [`Rect::row_test`](fplane::Rect::row_test)).
    /// Not in `f64`, whose rays are normalised.
    #[cfg(feature = "plan")]
    AtAcross {
        /// Where the rays meet the object.
        t: S,
        /// The least `dir.x` of a ray that meets it.
        lo: S,
        /// The greatest.
        hi: S,
        /// The first column of the run (as the row counts them: 0 the left).
        first: u16,
        /// The last.
        last: u16,
    },
    /// Each ray is tested with the kind's `hits`.
    Hits,
}

/// The surface look-up of a kind (see [`ObjectVTable::surface`]): it writes the surface
/// (or `None`) into its last argument.
pub type SurfaceLookup<S> =
    for<'s> fn(&Object<S>, &Palette<'s, S>, &Ray<S>, S, &mut Option<Surface<'s, S>>);

/// The function table of an object kind: the C `object_t`'s function pointers.
///
/// The hot path makes one `hits` call per object a ray is tested against, and one `surface`
/// call for the object it meets first.
#[derive(Debug)]
pub struct ObjectVTable<S: Scalar> {
    /// The kind, for the printer's keyword.
    pub kind: Entity,
    /// The C `hits`: the ray parameter `t` of the nearest hit with `0 < t < limit`, or
    /// `None` (the scene's closest-hit search applies the z rule, which depends on the
    /// scene's scale). The limit lets a kind skip work for hits that could not count: the
    /// nearest hit so far, or the distance to a light.
    pub hits: fn(&Object<S>, &Ray<S>, S) -> Option<S>,
    /// The unit surface normal at a point that `hits` found.
    pub normal: fn(&Object<S>, Vec3<S>) -> Vec3<S>,
    /// Prepares the test of one image row's primary rays (a cheaper primary-ray test, as
    /// a C programmer adds one: planes work out once what is the same along the row).
    pub row_test: fn(&Object<S>, &RowOrigin<S>) -> RowTest<S>,
    /// Writes the object's block in scene text.
    #[cfg(feature = "print")]
    pub printer: fn(&Object<S>, &Palette<'_, S>, &mut dyn fmt::Write) -> fmt::Result,
    /// The material in effect at a point (the tiled plane's checkerboard overrides it).
    pub material: fn(&Object<S>, Vec3<S>) -> MaterialId,
    /// The surface where a ray meets the object at the `t` that `hits` found: the hit
    /// record (point and normal) and the C `ambient`, `diffuse` and `specular` look-ups, in
    /// one call (the textured plane multiplies ambient and diffuse by its texel). Written
    /// through a pointer, as a C function fills a struct: a record returned by value is
    /// copied to where it stays, in pieces that the processor cannot forward from the
    /// look-up's own stores (a fifth of a row batch's shading time, measured).
    pub surface: SurfaceLookup<S>,
}

/// Each kind's own data.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape<S> {
    /// An infinite plane.
    Plane(Plane<S>),
    /// A sphere.
    Sphere(Sphere<S>),
    /// A finite rectangle.
    FPlane(Rect<S>),
    /// An infinite checkerboard plane.
    TiledPlane(TiledPlane<S>),
    /// A textured rectangle.
    TexPlane(TexPlane<S>),
    /// A surface of revolution.
    RevSurf(RevSurf<S>),
}

/// An object of the scene: name, material, shape data and its kind's function table.
#[derive(Clone, Debug)]
pub struct Object<S: Scalar> {
    vtable: &'static ObjectVTable<S>,
    name: Name,
    material: MaterialId,
    shape: Shape<S>,
}

impl<S: Scalar> PartialEq for Object<S> {
    fn eq(&self, other: &Self) -> bool {
        // One table per kind: comparing kinds compares tables (addresses of promoted
        // constants are not unique, so they are not compared).
        self.vtable.kind == other.vtable.kind
            && self.name == other.name
            && self.material == other.material
            && self.shape == other.shape
    }
}

impl<S: Scalar> Object<S> {
    /// What every kind's constructor does first, as the C `object_init`: name and material.
    pub(crate) fn init(
        vtable: &'static ObjectVTable<S>,
        name: &str,
        material: MaterialId,
        shape: Shape<S>,
    ) -> Result<Self, ErrorKind> {
        Ok(Self {
            vtable,
            name: bounded(name)?,
            material,
            shape,
        })
    }

    /// The ray parameter of the nearest hit along `ray` with `0 < t < limit`.
    #[inline]
    pub fn hits(&self, ray: &Ray<S>, limit: S) -> Option<S> {
        (self.vtable.hits)(self, ray, limit)
    }

    /// The hit record at ray parameter `t` (from [`hits`](Self::hits)): the point and the
    /// normal there.
    #[inline]
    pub fn hit_at(&self, ray: &Ray<S>, t: S) -> Hit<S> {
        let point = ray.at(t);
        Hit {
            t,
            point,
            normal: (self.vtable.normal)(self, point),
        }
    }

    /// The nearest hit along `ray` with `t > 0`, as a hit record.
    pub fn hit(&self, ray: &Ray<S>) -> Option<Hit<S>> {
        self.hits(ray, S::UNBOUNDED).map(|t| self.hit_at(ray, t))
    }
    /// Writes the object's block.
    #[cfg(feature = "print")]
    pub fn print(&self, palette: &Palette<'_, S>, out: &mut dyn fmt::Write) -> fmt::Result {
        (self.vtable.printer)(self, palette, out)
    }
    /// The material in effect at a point of the surface.
    #[inline]
    pub fn material_at(&self, point: Vec3<S>) -> MaterialId {
        (self.vtable.material)(self, point)
    }
    /// The surface where `ray` meets the object at `t`: hit record, material, ambient and
    /// diffuse reflectivity.
    #[inline]
    pub fn surface<'s>(
        &self,
        palette: &Palette<'s, S>,
        ray: &Ray<S>,
        t: S,
    ) -> Option<Surface<'s, S>> {
        let mut found = None;
        self.surface_into(palette, ray, t, &mut found);
        found
    }
    /// [`surface`](Self::surface) written into `out`, where it is to stay.
    #[inline]
    pub fn surface_into<'s>(
        &self,
        palette: &Palette<'s, S>,
        ray: &Ray<S>,
        t: S,
        out: &mut Option<Surface<'s, S>>,
    ) {
        (self.vtable.surface)(self, palette, ray, t, out)
    }

    /// The object's kind.
    pub fn kind(&self) -> Entity {
        self.vtable.kind
    }
    /// The object's name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// The object's own material (before any per-hit override).
    pub fn material(&self) -> MaterialId {
        self.material
    }
    /// The kind's test for one image row's primary rays.
    #[inline]
    pub fn row_test(&self, origin: &RowOrigin<S>) -> RowTest<S> {
        (self.vtable.row_test)(self, origin)
    }
    /// The kind's data.
    pub fn shape(&self) -> &Shape<S> {
        &self.shape
    }
    /// The function table.
    pub fn vtable(&self) -> &'static ObjectVTable<S> {
        self.vtable
    }
    /// Whether `hits` reads nothing of a ray's `x` (base or direction), so rays that differ
    /// only in `x` get the same answer bit for bit: the infinite plane kinds whose normal
    /// has no x part (`0 * x` adds nothing to their dot products, and the hit's `z`, which
    /// the z rule reads, is the same). Asked once a row, not per ray.
    pub fn hits_ignore_x(&self) -> bool {
        self.infinite_plane()
            .is_some_and(|plane| plane.unit_normal.x == S::ZERO)
    }
    /// The plane of an infinite plane kind (plain or tiled), whose test is its plane's.
    pub fn infinite_plane(&self) -> Option<&Plane<S>> {
        match &self.shape {
            Shape::Plane(plane) => Some(plane),
            Shape::TiledPlane(tiled) => Some(&tiled.rect.plane),
            _ => None,
        }
    }
    /// `hits` for a ray whose base is `distance` from the object's plane (a prepared
    /// [`RowTest::Plane`]): the same answer as `hits`, bit for bit, without the part of
    /// the plane test that depends on the base.
    #[cfg(feature = "plan")]
    #[inline]
    pub fn hits_from_distance(&self, ray: &Ray<S>, distance: S, limit: S) -> Option<S> {
        match &self.shape {
            Shape::Plane(plane) => plane.nearest_from(distance, ray.dir, limit),
            Shape::TiledPlane(tiled) => tiled.rect.plane.nearest_from(distance, ray.dir, limit),
            Shape::FPlane(rect) => rect.nearest_from(distance, ray, limit),
            Shape::TexPlane(textured) => textured.rect.nearest_from(distance, ray, limit),
            _ => self.hits(ray, limit),
        }
    }
    /// Whether the surface look-up gives the same material, reflectivities and normal at
    /// every point (a plain plane or a plain finite one, whose look-up is the plane's), so
    /// only the hit point changes from hit to hit.
    pub fn surface_is_uniform(&self) -> bool {
        matches!(self.shape, Shape::Plane(_) | Shape::FPlane(_))
    }
}

/// The default `row_test`: every ray tested with `hits`.
pub fn object_row_test<S: Scalar>(_: &Object<S>, _: &RowOrigin<S>) -> RowTest<S> {
    RowTest::Hits
}

/// The default `hits`: no hit, as the C `object_no_hit`.
pub fn object_no_hit<S: Scalar>(_: &Object<S>, _: &Ray<S>, _: S) -> Option<S> {
    None
}

/// The common printer (the C `object_print`): the block's header and its material.
#[cfg(feature = "print")]
pub fn object_print<S: Scalar>(
    obj: &Object<S>,
    palette: &Palette<'_, S>,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    write::header(out, obj.kind().keyword(), obj.name())?;
    material_ref(out, Attr::Material, palette, obj.material)
}

/// `  ATTR MATERIAL-NAME`.
#[cfg(feature = "print")]
pub fn material_ref<S: Scalar>(
    out: &mut dyn fmt::Write,
    attr: Attr,
    palette: &Palette<'_, S>,
    id: MaterialId,
) -> fmt::Result {
    write::word(out, attr, palette.material(id).map_or("", |m| m.name()))
}

/// The default material look-up: the object's own.
pub fn object_material<S: Scalar>(obj: &Object<S>, _: Vec3<S>) -> MaterialId {
    obj.material
}

/// The surface look-up of the kinds that show their own material (the C
/// `material_getamb`, `_getdiff`, `_getspec`): the hit record with the kind's normal
/// function, and the material's colours, written into `out`.
#[inline]
pub fn object_surface<'s, S: Scalar>(
    obj: &Object<S>,
    palette: &Palette<'s, S>,
    ray: &Ray<S>,
    t: S,
    normal: fn(&Object<S>, Vec3<S>) -> Vec3<S>,
    out: &mut Option<Surface<'s, S>>,
) {
    let point = ray.at(t);
    let hit = Hit {
        t,
        point,
        normal: normal(obj, point),
    };
    write_surface(out, hit, palette.material(obj.material));
}

/// Writes into `out` the surface showing `material` at `hit`, or `None` without a material:
/// the two on their own paths (a `None` sharing the stores would take the record through a
/// temporary).
#[inline]
pub fn write_surface<'s, S: Scalar>(
    out: &mut Option<Surface<'s, S>>,
    hit: Hit<S>,
    material: Option<&'s Material<S>>,
) {
    let Some(material) = material else {
        *out = None;
        return;
    };
    *out = surface_of(hit, material);
}

/// A surface showing `material` at `hit`.
#[inline]
pub fn surface_of<'s, S: Scalar>(hit: Hit<S>, material: &'s Material<S>) -> Option<Surface<'s, S>> {
    Some(Surface {
        hit,
        material,
        ambient: material.ambient,
        diffuse: material.diffuse,
    })
}

/// `t` if it is ahead of the ray (`t > 0`) and below `limit`. Every limit is at most
/// [`Scalar::UNBOUNDED`], so a `t` that overflowed to infinity, is NaN or saturated (no
/// place on the ray) is not below it.
#[inline]
pub(crate) fn ahead<S: Scalar>(t: S, limit: S) -> Option<S> {
    (t > S::ZERO && t < limit).then_some(t)
}

/// A ray's direction made a unit one with one wide reciprocal, and the reciprocal (which
/// turns a unit ray's `t` back into the ray's): for fixed point, which has no range for
/// the products of a long direction.
#[inline]
pub(crate) fn unit_direction<S: Scalar>(ray: &Ray<S>) -> Option<(Vec3<S>, S::Wide)> {
    let inv = S::wide_recip(ray.length().to_wide()?);
    let unit = Vec3::new(
        ray.dir.x.scale(inv),
        ray.dir.y.scale(inv),
        ray.dir.z.scale(inv),
    );
    Some((unit, inv))
}

/// An object of a row's list and its kind's test for the row's primary rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowEntry<S> {
    /// The object's index in the scene.
    pub index: u16,
    /// Its test.
    pub test: RowTest<S>,
}

pub use crate::ray::Z_LIMIT;

/// An object as written: name, material and kind-specific data, all plain `f64`.
///
/// Every constructor is a `const fn`, so firmware can keep its scene in flash:
/// ```
/// use microray::ObjectDef;
/// const BALL: ObjectDef<'static> = ObjectDef::sphere("ball", "red", [4.0, 3.0, -6.0], 2.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectDef<'a> {
    /// The object's name.
    pub name: &'a str,
    /// The name of its material.
    pub material: &'a str,
    /// The kind and its data.
    pub shape: ShapeDef<'a>,
}

/// An object kind's data as written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShapeDef<'a> {
    /// `plane`.
    Plane(PlaneDef),
    /// `sphere`.
    Sphere(SphereDef),
    /// `fplane`.
    FPlane(RectDef),
    /// `tiled_plane`, with the name of its second material.
    TiledPlane(RectDef, &'a str),
    /// `texplane`, with the name of its texture and the mode.
    TexPlane(RectDef, &'a str, TextureMode),
    /// `revsurf`.
    RevSurf(RevSurfDef),
}

impl<'a> ObjectDef<'a> {
    /// An infinite plane.
    pub const fn plane(
        name: &'a str,
        material: &'a str,
        normal: [f64; 3],
        point: [f64; 3],
    ) -> Self {
        Self {
            name,
            material,
            shape: ShapeDef::Plane(PlaneDef { normal, point }),
        }
    }
    /// A sphere.
    pub const fn sphere(name: &'a str, material: &'a str, center: [f64; 3], radius: f64) -> Self {
        Self {
            name,
            material,
            shape: ShapeDef::Sphere(SphereDef { center, radius }),
        }
    }
    /// A finite rectangle.
    pub const fn fplane(name: &'a str, material: &'a str, rect: RectDef) -> Self {
        Self {
            name,
            material,
            shape: ShapeDef::FPlane(rect),
        }
    }
    /// An infinite checkerboard plane; tiles where `ix + iy` is even use `altmaterial`.
    pub const fn tiled_plane(
        name: &'a str,
        material: &'a str,
        rect: RectDef,
        altmaterial: &'a str,
    ) -> Self {
        Self {
            name,
            material,
            shape: ShapeDef::TiledPlane(rect, altmaterial),
        }
    }
    /// A textured rectangle.
    pub const fn texplane(
        name: &'a str,
        material: &'a str,
        rect: RectDef,
        texname: &'a str,
        mode: TextureMode,
    ) -> Self {
        Self {
            name,
            material,
            shape: ShapeDef::TexPlane(rect, texname, mode),
        }
    }

    /// A surface of revolution: profile `surfer` about the axis from `base` along
    /// `direction`, `height` long.
    ///
    /// ```
    /// use microray::{ObjectDef, object::Surfer};
    ///
    /// // revsurfe's gold vase.
    /// let vase = ObjectDef::revsurf("vase", "gold", Surfer::Vase, [2.0, 0.0, -4.0], [0.0, 1.0, 0.0], 6.28);
    /// assert_eq!(vase.entity(), microray::error::Entity::RevSurf);
    /// ```
    pub const fn revsurf(
        name: &'a str,
        material: &'a str,
        surfer: Surfer,
        base: [f64; 3],
        direction: [f64; 3],
        height: f64,
    ) -> Self {
        Self {
            name,
            material,
            shape: ShapeDef::RevSurf(RevSurfDef {
                surfer,
                base,
                direction,
                height,
            }),
        }
    }

    /// The kind of object this defines.
    pub const fn entity(&self) -> Entity {
        match self.shape {
            ShapeDef::Plane(_) => Entity::Plane,
            ShapeDef::Sphere(_) => Entity::Sphere,
            ShapeDef::FPlane(_) => Entity::FPlane,
            ShapeDef::TiledPlane(..) => Entity::TiledPlane,
            ShapeDef::TexPlane(..) => Entity::TexPlane,
            ShapeDef::RevSurf(_) => Entity::RevSurf,
        }
    }
}

impl<S: Scalar> Object<S> {
    /// Checks a definition and builds the object with its kind's table. Names of materials
    /// and textures are resolved with the given look-ups.
    pub(crate) fn build(
        def: &ObjectDef<'_>,
        find_material: impl Fn(&str) -> Option<MaterialId>,
        find_texture: impl Fn(&str) -> Option<u16>,
        scale: f64,
    ) -> Result<Self, ErrorKind> {
        let material_named = |attr: Attr, name: &str| {
            find_material(name).ok_or(ErrorKind::UndefinedMaterial {
                attr,
                name: Snippet::new(name.as_bytes()),
            })
        };
        let material = material_named(Attr::Material, def.material)?;
        match &def.shape {
            ShapeDef::Plane(p) => plane::plane_init(def.name, material, p, scale),
            ShapeDef::Sphere(s) => sphere::sphere_init(def.name, material, s, scale),
            ShapeDef::FPlane(r) => {
                Feature::FPlane.require(None)?;
                fplane::fplane_init(def.name, material, r, scale)
            }
            ShapeDef::TiledPlane(r, alt) => {
                Feature::TiledPlane.require(None)?;
                let alt = material_named(Attr::Altmaterial, alt)?;
                tiled_plane::tiled_plane_init(def.name, material, r, alt, scale)
            }
            ShapeDef::TexPlane(r, texname, mode) => {
                Feature::Texture.require(None)?;
                let texture = find_texture(texname).ok_or(ErrorKind::UndefinedTexture {
                    name: Snippet::new(texname.as_bytes()),
                })?;
                texplane::texplane_init(def.name, material, r, texture, *mode, scale)
            }
            ShapeDef::RevSurf(r) => {
                Feature::RevSurf.require(None)?;
                revsurf::revsurf_init(def.name, material, r, scale)
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod test_support {
    //! A tiny palette for the kinds' unit tests.
    use super::*;
    use crate::camera::CameraDef;
    use crate::material::MaterialDef;

    pub(crate) fn materials() -> [Material<f64>; 2] {
        [
            Material::build(
                &MaterialDef::new("red")
                    .ambient([1.0, 0.0, 0.0])
                    .diffuse([2.0, 0.0, 0.0]),
                1.0,
            )
            .unwrap(),
            Material::build(
                &MaterialDef::new("gray")
                    .ambient([0.5; 3])
                    .diffuse([3.0; 3])
                    .specular(0.25),
                1.0,
            )
            .unwrap(),
        ]
    }

    pub(crate) fn camera() -> Camera<f64> {
        Camera::build(
            &CameraDef::new("c", [80, 60], [8.0, 6.0], [4.0, 3.0, 3.0]),
            1024,
            1.0,
        )
        .unwrap()
    }

    pub(crate) fn ray(base: [f64; 3], dir: [f64; 3]) -> Ray<f64> {
        Ray::new(
            Vec3::from_array(base),
            Vec3::from_array(dir).unit_f64().unwrap(),
        )
    }

    /// A deterministic stream of numbers in [0, 1).
    pub(crate) fn stream(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        }
    }
}
