//! Mirror reflection and Snell refraction of directions (Hecht, *Optics*, 5th ed., §4.4 for
//! the laws of reflection and refraction; the vector form as in Pharr, Jakob & Humphreys,
//! *Physically Based Rendering*, 4th ed., §9.3).
//!
//! Directions are travel directions (pointing away from the light's source), unit length.

use glam::Vec3;

/// Mirror reflection of the incoming travel direction `dir` about the unit normal `normal`
/// (either orientation).
#[inline]
pub fn reflect(dir: Vec3, normal: Vec3) -> Vec3 {
    dir - 2.0 * dir.dot(normal) * normal
}

/// Refraction of the unit travel direction `dir` through an interface with unit `normal` (either
/// orientation), where `eta_ratio` = n_incident / n_transmitted. `None` under total internal
/// reflection.
///
/// With cos θi = |dir · normal| and the normal `n` turned to face the incident side, Snell's law
/// n_i sin θi = n_t sin θt gives t = eta_ratio · dir + (eta_ratio cos θi − cos θt) n, a unit
/// vector in the plane of `dir` and `normal`. cos² θt = 1 − (1 − cos² θi) eta_ratio² is
/// computed with the same fused multiply-adds as [`crate::optics::fresnel_dielectric`], so for
/// the same cos θi and `eta_ratio` = its `eta_ti` the two agree on where total internal
/// reflection begins (at cos² θt ≤ 0, the critical angle included).
#[inline]
pub fn refract(dir: Vec3, normal: Vec3, eta_ratio: f32) -> Option<Vec3> {
    debug_assert!(dir.is_normalized() && normal.is_normalized(), "{dir} {normal}");
    debug_assert!(eta_ratio.is_finite() && eta_ratio > 0.0, "eta_ratio {eta_ratio}");
    let cos_dir_normal = dir.dot(normal);
    // Turn the normal against the travel direction, towards the incident side.
    let (normal, cos_theta_i) =
        if cos_dir_normal > 0.0 { (-normal, cos_dir_normal) } else { (normal, -cos_dir_normal) };
    let sin_theta_i_sqr = (-cos_theta_i).mul_add(cos_theta_i, 1.0);
    let cos_theta_t_sqr = (-sin_theta_i_sqr).mul_add(eta_ratio * eta_ratio, 1.0);
    if cos_theta_t_sqr <= 0.0 {
        return None;
    }
    let cos_theta_t = cos_theta_t_sqr.sqrt();
    Some(eta_ratio * dir + (eta_ratio * cos_theta_i - cos_theta_t) * normal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_core::{RngCore, SeedableRng};
    use rand_pcg::Pcg32;

    /// A uniformly distributed unit vector (Archimedes: z uniform in [−1, 1]).
    fn random_unit(rng: &mut Pcg32) -> Vec3 {
        let z = 2.0 * uniform(rng) - 1.0;
        let phi = std::f32::consts::TAU * uniform(rng);
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    fn uniform(rng: &mut Pcg32) -> f32 {
        (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32
    }

    fn sin_between(a: Vec3, b: Vec3) -> f32 {
        a.cross(b).length()
    }

    #[test]
    fn refraction_obeys_snells_law() {
        // n_i sin θi = n_t sin θt; the refracted ray stays in the plane of incidence, on the far
        // side of the interface, and has unit length.
        let mut rng = Pcg32::seed_from_u64(0x5e11);
        let indices = [1.0_f32, 1.333, 1.5, 1.7, 2.4];
        let mut refracted = 0;
        for _ in 0..2000 {
            let (dir, normal) = (random_unit(&mut rng), random_unit(&mut rng));
            let n_i = indices[(rng.next_u32() % 5) as usize];
            let n_t = indices[(rng.next_u32() % 5) as usize];
            let sin_i = sin_between(dir, normal);
            let Some(t) = refract(dir, normal, n_i / n_t) else {
                // Only past the critical angle, sin θi ≥ n_t / n_i.
                assert!(sin_i >= n_t / n_i - 1e-5, "{dir} {normal} {n_i} {n_t}");
                continue;
            };
            refracted += 1;
            assert!((t.length() - 1.0).abs() < 1e-5, "|t| = {}", t.length());
            let sin_t = sin_between(t, normal);
            assert!((n_i * sin_i - n_t * sin_t).abs() < 2e-5, "{n_i}·{sin_i} vs {n_t}·{sin_t}");
            assert!(t.dot(dir.cross(normal)).abs() < 1e-5, "t leaves the plane of incidence");
            assert!(t.dot(normal) * dir.dot(normal) >= 0.0, "t must cross the interface");
        }
        assert!(refracted > 1000, "most random pairs refract; got {refracted}");
    }

    #[test]
    fn matched_indices_go_straight_through() {
        let dir = Vec3::new(0.6, 0.0, -0.8);
        let t = refract(dir, Vec3::Z, 1.0).expect("no TIR at eta 1");
        assert!((t - dir).length() < 1e-6, "{t}");
    }

    #[test]
    fn normal_incidence_is_not_deviated() {
        let t = refract(-Vec3::Z, Vec3::Z, 1.0 / 1.5).expect("normal incidence refracts");
        assert!((t + Vec3::Z).length() < 1e-6, "{t}");
    }

    #[test]
    fn total_internal_reflection_past_the_critical_angle() {
        // Glass (1.5) to air: θc = asin(1/1.5) = 41.81°; at 45° nothing is transmitted, at 40°
        // the ray leaves at asin(1.5 sin 40°) = 74.62°.
        let at = |degrees: f32| {
            let theta = degrees.to_radians();
            Vec3::new(theta.sin(), 0.0, theta.cos())
        };
        assert_eq!(refract(at(45.0), Vec3::Z, 1.5), None);
        assert_eq!(refract(at(89.9), -Vec3::Z, 1.5), None);
        let t = refract(at(40.0), Vec3::Z, 1.5).expect("below the critical angle");
        let expected = 74.62_f32.to_radians().sin();
        assert!((t.x - expected).abs() < 1e-4, "{t}");
    }

    #[test]
    fn reflection_preserves_the_angle() {
        // Law of reflection: θr = θi, in the plane of incidence, on the incident side.
        let mut rng = Pcg32::seed_from_u64(0x4ef1);
        for _ in 0..1000 {
            let (dir, normal) = (random_unit(&mut rng), random_unit(&mut rng));
            let r = reflect(dir, normal);
            assert!((r.length() - 1.0).abs() < 1e-5);
            assert!((r.dot(normal) + dir.dot(normal)).abs() < 1e-5);
            assert!(r.dot(dir.cross(normal)).abs() < 1e-5);
        }
    }
}
