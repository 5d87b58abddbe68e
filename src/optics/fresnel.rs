//! Fresnel equations for a smooth interface between two dielectrics (Hecht, *Optics*, 5th ed.,
//! §4.6 for the amplitude coefficients, §4.7 for total internal reflection, §4.10 for the
//! Stokes relations).
//!
//! Convention (the same as Mitsuba 3's `fresnel` and `fresnel_polarized`, so that their values
//! are directly comparable): `eta` is the relative index n_interior / n_exterior, `cos_theta_i`
//! is measured against the normal on the exterior side, and a negative `cos_theta_i` means light
//! arriving from the interior. `eta_it` = n_t / n_i is the index ratio seen by the incident ray
//! and `eta_ti` = 1 / `eta_it`. `cos_theta_i` = −0 counts as the exterior, for `cos_theta_t`'s
//! sign too (Mitsuba signs its `cos_theta_t` by the sign bit there, as if from the interior).
//!
//! Sign convention of the amplitudes (Hecht §4.6, the "Verdet convention" Mitsuba also uses):
//! with θi, θt the unsigned angles of incidence and transmission,
//! ```text
//! r_s = (cos θi − eta_it cos θt) / (cos θi + eta_it cos θt)      (= r⊥)
//! r_p = (eta_it cos θi − cos θt) / (eta_it cos θi + cos θt)      (= r∥)
//! t_s = 2 cos θi / (cos θi + eta_it cos θt)                      (= t⊥)
//! t_p = 2 cos θi / (eta_it cos θi + cos θt)                      (= t∥)
//! ```
//! so at normal incidence r_p = −r_s = (eta_it − 1)/(eta_it + 1). Transmittances carry the
//! beam-area and index factor: T = eta_it (cos θt / cos θi) |t|², and R + T = 1.
//!
//! Past the critical angle cos θt is imaginary. [`fresnel_dielectric_amplitudes`] takes the root
//! cos θt = −i √(eta_ti² sin² θi − 1), as Mitsuba does (after Clarke, *Stellar Polarimetry*,
//! App. A.2), which gives r = e^{iδ} with Hecht's phase shifts tan(δs/2) = √(sin²θi − eta_it²) /
//! cos θi and tan(δp/2) = √(sin²θi − eta_it²) / (eta_it² cos θi), both positive.
//!
//! Numerics: near the critical angle cos θt = √(cos² θt) magnifies any rounding of
//! cos² θt = 1 − (1 − cos² θi) eta_ti². [`fresnel_dielectric`] evaluates it with a fused
//! multiply-add, which rounds once, like Mitsuba's `fresnel`; [`fresnel_dielectric_amplitudes`]
//! rounds like Mitsuba's `fresnel_polarized`, so that each can be validated against its
//! counterpart row by row (`tests/fresnel_fixtures.rs`), critical angles included.

use num_complex::Complex32;

/// The Fresnel coefficients of one incidence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricFresnel {
    /// Amplitude reflection coefficient for s (TE) polarisation.
    pub r_s: f32,
    /// Amplitude reflection coefficient for p (TM) polarisation.
    pub r_p: f32,
    /// Reflectance (power) for s polarisation, |r_s|².
    pub reflectance_s: f32,
    /// Reflectance (power) for p polarisation, |r_p|².
    pub reflectance_p: f32,
    /// Unpolarised reflectance (R_s + R_p) / 2; 1 under total internal reflection.
    pub reflectance: f32,
    /// Cosine of the transmitted angle, signed like Mitsuba's: negative when the transmitted ray
    /// goes into the interior. 0 under total internal reflection.
    pub cos_theta_t: f32,
    /// Relative index seen by the incident ray, n_t / n_i.
    pub eta_it: f32,
}

impl DielectricFresnel {
    /// Unpolarised transmittance T = 1 − R: a lossless interface conserves energy. 0 under
    /// total internal reflection.
    pub fn transmittance(&self) -> f32 {
        1.0 - self.reflectance
    }
}

/// Fresnel coefficients for unpolarised light hitting an interface of relative index `eta`
/// (n_interior / n_exterior, > 0) at `cos_theta_i` in [-1, 1]. Never NaN for finite inputs.
///
/// Under total internal reflection (including exactly at the critical angle) the amplitudes
/// have modulus 1 and a phase this real-valued summary drops: `r_s` = `r_p` = 1 (their common
/// value at the critical angle), `reflectance` = 1, `cos_theta_t` = 0. Use
/// [`fresnel_dielectric_amplitudes`] for the complex amplitudes. An index-matched interface
/// (`eta` = 1) reflects nothing at every angle, grazing included.
pub fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> DielectricFresnel {
    let snell = Snell::new(cos_theta_i, eta, Rounding::Fused);
    if eta == 1.0 {
        return DielectricFresnel {
            r_s: 0.0,
            r_p: 0.0,
            reflectance_s: 0.0,
            reflectance_p: 0.0,
            reflectance: 0.0,
            cos_theta_t: snell.signed_cos_theta_t(),
            eta_it: snell.eta_it,
        };
    }
    if snell.is_total_internal_reflection() {
        return DielectricFresnel {
            r_s: 1.0,
            r_p: 1.0,
            reflectance_s: 1.0,
            reflectance_p: 1.0,
            reflectance: 1.0,
            cos_theta_t: 0.0,
            eta_it: snell.eta_it,
        };
    }
    let (cos_i, cos_t, eta_it) = (snell.cos_theta_i_abs, snell.cos_theta_t_sqr.sqrt(), snell.eta_it);
    // Both denominators are > 0: cos_t > 0 outside total internal reflection.
    let r_s = (-eta_it).mul_add(cos_t, cos_i) / eta_it.mul_add(cos_t, cos_i);
    let r_p = eta_it.mul_add(cos_i, -cos_t) / eta_it.mul_add(cos_i, cos_t);
    let (reflectance_s, reflectance_p) = (r_s * r_s, r_p * r_p);
    DielectricFresnel {
        r_s,
        r_p,
        reflectance_s,
        reflectance_p,
        reflectance: 0.5 * (reflectance_s + reflectance_p),
        cos_theta_t: snell.signed_cos_theta_t(),
        eta_it,
    }
}

/// Complex amplitude coefficients and power transmittances of one incidence, for polarisation
/// work and for checking energy conservation; see the module documentation for the conventions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricAmplitudes {
    /// Amplitude reflection coefficient r⊥ for s (TE) polarisation; real outside total
    /// internal reflection, of modulus 1 under it.
    pub r_s: Complex32,
    /// Amplitude reflection coefficient r∥ for p (TM) polarisation (Hecht's sign convention).
    pub r_p: Complex32,
    /// Amplitude transmission coefficient t⊥ for s polarisation; under total internal
    /// reflection it is the amplitude of the evanescent wave, which carries no power.
    pub t_s: Complex32,
    /// Amplitude transmission coefficient t∥ for p polarisation.
    pub t_p: Complex32,
    /// Reflectance for s polarisation, |r_s|².
    pub reflectance_s: f32,
    /// Reflectance for p polarisation, |r_p|².
    pub reflectance_p: f32,
    /// Unpolarised reflectance (R_s + R_p) / 2.
    pub reflectance: f32,
    /// Transmittance for s polarisation, eta_it (cos θt / cos θi) |t_s|²; 0 under total
    /// internal reflection and at grazing incidence.
    pub transmittance_s: f32,
    /// Transmittance for p polarisation, eta_it (cos θt / cos θi) |t_p|².
    pub transmittance_p: f32,
    /// Unpolarised transmittance (T_s + T_p) / 2.
    pub transmittance: f32,
    /// Cosine of the transmitted angle, signed as in [`DielectricFresnel::cos_theta_t`]; 0 under
    /// total internal reflection.
    pub cos_theta_t: f32,
    /// Relative index seen by the incident ray, n_t / n_i.
    pub eta_it: f32,
    /// Its reciprocal n_i / n_t, the factor that scales the tangential part of the direction
    /// in Snell's law.
    pub eta_ti: f32,
}

/// Complex Fresnel amplitudes r_s, r_p, t_s, t_p and the power coefficients for an interface
/// of relative index `eta` (n_interior / n_exterior, > 0) at `cos_theta_i` in [-1, 1]; the
/// values of Mitsuba 3's `fresnel_polarized` plus the transmission side. Never NaN for finite
/// inputs. `eta` = 1 gives r = 0, t = 1, T = 1.
///
/// Its float32 rounding of cos² θt is that of Mitsuba's `fresnel_polarized`, where
/// [`fresnel_dielectric`] follows Mitsuba's `fresnel`; the two Mitsuba functions (and so these
/// two) agree to ~1e-7 except within a few ulps of cos θt = 0 (the critical angle, or eta ≈ 1
/// at grazing incidence), where cos θt = √(cos² θt) turns one rounding into errors up to ~1e-3
/// and no float32 evaluation is better than another.
pub fn fresnel_dielectric_amplitudes(cos_theta_i: f32, eta: f32) -> DielectricAmplitudes {
    let snell = Snell::new(cos_theta_i, eta, Rounding::ComplexIndex);
    let (cos_i, eta_it) = (snell.cos_theta_i_abs, snell.eta_it);
    let zero = Complex32::new(0.0, 0.0);
    let one = Complex32::new(1.0, 0.0);
    if eta == 1.0 {
        return DielectricAmplitudes {
            r_s: zero,
            r_p: zero,
            t_s: one,
            t_p: one,
            reflectance_s: 0.0,
            reflectance_p: 0.0,
            reflectance: 0.0,
            transmittance_s: 1.0,
            transmittance_p: 1.0,
            transmittance: 1.0,
            cos_theta_t: snell.signed_cos_theta_t(),
            eta_it,
            eta_ti: snell.eta_ti,
        };
    }
    let total_internal_reflection = snell.is_total_internal_reflection();
    let cos_t = if total_internal_reflection {
        Complex32::new(0.0, -(-snell.cos_theta_t_sqr).sqrt())
    } else {
        Complex32::new(snell.cos_theta_t_sqr.sqrt(), 0.0)
    };
    // Denominators vanish only when cos θi = 0 and cos θt = 0 together, which needs
    // eta_ti = 1, the index-matched case handled above.
    let denominator_s = cos_i + eta_it * cos_t;
    let denominator_p = eta_it * cos_i + cos_t;
    let r_s = (cos_i - eta_it * cos_t) / denominator_s;
    let r_p = (eta_it * cos_i - cos_t) / denominator_p;
    let t_s = 2.0 * cos_i / denominator_s;
    let t_p = 2.0 * cos_i / denominator_p;
    let (transmittance_s, transmittance_p) = if total_internal_reflection {
        (0.0, 0.0)
    } else {
        // eta_it (cos θt / cos θi) |t|², written without dividing by cos θi so that grazing
        // incidence gives 0 instead of 0/0.
        let flux = 4.0 * cos_i * eta_it * cos_t.re;
        (flux / denominator_s.norm_sqr(), flux / denominator_p.norm_sqr())
    };
    let (reflectance_s, reflectance_p) = (r_s.norm_sqr(), r_p.norm_sqr());
    DielectricAmplitudes {
        r_s,
        r_p,
        t_s,
        t_p,
        reflectance_s,
        reflectance_p,
        reflectance: 0.5 * (reflectance_s + reflectance_p),
        transmittance_s,
        transmittance_p,
        transmittance: 0.5 * (transmittance_s + transmittance_p),
        cos_theta_t: if total_internal_reflection { 0.0 } else { snell.signed_cos_theta_t() },
        eta_it,
        eta_ti: snell.eta_ti,
    }
}

/// Snell's law for one incidence: the quantities both Fresnel functions share.
struct Snell {
    /// True when the light arrives from the exterior (`cos_theta_i` ≥ 0, −0 included).
    from_exterior: bool,
    cos_theta_i_abs: f32,
    /// cos² θt = 1 − sin² θi · eta_ti²; ≤ 0 under total internal reflection.
    cos_theta_t_sqr: f32,
    eta_it: f32,
    eta_ti: f32,
}

/// How [`Snell`] rounds; the two agree except within a few ulps of where cos θt → 0.
#[derive(Clone, Copy)]
enum Rounding {
    /// eta_ti = 1/eta, cos² θt = fma(−sin² θi, eta_ti², 1): one rounding, as Mitsuba's
    /// `fresnel` (its scalar float32 build fuses the multiply-add).
    Fused,
    /// eta_ti = eta · (1/eta²), cos² θt = 1 − eta_ti² · sin² θi in two roundings, as Mitsuba's
    /// complex-index `fresnel_polarized` computes them (its complex reciprocal is z̄/|z|²).
    ComplexIndex,
}

impl Snell {
    fn new(cos_theta_i: f32, eta: f32, rounding: Rounding) -> Self {
        debug_assert!(eta.is_finite() && eta > 0.0, "relative index {eta} must be finite and > 0");
        // Dot products of unit vectors overshoot 1 by a few ulps; that is harmless here.
        debug_assert!(cos_theta_i.abs() <= 1.0 + 1e-5, "cos θi = {cos_theta_i} outside [-1, 1]");
        let from_exterior = cos_theta_i >= 0.0;
        let rcp_eta = match rounding {
            Rounding::Fused => 1.0 / eta,
            Rounding::ComplexIndex => eta * (1.0 / (eta * eta)),
        };
        let (eta_it, eta_ti) = if from_exterior { (eta, rcp_eta) } else { (rcp_eta, eta) };
        let sin_theta_i_sqr = (-cos_theta_i).mul_add(cos_theta_i, 1.0);
        let cos_theta_t_sqr = match rounding {
            Rounding::Fused => (-sin_theta_i_sqr).mul_add(eta_ti * eta_ti, 1.0),
            Rounding::ComplexIndex => 1.0 - eta_ti * eta_ti * sin_theta_i_sqr,
        };
        Self { from_exterior, cos_theta_i_abs: cos_theta_i.abs(), cos_theta_t_sqr, eta_it, eta_ti }
    }

    /// At exactly the critical angle cos θt = 0 and R = 1, the limit from either side.
    fn is_total_internal_reflection(&self) -> bool {
        self.cos_theta_t_sqr <= 0.0
    }

    /// The transmitted ray continues to the other side of the interface: negative cosine when
    /// entering the interior.
    fn signed_cos_theta_t(&self) -> f32 {
        let cos_theta_t = self.cos_theta_t_sqr.max(0.0).sqrt();
        if self.from_exterior {
            -cos_theta_t
        } else {
            cos_theta_t
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Relative indices used across the tests: rarer and denser interiors, near-matched, water,
    /// crown glass, diamond.
    const ETAS: [f32; 9] = [0.5, 0.75, 1.0 / 1.5, 1.0, 1.0001, 1.333, 1.5, 1.7, 2.4];

    /// cos θi from −1 to 1 in 2/400 steps, with ±1 and 0 exactly, and the critical angle of
    /// every eta in [`ETAS`] together with its neighbouring f32 values.
    fn cos_grid() -> Vec<f32> {
        let mut grid: Vec<f32> = (0..=400).map(|i| (i as f32 - 200.0) / 200.0).collect();
        for eta in ETAS {
            let eta = eta as f64;
            let sin_critical = eta.min(1.0 / eta);
            let cos_critical = (1.0 - sin_critical * sin_critical).sqrt() as f32;
            for c in [cos_critical, cos_critical.next_up(), cos_critical.next_down()] {
                grid.extend([c, -c]);
            }
        }
        grid
    }

    #[test]
    fn normal_incidence_reflects_the_textbook_fraction() {
        // Hecht §4.6.4: at normal incidence R = ((n − 1)/(n + 1))² from either side; for
        // n = 1.5 that is 0.04, for diamond (2.4) (1.4/3.4)² = 0.169550, for water (1.333)
        // (0.333/2.333)² = 0.0203732.
        for (n, expected) in [(1.5_f32, 0.04_f32), (2.4, 0.169_550_17), (1.333, 0.020_373_19)] {
            for cos_theta_i in [1.0, -1.0] {
                let f = fresnel_dielectric(cos_theta_i, n);
                assert!((f.reflectance - expected).abs() < 1e-6, "n {n}: {f:?}");
                assert!((f.reflectance_s - f.reflectance_p).abs() < 1e-6);
                // Hecht's convention: r∥ = −r⊥ at normal incidence, r⊥ < 0 going into the
                // denser medium (a phase flip of π on external reflection).
                assert!((f.r_s + f.r_p).abs() < 1e-6);
                assert_eq!(f.r_s < 0.0, cos_theta_i > 0.0, "n {n}, cos {cos_theta_i}: {f:?}");
            }
        }
    }

    #[test]
    fn amplitudes_agree_with_hechts_angle_forms() {
        // Hecht §4.6.3 writes the coefficients through the angles alone (independent of
        // the index form used by the code): r⊥ = −sin(θi−θt)/sin(θi+θt),
        // r∥ = tan(θi−θt)/tan(θi+θt), t⊥ = 2 sinθt cosθi / sin(θi+θt),
        // t∥ = 2 sinθt cosθi / (sin(θi+θt) cos(θi−θt)), with θt from Snell's law.
        for n in [1.333_f64, 1.5, 2.4] {
            for degrees in [5.0_f64, 20.0, 45.0, 60.0, 80.0] {
                let theta_i = degrees.to_radians();
                let theta_t = (theta_i.sin() / n).asin();
                let (sum, diff) = (theta_i + theta_t, theta_i - theta_t);
                let expected_r_s = -diff.sin() / sum.sin();
                let expected_r_p = diff.tan() / sum.tan();
                let expected_t_s = 2.0 * theta_t.sin() * theta_i.cos() / sum.sin();
                let expected_t_p = expected_t_s / diff.cos();
                let f = fresnel_dielectric(theta_i.cos() as f32, n as f32);
                let a = fresnel_dielectric_amplitudes(theta_i.cos() as f32, n as f32);
                let context = format!("n {n}, θi {degrees}°");
                assert!((f.r_s as f64 - expected_r_s).abs() < 2e-6, "{context}: {f:?}");
                assert!((f.r_p as f64 - expected_r_p).abs() < 2e-6, "{context}: {f:?}");
                assert!((a.r_s.re as f64 - expected_r_s).abs() < 2e-6, "{context}: {a:?}");
                assert!((a.r_p.re as f64 - expected_r_p).abs() < 2e-6, "{context}: {a:?}");
                assert!((a.t_s.re as f64 - expected_t_s).abs() < 2e-6, "{context}: {a:?}");
                assert!((a.t_p.re as f64 - expected_t_p).abs() < 2e-6, "{context}: {a:?}");
                assert!((f.cos_theta_t as f64 + theta_t.cos()).abs() < 1e-6, "{context}");
            }
        }
    }

    #[test]
    fn crown_glass_at_45_degrees() {
        // Hecht §4.6 worked numbers for n = 1.5 at 45°: θt = 28.13°, R⊥ = 0.0920, R∥ = 0.0085.
        let f = fresnel_dielectric(std::f32::consts::FRAC_1_SQRT_2, 1.5);
        assert!((f.reflectance_s - 0.0920).abs() < 1e-4, "{f:?}");
        assert!((f.reflectance_p - 0.0085).abs() < 1e-4, "{f:?}");
    }

    #[test]
    fn p_polarisation_vanishes_at_brewsters_angle() {
        // Brewster: tan θB = n_t / n_i = eta_it, where θi + θt = 90° and r∥ = 0 (Hecht §8.6).
        for eta in [1.333_f64, 1.5, 2.4] {
            for (eta_it, sign) in [(eta, 1.0), (1.0 / eta, -1.0)] {
                let cos_brewster = (sign * eta_it.atan().cos()) as f32;
                let f = fresnel_dielectric(cos_brewster, eta as f32);
                assert!(f.r_p.abs() < 1e-6, "eta {eta}, from {sign}: {f:?}");
                assert!(f.reflectance_s > 0.01, "R⊥ does not vanish there: {f:?}");
                // θt is the complement of θB: cos θt = sin θB.
                let sin_brewster = eta_it.atan().sin();
                assert!((f.cos_theta_t.abs() as f64 - sin_brewster).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn total_internal_reflection_past_the_critical_angle() {
        // From inside glass (n = 1.5) sin θc = 1/1.5, θc = 41.81°; beyond it all is reflected.
        // (89.99° rather than 90°: cos 90° rounds to +4e-8 in f32, which would be the exterior.)
        for degrees in [41.9_f32, 50.0, 70.0, 89.0, 89.99] {
            let cos_theta_i = -degrees.to_radians().cos();
            let f = fresnel_dielectric(cos_theta_i, 1.5);
            assert_eq!(f.reflectance, 1.0, "{degrees}°: {f:?}");
            assert_eq!(f.transmittance(), 0.0);
            assert_eq!(f.cos_theta_t, 0.0);
            let a = fresnel_dielectric_amplitudes(cos_theta_i, 1.5);
            assert!((a.reflectance - 1.0).abs() < 1e-6, "{degrees}°: {a:?}");
            assert_eq!(a.transmittance, 0.0);
        }
        // Just short of it, some light still gets out.
        let f = fresnel_dielectric(-41.7_f32.to_radians().cos(), 1.5);
        assert!(f.reflectance < 1.0 && f.cos_theta_t > 0.0, "{f:?}");
    }

    #[test]
    fn total_internal_reflection_phases_follow_hecht() {
        // Hecht §4.7: under TIR r = e^{iδ} with tan(δ⊥/2) = √(sin²θi − n²)/cos θi and
        // tan(δ∥/2) = √(sin²θi − n²)/(n² cos θi), n = n_t/n_i; glass (1.5) to air, n = 1/1.5.
        let n = 1.0 / 1.5_f64;
        for degrees in [45.0_f64, 60.0, 75.0] {
            let theta_i = degrees.to_radians();
            let root = (theta_i.sin().powi(2) - n * n).sqrt();
            let delta_s = 2.0 * (root / theta_i.cos()).atan();
            let delta_p = 2.0 * (root / (n * n * theta_i.cos())).atan();
            let a = fresnel_dielectric_amplitudes(-theta_i.cos() as f32, 1.5);
            assert!((a.r_s.norm() - 1.0).abs() < 1e-6, "{degrees}°: {a:?}");
            assert!((a.r_p.norm() - 1.0).abs() < 1e-6, "{degrees}°: {a:?}");
            assert!((a.r_s.arg() as f64 - delta_s).abs() < 1e-5, "{degrees}°: {a:?}");
            assert!((a.r_p.arg() as f64 - delta_p).abs() < 1e-5, "{degrees}°: {a:?}");
        }
    }

    #[test]
    fn reflection_and_transmission_conserve_energy() {
        // A lossless interface: R + T = 1 for each polarisation (Hecht §4.6.4).
        for eta in ETAS {
            for cos_theta_i in cos_grid() {
                let a = fresnel_dielectric_amplitudes(cos_theta_i, eta);
                let context = format!("eta {eta}, cos θi {cos_theta_i}: {a:?}");
                assert!((a.reflectance_s + a.transmittance_s - 1.0).abs() < 2e-6, "{context}");
                assert!((a.reflectance_p + a.transmittance_p - 1.0).abs() < 2e-6, "{context}");
            }
        }
    }

    #[test]
    fn stokes_relations_hold() {
        // Hecht §4.10: for the reverse path (from the transmitted side at θt),
        // r' = −r and t t' = 1 − r², for each polarisation.
        for eta in [0.75_f32, 1.0 / 1.5, 1.333, 1.5, 2.4] {
            for cos_theta_i in [1.0_f32, 0.9, 0.6, 0.3, -0.2, -0.5, -0.8, -1.0] {
                let forward = fresnel_dielectric_amplitudes(cos_theta_i, eta);
                if forward.transmittance == 0.0 {
                    continue; // total internal reflection: no reverse path
                }
                // The transmitted ray's cosine is the reverse ray's incidence, same sign.
                let reverse = fresnel_dielectric_amplitudes(forward.cos_theta_t, eta);
                let context = format!("eta {eta}, cos θi {cos_theta_i}");
                assert!((reverse.r_s + forward.r_s).norm() < 2e-6, "{context}");
                assert!((reverse.r_p + forward.r_p).norm() < 2e-6, "{context}");
                let s = forward.t_s * reverse.t_s - (one() - forward.r_s * forward.r_s);
                let p = forward.t_p * reverse.t_p - (one() - forward.r_p * forward.r_p);
                assert!(s.norm() < 4e-6 && p.norm() < 4e-6, "{context}: {s} {p}");
            }
        }
    }

    fn one() -> Complex32 {
        Complex32::new(1.0, 0.0)
    }

    #[test]
    fn going_in_and_out_reflect_alike() {
        // Reciprocity: the reflectance entering at θi equals the reflectance leaving at θt,
        // and the reverse ray comes back at the original angle.
        for eta in [1.333_f32, 1.5, 2.4] {
            for degrees in [0.0_f32, 10.0, 30.0, 50.0, 70.0, 85.0] {
                let cos_theta_i = degrees.to_radians().cos();
                let inward = fresnel_dielectric(cos_theta_i, eta);
                let outward = fresnel_dielectric(inward.cos_theta_t, eta);
                // Tolerances: grazing entry maps to a reverse incidence near the critical angle,
                // where R and cos θt change like 1/cos θt per unit cos θi and amplify the f32
                // rounding of cos θt (6e-8) some 10- to 40-fold at 85°.
                let context = format!("eta {eta}, {degrees}°: {inward:?} {outward:?}");
                assert!((inward.reflectance - outward.reflectance).abs() < 5e-6, "{context}");
                assert!((outward.cos_theta_t - cos_theta_i).abs() < 5e-6, "{context}");
                assert!((inward.eta_it * outward.eta_it - 1.0).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn transmitted_angle_obeys_snell() {
        // sin θt = sin θi / eta_it, with eta_it = eta from outside and 1/eta from inside.
        for eta in ETAS {
            for cos_theta_i in cos_grid() {
                let a = fresnel_dielectric_amplitudes(cos_theta_i, eta);
                let from_exterior = cos_theta_i >= 0.0;
                let expected_eta_it = if from_exterior { eta } else { 1.0 / eta };
                // Within an ulp: the amplitudes form its reciprocal as eta / eta².
                assert!((a.eta_it - expected_eta_it).abs() <= 2e-7 * expected_eta_it, "{a:?}");
                assert!((a.eta_it * a.eta_ti - 1.0).abs() < 1e-6);
                if a.transmittance > 0.0 {
                    let sin_i = (1.0 - cos_theta_i as f64 * cos_theta_i as f64).max(0.0).sqrt();
                    let sin_t = (1.0 - a.cos_theta_t as f64 * a.cos_theta_t as f64).sqrt();
                    assert!((sin_i - a.eta_it as f64 * sin_t).abs() < 1e-5, "{a:?}");
                    // The transmitted ray crosses to the other side (unless it grazes it).
                    if a.cos_theta_t != 0.0 {
                        assert_eq!(a.cos_theta_t < 0.0, from_exterior, "{a:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn matched_indices_do_not_reflect() {
        // eta = 1: no interface at all, even at grazing incidence; the ray goes straight on.
        for cos_theta_i in [1.0_f32, 0.5, 0.0, -0.5, -1.0] {
            let f = fresnel_dielectric(cos_theta_i, 1.0);
            assert_eq!(f.reflectance, 0.0);
            assert!((f.cos_theta_t + cos_theta_i).abs() < 1e-6, "{f:?}");
            let a = fresnel_dielectric_amplitudes(cos_theta_i, 1.0);
            assert_eq!(a.transmittance, 1.0);
        }
    }

    #[test]
    fn grazing_incidence_reflects_everything() {
        // θi → 90°: r⊥ → −1 and r∥ → −1, R → 1 for any mismatched interface (Hecht §4.6.3).
        for eta in [0.5_f32, 1.0001, 1.5, 2.4] {
            let f = fresnel_dielectric(0.0, eta);
            assert_eq!(f.reflectance, 1.0, "eta {eta}: {f:?}");
        }
    }

    #[test]
    fn never_nan_on_the_whole_domain() {
        // Exact ±1 and 0, critical angles and their f32 neighbours, rarer and denser media.
        for eta in ETAS {
            for cos_theta_i in cos_grid() {
                let f = fresnel_dielectric(cos_theta_i, eta);
                let a = fresnel_dielectric_amplitudes(cos_theta_i, eta);
                let values = [
                    f.r_s,
                    f.r_p,
                    f.reflectance_s,
                    f.reflectance_p,
                    f.reflectance,
                    f.cos_theta_t,
                    f.eta_it,
                    a.r_s.re,
                    a.r_s.im,
                    a.r_p.re,
                    a.r_p.im,
                    a.t_s.re,
                    a.t_s.im,
                    a.t_p.re,
                    a.t_p.im,
                    a.transmittance_s,
                    a.transmittance_p,
                    a.transmittance,
                    a.cos_theta_t,
                    a.eta_ti,
                ];
                assert!(values.iter().all(|v| v.is_finite()), "eta {eta}, cos {cos_theta_i}");
                assert!((0.0..=1.0).contains(&f.reflectance), "{f:?}");
            }
        }
    }

    #[test]
    fn real_and_complex_forms_agree_where_well_conditioned() {
        // The two functions round cos² θt differently (as Mitsuba's fresnel and
        // fresnel_polarized do), by δ ≲ 4e-7 (a few float32 roundings of terms ≤ 1). That moves
        // cos θt by δ/(2|cos θt|), and r by |∂r/∂cos θt| ≤ 1/(2|cos θt|) times that (the
        // maximum over cos θi of 2 eta cos θi/(cos θi + eta cos θt)²): with |cos θt| > 0.1, by
        // at most 25 δ ≲ 1e-5. Under total internal reflection both give R = 1. Only the
        // points within rounding of cos θt = 0 are left out.
        let mut compared = 0;
        for eta in ETAS {
            for cos_theta_i in cos_grid() {
                let f = fresnel_dielectric(cos_theta_i, eta);
                let a = fresnel_dielectric_amplitudes(cos_theta_i, eta);
                let context = format!("eta {eta}, cos θi {cos_theta_i}: {f:?} {a:?}");
                if f.cos_theta_t.abs() > 0.1 {
                    compared += 1;
                    assert!((f.cos_theta_t - a.cos_theta_t).abs() < 2e-6, "{context}");
                    assert!((f.reflectance - a.reflectance).abs() < 1e-5, "{context}");
                    assert!((f.r_s - a.r_s.re).abs() < 1e-5 && a.r_s.im == 0.0, "{context}");
                    assert!((f.r_p - a.r_p.re).abs() < 1e-5 && a.r_p.im == 0.0, "{context}");
                } else if f.cos_theta_t == 0.0 && a.cos_theta_t == 0.0 && eta != 1.0 {
                    compared += 1;
                    assert!((a.reflectance - 1.0).abs() < 1e-6, "{context}");
                }
                assert!((f.eta_it - a.eta_it).abs() <= 2e-7 * f.eta_it, "{context}");
            }
        }
        // Most of the 9 × 455 points.
        assert!(compared > 3500, "{compared}");
    }
}
