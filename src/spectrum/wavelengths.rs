//! [`SampledWavelengths`]: the wavelengths one camera sample carries and their sampling densities.
//!
//! A camera sample carries a hero wavelength and `count - 1` stratified rotations of it
//! (Wilkie et al. 2014, "Hero Wavelength Spectral Sampling"): one uniform number `u` gives the
//! lanes `u_i = (u + i) / count`, 1/count apart, and each `u_i` is mapped through an inverse CDF
//! that follows the
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
//!
//! **Why (u + i)/count and not the usual rotation frac(u + i/count).** Both give the same
//! set of lanes for some u (the rotation's set repeats with period 1/count in u), and both are
//! unbiased with the lanes averaged, but they map stratified values of u differently. The
//! sampler stratifies u over a pixel's samples (one value in each 1/N of [0, 1) for N samples);
//! the rotation folds those N strata onto only N/count distinct lane sets (u and u + 1/count
//! give the same wavelengths), whereas (u + i)/count sends them to N distinct sets, so the
//! N·count wavelengths of a pixel fall one in each 1/(N·count) of [0, 1). On the TP6 scene with
//! four lanes at 16 spp this cut the relMSE against the Mitsuba reference from 1.66e-3 to 1.84e-4
//! (the specular-spheres scene: 2.57e-3 to 5.3e-4). Since the sampler gives a pixel's first 2^m
//! samples their u on an evenly spaced grid (a digitally shifted Sobol dimension, see
//! [`crate::sampler`]), those wavelengths are moreover evenly spaced in the CDF, one grid of
//! 2^m·count points, which integrates smooth spectra much better than one point jittered in
//! each interval (11× less colour noise with four lanes at 2 spp on the Newton prism).
//!
//! **Tabulated, so a sample costs a lookup.** Evaluating `atanh` and `cosh` per lane was a tenth
//! of a TP6 render's instructions (about 320 per camera sample). The renderer instead samples
//! the density whose inverse CDF is the *piecewise-linear* interpolation of the analytic one
//! through [`SEGMENTS`] + 1 knots `λ_j = λ(j / SEGMENTS)`: u falls in segment `j = ⌊u·SEGMENTS⌋`
//! and maps linearly onto `[λ_j, λ_{j+1}]`, so the density is piecewise constant,
//! `p_j = 1 / (SEGMENTS · (λ_{j+1} − λ_j))`. That density is sampled exactly (the estimator
//! stays unbiased: the pdf divided out is the one sampled), integrates to 1 by construction, is
//! positive everywhere on 360–830 nm, keeps the stratification of u (the map is monotonic), and
//! lies within 1.5 % of the analytic p(λ) (tested; the analytic density itself changes by 3 %
//! across the widest segment, 2.1 nm at 830 nm), which leaves the variance as it was. The knots
//! are computed once, in f64.
//!
//! Each lane also records where its wavelength falls on the shared 1 nm grid of the spectral
//! tables ([`SampledWavelengths::grid`]), so that every spectrum looked up for the sample (all
//! tabulated on that grid: [`super::DenseSpectrum`], the CIE functions) is one interpolation.

use std::sync::LazyLock;

use super::tables::GridPositions;
use super::{SampledSpectrum, LAMBDA_MAX_NM, LAMBDA_MIN_NM, N_LAMBDA};
use crate::float_index::floor_index;

/// Centre of the visible-importance density, in nm.
const VISIBLE_CENTRE_NM: f64 = 538.0;
/// Rate of the visible-importance density, per nm (`p ∝ 1/cosh²(rate · (λ − centre))`).
const VISIBLE_RATE_PER_NM: f64 = 0.0072;

/// Segments of the tabulated inverse CDF. At 2048 the segments are 0.12 nm wide at the density's
/// peak and 2.1 nm at 830 nm, where it is lowest; the table takes 24 KiB.
pub const SEGMENTS: usize = 2048;

/// `tanh(k (λ − 538 nm))` at 360 nm and at 830 nm: the CDF's end values before normalisation.
fn visible_tanh_bounds() -> (f64, f64) {
    (
        (VISIBLE_RATE_PER_NM * (f64::from(LAMBDA_MIN_NM) - VISIBLE_CENTRE_NM)).tanh(),
        (VISIBLE_RATE_PER_NM * (f64::from(LAMBDA_MAX_NM) - VISIBLE_CENTRE_NM)).tanh(),
    )
}

/// The analytic visible-importance density at `lambda_nm` (within 360–830 nm), per nm.
pub fn analytic_visible_pdf_per_nm(lambda_nm: f64) -> f64 {
    let (tanh_min, tanh_max) = visible_tanh_bounds();
    let cosh = (VISIBLE_RATE_PER_NM * (lambda_nm - VISIBLE_CENTRE_NM)).cosh();
    VISIBLE_RATE_PER_NM / ((tanh_max - tanh_min) * cosh * cosh)
}

/// The analytic inverse CDF of [`analytic_visible_pdf_per_nm`]: the wavelength (nm) at which
/// the CDF equals `u` in [0, 1].
pub fn analytic_visible_lambda_nm(u: f64) -> f64 {
    let (tanh_min, tanh_max) = visible_tanh_bounds();
    (VISIBLE_CENTRE_NM + (tanh_min + u * (tanh_max - tanh_min)).atanh() / VISIBLE_RATE_PER_NM)
        .clamp(f64::from(LAMBDA_MIN_NM), f64::from(LAMBDA_MAX_NM))
}

/// One segment of the tabulated inverse CDF: u in [j, j + 1)/SEGMENTS maps linearly onto
/// [`start_nm`, `start_nm + width_nm`), where the density is `pdf_per_nm`. The three values a lane
/// needs sit together, so a lane's lookup touches one cache line (two when a record straddles
/// a line boundary).
#[derive(Clone, Copy, Debug)]
struct Segment {
    /// `λ_j` (nm).
    start_nm: f32,
    /// `λ_{j+1} − λ_j` (nm).
    width_nm: f32,
    /// `p_j = 1 / (SEGMENTS · width_j)` (per nm).
    pdf_per_nm: f32,
}

/// The segments; the first starts at 360 nm and the last ends at 830 nm.
static VISIBLE_TABLE: LazyLock<[Segment; SEGMENTS]> = LazyLock::new(|| {
    let knots_nm: [f32; SEGMENTS + 1] =
        std::array::from_fn(|j| analytic_visible_lambda_nm(j as f64 / SEGMENTS as f64) as f32);
    std::array::from_fn(|j| Segment {
        start_nm: knots_nm[j],
        width_nm: knots_nm[j + 1] - knots_nm[j],
        pdf_per_nm: (1.0 / (SEGMENTS as f64 * (f64::from(knots_nm[j + 1]) - f64::from(knots_nm[j])))) as f32,
    })
});

/// The density that [`SampledWavelengths::sample_visible`] samples, at `lambda_nm`, per nm: the
/// piecewise-constant `p_j` of the segment holding it, and 0 outside 360–830 nm.
pub fn visible_pdf_per_nm(lambda_nm: f32) -> f32 {
    if !(LAMBDA_MIN_NM..=LAMBDA_MAX_NM).contains(&lambda_nm) {
        return 0.0;
    }
    let table = &*VISIBLE_TABLE;
    let segment = table.partition_point(|segment| segment.start_nm <= lambda_nm).clamp(1, SEGMENTS) - 1;
    table[segment].pdf_per_nm
}

/// The wavelength in nm (within 360–830) that [`SampledWavelengths::sample_visible`] gives a
/// lane with uniform number `u` in [0, 1), and that segment's density (per nm).
#[inline]
pub fn sample_visible_lambda_nm(u: f32) -> (f32, f32) {
    segment_sample(&VISIBLE_TABLE, u)
}

/// [`sample_visible_lambda_nm`] with the table at hand (the camera sample's lanes look it up
/// once).
#[inline(always)]
fn segment_sample(table: &[Segment; SEGMENTS], u: f32) -> (f32, f32) {
    debug_assert!((0.0..=1.0).contains(&u), "u = {u} outside [0, 1]");
    let scaled = u * SEGMENTS as f32;
    // u = 1 (and rounding just below it) stays in the last segment.
    let segment = floor_index(scaled, SEGMENTS as u32 - 1) as usize;
    let within = scaled - segment as f32;
    let Segment { start_nm, width_nm, pdf_per_nm } = table[segment];
    ((start_nm + within * width_nm).min(LAMBDA_MAX_NM), pdf_per_nm)
}

/// Wavelengths (nm) of one camera sample with their probability densities (per nm) and their
/// places on the 1 nm table grid.
///
/// Lanes at index `>= active` are unused: their pdf is zero and the film ignores them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledWavelengths {
    lambda_nm: [f32; N_LAMBDA],
    pdf_per_nm: [f32; N_LAMBDA],
    grid: GridPositions,
    active: usize,
    /// The first live lane: 0, or lane `i` alone for [`SampledWavelengths::lane_alone`].
    first_live: usize,
    monochromatic: bool,
}

impl SampledWavelengths {
    /// Samples `count` (1..=N_LAMBDA) wavelengths from one uniform number `u` in [0, 1): the
    /// lanes (u + i)/count of the sampling CDF, 1/count apart, each importance-sampled over
    /// 360–830 nm. Panics if `count` is 0 or larger than `N_LAMBDA`.
    #[inline]
    pub fn sample_visible(u: f32, count: usize) -> Self {
        assert!((1..=N_LAMBDA).contains(&count), "wavelength count {count} outside 1..={N_LAMBDA}");
        debug_assert!((0.0..1.0).contains(&u), "u = {u} outside [0, 1)");
        // u_i = (u + i)/count for the active lanes (see the module notes); inactive lanes take
        // the hero's wavelength, so that anything evaluated there is finite, and pdf 0, which
        // keeps them out of the film. Written lane-parallel, so that it compiles to vector
        // arithmetic around the table loads. The product can round up to 1 for count = 3, which
        // the table lookup keeps in its last segment.
        let step = 1.0 / count as f32;
        let table = &*VISIBLE_TABLE;
        let mut lambda_nm = [0.0; N_LAMBDA];
        let mut pdf_per_nm = [0.0; N_LAMBDA];
        for lane in 0..N_LAMBDA {
            let offset = if lane < count { lane as f32 } else { 0.0 };
            let (lane_nm, lane_pdf) = segment_sample(table, (u + offset) * step);
            lambda_nm[lane] = lane_nm;
            pdf_per_nm[lane] = if lane < count { lane_pdf } else { 0.0 };
        }
        Self {
            lambda_nm,
            pdf_per_nm,
            grid: GridPositions::of(&lambda_nm),
            active: count,
            first_live: 0,
            monochromatic: false,
        }
    }
    /// A single fixed wavelength (lane 0 only, pdf 1): the `--wavelength` monochromatic mode.
    pub fn monochromatic(lambda_nm: f32) -> Self {
        let mut pdf = [0.0; N_LAMBDA];
        pdf[0] = 1.0;
        Self {
            lambda_nm: [lambda_nm; N_LAMBDA],
            pdf_per_nm: pdf,
            grid: GridPositions::of(&[lambda_nm; N_LAMBDA]),
            active: 1,
            first_live: 0,
            monochromatic: true,
        }
    }
    /// Wavelength of lane `i`, in nm.
    #[inline]
    pub fn lambda_nm(&self, i: usize) -> f32 {
        self.lambda_nm[i]
    }
    /// The sampling density p at lane `i`'s wavelength, per nm (0 for inactive lanes). Lane `i`
    /// alone covers the i-th 1/active of the CDF, with density active·p; the film's estimate
    /// averages L/p over the lanes, which is the same thing.
    #[inline]
    pub fn pdf_per_nm(&self, i: usize) -> f32 {
        self.pdf_per_nm[i]
    }
    /// Where each lane's wavelength falls on the 1 nm table grid (clamped to 360–830 nm).
    #[inline]
    pub(crate) fn grid(&self) -> &GridPositions {
        &self.grid
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
    /// The same wavelengths with lane `lane` (< [`Self::active`]) the only live one: its
    /// [`Self::active_mask`] is 1 there and 0 elsewhere, so an integrator given it traces that
    /// lane alone (a lens-system camera, whose ray differs per wavelength). The wavelengths and
    /// densities stay those of the whole sample; [`Self::active`] becomes `lane + 1`, so this
    /// is for the integrator only: the film is given the whole sample's wavelengths with the
    /// lanes' results put together.
    pub fn lane_alone(&self, lane: usize) -> Self {
        debug_assert!(lane < self.active, "lane {lane} of {} active", self.active);
        Self { first_live: lane, active: lane + 1, ..*self }
    }
    /// 1 on active lanes, 0 on the others: the starting throughput of a camera ray.
    #[inline]
    pub fn active_mask(&self) -> SampledSpectrum {
        // Lane by lane, so that it is made in a register: a fill of the first `active` lanes
        // was a masked store read back at once by a wide load, which the processor cannot
        // forward (about 3 % of a camera sample's time in a monochromatic render).
        SampledSpectrum {
            values: std::array::from_fn(|lane| {
                if lane >= self.first_live && lane < self.active {
                    1.0
                } else {
                    0.0
                }
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::tables::GridPosition;
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

    /// The analytic density integrates to 1 over 360–830 nm (Simpson, 4700 intervals: the
    /// integrand is smooth, so the quadrature error is far below 1e-9), and so does the
    /// tabulated one, exactly: Σ p_j·width_j = Σ 1/SEGMENTS. Outside the range it is 0.
    #[test]
    fn visible_pdf_integrates_to_one() {
        let total = simpson(analytic_visible_pdf_per_nm, 360.0, 830.0, 4700);
        assert!((total - 1.0).abs() < 1e-9, "∫p = {total}");
        let table = &*VISIBLE_TABLE;
        let tabulated: f64 = table.iter().map(|s| f64::from(s.pdf_per_nm) * f64::from(s.width_nm)).sum();
        assert!((tabulated - 1.0).abs() < 1e-5, "Σ p_j·width_j = {tabulated}");
        assert_eq!(table[0].start_nm, 360.0);
        assert_eq!(table[SEGMENTS - 1].start_nm + table[SEGMENTS - 1].width_nm, 830.0);
        assert_eq!(visible_pdf_per_nm(359.0), 0.0);
        assert_eq!(visible_pdf_per_nm(831.0), 0.0);
    }

    /// The analytic normalisation and inverse CDF reproduce pbrt-v4's published constants
    /// (`SampleVisibleWavelengths`: λ = 538 − 138.888889·atanh(0.85691062 − 1.82750197 u),
    /// pdf = 0.0039398042 / cosh²(0.0072 (λ − 538))).
    #[test]
    fn visible_density_matches_pbrt_v4_constants() {
        let (tanh_min, tanh_max) = visible_tanh_bounds();
        assert!((-tanh_min - 0.856_910_62).abs() < 1e-8);
        assert!((tanh_max - tanh_min - 1.827_501_97).abs() < 1e-8);
        assert!((analytic_visible_pdf_per_nm(538.0) - 0.003_939_804_2).abs() < 1e-10);
        for u in [0.1_f64, 0.5, 0.9] {
            let pbrt_nm = 538.0 - 138.888_889 * (0.856_910_62 - 1.827_501_97 * u).atanh();
            assert!((analytic_visible_lambda_nm(u) - pbrt_nm).abs() < 1e-4);
        }
    }

    /// The analytic inverse CDF maps u = 0 and u = 1 to the range ends, and is the inverse of the
    /// CDF: the pdf integrated from 360 nm up to λ(u) gives back u.
    #[test]
    fn inverse_cdf_inverts_the_integrated_pdf() {
        assert!((analytic_visible_lambda_nm(0.0) - 360.0).abs() < 1e-9);
        assert!((analytic_visible_lambda_nm(1.0) - 830.0).abs() < 1e-9);
        for u in [0.05, 0.25, 0.5, 0.75, 0.95] {
            let lambda_nm = analytic_visible_lambda_nm(u);
            let cdf = simpson(analytic_visible_pdf_per_nm, 360.0, lambda_nm, 2000);
            assert!((cdf - u).abs() < 1e-9, "u = {u}: CDF(λ(u)) = {cdf}");
        }
    }

    /// The tabulated sampling follows the analytic one: λ(u) within 0.01 nm of the analytic
    /// inverse CDF (the error of linear interpolation between knots, 0.008 nm at most, in the
    /// last segments where λ(u) curves most), and the piecewise-constant density within 1.5 %
    /// of the analytic density (which changes by 3 % across the widest segment, 2.1 nm).
    #[test]
    fn tabulated_sampling_follows_the_analytic_density() {
        for i in 0..=100_000 {
            let u = i as f32 / 100_000.0;
            let (lambda_nm, pdf) = sample_visible_lambda_nm(u.min(1.0 - f32::EPSILON));
            let analytic_nm = analytic_visible_lambda_nm(f64::from(u));
            assert!(
                (f64::from(lambda_nm) - analytic_nm).abs() < 0.01,
                "u = {u}: {lambda_nm} vs {analytic_nm}"
            );
            let analytic_pdf = analytic_visible_pdf_per_nm(f64::from(lambda_nm));
            assert!(
                (f64::from(pdf) / analytic_pdf - 1.0).abs() < 1.5e-2,
                "λ = {lambda_nm}: {pdf} vs {analytic_pdf}"
            );
        }
    }

    /// Every active lane lies in 360–830 nm with the positive pdf of its segment; the lanes are
    /// (u + i)/count, so for count = 4 their u values are 1/4 apart; inactive lanes have pdf 0;
    /// each lane's grid position is that of its wavelength.
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
                    assert_eq!(wavelengths.grid().lane(lane), GridPosition::of(lambda_nm));
                    let pdf = wavelengths.pdf_per_nm(lane);
                    if lane < count {
                        let u_lane = (u + lane as f32) * (1.0 / count as f32);
                        assert_eq!((lambda_nm, pdf), sample_visible_lambda_nm(u_lane));
                        assert!(pdf > 0.0);
                    } else {
                        assert_eq!(pdf, 0.0);
                    }
                }
            }
        }
        let mask = SampledWavelengths::sample_visible(0.3, 2).active_mask();
        assert_eq!(mask.values[..4], [1.0, 1.0, 0.0, 0.0]);
        assert!(mask.values[4..].iter().all(|&v| v == 0.0));
    }

    /// `lane_alone` keeps the wavelengths and densities and makes one lane live.
    #[test]
    fn lane_alone_keeps_one_lane_live() {
        let wavelengths = SampledWavelengths::sample_visible(0.37, 4);
        for lane in 0..4 {
            let alone = wavelengths.lane_alone(lane);
            let mask = alone.active_mask();
            for i in 0..N_LAMBDA {
                assert_eq!(mask.values[i], if i == lane { 1.0 } else { 0.0 });
                assert_eq!(alone.lambda_nm(i), wavelengths.lambda_nm(i));
            }
            assert_eq!(alone.pdf_per_nm(lane), wavelengths.pdf_per_nm(lane));
        }
        // The whole sample's mask is unchanged by the field.
        assert_eq!(wavelengths.active_mask().values[..5], [1.0, 1.0, 1.0, 1.0, 0.0]);
    }

    /// A histogram of 400 000 hero wavelengths (seeded) over 47 bins of 10 nm matches the
    /// analytic density integrated over each bin: every bin's count is within 5 binomial
    /// standard deviations.
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
            let probability = simpson(analytic_visible_pdf_per_nm, start_nm, start_nm + 10.0, 20);
            let expected = probability * SAMPLES as f64;
            let sigma = (expected * (1.0 - probability)).sqrt();
            assert!(
                (count as f64 - expected).abs() < 5.0 * sigma,
                "bin {start_nm} nm: {count} samples, expected {expected:.0} ± {sigma:.0}"
            );
        }
    }

    /// The density looked up by wavelength is the one the sampler divides by: for wavelengths
    /// inside a segment (away from its knots, where rounding may assign either neighbour).
    #[test]
    fn pdf_lookup_agrees_with_sampling() {
        for j in 0..SEGMENTS {
            let (lambda_nm, pdf) = sample_visible_lambda_nm((j as f32 + 0.5) / SEGMENTS as f32);
            assert_eq!(visible_pdf_per_nm(lambda_nm), pdf, "segment {j}");
        }
    }

    /// The tabulated CDF at `lambda_nm`: the u that [`sample_visible_lambda_nm`] maps to it.
    fn tabulated_cdf(lambda_nm: f32) -> f64 {
        let table = &*VISIBLE_TABLE;
        let j = table.partition_point(|segment| segment.start_nm <= lambda_nm).clamp(1, SEGMENTS) - 1;
        let within = f64::from(lambda_nm - table[j].start_nm) / f64::from(table[j].width_nm);
        (j as f64 + within) / SEGMENTS as f64
    }

    /// Regression: the wavelengths of a pixel's N stratified samples (the renderer's sampler,
    /// dimension 2) fill the N·count strata of the CDF one each. The usual rotation
    /// frac(u + i/count) put two samples' lanes in the same strata and left others empty, which
    /// made colour noise on the TP6 walls 9× larger at 16 spp.
    #[test]
    fn lanes_of_a_pixels_samples_fill_every_stratum() {
        for count in 1..=N_LAMBDA {
            for (x, y) in [(0, 0), (17, 3), (120, 99)] {
                const SAMPLES: usize = 16;
                let strata = SAMPLES * count;
                let mut cells = vec![0u32; strata];
                for sample in 0..SAMPLES as u32 {
                    let mut rng = crate::sampler::PixelRng::new(9, x, y, sample);
                    let _pixel_position = (rng.uniform(), rng.uniform());
                    let wavelengths = SampledWavelengths::sample_visible(rng.uniform(), count);
                    for lane in 0..count {
                        let u = tabulated_cdf(wavelengths.lambda_nm(lane));
                        cells[((u * strata as f64) as usize).min(strata - 1)] += 1;
                    }
                }
                assert!(cells.iter().all(|&c| c == 1), "count {count}, pixel ({x}, {y}): {cells:?}");
            }
        }
    }

    /// `count` outside 1..=N_LAMBDA is a programming error.
    #[test]
    #[should_panic(expected = "wavelength count 0")]
    fn sample_visible_rejects_zero_count() {
        SampledWavelengths::sample_visible(0.5, 0);
    }
}
