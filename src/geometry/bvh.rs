//! The bounding volume hierarchy over the finite shapes.
//!
//! * **Build**: top-down, binned surface area heuristic (SAH: Goldsmith & Salmon 1987,
//!   MacDonald & Booth 1990) with 16 bins over the centroid bounds on each axis, as in I. Wald,
//!   "On fast Construction of SAH-based Bounding Volume Hierarchies", *IEEE Symposium on
//!   Interactive Ray Tracing* 2007. Leaves hold at most 4 primitives. When every centroid
//!   coincides the node is split by count. The build runs on an explicit work list (no
//!   recursion) and is O(n log n): each level bins and partitions its primitives once, and a
//!   depth cap forces median splits before any subtree could grow deeper than [`MAX_DEPTH`].
//! * **Layout**: one flat `Vec` of 32-byte nodes in depth-first order; an interior node's first
//!   child is the next node and it stores the index of its second child (PBR 3rd ed. §4.3.4,
//!   "compact BVH for traversal"). Leaves store a range of primitive ids.
//! * **Traversal**: explicit fixed-size stack, both children tested at their parent and the
//!   nearer entered first, the farther pushed with its entry distance and skipped on pop when a
//!   closer hit has been found; slab tests with a precomputed inverse direction, robust per
//!   Ize 2013 (see [`super::aabb`]).

use glam::Vec3;

use super::aabb::{Aabb, BoxRay};
use super::Ray;

/// Most primitives in one leaf.
pub const MAX_LEAF_PRIMITIVES: usize = 4;

/// Deepest leaf the build produces (root at depth 0); also the traversal stack size, since the
/// stack holds at most one pending sibling per level.
pub const MAX_DEPTH: usize = 64;

/// SAH bins per axis.
const BIN_COUNT: usize = 16;

/// Cost of visiting an interior node, in units of one primitive intersection (both children's
/// slab tests against a triangle or quad test, which is several times a single slab test).
const TRAVERSAL_COST: f32 = 1.0;

/// A primitive to build over: its id (reported back by the traversal) and its bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhPrimitive {
    /// Caller's identifier (prisma: the index of the shape).
    pub id: u32,
    /// Bounding box (scene units).
    pub bounds: Aabb,
}

/// One node, 32 bytes.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
struct Node {
    min: Vec3,
    /// Leaf: index of the first id in `Bvh::ids`. Interior: index of the second child.
    offset: u32,
    max: Vec3,
    /// Leaf: number of primitives (≥ 1). Interior: 0.
    count: u32,
}

impl Node {
    fn bounds(&self) -> Aabb {
        Aabb { min: self.min, max: self.max }
    }
}

/// Size and shape of a built [`Bvh`], for benchmarks and reports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhStats {
    /// Primitives in the hierarchy.
    pub primitives: usize,
    /// Nodes (interior and leaves).
    pub nodes: usize,
    /// Leaf nodes.
    pub leaves: usize,
    /// Depth of the deepest leaf (the root is at depth 0).
    pub max_depth: usize,
    /// Memory of the nodes and the primitive id list (bytes), excluding the primitives.
    pub bytes: usize,
}

impl BvhStats {
    /// [`Self::bytes`] per primitive (bytes per triangle for a mesh); 0 when empty.
    pub fn bytes_per_primitive(&self) -> f64 {
        if self.primitives == 0 {
            0.0
        } else {
            self.bytes as f64 / self.primitives as f64
        }
    }
}

/// A bounding volume hierarchy over primitives given by their bounds.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    ids: Vec<u32>,
    max_depth: usize,
}

/// A node still to be built: primitives `start..end`, and the parent that needs this node's
/// index as its second child.
struct Task {
    start: usize,
    end: usize,
    depth: usize,
    second_child_of: Option<usize>,
}

impl Bvh {
    /// Builds the hierarchy over `primitives` (in any order; ids need not be distinct).
    /// Non-finite bounds do not make it fail, but rays will not find such primitives reliably.
    pub fn build(mut primitives: Vec<BvhPrimitive>) -> Bvh {
        if primitives.is_empty() {
            return Bvh::default();
        }
        let mut nodes = Vec::with_capacity(primitives.len().div_ceil(MAX_LEAF_PRIMITIVES) * 2);
        let mut max_depth = 0;
        // Depth first: the second child is pushed first, so the first child is built next and
        // lands right after its parent.
        let mut tasks = vec![Task { start: 0, end: primitives.len(), depth: 0, second_child_of: None }];
        while let Some(task) = tasks.pop() {
            let index = nodes.len();
            if let Some(parent) = task.second_child_of {
                let parent: &mut Node = &mut nodes[parent];
                parent.offset = index as u32;
            }
            let items = &mut primitives[task.start..task.end];
            let (bounds, centroids) = bounds_and_centroid_bounds(items);
            let node = Node {
                min: bounds.min,
                offset: task.start as u32,
                max: bounds.max,
                count: items.len() as u32,
            };
            match choose_split(items, &bounds, &centroids, task.depth) {
                None => {
                    nodes.push(node);
                    max_depth = max_depth.max(task.depth);
                }
                Some(left_count) => {
                    nodes.push(Node { count: 0, ..node });
                    let middle = task.start + left_count;
                    tasks.push(Task {
                        start: middle,
                        end: task.end,
                        depth: task.depth + 1,
                        second_child_of: Some(index),
                    });
                    tasks.push(Task {
                        start: task.start,
                        end: middle,
                        depth: task.depth + 1,
                        second_child_of: None,
                    });
                }
            }
        }
        Bvh { nodes, ids: primitives.iter().map(|p| p.id).collect(), max_depth }
    }

    /// The bounds of everything in the hierarchy; `None` when it is empty.
    pub fn bounds(&self) -> Option<Aabb> {
        self.nodes.first().map(Node::bounds)
    }

    /// Node count, depth and memory.
    pub fn stats(&self) -> BvhStats {
        BvhStats {
            primitives: self.ids.len(),
            nodes: self.nodes.len(),
            leaves: self.nodes.iter().filter(|n| n.count > 0).count(),
            max_depth: self.max_depth,
            bytes: std::mem::size_of_val(self.nodes.as_slice()) + std::mem::size_of_val(self.ids.as_slice()),
        }
    }

    /// Nearest-hit traversal: calls `intersect(id, t_max)` for the primitives whose boxes the
    /// ray enters before `t_max`, nearest boxes first. `intersect` returns the distance of a hit
    /// closer than the `t_max` it was given (which then shrinks), or `None`.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray, t_max: f32, intersect: impl FnMut(u32, f32) -> Option<f32>) {
        self.traverse::<false>(ray, t_max, intersect);
    }

    /// Any-hit traversal: true as soon as `intersect(id, t_max)` reports a hit.
    #[inline]
    pub fn any_hit(&self, ray: &Ray, t_max: f32, mut intersect: impl FnMut(u32, f32) -> bool) -> bool {
        self.traverse::<true>(ray, t_max, |id, t| intersect(id, t).then_some(t))
    }

    /// The traversal loop; with `ANY_HIT` it returns at the first hit. Returns whether anything
    /// was hit.
    #[inline]
    fn traverse<const ANY_HIT: bool>(
        &self,
        ray: &Ray,
        mut t_max: f32,
        mut intersect: impl FnMut(u32, f32) -> Option<f32>,
    ) -> bool {
        let box_ray = BoxRay::new(ray);
        let Some(root) = self.nodes.first() else {
            return false;
        };
        if root.bounds().entry_distance(&box_ray, t_max).is_none() {
            return false;
        }
        let mut stack = [(0u32, 0f32); MAX_DEPTH];
        let mut stack_len = 0;
        let mut node_index = 0usize;
        let mut found = false;
        loop {
            let node = &self.nodes[node_index];
            if node.count > 0 {
                let first = node.offset as usize;
                for &id in &self.ids[first..first + node.count as usize] {
                    if let Some(t) = intersect(id, t_max) {
                        found = true;
                        if ANY_HIT {
                            return true;
                        }
                        t_max = t;
                    }
                }
            } else {
                let first_child = node_index + 1;
                let second_child = node.offset as usize;
                let first_entry = self.nodes[first_child].bounds().entry_distance(&box_ray, t_max);
                let second_entry = self.nodes[second_child].bounds().entry_distance(&box_ray, t_max);
                match (first_entry, second_entry) {
                    (Some(first_t), Some(second_t)) => {
                        let (near, far, far_t) = if first_t <= second_t {
                            (first_child, second_child, second_t)
                        } else {
                            (second_child, first_child, first_t)
                        };
                        stack[stack_len] = (far as u32, far_t);
                        stack_len += 1;
                        node_index = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node_index = first_child;
                        continue;
                    }
                    (None, Some(_)) => {
                        node_index = second_child;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Next pending node that a closer hit has not made irrelevant.
            loop {
                if stack_len == 0 {
                    return found;
                }
                stack_len -= 1;
                let (pending, entry) = stack[stack_len];
                if entry <= t_max {
                    node_index = pending as usize;
                    break;
                }
            }
        }
    }
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
    if count <= MAX_LEAF_PRIMITIVES && count as f32 * area <= TRAVERSAL_COST * area + best.cost {
        return None;
    }
    let binning = Binning::new(centroids, best.axis);
    let mut left = 0;
    for i in 0..count {
        if binning.bin(&items[i]) <= best.last_left_bin {
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

/// Maps centroids to bins along one axis.
struct Binning {
    axis: usize,
    origin: f32,
    scale: f32,
}

impl Binning {
    fn new(centroids: &Aabb, axis: usize) -> Self {
        let extent = centroids.max[axis] - centroids.min[axis];
        Self {
            axis,
            origin: centroids.min[axis],
            scale: if extent > 0.0 { BIN_COUNT as f32 / extent } else { 0.0 },
        }
    }

    /// The bin of `item`'s centroid (the float-to-int cast saturates, so out-of-range and NaN
    /// values land in the first or last bin).
    #[inline]
    fn bin(&self, item: &BvhPrimitive) -> usize {
        let position = (item.bounds.centroid()[self.axis] - self.origin) * self.scale;
        (position as usize).min(BIN_COUNT - 1)
    }
}

/// A candidate split: bins `0..=last_left_bin` along `axis` go to the first child.
struct BinnedSplit {
    axis: usize,
    last_left_bin: usize,
    /// Σ area × count over both children (scene units²).
    cost: f32,
}

/// The cheapest SAH split over all axes and bin boundaries with primitives on both sides.
/// With finite centroid bounds of positive extent there is always one; `None` otherwise.
/// (Costs of huge boxes may overflow to ∞; the first such candidate is still a valid split.)
fn best_binned_split(items: &[BvhPrimitive], centroids: &Aabb) -> Option<BinnedSplit> {
    let mut best: Option<BinnedSplit> = None;
    for axis in 0..3 {
        let binning = Binning::new(centroids, axis);
        if binning.scale == 0.0 {
            continue;
        }
        let mut bins = [(Aabb::EMPTY, 0usize); BIN_COUNT];
        for item in items {
            let bin = &mut bins[binning.bin(item)];
            bin.0 = bin.0.union(item.bounds);
            bin.1 += 1;
        }
        // right_cost[i]: area × count of bins i+1.. (the second child when splitting after bin i).
        let mut right_cost = [0.0f32; BIN_COUNT];
        let (mut right_bounds, mut right_count) = (Aabb::EMPTY, 0);
        for i in (1..BIN_COUNT).rev() {
            right_bounds = right_bounds.union(bins[i].0);
            right_count += bins[i].1;
            right_cost[i - 1] = right_bounds.surface_area() * right_count as f32;
        }
        let (mut left_bounds, mut left_count) = (Aabb::EMPTY, 0);
        for (i, &(bin_bounds, bin_count)) in bins.iter().enumerate().take(BIN_COUNT - 1) {
            left_bounds = left_bounds.union(bin_bounds);
            left_count += bin_count;
            if left_count == 0 || left_count == items.len() {
                continue;
            }
            let cost = left_bounds.surface_area() * left_count as f32 + right_cost[i];
            if best.as_ref().is_none_or(|best| cost < best.cost) {
                best = Some(BinnedSplit { axis, last_left_bin: i, cost });
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::test_util::Rng;

    fn random_boxes(rng: &mut Rng, count: usize) -> Vec<BvhPrimitive> {
        (0..count)
            .map(|id| {
                let centre = rng.point_in(Vec3::splat(-100.0), Vec3::splat(100.0));
                let half = rng.point_in(Vec3::ZERO, Vec3::splat(2.0));
                BvhPrimitive { id: id as u32, bounds: Aabb { min: centre - half, max: centre + half } }
            })
            .collect()
    }

    /// Checks the invariants the traversal relies on and returns the stats.
    fn check_structure(primitives: &[BvhPrimitive]) -> BvhStats {
        let bvh = Bvh::build(primitives.to_vec());
        let stats = bvh.stats();
        // A binary tree with L leaves has 2L − 1 nodes.
        assert_eq!(stats.nodes, 2 * stats.leaves - 1);
        assert!(stats.max_depth <= MAX_DEPTH);
        // Every primitive appears exactly once.
        let mut ids = bvh.ids.clone();
        ids.sort_unstable();
        assert!(ids.iter().copied().eq(0..primitives.len() as u32));
        for (index, node) in bvh.nodes.iter().enumerate() {
            if node.count > 0 {
                assert!(node.count as usize <= MAX_LEAF_PRIMITIVES);
                let first = node.offset as usize;
                for &id in &bvh.ids[first..first + node.count as usize] {
                    assert!(node.bounds().contains(&primitives[id as usize].bounds));
                }
            } else {
                let second = node.offset as usize;
                assert!(second > index + 1 && second < bvh.nodes.len());
                assert!(node.bounds().contains(&bvh.nodes[index + 1].bounds()));
                assert!(node.bounds().contains(&bvh.nodes[second].bounds()));
            }
        }
        stats
    }

    #[test]
    fn random_boxes_build_a_valid_compact_tree() {
        let mut rng = Rng::new(1);
        let stats = check_structure(&random_boxes(&mut rng, 10_000));
        // Leaves of up to 4 primitives: at least 2500 leaves; a 16-bin SAH tree over uniform
        // boxes should stay within a few levels of the balanced depth log₂(2500) ≈ 11.3.
        assert!(stats.leaves >= 2_500);
        assert!(stats.max_depth <= 30, "depth {}", stats.max_depth);
        // 32-byte nodes and a 4-byte id per primitive. These small boxes are mostly disjoint, so
        // the SAH splits down to single primitives: at most 2n − 1 nodes, < 68 bytes each.
        assert_eq!(std::mem::size_of::<Node>(), 32);
        assert_eq!(stats.bytes, 32 * stats.nodes + 4 * stats.primitives);
        assert!(stats.bytes_per_primitive() < 68.0, "{} B/primitive", stats.bytes_per_primitive());
    }

    #[test]
    fn identical_boxes_split_by_count() {
        // Ten thousand copies of one box: the SAH sees no difference; splitting by count gives
        // a balanced tree of depth ⌈log₂(10000 / 4)⌉ = 12.
        let unit = Aabb { min: Vec3::ZERO, max: Vec3::ONE };
        let primitives: Vec<_> = (0..10_000).map(|id| BvhPrimitive { id, bounds: unit }).collect();
        let stats = check_structure(&primitives);
        assert_eq!(stats.max_depth, 12);
    }

    #[test]
    fn depth_cap_forces_median_splits_then_leaves() {
        let mut rng = Rng::new(6);
        // Nine primitives need ⌈log₂(9/4)⌉ = 2 more levels of median splits; at depth 62 that
        // reaches MAX_DEPTH, so the split must be the median one: 4 | 5 by centroid.
        let mut nine = random_boxes(&mut rng, 9);
        let (bounds, centroids) = bounds_and_centroid_bounds(&nine);
        let axis = (centroids.max - centroids.min).max_position();
        assert_eq!(choose_split(&mut nine, &bounds, &centroids, MAX_DEPTH - 2), Some(4));
        let largest_left = nine[..4].iter().map(|p| p.bounds.centroid()[axis]).fold(f32::MIN, f32::max);
        assert!(nine[4..].iter().all(|p| p.bounds.centroid()[axis] >= largest_left));
        // Four scattered boxes: the SAH splits them at depth 0; at MAX_DEPTH they make a leaf.
        let mut four = random_boxes(&mut rng, 4);
        let (bounds, centroids) = bounds_and_centroid_bounds(&four);
        assert!(choose_split(&mut four, &bounds, &centroids, 0).is_some());
        assert_eq!(choose_split(&mut four, &bounds, &centroids, MAX_DEPTH), None);
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
                }
            })
            .collect();
        check_structure(&primitives);
        let bvh = Bvh::build(primitives);
        let ray = Ray::new(Vec3::new(0.0, 0.5, 0.5), Vec3::X);
        let mut visited = Vec::new();
        bvh.closest_hit(&ray, f32::INFINITY, |id, _| {
            visited.push(id);
            None
        });
        visited.sort_unstable();
        assert!(visited.iter().copied().eq(0..300));
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
        let bvh = Bvh::build(primitives.clone());
        let stats = bvh.stats();
        assert_eq!((stats.primitives, stats.nodes), (100, 2 * stats.leaves - 1));
        let target = primitives[50].bounds.centroid();
        let ray = Ray::new(target + Vec3::new(0.0, 0.0, 500.0), -Vec3::Z);
        let mut found = false;
        bvh.closest_hit(&ray, f32::INFINITY, |id, _| {
            found |= id == 50;
            None
        });
        assert!(found);
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
            })
            .collect();
        let bvh = Bvh::build(primitives.clone());
        let ray = Ray::new(Vec3::new(55.0, 0.5, 0.5), -Vec3::X);
        let box_ray = BoxRay::new(&ray);
        let mut nearest = None;
        bvh.closest_hit(&ray, f32::INFINITY, |id, t_max| {
            let t = primitives[id as usize].bounds.entry_distance(&box_ray, t_max)?;
            nearest = Some(id);
            Some(t)
        });
        assert_eq!(nearest, Some(5));
        assert!(bvh.any_hit(&ray, f32::INFINITY, |_, _| true));
        // Nothing in the other direction past x = 991.
        let away = Ray::new(Vec3::new(995.0, 0.5, 0.5), Vec3::X);
        assert!(!bvh.any_hit(&away, f32::INFINITY, |_, _| true));
        assert_eq!(Bvh::build(Vec::new()).bounds(), None);
    }
}
