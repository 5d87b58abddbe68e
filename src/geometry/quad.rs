//! [`Quad`]: a parallelogram, and its ray intersection.
//!
//! The parallelogram is tested as its two triangles (corner, +e1, +e1+e2) and (corner, +e1+e2,
//! +e2) with the watertight test of [`super::triangle`]: the shared diagonal cannot leak, nor can
//! the edge between two quads whose corners coincide exactly, and a ray starting on the quad
//! never re-hits it. The hit point is rebuilt as `corner + u·e1 + v·e2`.

use glam::Vec3;

use super::aabb::Aabb;
use super::triangle::{intersect_triangle, ShearedRay, TriangleHit};
use super::Hit;

/// The parallelogram `corner + u·edge1 + v·edge2`, u, v in [0, 1]. Its outside (normal) is along
/// `edge1 × edge2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    /// One corner.
    pub corner: Vec3,
    /// First edge from the corner.
    pub edge1: Vec3,
    /// Second edge from the corner.
    pub edge2: Vec3,
}

impl Quad {
    /// Unit normal along `edge1 × edge2`.
    pub fn normal(&self) -> Vec3 {
        self.edge1.cross(self.edge2).normalize()
    }
    /// Area (scene units²).
    pub fn area(&self) -> f32 {
        self.edge1.cross(self.edge2).length()
    }
    /// The point at parameters (u, v) in [0, 1]².
    pub fn point_at(&self, u: f32, v: f32) -> Vec3 {
        self.corner + u * self.edge1 + v * self.edge2
    }

    /// The four corners, counter-clockwise seen from the outside: (0,0), (1,0), (1,1), (0,1).
    pub fn corners(&self) -> [Vec3; 4] {
        let far = self.corner + self.edge1 + self.edge2;
        [self.corner, self.corner + self.edge1, far, self.corner + self.edge2]
    }

    /// The bounding box of the four corners.
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(&self.corners())
    }

    /// The intersection with t in (0, `t_max`), from either side; `prim` is copied into the hit.
    /// The hit's normal is [`Self::normal`] whichever side is hit. Degenerate (zero-area) quads
    /// are never hit.
    #[inline]
    pub fn intersect(&self, ray: &ShearedRay, t_max: f32, prim: u32) -> Option<Hit> {
        let (t, u, v) = self.intersect_uv(ray, t_max)?;
        self.hit_record(t, u, v, prim)
    }

    /// The distance and the parameters (u, v) of the intersection with t in (0, `t_max`), before
    /// the hit record is built: what a nearest-hit search needs per candidate.
    #[inline]
    pub(crate) fn intersect_uv(&self, ray: &ShearedRay, t_max: f32) -> Option<(f32, f32, f32)> {
        let [lower_half, upper_half] = self.halves();
        let lower = intersect_triangle(ray, &lower_half, t_max).map(|hit| {
            let (u, v) = Self::half_uv(0, &hit);
            (hit.t, u, v)
        });
        let upper_t_max = lower.map_or(t_max, |(t, _, _)| t);
        let upper = intersect_triangle(ray, &upper_half, upper_t_max).map(|hit| {
            let (u, v) = Self::half_uv(1, &hit);
            (hit.t, u, v)
        });
        upper.or(lower)
    }

    /// The two triangles the quad is tested as: (0,0), (1,0), (1,1) and (0,0), (1,1), (0,1).
    #[inline]
    pub(crate) fn halves(&self) -> [[Vec3; 3]; 2] {
        let [p00, p10, p11, p01] = self.corners();
        [[p00, p10, p11], [p00, p11, p01]]
    }

    /// The parameters (u, v) of a hit on half `half` (0: lower, 1: upper) of [`Self::halves`].
    #[inline]
    pub(crate) fn half_uv(half: usize, hit: &TriangleHit) -> (f32, f32) {
        let [_, b1, b2] = hit.barycentric;
        if half == 0 {
            // Weights of (0,0), (1,0), (1,1): u = b1 + b2, v = b2.
            (b1 + b2, b2)
        } else {
            // Weights of (0,0), (1,1), (0,1): u = b1, v = b1 + b2.
            (b1, b1 + b2)
        }
    }

    /// The hit record at distance `t` and parameters (`u`, `v`); `None` for a degenerate quad
    /// (no normal), which [`Self::intersect`] therefore never reports.
    #[inline]
    pub(crate) fn hit_record(&self, t: f32, u: f32, v: f32, prim: u32) -> Option<Hit> {
        let normal = self.edge1.cross(self.edge2).try_normalize()?;
        Some(Hit { t, point: self.point_at(u, v), normal, shading_normal: normal, prim })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::spawn_origin;
    use crate::geometry::test_util::Rng;
    use crate::geometry::Ray;

    /// The square [0,2]×[0,1] in z = 0, normal +z.
    const SQUARE: Quad =
        Quad { corner: Vec3::ZERO, edge1: Vec3::new(2.0, 0.0, 0.0), edge2: Vec3::new(0.0, 1.0, 0.0) };

    fn intersect(quad: &Quad, origin: Vec3, dir: Vec3) -> Option<Hit> {
        quad.intersect(&ShearedRay::new(Ray::new(origin, dir.normalize())), f32::INFINITY, 9)
    }

    #[test]
    fn hit_in_both_halves_and_from_the_back() {
        // (1.5, 0.25) lies in the lower triangle, (0.5, 0.75) in the upper one; both at t = 1.
        let lower = intersect(&SQUARE, Vec3::new(1.5, 0.25, 1.0), -Vec3::Z).expect("lower half");
        assert_eq!(
            (lower.t, lower.point, lower.normal, lower.prim),
            (1.0, Vec3::new(1.5, 0.25, 0.0), Vec3::Z, 9)
        );
        let upper = intersect(&SQUARE, Vec3::new(0.5, 0.75, 1.0), -Vec3::Z).expect("upper half");
        assert_eq!(upper.point, Vec3::new(0.5, 0.75, 0.0));
        // From below (the back side): hit, and the normal stays +z (edge1 × edge2).
        let back = intersect(&SQUARE, Vec3::new(0.5, 0.75, -2.0), Vec3::Z).expect("back side");
        assert_eq!((back.t, back.normal), (2.0, Vec3::Z));
    }

    #[test]
    fn misses_outside_parallel_and_degenerate() {
        assert!(intersect(&SQUARE, Vec3::new(2.5, 0.5, 1.0), -Vec3::Z).is_none());
        assert!(intersect(&SQUARE, Vec3::new(1.0, -0.1, 1.0), -Vec3::Z).is_none());
        // Parallel, above the quad and in its plane.
        assert!(intersect(&SQUARE, Vec3::new(-1.0, 0.5, 1.0), Vec3::X).is_none());
        assert!(intersect(&SQUARE, Vec3::new(-1.0, 0.5, 0.0), Vec3::X).is_none());
        let line = Quad { corner: Vec3::ZERO, edge1: Vec3::X, edge2: 2.0 * Vec3::X };
        assert!(intersect(&line, Vec3::new(0.5, 0.0, 1.0), -Vec3::Z).is_none());
    }

    #[test]
    fn grazing_ray_hits_near_the_edge() {
        // Descending 1 in 1000 towards the point (1.999, 0.5): hit there, after ≈ 1.999 units.
        let target = Vec3::new(1.999, 0.5, 0.0);
        let dir = Vec3::new(1000.0, 0.0, -1.0).normalize();
        let hit = intersect(&SQUARE, target - 1.999 * dir, dir).expect("grazing hit");
        assert!((hit.point - target).length() < 1e-5, "point {}", hit.point);
    }

    #[test]
    fn diagonal_is_watertight() {
        // Rays aimed exactly at the shared diagonal (0,0)–(2,1) from random directions hit.
        let mut rng = Rng::new(17);
        for _ in 0..10_000 {
            let s = rng.uniform(0.0, 1.0);
            let on_diagonal = SQUARE.point_at(s, s);
            let dir = rng.unit_vector();
            if dir.z.abs() < 1e-3 {
                continue;
            }
            assert!(intersect(&SQUARE, on_diagonal - 3.0 * dir, dir).is_some(), "leak at {on_diagonal}");
        }
    }

    #[test]
    fn spawned_rays_do_not_re_hit_the_quad() {
        // Random parallelograms of size 0.01 to 1000 anywhere within 1000 units, hit from a
        // random place; rays spawned from the hit to either side never hit the quad again.
        let mut rng = Rng::new(23);
        let mut tested = 0;
        for _ in 0..5_000 {
            let size = rng.log_uniform(0.01, 1000.0);
            let quad = Quad {
                corner: rng.point_in(Vec3::splat(-1000.0), Vec3::splat(1000.0)),
                edge1: size * rng.unit_vector(),
                edge2: size * rng.uniform(0.1, 1.0) * rng.unit_vector(),
            };
            let target = quad.point_at(rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0));
            let from = target + rng.log_uniform(0.01, 1000.0) * rng.unit_vector();
            let Some(hit) = intersect(&quad, from, target - from) else {
                continue;
            };
            for _ in 0..4 {
                let dir = rng.unit_vector();
                let origin = spawn_origin(hit.point, hit.normal, dir);
                assert_eq!(
                    intersect(&quad, origin, dir),
                    None,
                    "re-hit of {quad:?} from {origin} along {dir}"
                );
                tested += 1;
            }
        }
        // Most rays aimed at the quad hit it (some are lost to rays nearly in its plane).
        assert!(tested > 15_000, "only {tested} spawned rays tested");
    }
}
