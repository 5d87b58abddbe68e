//! Fresnel reflectance of a conductor, an absorbing medium of complex index n + ik (Born & Wolf,
//! *Principles of Optics*, ch. 14 "Optics of metals"; Hecht, *Optics*, 5th ed., §4.8).
//!
//! With η = (n + ik) / n_exterior the relative complex index, Snell's law gives the complex
//! η cos θt = √(η² − sin² θi) =: a + ib, a ≥ 0, and the Fresnel equations become
//! ```text
//! R_s = ((a − cos θi)² + b²) / ((a + cos θi)² + b²)
//! R_p = R_s · ((a − sin θi tan θi)² + b²) / ((a + sin θi tan θi)² + b²)
//! ```
//! with a² = (|η² − sin² θi| + Re(η² − sin² θi)) / 2 and b² = (|η² − sin² θi| − Re(…)) / 2;
//! only b² enters, so the sign convention of k (n + ik or n − ik) does not matter. Mitsuba 3's
//! `fresnel_conductor` and pbrt-v3's `FrConductor` evaluate the same closed form, expanded;
//! prisma keeps each numerator a sum of squares, so no rounding can make R negative. k = 0
//! reduces it to the dielectric reflectance of [`crate::optics::fresnel_dielectric`], total
//! internal reflection included.
//!
//! Tabulated n, k of real metals live in [`crate::optics::metals`].

use num_complex::Complex32;

/// The reflectances of a conductor for one incidence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConductorFresnel {
    /// Reflectance for s (TE) polarisation.
    pub reflectance_s: f32,
    /// Reflectance for p (TM) polarisation.
    pub reflectance_p: f32,
    /// Unpolarised reflectance (R_s + R_p) / 2.
    pub reflectance: f32,
}

/// Fresnel reflectance of a smooth conductor for light incident from the exterior at
/// `cos_theta_i` in [0, 1], with `eta` the relative complex index (n + ik) / n_exterior
/// (`eta` ≠ 0). The sign of `cos_theta_i` is ignored: light arrives from the exterior, since no
/// ray travels inside a metal. Never NaN for finite inputs.
pub fn fresnel_conductor(cos_theta_i: f32, eta: Complex32) -> ConductorFresnel {
    debug_assert!(eta.re.is_finite() && eta.im.is_finite() && eta.norm_sqr() > 0.0, "{eta}");
    // Dot products of unit vectors overshoot 1 by a few ulps; that is harmless here.
    debug_assert!(cos_theta_i.abs() <= 1.0 + 1e-5, "cos θi = {cos_theta_i} outside [-1, 1]");
    let cos_i = cos_theta_i.abs();
    let sin_i_sqr = (-cos_i).mul_add(cos_i, 1.0);
    // η² − sin² θi = (n² − k² − sin² θi) + i 2nk =: (a + ib)².
    let real_part = eta.re * eta.re - eta.im * eta.im - sin_i_sqr;
    let modulus = real_part.hypot(2.0 * eta.re * eta.im);
    // a² = (|z| + Re z)/2 and b² = (|z| − Re z)/2 are ≥ 0 analytically; max(0, ·) only absorbs
    // rounding, so that every numerator below is a sum of squares and R ≥ 0.
    let a = (0.5 * (modulus + real_part)).max(0.0).sqrt();
    let b_sqr = (0.5 * (modulus - real_part)).max(0.0);

    // R_s = ((a − cos θi)² + b²) / ((a + cos θi)² + b²). The denominator vanishes only for
    // η = 1 at grazing incidence (a = b = cos θi = 0): no interface, nothing reflected.
    let reflectance_s = ratio_or_zero(square(a - cos_i) + b_sqr, square(a + cos_i) + b_sqr);
    // R_p / R_s = ((a − sin θi tan θi)² + b²) / ((a + sin θi tan θi)² + b²), multiplied through
    // by cos² θi so that grazing incidence stays finite. Its denominator would vanish only for
    // sin θi = 0 and η = 0, which is excluded.
    let (a_cos, b_sqr_cos_sqr) = (a * cos_i, b_sqr * cos_i * cos_i);
    let reflectance_p = reflectance_s
        * ratio_or_zero(square(a_cos - sin_i_sqr) + b_sqr_cos_sqr, square(a_cos + sin_i_sqr) + b_sqr_cos_sqr);
    ConductorFresnel { reflectance_s, reflectance_p, reflectance: 0.5 * (reflectance_s + reflectance_p) }
}

/// Complex amplitude reflection coefficients (r_s, r_p) of a smooth conductor for light from
/// the exterior at `cos_theta_i` (sign ignored), with `eta` = (n + ik)/n_exterior as users and
/// data tables give it (k ≥ 0 absorbs).
///
/// Phase convention: fields `E·e^{+iωt}` (see [`crate::polarization`]), in which an absorbing
/// medium has index n − ik; so the formulas use η̄ = n − ik, and η̄·cos θt = √(η̄² − sin²θi)
/// takes the root with Im ≤ 0, the transmitted wave that decays. Hecht's signs:
/// ```text
/// r_s = (cos θi − η̄ cos θt)/(cos θi + η̄ cos θt),   r_p = (η̄² cos θi − η̄ cos θt)/(η̄² cos θi + η̄ cos θt)
/// ```
/// |r_s|², |r_p|² are [`fresnel_conductor`]'s R_s, R_p; k = 0 gives the dielectric amplitudes
/// of [`crate::optics::fresnel_dielectric_amplitudes`], total internal reflection included,
/// and |η| → ∞ the perfect conductor (−1, +1).
pub fn fresnel_conductor_amplitudes(cos_theta_i: f32, eta: Complex32) -> (Complex32, Complex32) {
    debug_assert!(eta.re.is_finite() && eta.im.is_finite() && eta.norm_sqr() > 0.0, "{eta}");
    let cos_i = cos_theta_i.abs().min(1.0);
    let sin_i_sqr = (-cos_i).mul_add(cos_i, 1.0);
    let eta = Complex32::new(eta.re, -eta.im.abs());
    let eta_sqr = eta * eta;
    let mut eta_cos_t = (eta_sqr - sin_i_sqr).sqrt();
    if eta_cos_t.im > 0.0 {
        eta_cos_t = -eta_cos_t;
    }
    let ratio = |numerator: Complex32, denominator: Complex32| {
        if denominator.norm_sqr() > 0.0 {
            numerator / denominator
        } else {
            Complex32::new(0.0, 0.0)
        }
    };
    let r_s = ratio(cos_i - eta_cos_t, cos_i + eta_cos_t);
    let r_p = ratio(eta_sqr * cos_i - eta_cos_t, eta_sqr * cos_i + eta_cos_t);
    (r_s, r_p)
}

fn square(x: f32) -> f32 {
    x * x
}

/// `numerator / denominator`, or 0 when both vanish (the index-matched limit).
fn ratio_or_zero(numerator: f32, denominator: f32) -> f32 {
    if denominator > 0.0 {
        numerator / denominator
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::fresnel_dielectric;

    fn eta(n: f32, k: f32) -> Complex32 {
        Complex32::new(n, k)
    }

    #[test]
    fn normal_incidence_matches_the_textbook_formula() {
        // Hecht §4.8 / Born & Wolf ch. 14: at normal incidence R = ((n−1)² + k²)/((n+1)² + k²).
        // Silver-like 0.05 + 4.2i: (0.9025 + 17.64)/(1.1025 + 17.64) = 0.989329…
        for (n, k) in [(0.05_f32, 4.2_f32), (0.2, 3.5), (1.0, 6.7), (2.0, 1.0), (1.5, 0.0)] {
            let expected = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
            let f = fresnel_conductor(1.0, eta(n, k));
            assert!((f.reflectance - expected).abs() < 1e-6, "{n}+{k}i: {f:?} vs {expected}");
            assert!((f.reflectance_s - f.reflectance_p).abs() < 1e-6);
        }
        let silver_like = fresnel_conductor(1.0, eta(0.05, 4.2)).reflectance;
        assert!((silver_like - 0.989_329).abs() < 1e-5);
    }

    #[test]
    fn zero_absorption_is_a_dielectric() {
        // k = 0 turns the conductor formula into the dielectric one, for denser (n > 1) and
        // rarer (n < 1, with total internal reflection past θc) media alike.
        for n in [0.5_f32, 0.75, 1.333, 1.5, 2.4] {
            for i in 0..=100 {
                let cos_theta_i = i as f32 / 100.0;
                let conductor = fresnel_conductor(cos_theta_i, eta(n, 0.0));
                let dielectric = fresnel_dielectric(cos_theta_i, n);
                let context = format!("n {n}, cos θi {cos_theta_i}: {conductor:?} {dielectric:?}");
                assert!((conductor.reflectance - dielectric.reflectance).abs() < 2e-6, "{context}");
                assert!((conductor.reflectance_s - dielectric.reflectance_s).abs() < 2e-6);
                assert!((conductor.reflectance_p - dielectric.reflectance_p).abs() < 2e-6);
            }
        }
    }

    #[test]
    fn the_sign_of_k_does_not_matter() {
        // n + ik and n − ik describe the same absorbing medium under the two time conventions.
        for cos_theta_i in [1.0_f32, 0.7, 0.2, 0.0] {
            let plus = fresnel_conductor(cos_theta_i, eta(0.2, 3.5));
            let minus = fresnel_conductor(cos_theta_i, eta(0.2, -3.5));
            assert_eq!(plus, minus);
        }
    }

    #[test]
    fn metals_have_a_principal_angle_with_a_p_minimum() {
        // Born & Wolf ch. 14: R_p of a metal dips (without reaching 0) near the principal
        // angle, then rises to 1 at grazing incidence; R_s grows monotonically to 1.
        let metal = eta(1.0, 6.7);
        let samples: Vec<ConductorFresnel> =
            (0..=1000).map(|i| fresnel_conductor(1.0 - i as f32 / 1000.0, metal)).collect();
        let min_p = samples.iter().map(|f| f.reflectance_p).fold(f32::INFINITY, f32::min);
        assert!(min_p > 0.0 && min_p < samples[0].reflectance_p - 0.05, "{min_p}");
        assert!(samples.windows(2).all(|w| w[1].reflectance_s >= w[0].reflectance_s - 1e-6));
        let grazing = samples[1000];
        assert!((grazing.reflectance - 1.0).abs() < 1e-6, "{grazing:?}");
    }

    #[test]
    fn amplitudes_square_to_the_reflectances() {
        for metal in [eta(0.05, 4.2), eta(0.35, 2.71), eta(1.0, 6.7), eta(2.0, 1.0)] {
            for i in 0..=50 {
                let cos_theta_i = i as f32 / 50.0;
                let (r_s, r_p) = fresnel_conductor_amplitudes(cos_theta_i, metal);
                let f = fresnel_conductor(cos_theta_i, metal);
                assert!((r_s.norm_sqr() - f.reflectance_s).abs() < 2e-5, "{metal} {cos_theta_i}");
                assert!((r_p.norm_sqr() - f.reflectance_p).abs() < 2e-5, "{metal} {cos_theta_i}");
            }
        }
    }

    #[test]
    fn amplitudes_without_absorption_are_the_dielectric_ones() {
        // Including the phases of total internal reflection (n < 1 past the critical angle):
        // the decaying root of the conductor is the dielectric's cos θt = −i·q.
        for n in [0.6_f32, 1.0 / 1.5, 1.5] {
            // Within a few ulps of the critical angle cos θt = √(cos² θt) turns one rounding
            // into errors of 1e-3 whatever the formula (see `fresnel_dielectric_amplitudes`).
            let cos_critical = (1.0 - n * n).max(0.0).sqrt();
            for i in (1..=40).filter(|&i| (i as f32 / 40.0 - cos_critical).abs() > 1e-3) {
                let cos_theta_i = i as f32 / 40.0;
                let (r_s, r_p) = fresnel_conductor_amplitudes(cos_theta_i, eta(n, 0.0));
                let dielectric = crate::optics::fresnel_dielectric_amplitudes(cos_theta_i, n);
                assert!(
                    (r_s - dielectric.r_s).norm() < 1e-4,
                    "n {n} cos {cos_theta_i}: {r_s} {}",
                    dielectric.r_s
                );
                assert!(
                    (r_p - dielectric.r_p).norm() < 1e-4,
                    "n {n} cos {cos_theta_i}: {r_p} {}",
                    dielectric.r_p
                );
            }
        }
    }

    #[test]
    fn a_huge_index_is_the_perfect_conductor() {
        for cos_theta_i in [1.0_f32, 0.5, 0.1] {
            let (r_s, r_p) = fresnel_conductor_amplitudes(cos_theta_i, eta(0.0, 1e5));
            assert!((r_s - Complex32::new(-1.0, 0.0)).norm() < 1e-3, "{r_s}");
            assert!((r_p - Complex32::new(1.0, 0.0)).norm() < 1e-3, "{r_p}");
        }
    }

    #[test]
    fn never_nan_and_never_above_one() {
        let etas =
            [eta(0.05, 4.2), eta(1.0, 0.0), eta(0.5, 0.0), eta(1.0, 1e-6), eta(3.0, 0.01), eta(0.01, 10.0)];
        for eta in etas {
            for i in 0..=200 {
                let cos_theta_i = i as f32 / 200.0;
                let f = fresnel_conductor(cos_theta_i, eta);
                for r in [f.reflectance_s, f.reflectance_p, f.reflectance] {
                    assert!(r.is_finite() && (0.0..=1.0 + 1e-6).contains(&r), "{eta} {f:?}");
                }
            }
        }
        // η = 1 exactly reflects nothing, grazing incidence included.
        assert_eq!(fresnel_conductor(0.0, eta(1.0, 0.0)).reflectance, 0.0);
    }
}
