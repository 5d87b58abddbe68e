//! [`SampledWavelengths`]: the wavelengths one camera sample carries and their sampling densities.
//!
//! A camera sample carries a hero wavelength and `count - 1` stratified rotations of it
//! (Wilkie et al. 2014, "Hero Wavelength Spectral Sampling"): one uniform number `u` gives
//! `u_i = frac(u + i / count)`, and each `u_i` is mapped through the inverse CDF of the
//! visible-importance density of pbrt-v4 (`SampleVisibleWavelengths` in `util/spectrum.h`;
//! Pharr, Jakob & Humphreys, "Physically Based Rendering", 4th ed.) and Mitsuba 3
//! (`sample_rgb_spectrum`):
//!
//! ```text
//! p(λ) = k / ((T_max − T_min) · cosh²(k (λ − 538 nm))),   k = 0.0072 nm⁻¹,  λ ∈ [360, 830] nm
//! ```
//!
//! Derivation: `∫ sech²(k(λ − c)) dλ = tanh(k(λ − c)) / k`, so with `T(λ) = tanh(k(λ − 538))`,
//! `T_min = T(360)` and `T_max = T(830)` the CDF is `(T(λ) − T_min) / (T_max − T_min)`, and its
//! inverse is `λ(u) = 538 + atanh(T_min + u (T_max − T_min)) / k`. (pbrt-v4's constants
//! 0.0039398042, 0.85691062 and 1.82750197 are `k / (T_max − T_min)`, `−T_min` and
//! `T_max − T_min`; a test checks them.) The density follows the luminous efficiency roughly, so
//! wavelengths the eye barely sees are rarely sampled, yet it is positive over the whole range:
//! the estimator stays unbiased for spectra that matter only there.

use std::sync::LazyLock;

use super::{SampledSpectrum, LAMBDA_MAX_NM, LAMBDA_MIN_NM, N_LAMBDA};

/// Centre of the visible-importance density, in nm.
const VISIBLE_CENTRE_NM: f32 = 538.0;
/// Rate of the visible-importance density, per nm (`p ∝ 1/cosh²(rate · (λ − centre))`).
const VISIBLE_RATE_PER_NM: f32 = 0.0072;

/// `tanh(k (λ − 538 nm))` at 360 nm and at 830 nm: the CDF's end values before normalisation
/// (computed once: `tanh` is not a `const fn`).
static VISIBLE_TANH_BOUNDS: LazyLock<(f32, f32)> = LazyLock::new(|| {
    (
        (VISIBLE_RATE_PER_NM * (LAMBDA_MIN_NM - VISIBLE_CENTRE_NM)).tanh(),
        (VISIBLE_RATE_PER_NM * (LAMBDA_MAX_NM - VISIBLE_CENTRE_NM)).tanh(),
    )
});

/// The visible-importance density at `lambda_nm`, per nm: `p(λ) ∝ 1/cosh²(0.0072 (λ − 538))`
/// normalised over 360–830 nm, and 0 outside that range.
pub fn visible_pdf_per_nm(lambda_nm: f32) -> f32 {
    if !(LAMBDA_MIN_NM..=LAMBDA_MAX_NM).contains(&lambda_nm) {
        return 0.0;
    }
    let (tanh_min, tanh_max) = *VISIBLE_TANH_BOUNDS;
    let cosh = (VISIBLE_RATE_PER_NM * (lambda_nm - VISIBLE_CENTRE_NM)).cosh();
    VISIBLE_RATE_PER_NM / ((tanh_max - tanh_min) * cosh * cosh)
}

/// The wavelength in nm (within 360–830) at which the CDF of [`visible_pdf_per_nm`] equals `u`
/// in [0, 1]: the inverse-CDF sample of the visible-importance density.
pub fn sample_visible_lambda_nm(u: f32) -> f32 {
    debug_assert!((0.0..=1.0).contains(&u), "u = {u} outside [0, 1]");
    let (tanh_min, tanh_max) = *VISIBLE_TANH_BOUNDS;
    let lambda_nm = VISIBLE_CENTRE_NM + (tanh_min + u * (tanh_max - tanh_min)).atanh() / VISIBLE_RATE_PER_NM;
    // f32 rounding in tanh/atanh can land a hair outside the range at u = 0 or 1.
    lambda_nm.clamp(LAMBDA_MIN_NM, LAMBDA_MAX_NM)
}

/// Wavelengths (nm) of one camera sample with their probability densities (per nm).
///
/// Lanes at index `>= active` are unused: their pdf is zero and the film ignores them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledWavelengths {
    lambda_nm: [f32; N_LAMBDA],
    pdf_per_nm: [f32; N_LAMBDA],
    active: usize,
    monochromatic: bool,
}

impl SampledWavelengths {
    /// Samples `count` (1..=N_LAMBDA) wavelengths from one uniform number `u` in [0, 1): a hero
    /// wavelength and `count - 1` stratified rotations of it, all importance-sampled over
    /// 360–830 nm. Panics if `count` is 0 or larger than `N_LAMBDA`.
    pub fn sample_visible(u: f32, count: usize) -> Self {
        assert!((1..=N_LAMBDA).contains(&count), "wavelength count {count} outside 1..={N_LAMBDA}");
        debug_assert!((0.0..1.0).contains(&u), "u = {u} outside [0, 1)");
        let mut lambda_nm = [0.0; N_LAMBDA];
        let mut pdf_per_nm = [0.0; N_LAMBDA];
        for lane in 0..count {
            let u_lane = (u + lane as f32 / count as f32).fract();
            lambda_nm[lane] = sample_visible_lambda_nm(u_lane);
            pdf_per_nm[lane] = visible_pdf_per_nm(lambda_nm[lane]);
        }
        // Inactive lanes repeat the hero wavelength so that anything evaluated there is finite;
        // their zero pdf keeps them out of the film.
        let hero_nm = lambda_nm[0];
        lambda_nm[count..].fill(hero_nm);
        Self { lambda_nm, pdf_per_nm, active: count, monochromatic: false }
    }
    /// A single fixed wavelength (lane 0 only, pdf 1): the `--wavelength` monochromatic mode.
    pub fn monochromatic(lambda_nm: f32) -> Self {
        let mut lambda = [lambda_nm; N_LAMBDA];
        lambda[0] = lambda_nm;
        let mut pdf = [0.0; N_LAMBDA];
        pdf[0] = 1.0;
        Self { lambda_nm: lambda, pdf_per_nm: pdf, active: 1, monochromatic: true }
    }
    /// Wavelength of lane `i`, in nm.
    #[inline]
    pub fn lambda_nm(&self, i: usize) -> f32 {
        self.lambda_nm[i]
    }
    /// Probability density of lane `i`, per nm (0 for inactive lanes).
    #[inline]
    pub fn pdf_per_nm(&self, i: usize) -> f32 {
        self.pdf_per_nm[i]
    }
    /// Number of active lanes (lanes `0..active`).
    #[inline]
    pub fn active(&self) -> usize {
        self.active
    }
    /// True in the single-wavelength `--wavelength` mode.
    #[inline]
    pub fn is_monochromatic(&self) -> bool {
        self.monochromatic
    }
    /// 1 on active lanes, 0 on the others: the starting throughput of a camera ray.
    #[inline]
    pub fn active_mask(&self) -> SampledSpectrum {
        SampledSpectrum { values: std::array::from_fn(|i| if i < self.active { 1.0 } else { 0.0 }) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_core::{RngCore, SeedableRng};

    /// Composite Simpson's rule of `f` over [a, b] with `intervals` (even) sub-intervals.
    fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, intervals: usize) -> f64 {
        let h = (b - a) / intervals as f64;
        let inner: f64 =
            (1..intervals).map(|i| if i % 2 == 1 { 4.0 } else { 2.0 } * f(a + i as f64 * h)).sum();
        (f(a) + inner + f(b)) * h / 3.0
    }

    /// A uniform number in [0, 1) from 24 random bits (exactly representable in f32).
    fn uniform(rng: &mut rand_pcg::Pcg32) -> f32 {
        (rng.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    /// A probability density integrates to 1 over its support, 360–830 nm (Simpson, 4700
    /// intervals: the integrand is smooth, so the quadrature error is far below 1e-5).
    #[test]
    fn visible_pdf_integrates_to_one() {
        let total = simpson(|l| visible_pdf_per_nm(l as f32) as f64, 360.0, 830.0, 4700);
        assert!((total - 1.0).abs() < 1e-5, "∫p = {total}");
        assert_eq!(visible_pdf_per_nm(359.0), 0.0);
        assert_eq!(visible_pdf_per_nm(831.0), 0.0);
    }

    /// Our analytic normalisation and inverse CDF reproduce pbrt-v4's published constants
    /// (`SampleVisibleWavelengths`: λ = 538 − 138.888889·atanh(0.85691062 − 1.82750197 u),
    /// pdf = 0.0039398042 / cosh²(0.0072 (λ − 538))).
    #[test]
    fn visible_density_matches_pbrt_v4_constants() {
        let (tanh_min, tanh_max) = *VISIBLE_TANH_BOUNDS;
        assert!((-tanh_min - 0.856_910_6).abs() < 1e-6);
        assert!((tanh_max - tanh_min - 1.827_502).abs() < 1e-6);
        assert!((f64::from(visible_pdf_per_nm(538.0)) - 0.003_939_804_2).abs() < 1e-9);
        for u in [0.1_f32, 0.5, 0.9] {
            let pbrt_nm = 538.0 - 138.888_89 * (0.856_910_6 - 1.827_502 * u).atanh();
            assert!((sample_visible_lambda_nm(u) - pbrt_nm).abs() < 1e-3);
        }
    }

    /// The inverse CDF maps u = 0 and u = 1 to the range ends, and is the inverse of the CDF:
    /// the pdf integrated from 360 nm up to λ(u) gives back u.
    #[test]
    fn inverse_cdf_inverts_the_integrated_pdf() {
        assert!((sample_visible_lambda_nm(0.0) - 360.0).abs() < 1e-3);
        assert!((sample_visible_lambda_nm(1.0) - 830.0).abs() < 1e-3);
        for u in [0.05, 0.25, 0.5, 0.75, 0.95] {
            let lambda_nm = sample_visible_lambda_nm(u) as f64;
            let cdf = simpson(|l| visible_pdf_per_nm(l as f32) as f64, 360.0, lambda_nm, 2000);
            assert!((cdf - u as f64).abs() < 1e-5, "u = {u}: CDF(λ(u)) = {cdf}");
        }
    }

    /// Every active lane lies in 360–830 nm with a positive pdf equal to the density there; the
    /// lanes are the rotations frac(u + i/count), so for count = 4 their u values are 1/4 apart;
    /// inactive lanes have pdf 0.
    #[test]
    fn sample_visible_stays_in_range_and_stratifies() {
        let mut rng = rand_pcg::Pcg32::seed_from_u64(0x5eed_0001);
        for count in 1..=N_LAMBDA {
            for _ in 0..10_000 {
                let u = uniform(&mut rng);
                let wavelengths = SampledWavelengths::sample_visible(u, count);
                assert_eq!(wavelengths.active(), count);
                assert!(!wavelengths.is_monochromatic());
                for lane in 0..N_LAMBDA {
                    let lambda_nm = wavelengths.lambda_nm(lane);
                    assert!((360.0..=830.0).contains(&lambda_nm), "λ = {lambda_nm}");
                    let pdf = wavelengths.pdf_per_nm(lane);
                    if lane < count {
                        let u_lane = (u + lane as f32 / count as f32).fract();
                        assert_eq!(lambda_nm, sample_visible_lambda_nm(u_lane));
                        assert_eq!(pdf, visible_pdf_per_nm(lambda_nm));
                        assert!(pdf > 0.0);
                    } else {
                        assert_eq!(pdf, 0.0);
                    }
                }
            }
        }
        let mask = SampledWavelengths::sample_visible(0.3, 2).active_mask();
        assert_eq!(mask.values, [1.0, 1.0, 0.0, 0.0]);
    }

    /// A histogram of 400 000 hero wavelengths (seeded) over 47 bins of 10 nm matches the pdf
    /// integrated over each bin: every bin's count is within 5 binomial standard deviations.
    #[test]
    fn histogram_of_samples_matches_the_pdf() {
        const SAMPLES: usize = 400_000;
        const BINS: usize = 47;
        let mut counts = [0usize; BINS];
        let mut rng = rand_pcg::Pcg32::seed_from_u64(0x5eed_0002);
        for _ in 0..SAMPLES {
            let lambda_nm = SampledWavelengths::sample_visible(uniform(&mut rng), 1).lambda_nm(0);
            counts[(((lambda_nm - 360.0) / 10.0) as usize).min(BINS - 1)] += 1;
        }
        for (bin, &count) in counts.iter().enumerate() {
            let start_nm = 360.0 + 10.0 * bin as f64;
            let probability = simpson(|l| visible_pdf_per_nm(l as f32) as f64, start_nm, start_nm + 10.0, 20);
            let expected = probability * SAMPLES as f64;
            let sigma = (expected * (1.0 - probability)).sqrt();
            assert!(
                (count as f64 - expected).abs() < 5.0 * sigma,
                "bin {start_nm} nm: {count} samples, expected {expected:.0} ± {sigma:.0}"
            );
        }
    }

    /// `count` outside 1..=N_LAMBDA is a programming error.
    #[test]
    #[should_panic(expected = "wavelength count 0")]
    fn sample_visible_rejects_zero_count() {
        SampledWavelengths::sample_visible(0.5, 0);
    }
}
