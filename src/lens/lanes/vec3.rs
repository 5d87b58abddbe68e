//! Three-vectors and masks over the wavelength lanes: one [`wide::f64x8`] per coordinate, with
//! glam's `DVec3` arithmetic operation for operation (the same products summed in the same
//! order, the same square roots and divisions), so that each lane is the scalar code's number to
//! the bit. No fused multiply-adds: Rust does not contract the scalar code's `a * b + c`, so
//! neither may this.

use glam::DVec3;
use wide::f64x8;

use crate::lens::trace::MAX_LANES;

// One `f64x8` holds a camera sample's lanes.
const _: () = assert!(MAX_LANES == 8);

/// A mask: every bit of a lane set (true) or clear (false), as `wide`'s comparisons give.
pub(super) type Mask = f64x8;

/// The mask of no lane.
pub(super) const NONE: Mask = f64x8::ZERO;

/// `mask` with the lanes of `off` cleared.
#[inline(always)]
pub(super) fn and_not(mask: Mask, off: Mask) -> Mask {
    off.select(NONE, mask)
}

/// The mask of the first `count` lanes.
#[inline]
pub(super) fn first_lanes(count: usize) -> Mask {
    f64x8::from([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]).simd_lt(f64x8::splat(count as f64))
}

/// Whether lane `lane` of `mask` is set.
#[inline]
pub(super) fn lane_set(mask: Mask, lane: usize) -> bool {
    mask.to_bitmask() & (1 << lane) != 0
}

/// A three-vector per lane.
#[derive(Clone, Copy, Debug)]
pub(super) struct V3 {
    pub x: f64x8,
    pub y: f64x8,
    pub z: f64x8,
}

impl V3 {
    /// `v` in every lane.
    #[inline]
    pub fn splat(v: DVec3) -> Self {
        Self { x: f64x8::splat(v.x), y: f64x8::splat(v.y), z: f64x8::splat(v.z) }
    }

    /// From one `DVec3` per lane.
    #[inline]
    pub fn from_lanes(v: &[DVec3; MAX_LANES]) -> Self {
        Self {
            x: f64x8::from(v.map(|v| v.x)),
            y: f64x8::from(v.map(|v| v.y)),
            z: f64x8::from(v.map(|v| v.z)),
        }
    }

    /// Every lane as a `DVec3`.
    #[inline]
    pub fn lanes(&self) -> [DVec3; MAX_LANES] {
        let (x, y, z) = (self.x.to_array(), self.y.to_array(), self.z.to_array());
        std::array::from_fn(|lane| DVec3::new(x[lane], y[lane], z[lane]))
    }

    /// `DVec3::dot`: (x·x′ + y·y′) + z·z′.
    #[inline(always)]
    pub fn dot(self, rhs: Self) -> f64x8 {
        self.x * rhs.x + self.y * rhs.y + self.z * rhs.z
    }

    /// `DVec3::cross`.
    #[inline(always)]
    pub fn cross(self, rhs: Self) -> Self {
        Self {
            x: self.y * rhs.z - rhs.y * self.z,
            y: self.z * rhs.x - rhs.z * self.x,
            z: self.x * rhs.y - rhs.x * self.y,
        }
    }

    /// Every coordinate times `k`.
    #[inline(always)]
    pub fn scaled(self, k: f64x8) -> Self {
        Self { x: self.x * k, y: self.y * k, z: self.z * k }
    }

    /// Every coordinate divided by `k` (`DVec3 / f64`).
    #[inline(always)]
    pub fn divided(self, k: f64x8) -> Self {
        Self { x: self.x / k, y: self.y / k, z: self.z / k }
    }

    /// The sum.
    #[inline(always)]
    pub fn plus(self, rhs: Self) -> Self {
        Self { x: self.x + rhs.x, y: self.y + rhs.y, z: self.z + rhs.z }
    }

    /// The negation (exact).
    #[inline(always)]
    pub fn neg(self) -> Self {
        Self { x: -self.x, y: -self.y, z: -self.z }
    }

    /// `DVec3::normalize`: times 1/√(v·v).
    #[inline(always)]
    pub fn normalize(self) -> Self {
        self.scaled(f64x8::ONE / self.dot(self).sqrt())
    }

    /// Whether every coordinate is finite, per lane.
    #[inline(always)]
    pub fn is_finite(self) -> Mask {
        self.x.is_finite() & self.y.is_finite() & self.z.is_finite()
    }

    /// `a` where `mask` is set, else `b`.
    #[inline(always)]
    pub fn select(mask: Mask, a: Self, b: Self) -> Self {
        Self { x: mask.select(a.x, b.x), y: mask.select(a.y, b.y), z: mask.select(a.z, b.z) }
    }
}
