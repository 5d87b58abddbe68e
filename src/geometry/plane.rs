//! [`Plane`]: an infinite plane, and its ray intersection.
//!
//! t = ((point − origin)·n) / (dir·n). The hit is rejected when the numerator is within its
//! rounding-error bound of 0 (the origin lies on the plane: a ray spawned from it must not
//! re-hit it) or the denominator is (the ray runs parallel to the plane to within rounding, so
//! even the side of the plane it would reach is unknown). The hit point is reprojected onto the
//! plane. Infinite planes have no bounding box; [`super::Geometry`] tests them outside the BVH.

use glam::Vec3;

use super::rounding::gamma;
use super::{Hit, Ray};

/// The infinite plane through `point` with unit `normal`; its outside is the side `normal` points to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point of the plane.
    pub point: Vec3,
    /// Unit normal.
    pub normal: Vec3,
}

impl Plane {
    /// The intersection with t in (0, `t_max`), from either side; `prim` is copied into the hit.
    /// The hit's normal is the plane's `normal`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32, prim: u32) -> Option<Hit> {
        self.distance(ray, t_max).map(|t| self.hit_at(ray, t, prim))
    }

    /// The distance t of [`Self::intersect`]'s hit, without its hit record (which
    /// [`Self::hit_at`] builds): a scene's nearest-hit search builds the record of the one plane
    /// that is nearest, after its other shapes have had their turn.
    #[inline(always)]
    pub fn distance(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        debug_assert!(
            (self.normal.length_squared() - 1.0).abs() < 1e-3,
            "plane normal not unit: {}",
            self.normal
        );
        let to_plane = self.point - ray.origin;
        let numerator = to_plane.dot(self.normal);
        let denominator = ray.dir.dot(self.normal);
        // One rounding for the difference and three for the dot product; three for dir·n.
        let error_numerator = gamma(4) * to_plane.abs().dot(self.normal.abs());
        let error_denominator = gamma(3) * ray.dir.abs().dot(self.normal.abs());
        if !(numerator.abs() > error_numerator && denominator.abs() > error_denominator) {
            return None;
        }
        let t = numerator / denominator;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        Some(t)
    }

    /// The hit record of `ray` meeting the plane at distance `t` (from [`Self::distance`]): the
    /// point reprojected onto the plane, the plane's normal, `prim`.
    #[inline(always)]
    pub fn hit_at(&self, ray: &Ray, t: f32, prim: u32) -> Hit {
        let on_ray = ray.at(t);
        let point = on_ray - (on_ray - self.point).dot(self.normal) * self.normal;
        Hit { t, point, normal: self.normal, shading_normal: self.normal, prim }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::spawn_origin;
    use crate::geometry::test_util::Rng;

    const FLOOR: Plane = Plane { point: Vec3::ZERO, normal: Vec3::Y };

    fn ray(origin: Vec3, dir: Vec3) -> Ray {
        Ray::new(origin, dir.normalize())
    }

    #[test]
    fn hit_from_above_and_below_keeps_the_normal() {
        // From y = 2 straight down: t = 2 at (1, 0, 1), normal +y.
        let above = FLOOR.intersect(&ray(Vec3::new(1.0, 2.0, 1.0), -Vec3::Y), f32::INFINITY, 5).expect("hit");
        assert_eq!(
            (above.t, above.point, above.normal, above.prim),
            (2.0, Vec3::new(1.0, 0.0, 1.0), Vec3::Y, 5)
        );
        // From below at 45°: t = √2·3, and the normal is still the plane's (+y).
        let below = FLOOR
            .intersect(&ray(Vec3::new(0.0, -3.0, 0.0), Vec3::new(1.0, 1.0, 0.0)), f32::INFINITY, 0)
            .expect("hit");
        assert!((below.t - 3.0 * 2f32.sqrt()).abs() < 1e-6);
        assert_eq!(below.normal, Vec3::Y);
        assert_eq!(below.point.y, 0.0);
    }

    #[test]
    fn parallel_ray_and_plane_behind_miss() {
        assert!(FLOOR.intersect(&ray(Vec3::new(0.0, 1.0, 0.0), Vec3::X), f32::INFINITY, 0).is_none());
        assert!(FLOOR.intersect(&ray(Vec3::new(0.0, 0.0, 0.0), Vec3::X), f32::INFINITY, 0).is_none());
        assert!(FLOOR.intersect(&ray(Vec3::new(0.0, 1.0, 0.0), Vec3::Y), f32::INFINITY, 0).is_none());
        assert!(FLOOR.intersect(&ray(Vec3::new(0.0, 1.0, 0.0), -Vec3::Y), 0.5, 0).is_none());
    }

    #[test]
    fn ray_starting_on_the_plane_does_not_hit_it() {
        // Origins exactly on the plane (its own point for tilted planes; any point of an
        // axis-aligned one), without any push, in every direction: t would be ~0, within the
        // numerator's rounding error: no hit. (An f32 point merely near a tilted plane is
        // really off it by its rounding, and a ray from it really crosses the plane at t ~ 1e-7;
        // spawn_origin moves hit points clear of that: see the next test.)
        let mut rng = Rng::new(9);
        for _ in 0..10_000 {
            let tilted = Plane {
                point: rng.point_in(Vec3::splat(-1000.0), Vec3::splat(1000.0)),
                normal: rng.unit_vector(),
            };
            let dir = rng.unit_vector();
            assert_eq!(tilted.intersect(&ray(tilted.point, dir), f32::INFINITY, 0), None, "{tilted:?}");
            let height = rng.uniform(-1000.0, 1000.0);
            let level = Plane { point: Vec3::new(0.0, height, 0.0), normal: Vec3::Y };
            let on_level = Vec3::new(rng.uniform(-1000.0, 1000.0), height, rng.uniform(-1000.0, 1000.0));
            assert_eq!(level.intersect(&ray(on_level, dir), f32::INFINITY, 0), None, "{level:?}");
        }
    }

    #[test]
    fn grazing_ray_hits_far_away() {
        // Descending 1 in 1000 from y = 1: reaches the floor after √(1000² + 1) ≈ 1000.0005.
        let hit = FLOOR
            .intersect(&ray(Vec3::new(0.0, 1.0, 0.0), Vec3::new(1000.0, -1.0, 0.0)), f32::INFINITY, 0)
            .expect("grazing hit");
        assert!((hit.t - 1000.0005).abs() < 1e-3, "t = {}", hit.t);
    }

    #[test]
    fn spawned_rays_do_not_re_hit_the_plane() {
        // Tilted planes anywhere within 1000 units, hit from random places; rays spawned from
        // the hit point to either side never hit the plane again.
        let mut rng = Rng::new(5);
        for _ in 0..5_000 {
            let plane = Plane {
                point: rng.point_in(Vec3::splat(-1000.0), Vec3::splat(1000.0)),
                normal: rng.unit_vector(),
            };
            let target = plane.point + rng.uniform(0.0, 50.0) * rng.unit_vector().cross(plane.normal);
            let from = target + rng.uniform(0.1, 500.0) * rng.unit_vector();
            let Some(hit) = plane.intersect(&ray(from, target - from), f32::INFINITY, 0) else {
                continue;
            };
            for _ in 0..4 {
                let dir = rng.unit_vector();
                let origin = spawn_origin(hit.point, hit.normal, dir);
                assert_eq!(plane.intersect(&ray(origin, dir), f32::INFINITY, 0), None);
            }
        }
    }
}
