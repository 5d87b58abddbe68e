//! The bounding volume hierarchy over the finite shapes: an 8-wide BVH ("BVH8", as in Embree:
//! I. Wald et al., "Embree: A Kernel Framework for Efficient CPU Ray Tracing", *ACM TOG* 33(4),
//! 2014; the collapse of a binary tree into a wide one follows Wald, Benthin, Boulos, "Getting
//! Rid of Packets", *IEEE Symposium on Interactive Ray Tracing* 2008).
//!
//! * **Build**: a binary tree first, top-down, with the binned surface area heuristic (SAH:
//!   Goldsmith & Salmon 1987, MacDonald & Booth 1990) over `BIN_COUNT` (16) bins of the centroid
//!   bounds on each axis, all three axes binned in one pass (I. Wald, "On fast Construction of
//!   SAH-based Bounding Volume Hierarchies", *IEEE Symposium on Interactive Ray Tracing* 2007).
//!   The caller intersects primitives [`LEAF_BLOCK`] at a time, so the SAH counts a leaf's cost
//!   in such blocks (as Embree does for its 4-triangle leaves): one to four triangles cost the
//!   same, and leaves fill up to four. A primitive says how many lanes of a block it takes
//!   ([`BvhPrimitive::lanes`]): a sphere, tested on its own, takes a whole block, so two
//!   spheres are worth separate boxes. Leaves hold at most [`MAX_LEAF_PRIMITIVES`]. Subtrees of
//!   more than `PARALLEL_BUILD_MIN` primitives are built in parallel (`rayon::join`). When
//!   every centroid coincides the node is split by count; a depth cap forces median splits
//!   before any subtree could grow deeper than [`MAX_DEPTH`], so the build stays O(n log n).
//! * **Collapse**: each node of the 8-wide tree takes the two children of a binary node and
//!   keeps replacing the child of largest surface area by its own two children until it has
//!   eight (or only leaves are left).
//! * **Layout**: one flat `Vec` of 256-byte nodes (four cache lines) in depth-first order; a
//!   node stores the boxes of its eight children in structure-of-arrays form (one lane per
//!   child), so one node visit tests eight boxes with 8-wide vector arithmetic (AVX through
//!   the `wide` crate where the CPU has it, two 4-wide halves elsewhere). Leaves are not
//!   nodes: a child slot is either another node or a run of consecutive positions in the
//!   *leaf order* that [`Bvh::build`] returns, which the caller may renumber
//!   ([`Bvh::map_leaves`]; [`super::Geometry`] makes them runs of its primitive packets).
//!   Large node arrays are placed on 2 MiB pages where Linux grants them (`huge_pages`).
//! * **Traversal**: a fixed-size stack holding (child, entry distance); the children a ray
//!   enters are visited nearest first, the others pushed and skipped on pop once a closer hit
//!   is known (any-hit traversal skips the sort and stops at the first hit). The nodes of
//!   pushed children are prefetched, so that their fetch from memory overlaps with the work on
//!   the nearer ones (about +10 % on incoherent rays through a 1M-triangle mesh, measured
//!   interleaved on a noisy machine). The traversal loop is compiled once per direction octant
//!   (a const parameter), so that which plane of each axis a ray meets first is a constant and
//!   not a row index held in a register: 11–13 % fewer instructions per ray on the mesh, about
//!   10 % more rays per second, where the indices had been spilled to the stack.
//! * **Packets** (`ray_packet`): up to 16 rays through the tree together, one 16-wide slab
//!   test per child box for all of them, switching to the single-ray loop where few rays are
//!   left ([`Bvh::closest_hit_packet`], [`Bvh::any_hit_packet`]).
//! * **Robust slab test** (T. Ize, "Robust BVH Ray Traversal", *JCGT* 2(2), 2013): the exit
//!   distance is enlarged by 1 + 2·γ(3) so that rounding in `(bound − origin)·(1/dir)` never
//!   makes a ray miss a box that holds the primitive it hits. A direction component of ±0 gives
//!   an infinite inverse; the one indeterminate case, 0·∞ (origin exactly on a slab plane of a
//!   ray parallel to it), constrains nothing, which is the conservative answer.
//! * **Eight children, not four**: on the 1M-triangle mesh (`prisma bench-rays`, 2 threads,
//!   an AVX-512 Xeon, three alternating runs), 10–14 % more incoherent rays per second, nearest
//!   and any hit (2.17–2.26 → 2.47–2.50 and 2.53–2.66 → 2.79–2.87 Mrays/s), single coherent
//!   rays 20 % more (15.7 → 18.9), coherent packets within 5 %, renders of the small
//!   validation scenes unchanged, for 14.3 bytes of nodes per triangle instead of 11.9. A
//!   visit tests eight boxes in the instructions that tested four, and a ray crosses about a
//!   third fewer levels, each a likely cache miss for incoherent rays. (An earlier attempt on
//!   an AMD EPYC, with two 4-wide tests per node, had shown no gain beyond the noise.)
//! * **Measured and not kept**: 32 SAH
//!   bins (0.7 % fewer instructions per incoherent ray, slower build), prefetching leaves,
//!   completing the triangle test's error bound 4-wide (no fewer instructions: most packets
//!   that reach it have a single candidate), nearest-first order in any-hit traversal
//!   (incoherent shadow rays 6 % slower, coherent ones slower too), and testing a node's leaf
//!   children before descending into its other children in any-hit traversal (no change
//!   beyond the noise).

use std::mem::MaybeUninit;

use wide::f32x8;

use super::aabb::Aabb;
use super::rounding::gamma;
use super::Ray;
use crate::float_index::floor_index;

/// `$body` with the constant `$octant` equal to `$value` (a direction octant, 0..8): one
/// compiled copy of `$body` per octant.
macro_rules! by_octant {
    ($value:expr, $octant:ident => $body:expr) => {
        match $value {
            0 => {
                const $octant: usize = 0;
                $body
            }
            1 => {
                const $octant: usize = 1;
                $body
            }
            2 => {
                const $octant: usize = 2;
                $body
            }
            3 => {
                const $octant: usize = 3;
                $body
            }
            4 => {
                const $octant: usize = 4;
                $body
            }
            5 => {
                const $octant: usize = 5;
                $body
            }
            6 => {
                const $octant: usize = 6;
                $body
            }
            _ => {
                const $octant: usize = 7;
                $body
            }
        }
    };
}

mod ray_packet;
pub use ray_packet::PACKET_RAYS;

/// Most primitives in one leaf.
pub const MAX_LEAF_PRIMITIVES: usize = 8;

/// Primitives the caller intersects together (prisma: four triangles in one 4-wide test): the
/// SAH counts the cost of a leaf in such blocks, so a leaf of 1 to 4 costs the same.
pub const LEAF_BLOCK: usize = 4;

/// Deepest leaf of the binary tree (root at depth 0); the 8-wide tree is never deeper. Also
/// bounds the traversal stack, which holds at most seven pending children per level.
pub const MAX_DEPTH: usize = 64;

/// SAH bins per axis.
const BIN_COUNT: usize = 16;

/// Cost of visiting a node (eight slab tests in one 8-wide test), in units of the intersection
/// of one block of [`LEAF_BLOCK`] primitives.
const TRAVERSAL_COST: f32 = 1.0;

/// Subtrees with more primitives than this are built in parallel; below, the work per task is
/// too small to be worth a split.
const PARALLEL_BUILD_MIN: usize = 4096;

/// Child slots per node.
const WIDTH: usize = 8;

/// One f32 per child slot.
type Lanes = f32x8;

/// 64-byte cache lines per node.
const NODE_LINES: usize = std::mem::size_of::<Node>() / 64;

/// The traversal stack: seven pending children per level at most.
const STACK_SIZE: usize = (WIDTH - 1) * MAX_DEPTH + 1;

/// Ize (2013), §3: the rounding of `(bound − origin)·inv_dir` and of `inv_dir = 1/dir` moves a
/// slab distance by at most a relative γ(3) each way, so scaling the exit by 1 + 2γ(3) keeps the
/// computed interval a superset of the true one.
const ROBUST_EXIT_SCALE: f32 = 1.0 + 2.0 * gamma(3);

/// A primitive to build over: its id (reported back in leaf order by [`Bvh::build`]), its
/// bounds, and its share of a leaf's intersection cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhPrimitive {
    /// Caller's identifier (prisma: the index of the shape).
    pub id: u32,
    /// Bounding box (scene units).
    pub bounds: Aabb,
    /// Lanes it takes in the caller's [`LEAF_BLOCK`]-wide tests (prisma: 1 for a triangle, 2 for
    /// a quad, [`LEAF_BLOCK`] for a sphere, which is tested alone). The SAH counts a leaf's cost
    /// as its lanes in blocks of [`LEAF_BLOCK`].
    pub lanes: u32,
}

/// One node: the boxes of up to eight children, 256 bytes.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
struct Node {
    /// The children's boxes by plane: min x, max x, min y, max y, min z, max z; lane i is
    /// child i. An unused slot has the empty box (min +∞, max −∞), which no ray enters.
    planes: [[f32; WIDTH]; 6],
    /// Interior child: index of its node. Leaf child: its first position in leaf order (or
    /// what [`Bvh::map_leaves`] made of it).
    child: [u32; WIDTH],
    /// Leaf child: number of primitives (≥ 1; or what [`Bvh::map_leaves`] made of it).
    /// Interior child and unused slot: 0.
    count: [u32; WIDTH],
}

impl Node {
    const EMPTY: Node = Node {
        planes: [
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ],
        child: [u32::MAX; WIDTH],
        count: [0; WIDTH],
    };

    /// Slot `slot` (taken modulo [`WIDTH`]) as a child to visit, entered at `entry[slot]`.
    #[inline(always)]
    fn pending(&self, slot: usize, entry: &[f32; WIDTH]) -> Pending {
        let slot = slot % WIDTH;
        Pending { child: self.child[slot], count: self.count[slot], entry: entry[slot] }
    }

    fn set_bounds(&mut self, slot: usize, bounds: &Aabb) {
        for axis in 0..3 {
            self.planes[2 * axis][slot] = bounds.min[axis];
            self.planes[2 * axis + 1][slot] = bounds.max[axis];
        }
    }
}

/// Size and shape of a built [`Bvh`], for benchmarks and reports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhStats {
    /// Primitives in the hierarchy.
    pub primitives: usize,
    /// Nodes (8-wide; leaves are child slots, not nodes).
    pub nodes: usize,
    /// Leaves (runs of at most [`MAX_LEAF_PRIMITIVES`] primitives).
    pub leaves: usize,
    /// Depth of the deepest leaf: 1 for a leaf in the root node's slots.
    pub max_depth: usize,
    /// Memory of the nodes (bytes).
    pub bytes: usize,
    /// Memory of the primitive data the intersector keeps in leaf order next to the hierarchy
    /// (bytes; for [`super::Geometry`], the packets that copy the triangles' vertices, the
    /// other shapes and their indices), not counted in [`Self::bytes`].
    pub primitive_bytes: usize,
}

impl BvhStats {
    /// [`Self::bytes`] per primitive (bytes per triangle for a mesh); 0 when empty.
    pub fn bytes_per_primitive(&self) -> f64 {
        self.per_primitive(self.bytes)
    }

    /// [`Self::bytes`] and [`Self::primitive_bytes`] together, per primitive; 0 when empty.
    pub fn total_bytes_per_primitive(&self) -> f64 {
        self.per_primitive(self.bytes + self.primitive_bytes)
    }

    fn per_primitive(&self, bytes: usize) -> f64 {
        if self.primitives == 0 {
            0.0
        } else {
            bytes as f64 / self.primitives as f64
        }
    }
}

/// An 8-wide bounding volume hierarchy over primitives given by their bounds.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    primitives: usize,
    /// The union of every primitive's box.
    bounds: Option<Aabb>,
    max_depth: usize,
}

/// The binary tree of the first build stage.
enum BuildNode {
    Leaf { bounds: Aabb, start: u32, count: u32 },
    Interior { bounds: Aabb, children: Box<[BuildNode; 2]> },
}

impl BuildNode {
    fn bounds(&self) -> &Aabb {
        match self {
            BuildNode::Leaf { bounds, .. } | BuildNode::Interior { bounds, .. } => bounds,
        }
    }
}

impl Bvh {
    /// Builds the hierarchy over `primitives` (in any order; ids need not be distinct), and
    /// returns it with the primitives' ids in leaf order: the leaf the traversal reports as
    /// positions `first..first + count` holds the primitives `ids[first..first + count]`.
    /// Non-finite bounds do not make it fail, but rays will not find such primitives reliably.
    pub fn build(mut primitives: Vec<BvhPrimitive>) -> (Bvh, Vec<u32>) {
        if primitives.is_empty() {
            return (Bvh::default(), Vec::new());
        }
        let root = build_binary(&mut primitives, 0, 0);
        let bounds = *root.bounds();
        let mut nodes = Vec::new();
        let mut max_depth = 0;
        match &root {
            BuildNode::Leaf { bounds, start, count } => {
                let mut node = Node::EMPTY;
                node.set_bounds(0, bounds);
                (node.child[0], node.count[0]) = (*start, *count);
                nodes.push(node);
                max_depth = 1;
            }
            BuildNode::Interior { .. } => {
                emit(&root, &mut nodes, 0, &mut max_depth);
            }
        }
        let nodes = super::huge_pages::on_huge_pages(nodes);
        let bvh = Bvh { nodes, primitives: primitives.len(), bounds: Some(bounds), max_depth };
        (bvh, primitives.iter().map(|p| p.id).collect())
    }

    /// Every leaf as (first position, count), in no particular order.
    pub fn leaves(&self) -> Vec<(u32, u32)> {
        let slots = self.nodes.iter().flat_map(|node| node.child.iter().zip(&node.count));
        slots.filter(|&(_, &count)| count > 0).map(|(&first, &count)| (first, count)).collect()
    }

    /// Replaces every leaf's (first position, count) by `f(first, count)`, which must not give
    /// a count of 0; the traversal then reports the new pair. (prisma: positions of shapes
    /// become runs of packets of four.)
    pub fn map_leaves(&mut self, mut f: impl FnMut(u32, u32) -> (u32, u32)) {
        for node in &mut self.nodes {
            for slot in 0..WIDTH {
                if node.count[slot] > 0 {
                    (node.child[slot], node.count[slot]) = f(node.child[slot], node.count[slot]);
                    assert!(node.count[slot] > 0, "a leaf must keep a non-zero count");
                }
            }
        }
    }

    /// The bounds of everything in the hierarchy; `None` when it is empty.
    pub fn bounds(&self) -> Option<Aabb> {
        self.bounds
    }

    /// Node count, depth and memory (without primitive data: [`BvhStats::primitive_bytes`] is 0).
    pub fn stats(&self) -> BvhStats {
        let leaves = self.nodes.iter().map(|n| n.count.iter().filter(|&&c| c > 0).count()).sum();
        BvhStats {
            primitives: self.primitives,
            nodes: self.nodes.len(),
            leaves,
            max_depth: self.max_depth,
            bytes: std::mem::size_of_val(self.nodes.as_slice()),
            primitive_bytes: 0,
        }
    }

    /// Nearest-hit traversal: calls `intersect(first, count, t_max)` for the leaves whose boxes
    /// the ray enters before `t_max`, nearest boxes first; leaf positions `first..first + count`
    /// (see [`Self::build`] and [`Self::map_leaves`]). `intersect` returns the distance of the nearest hit in the leaf closer
    /// than the `t_max` it was given (which then shrinks), or `None`. Returns whether anything
    /// was hit.
    #[inline]
    pub fn closest_hit(
        &self,
        ray: &Ray,
        t_max: f32,
        mut intersect: impl FnMut(u32, u32, f32) -> Option<f32>,
    ) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let boxes = RayBoxes::new(ray);
        let f = &mut intersect;
        by_octant!(boxes.octant(), O => self.closest_in::<O>(&boxes, Pending::ROOT, t_max, f).is_some())
    }

    /// [`Self::closest_hit`] for a ray of direction octant `OCTANT` (bit a set: negative along
    /// axis a), so that the near and far planes of each axis are known at compile time, in the
    /// subtree `start` (the root, or a child that a packet of rays handed to a single ray:
    /// [`ray_packet`]). Returns the distance of the nearest hit, if any.
    #[inline(always)]
    fn closest_in<const OCTANT: usize>(
        &self,
        boxes: &RayBoxes,
        start: Pending,
        mut t_max: f32,
        intersect: &mut impl FnMut(u32, u32, f32) -> Option<f32>,
    ) -> Option<f32> {
        let mut stack = Stack::new();
        let mut current = start;
        let mut found = false;
        loop {
            if current.count == 0 {
                let node = &self.nodes[current.child as usize];
                let (entry, mask) = boxes.enter::<OCTANT>(node, t_max);
                let entry = entry.to_array();
                // The entered children are visited nearest first: the nearest now, the others
                // pushed farthest first. One or two children are the common cases.
                // (Bit tricks rather than `count_ones`: x86-64's baseline has no `popcnt`.)
                let rest = mask & mask.wrapping_sub(1);
                let beyond_two = rest & rest.wrapping_sub(1);
                match (mask, rest, beyond_two) {
                    (0, _, _) => {}
                    (_, 0, _) => {
                        current = node.pending(mask.trailing_zeros() as usize, &entry);
                        continue;
                    }
                    (_, _, 0) => {
                        let first = mask.trailing_zeros() as usize;
                        let second = rest.trailing_zeros() as usize;
                        let (near, far) = if entry[second % WIDTH] < entry[first % WIDTH] {
                            (second, first)
                        } else {
                            (first, second)
                        };
                        let far = node.pending(far, &entry);
                        self.prefetch(far);
                        stack.push(far);
                        current = node.pending(near, &entry);
                        continue;
                    }
                    _ => {
                        // Three or more: insertion sort, nearest first.
                        let mut hits = [Pending { child: 0, count: 0, entry: 0.0 }; WIDTH];
                        let mut hit_count = 0;
                        let mut remaining = mask;
                        while remaining != 0 {
                            let pending = node.pending(remaining.trailing_zeros() as usize, &entry);
                            remaining &= remaining - 1;
                            let mut i = hit_count;
                            while i > 0 && hits[i - 1].entry > pending.entry {
                                hits[i] = hits[i - 1];
                                i -= 1;
                            }
                            hits[i] = pending;
                            hit_count += 1;
                        }
                        for far in hits[1..hit_count].iter().rev() {
                            self.prefetch(*far);
                            stack.push(*far);
                        }
                        current = hits[0];
                        continue;
                    }
                }
            } else if let Some(t) = intersect(current.child, current.count, t_max) {
                found = true;
                t_max = t;
            }
            // Next pending child that a closer hit has not made irrelevant.
            loop {
                let Some(pending) = stack.pop() else {
                    return found.then_some(t_max);
                };
                if pending.entry <= t_max {
                    current = pending;
                    break;
                }
            }
        }
    }

    /// Asks the memory system for the node of `pending`, if it is one, which the traversal
    /// will visit later unless a closer hit culls it; the fetch then overlaps with the work on
    /// the nearer children instead of stalling the visit.
    #[inline(always)]
    fn prefetch(&self, pending: Pending) {
        #[cfg(target_arch = "x86_64")]
        if pending.count == 0 {
            if let Some(node) = self.nodes.get(pending.child as usize) {
                let address = (node as *const Node).cast::<i8>();
                // SAFETY: a prefetch is a hint that never faults, and every address lies inside
                // `node` (NODE_LINES cache lines).
                unsafe {
                    use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
                    for line in 0..NODE_LINES {
                        _mm_prefetch::<_MM_HINT_T0>(address.add(64 * line));
                    }
                }
            }
        }
    }

    /// Any-hit traversal: true as soon as `intersect(first, count, t_max)` reports a hit in a
    /// leaf (see [`Self::closest_hit`]); children are visited in no particular order.
    #[inline]
    pub fn any_hit(&self, ray: &Ray, t_max: f32, mut intersect: impl FnMut(u32, u32, f32) -> bool) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let boxes = RayBoxes::new(ray);
        let f = &mut intersect;
        by_octant!(boxes.octant(), O => self.any_in::<O>(&boxes, Pending::ROOT, t_max, f))
    }

    /// [`Self::any_hit`] for a ray of direction octant `OCTANT` in the subtree `start` (see
    /// [`Self::closest_in`]).
    #[inline(always)]
    fn any_in<const OCTANT: usize>(
        &self,
        boxes: &RayBoxes,
        start: Pending,
        t_max: f32,
        intersect: &mut impl FnMut(u32, u32, f32) -> bool,
    ) -> bool {
        let mut stack = Stack::new();
        let mut current = start;
        loop {
            if current.count == 0 {
                let node = &self.nodes[current.child as usize];
                let (_, mut mask) = boxes.enter::<OCTANT>(node, t_max);
                if mask != 0 {
                    let no_entry = [0.0; WIDTH];
                    let first = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    while mask != 0 {
                        let other = node.pending(mask.trailing_zeros() as usize, &no_entry);
                        self.prefetch(other);
                        stack.push(other);
                        mask &= mask - 1;
                    }
                    current = node.pending(first, &no_entry);
                    continue;
                }
            } else if intersect(current.child, current.count, t_max) {
                return true;
            }
            match stack.pop() {
                Some(pending) => current = pending,
                None => return false,
            }
        }
    }
}

/// A child waiting to be visited: a node (`count` 0) or a leaf, and the distance at which the
/// ray enters its box.
#[derive(Clone, Copy, Debug)]
struct Pending {
    child: u32,
    count: u32,
    entry: f32,
}

impl Pending {
    /// The root node, where every traversal starts.
    const ROOT: Pending = Pending { child: 0, count: 0, entry: 0.0 };
}

/// The traversal stack. Fixed size and left uninitialised: zeroing its 2.3 kB (with 4-wide
/// nodes; 5.4 kB now) for every ray cost more than the whole traversal of a small scene. The
/// entries are made in a `const` block: from `[MaybeUninit::uninit(); N]` an x86-64-v3 build
/// of rustc 1.95 still emitted a memset of the whole array per ray.
struct Stack {
    entries: [MaybeUninit<Pending>; STACK_SIZE],
    len: usize,
}

impl Stack {
    #[inline]
    fn new() -> Self {
        Self { entries: [const { MaybeUninit::uninit() }; STACK_SIZE], len: 0 }
    }

    /// Panics (index out of bounds) if the stack is full, which the depth cap rules out.
    #[inline]
    fn push(&mut self, pending: Pending) {
        self.entries[self.len] = MaybeUninit::new(pending);
        self.len += 1;
    }

    #[inline]
    fn pop(&mut self) -> Option<Pending> {
        self.len = self.len.checked_sub(1)?;
        // SAFETY: entries[..len] were all written by `push` (len only grows there), and
        // entries[len] is below the old length.
        Some(unsafe { self.entries[self.len].assume_init() })
    }
}

/// A ray prepared for 8-wide slab tests: its origin and the componentwise inverse of its
/// direction (±∞ for zero components), each splat over eight lanes, and the octant of its
/// direction, which decides which plane of a box it meets first on each axis.
#[derive(Clone, Copy, Debug)]
struct RayBoxes {
    origin: [Lanes; 3],
    inv_dir: [Lanes; 3],
    /// Bit a set when the direction is negative (or −0) along axis a: the ray then meets the max
    /// plane of each box first on that axis (the inverse of −0 is −∞).
    octant: usize,
}

impl RayBoxes {
    #[inline]
    fn new(ray: &Ray) -> Self {
        let dir = ray.dir.to_array();
        let origin = ray.origin.to_array().map(Lanes::splat);
        Self {
            origin,
            inv_dir: dir.map(|d| Lanes::splat(1.0 / d)),
            octant: ray.dir.is_negative_bitmask() as usize,
        }
    }

    /// The ray with origin `origin` and inverse direction `inv_dir` (componentwise `1 / dir`),
    /// whose direction lies in octant `octant`.
    #[inline]
    fn from_parts(origin: [f32; 3], inv_dir: [f32; 3], octant: usize) -> Self {
        Self { origin: origin.map(Lanes::splat), inv_dir: inv_dir.map(Lanes::splat), octant }
    }

    /// The octant, 0..8.
    #[inline]
    fn octant(&self) -> usize {
        self.octant & 7
    }

    /// The distances at which the ray enters the eight child boxes of `node` (clamped to 0 when
    /// it starts inside), and a mask of the boxes it overlaps for some t in [0, `t_max`] (bit
    /// i: child i), for a ray of octant `OCTANT` (which must be [`Self::octant`]). Conservative:
    /// may report a box the ray just misses, never misses a box the ray enters.
    ///
    /// A slab distance of 0·∞ = NaN (the ray runs inside a slab plane) constrains nothing: the
    /// running entry and exit distances are replaced only where the comparison with the new one
    /// holds, which it never does for NaN (x86 compiles these selects to `maxps` / `minps`).
    #[inline(always)]
    fn enter<const OCTANT: usize>(&self, node: &Node, t_max: f32) -> (Lanes, u32) {
        debug_assert_eq!(OCTANT, self.octant());
        let mut entry = Lanes::ZERO;
        let mut exit = Lanes::splat(f32::INFINITY);
        for axis in 0..3 {
            // Row of `Node::planes` of the near plane: min for a positive direction, max for a
            // negative one.
            let near_row = 2 * axis + ((OCTANT >> axis) & 1);
            let near = (Lanes::new(node.planes[near_row]) - self.origin[axis]) * self.inv_dir[axis];
            let far = (Lanes::new(node.planes[near_row ^ 1]) - self.origin[axis]) * self.inv_dir[axis];
            entry = larger_unless_nan(near, entry);
            exit = smaller_unless_nan(far, exit);
        }
        let exit = smaller_unless_nan(exit * Lanes::splat(ROBUST_EXIT_SCALE), Lanes::splat(t_max));
        (entry, entry.simd_le(exit).to_bitmask())
    }
}

/// Lane-wise `candidate > running ? candidate : running`: `running` where `candidate` is NaN.
/// On x86-64 this is exactly `maxps` (which returns its second operand when either is NaN);
/// elsewhere a compare and select.
#[inline(always)]
fn larger_unless_nan(candidate: Lanes, running: Lanes) -> Lanes {
    #[cfg(target_arch = "x86_64")]
    {
        candidate.fast_max(running)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        candidate.simd_gt(running).blend(candidate, running)
    }
}

/// Lane-wise `candidate < running ? candidate : running`: `running` where `candidate` is NaN
/// (`minps` on x86-64).
#[inline(always)]
fn smaller_unless_nan(candidate: Lanes, running: Lanes) -> Lanes {
    #[cfg(target_arch = "x86_64")]
    {
        candidate.fast_min(running)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        candidate.simd_lt(running).blend(candidate, running)
    }
}

/// Builds the binary tree over `items`, which start at position `start` of the whole list, at
/// depth `depth`; reorders `items` so that every leaf's primitives are contiguous.
fn build_binary(items: &mut [BvhPrimitive], start: usize, depth: usize) -> BuildNode {
    let (bounds, centroids) = bounds_and_centroid_bounds(items);
    let items_len = items.len();
    let Some(left_count) = choose_split(items, &bounds, &centroids, depth) else {
        return BuildNode::Leaf { bounds, start: start as u32, count: items_len as u32 };
    };
    let (left, right) = items.split_at_mut(left_count);
    let right_start = start + left_count;
    let children = if items_len > PARALLEL_BUILD_MIN {
        rayon::join(|| build_binary(left, start, depth + 1), || build_binary(right, right_start, depth + 1))
    } else {
        (build_binary(left, start, depth + 1), build_binary(right, right_start, depth + 1))
    };
    BuildNode::Interior { bounds, children: Box::new([children.0, children.1]) }
}

/// Appends the 8-wide node for the interior binary node `node` (at 8-wide depth `depth`) and,
/// after it, its subtree; returns its index. `max_depth` tracks the deepest leaf.
fn emit(node: &BuildNode, nodes: &mut Vec<Node>, depth: usize, max_depth: &mut usize) -> u32 {
    let BuildNode::Interior { children, .. } = node else {
        unreachable!("only interior binary nodes become 8-wide nodes")
    };
    let index = nodes.len();
    nodes.push(Node::EMPTY);
    // Open the interior child of largest area until there are eight children; among equal
    // areas the one nearest the binary root, so that ties (identical boxes) open whole levels.
    let mut slots: Vec<(&BuildNode, usize)> = Vec::with_capacity(WIDTH);
    slots.extend(children.iter().map(|child| (child, 1)));
    while slots.len() < WIDTH {
        let mut largest: Option<(usize, f32, usize)> = None;
        for (slot, &(child, level)) in slots.iter().enumerate() {
            if let BuildNode::Interior { bounds, .. } = child {
                let area = bounds.surface_area();
                let larger = largest.is_none_or(|(_, best_area, best_level)| {
                    area > best_area || (area == best_area && level < best_level)
                });
                if larger {
                    largest = Some((slot, area, level));
                }
            }
        }
        let Some((slot, _, level)) = largest else { break };
        let BuildNode::Interior { children, .. } = slots[slot].0 else { unreachable!() };
        slots[slot] = (&children[0], level + 1);
        slots.push((&children[1], level + 1));
    }
    for (slot, (child, _)) in slots.into_iter().enumerate() {
        nodes[index].set_bounds(slot, child.bounds());
        let (reference, count) = match child {
            BuildNode::Leaf { start, count, .. } => {
                *max_depth = (*max_depth).max(depth + 1);
                (*start, *count)
            }
            BuildNode::Interior { .. } => (emit(child, nodes, depth + 1, max_depth), 0),
        };
        nodes[index].child[slot] = reference;
        nodes[index].count[slot] = count;
    }
    index as u32
}

/// The union of the boxes of `items` and the bounds of their centroids, in one pass.
fn bounds_and_centroid_bounds(items: &[BvhPrimitive]) -> (Aabb, Aabb) {
    items.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(bounds, centroids), item| {
        (bounds.union(item.bounds), centroids.grown(item.bounds.centroid()))
    })
}

/// Levels of median splits needed to bring `count` primitives down to leaves.
fn balanced_height(mut count: usize) -> usize {
    let mut height = 0;
    while count > MAX_LEAF_PRIMITIVES {
        count = count.div_ceil(2);
        height += 1;
    }
    height
}

/// Decides between a leaf (`None`) and a split; for a split, reorders `items` so that the first
/// child's primitives come first and returns how many there are (≥ 1, < `items.len()`).
fn choose_split(items: &mut [BvhPrimitive], bounds: &Aabb, centroids: &Aabb, depth: usize) -> Option<usize> {
    let count = items.len();
    if count == 1 {
        return None;
    }
    let extent = centroids.max - centroids.min;
    let axis = extent.max_position();
    let spread = extent[axis] > 0.0; // false for NaN as well
    if !spread {
        // Every centroid coincides (or is not finite): the SAH cannot separate them, so the
        // only sensible split is by count, which keeps the build O(n log n).
        return (count > MAX_LEAF_PRIMITIVES).then_some(count / 2);
    }
    if depth + balanced_height(count) >= MAX_DEPTH {
        // From here on only median splits keep every leaf within MAX_DEPTH.
        return (count > MAX_LEAF_PRIMITIVES).then(|| median_split(items, axis));
    }
    let Some(best) = best_binned_split(items, centroids) else {
        // Only with non-finite centroid bounds: every centroid falls in one bin.
        return Some(median_split(items, axis));
    };
    let area = bounds.surface_area();
    let lanes = items.iter().map(|item| item.lanes).sum();
    if count <= MAX_LEAF_PRIMITIVES && blocks(lanes) * area <= TRAVERSAL_COST * area + best.cost {
        return None;
    }
    let binning = Binning::new(centroids);
    let mut left = 0;
    for i in 0..count {
        if binning.bin(items[i].bounds.centroid()[best.axis], best.axis) <= best.last_left_bin {
            items.swap(left, i);
            left += 1;
        }
    }
    Some(left)
}

/// Reorders `items` around the median of their centroids along `axis`; returns the index of the
/// median (the size of the first half).
fn median_split(items: &mut [BvhPrimitive], axis: usize) -> usize {
    let middle = items.len() / 2;
    items.select_nth_unstable_by(middle, |a, b| {
        a.bounds.centroid()[axis].total_cmp(&b.bounds.centroid()[axis])
    });
    middle
}

/// Maps centroids to bins along each axis.
struct Binning {
    origin: [f32; 3],
    /// Bins per unit length; 0 on an axis of zero extent.
    scale: [f32; 3],
}

impl Binning {
    fn new(centroids: &Aabb) -> Self {
        let extent = centroids.max - centroids.min;
        Self {
            origin: centroids.min.to_array(),
            scale: std::array::from_fn(|axis| {
                if extent[axis] > 0.0 {
                    BIN_COUNT as f32 / extent[axis]
                } else {
                    0.0
                }
            }),
        }
    }

    /// The bin of the centroid coordinate `centroid` along `axis` (out-of-range values land in
    /// the first or last bin, NaN in the first).
    #[inline]
    fn bin(&self, centroid: f32, axis: usize) -> usize {
        let position = (centroid - self.origin[axis]) * self.scale[axis];
        floor_index(position, BIN_COUNT as u32 - 1) as usize
    }
}

/// A candidate split: bins `0..=last_left_bin` along `axis` go to the first child.
struct BinnedSplit {
    axis: usize,
    last_left_bin: usize,
    /// Σ area × blocks over both children (scene units²).
    cost: f32,
}

/// The intersection cost of primitives taking `lanes` lanes, in blocks of [`LEAF_BLOCK`].
#[inline]
fn blocks(lanes: u32) -> f32 {
    lanes.div_ceil(LEAF_BLOCK as u32) as f32
}

/// The cheapest SAH split over all axes and bin boundaries with primitives on both sides.
/// With finite centroid bounds of positive extent there is always one; `None` otherwise.
/// (Costs of huge boxes may overflow to ∞; the first such candidate is still a valid split.)
fn best_binned_split(items: &[BvhPrimitive], centroids: &Aabb) -> Option<BinnedSplit> {
    let binning = Binning::new(centroids);
    // One pass over the primitives fills the bins of all three axes.
    // Each bin: bounds, primitives, lanes.
    let mut bins = [[(Aabb::EMPTY, 0usize, 0u32); BIN_COUNT]; 3];
    for item in items {
        let centroid = item.bounds.centroid().to_array();
        for (axis, axis_bins) in bins.iter_mut().enumerate() {
            let bin = &mut axis_bins[binning.bin(centroid[axis], axis)];
            bin.0 = bin.0.union(item.bounds);
            bin.1 += 1;
            bin.2 += item.lanes;
        }
    }
    let mut best: Option<BinnedSplit> = None;
    for (axis, bins) in bins.iter().enumerate() {
        if binning.scale[axis] == 0.0 {
            continue;
        }
        // right_cost[i]: area × blocks of bins i+1.. (the second child when splitting after bin i).
        let mut right_cost = [0.0f32; BIN_COUNT];
        let (mut right_bounds, mut right_lanes) = (Aabb::EMPTY, 0);
        for i in (1..BIN_COUNT).rev() {
            right_bounds = right_bounds.union(bins[i].0);
            right_lanes += bins[i].2;
            right_cost[i - 1] = right_bounds.surface_area() * blocks(right_lanes);
        }
        let (mut left_bounds, mut left_count, mut left_lanes) = (Aabb::EMPTY, 0, 0);
        for (i, &(bin_bounds, bin_count, bin_lanes)) in bins.iter().enumerate().take(BIN_COUNT - 1) {
            left_bounds = left_bounds.union(bin_bounds);
            left_count += bin_count;
            left_lanes += bin_lanes;
            if left_count == 0 || left_count == items.len() {
                continue;
            }
            let cost = left_bounds.surface_area() * blocks(left_lanes) + right_cost[i];
            if best.as_ref().is_none_or(|best| cost < best.cost) {
                best = Some(BinnedSplit { axis, last_left_bin: i, cost });
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::geometry::test_util::Rng;

    pub(super) fn random_boxes(rng: &mut Rng, count: usize) -> Vec<BvhPrimitive> {
        (0..count)
            .map(|id| {
                let centre = rng.point_in(Vec3::splat(-100.0), Vec3::splat(100.0));
                let half = rng.point_in(Vec3::ZERO, Vec3::splat(2.0));
                BvhPrimitive {
                    id: id as u32,
                    bounds: Aabb { min: centre - half, max: centre + half },
                    lanes: 1,
                }
            })
            .collect()
    }

    /// The box of slot `slot` of `node`.
    fn slot_bounds(node: &Node, slot: usize) -> Aabb {
        let p = node.planes;
        Aabb {
            min: Vec3::new(p[0][slot], p[2][slot], p[4][slot]),
            max: Vec3::new(p[1][slot], p[3][slot], p[5][slot]),
        }
    }

    /// Checks the invariants the traversal relies on and returns the stats.
    fn check_structure(primitives: &[BvhPrimitive]) -> BvhStats {
        let (bvh, leaf_ids) = Bvh::build(primitives.to_vec());
        let stats = bvh.stats();
        // Every primitive appears exactly once in leaf order.
        let mut ids = leaf_ids.clone();
        ids.sort_unstable();
        assert!(ids.iter().copied().eq(0..primitives.len() as u32));
        // Every leaf position is covered by exactly one leaf.
        let mut covered = vec![0; primitives.len()];
        let mut referenced = vec![0; bvh.nodes.len()];
        for (index, node) in bvh.nodes.iter().enumerate() {
            let mut used = 0;
            for slot in 0..WIDTH {
                let bounds = slot_bounds(node, slot);
                let (child, count) = (node.child[slot] as usize, node.count[slot] as usize);
                if count > 0 {
                    used += 1;
                    assert!(count <= MAX_LEAF_PRIMITIVES);
                    for position in child..child + count {
                        covered[position] += 1;
                        assert!(bounds.contains(&primitives[leaf_ids[position] as usize].bounds));
                    }
                } else if child != u32::MAX as usize {
                    used += 1;
                    // Depth-first order: children come after their parent.
                    assert!(child > index && child < bvh.nodes.len());
                    referenced[child] += 1;
                    for grandchild in 0..WIDTH {
                        let inner = slot_bounds(&bvh.nodes[child], grandchild);
                        assert!(inner == Aabb::EMPTY || bounds.contains(&inner));
                    }
                } else {
                    // An unused slot has the empty box, which no ray enters.
                    assert_eq!(bounds, Aabb::EMPTY);
                }
            }
            // Only the root may have a single child (a scene that is one leaf).
            assert!(used >= 2 || bvh.nodes.len() == 1, "node {index} has {used} children");
        }
        assert!(covered.iter().all(|&c| c == 1));
        assert_eq!(referenced[0], 0);
        assert!(referenced[1..].iter().all(|&r| r == 1));
        assert!(stats.max_depth <= MAX_DEPTH);
        stats
    }

    #[test]
    fn random_boxes_build_a_valid_compact_tree() {
        let mut rng = Rng::new(1);
        let stats = check_structure(&random_boxes(&mut rng, 10_000));
        // Leaves of at most 8; and since up to four primitives cost one block, the SAH hardly
        // ever splits four or fewer: leaves average close to 4 (3.97 when this was written), so
        // there are about 2500 of them, which a balanced 8-wide tree holds at depth
        // ⌈log₈ 2500⌉ = 4 (5 when this was written: the collapse opens the largest boxes first,
        // not whole levels).
        assert!(stats.leaves >= 10_000 / MAX_LEAF_PRIMITIVES);
        assert!(stats.leaves <= 3_400, "{stats:?}");
        assert!(stats.max_depth <= 6, "{stats:?}");
        // 256-byte nodes. Nodes average about five children (the last binary levels above the
        // leaves often give fewer than eight): 592 nodes, 15 bytes per primitive when this was
        // written.
        assert_eq!(std::mem::size_of::<Node>(), 256);
        assert_eq!(stats.bytes, 256 * stats.nodes);
        assert!(stats.bytes_per_primitive() < 20.0, "{stats:?}");
    }

    #[test]
    fn identical_boxes_split_by_count() {
        // Ten thousand copies of one box: the SAH sees no difference; splitting by count gives
        // a balanced binary tree of depth ⌈log₂(10000 / 8)⌉ = 11, which the collapse turns into
        // 8-wide nodes of three binary levels each: leaves at depth ⌈11 / 3⌉ = 4.
        let unit = Aabb { min: Vec3::ZERO, max: Vec3::ONE };
        let primitives: Vec<_> = (0..10_000).map(|id| BvhPrimitive { id, bounds: unit, lanes: 1 }).collect();
        let stats = check_structure(&primitives);
        assert_eq!(stats.max_depth, 4);
    }

    #[test]
    fn depth_cap_forces_median_splits_then_leaves() {
        let mut rng = Rng::new(6);
        // Nine primitives need ⌈log₂(9/8)⌉ = 1 more level of median splits; at depth 63 that
        // reaches MAX_DEPTH, so the split must be the median one: 4 | 5 by centroid.
        let mut nine = random_boxes(&mut rng, 9);
        let (bounds, centroids) = bounds_and_centroid_bounds(&nine);
        let axis = (centroids.max - centroids.min).max_position();
        assert_eq!(choose_split(&mut nine, &bounds, &centroids, MAX_DEPTH - 1), Some(4));
        let largest_left = nine[..4].iter().map(|p| p.bounds.centroid()[axis]).fold(f32::MIN, f32::max);
        assert!(nine[4..].iter().all(|p| p.bounds.centroid()[axis] >= largest_left));
        // Two clusters of three unit boxes 100 apart: two one-block leaves of tiny boxes are far
        // cheaper than one two-block leaf of the whole span, so the SAH splits them 3 | 3 at
        // depth 0; at MAX_DEPTH they make a leaf.
        let cluster = |x: f32| {
            (0..3).map(move |i| Aabb {
                min: Vec3::new(x, i as f32, 0.0),
                max: Vec3::new(x + 1.0, i as f32 + 1.0, 1.0),
            })
        };
        let mut six: Vec<_> = cluster(0.0)
            .chain(cluster(100.0))
            .enumerate()
            .map(|(id, bounds)| BvhPrimitive { id: id as u32, bounds, lanes: 1 })
            .collect();
        let (bounds, centroids) = bounds_and_centroid_bounds(&six);
        assert_eq!(choose_split(&mut six, &bounds, &centroids, 0), Some(3));
        assert_eq!(choose_split(&mut six, &bounds, &centroids, MAX_DEPTH), None);
        // Four scattered boxes are one block: a leaf even at depth 0.
        let mut four = random_boxes(&mut rng, 4);
        let (bounds, centroids) = bounds_and_centroid_bounds(&four);
        assert_eq!(choose_split(&mut four, &bounds, &centroids, 0), None);
    }

    /// Every id whose leaf `bvh` visits for `ray`, sorted.
    fn visited((bvh, ids): &(Bvh, Vec<u32>), ray: &Ray) -> Vec<u32> {
        let mut visited = Vec::new();
        bvh.closest_hit(ray, f32::INFINITY, |first, count, _| {
            visited.extend_from_slice(&ids[first as usize..(first + count) as usize]);
            None
        });
        visited.sort_unstable();
        visited
    }

    #[test]
    fn huge_growing_boxes_build() {
        // Box i spans x in [1.15ⁱ, 1.15ⁱ⁺¹] and is 1.15ⁱ high and deep, up to ~10¹⁸: each is
        // about as large as all smaller ones together, and area × count overflows f32 to ∞ in
        // the SAH costs. The build must still give a valid tree in which every box is found.
        let primitives: Vec<_> = (0..300)
            .map(|i| {
                let start = 1.15f32.powi(i);
                BvhPrimitive {
                    id: i as u32,
                    bounds: Aabb {
                        min: Vec3::new(start, 0.0, 0.0),
                        max: Vec3::new(1.15 * start, start, start),
                    },
                    lanes: 1,
                }
            })
            .collect();
        check_structure(&primitives);
        let built = Bvh::build(primitives);
        let ray = Ray::new(Vec3::new(0.0, 0.5, 0.5), Vec3::X);
        assert!(visited(&built, &ray).into_iter().eq(0..300));
    }

    #[test]
    fn non_finite_bounds_do_not_break_the_build() {
        // Boxes with infinite and NaN corners (a sphere of infinite radius, a NaN vertex): the
        // build terminates with a valid tree (the finite boxes are still found).
        let mut rng = Rng::new(4);
        let mut primitives = random_boxes(&mut rng, 100);
        primitives[10].bounds.max = Vec3::INFINITY;
        primitives[20].bounds.min = Vec3::NEG_INFINITY;
        primitives[30].bounds.min.x = f32::NAN;
        primitives[40].bounds = Aabb { min: Vec3::NEG_INFINITY, max: Vec3::INFINITY };
        let built = Bvh::build(primitives.clone());
        assert_eq!(built.0.stats().primitives, 100);
        let mut ids = built.1.clone();
        ids.sort_unstable();
        assert!(ids.into_iter().eq(0..100));
        let target = primitives[50].bounds.centroid();
        let ray = Ray::new(target + Vec3::new(0.0, 0.0, 500.0), -Vec3::Z);
        assert!(visited(&built, &ray).contains(&50));
    }

    /// The exact (f64) distance at which `ray` enters `bounds`, if it does.
    fn exact_entry(bounds: &Aabb, ray: &Ray) -> Option<f32> {
        let (mut enter, mut exit) = (0.0f64, f64::INFINITY);
        for axis in 0..3 {
            let (origin, dir) = (f64::from(ray.origin[axis]), f64::from(ray.dir[axis]));
            let (low, high) = (f64::from(bounds.min[axis]), f64::from(bounds.max[axis]));
            if dir == 0.0 {
                if origin < low || origin > high {
                    return None;
                }
                continue;
            }
            let (t0, t1) = ((low - origin) / dir, (high - origin) / dir);
            enter = enter.max(t0.min(t1));
            exit = exit.min(t0.max(t1));
        }
        (enter <= exit).then_some(enter as f32)
    }

    #[test]
    fn traversal_finds_the_nearest_and_any() {
        // Boxes along the x axis at x = 0, 10, 20, ...; a ray from x = 55 towards −x reaches
        // the box at 50 first (t = 4, its far face is at 51) and `closest_hit` reports it.
        let primitives: Vec<_> = (0..100)
            .map(|i| BvhPrimitive {
                id: i,
                bounds: Aabb {
                    min: Vec3::new(10.0 * i as f32, 0.0, 0.0),
                    max: Vec3::new(10.0 * i as f32 + 1.0, 1.0, 1.0),
                },
                lanes: 1,
            })
            .collect();
        let (bvh, ids) = Bvh::build(primitives.clone());
        let ray = Ray::new(Vec3::new(55.0, 0.5, 0.5), -Vec3::X);
        let mut nearest = None;
        let found = bvh.closest_hit(&ray, f32::INFINITY, |first, count, mut t_max| {
            let mut hit = None;
            for &id in &ids[first as usize..(first + count) as usize] {
                if let Some(t) = exact_entry(&primitives[id as usize].bounds, &ray).filter(|&t| t < t_max) {
                    (nearest, hit, t_max) = (Some(id), Some(t), t);
                }
            }
            hit
        });
        assert!(found);
        assert_eq!(nearest, Some(5));
        assert!(bvh.any_hit(&ray, f32::INFINITY, |_, _, _| true));
        // Nothing in the other direction past x = 991.
        let away = Ray::new(Vec3::new(995.0, 0.5, 0.5), Vec3::X);
        assert!(!bvh.any_hit(&away, f32::INFINITY, |_, _, _| true));
        assert!(!bvh.closest_hit(&away, f32::INFINITY, |_, _, _| Some(0.0)));
        assert_eq!(Bvh::build(Vec::new()).0.bounds(), None);
    }

    #[test]
    fn traversal_agrees_with_exact_box_tests() {
        // Random rays through 2000 random boxes: the leaves visited by `any_hit` with a callback
        // that never hits are exactly the boxes the ray enters (by an exact f64 slab test),
        // except boxes that the ray just grazes, which the conservative test may add.
        let mut rng = Rng::new(12);
        let primitives = random_boxes(&mut rng, 2_000);
        let (bvh, ids) = Bvh::build(primitives.clone());
        for _ in 0..2_000 {
            let origin = rng.point_in(Vec3::splat(-150.0), Vec3::splat(150.0));
            let ray = Ray::new(origin, rng.unit_vector());
            let t_max = rng.uniform(10.0, 300.0);
            let mut reported = Vec::new();
            bvh.any_hit(&ray, t_max, |first, count, _| {
                reported.extend_from_slice(&ids[first as usize..(first + count) as usize]);
                false
            });
            for (id, primitive) in primitives.iter().enumerate() {
                if exact_entry(&primitive.bounds, &ray).is_some_and(|t| t < t_max * (1.0 - 1e-6)) {
                    assert!(reported.contains(&(id as u32)), "box {id} missed by {ray:?}");
                }
            }
        }
    }

    /// The entry distance and hit bit of a single box in slot 0 of a node.
    fn enter_one(bounds: Aabb, ray: Ray, t_max: f32) -> Option<f32> {
        let mut node = Node::EMPTY;
        node.set_bounds(0, &bounds);
        let boxes = RayBoxes::new(&ray);
        let (entry, mask) = by_octant!(boxes.octant(), O => boxes.enter::<O>(&node, t_max));
        assert_eq!(mask & !1, 0, "unused slots are never entered");
        (mask & 1 == 1).then_some(entry.as_array()[0])
    }

    fn unit_box() -> Aabb {
        Aabb { min: Vec3::ZERO, max: Vec3::ONE }
    }

    #[test]
    fn entry_distance_of_a_hit_and_a_miss() {
        // From x = −2 along +x through the middle of [0,1]³: enters at t = 2.
        let along_x = Ray::new(Vec3::new(-2.0, 0.5, 0.5), Vec3::X);
        assert_eq!(enter_one(unit_box(), along_x, 10.0), Some(2.0));
        // Same ray with t_max = 1.5 stops before the box.
        assert_eq!(enter_one(unit_box(), along_x, 1.5), None);
        // Passing above the box misses; a box behind the origin misses.
        assert_eq!(enter_one(unit_box(), Ray::new(Vec3::new(-2.0, 1.5, 0.5), Vec3::X), 10.0), None);
        assert_eq!(enter_one(unit_box(), Ray::new(Vec3::new(2.0, 0.5, 0.5), Vec3::X), 10.0), None);
        // The same along −x from the other side, and from inside (entry clamped to 0).
        assert_eq!(enter_one(unit_box(), Ray::new(Vec3::new(3.0, 0.5, 0.5), -Vec3::X), 10.0), Some(2.0));
        assert_eq!(enter_one(unit_box(), Ray::new(Vec3::splat(0.5), Vec3::Y), 10.0), Some(0.0));
    }

    #[test]
    fn ray_in_a_slab_plane_counts_as_inside() {
        // Origin exactly on the face y = 0, travelling along +x (dir.y = 0): (0 − 0)·∞ is NaN;
        // the ray grazes the face, which the conservative test must report (entry at t = 1).
        let grazing = Ray::new(Vec3::new(-1.0, 0.0, 0.5), Vec3::X);
        assert_eq!(enter_one(unit_box(), grazing, 10.0), Some(1.0));
        // Same with a negative zero component and the face y = 1.
        let negative_zero = Ray::new(Vec3::new(-1.0, 1.0, 0.5), Vec3::new(1.0, -0.0, 0.0));
        assert_eq!(enter_one(unit_box(), negative_zero, 10.0), Some(1.0));
        // A flat box (a quad's bounds, zero thickness in y) and a ray inside its plane, with +0
        // and −0 as the direction's y component.
        let flat = Aabb { min: Vec3::ZERO, max: Vec3::new(1.0, 0.0, 1.0) };
        assert_eq!(enter_one(flat, grazing, 10.0), Some(1.0));
        let flat_negative_zero = Ray::new(Vec3::new(-1.0, 0.0, 0.5), Vec3::new(1.0, -0.0, 0.0));
        assert_eq!(enter_one(flat, flat_negative_zero, 10.0), Some(1.0));
        // Parallel to the slab but outside it, on either side and with either zero: a miss.
        for (y, dir_y) in [(2.0, 0.0), (2.0, -0.0), (-1.0, 0.0), (-1.0, -0.0)] {
            let outside = Ray::new(Vec3::new(-1.0, y, 0.5), Vec3::new(1.0, dir_y, 0.0));
            assert_eq!(enter_one(unit_box(), outside, 10.0), None, "y = {y}, dir.y = {dir_y}");
        }
    }
}
