//! [`Sphere`] and its ray intersection.
//!
//! The quadratic is solved as in E. Haines, J. Günther, T. Akenine-Möller, "Precision
//! Improvements for Ray/Sphere Intersection" (*Ray Tracing Gems*, ch. 7, 2019): the discriminant
//! is r² − |f − (f·d)d|² (f = origin − centre), which does not cancel catastrophically for a
//! small sphere seen from far away, and the two roots are q and c/q with
//! q = b + sign(b)·√Δ (Press et al., *Numerical Recipes*, §5.6), so neither root cancels.
//!
//! A root is accepted only when it is surely positive given rounding-error bounds on b and c
//! (in the spirit of the conservative quadric test of PBR 3rd ed. §3.9.6, with explicit bounds
//! instead of interval types): a ray starting on the sphere does not re-hit it where it starts,
//! and a ray spawned inward does hit the far side. In f32 the discriminant of a ray starting on
//! the sphere is known to about 24·u·r² (u = 2⁻²⁴), so a ray within ~0.1° of tangent
//! (chord below ~3·10⁻³ r) may miss its far side. The hit point is reprojected onto the sphere.

use glam::Vec3;

use super::aabb::Aabb;
use super::rounding::gamma;
use super::{Hit, Ray};

/// A sphere; its outside is where the normal points away from the centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre (scene units).
    pub center: Vec3,
    /// Radius (scene units, > 0).
    pub radius: f32,
}

impl Sphere {
    /// The bounding box: the centre ± the radius.
    pub fn bounds(&self) -> Aabb {
        let extent = Vec3::splat(self.radius);
        Aabb { min: self.center - extent, max: self.center + extent }
    }

    /// The nearest intersection with t in (0, `t_max`), from outside or inside; `prim` is copied
    /// into the hit. The normal points away from the centre.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_max: f32, prim: u32) -> Option<Hit> {
        let dir = ray.dir;
        let to_origin = ray.origin - self.center;
        let r2 = self.radius * self.radius;
        // With |dir| = 1 the roots of |f + t·d|² = r² are t = b ± √Δ, b = −f·d.
        let b = -to_origin.dot(dir);
        let perpendicular = to_origin + b * dir;
        let perpendicular2 = perpendicular.length_squared();
        let discriminant = r2 - perpendicular2;
        let real_roots = discriminant >= 0.0; // false for NaN as well
        if !real_roots {
            return None;
        }
        let f2 = to_origin.length_squared();
        let c = f2 - r2;
        let q = b + discriminant.sqrt().copysign(b);

        // Which roots are surely positive, from rounding-error bounds (γ(n): n roundings).
        // b: f rounded once, then a dot product of 3 terms.
        let error_b = gamma(4) * to_origin.abs().dot(dir.abs());
        // |f|² − r²: f's rounding doubled by squaring, the dot product, r², the difference.
        let error_c = gamma(6) * (f2 + r2);
        let sign_of_c_known = c.abs() > error_c;
        // The root c/q is ~0 exactly when the origin is on the sphere (c ~ 0): it is kept only
        // when the sign of c, hence on which side of the surface the origin is, is certain.
        let near_root = c / q;
        let near_ok = sign_of_c_known & (near_root > 0.0) & (near_root < t_max);
        // The root q has the sign of b, certain when |b| exceeds its error (then |q| ≥ |b| is
        // not ~0 either). Otherwise the ray is near tangent at its origin; its roots are then
        // still certain to have opposite signs if the origin is surely inside (c < 0), and the
        // positive one is the far side, whichever of the two it is.
        let far_known = (b.abs() > error_b) | (sign_of_c_known & (c < 0.0));
        let far_ok = far_known & (q > 0.0) & (q < t_max);
        // The nearer of the roots kept, chosen without branches: which root it is changes from
        // ray to ray (a third of the mispredicted branches of the caustic benchmark were here).
        // Both kept roots are finite and positive (below `t_max`), so `min` picks as a total
        // order would; a root not kept counts as +∞, and +∞ means no hit.
        let t = (if near_ok { near_root } else { f32::INFINITY }).min(if far_ok { q } else { f32::INFINITY });
        if t == f32::INFINITY {
            return None;
        }

        // Reproject from the centre: the point's error is then one rounding of c + r·n instead of
        // the error of t along the ray.
        let normal = (to_origin + t * dir).try_normalize()?;
        let point = self.center + self.radius * normal;
        Some(Hit { t, point, normal, shading_normal: normal, prim })
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geometry::spawn_origin;
    use crate::geometry::test_util::{far_side_distance, far_side_tolerance, Rng};

    const UNIT: Sphere = Sphere { center: Vec3::ZERO, radius: 1.0 };

    fn ray(origin: Vec3, dir: Vec3) -> Ray {
        Ray::new(origin, dir.normalize())
    }

    #[test]
    fn hit_from_outside() {
        // From z = 5 towards the centre of the unit sphere: first surface at t = 4, point (0,0,1),
        // normal +z (away from the centre).
        let hit = UNIT.intersect(&ray(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z), f32::INFINITY, 3).expect("hit");
        assert_eq!(hit.t, 4.0);
        assert_eq!(hit.point, Vec3::Z);
        assert_eq!(hit.normal, Vec3::Z);
        assert_eq!(hit.shading_normal, Vec3::Z);
        assert_eq!(hit.prim, 3);
    }

    #[test]
    fn hit_from_inside_has_the_outward_normal() {
        // From the centre, the sphere is hit at t = r = 1; the normal still points away from the
        // centre, i.e. along the ray.
        let hit = UNIT.intersect(&ray(Vec3::ZERO, Vec3::X), f32::INFINITY, 0).expect("hit");
        assert_eq!(hit.t, 1.0);
        assert_eq!(hit.normal, Vec3::X);
    }

    #[test]
    fn misses_behind_beside_and_beyond_t_max() {
        assert!(UNIT.intersect(&ray(Vec3::new(0.0, 0.0, 5.0), Vec3::Z), f32::INFINITY, 0).is_none());
        assert!(UNIT.intersect(&ray(Vec3::new(0.0, 1.5, 5.0), -Vec3::Z), f32::INFINITY, 0).is_none());
        // The surface at t = 4 is beyond t_max = 3.9.
        assert!(UNIT.intersect(&ray(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z), 3.9, 0).is_none());
    }

    #[test]
    fn grazing_ray() {
        // A ray whose line passes at distance 1 − 1e-3 from the centre: a short chord of length
        // 2·√(1 − 0.999²) ≈ 0.0894 centred at t = 5.
        let offset = 1.0 - 1e-3;
        let grazing = ray(Vec3::new(-5.0, offset, 0.0), Vec3::X);
        let hit = UNIT.intersect(&grazing, f32::INFINITY, 0).expect("grazing hit");
        let half_chord = (1.0f32 - offset * offset).sqrt();
        assert!((hit.t - (5.0 - half_chord)).abs() < 1e-4, "t = {}", hit.t);
        // Passing at 1 + 1e-3 misses.
        assert!(UNIT.intersect(&ray(Vec3::new(-5.0, 1.0 + 1e-3, 0.0), Vec3::X), f32::INFINITY, 0).is_none());
    }

    #[test]
    fn small_sphere_far_away_is_precise() {
        // r = 0.01 seen from 1000 units: the textbook discriminant b² − c would lose everything
        // (b² ≈ 1e6, 1 ULP ≈ 0.06 ≫ r² = 1e-4); this one finds the front at t = 1000 − 0.01 to
        // within a few ULPs of 1000.
        let sphere = Sphere { center: Vec3::new(0.0, 0.0, -1000.0), radius: 0.01 };
        let hit = sphere.intersect(&ray(Vec3::ZERO, -Vec3::Z), f32::INFINITY, 0).expect("hit");
        assert!((hit.t - 999.99).abs() < 4e-4, "t = {}", hit.t);
        // Reprojected: exactly on the sphere to within f32 rounding at 1000.
        assert!(((hit.point - sphere.center).length() - 0.01).abs() < 1e-4);
        // Aimed 0.02 to the side: a miss.
        assert!(sphere.intersect(&ray(Vec3::new(0.02, 0.0, 0.0), -Vec3::Z), f32::INFINITY, 0).is_none());
    }

    #[test]
    fn ray_starting_on_the_sphere() {
        // Origins on the unit sphere as computed (so up to rounding off the surface), without
        // any push: outward rays must not hit at all; inward rays must hit the far side, at the
        // exact (f64) distance from that origin (the chord 2·cos θ up to the origin's rounding).
        let mut rng = Rng::new(3);
        for _ in 0..10_000 {
            let normal = rng.unit_vector();
            let on_surface = UNIT.center + UNIT.radius * normal;
            let outward = rng.unit_vector_around(normal);
            assert_eq!(UNIT.intersect(&ray(on_surface, outward), f32::INFINITY, 0), None);
            let inward = rng.unit_vector_around(-normal);
            let hit = UNIT.intersect(&ray(on_surface, inward), f32::INFINITY, 0);
            check_far_side(&UNIT, on_surface, inward, hit);
        }
    }

    /// `hit` must be the exit through the far side (never the surface at the origin). Within
    /// ~0.1° of tangent (a chord below 3·10⁻³ r, see the module notes) f32 cannot tell a short
    /// chord from a miss, and either answer is accepted.
    pub(crate) fn check_far_side(sphere: &Sphere, origin: Vec3, dir: Vec3, hit: Option<Hit>) {
        let grazing = 3e-3 * f64::from(sphere.radius);
        let expected = far_side_distance(sphere, origin, dir);
        let context = format!("{sphere:?} from {origin} along {dir}");
        match (hit, expected) {
            (Some(hit), Some(expected)) => {
                let tolerance = far_side_tolerance(sphere.radius, expected);
                let error = (f64::from(hit.t) - expected).abs();
                assert!(error < tolerance, "{context}: t {} instead of {expected}", hit.t);
            }
            (None, expected) => assert!(
                expected.is_none_or(|t| t < grazing),
                "{context}: missed the far side at {expected:?}"
            ),
            (Some(hit), None) => {
                assert!(f64::from(hit.t) < grazing, "{context}: hit at {} although the line misses", hit.t)
            }
        }
    }

    #[test]
    fn spawned_transmission_hits_the_far_side() {
        // r = 0.01 at 1000 units from the origin, hit from outside; the refracted ray spawned
        // with spawn_origin must exit through the far side, not re-hit the entry point.
        let sphere = Sphere { center: Vec3::new(600.0, -800.0, 5.0), radius: 0.01 };
        let camera = Vec3::new(0.0, 0.0, 5.0);
        let to_sphere = (sphere.center - camera).normalize();
        let hit = sphere.intersect(&ray(camera, to_sphere), f32::INFINITY, 0).expect("hit");
        let inward = (-hit.normal + 0.3 * Vec3::Z).normalize();
        let origin = spawn_origin(hit.point, hit.normal, inward);
        let exit = sphere.intersect(&ray(origin, inward), f32::INFINITY, 0);
        check_far_side(&sphere, origin, inward, exit);
        // The push is a few ULPs of the coordinates (γ(2)·|p|·√3 + 1 ULP ≈ 3e-4 at |p| = 1000):
        // under 5 % of this small radius.
        assert!((origin - hit.point).length() < 0.05 * sphere.radius);
    }

    #[test]
    fn bounds_enclose_the_sphere() {
        let sphere = Sphere { center: Vec3::new(1.0, 2.0, 3.0), radius: 0.5 };
        let bounds = sphere.bounds();
        assert_eq!(bounds.min, Vec3::new(0.5, 1.5, 2.5));
        assert_eq!(bounds.max, Vec3::new(1.5, 2.5, 3.5));
    }
}
