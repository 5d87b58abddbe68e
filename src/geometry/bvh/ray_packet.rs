//! Traversal of up to [`PACKET_RAYS`] rays at once, for rays that travel together through the
//! same nodes: a pinhole camera's neighbouring rays, shadow rays towards one light.
//!
//! A *ray packet* (I. Wald, P. Slusallek, C. Benthin, M. Wagner, "Interactive Rendering with
//! Coherent Ray Tracing", *Computer Graphics Forum* 20(3), 2001) visits a node once for all its
//! rays: each child box is tested against the sixteen rays in one 16-wide slab test (two
//! AVX2 or four SSE instructions per step, by the `wide` crate; `.cargo/config.toml` leaves
//! AVX-512 out), and a child is entered with the mask of the rays that enter it. Where
//! the packet thins out, in the lower levels and the leaves, the few rays left continue one by
//! one through the single-ray traversal of [`Bvh::closest_hit`] from that child on (the
//! hybrid of C. Benthin, I. Wald, S. Woop, M. Ernst, W. R. Mark, "Combining Single and Packet
//! Ray Tracing for Arbitrary Ray Distributions on the Intel MIC Architecture", *IEEE TVCG*
//! 18(9), 2012, which Embree's packet kernels use): incoherent rays pay a few shared visits
//! near the root and then trace as single rays.
//!
//! Each ray's slab test is the single-ray test, lane by lane (the same operations on the same
//! operands, so the same conservative answer), and leaves are intersected ray by ray through
//! the caller's leaf test, so a packet finds exactly the hits that its rays find alone; only
//! which of two hits at exactly the same distance is reported may differ, since the nodes are
//! visited in another order.
//!
//! A packet traverses with one direction octant, so that the near plane of each axis is a
//! constant as in the single-ray loop; the rays of a packet are grouped by octant first
//! (coherent rays nearly always share one).
//!
//! [`Bvh::coherent_lanes`] tells the caller which rays to hand over together: those whose
//! octant at least half the packet shares. Rays with spread directions also have spread
//! origins or boxes, split after the root, and traced together cost more than alone.
//!
//! Measured on the 1M-triangle mesh of `validation/bench/bench.py` (`prisma bench-rays`, 2
//! threads, an AVX-512 Xeon; camera rays in rows of 1000, sixteen consecutive rays a packet):
//! with 4-wide nodes, nearest hits 15–16.5 Mrays/s one by one and 17.5–21 in packets, any hits
//! 16–18 and 24–29; with 8-wide nodes (in RESULTS.md) 19.7 and 23.2, 20.3 and 26.9. A packet's
//! rays visited 92 4-wide nodes one by one and about 11 in the packet (7.4 packet visits and
//! 3.7 single-ray ones below the switch); the leaf tests, still ray by ray, are then most of
//! the cost. Incoherent rays: 0–10 % slower than one by one (the octant grouping, and the
//! occasional group of eight that splits after the root).
//!
//! Below the root, a node is first tested against the packet's *frustum* ([`PacketFrustum`]:
//! the bounds of its rays' origins and inverse directions, one conservative 8-wide test for
//! all eight children), and only the children it keeps get the exact 16-wide test: on the
//! coherent bench rays it kept 1.8 of 8 children per packet visit. With it, and with the
//! packet's boxes made without a call per lane, packets of camera rays went from 20.9 to 23.4
//! Mrays/s (nearest) and from 28.2 to 31.9 (any) on a 2-core AMD EPYC (best of 8 alternating
//! runs each; single rays 19.2–20.6 and 23.4–23.5 in the same runs). Most packets of that set
//! miss the mesh's box, so what a packet costs before its first node counts: the frustum is
//! made only on the first visit below the root.
//!
//! Measured and not kept: testing the rays that reach a leaf together 16 at a time against
//! each triangle (the 4-wide filter of `packet` made 16 rays wide): on the same rays a leaf is
//! reached by 3 rays of a packet on average, and the packets were no faster (within the
//! noise, 0–10 % slower).

use std::mem::MaybeUninit;

use wide::f32x16;

use super::{Bvh, Lanes, Node, Pending, RayBoxes, ROBUST_EXIT_SCALE, STACK_SIZE, WIDTH};
use crate::geometry::Ray;

/// Rays in a packet.
pub const PACKET_RAYS: usize = 16;

/// Every child slot of a node, as a mask.
const ALL_CHILDREN: LaneMask = (1 << WIDTH) - 1;

/// A packet's rays that still traverse a subtree, bit i for lane i; or fewer,
/// [`SINGLE_RAYS_MAX`] or less, which then continue one by one.
type LaneMask = u32;

/// A child entered by at most this many of a packet's rays is traversed by each of them alone:
/// a 16-wide test then costs more than the single-ray tests it replaces.
const SINGLE_RAYS_MAX: u32 = 3;

/// [`Bvh::coherent_lanes`]: rays of one octant fewer than this are traced alone from the root.
/// Fewer rays of a packet share an octant when their directions are spread, and then, on the
/// bench mesh's incoherent rays (where 29 % of the rays are in groups of four or more), their
/// boxes also differ: such groups split after the root, and traversing them together cost
/// 12–15 % of the single-ray throughput.
const PACKET_MIN_RAYS: u32 = PACKET_RAYS as u32 / 2;

/// Sixteen rays prepared for 16-wide slab tests: origins and componentwise inverse directions
/// by axis, lane i the packet's ray i.
struct PacketBoxes {
    origin: [f32x16; 3],
    inv_dir: [f32x16; 3],
}

impl PacketBoxes {
    fn new(rays: &[Ray; PACKET_RAYS]) -> Self {
        let mut origin = [[0.0; PACKET_RAYS]; 3];
        let mut dir = [[0.0; PACKET_RAYS]; 3];
        for (lane, ray) in rays.iter().enumerate() {
            for axis in 0..3 {
                origin[axis][lane] = ray.origin[axis];
                dir[axis][lane] = ray.dir[axis];
            }
        }
        Self { origin: origin.map(f32x16::new), inv_dir: dir.map(|d| f32x16::ONE / f32x16::new(d)) }
    }

    /// The single-ray form of lane `lane`, of octant `octant` (the same inverse directions).
    #[inline]
    fn single(&self, lane: usize, octant: usize) -> RayBoxes {
        RayBoxes::from_parts(
            self.origin.map(|o| o.as_array()[lane]),
            self.inv_dir.map(|d| d.as_array()[lane]),
            octant,
        )
    }

    /// For every ray, the distance at which it enters child `slot` of `node` and, as a mask,
    /// whether it overlaps the box for some t in [0, its `t_max`]: [`RayBoxes::enter`] lane by
    /// lane, for rays of octant `OCTANT`.
    #[inline(always)]
    fn enter<const OCTANT: usize>(&self, node: &Node, slot: usize, t_max: f32x16) -> (f32x16, LaneMask) {
        let mut entry = f32x16::ZERO;
        let mut exit = f32x16::splat(f32::INFINITY);
        for axis in 0..3 {
            let near_row = 2 * axis + ((OCTANT >> axis) & 1);
            let near = (f32x16::splat(node.planes[near_row][slot]) - self.origin[axis]) * self.inv_dir[axis];
            let far =
                (f32x16::splat(node.planes[near_row ^ 1][slot]) - self.origin[axis]) * self.inv_dir[axis];
            entry = larger_unless_nan(near, entry);
            exit = smaller_unless_nan(far, exit);
        }
        let exit = smaller_unless_nan(exit * f32x16::splat(ROBUST_EXIT_SCALE), t_max);
        (entry, entry.simd_le(exit).to_bitmask())
    }
}

/// Bounds of the rays of one octant group of a packet, for a conservative test of all eight
/// children of a node at once before the exact 16-wide tests (the packet's "frustum", in the
/// spirit of the interval-arithmetic culling of I. Wald, S. Boulos, P. Shirley, "Ray Tracing
/// Deformable Scenes using Dynamic Bounding Volume Hierarchies", *ACM TOG* 26(1), 2007): the
/// smallest and largest origin and inverse direction on each axis over the group's rays, and
/// their largest `t_max`.
///
/// Every f32 operation of the slab test (`(plane − origin)·inv_dir`, the scaled exit) is
/// monotone in each operand, so the same operations on the bounds give a lower bound of every
/// ray's entry distance and an upper bound of its exit distance: a child whose bounds are
/// disjoint is entered by none of the rays, and the exact test of the others decides. Made only
/// where every inverse direction is finite, so that no bound is 0·∞.
struct PacketFrustum {
    origin_lo: [Lanes; 3],
    origin_hi: [Lanes; 3],
    inv_lo: [Lanes; 3],
    inv_hi: [Lanes; 3],
    t_max: Lanes,
}

impl PacketFrustum {
    /// The bounds of the rays `lanes` of `packet` with limits `t_max`; `None` where some inverse
    /// direction is infinite (a zero direction component) or NaN.
    fn new(packet: &PacketBoxes, lanes: LaneMask, t_max: &[f32; PACKET_RAYS]) -> Option<Self> {
        // In vector registers: lanes outside `lanes` are replaced by ±∞, then the sixteen
        // lanes are folded in halves.
        let taken =
            f32x16::new(std::array::from_fn(|lane| ((lanes >> lane) & 1) as f32)).simd_ne(f32x16::ZERO);
        let range = |values: f32x16| {
            let lo = taken.bitselect(values, f32x16::splat(f32::INFINITY));
            let hi = taken.bitselect(values, f32x16::splat(f32::NEG_INFINITY));
            (fold(lo, f32::min), fold(hi, f32::max))
        };
        let origin = packet.origin.map(range);
        let inv = packet.inv_dir.map(range);
        // `f32::min` and `max` skip NaN: a NaN inverse direction (never made from a ray) would
        // not show in the bounds, so it is ruled out here with the infinite ones.
        let finite = packet.inv_dir.iter().all(|d| d.is_finite().to_bitmask() & lanes == lanes);
        if !finite {
            return None;
        }
        let (_, t_max) = range(f32x16::new(*t_max));
        Some(Self {
            origin_lo: origin.map(|(lo, _)| Lanes::splat(lo)),
            origin_hi: origin.map(|(_, hi)| Lanes::splat(hi)),
            inv_lo: inv.map(|(lo, _)| Lanes::splat(lo)),
            inv_hi: inv.map(|(_, hi)| Lanes::splat(hi)),
            t_max: Lanes::splat(t_max),
        })
    }

    /// The children of `node` that some ray of the group may enter (bit i: child i), for rays
    /// of octant `OCTANT`: a superset of the union of their [`PacketBoxes::enter`] masks.
    #[inline(always)]
    fn children<const OCTANT: usize>(&self, node: &Node) -> LaneMask {
        let mut entry = Lanes::ZERO;
        let mut exit = Lanes::splat(f32::INFINITY);
        for axis in 0..3 {
            let negative = (OCTANT >> axis) & 1 == 1;
            let near_row = 2 * axis + usize::from(negative);
            let near = Lanes::new(node.planes[near_row]);
            let far = Lanes::new(node.planes[near_row ^ 1]);
            // A positive inverse direction: the distance grows with `plane − origin`, so the
            // largest origin gives the smallest near distance and the smallest the largest far
            // one; a negative inverse direction the other way round. Then the smaller (larger)
            // of the products with the two inverse-direction bounds.
            let (near_offset, far_offset) = if negative {
                (near - self.origin_lo[axis], far - self.origin_hi[axis])
            } else {
                (near - self.origin_hi[axis], far - self.origin_lo[axis])
            };
            let near_t = (near_offset * self.inv_lo[axis]).fast_min(near_offset * self.inv_hi[axis]);
            let far_t = (far_offset * self.inv_lo[axis]).fast_max(far_offset * self.inv_hi[axis]);
            entry = super::larger_unless_nan(near_t, entry);
            exit = super::smaller_unless_nan(far_t, exit);
        }
        let exit = super::smaller_unless_nan(exit * Lanes::splat(ROBUST_EXIT_SCALE), self.t_max);
        entry.simd_le(exit).to_bitmask()
    }
}

/// A packet's [`PacketFrustum`], made on the first visit below the root, which many packets
/// never get past (`None` inside: no frustum can be made for these rays).
#[derive(Default)]
struct LazyFrustum(Option<Option<PacketFrustum>>);

impl LazyFrustum {
    /// The children of node `index` (`node`) to give the exact test: all of them at the root or
    /// without a frustum, else [`PacketFrustum::children`] of the frustum of the rays `lanes`
    /// of `packet` with limits `t_max`, made on first use.
    #[inline(always)]
    fn children<const OCTANT: usize>(
        &mut self,
        index: u32,
        node: &Node,
        packet: &PacketBoxes,
        lanes: LaneMask,
        t_max: &[f32; PACKET_RAYS],
    ) -> LaneMask {
        if index == 0 {
            return ALL_CHILDREN;
        }
        let frustum = self.0.get_or_insert_with(|| PacketFrustum::new(packet, lanes, t_max));
        frustum.as_ref().map_or(ALL_CHILDREN, |frustum| frustum.children::<OCTANT>(node))
    }
}

/// `combine` over the sixteen lanes of `values`, pairwise.
#[inline(always)]
fn fold(values: f32x16, combine: fn(f32, f32) -> f32) -> f32 {
    let mut lanes = values.to_array();
    let mut width = PACKET_RAYS / 2;
    while width > 0 {
        for lane in 0..width {
            lanes[lane] = combine(lanes[lane], lanes[lane + width]);
        }
        width /= 2;
    }
    lanes[0]
}

/// Lane-wise `candidate > running ? candidate : running` (`running` where `candidate` is NaN),
/// as [`super::larger_unless_nan`].
#[inline(always)]
fn larger_unless_nan(candidate: f32x16, running: f32x16) -> f32x16 {
    // On x86-64, `fast_max` is `maxps` (or its AVX forms), which returns the second operand when
    // either is NaN; elsewhere a compare and select.
    #[cfg(target_arch = "x86_64")]
    {
        candidate.fast_max(running)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        candidate.simd_gt(running).blend(candidate, running)
    }
}

/// Lane-wise `candidate < running ? candidate : running` (`running` where `candidate` is NaN).
#[inline(always)]
fn smaller_unless_nan(candidate: f32x16, running: f32x16) -> f32x16 {
    #[cfg(target_arch = "x86_64")]
    {
        candidate.fast_min(running)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        candidate.simd_lt(running).blend(candidate, running)
    }
}

/// A child for a subset of a packet's rays.
#[derive(Clone, Copy, Debug)]
struct PacketPending {
    /// Node index, or first leaf position (see [`Pending`]).
    child: u32,
    /// 0 for a node, else the leaf's count.
    count: u32,
    /// The rays that entered it.
    lanes: LaneMask,
}

impl PacketPending {
    /// The same child as a single ray's pending visit.
    #[inline]
    fn single(self) -> Pending {
        Pending { child: self.child, count: self.count, entry: 0.0 }
    }
}

/// The packet traversal's stack: children with their rays and, for nearest-hit traversal, the
/// rays' entry distances (`E` = [`f32x16`]; `()` for any-hit). Left uninitialised, as
/// [`super::Stack`].
struct PacketStack<E: Copy> {
    entries: [MaybeUninit<(PacketPending, E)>; STACK_SIZE],
    len: usize,
}

impl<E: Copy> PacketStack<E> {
    #[inline]
    fn new() -> Self {
        Self { entries: [const { MaybeUninit::uninit() }; STACK_SIZE], len: 0 }
    }

    /// Panics (index out of bounds) if the stack is full, which the depth cap rules out: a
    /// visit pushes at most `WIDTH − 1` children, as in the single-ray traversal.
    #[inline]
    fn push(&mut self, pending: PacketPending, extra: E) {
        self.entries[self.len] = MaybeUninit::new((pending, extra));
        self.len += 1;
    }

    #[inline]
    fn pop(&mut self) -> Option<(PacketPending, E)> {
        self.len = self.len.checked_sub(1)?;
        // SAFETY: entries[..len] were all written by `push` (len only grows there), and
        // entries[len] is below the old length.
        Some(unsafe { self.entries[self.len].assume_init() })
    }
}

/// The rays `lanes` (bit i: `rays[i]`; lanes beyond [`PACKET_RAYS`] ignored) grouped by
/// direction octant (bit a: negative along axis a, as [`RayBoxes`]): each group's lanes and
/// its octant, in the order of the groups' lowest lanes.
#[inline]
fn octant_groups(rays: &[Ray; PACKET_RAYS], lanes: u32) -> impl Iterator<Item = (LaneMask, usize)> {
    let octants: [usize; PACKET_RAYS] =
        std::array::from_fn(|lane| rays[lane].dir.is_negative_bitmask() as usize & 7);
    let mut remaining = lanes & ((1 << PACKET_RAYS) - 1);
    std::iter::from_fn(move || {
        (remaining != 0).then(|| {
            let octant = octants[remaining.trailing_zeros() as usize];
            let group =
                each_lane(remaining).filter(|&lane| octants[lane] == octant).fold(0, |m, lane| m | 1 << lane);
            remaining &= !group;
            (group, octant)
        })
    })
}

/// The lanes of a mask, lowest first.
#[inline]
fn each_lane(mut lanes: LaneMask) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (lanes != 0).then(|| {
            let lane = lanes.trailing_zeros() as usize;
            lanes &= lanes - 1;
            lane
        })
    })
}

impl Bvh {
    /// The rays among `lanes` (bit i: `rays[i]`) that gain from traversing together: those
    /// whose direction octant is shared by at least `PACKET_MIN_RAYS` (8) of them. The others
    /// are better traced alone from the root ([`Self::closest_hit`], [`Self::any_hit`]):
    /// incoherent rays then pay nothing for being handed over in a packet.
    pub fn coherent_lanes(rays: &[Ray; PACKET_RAYS], lanes: u32) -> u32 {
        octant_groups(rays, lanes)
            .filter(|(group, _)| group.count_ones() >= PACKET_MIN_RAYS)
            .fold(0, |coherent, (group, _)| coherent | group)
    }

    /// Nearest-hit traversal of a packet: for every ray `rays[i]` with bit i of `lanes` set,
    /// what [`Self::closest_hit`] does for it alone with `t_max[i]`, calling
    /// `intersect(i, first, count, t_max)` for its leaves; `t_max[i]` becomes the distance of
    /// its nearest hit. Returns the mask of the rays that hit something. Lanes outside `lanes`
    /// are ignored (their rays need not be valid).
    pub fn closest_hit_packet(
        &self,
        rays: &[Ray; PACKET_RAYS],
        lanes: u32,
        t_max: &mut [f32; PACKET_RAYS],
        mut intersect: impl FnMut(usize, u32, u32, f32) -> Option<f32>,
    ) -> u32 {
        if self.nodes.is_empty() || lanes & ((1 << PACKET_RAYS) - 1) == 0 {
            return 0;
        }
        let packet = PacketBoxes::new(rays);
        let mut found = 0;
        for (group, octant) in octant_groups(rays, lanes) {
            let f = &mut intersect;
            found |= by_octant!(octant, O => self.closest_packet_in::<O>(&packet, group, t_max, f));
        }
        found
    }

    /// Any-hit traversal of a packet: the mask of the rays `rays[i]` (bit i of `lanes` set)
    /// for which [`Self::any_hit`] with `t_max[i]` would return true, calling
    /// `intersect(i, first, count, t_max)` for their leaves; a ray stops at its first hit.
    pub fn any_hit_packet(
        &self,
        rays: &[Ray; PACKET_RAYS],
        lanes: u32,
        t_max: &[f32; PACKET_RAYS],
        mut intersect: impl FnMut(usize, u32, u32, f32) -> bool,
    ) -> u32 {
        if self.nodes.is_empty() || lanes & ((1 << PACKET_RAYS) - 1) == 0 {
            return 0;
        }
        let packet = PacketBoxes::new(rays);
        let mut occluded = 0;
        for (group, octant) in octant_groups(rays, lanes) {
            let f = &mut intersect;
            occluded |= by_octant!(octant, O => self.any_packet_in::<O>(&packet, group, t_max, f));
        }
        occluded
    }

    /// [`Self::closest_hit_packet`] for the rays `lanes`, all of direction octant `OCTANT`.
    #[inline(always)]
    fn closest_packet_in<const OCTANT: usize>(
        &self,
        packet: &PacketBoxes,
        lanes: LaneMask,
        t_max: &mut [f32; PACKET_RAYS],
        intersect: &mut impl FnMut(usize, u32, u32, f32) -> Option<f32>,
    ) -> LaneMask {
        let mut frustum = LazyFrustum::default();
        let mut stack = PacketStack::<f32x16>::new();
        let mut current = PacketPending { child: 0, count: 0, lanes };
        let mut found = 0;
        loop {
            if current.lanes.count_ones() <= SINGLE_RAYS_MAX || current.count > 0 {
                // A thin packet, or a leaf: each ray on its own.
                for lane in each_lane(current.lanes) {
                    let boxes = packet.single(lane, OCTANT);
                    let leaf = &mut |first, count, t| intersect(lane, first, count, t);
                    if let Some(t) = self.closest_in::<OCTANT>(&boxes, current.single(), t_max[lane], leaf) {
                        t_max[lane] = t;
                        found |= 1 << lane;
                    }
                }
            } else {
                let node = &self.nodes[current.child as usize];
                let limit = f32x16::new(*t_max);
                // The children entered by some ray, with their rays' entry distances; ordered
                // (by index, so that the 64-byte distance vectors stay in place) by the entry
                // distance of their first ray: nearest first for the packet's lowest ray.
                let mut entries = [f32x16::ZERO; WIDTH];
                let mut children = [PacketPending { child: 0, count: 0, lanes: 0 }; WIDTH];
                let mut keys = [0.0f32; WIDTH];
                let mut order = [0u8; WIDTH];
                let mut hit_count = 0;
                let maybe = frustum.children::<OCTANT>(current.child, node, packet, lanes, t_max);
                for slot in each_lane(maybe) {
                    let (entry, entered) = packet.enter::<OCTANT>(node, slot, limit);
                    let entered = entered & current.lanes;
                    if entered == 0 {
                        continue;
                    }
                    let key = entry.as_array()[entered.trailing_zeros() as usize];
                    (entries[slot], keys[slot]) = (entry, key);
                    children[slot] =
                        PacketPending { child: node.child[slot], count: node.count[slot], lanes: entered };
                    let mut i = hit_count;
                    while i > 0 && keys[order[i - 1] as usize] > key {
                        order[i] = order[i - 1];
                        i -= 1;
                    }
                    order[i] = slot as u8;
                    hit_count += 1;
                }
                if hit_count > 0 {
                    for &slot in order[1..hit_count].iter().rev() {
                        let far = children[slot as usize];
                        self.prefetch(far.single());
                        stack.push(far, entries[slot as usize]);
                    }
                    current = children[order[0] as usize];
                    continue;
                }
            }
            // Next pending child that one of its rays still needs, with only those rays.
            loop {
                let Some((pending, entry)) = stack.pop() else {
                    return found;
                };
                let needed = pending.lanes & entry.simd_le(f32x16::new(*t_max)).to_bitmask();
                if needed != 0 {
                    current = PacketPending { lanes: needed, ..pending };
                    break;
                }
            }
        }
    }

    /// [`Self::any_hit_packet`] for the rays `lanes`, all of direction octant `OCTANT`.
    #[inline(always)]
    fn any_packet_in<const OCTANT: usize>(
        &self,
        packet: &PacketBoxes,
        lanes: LaneMask,
        t_max: &[f32; PACKET_RAYS],
        intersect: &mut impl FnMut(usize, u32, u32, f32) -> bool,
    ) -> LaneMask {
        let limit = f32x16::new(*t_max);
        let mut frustum = LazyFrustum::default();
        let mut stack = PacketStack::<()>::new();
        let mut current = PacketPending { child: 0, count: 0, lanes };
        // Rays not yet known to be occluded.
        let mut open = lanes;
        loop {
            if current.lanes.count_ones() <= SINGLE_RAYS_MAX || current.count > 0 {
                for lane in each_lane(current.lanes) {
                    let boxes = packet.single(lane, OCTANT);
                    let leaf = &mut |first, count, t| intersect(lane, first, count, t);
                    if self.any_in::<OCTANT>(&boxes, current.single(), t_max[lane], leaf) {
                        open &= !(1 << lane);
                    }
                }
                if open == 0 {
                    return lanes;
                }
            } else {
                let node = &self.nodes[current.child as usize];
                let maybe = frustum.children::<OCTANT>(current.child, node, packet, lanes, t_max);
                let mut first = None;
                for slot in each_lane(maybe) {
                    let entered = packet.enter::<OCTANT>(node, slot, limit).1 & current.lanes;
                    if entered == 0 {
                        continue;
                    }
                    let pending =
                        PacketPending { child: node.child[slot], count: node.count[slot], lanes: entered };
                    if first.is_none() {
                        first = Some(pending);
                    } else {
                        self.prefetch(pending.single());
                        stack.push(pending, ());
                    }
                }
                if let Some(first) = first {
                    current = first;
                    continue;
                }
            }
            // Next pending child with rays still open.
            loop {
                let Some((pending, ())) = stack.pop() else {
                    return lanes & !open;
                };
                let needed = pending.lanes & open;
                if needed != 0 {
                    current = PacketPending { lanes: needed, ..pending };
                    break;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::super::tests::random_boxes;
    use super::super::BvhPrimitive;
    use super::*;
    use crate::geometry::test_util::Rng;
    use crate::geometry::Aabb;

    /// The distance at which `ray` enters `bounds` (0 from inside), in f64, if it does so
    /// for some t in [0, `t_max`): the boxes themselves are the "primitives" here.
    fn box_hit(ray: &Ray, bounds: &Aabb, t_max: f32) -> Option<f32> {
        let (mut entry, mut exit) = (0.0f64, f64::from(t_max));
        for axis in 0..3 {
            let (o, d) = (f64::from(ray.origin[axis]), f64::from(ray.dir[axis]));
            let (lo, hi) = (f64::from(bounds.min[axis]), f64::from(bounds.max[axis]));
            if d == 0.0 {
                if o < lo || o > hi {
                    return None;
                }
                continue;
            }
            let (a, b) = ((lo - o) / d, (hi - o) / d);
            entry = entry.max(a.min(b));
            exit = exit.min(a.max(b));
        }
        (entry <= exit).then_some(entry as f32)
    }

    /// Sixteen rays of each kind the packet traversal must handle: a narrow fan from one
    /// origin (one octant: shared node visits all the way down), a wide fan whose z component
    /// changes sign (two octant groups), rays in random directions (thin groups at once), and
    /// axis-parallel rays that graze box faces (the slab test's 0 × ∞ = NaN case).
    fn packets(rng: &mut Rng, primitives: &[BvhPrimitive]) -> Vec<[Ray; PACKET_RAYS]> {
        let mut packets = Vec::new();
        for _ in 0..200 {
            let origin = rng.point_in(Vec3::splat(-150.0), Vec3::splat(150.0));
            let target = rng.point_in(Vec3::splat(-60.0), Vec3::splat(60.0));
            let axis = (target - origin).normalize();
            packets.push(std::array::from_fn(|_| {
                Ray::new(origin, (axis + 0.02 * rng.unit_vector()).normalize())
            }));
            let level = Vec3::new(axis.x, axis.y, 0.0).normalize();
            packets.push(std::array::from_fn(|_| {
                Ray::new(origin, (level + 0.3 * rng.unit_vector()).normalize())
            }));
            packets.push(std::array::from_fn(|_| {
                Ray::new(rng.point_in(Vec3::splat(-150.0), Vec3::splat(150.0)), rng.unit_vector())
            }));
            // Along ±x in the plane of a box's front or back face (z constant), across the face.
            let face = primitives
                [(rng.uniform(0.0, primitives.len() as f32) as usize).min(primitives.len() - 1)]
            .bounds;
            let z = if rng.uniform(0.0, 1.0) < 0.5 { face.min.z } else { face.max.z };
            packets.push(std::array::from_fn(|lane| {
                let (start, dir) = if lane % 2 == 0 { (-150.0, Vec3::X) } else { (150.0, Vec3::NEG_X) };
                Ray::new(Vec3::new(start, rng.uniform(face.min.y, face.max.y), z), dir)
            }));
        }
        packets
    }

    #[test]
    fn frustum_keeps_every_child_a_ray_enters_and_culls_others() {
        // Every node of a tree over 5000 boxes against the octant groups of 800 packets (with
        // per-lane t_max): the frustum's children include every child that one of the group's
        // rays enters by the exact 16-wide test, and leave out most of the others for the
        // narrow fans (or the test would not see a frustum that culls nothing).
        let mut rng = Rng::new(78);
        let primitives = random_boxes(&mut rng, 5_000);
        let (bvh, _) = Bvh::build(primitives.clone());
        let (mut culled, mut missed_by_all) = (0u32, 0u32);
        for rays in packets(&mut rng, &primitives) {
            let limits: [f32; PACKET_RAYS] = std::array::from_fn(|_| {
                if rng.uniform(0.0, 1.0) < 0.5 {
                    f32::INFINITY
                } else {
                    rng.uniform(1.0, 300.0)
                }
            });
            let boxes = PacketBoxes::new(&rays);
            let limit = f32x16::new(limits);
            for (group, octant) in octant_groups(&rays, 0xffff) {
                let Some(frustum) = PacketFrustum::new(&boxes, group, &limits) else {
                    continue;
                };
                for node in &bvh.nodes {
                    let (entered, maybe) = by_octant!(octant, O => (
                        (0..WIDTH)
                            .filter(|&slot| boxes.enter::<O>(node, slot, limit).1 & group != 0)
                            .fold(0, |mask, slot| mask | 1 << slot),
                        frustum.children::<O>(node),
                    ));
                    assert_eq!(entered & !maybe, 0, "frustum {maybe:#b} drops children {entered:#b}");
                    missed_by_all += (ALL_CHILDREN & !entered).count_ones();
                    culled += (ALL_CHILDREN & !maybe).count_ones();
                }
            }
        }
        assert!(culled * 2 > missed_by_all, "culled {culled} of {missed_by_all} children no ray enters");
    }

    #[test]
    fn packets_find_what_their_rays_find_alone() {
        // Nearest and any hits of 800 packets over 5000 boxes, each lane against the single-ray
        // traversal with the same leaf test: same rays hit, at the same distances, for random
        // subsets of the lanes and per-lane t_max (some infinite).
        let mut rng = Rng::new(77);
        let primitives = random_boxes(&mut rng, 5_000);
        let (bvh, ids) = Bvh::build(primitives.clone());
        let bounds_at = |position: u32| &primitives[ids[position as usize] as usize].bounds;
        let leaf_nearest = |ray: &Ray, first: u32, count: u32, mut t_max: f32| {
            let mut found = None;
            for position in first..first + count {
                if let Some(t) = box_hit(ray, bounds_at(position), t_max) {
                    (t_max, found) = (t, Some(t));
                }
            }
            found
        };
        let leaf_any = |ray: &Ray, first: u32, count: u32, t_max: f32| {
            (first..first + count).any(|position| box_hit(ray, bounds_at(position), t_max).is_some())
        };
        let (mut hits, mut shared) = (0, 0);
        for rays in packets(&mut rng, &primitives) {
            let lanes = if rng.uniform(0.0, 1.0) < 0.5 { 0xffff } else { rng.uniform(1.0, 65536.0) as u32 };
            let limits: [f32; PACKET_RAYS] = std::array::from_fn(|_| {
                if rng.uniform(0.0, 1.0) < 0.5 {
                    f32::INFINITY
                } else {
                    rng.uniform(1.0, 300.0)
                }
            });
            let mut nearest = limits;
            let found = bvh.closest_hit_packet(&rays, lanes, &mut nearest, |lane, first, count, t_max| {
                leaf_nearest(&rays[lane], first, count, t_max)
            });
            let occluded = bvh.any_hit_packet(&rays, lanes, &limits, |lane, first, count, t_max| {
                leaf_any(&rays[lane], first, count, t_max)
            });
            shared += Bvh::coherent_lanes(&rays, lanes).count_ones();
            for lane in 0..PACKET_RAYS {
                let bit = 1 << lane;
                if lanes & bit == 0 {
                    assert_eq!((found & bit, occluded & bit), (0, 0), "lane {lane} was not asked for");
                    continue;
                }
                let ray = &rays[lane];
                let mut alone = limits[lane];
                let alone_found = bvh.closest_hit(ray, limits[lane], |first, count, t_max| {
                    let t = leaf_nearest(ray, first, count, t_max);
                    alone = t.unwrap_or(alone);
                    t
                });
                assert_eq!(found & bit != 0, alone_found, "{ray:?}, t_max {}", limits[lane]);
                if alone_found {
                    assert_eq!(nearest[lane], alone, "{ray:?}");
                    hits += 1;
                }
                let alone_any =
                    bvh.any_hit(ray, limits[lane], |first, count, t_max| leaf_any(ray, first, count, t_max));
                assert_eq!(occluded & bit != 0, alone_any, "{ray:?}, t_max {}", limits[lane]);
                assert_eq!(alone_any, alone_found);
            }
        }
        // The rays hit often enough, and many of them traverse in shared packets.
        assert!(hits > 2_000, "{hits} hits");
        assert!(shared > 3_000, "{shared} rays in coherent groups");
    }

    #[test]
    fn empty_trees_and_empty_packets_find_nothing() {
        let rays = [Ray::new(Vec3::ZERO, Vec3::X); PACKET_RAYS];
        let mut t_max = [f32::INFINITY; PACKET_RAYS];
        let never = |_: usize, _: u32, _: u32, _: f32| -> Option<f32> { panic!("no leaf to test") };
        assert_eq!(Bvh::default().closest_hit_packet(&rays, 0xffff, &mut t_max, never), 0);
        let mut rng = Rng::new(3);
        let (bvh, _) = Bvh::build(random_boxes(&mut rng, 100));
        assert_eq!(bvh.closest_hit_packet(&rays, 0, &mut t_max, never), 0);
        assert_eq!(bvh.any_hit_packet(&rays, 0, &t_max, |_, _, _, _| panic!("no leaf to test")), 0);
        assert_eq!(t_max, [f32::INFINITY; PACKET_RAYS]);
    }
}
