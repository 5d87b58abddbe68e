//! Axis-aligned bounding boxes, the building blocks of the BVH (its robust ray–box test, 4 boxes
//! at a time, is in [`super::bvh`]).

use glam::Vec3;

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
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Aabb {
        Aabb { min: Vec3::ZERO, max: Vec3::ONE }
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
}
