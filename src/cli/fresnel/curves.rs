//! What `prisma fresnel` tabulates and plots: for each angle of incidence, the reflectances
//! R_s, R_p, R and the phases of the amplitude reflection coefficients r_s, r_p, with their
//! difference δ = arg r_p − arg r_s (the retardance of one reflection).
//!
//! Phase convention (the one of [`prisma::polarization`] and of Mitsuba 3's Fresnel code):
//! fields are `E·e^{+iωt}`, so an absorbing medium has index n − ik, an evanescent wave past
//! the critical angle has cos θt = −i√(sin²θt − 1), and a coefficient of phase φ > 0 *leads*:
//! δ > 0 means the p component leads the s component. The amplitudes have Hecht's signs
//! (*Optics*, §4.6), so r_p = −r_s at normal incidence and δ = 180° there. Phases are written
//! in degrees in (−180°, 180°], except that a phase within 0.001° of −180° is written as its
//! equal just above +180°, so that a negative real coefficient always reads ≈ 180°, whatever
//! the sign of the rounding in its imaginary part.

use num_complex::{Complex32, Complex64};

use prisma::optics::{fresnel_conductor, fresnel_conductor_amplitudes, fresnel_dielectric_amplitudes};

/// Reflection at one angle of incidence, seen from one side of the interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reflection {
    /// Reflectance for s (TE) polarisation, |r_s|².
    pub reflectance_s: f64,
    /// Reflectance for p (TM) polarisation, |r_p|².
    pub reflectance_p: f64,
    /// Unpolarised reflectance (R_s + R_p)/2.
    pub reflectance: f64,
    /// arg r_s in degrees, as [`phase_deg`] gives it.
    pub phase_s_deg: f64,
    /// arg r_p in degrees, as [`phase_deg`] gives it.
    pub phase_p_deg: f64,
    /// δ = arg r_p − arg r_s in degrees, as [`phase_deg`] gives it: the phase by which p leads s.
    pub delta_deg: f64,
}

impl Reflection {
    fn new(r_s: Complex32, r_p: Complex32, reflectance_s: f32, reflectance_p: f32) -> Self {
        Self {
            reflectance_s: f64::from(reflectance_s),
            reflectance_p: f64::from(reflectance_p),
            reflectance: 0.5 * (f64::from(reflectance_s) + f64::from(reflectance_p)),
            phase_s_deg: phase_deg(r_s),
            phase_p_deg: phase_deg(r_p),
            // arg(r_p · conj r_s) is the difference already reduced to one turn.
            delta_deg: phase_deg(r_p * r_s.conj()),
        }
    }
}

/// The phase of `z` in degrees, in (−179.999, 180.001]: (−180, 180] with the phases within
/// 0.001° of −180° moved to their equals near +180°; 0 for z = 0.
pub fn phase_deg(z: Complex32) -> f64 {
    phase_deg_f64(Complex64::new(f64::from(z.re), f64::from(z.im)))
}

/// [`phase_deg`] of a double-precision coefficient (those of a coating).
pub fn phase_deg_f64(z: Complex64) -> f64 {
    let degrees = z.im.atan2(z.re).to_degrees();
    // Rounding of a negative real coefficient leaves its imaginary part ±tiny; both signs are
    // the same phase, and one value reads better in tables and plots.
    if degrees <= -179.999 {
        degrees + 360.0
    } else {
        degrees
    }
}

/// Reflection off a dielectric of relative index `n` (n_interior / n_exterior) at `angle_deg`,
/// from the exterior or, when `from_inside`, from the interior (total internal reflection past
/// the critical angle, with its phases).
pub fn dielectric(angle_deg: f64, n: f32, from_inside: bool) -> Reflection {
    let cos = angle_deg.to_radians().cos() as f32;
    let amplitudes = fresnel_dielectric_amplitudes(if from_inside { -cos } else { cos }, n);
    Reflection::new(amplitudes.r_s, amplitudes.r_p, amplitudes.reflectance_s, amplitudes.reflectance_p)
}

/// Reflection off a conductor of relative complex index `eta` = n + ik (k ≥ 0 absorbs) at
/// `angle_deg`, from the exterior.
pub fn conductor(angle_deg: f64, eta: Complex32) -> Reflection {
    let cos = angle_deg.to_radians().cos() as f32;
    let power = fresnel_conductor(cos, eta);
    let (r_s, r_p) = fresnel_conductor_amplitudes(cos, eta);
    Reflection::new(r_s, r_p, power.reflectance_s, power.reflectance_p)
}

/// The principal angle of a conductor, where δ = 90° (the reflected light of incident light at
/// 45° is circularly polarised when R_s = R_p there): the first crossing of 90° by δ along
/// `angles_deg`, linearly interpolated, if any.
pub fn principal_angle(angles_deg: &[f64], rows: &[Reflection]) -> Option<f64> {
    angles_deg.windows(2).zip(rows.windows(2)).find_map(|(angle, row)| {
        let (d0, d1) = (row[0].delta_deg - 90.0, row[1].delta_deg - 90.0);
        // A genuine crossing, not a jump through ±180° (δ changes by < 90° per step there).
        let crosses = d0.signum() != d1.signum() && (d1 - d0).abs() < 90.0;
        crosses.then(|| angle[0] + (angle[1] - angle[0]) * d0 / (d0 - d1))
    })
}

/// The points (angle, phase) of one phase curve for plotting, with a non-finite y inserted
/// where the phase wraps from about +180° to about −180° (a jump of more than 270° in one
/// step), so that no vertical line is drawn across the plot. Genuine jumps of 180° (the sign
/// change of r_p at Brewster's angle) stay drawn.
pub fn phase_points(angles_deg: &[f64], phases_deg: impl Iterator<Item = f64>) -> Vec<(f64, f64)> {
    let mut points: Vec<(f64, f64)> = Vec::with_capacity(angles_deg.len());
    for (&angle, phase) in angles_deg.iter().zip(phases_deg) {
        if let Some(&(_, last)) = points.last() {
            if (phase - last).abs() > 270.0 {
                points.push((angle, f64::NAN));
            }
        }
        points.push((angle, phase));
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hecht (*Optics*, 5th ed., §8.6): in a Fresnel rhomb of glass n = 1.51, each total internal
    /// reflection at 54.6° (or at 48.6°) retards the two components by 45°, two of them by 90°.
    /// With e^{+iωt} and φ > 0 past the critical angle, p leads s: δ = +45°.
    #[test]
    fn fresnel_rhomb_retards_by_45_degrees_per_reflection() {
        for angle in [54.6, 48.6] {
            let delta = dielectric(angle, 1.51, true).delta_deg;
            assert!((delta - 45.0).abs() < 0.1, "δ at {angle}°: {delta}°");
        }
        // The critical angle asin(1/1.51) = 41.47°: δ = 0 just below it, > 0 beyond.
        assert_eq!(dielectric(41.0, 1.51, true).delta_deg, 0.0);
        assert!(dielectric(42.0, 1.51, true).delta_deg > 0.0);
    }

    /// From outside, r_s < 0 at every angle (phase 180°) and r_p changes sign at Brewster's angle
    /// atan(n): δ = 180° below it and 0 above it.
    #[test]
    fn p_phase_jumps_by_180_degrees_at_brewsters_angle() {
        let brewster = 1.5f64.atan().to_degrees(); // 56.31°
        let below = dielectric(brewster - 0.5, 1.5, false);
        let above = dielectric(brewster + 0.5, 1.5, false);
        assert_eq!((below.phase_s_deg, below.phase_p_deg, below.delta_deg), (180.0, 0.0, 180.0));
        assert_eq!((above.phase_s_deg, above.phase_p_deg, above.delta_deg), (180.0, 180.0, 0.0));
    }

    /// At normal incidence r = (1 − η̄)/(1 + η̄) with η̄ = n − ik in the e^{+iωt} convention; for
    /// n + ik = 0.2 + 3.5i by hand: (0.8 + 3.5i)/(1.2 − 3.5i) = (−11.29 + 7.00i)/13.69, whose
    /// phase is 180° − atan(7.00/11.29) = 148.20°; r_p = −r_s, so δ = 180°.
    #[test]
    fn metal_phase_at_normal_incidence_matches_the_closed_form() {
        let row = conductor(0.0, Complex32::new(0.2, 3.5));
        assert!((row.phase_s_deg - 148.20).abs() < 0.01, "{}", row.phase_s_deg);
        assert!((row.phase_p_deg - (148.20 - 180.0)).abs() < 0.01, "{}", row.phase_p_deg);
        assert!((row.delta_deg - 180.0).abs() < 1e-3, "{}", row.delta_deg);
    }

    /// δ falls from 180° at normal incidence to 0 at grazing incidence and passes 90° at the
    /// principal angle, where (Born & Wolf §14.4) the reflected wave of light polarised at 45° is
    /// elliptical with its axes along s and p. For |η| ≫ 1 it satisfies sin θ̄ tan θ̄ ≈ |η|
    /// (Born & Wolf §14.4); for η = 1 + 20i that is 87.14°, and the exact crossing lies within
    /// 0.01° of it.
    #[test]
    fn metal_retardance_passes_90_degrees_at_the_principal_angle() {
        let eta = Complex32::new(1.0, 20.0);
        let angles: Vec<f64> = (0..=3600).map(|i| f64::from(i) * 0.025).collect();
        let rows: Vec<Reflection> = angles.iter().map(|&a| conductor(a, eta)).collect();
        let principal = principal_angle(&angles, &rows).expect("δ crosses 90°");
        let approximation = {
            // Solve sin θ tan θ = |η| by bisection.
            let (mut lo, mut hi) = (0.0f64, 90.0f64.to_radians() - 1e-9);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if mid.sin() * mid.tan() < f64::from(eta.norm()) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo.to_degrees()
        };
        assert!((principal - approximation).abs() < 0.2, "{principal}° vs {approximation}°");
        assert!(rows.windows(2).all(|w| w[1].delta_deg <= w[0].delta_deg + 1e-3), "δ decreases");
    }

    #[test]
    fn phase_wraps_are_broken_but_sign_changes_are_drawn() {
        let angles = [0.0, 1.0, 2.0, 3.0];
        let points = phase_points(&angles, [179.0, -179.0, 0.0, 180.0].into_iter());
        assert_eq!(points.len(), 5);
        assert!(points[1].1.is_nan(), "a break between 179° and −179°");
        assert_eq!(points[4], (3.0, 180.0), "the jump 0 → 180° stays a line");
    }
}
