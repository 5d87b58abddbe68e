//! The CIE 1931 2° standard observer and the spectral → XYZ conversion of a sampled estimate.
//!
//! The colour-matching functions x̄, ȳ, z̄ are the 1 nm table of ISO 11664-1:2007 /
//! CIE S 014-1:2006, 360–830 nm, embedded from `data/cie1931_2deg.csv` (whose header names the
//! package the numbers were extracted from), and linearly interpolated between table points.
//!
//! Normalisation (the one Mitsuba 3 uses for spectral → XYZ): `XYZ = ∫ L(λ)·cmf(λ) dλ / ∫ ȳ(λ) dλ`,
//! so an equal-energy spectrum of value 1 has Y = 1, and Y has the unit of the spectral quantity
//! itself (a radiance in W·m⁻²·sr⁻¹·nm⁻¹ gives Y in W·m⁻²·sr⁻¹·nm⁻¹): "Y = 1 is as bright as a
//! flat spectrum of 1".

use std::sync::OnceLock;

use glam::{Vec3, Vec3A};

use super::tables::{cmf_table, grid_lambda_nm, trapezoid_weight_nm, GridPosition, GRID_LEN};
use super::{SampledSpectrum, SampledWavelengths, LAMBDA_MAX_NM, LAMBDA_MIN_NM, N_LAMBDA};

/// ∫ ȳ(λ) dλ over 360–830 nm of the shipped table (nm). An equal-energy spectrum of value 1 has
/// Y = 1 under prisma's (and Mitsuba 3's) convention `XYZ = ∫ L·cmf dλ / ∫ ȳ dλ`.
///
/// Computed once with the trapezoid rule on the 1 nm table, which is the exact integral of the
/// interpolated ȳ that [`cmf`] returns (so the Monte Carlo estimate of [`to_xyz`] is unbiased for
/// the same normalisation): 106.856 nm.
pub fn cie_y_integral() -> f32 {
    observer().y_integral_nm
}

/// The colour-matching table with its ȳ integral, behind one initialisation check (the hot path
/// reads both for every camera sample).
struct Observer {
    cmf: &'static [Vec3A; GRID_LEN],
    y_integral_nm: f32,
}

/// The observer's tables, computed on first use.
fn observer() -> &'static Observer {
    static OBSERVER: OnceLock<Observer> = OnceLock::new();
    OBSERVER.get_or_init(|| {
        let cmf = cmf_table();
        let y_integral_nm =
            (0..GRID_LEN).map(|i| trapezoid_weight_nm(i) * cmf[i].y as f64).sum::<f64>() as f32;
        Observer { cmf, y_integral_nm }
    })
}

/// The colour-matching functions (x̄, ȳ, z̄) at `lambda_nm`, linearly interpolated; zero outside
/// 360–830 nm.
pub fn cmf(lambda_nm: f32) -> Vec3 {
    if !(LAMBDA_MIN_NM..=LAMBDA_MAX_NM).contains(&lambda_nm) {
        return Vec3::ZERO;
    }
    Vec3::from(GridPosition::of(lambda_nm).lerp_vec3(cmf_table()))
}

/// Monte Carlo estimate of XYZ from radiance sampled at `wavelengths`: the only place where the
/// wavelength pdf is divided out. In monochromatic mode it returns (L, L, L) of lane 0 instead.
///
/// The estimate is `Σ_active L(λ_i)·cmf(λ_i) / p(λ_i) / active / ∫ȳ`: lane i samples the i-th
/// 1/active of the sampling CDF, with density active·p there, so its term estimates that part of
/// `∫ L·cmf dλ` without bias and the sum estimates the whole.
#[inline]
pub fn to_xyz(radiance: &SampledSpectrum, wavelengths: &SampledWavelengths) -> Vec3 {
    if wavelengths.is_monochromatic() {
        return Vec3::splat(radiance[0]);
    }
    spectral_to_xyz(radiance, wavelengths)
}

/// [`to_xyz`] for sampled wavelengths: out of line, so that a monochromatic caller inlines only
/// the test above.
fn spectral_to_xyz(radiance: &SampledSpectrum, wavelengths: &SampledWavelengths) -> Vec3 {
    let active = wavelengths.active();
    let observer = observer();
    let grid = wavelengths.grid();
    // Every lane's weight L/p at once (inactive lanes 0), then the interpolated CMFs: the lanes'
    // grid positions were computed with their wavelengths, so this is `cmf` without finding the
    // positions again.
    // (Selects rather than branches, so that the lanes run as one vector.)
    let mut weights = [0.0f32; N_LAMBDA];
    for (lane, weight) in weights.iter_mut().enumerate() {
        let pdf_per_nm = wavelengths.pdf_per_nm(lane);
        debug_assert!(lane >= active || pdf_per_nm > 0.0, "active lane {lane} has pdf {pdf_per_nm}");
        let quotient = radiance[lane] / if lane < active { pdf_per_nm } else { 1.0 };
        *weight = if lane < active { quotient } else { 0.0 };
    }
    let sum = grid.weighted_sum_vec3(observer.cmf, &weights);
    Vec3::from(sum / (active as f32 * observer.y_integral_nm))
}

/// CIE XYZ of the spectral function `value_at(λ)` (λ in nm) under the same normalisation as
/// [`to_xyz`], by deterministic quadrature: the trapezoid rule on the 1 nm table grid over
/// 360–830 nm, accumulated in f64. Used to normalise spectra when a scene is built and as the
/// exact reference in tests; an equal-energy spectrum of value 1 gives Y = 1.
pub fn xyz_by_quadrature(value_at: impl Fn(f32) -> f32) -> Vec3 {
    let table = cmf_table();
    let mut sum = [0.0_f64; 3];
    for (i, cmf_i) in table.iter().enumerate() {
        let weighted = trapezoid_weight_nm(i) * value_at(grid_lambda_nm(i)) as f64;
        sum[0] += weighted * cmf_i.x as f64;
        sum[1] += weighted * cmf_i.y as f64;
        sum[2] += weighted * cmf_i.z as f64;
    }
    let y_integral_nm = cie_y_integral() as f64;
    Vec3::new(
        (sum[0] / y_integral_nm) as f32,
        (sum[1] / y_integral_nm) as f32,
        (sum[2] / y_integral_nm) as f32,
    )
}

/// Chromaticity (x, y) = (X, Y) / (X + Y + Z) of `xyz`.
pub fn chromaticity(xyz: Vec3) -> [f32; 2] {
    let sum = xyz.x + xyz.y + xyz.z;
    [xyz.x / sum, xyz.y / sum]
}

#[cfg(test)]
mod tests {
    use rand_core::{RngCore, SeedableRng};

    use super::*;

    /// The photopic ȳ peaks at 555 nm with the value 1 by definition of the CIE 1931 tables;
    /// outside the table the functions are zero; between table points they interpolate.
    #[test]
    fn cmf_values_at_known_wavelengths() {
        assert!((cmf(555.0).y - 1.0).abs() < 1e-6);
        assert_eq!(cmf(359.9), Vec3::ZERO);
        assert_eq!(cmf(830.1), Vec3::ZERO);
        assert_eq!(cmf(f32::NAN), Vec3::ZERO);
        assert!((cmf(830.0).x - 1.251_141e-6).abs() < 1e-12);
        let midpoint = cmf(600.5);
        let expected = (cmf(600.0) + cmf(601.0)) * 0.5;
        assert!((midpoint - expected).abs().max_element() < 1e-6);
    }

    /// ∫ȳ over 360–830 nm of the 1 nm table is 106.857 nm (Mitsuba 3's `CIE_Y_integral`,
    /// 106.856895, is the same sum without the half end weights, which are ~2e-6 here).
    #[test]
    fn y_integral_matches_published_value() {
        assert!((cie_y_integral() - 106.856_895).abs() < 1e-3, "{}", cie_y_integral());
    }

    /// The CIE 1931 functions were scaled so that the equal-energy illuminant E has
    /// ∫x̄ = ∫ȳ = ∫z̄: under prisma's normalisation it has Y = 1 and chromaticity (1/3, 1/3).
    #[test]
    fn equal_energy_spectrum_is_white_with_unit_luminance() {
        let xyz = xyz_by_quadrature(|_| 1.0);
        assert!((xyz.y - 1.0).abs() < 1e-6, "Y = {}", xyz.y);
        let [x, y] = chromaticity(xyz);
        assert!((x - 1.0 / 3.0).abs() < 1e-3 && (y - 1.0 / 3.0).abs() < 1e-3, "({x}, {y})");
    }

    /// The Monte Carlo estimator of `to_xyz` over `sample_visible` draws (seeded) converges to the
    /// quadrature value for the equal-energy spectrum, for one lane and for N_LAMBDA stratified
    /// lanes: the mean of 200 000 estimates lies within 5 standard errors of (X, Y, Z)_E. The
    /// standard error is below 5e-3 for one lane (z̄, which peaks where the density is low, is
    /// the noisiest channel) and the stratified lanes must lower it.
    #[test]
    fn monte_carlo_estimate_converges_to_quadrature() {
        const SAMPLES: usize = 200_000;
        let exact = xyz_by_quadrature(|_| 1.0);
        let mut standard_errors = Vec::new();
        for count in [1, crate::spectrum::N_LAMBDA] {
            let mut rng = rand_pcg::Pcg32::seed_from_u64(0x5eed_0003);
            let mut sum = [0.0_f64; 3];
            let mut sum_sq = [0.0_f64; 3];
            for _ in 0..SAMPLES {
                let u = (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
                let wavelengths = SampledWavelengths::sample_visible(u, count);
                let estimate = to_xyz(&wavelengths.active_mask(), &wavelengths);
                for c in 0..3 {
                    sum[c] += estimate[c] as f64;
                    sum_sq[c] += (estimate[c] as f64).powi(2);
                }
            }
            let mut worst_se = 0.0_f64;
            for c in 0..3 {
                let mean = sum[c] / SAMPLES as f64;
                let variance = sum_sq[c] / SAMPLES as f64 - mean * mean;
                let standard_error = (variance / SAMPLES as f64).sqrt();
                assert!(
                    (mean - exact[c] as f64).abs() < 5.0 * standard_error + 1e-6,
                    "count {count}, channel {c}: mean {mean}, exact {}, se {standard_error}",
                    exact[c]
                );
                worst_se = worst_se.max(standard_error);
            }
            assert!(worst_se < 5e-3, "count {count}: standard error {worst_se}");
            standard_errors.push(worst_se);
        }
        assert!(standard_errors[1] < standard_errors[0], "{standard_errors:?}");
    }

    /// With evenly spaced u (u_k = (k + ½)/n) the estimator is a deterministic quadrature of the
    /// same integral, so 10 000 samples already land within 1e-4 of (X, Y, Z)_E: the estimator
    /// is consistent with the exact normalisation, not merely close on average.
    #[test]
    fn evenly_spaced_samples_reproduce_the_equal_energy_white() {
        const SAMPLES: usize = 10_000;
        let exact = xyz_by_quadrature(|_| 1.0);
        let mut sum = Vec3::ZERO;
        for k in 0..SAMPLES {
            let u = (k as f32 + 0.5) / SAMPLES as f32;
            let wavelengths = SampledWavelengths::sample_visible(u, crate::spectrum::N_LAMBDA);
            sum += to_xyz(&wavelengths.active_mask(), &wavelengths);
        }
        let mean = sum / SAMPLES as f32;
        assert!((mean - exact).abs().max_element() < 1e-4, "{mean} vs {exact}");
    }

    /// In monochromatic mode there is no wavelength integral: the film shows lane 0's value grey.
    #[test]
    fn monochromatic_mode_returns_lane_zero_as_grey() {
        let wavelengths = SampledWavelengths::monochromatic(589.0);
        let mut radiance = SampledSpectrum::splat(7.0);
        radiance[0] = 0.25;
        assert_eq!(to_xyz(&radiance, &wavelengths), Vec3::splat(0.25));
    }
}
