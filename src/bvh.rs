//! A bounding-volume hierarchy: the scene's bounded objects (spheres, rectangles) in a
//! tree of axis-aligned boxes, built once before rendering into fixed-capacity arrays, so
//! that a ray meets `O(log n)` of them instead of all.
//!
//! - Build: top-down, in `f64`, from each object's box; a node's objects are split at the
//!   median of their centres along the longest side of the centres' box. Leaves hold one
//!   or two objects; the tree never has more nodes than its capacity (a range that would
//!   need more becomes one leaf).
//! - Walk: the slab test with the ray's inverse direction, worked out once per ray (three
//!   divisions), nearer child first; it takes the ray's parameter as it is, so rays of any
//!   length need no normalising.
//! - Every box is widened by the rounding its test can make in the number type, so a ray
//!   that meets an object always meets every box above it: the tree only decides which
//!   objects are tested, never what a test answers. Objects are then tested through their
//!   kinds' function tables, and ties go to the object defined first, as without the tree;
//!   `tests/bvh.rs` compares every search with and without it, and `tests/plan.rs` every
//!   scene.
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

/// A node: a box, and either two children or one or two objects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node<S> {
    /// The box's lowest corner, widened by the test's rounding.
    pub low: Vec3<S>,
    /// Its highest corner, widened likewise.
    pub high: Vec3<S>,
    /// A leaf's first object in `Bvh::order`; an inner node's second child (the first
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

/// An object's box in `f64`: lowest and highest corner. `None` for unbounded kinds.
pub(crate) fn bounds<S: Scalar>(object: &Object<S>) -> Option<(Vec3<f64>, Vec3<f64>)> {
    let rect = match object.shape() {
        Shape::Sphere(s) => {
            let (c, r) = (s.center.to_f64(), s.radius.to_f64());
            let reach = Vec3::new(r, r, r);
            return Some((c - reach, c + reach));
        }
        Shape::RevSurf(s) if cfg!(feature = "revsurf") => {
            let (c, r) = (s.center.to_f64(), s.bound.to_f64());
            let reach = Vec3::new(r, r, r);
            return Some((c - reach, c + reach));
        }
        Shape::FPlane(rect) => rect,
        Shape::TexPlane(textured) => &textured.rect,
        Shape::Plane(_) | Shape::TiledPlane(_) | Shape::RevSurf(_) => return None,
    };
    let [p, across, up] = rect.corner_and_sides();
    let corners = [p + across, p + up, p + across + up];
    Some(corners.iter().fold((p, p), |(low, high), &c| {
        (min_each(low, c), max_each(high, c))
    }))
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

/// Sorts object indices by a key, keeping the order of ties: an insertion sort, the least
/// code for the few dozen objects a scene has, sorted once at load (`select_nth_unstable`
/// took 0.9 KB of a Cortex-M0's flash at opt-level z, 1.9 KB at 3).
fn sort_by_key(indices: &mut [u16], key: impl Fn(u16) -> f64) {
    for i in 1..indices.len() {
        let mut j = i;
        while let (Some(&before), Some(&at)) = (indices.get(j.wrapping_sub(1)), indices.get(j)) {
            if key(before).total_cmp(&key(at)).is_le() {
                break;
            }
            indices.swap(j - 1, j);
            j -= 1;
        }
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
    /// No tree (what a renderer holds without the `plan` feature).
    pub const fn empty() -> Self {
        Self {
            nodes: Vec::new(),
            order: Vec::new(),
            unbounded: Vec::new(),
        }
    }

    /// The tree of the objects `kept` (a render plan's, in increasing index order) seen from
    /// `eye`; empty (every object unbounded) below [`MIN_OBJECTS`] bounded objects. Out of
    /// line: its working arrays must not stay in the caller's frame while it renders.
    #[inline(never)]
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
            if let Some((low, high)) = objects.get(usize::from(index)).and_then(|o| bounds(o)) {
                for c in [low, high] {
                    extent = extent.max(libm::fabs(c.x).max(libm::fabs(c.y)).max(libm::fabs(c.z)));
                }
            }
        }
        let margin = 64.0 * S::UNIT_STEP * (2.0 * extent + 1.0) + 64.0 * S::MIN_NORMAL;
        let len = tree.order.len();
        tree.build(objects, 0, len, margin, 0);
        tree
    }

    /// Builds the subtree of `order[lo..hi]` at the next node.
    fn build(&mut self, objects: &[Object<S>], lo: usize, hi: usize, margin: f64, depth: usize) {
        let boxed = |index: &u16| {
            let origin = Vec3::new(0.0, 0.0, 0.0);
            objects
                .get(usize::from(*index))
                .and_then(|o| bounds(o))
                .unwrap_or((origin, origin))
        };
        let center = |index: &u16| {
            let (low, high) = boxed(index);
            (low + high) * 0.5
        };
        let Some(range) = self.order.get(lo..hi) else {
            return;
        };
        // The box of the objects' boxes, and the box of their centres.
        let far = Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let (mut low, mut high) = (far, -far);
        let (mut c_low, mut c_high) = (far, -far);
        for index in range {
            let (l, h) = boxed(index);
            low = min_each(low, l);
            high = max_each(high, h);
            c_low = min_each(c_low, center(index));
            c_high = max_each(c_high, center(index));
        }
        let widen = Vec3::new(margin, margin, margin);
        let count = hi - lo;
        // Room for this node and, if it splits, at least two more.
        let leaf = count <= 4 || depth + 1 >= STACK || self.nodes.len() + 3 > N;
        let node = Node {
            low: (low - widen).cast(),
            high: (high + widen).cast(),
            first: if leaf { lo as u16 } else { 0 },
            count: if leaf { count as u16 } else { 0 },
        };
        let at = self.nodes.len();
        if self.nodes.push(node).is_err() || leaf {
            return;
        }
        // Split along the longest side of the centres' box: at its middle, or at the median
        // when the middle leaves a side empty.
        let axis = longest(c_high - c_low);
        let key = |index: u16| component(center(&index), axis);
        let mut mid = lo + count / 2;
        if let Some(range) = self.order.get_mut(lo..hi) {
            sort_by_key(range, key);
            // (At the middle, a grid's rows stay whole.)
            let middle = (component(c_low, axis) + component(c_high, axis)) * 0.5;
            let at = range.iter().take_while(|&&i| key(i) < middle).count();
            if at > 0 && at < count {
                mid = lo + at;
            }
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

/// A ray as the walk tests boxes with it: its base, the inverse of each direction component
/// (infinite, or the type's largest value, for a zero component: the ray then stays in one
/// slab, and the products tell whether it is inside).
#[derive(Clone, Copy, Debug)]
pub struct Slabs<S> {
    base: Vec3<S>,
    inverse: Vec3<S>,
}

impl<S: Scalar> Slabs<S> {
    /// The slabs of a ray from `base` along `dir` (three divisions).
    #[inline]
    pub fn new(base: Vec3<S>, dir: Vec3<S>) -> Self {
        let inverse = Vec3::new(dir.x.recip(), dir.y.recip(), dir.z.recip());
        Self { base, inverse }
    }

    /// The parameter where the ray enters the box (0 when it starts inside), if it meets
    /// the box with a parameter in `(0, limit)`.
    #[inline]
    fn enters(&self, node: &Node<S>, limit: S) -> Option<S> {
        let axis = |low: S, high: S, base: S, inverse: S| {
            let (a, b) = ((low - base) * inverse, (high - base) * inverse);
            (a.min(b), a.max(b))
        };
        let (b, i) = (self.base, self.inverse);
        let (x0, x1) = axis(node.low.x, node.high.x, b.x, i.x);
        let (y0, y1) = axis(node.low.y, node.high.y, b.y, i.y);
        let (z0, z1) = axis(node.low.z, node.high.z, b.z, i.z);
        // A NaN (a base exactly on a face that a zero component runs along) makes the
        // test reject the box: such a ray lies in the face, which the widening keeps
        // clear of every object in the box.
        let enter = S::ZERO.max(x0).max(y0).max(z0);
        let exit = limit.min(x1).min(y1).min(z1);
        (!(enter > exit)).then_some(enter)
    }
}

impl<S: Scalar> Tree<'_, S> {
    /// Calls `visit` with every object index whose leaf the ray of `slabs` can reach with a
    /// parameter below `limit(state)`, nearer boxes first, until `visit` returns `true`.
    /// The limit is read again at every node: the nearest hit so far shrinks it. Each inner
    /// node tests both children's boxes, walks the nearer and keeps the other on a stack.
    #[inline]
    pub fn walk<T>(
        &self,
        slabs: &Slabs<S>,
        state: &mut T,
        limit: impl Fn(&T) -> S,
        mut visit: impl FnMut(&mut T, usize) -> bool,
    ) {
        // Nodes whose boxes the ray met, with the parameter where it entered them (a
        // heapless vector: nothing to clear for a walk that ends at the root).
        let mut stack: Vec<(u16, S), STACK> = Vec::new();
        let mut next = match self.nodes.first() {
            Some(root) => slabs.enters(root, limit(state)).map(|t| (0u16, t)),
            None => None,
        };
        loop {
            let Some((at, enter)) = next.take().or_else(|| stack.pop()) else {
                return;
            };
            // The nearest hit so far may have come closer since the box was met.
            if enter > limit(state) {
                continue;
            }
            let Some(node) = self.nodes.get(usize::from(at)) else {
                continue;
            };
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
            // Both children's boxes now; the nearer is walked next, the other kept.
            let bound = limit(state);
            let meet = |i: u16| {
                self.nodes
                    .get(usize::from(i))
                    .and_then(|n| slabs.enters(n, bound))
                    .map(|t| (i, t))
            };
            match (meet(at + 1), meet(node.first)) {
                (Some(a), Some(b)) => {
                    let (near, far) = if b.1 < a.1 { (b, a) } else { (a, b) };
                    // Cannot fail: the tree is at most `STACK` deep.
                    let _ = stack.push(far);
                    next = Some(near);
                }
                (Some(a), None) => next = Some(a),
                (None, Some(b)) => next = Some(b),
                (None, None) => {}
            }
        }
    }
}
