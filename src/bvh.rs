//! A bounding-volume hierarchy: the scene's bounded objects (spheres, rectangles) in a
//! tree of bounding spheres, built once before rendering into fixed-capacity arrays, so
//! that a ray meets `O(log n)` of them instead of all.
//!
//! Why spheres and not boxes: the ray-sphere test needs no division (a box's slab test
//! divides by each direction component), so it costs the same few products in every
//! number type, Q16.16 included.
//!
//! - Build: top-down, in `f64`, from each object's bounding sphere; a node's objects are
//!   split at the median of their centres along the longest side of the centres' box.
//!   Leaves hold one or two objects; the tree never has more nodes than the scene has
//!   object slots (a range that would need more becomes one leaf).
//! - Every node's radius is widened by the rounding its test can make in the number type,
//!   so a ray that meets an object always meets every node above it: the tree only decides
//!   which objects are tested, never what a test answers. Objects are then tested through
//!   their kinds' function tables, and ties go to the object defined first, as without the
//!   tree; `tests/plan.rs` renders every scene with and without it and compares.
//! - Unbounded objects (infinite planes) stay outside the tree and are tested on every ray.

use crate::object::{Object, Shape};
use crate::scalar::Scalar;
use crate::vec3::Vec3;
use heapless::Vec;

/// Below this many bounded objects the tree costs more than it saves.
pub const MIN_OBJECTS: usize = 6;

/// Depth of the traversal stack: a median split halves the objects at every level, so 32
/// levels hold far more objects than any scene's capacity.
const STACK: usize = 32;

/// A node: a bounding sphere, and either two children or one or two objects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node<S> {
    /// The sphere's centre.
    pub center: Vec3<S>,
    /// Its radius, widened by the test's rounding.
    pub radius: S,
    /// The radius squared.
    pub radius_squared: S,
    /// A leaf's first object in [`Bvh::order`]; an inner node's second child (the first
    /// is the next node).
    pub first: u16,
    /// A leaf's object count; 0 for an inner node.
    pub count: u16,
}

/// The tree of a scene's bounded objects, and its unbounded ones.
#[derive(Clone, Debug, PartialEq)]
pub struct Bvh<S, const N: usize> {
    nodes: Vec<Node<S>, N>,
    order: Vec<u16, N>,
    unbounded: Vec<u16, N>,
}

/// A built tree as the closest-hit and shadow searches walk it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tree<'a, S> {
    /// Nodes, the root first, each inner node followed by its first child.
    pub nodes: &'a [Node<S>],
    /// Object indices in leaf order.
    pub order: &'a [u16],
    /// The objects outside the tree, in increasing index order.
    pub unbounded: &'a [u16],
}

/// An object's bounding sphere in `f64`: centre and radius. `None` for unbounded kinds.
fn bounds<S: Scalar>(object: &Object<S>) -> Option<(Vec3<f64>, f64)> {
    let rect = match object.shape() {
        Shape::Sphere(s) => return Some((s.center.to_f64(), s.radius.to_f64())),
        Shape::FPlane(rect) => rect,
        Shape::TexPlane(textured) => &textured.rect,
        Shape::Plane(_) | Shape::TiledPlane(_) => return None,
    };
    let p = rect.plane.point.to_f64();
    let across = rect.u.to_f64() * rect.dimensions[0].to_f64();
    let up = rect.v.to_f64() * rect.dimensions[1].to_f64();
    let half = (across + up) * 0.5;
    Some((p + half, libm::sqrt(half.dot(half))))
}

fn distance(a: Vec3<f64>, b: Vec3<f64>) -> f64 {
    let d = a - b;
    libm::sqrt(d.dot(d))
}

fn min_each(a: Vec3<f64>, b: Vec3<f64>) -> Vec3<f64> {
    Vec3::new(a.x.min(b.x), a.y.min(b.y), a.z.min(b.z))
}

fn max_each(a: Vec3<f64>, b: Vec3<f64>) -> Vec3<f64> {
    Vec3::new(a.x.max(b.x), a.y.max(b.y), a.z.max(b.z))
}

/// The longest side of a box: 0, 1 or 2 for x, y, z.
fn longest(side: Vec3<f64>) -> u8 {
    if side.x >= side.y && side.x >= side.z {
        0
    } else if side.y >= side.z {
        1
    } else {
        2
    }
}

fn component(v: Vec3<f64>, axis: u8) -> f64 {
    match axis {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

impl<S: Scalar, const N: usize> Bvh<S, N> {
    /// The tree of the objects `kept` (a render plan's, in increasing index order) seen from
    /// `eye`; empty (every object unbounded) below [`MIN_OBJECTS`] bounded objects.
    pub fn new(objects: &[Object<S>], kept: &[u16], eye: Vec3<S>) -> Self {
        let mut tree = Self {
            nodes: Vec::new(),
            order: Vec::new(),
            unbounded: Vec::new(),
        };
        let bounded = |index: &u16| {
            objects
                .get(usize::from(*index))
                .and_then(|o| bounds(o))
                .is_some()
        };
        let count = kept.iter().filter(|i| bounded(i)).count();
        for &index in kept {
            // Neither can overflow: both hold at most the kept objects.
            let _ = if count >= MIN_OBJECTS && bounded(&index) {
                tree.order.push(index)
            } else {
                tree.unbounded.push(index)
            };
        }
        if tree.order.is_empty() {
            return tree;
        }
        // The rounding of a node's test: a few steps of the type's resolution on the scale
        // of the scene (its largest coordinate, the eye's included).
        let e = eye.to_f64();
        let mut extent = libm::fabs(e.x).max(libm::fabs(e.y)).max(libm::fabs(e.z));
        for &index in &tree.order {
            if let Some((c, r)) = objects.get(usize::from(index)).and_then(|o| bounds(o)) {
                let far = libm::fabs(c.x).max(libm::fabs(c.y)).max(libm::fabs(c.z));
                extent = extent.max(far + r);
            }
        }
        let margin = 64.0 * S::UNIT_STEP * (2.0 * extent + 1.0) + 64.0 * S::MIN_NORMAL;
        let len = tree.order.len();
        tree.build(objects, 0, len, margin, 0);
        tree
    }

    /// Builds the subtree of `order[lo..hi]` at the next node.
    fn build(&mut self, objects: &[Object<S>], lo: usize, hi: usize, margin: f64, depth: usize) {
        let sphere = |index: &u16| {
            objects
                .get(usize::from(*index))
                .and_then(|o| bounds(o))
                .unwrap_or((Vec3::new(0.0, 0.0, 0.0), 0.0))
        };
        let Some(range) = self.order.get(lo..hi) else {
            return;
        };
        // The box of the spheres, its centre, and the sphere around them all.
        let far = Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let (mut low, mut high) = (far, -far);
        let (mut c_low, mut c_high) = (far, -far);
        for index in range {
            let (c, r) = sphere(index);
            let reach = Vec3::new(r, r, r);
            low = min_each(low, c - reach);
            high = max_each(high, c + reach);
            c_low = min_each(c_low, c);
            c_high = max_each(c_high, c);
        }
        let center = (low + high) * 0.5;
        let radius = range.iter().fold(0.0f64, |m, index| {
            let (c, r) = sphere(index);
            m.max(distance(c, center) + r)
        });
        let radius = radius * (1.0 + 1e-9) + margin;
        let count = hi - lo;
        // Room for this node and, if it splits, at least two more.
        let leaf = count <= 2 || depth + 1 >= STACK || self.nodes.len() + 3 > N;
        let node = Node {
            center: center.cast(),
            radius: S::from_f64(radius),
            radius_squared: S::from_f64(radius * radius),
            first: if leaf { lo as u16 } else { 0 },
            count: if leaf { count as u16 } else { 0 },
        };
        let at = self.nodes.len();
        if self.nodes.push(node).is_err() || leaf {
            return;
        }
        // Median split along the longest side of the centres' box.
        let axis = longest(c_high - c_low);
        let mid = lo + count / 2;
        if let Some(range) = self.order.get_mut(lo..hi) {
            range.select_nth_unstable_by(count / 2, |a, b| {
                component(sphere(a).0, axis).total_cmp(&component(sphere(b).0, axis))
            });
        }
        self.build(objects, lo, mid, margin, depth + 1);
        let second = self.nodes.len() as u16;
        if let Some(node) = self.nodes.get_mut(at) {
            node.first = second;
        }
        self.build(objects, mid, hi, margin, depth + 1);
    }

    /// The tree to walk, or `None` when every object is outside it.
    pub fn tree(&self) -> Option<Tree<'_, S>> {
        (!self.nodes.is_empty()).then_some(Tree {
            nodes: &self.nodes,
            order: &self.order,
            unbounded: &self.unbounded,
        })
    }

    /// How many nodes the tree has.
    pub fn nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Whether object `index` is in the tree.
    pub fn contains(&self, index: u16) -> bool {
        self.order.contains(&index)
    }
}

impl<S: Scalar> Tree<'_, S> {
    /// Calls `visit` with every object index whose leaf a ray from `base` along the unit
    /// direction `d` can reach within `limit(state)` (in units of `d`), nearer nodes first,
    /// until `visit` returns `true`. The limit is read again at every node: the nearest hit
    /// so far shrinks it.
    #[inline]
    pub fn walk<T>(
        &self,
        base: Vec3<S>,
        d: Vec3<S>,
        state: &mut T,
        limit: impl Fn(&T) -> S,
        mut visit: impl FnMut(&mut T, usize) -> bool,
    ) {
        let mut stack = [0u16; STACK];
        let mut top = 1usize;
        while top > 0 {
            top -= 1;
            let Some(&at) = stack.get(top) else {
                return;
            };
            let Some(node) = self.nodes.get(usize::from(at)) else {
                continue;
            };
            if !meets(node, base, d, limit(state)) {
                continue;
            }
            if node.count > 0 {
                let first = usize::from(node.first);
                let leaf = self
                    .order
                    .get(first..first + usize::from(node.count))
                    .unwrap_or(&[]);
                for &index in leaf {
                    if visit(state, usize::from(index)) {
                        return;
                    }
                }
                continue;
            }
            // The nearer child is walked first: pushed last.
            let (a, b) = (at + 1, node.first);
            let along = |i: u16| {
                self.nodes
                    .get(usize::from(i))
                    .map_or(S::ZERO, |n| (n.center - base).dot(d))
            };
            let (near, far) = if along(b) < along(a) { (b, a) } else { (a, b) };
            for child in [far, near] {
                if let Some(slot) = stack.get_mut(top) {
                    *slot = child;
                    top += 1;
                }
            }
        }
    }
}

/// Whether a ray from `base` along the unit `d` can meet the node's sphere with `t` in
/// `(0, limit)`: not wholly behind, not wholly beyond `limit`, and passing within the radius
/// of the centre (perpendicular distance, no large squares subtracted).
#[inline]
fn meets<S: Scalar>(node: &Node<S>, base: Vec3<S>, d: Vec3<S>, limit: S) -> bool {
    let f = node.center - base;
    let b = f.dot(d);
    if b + node.radius < S::ZERO || b - node.radius > limit {
        return false;
    }
    let p = f - d * b;
    !(p.dot(p) > node.radius_squared)
}
