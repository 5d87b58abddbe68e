//! Several triangles tested against one ray at once: [`test_triangles`], the lanes' form of
//! [`intersect_triangle`] shared by the 4-wide packets of a BVH leaf (`super::packet`, glam's
//! `Vec4`) and the 16-wide quad halves of a small scene (`super::quad_lanes`, `wide::f32x16`).
//!
//! Lane by lane it evaluates the same f32 operations in the same order as
//! [`intersect_triangle`] (translation, shear, edge functions, determinant, scaled distance and
//! its range check, then the division and the distance's error bound), so it rejects exactly
//! the triangles the scalar test rejects and returns, bit for bit, the hits it returns. The lanes
//! it cannot decide (an edge function that rounds to exactly 0, which the scalar test recomputes
//! in f64) are left to [`intersect_triangle`] itself; watertightness and the conservative
//! distance bound are therefore the scalar test's. Lanes holding NaN coordinates fail every
//! comparison and are never hit. The division and the error bound are computed only when some
//! lane passed the range check, which most tests a ray makes do not.

use std::ops::{BitAnd, BitOr, Div, Not, Sub};

use glam::{BVec4A, Vec4};
use wide::f32x16;

use super::triangle::{distance_error_bound, BoundLanes, ShearedRay, TriangleHit};

#[cfg(doc)]
use super::triangle::intersect_triangle;

/// Several f32 lanes with their comparisons, for [`test_triangles`].
pub(crate) trait TriangleLanes: BoundLanes + Sub<Output = Self> + Div<Output = Self> {
    /// A lane mask, as the comparisons return it.
    type Mask: Copy + BitAnd<Output = Self::Mask> + BitOr<Output = Self::Mask> + Not<Output = Self::Mask>;
    /// Lane-wise `==` (false for NaN).
    fn cmp_eq(self, other: Self) -> Self::Mask;
    /// Lane-wise `!=` (true for NaN).
    fn cmp_ne(self, other: Self) -> Self::Mask;
    /// Lane-wise `<` (false for NaN).
    fn cmp_lt(self, other: Self) -> Self::Mask;
    /// Lane-wise `>` (false for NaN).
    fn cmp_gt(self, other: Self) -> Self::Mask;
    /// Bit `i` set where lane `i` of `mask` is true.
    fn bitmask(mask: Self::Mask) -> u32;
    /// Lane `lane`'s value.
    fn lane(&self, lane: usize) -> f32;
}

impl TriangleLanes for Vec4 {
    type Mask = BVec4A;
    #[inline(always)]
    fn cmp_eq(self, other: Self) -> BVec4A {
        self.cmpeq(other)
    }
    #[inline(always)]
    fn cmp_ne(self, other: Self) -> BVec4A {
        self.cmpne(other)
    }
    #[inline(always)]
    fn cmp_lt(self, other: Self) -> BVec4A {
        self.cmplt(other)
    }
    #[inline(always)]
    fn cmp_gt(self, other: Self) -> BVec4A {
        self.cmpgt(other)
    }
    #[inline(always)]
    fn bitmask(mask: BVec4A) -> u32 {
        mask.bitmask()
    }
    #[inline(always)]
    fn lane(&self, lane: usize) -> f32 {
        self[lane]
    }
}

impl TriangleLanes for f32x16 {
    type Mask = f32x16;
    #[inline(always)]
    fn cmp_eq(self, other: Self) -> f32x16 {
        self.simd_eq(other)
    }
    #[inline(always)]
    fn cmp_ne(self, other: Self) -> f32x16 {
        self.simd_ne(other)
    }
    #[inline(always)]
    fn cmp_lt(self, other: Self) -> f32x16 {
        self.simd_lt(other)
    }
    #[inline(always)]
    fn cmp_gt(self, other: Self) -> f32x16 {
        self.simd_gt(other)
    }
    #[inline(always)]
    fn bitmask(mask: f32x16) -> u32 {
        mask.to_bitmask()
    }
    #[inline(always)]
    fn lane(&self, lane: usize) -> f32 {
        self.as_array()[lane]
    }
}

/// What [`test_triangles`] decided for one ray.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LanesTest<T> {
    /// Lanes that only [`intersect_triangle`] can decide (an edge function rounded to 0).
    pub(crate) undecided: u32,
    /// Lanes that [`intersect_triangle`] hits, with the hit of [`Self::hit`].
    pub(crate) hits: u32,
    t: T,
    barycentric: [T; 3],
}

impl<T: TriangleLanes> LanesTest<T> {
    /// The hit on lane `lane` (one of [`Self::hits`]): bit for bit what [`intersect_triangle`]
    /// returns.
    #[inline]
    pub(crate) fn hit(&self, lane: usize) -> TriangleHit {
        TriangleHit { t: self.t.lane(lane), barycentric: self.barycentric.map(|b| b.lane(lane)) }
    }

    /// The hits among the lanes nearer and nearer, in lane order, for a test made at
    /// `tested_limit`: `found(lane, hit)` for each lane hit closer than the lanes before it (the
    /// first of equal distances stays). A lane the test hit keeps its hit while the limit it was
    /// tested against stands; after a closer hit, `exact(lane, limit)` (the scalar test of that
    /// lane) decides at the new limit, as it would lane by lane (a lane missed at a limit is
    /// missed at every smaller one: each check is monotone in the limit). Returns the last limit.
    #[inline(always)]
    pub(crate) fn nearer(
        &self,
        tested_limit: f32,
        mut exact: impl FnMut(usize, f32) -> Option<TriangleHit>,
        mut found: impl FnMut(usize, TriangleHit),
    ) -> f32 {
        let mut t_limit = tested_limit;
        let mut candidates = self.hits | self.undecided;
        while candidates != 0 {
            let lane = candidates.trailing_zeros() as usize;
            candidates &= candidates - 1;
            let hit = if self.hits & (1 << lane) != 0 && t_limit == tested_limit {
                Some(self.hit(lane))
            } else {
                exact(lane, t_limit)
            };
            if let Some(hit) = hit {
                t_limit = hit.t;
                found(lane, hit);
            }
        }
        t_limit
    }

    /// Whether some lane is hit: one the test decided, or an undecided one that `exact` (the
    /// scalar test of that lane) hits.
    #[inline(always)]
    pub(crate) fn any(&self, mut exact: impl FnMut(usize) -> bool) -> bool {
        if self.hits != 0 {
            return true;
        }
        let mut undecided = self.undecided;
        while undecided != 0 {
            let lane = undecided.trailing_zeros() as usize;
            undecided &= undecided - 1;
            if exact(lane) {
                return true;
            }
        }
        false
    }
}

/// The test of the triangles in `rows` (rows 0–2: x, y, z of each lane's first vertex, 3–5 of
/// its second, 6–8 of its third) against `ray` for hits with t in (0, `t_max`), for the lanes in
/// `used`: the lanes that [`intersect_triangle`] hits, with their hits, and the lanes only it can
/// decide; it surely misses every other lane (module notes). Each line repeats the operation of
/// [`intersect_triangle`] it is named after, with the same operands in the same order.
#[inline(always)]
pub(crate) fn test_triangles<T: TriangleLanes>(
    rows: &[T; 9],
    used: u32,
    ray: &ShearedRay,
    t_max: f32,
) -> LanesTest<T> {
    let ([kx, ky, kz], origin, shear) = ray.parts();
    // Always true (the axes are a permutation of 0, 1, 2); stated so that the row indices
    // below need no bounds checks.
    assert!(kx < 3 && ky < 3 && kz < 3);
    let [origin_x, origin_y, origin_z] = origin.map(T::splat);
    let [shear_x, shear_y, shear_z] = shear.map(T::splat);
    // `relative`: the sheared 2D position (x, y) and the translated z of each vertex.
    let relative = |vertex: usize| {
        let z = rows[3 * vertex + kz] - origin_z;
        (
            (rows[3 * vertex + kx] - origin_x) + shear_x * z,
            (rows[3 * vertex + ky] - origin_y) + shear_y * z,
            z,
        )
    };
    let (ax, ay, a_z) = relative(0);
    let (bx, by, b_z) = relative(1);
    let (cx, cy, c_z) = relative(2);
    // edge_function(c, b), edge_function(a, c), edge_function(b, a).
    let e0 = cx * by - cy * bx;
    let e1 = ax * cy - ay * cx;
    let e2 = bx * ay - by * ax;
    let zero = T::splat(0.0);
    let any_zero = e0.cmp_eq(zero) | e1.cmp_eq(zero) | e2.cmp_eq(zero);
    let any_negative = e0.cmp_lt(zero) | e1.cmp_lt(zero) | e2.cmp_lt(zero);
    let any_positive = e0.cmp_gt(zero) | e1.cmp_gt(zero) | e2.cmp_gt(zero);
    let det = e0 + e1 + e2;
    let z = [shear_z * a_z, shear_z * b_z, shear_z * c_z];
    let t_scaled = e0 * z[0] + e1 * z[1] + e2 * z[2];
    let limit = T::splat(t_max) * det;
    let positive = det.cmp_gt(zero);
    let in_range_positive = positive & t_scaled.cmp_gt(zero) & t_scaled.cmp_lt(limit);
    let in_range_negative = !positive & t_scaled.cmp_lt(zero) & t_scaled.cmp_gt(limit);
    let in_range = in_range_positive | in_range_negative;
    let decided = !(any_negative & any_positive) & det.cmp_ne(zero) & in_range;
    // Lanes with an edge function of exactly 0 go to the scalar test, which recomputes it in
    // f64; the others are decided here. (NaN lanes compare false everywhere.)
    let undecided = T::bitmask(any_zero) & used;
    let passed = T::bitmask(decided & !any_zero) & used;
    let mut test = LanesTest { undecided, hits: 0, t: zero, barycentric: [zero; 3] };
    if passed == 0 {
        return test;
    }
    // The rest of `intersect_triangle` for the lanes that passed: the division, and the
    // distance against t_max and its error bound.
    let inv_det = T::splat(1.0) / det;
    let t = t_scaled * inv_det;
    let bound = distance_error_bound(&[(ax, ay), (bx, by), (cx, cy)], &z, &[e0, e1, e2], inv_det);
    let accepted = t.cmp_lt(T::splat(t_max)) & t.cmp_gt(bound);
    test.hits = passed & T::bitmask(accepted);
    test.t = t;
    test.barycentric = [e0 * inv_det, e1 * inv_det, e2 * inv_det];
    test
}
