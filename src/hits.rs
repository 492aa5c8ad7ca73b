//! Rays against the scene's objects: the nearest hit and whether any object blocks a
//! shadow ray, over every object, a render plan's list, a row's prepared tests or the
//! tree. The objects' own tests (each kind's `hits`) are in [`crate::object`]; this is
//! the loop around them, with the course's rules: ties go to the object defined first,
//! and a hit point in front of the image plane does not count (the z rule).

use crate::bvh::{Slabs, Tree};
#[cfg(feature = "batch")]
use crate::lanes::BATCH;
#[cfg(feature = "batch")]
use crate::object::Shape;
#[cfg(all(feature = "batch", feature = "plan"))]
use crate::object::plane;
use crate::object::{Hit, Object, RowEntry, RowTest};
use crate::ray::Ray;
use crate::scalar::Scalar;
use core::ops::ControlFlow;

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

/// [`closest_hit_among`] for a primary ray of a row, over the row's objects and their
/// prepared tests (in increasing index order, so ties still go to the object defined
/// first), and the objects of `tree` (which the row's list then leaves out). In line
/// where speed counts: out of line, the call cost scenes without rectangles 1-2 % on the
/// Cortex-M4F in Q16.16 (docs/speed-log.md, step 10).
#[cfg_attr(not(microray_small), inline(always))]
#[cfg_attr(microray_small, inline)]
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
            #[cfg(all(feature = "plan", not(microray_small)))]
            &RowTest::AtAcross { t, lo, hi, .. } => {
                if ray.dir.x >= lo && ray.dir.x <= hi {
                    nearest.take_row_at(index, t);
                }
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

/// [`closest_hit_in_row`] for up to [`BATCH`] primary rays of a row
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
    }; BATCH];
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
            #[cfg(feature = "plan")]
            (&RowTest::AtAcross { t, lo, hi, .. }, _) => {
                for (nearest, ray) in lanes {
                    if ray.dir.x >= lo && ray.dir.x <= hi {
                        nearest.take_row_at(index, t);
                    }
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
    row_plane_within(row, None)
}

/// [`row_plane`] for the columns `within` (`[first, last]`) of the row: there a run of
/// columns ([`RowTest::AtAcross`]) that holds them all is a plane at one `t`, and one that
/// holds none of them a miss (a segment of the row cut at the runs' ends).
pub(crate) fn row_plane_within<S: Scalar>(
    row: &[RowEntry<S>],
    within: Option<[u16; 2]>,
) -> Option<(usize, S, bool)> {
    let mut best = None;
    let mut limit = S::UNBOUNDED;
    let mut tested = false;
    #[cfg(any(not(feature = "plan"), microray_small))]
    let _ = within;
    for entry in row {
        // Entries come in increasing index order: ties go to the first.
        let mut at = |t: S| {
            if t < limit {
                best = Some((usize::from(entry.index), t));
                limit = t;
            }
        };
        match entry.test {
            RowTest::Miss => {}
            RowTest::At(t) => at(t),
            #[cfg(all(feature = "plan", not(microray_small)))]
            RowTest::AtAcross { t, first, last, .. } => match within {
                Some([from, to]) if first <= from && to <= last => at(t),
                Some([from, to]) if to < first || last < from => {}
                _ => tested = true,
            },
            #[cfg(feature = "plan")]
            RowTest::Plane(_) => tested = true,
            #[cfg(all(feature = "plan", microray_small))]
            RowTest::AtAcross { .. } => tested = true,
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
pub(crate) fn object_blocks<S: Scalar>(
    object: &Object<S>,
    ray: &Ray<S>,
    limit: S,
    z_limit: S,
) -> bool {
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
