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

use crate::bvh::{Slabs, Tree};
use crate::camera::Camera;
use crate::error::{Attr, Entity, ErrorKind, Feature, Snippet};
use crate::material::{Material, MaterialId};
use crate::name::{Name, bounded};
#[cfg(feature = "print")]
use crate::print;
use crate::ray::Ray;
use crate::scalar::Scalar;
use crate::texture::Texture;
use crate::vec3::Vec3;
#[cfg(feature = "print")]
use core::fmt;
use core::ops::ControlFlow;

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
    pub limits: crate::scene::Limits<S>,
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

/// The primary rays of one image row as a kind sees them when it prepares its test: every
/// one starts at `eye`, and the direction of the ray through pixel position `x` is
/// `(x - eye.x, dy, dz)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowOrigin<S> {
    /// Where every primary ray starts.
    pub eye: Vec3<S>,
    /// The rays' `y` component.
    pub dy: S,
    /// The rays' `z` component.
    pub dz: S,
    /// The scene's z rule (see [`closest_hit`]).
    pub z_limit: S,
}

#[cfg(all(feature = "plan", feature = "batch"))]
impl<S: Scalar> RowOrigin<S> {
    /// `dy^2 + dz^2` in `f64`: a ray's length squared is `a^2` more, `a` its `x`.
    pub(crate) fn dy_dz_squared(&self) -> f64 {
        let (dy, dz) = (self.dy.to_f64(), self.dz.to_f64());
        dy * dy + dz * dz
    }
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
    /// every point (a plain plane), so only the hit point changes from hit to hit.
    pub fn surface_is_uniform(&self) -> bool {
        matches!(self.shape, Shape::Plane(_))
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
    print::header(out, obj.kind().keyword(), obj.name())?;
    print::material_ref(out, Attr::Material, palette, obj.material)
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

/// The nearest hit with `t > 0` among `objects`, skipping index `skip` (the object a ray
/// leaves from), with the z rule: a hit point with `z > z_limit` is in front of the image
/// plane, between screen and viewer, and does not count. Ties go to the object defined
/// first.
#[inline]
pub fn closest_hit<S: Scalar>(
    objects: &[Object<S>],
    ray: &Ray<S>,
    skip: Option<usize>,
    z_limit: S,
) -> Option<(usize, Hit<S>)> {
    let (index, t) = closest_hit_among(objects, &Among::All, ray, skip, S::UNBOUNDED, z_limit)?;
    Some((index, objects.get(index)?.hit_at(ray, t)))
}

/// Which objects a ray is tested against.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Among<'a, S> {
    /// Every object of the scene.
    All,
    /// Only these, by index, in increasing order (so that ties still go to the object
    /// defined first): a render plan's list.
    Only(&'a [u16]),
    /// A render plan's objects in a bounding-volume hierarchy (see [`crate::bvh`]).
    Tree(Tree<'a, S>),
}

/// The nearest hit so far, for a search that meets objects out of index order (a tree
/// walk): a later object must be nearer, an earlier one may tie.
#[derive(Clone, Copy, Debug)]
struct Nearest<S> {
    best: Option<(usize, S)>,
    limit: S,
}

impl<S: Scalar> Nearest<S> {
    /// The limit for object `index`: ties with the best so far count for earlier objects.
    #[inline]
    fn limit_for(&self, index: usize) -> S {
        match self.best {
            Some((best, t)) if index < best => t.next_up(),
            _ => self.limit,
        }
    }

    /// Takes a hit at `t` (below [`limit_for`](Self::limit_for)).
    #[inline]
    fn offer(&mut self, index: usize, t: S) {
        if self.best.is_none_or(|(best, at)| t < at || index < best) {
            self.best = Some((index, t));
            self.limit = t;
        }
    }

    /// Takes a row test's `t` (the z rule already applied) if it is nearer: the objects of
    /// a row's list come in index order, so a tie stays with the earlier one.
    #[inline]
    fn take_row_at(&mut self, index: usize, t: S) {
        if t < self.limit {
            self.best = Some((index, t));
            self.limit = t;
        }
    }

    /// Takes a hit of `ray` at `t` (below the limit) if the hit point is behind the image
    /// plane (the point's `z` as `ray.at(t)` computes it).
    #[inline]
    fn take_in_front(&mut self, index: usize, t: S, ray: &Ray<S>, z_limit: S) {
        if ray.base.z + ray.dir.z * t <= z_limit {
            self.best = Some((index, t));
            self.limit = t;
        }
    }
}

impl<S: Scalar> Among<'_, S> {
    /// Calls `visit` with each object's index and the object, in increasing order, until
    /// it breaks. (Not for trees, whose searches walk them.)
    #[inline]
    pub(crate) fn each(
        &self,
        objects: &[Object<S>],
        mut visit: impl FnMut(usize, &Object<S>) -> ControlFlow<()>,
    ) {
        let list = match *self {
            Among::All => {
                for (index, object) in objects.iter().enumerate() {
                    if visit(index, object).is_break() {
                        return;
                    }
                }
                return;
            }
            Among::Only(list) => list,
            Among::Tree(tree) => tree.unbounded,
        };
        for &index in list {
            let index = usize::from(index);
            if let Some(object) = objects.get(index)
                && visit(index, object).is_break()
            {
                return;
            }
        }
    }
}

/// [`closest_hit_among`] over the objects of `list` (a row's list, in increasing index
/// order), but `skip`.
#[cfg(feature = "batch")]
#[inline(always)]
pub(crate) fn closest_in_list<S: Scalar>(
    objects: &[Object<S>],
    list: &[u16],
    ray: &Ray<S>,
    skip: Option<usize>,
    limit: S,
    z_limit: S,
) -> Option<(usize, S)> {
    let mut best = None;
    let mut limit = limit;
    for &index in list {
        let index = usize::from(index);
        if Some(index) == skip {
            continue;
        }
        let Some(object) = objects.get(index) else {
            continue;
        };
        if let Some(t) = object.hits(ray, limit) {
            // The hit point's z, as `ray.at(t)` computes it.
            if ray.base.z + ray.dir.z * t <= z_limit {
                best = Some((index, t));
                limit = t;
            }
        }
    }
    best
}

/// The index and ray parameter of the nearest hit with `0 < t < limit` among the objects
/// `among` (but `skip`), with the z rule of [`closest_hit`].
#[inline]
pub fn closest_hit_among<S: Scalar>(
    objects: &[Object<S>],
    among: &Among<'_, S>,
    ray: &Ray<S>,
    skip: Option<usize>,
    limit: S,
    z_limit: S,
) -> Option<(usize, S)> {
    // Trees come only from a render plan: without the feature the walk is left out.
    if let (true, Among::Tree(tree)) = (cfg!(feature = "plan"), among) {
        let mut nearest = Nearest { best: None, limit };
        search_tree(objects, tree, ray, skip, z_limit, &mut nearest);
        return nearest.best;
    }
    let mut best = None;
    let mut limit = limit;
    among.each(objects, |index, object| {
        if Some(index) != skip
            && let Some(t) = object.hits(ray, limit)
        {
            // The hit point's z, as `ray.at(t)` computes it.
            if ray.base.z + ray.dir.z * t <= z_limit {
                best = Some((index, t));
                limit = t;
            }
        }
        ControlFlow::Continue(())
    });
    best
}

/// The nearest hit among a tree's objects, its unbounded ones included, into `nearest`
/// (out of line: scenes without a tree keep their searches small).
#[inline(never)]
fn search_tree<S: Scalar>(
    objects: &[Object<S>],
    tree: &Tree<'_, S>,
    ray: &Ray<S>,
    skip: Option<usize>,
    z_limit: S,
    nearest: &mut Nearest<S>,
) {
    let test = |nearest: &mut Nearest<S>, index: usize| {
        if Some(index) == skip {
            return;
        }
        let Some(object) = objects.get(index) else {
            return;
        };
        if let Some(t) = object.hits(ray, nearest.limit_for(index))
            && ray.base.z + ray.dir.z * t <= z_limit
        {
            nearest.offer(index, t);
        }
    };
    for &index in tree.unbounded {
        test(nearest, usize::from(index));
    }
    let slabs = Slabs::new(ray.base, ray.dir);
    tree.walk(
        &slabs,
        nearest,
        |nearest| nearest.limit,
        |nearest, index| {
            test(nearest, index);
            false
        },
    );
}

/// An object of a row's list and its kind's test for the row's primary rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowEntry<S> {
    /// The object's index in the scene.
    pub index: u16,
    /// Its test.
    pub test: RowTest<S>,
}

/// [`closest_hit_among`] for a primary ray of a row, over the row's objects and their
/// prepared tests (in increasing index order, so ties still go to the object defined
/// first), and the objects of `tree` (which the row's list then leaves out).
#[inline]
pub fn closest_hit_in_row<S: Scalar>(
    objects: &[Object<S>],
    row: &[RowEntry<S>],
    tree: Option<&Tree<'_, S>>,
    ray: &Ray<S>,
    z_limit: S,
) -> Option<(usize, S)> {
    let mut nearest = Nearest {
        best: None,
        limit: S::UNBOUNDED,
    };
    for entry in row {
        let index = usize::from(entry.index);
        let found = match &entry.test {
            RowTest::Miss => None,
            RowTest::At(t) => {
                nearest.take_row_at(index, *t);
                None
            }
            // Only `f64` rows have these (see `Plane::row_test`): the other types' code has
            // no use for them (flash on the Cortex-M0).
            #[cfg(feature = "plan")]
            RowTest::Plane(distance) if S::COURSE_ORDER => objects
                .get(index)
                .and_then(|object| object.hits_from_distance(ray, *distance, nearest.limit)),
            _ => objects
                .get(index)
                .and_then(|object| object.hits(ray, nearest.limit)),
        };
        if let Some(t) = found {
            nearest.take_in_front(index, t, ray, z_limit);
        }
    }
    rest_of_row_in_tree(objects, tree, ray, z_limit, &mut nearest);
    nearest.best
}

/// The objects of `tree` (not its unbounded ones: a row's list holds those) into the
/// nearest hit a primary ray found in its row's list.
#[inline]
fn rest_of_row_in_tree<S: Scalar>(
    objects: &[Object<S>],
    tree: Option<&Tree<'_, S>>,
    ray: &Ray<S>,
    z_limit: S,
    nearest: &mut Nearest<S>,
) {
    if let (true, Some(tree)) = (cfg!(feature = "plan"), tree) {
        let no_unbounded = Tree {
            unbounded: &[],
            ..*tree
        };
        search_tree(objects, &no_unbounded, ray, None, z_limit, nearest);
    }
}

/// A primary ray of a batch, with the place its closest hit is written to.
#[cfg(feature = "batch")]
pub(crate) trait BatchRay<S> {
    /// The ray.
    fn ray(&self) -> &Ray<S>;
    /// Writes the ray's closest hit (index and ray parameter).
    fn set_hit(&mut self, hit: Option<(usize, S)>);
}

/// [`closest_hit_in_row`] for up to [`BATCH`](crate::shade::BATCH) primary rays of a row
/// shaded together (`None` where there is no ray), each hit written to its ray's lane;
/// whether any ray met an object. The row's entries are in the outer loop and the rays in
/// the inner one, so that the rays' tests of one object run side by side. Each ray meets
/// the entries in the same order with the same limits, so the same hits (tests/plan.rs).
#[cfg(feature = "batch")]
pub(crate) fn closest_hits_in_row<S: Scalar, L: BatchRay<S>>(
    objects: &[Object<S>],
    row: &[RowEntry<S>],
    tree: Option<&Tree<'_, S>>,
    lanes: &mut [Option<L>],
    z_limit: S,
) -> bool {
    let mut nearest = [Nearest {
        best: None,
        limit: S::UNBOUNDED,
    }; crate::shade::BATCH];
    for entry in row {
        let index = usize::from(entry.index);
        let lanes = nearest
            .iter_mut()
            .zip(lanes.iter())
            .filter_map(|(nearest, lane)| Some((nearest, lane.as_ref()?.ray())));
        match (&entry.test, objects.get(index)) {
            (RowTest::Miss, _) => {}
            (RowTest::At(t), _) => {
                for (nearest, _) in lanes {
                    nearest.take_row_at(index, *t);
                }
            }
            // Only the rays that can see the plane (see `behind`).
            #[cfg(feature = "plan")]
            (&RowTest::PlaneAcross { distance, lo, hi }, Some(object)) => {
                let [lo, hi] = [S::from_f64(f64::from(lo)), S::from_f64(f64::from(hi))];
                lanes_across(lanes, object, [distance, lo, hi], index, z_limit);
            }
            #[cfg(feature = "plan")]
            (RowTest::Plane(distance), Some(object)) if S::COURSE_ORDER => {
                // The kind and the plane's axis matched once, each case its own loop.
                let distance = *distance;
                match object.shape() {
                    Shape::Plane(plane) => {
                        lanes_from_plane(lanes, plane, distance, index, z_limit);
                    }
                    Shape::TiledPlane(tiled) => {
                        lanes_from_plane(lanes, &tiled.rect.plane, distance, index, z_limit);
                    }
                    Shape::FPlane(rect) => match (rect.plane.read_axis(), rect.axes()) {
                        // The coordinates each ray's test reads chosen here, once a row.
                        (Some(n), Some([x, y])) => {
                            let codes = [n, x, y];
                            let known = |lanes, axes: [u8; 3]| {
                                each_lane(lanes, index, z_limit, |ray, limit| {
                                    rect.nearest_from_on_known_axes(
                                        axes, codes, distance, ray, limit,
                                    )
                                })
                            };
                            match [x / 2, y / 2] {
                                [0, 1] => known(lanes, [2, 0, 1]),
                                [1, 0] => known(lanes, [2, 1, 0]),
                                [0, 2] => known(lanes, [1, 0, 2]),
                                [2, 0] => known(lanes, [1, 2, 0]),
                                [1, 2] => known(lanes, [0, 1, 2]),
                                _ => known(lanes, [0, 2, 1]),
                            }
                        }
                        _ => each_lane(lanes, index, z_limit, |ray, limit| {
                            rect.nearest_from(distance, ray, limit)
                        }),
                    },
                    Shape::TexPlane(textured) => {
                        each_lane(lanes, index, z_limit, |ray, limit| {
                            textured.rect.nearest_from(distance, ray, limit)
                        });
                    }
                    _ => each_lane(lanes, index, z_limit, |ray, limit| object.hits(ray, limit)),
                }
            }
            (test, Some(object)) => match object.shape() {
                // A sphere's test in the loop itself (what its table holds), not a call a
                // ray; only the rays within the row's outline of it (`RowTest::Across`).
                Shape::Sphere(sphere) => {
                    let (lo, hi) = match *test {
                        #[cfg(feature = "plan")]
                        RowTest::Across { lo, hi } => (lo, hi),
                        _ => (-S::UNBOUNDED, S::UNBOUNDED),
                    };
                    each_lane(lanes, index, z_limit, |ray, limit| {
                        let x = ray.dir.x;
                        if x >= lo && x <= hi {
                            sphere.nearest(ray, limit)
                        } else {
                            None
                        }
                    });
                }
                _ => each_lane(lanes, index, z_limit, |ray, limit| object.hits(ray, limit)),
            },
            (_, None) => {}
        }
    }
    let mut any = false;
    for (nearest, lane) in nearest.iter_mut().zip(lanes) {
        if let Some(lane) = lane {
            rest_of_row_in_tree(objects, tree, lane.ray(), z_limit, nearest);
            lane.set_hit(nearest.best);
            any |= nearest.best.is_some();
        }
    }
    any
}

/// Offers each lane's hit of `test` (given the ray and the lane's limit) to the lane.
#[cfg(feature = "batch")]
#[inline(always)]
fn each_lane<'a, S: Scalar + 'a>(
    lanes: impl Iterator<Item = (&'a mut Nearest<S>, &'a Ray<S>)>,
    index: usize,
    z_limit: S,
    test: impl Fn(&Ray<S>, S) -> Option<S>,
) {
    for (nearest, ray) in lanes {
        if let Some(t) = test(ray, nearest.limit) {
            nearest.take_in_front(index, t, ray, z_limit);
        }
    }
}

/// [`RowTest::PlaneAcross`]'s test (`[distance, lo, hi]`) for the lanes whose direction's
/// `x` lies in `lo..=hi`.
#[cfg(all(feature = "batch", feature = "plan"))]
#[inline(always)]
fn lanes_across<'a, S: Scalar + 'a>(
    lanes: impl Iterator<Item = (&'a mut Nearest<S>, &'a Ray<S>)>,
    object: &Object<S>,
    [distance, lo, hi]: [S; 3],
    index: usize,
    z_limit: S,
) {
    let lanes = lanes.filter(move |(_, ray)| ray.dir.x >= lo && ray.dir.x <= hi);
    match object.infinite_plane() {
        Some(plane) => lanes_from_plane(lanes, plane, distance, index, z_limit),
        None => each_lane(lanes, index, z_limit, |ray, limit| object.hits(ray, limit)),
    }
}

/// [`each_lane`] for an infinite plane `distance` from the rays' base, with the plane's
/// axis (if it reads one) chosen once.
#[cfg(all(feature = "batch", feature = "plan"))]
#[inline(always)]
fn lanes_from_plane<'a, S: Scalar + 'a>(
    lanes: impl Iterator<Item = (&'a mut Nearest<S>, &'a Ray<S>)>,
    plane: &plane::Plane<S>,
    distance: S,
    index: usize,
    z_limit: S,
) {
    // The axis a constant of each loop, so that no lane chooses the coordinate (codes 0
    // to 5: the last arm is 5's).
    let along = |lanes, axis: u8| {
        each_lane(lanes, index, z_limit, |ray, limit| {
            plane.nearest_from_axis(axis, distance, ray.dir, limit)
        });
    };
    match plane.read_axis() {
        Some(0) => along(lanes, 0),
        Some(1) => along(lanes, 1),
        Some(2) => along(lanes, 2),
        Some(3) => along(lanes, 3),
        Some(4) => along(lanes, 4),
        Some(axis) => along(lanes, axis),
        None => each_lane(lanes, index, z_limit, |ray, limit| {
            plane.nearest_from_leaning(distance, ray.dir, limit)
        }),
    }
}

/// The plane a row's prepared tests put at one `t` for every primary ray of the row, the
/// nearest such ([`RowTest::At`], ties to the first), and whether other objects of the row
/// are tested ray by ray ([`RowTest::Hits`]: they may be nearer for some rays). Without
/// them, every ray's closest hit ([`closest_hit_in_row`]) is this one. `None` when no
/// entry is at one `t`.
pub fn row_plane<S: Scalar>(row: &[RowEntry<S>]) -> Option<(usize, S, bool)> {
    let mut best = None;
    let mut limit = S::UNBOUNDED;
    let mut tested = false;
    for entry in row {
        match entry.test {
            RowTest::Miss => {}
            RowTest::At(t) => {
                if t < limit {
                    best = Some((usize::from(entry.index), t));
                    limit = t;
                }
            }
            #[cfg(feature = "plan")]
            RowTest::Plane(_) => tested = true,
            #[cfg(all(feature = "plan", feature = "batch"))]
            RowTest::Across { .. } | RowTest::PlaneAcross { .. } => tested = true,
            RowTest::Hits => tested = true,
        }
    }
    best.map(|(index, t)| (index, t, tested))
}

/// Whether any object `among` (but `skip`) is hit with `t < limit` and within the z rule:
/// the shadow test when nothing is transparent. It stops at the first such hit, where the
/// closest-hit search would test every object.
#[inline]
pub fn any_hit_among<S: Scalar>(
    objects: &[Object<S>],
    among: &Among<'_, S>,
    ray: &Ray<S>,
    skip: usize,
    limit: S,
    z_limit: S,
) -> bool {
    let blocks = |index: usize, object: &Object<S>| {
        index != skip && object_blocks(object, ray, limit, z_limit)
    };
    let mut blocked = false;
    among.each(objects, |index, object| {
        blocked = blocks(index, object);
        if blocked {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    if let (false, true, Among::Tree(tree)) = (blocked, cfg!(feature = "plan"), among) {
        blocked = first_blocker_in_tree(objects, tree, ray, skip, limit, z_limit).is_some();
    }
    blocked
}

/// [`any_hit_among`] for the objects in a tree (out of line, as [`search_tree`]): the
/// first blocker found.
#[inline(never)]
fn first_blocker_in_tree<S: Scalar>(
    objects: &[Object<S>],
    tree: &Tree<'_, S>,
    ray: &Ray<S>,
    skip: usize,
    limit: S,
    z_limit: S,
) -> Option<usize> {
    let slabs = Slabs::new(ray.base, ray.dir);
    let mut blocker = None;
    tree.walk(
        &slabs,
        &mut blocker,
        |_| limit,
        |blocker, index| {
            if blocks(objects, index, ray, skip, limit, z_limit) {
                *blocker = Some(index);
            }
            blocker.is_some()
        },
    );
    blocker
}

/// Whether object `index` (not `skip`) is hit with `t < limit` within the z rule.
#[inline]
fn blocks<S: Scalar>(
    objects: &[Object<S>],
    index: usize,
    ray: &Ray<S>,
    skip: usize,
    limit: S,
    z_limit: S,
) -> bool {
    index != skip
        && objects
            .get(index)
            .is_some_and(|object| object_blocks(object, ray, limit, z_limit))
}

/// Whether `object` is hit with `t < limit` within the z rule.
#[inline]
fn object_blocks<S: Scalar>(object: &Object<S>, ray: &Ray<S>, limit: S, z_limit: S) -> bool {
    object
        .hits(ray, limit)
        .is_some_and(|t| ray.base.z + ray.dir.z * t <= z_limit)
}

/// No object remembered (see [`any_hit_remembering`]).
pub(crate) const NONE_REMEMBERED: u16 = u16::MAX;

/// [`any_hit_among`] that, in a tree, tests the object `last` remembers first and
/// remembers the blocker it finds (a light's shadow cache; see
/// [`crate::shade::ShadowCache`]). The same answer: any blocker answers an any-hit test,
/// and the tree walk reaches every object a ray can hit. Without a tree or a slot it is
/// [`any_hit_among`]. Always inlined: a shadow test is a few dozen instructions
/// around each object's `hits`, and a call's saving and restoring of registers was a
/// quarter of them.
#[inline(always)]
pub fn any_hit_remembering<S: Scalar>(
    objects: &[Object<S>],
    among: &Among<'_, S>,
    ray: &Ray<S>,
    skip: usize,
    limit: S,
    z_limit: S,
    last: Option<&core::sync::atomic::AtomicU16>,
) -> bool {
    // One match on the set: a row's list (the common case) is walked here.
    let (tree, last) = match (among, last) {
        (Among::Only(list), _) => {
            // A plain loop: as `any` the compiler can leave it out of line (measured).
            for &index in *list {
                if blocks(objects, usize::from(index), ray, skip, limit, z_limit) {
                    return true;
                }
            }
            return false;
        }
        (Among::Tree(tree), Some(last)) if cfg!(feature = "plan") => (tree, last),
        _ => return any_hit_among(objects, among, ray, skip, limit, z_limit),
    };
    let remembered = last.load(core::sync::atomic::Ordering::Relaxed);
    if remembered != NONE_REMEMBERED
        && blocks(objects, usize::from(remembered), ray, skip, limit, z_limit)
    {
        return true;
    }
    for &index in tree.unbounded {
        if blocks(objects, usize::from(index), ray, skip, limit, z_limit) {
            return true;
        }
    }
    let blocker = first_blocker_in_tree(objects, tree, ray, skip, limit, z_limit);
    let blocker_index = blocker.map_or(NONE_REMEMBERED, |i| {
        u16::try_from(i).unwrap_or(NONE_REMEMBERED)
    });
    last.store(blocker_index, core::sync::atomic::Ordering::Relaxed);
    blocker.is_some()
}

/// Hit points with `z` above this are in front of the image plane (in scene units, before
/// any scaling of the scene).
pub const Z_LIMIT: f64 = 0.01;

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
}
