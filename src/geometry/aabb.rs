//! Axis-aligned bounding boxes and the robust ray–box (slab) test used by the BVH.
//!
//! The slab test is the one of Kay & Kajiya (1986) with the conservative bound of T. Ize,
//! "Robust BVH Ray Traversal", *JCGT* 2(2), 2013: the exit distance is enlarged by 1 + 2·γ(3) so
//! that rounding in `(bound − origin)·(1/dir)` can never make a ray miss a box that contains the
//! primitive it hits. Direction components equal to ±0 give infinite inverse components; the one
//! indeterminate case, 0·∞ (origin exactly on a slab plane of a ray parallel to it), counts as
//! inside, which is the conservative answer.

use glam::{BVec3A, Vec3, Vec3A};

use super::rounding::gamma;
use super::Ray;

/// A box `[min, max]` (scene units). The empty box has `min = +∞`, `max = −∞`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box: the identity of [`Self::union`].
    pub const EMPTY: Aabb = Aabb { min: Vec3::INFINITY, max: Vec3::NEG_INFINITY };

    /// The smallest box containing all `points` ([`Self::EMPTY`] for none).
    pub fn from_points(points: &[Vec3]) -> Aabb {
        points.iter().fold(Aabb::EMPTY, |bounds, &p| bounds.grown(p))
    }

    /// This box grown to contain `point`.
    #[inline]
    pub fn grown(self, point: Vec3) -> Aabb {
        Aabb { min: self.min.min(point), max: self.max.max(point) }
    }

    /// The smallest box containing both boxes.
    #[inline]
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    /// The centre of the box.
    #[inline]
    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Surface area (scene units²); 0 for the empty box and for a point.
    #[inline]
    pub fn surface_area(&self) -> f32 {
        let size = (self.max - self.min).max(Vec3::ZERO);
        2.0 * (size.x * size.y + size.y * size.z + size.z * size.x)
    }

    /// True when `other` lies inside this box (boundaries included).
    pub fn contains(&self, other: &Aabb) -> bool {
        self.min.cmple(other.min).all() && self.max.cmpge(other.max).all()
    }

    /// The distance at which `ray` enters the box, clamped to 0 when it starts inside, if it
    /// overlaps the box for some t in [0, `t_max`]. Conservative: may report a box the ray just
    /// misses, never misses a box the ray enters.
    #[inline]
    pub fn entry_distance(&self, ray: &BoxRay, t_max: f32) -> Option<f32> {
        let t_min_plane = (Vec3A::from(self.min) - ray.origin) * ray.inv_dir;
        let t_max_plane = (Vec3A::from(self.max) - ray.origin) * ray.inv_dir;
        // 0·∞ = NaN: the ray runs inside a slab plane; the slab then constrains nothing.
        let indeterminate: BVec3A = t_min_plane.is_nan_mask() | t_max_plane.is_nan_mask();
        let t_near = Vec3A::select(indeterminate, Vec3A::NEG_INFINITY, t_min_plane.min(t_max_plane));
        let t_far = Vec3A::select(indeterminate, Vec3A::INFINITY, t_min_plane.max(t_max_plane));
        let enter = t_near.max_element().max(0.0);
        let exit = (t_far.min_element() * ROBUST_EXIT_SCALE).min(t_max);
        (enter <= exit).then_some(enter)
    }
}

/// Ize (2013), §3: the rounding of `(bound − origin)·inv_dir` and of `inv_dir = 1/dir` moves a
/// slab distance by at most a relative γ(3) each way, so scaling the exit by 1 + 2γ(3) keeps the
/// computed interval a superset of the true one.
const ROBUST_EXIT_SCALE: f32 = 1.0 + 2.0 * gamma(3);

/// A ray prepared for many box tests: its origin and the componentwise inverse of its direction
/// (±∞ for zero components).
#[derive(Clone, Copy, Debug)]
pub struct BoxRay {
    origin: Vec3A,
    inv_dir: Vec3A,
}

impl BoxRay {
    /// Precomputes the inverse direction of `ray`.
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        Self { origin: ray.origin.into(), inv_dir: Vec3A::ONE / Vec3A::from(ray.dir) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Aabb {
        Aabb { min: Vec3::ZERO, max: Vec3::ONE }
    }

    fn box_ray(origin: Vec3, dir: Vec3) -> BoxRay {
        BoxRay::new(&Ray::new(origin, dir.normalize()))
    }

    #[test]
    fn union_area_and_centroid() {
        // [0,1]³ ∪ [2,3]×[0,1]² = [0,3]×[0,1]²: area 2·(3 + 1 + 3) = 14, centre (1.5, 0.5, 0.5).
        let other = Aabb { min: Vec3::new(2.0, 0.0, 0.0), max: Vec3::new(3.0, 1.0, 1.0) };
        let both = unit_box().union(other);
        assert_eq!(both.surface_area(), 14.0);
        assert_eq!(both.centroid(), Vec3::new(1.5, 0.5, 0.5));
        assert!(both.contains(&other) && !other.contains(&both));
        assert_eq!(Aabb::EMPTY.union(other), other);
        assert_eq!(Aabb::EMPTY.surface_area(), 0.0);
    }

    #[test]
    fn entry_distance_of_a_hit_and_a_miss() {
        // From x = −2 along +x through the middle of [0,1]³: enters at t = 2.
        let hit = unit_box().entry_distance(&box_ray(Vec3::new(-2.0, 0.5, 0.5), Vec3::X), 10.0);
        assert_eq!(hit, Some(2.0));
        // Same ray with t_max = 1.5 stops before the box.
        let short = unit_box().entry_distance(&box_ray(Vec3::new(-2.0, 0.5, 0.5), Vec3::X), 1.5);
        assert_eq!(short, None);
        // Passing above the box misses; a box behind the origin misses.
        let above = unit_box().entry_distance(&box_ray(Vec3::new(-2.0, 1.5, 0.5), Vec3::X), 10.0);
        assert_eq!(above, None);
        let behind = unit_box().entry_distance(&box_ray(Vec3::new(2.0, 0.5, 0.5), Vec3::X), 10.0);
        assert_eq!(behind, None);
        // From inside, the entry distance is clamped to 0.
        let inside = unit_box().entry_distance(&box_ray(Vec3::splat(0.5), Vec3::Y), 10.0);
        assert_eq!(inside, Some(0.0));
    }

    #[test]
    fn ray_in_a_slab_plane_counts_as_inside() {
        // Origin exactly on the face y = 0, travelling along +x (dir.y = 0): (0 − 0)·∞ is NaN;
        // the ray grazes the face, which the conservative test must report (entry at t = 1).
        let grazing = box_ray(Vec3::new(-1.0, 0.0, 0.5), Vec3::X);
        assert_eq!(unit_box().entry_distance(&grazing, 10.0), Some(1.0));
        // Same with a negative zero component and the face y = 1.
        let negative_zero = BoxRay::new(&Ray::new(Vec3::new(-1.0, 1.0, 0.5), Vec3::new(1.0, -0.0, 0.0)));
        assert_eq!(unit_box().entry_distance(&negative_zero, 10.0), Some(1.0));
        // A flat box (a quad's bounds, zero thickness in y) and a ray inside its plane.
        let flat = Aabb { min: Vec3::ZERO, max: Vec3::new(1.0, 0.0, 1.0) };
        assert_eq!(flat.entry_distance(&grazing, 10.0), Some(1.0));
        // Parallel to the slab but outside it: a miss.
        let outside = box_ray(Vec3::new(-1.0, 2.0, 0.5), Vec3::X);
        assert_eq!(unit_box().entry_distance(&outside, 10.0), None);
    }
}
