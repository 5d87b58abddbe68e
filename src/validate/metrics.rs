//! Image comparison metrics that separate noise from bias.
//!
//! Both renderers' noise is measured, not assumed: each side renders twice with independent seeds
//! (a, b). The compared images are the means (a + b)/2, whose per-pixel variance is estimated as
//! (a − b)²/4 and pooled over a (2r+1)² window (noise varies slowly across an image; one pixel's
//! pair alone has a single degree of freedom). Then, per pixel and channel,
//!
//!   z = (p̄ − m̄) / √(σ²_p + σ²_m + floor²),   floor = 10⁻⁴ + 10⁻³·|m̄|,
//!
//! where the floor absorbs float rounding on noiseless pixels. A correct renderer gives z ≈ N(0, 1)
//! (Student-like tails); the checks are
//! - the fraction of pixels with |z| > [`Z_OUTLIER`] (a local bias: an edge in the wrong place, a
//!   wrong Fresnel lobe),
//! - the z of the image-wide mean difference per channel (a global bias: wrong units, a scale);
//!   no allowance is added unless a case states a known cause ([`Options::mean_tolerance`]),
//! - the relative MSE, mean (p̄ − m̄)²/(m̄² + 0.01) (the metric of most renderer comparisons), less
//!   the part the measured noise explains.
//!
//! Pooling underestimates the variance of pixels on sharp edges (their neighbours are smoother),
//! so a few outliers appear even without any bias, the more so when the two renderers' noise
//! differs in structure (a stratified sampler puts nearly all its error on edges). The outlier
//! check is therefore calibrated empirically: the same statistic is computed for the null
//! difference (p_a − p_b)/2 + (m_a − m_b)/2, which has the variance of p̄ − m̄ when both render
//! the same image and is divided by the same estimate, and only the excess of outliers over that
//! null fraction counts.
//!
//! Where the references come with a variance image (each reference the mean of many passes, and
//! the per-pixel variance of that mean from the passes' moments), the reference's variance is
//! that per-pixel value instead of the pooled pair estimate: pooling underestimates the noise of
//! isolated highlights, which then look like outliers. prisma's own noise (stratified, and
//! small beside the references') is still estimated from its pair.
//!
//! Beside these, where the references carry variance images, Mitsuba 3's own pass rule
//! (`src/render/tests/test_renders.py`, [`Sidak`]): per pixel and channel, the two-sided
//! p-value of z against the Šidák-corrected level α = 1 − (1 − 0.01)^(1/N), N the number of
//! compared pixels; at least 99.75 % of the tests must pass. Mitsuba takes the test image's
//! variance from the reference's per-sample variance (the same estimator on both sides) and
//! neglects the reference's noise; here the two renderers differ, so z is the one above with
//! the reference's per-pixel variance and, for prisma, the larger of the pooled estimate and the
//! pixel's own (a − b)²/4 (validation/README.md, "Mitsuba's pass rule").

/// |z| above which a pixel counts as an outlier.
pub const Z_OUTLIER: f64 = 5.0;
/// Radius of the window over which variance is pooled.
pub const POOL_RADIUS: usize = 3;
/// Family-wise significance level of Mitsuba 3's image test (`test_renders.py`): the chance that
/// a correct image has any pixel test below the Šidák-corrected level.
pub const SIDAK_SIGNIFICANCE: f64 = 0.01;
/// Fraction of Mitsuba 3's per-pixel tests that must pass (`test_renders.py`: 99.75 %); the
/// check fails when more than 1 − this fail.
pub const SIDAK_MIN_PASS_FRACTION: f64 = 0.9975;

/// A multi-channel float image, channel-major: `data[c][y·width + x]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Planes {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// One plane per channel.
    pub data: Vec<Vec<f64>>,
}

impl Planes {
    /// Averages `factor`×`factor` blocks (exact for box-filtered images: a box-filtered image at
    /// full resolution, averaged over blocks, is the box-filtered image at the lower resolution).
    /// Returns `None` when the size is not divisible.
    pub fn downsample(&self, factor: usize) -> Option<Planes> {
        if factor == 1 {
            return Some(self.clone());
        }
        if factor == 0 || !self.width.is_multiple_of(factor) || !self.height.is_multiple_of(factor) {
            return None;
        }
        let (w, h) = (self.width / factor, self.height / factor);
        let norm = 1.0 / (factor * factor) as f64;
        let data = self
            .data
            .iter()
            .map(|plane| {
                let mut out = vec![0.0; w * h];
                for y in 0..self.height {
                    for x in 0..self.width {
                        out[(y / factor) * w + x / factor] += plane[y * self.width + x] * norm;
                    }
                }
                out
            })
            .collect();
        Some(Planes { width: w, height: h, data })
    }
}

/// The result of comparing two pairs of renders.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// Mean of (p̄ − m̄)²/(m̄² + 0.01) over pixels and channels.
    pub rel_mse: f64,
    /// The part of `rel_mse` that noise does not explain: the mean of
    /// ((p̄ − m̄)² − σ̂²_p − σ̂²_m)/(m̄² + 0.01) with the unpooled, unbiased per-pixel variance
    /// estimates; its expectation is zero for a correct renderer.
    pub rel_mse_excess: f64,
    /// Fraction of pixels with |z| > [`Z_OUTLIER`] in any channel.
    pub outlier_fraction: f64,
    /// The same fraction for the null comparison, (p_a − p_b)/2 + (m_a − m_b)/2 in place of
    /// p̄ − m̄: the same variance and the same denominator, but no bias. Pooled variance
    /// underestimates the noise of pixels on sharp edges, so some outliers occur under the null
    /// too; only the excess over this counts as bias.
    pub null_outlier_fraction: f64,
    /// Largest |z| of the image-wide mean difference over channels.
    pub mean_z: f64,
    /// Per pixel, the z of largest magnitude over channels (signed).
    pub z_map: Vec<f64>,
    /// Mean of p̄ / mean of m̄ per channel.
    pub mean_ratio: Vec<f64>,
    /// Mitsuba 3's own pass rule, when the references carry variance images ([`Sidak`]).
    pub sidak: Option<Sidak>,
}

/// Mitsuba 3's pass rule for an image (`src/render/tests/test_renders.py`): per pixel and
/// channel a two-sided z-test of the mean difference, at the Šidák-corrected level
/// α = 1 − (1 − [`SIDAK_SIGNIFICANCE`])^(1/N), N the number of compared pixels; the image
/// passes when at least [`SIDAK_MIN_PASS_FRACTION`] of the pixel-channel tests pass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sidak {
    /// The per-test significance level α.
    pub alpha: f64,
    /// Number of pixel-channel tests (compared pixels × channels).
    pub tests: usize,
    /// Fraction of the tests whose p-value is not above α (a NaN fails).
    pub failing_fraction: f64,
}

impl Sidak {
    /// True when at least [`SIDAK_MIN_PASS_FRACTION`] of the tests pass.
    pub fn passed(&self) -> bool {
        self.failing_fraction <= 1.0 - SIDAK_MIN_PASS_FRACTION
    }
}

/// Šidák's per-test level for `tests` independent tests at family-wise level `significance`:
/// 1 − (1 − significance)^(1/tests), computed without cancellation.
pub fn sidak_alpha(significance: f64, tests: usize) -> f64 {
    -((-significance).ln_1p() / tests.max(1) as f64).exp_m1()
}

/// The two-sided p-value of a standard normal statistic: P(|Z| ≥ |z|) = erfc(|z|/√2). NaN
/// for a NaN z.
pub fn two_sided_p(z: f64) -> f64 {
    erfc(z.abs() / std::f64::consts::SQRT_2)
}

/// The complementary error function, to a relative error below 1.2·10⁻⁷ for every x
/// (Press et al., Numerical Recipes, 2nd ed., §6.2, Chebyshev fit `erfcc`): enough to compare a
/// p-value with α, whose own uncertainty (the variance estimates) is far larger.
fn erfc(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.5 * x.abs());
    let poly = -1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let tail = t * (-x * x + poly).exp();
    if x >= 0.0 {
        tail
    } else {
        2.0 - tail
    }
}

/// What a comparison takes beside the four images.
#[derive(Debug, Clone, Copy, Default)]
pub struct Options<'a> {
    /// Compare only the pixels whose entry is true (all pixels when absent): the rest count
    /// neither as outliers nor in the means.
    pub mask: Option<&'a [bool]>,
    /// Per pixel and channel, the variance of the reference mean (ref_a + ref_b)/2, when the
    /// references carry variance images; otherwise it is estimated from the pair and pooled.
    pub reference_variance: Option<&'a Planes>,
    /// A systematic difference, relative to the image mean, that the mean test tolerates (a
    /// known, documented cause); 0 by default.
    pub mean_tolerance: f64,
}

/// Compares the test pair (`test_a`, `test_b`) with the reference pair (`ref_a`, `ref_b`).
/// Panics if the four images differ in size or channel count.
pub fn compare(test_a: &Planes, test_b: &Planes, ref_a: &Planes, ref_b: &Planes) -> Comparison {
    compare_with(test_a, test_b, ref_a, ref_b, &Options::default())
}

/// As [`compare`], with a mask, the references' variance and a mean tolerance ([`Options`]).
/// Panics if the mask or the variance does not match the images' size.
pub fn compare_with(
    test_a: &Planes,
    test_b: &Planes,
    ref_a: &Planes,
    ref_b: &Planes,
    options: &Options,
) -> Comparison {
    let mask = options.mask;
    let (w, h) = (ref_a.width, ref_a.height);
    for other in [test_a, test_b, ref_b] {
        assert!(
            other.width == w && other.height == h && other.data.len() == ref_a.data.len(),
            "size mismatch"
        );
    }
    let n = w * h;
    if let Some(mask) = mask {
        assert_eq!(mask.len(), n, "mask size mismatch");
    }
    if let Some(variance) = options.reference_variance {
        assert!(
            variance.width == w && variance.height == h && variance.data.len() == ref_a.data.len(),
            "variance size mismatch"
        );
    }
    let kept = |i: usize| mask.is_none_or(|m| m[i]);
    let counted = (0..n).filter(|&i| kept(i)).count();
    let mut z_map = vec![0.0f64; n];
    let mut outlier = vec![false; n];
    let (mut rel_mse, mut rel_mse_excess, mut mean_z, mut mean_ratio) = (0.0, 0.0, 0.0f64, Vec::new());
    let mut null_outlier = vec![false; n];
    let alpha = sidak_alpha(SIDAK_SIGNIFICANCE, counted);
    let mut sidak_failed = 0usize;
    for c in 0..ref_a.data.len() {
        let mean = |a: &Planes, b: &Planes| -> Vec<f64> {
            (0..n).map(|i| 0.5 * (a.data[c][i] + b.data[c][i])).collect()
        };
        let variance = |a: &Planes, b: &Planes| -> Vec<f64> {
            pool((0..n).map(|i| 0.25 * (a.data[c][i] - b.data[c][i]).powi(2)).collect(), w, h)
        };
        let (p, m) = (mean(test_a, test_b), mean(ref_a, ref_b));
        let vp = variance(test_a, test_b);
        let vm = match options.reference_variance {
            Some(variance) => variance.data[c].clone(),
            None => variance(ref_a, ref_b),
        };
        // The null comparison: (p_a − p_b)/2 + (m_a − m_b)/2 has the variance of p̄ − m̄ under
        // the null hypothesis (same truth, symmetric noise) and is divided by the same estimate.
        for i in (0..n).filter(|&i| kept(i)) {
            let floor = 1e-4 + 1e-3 * m[i].abs();
            let null_diff =
                0.5 * (test_a.data[c][i] - test_b.data[c][i]) + 0.5 * (ref_a.data[c][i] - ref_b.data[c][i]);
            let z = null_diff / (vp[i] + vm[i] + floor * floor).sqrt();
            null_outlier[i] |= z.is_nan() || z.abs() > Z_OUTLIER;
        }
        // Mitsuba's rule, where the references' variance is known per pixel. prisma's
        // variance per pixel is the larger of the pooled estimate and the pixel's own
        // (a − b)²/4: the latter is unbiased for the variance of (a + b)/2, so the larger is
        // never biased low, also on an edge or highlight noisier than its window.
        if options.reference_variance.is_some() {
            for i in (0..n).filter(|&i| kept(i)) {
                let floor = 1e-4 + 1e-3 * m[i].abs();
                let own = 0.25 * (test_a.data[c][i] - test_b.data[c][i]).powi(2);
                let z = (p[i] - m[i]) / (vp[i].max(own) + vm[i] + floor * floor).sqrt();
                // A test passes when p > α; a NaN p-value is not, so it fails.
                let passed = two_sided_p(z) > alpha;
                sidak_failed += usize::from(!passed);
            }
        }
        let (mut sum_diff, mut sum_var, mut sum_p, mut sum_m) = (0.0, 0.0, 0.0, 0.0);
        for i in (0..n).filter(|&i| kept(i)) {
            let diff = p[i] - m[i];
            let floor = 1e-4 + 1e-3 * m[i].abs();
            let z = diff / (vp[i] + vm[i] + floor * floor).sqrt();
            if z.abs() > z_map[i].abs() || z.is_nan() {
                z_map[i] = z;
            }
            // A NaN z (a NaN pixel) counts as an outlier.
            outlier[i] |= z.is_nan() || z.abs() > Z_OUTLIER;
            rel_mse += diff * diff / (m[i] * m[i] + 0.01);
            let reference_noise = match options.reference_variance {
                Some(variance) => variance.data[c][i],
                None => 0.25 * (ref_a.data[c][i] - ref_b.data[c][i]).powi(2),
            };
            let noise = 0.25 * (test_a.data[c][i] - test_b.data[c][i]).powi(2) + reference_noise;
            rel_mse_excess += (diff * diff - noise) / (m[i] * m[i] + 0.01);
            sum_diff += diff;
            sum_var += vp[i] + vm[i] + floor * floor;
            sum_p += p[i];
            sum_m += m[i];
        }
        // No allowance unless a case states a known cause for a systematic difference.
        let tolerance = options.mean_tolerance * sum_m.abs();
        mean_z = mean_z.max((sum_diff / (sum_var + tolerance * tolerance).sqrt()).abs());
        mean_ratio.push(if sum_m != 0.0 { sum_p / sum_m } else { f64::NAN });
    }
    let channels = ref_a.data.len().max(1) as f64;
    let fraction = |flags: &[bool]| flags.iter().filter(|&&o| o).count() as f64 / counted.max(1) as f64;
    Comparison {
        rel_mse: rel_mse / (counted.max(1) as f64 * channels),
        rel_mse_excess: rel_mse_excess / (counted.max(1) as f64 * channels),
        outlier_fraction: fraction(&outlier),
        null_outlier_fraction: fraction(&null_outlier),
        mean_z,
        z_map,
        mean_ratio,
        sidak: options.reference_variance.map(|_| {
            let tests = counted * ref_a.data.len();
            Sidak { alpha, tests, failing_fraction: sidak_failed as f64 / tests.max(1) as f64 }
        }),
    }
}

/// Box-averages `values` over a (2·[`POOL_RADIUS`]+1)² window clipped to the image.
fn pool(values: Vec<f64>, w: usize, h: usize) -> Vec<f64> {
    let r = POOL_RADIUS;
    let mut out = vec![0.0; values.len()];
    for y in 0..h {
        for x in 0..w {
            let (y0, y1, x0, x1) =
                (y.saturating_sub(r), (y + r).min(h - 1), x.saturating_sub(r), (x + r).min(w - 1));
            let mut sum = 0.0;
            for yy in y0..=y1 {
                sum += values[yy * w + x0..=yy * w + x1].iter().sum::<f64>();
            }
            out[y * w + x] = sum / ((y1 - y0 + 1) * (x1 - x0 + 1)) as f64;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic pseudo-noise in [-0.5, 0.5) (a hash; the metric tests need no real RNG).
    fn noise(i: usize, seed: u64) -> f64 {
        let mut x = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ seed.wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x ^= x >> 31;
        x = x.wrapping_mul(0x94D0_49BB_1331_11EB);
        x ^= x >> 29;
        (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }

    fn image(value: impl Fn(usize) -> f64, sigma: f64, seed: u64) -> Planes {
        // Sum of four uniforms: roughly normal with variance 4/12 = 1/3.
        let data = (0..64 * 64)
            .map(|i| value(i) + sigma * (3f64).sqrt() * (0..4).map(|k| noise(i, seed * 4 + k)).sum::<f64>())
            .collect();
        Planes { width: 64, height: 64, data: vec![data] }
    }

    #[test]
    fn same_truth_different_noise_passes() {
        let truth = |i: usize| 0.5 + 0.3 * ((i % 64) as f64 / 64.0);
        let c = compare(
            &image(truth, 0.02, 1),
            &image(truth, 0.02, 2),
            &image(truth, 0.01, 3),
            &image(truth, 0.01, 4),
        );
        assert!(c.outlier_fraction < 0.005, "{c:?}");
        assert!(c.mean_z < 5.0, "{}", c.mean_z);
    }

    #[test]
    fn a_one_percent_scale_is_caught_by_the_mean_z() {
        let truth = |i: usize| 0.5 + 0.3 * ((i % 64) as f64 / 64.0);
        let biased = |i: usize| 1.01 * truth(i);
        let c = compare(
            &image(biased, 0.02, 1),
            &image(biased, 0.02, 2),
            &image(truth, 0.01, 3),
            &image(truth, 0.01, 4),
        );
        assert!(c.mean_z > 5.0, "{}", c.mean_z);
    }

    #[test]
    fn a_shifted_edge_is_caught_by_outliers() {
        let edge = |shift: usize| move |i: usize| if i % 64 < 32 + shift { 1.0 } else { 0.0 };
        let c = compare(
            &image(edge(1), 0.01, 1),
            &image(edge(1), 0.01, 2),
            &image(edge(0), 0.01, 3),
            &image(edge(0), 0.01, 4),
        );
        // One column of 64 moved: 1/64 of the pixels, far above the noise.
        assert!(c.outlier_fraction > 0.01, "{}", c.outlier_fraction);
    }

    /// An isolated noisy highlight: one pixel whose reference noise is 50× its neighbours'.
    /// Pooled over its window, the pair estimate misses most of that variance and calls the
    /// pixel an outlier in some channel of many; the reference's own per-pixel variance does not.
    #[test]
    fn per_pixel_reference_variance_keeps_highlights_from_being_outliers() {
        let truth = |_: usize| 0.5;
        let hot = 64 * 32 + 32;
        let sigma_hot = 0.5;
        let reference = |seed: u64| {
            let mut planes = image(truth, 0.001, seed);
            planes.data[0][hot] =
                0.5 + sigma_hot * (3f64).sqrt() * (0..4).map(|k| noise(hot, seed * 7 + k)).sum::<f64>();
            planes
        };
        let (test_a, test_b) = (image(truth, 0.001, 1), image(truth, 0.001, 2));
        let mut flagged_pooled = 0;
        let mut flagged_per_pixel = 0;
        for trial in 0..40u64 {
            let (ref_a, ref_b) = (reference(100 + 2 * trial), reference(101 + 2 * trial));
            let mut variance =
                Planes { width: 64, height: 64, data: vec![vec![0.25 * 2.0 * 0.001f64.powi(2); 64 * 64]] };
            variance.data[0][hot] = 0.25 * 2.0 * sigma_hot * sigma_hot;
            let pooled = compare(&test_a, &test_b, &ref_a, &ref_b);
            let per_pixel = compare_with(
                &test_a,
                &test_b,
                &ref_a,
                &ref_b,
                &Options { reference_variance: Some(&variance), ..Options::default() },
            );
            flagged_pooled += usize::from(pooled.z_map[hot].abs() > Z_OUTLIER);
            flagged_per_pixel += usize::from(per_pixel.z_map[hot].abs() > Z_OUTLIER);
        }
        assert!(flagged_pooled > 10, "pooled: {flagged_pooled} of 40");
        assert_eq!(flagged_per_pixel, 0);
    }

    /// The Šidák rule's four images: prisma's pair (σ = 0.02 each) of `truth` shifted by
    /// `bias`, Mitsuba's pair (σ = 0.01 each) of `truth`, and the references' known variance
    /// image, (0.01² + 0.01²)/4 per pixel, as `render_references.py` writes it.
    fn sidak_case(bias: f64) -> (Planes, Planes, Planes, Planes, Planes) {
        let truth = |i: usize| 0.5 + 0.3 * ((i % 64) as f64 / 64.0);
        let shifted = move |i: usize| truth(i) + bias;
        let variance = Planes { width: 64, height: 64, data: vec![vec![0.5 * 0.01f64.powi(2); 64 * 64]] };
        (
            image(shifted, 0.02, 1),
            image(shifted, 0.02, 2),
            image(truth, 0.01, 3),
            image(truth, 0.01, 4),
            variance,
        )
    }

    fn sidak_of(
        test_a: &Planes,
        test_b: &Planes,
        ref_a: &Planes,
        ref_b: &Planes,
        variance: &Planes,
    ) -> Sidak {
        let options = Options { reference_variance: Some(variance), ..Options::default() };
        compare_with(test_a, test_b, ref_a, ref_b, &options).sidak.expect("variance given")
    }

    /// σ of p̄ − m̄ per pixel in [`sidak_case`]: √(0.02²/2 + 0.01²/2).
    const SIDAK_CASE_SIGMA: f64 = 0.015_811_388;

    #[test]
    fn sidak_alpha_and_p_values_match_closed_forms() {
        // One test: α is the family-wise level; two: 1 − √0.99.
        assert!((sidak_alpha(0.01, 1) - 0.01).abs() < 1e-15);
        assert!((sidak_alpha(0.01, 2) - (1.0 - 0.99f64.sqrt())).abs() < 1e-15);
        // 32 000 pixels (a 200 × 160 reference): α = 3.1408·10⁻⁷, |z| > 5.11 fails.
        let alpha = sidak_alpha(0.01, 32_000);
        assert!((alpha / 3.140_729_461e-7 - 1.0).abs() < 1e-9, "{alpha}");
        // Two-sided normal tails: P(|Z| ≥ 1) = 0.3173105, ≥ 3: 2.699796·10⁻³, ≥ 5: 5.733031·10⁻⁷
        // (erfc(z/√2)); relative error under 2·10⁻⁷.
        for (z, p) in [
            (0.0, 1.0),
            (1.0, 0.317_310_507_862_914),
            (-3.0, 2.699_796_063_260_19e-3),
            (5.0, 5.733_031_437_583_9e-7),
        ] {
            assert!((two_sided_p(z) / p - 1.0).abs() < 2e-7, "z {z}: {} against {p}", two_sided_p(z));
        }
        assert!((erfc(-1.0) - 1.842_700_792_949_715).abs() < 2e-7);
        assert!(two_sided_p(f64::NAN).is_nan());
    }

    #[test]
    fn sidak_rule_passes_the_same_mean_with_known_noise() {
        let (test_a, test_b, ref_a, ref_b, variance) = sidak_case(0.0);
        let sidak = sidak_of(&test_a, &test_b, &ref_a, &ref_b, &variance);
        assert_eq!(sidak.tests, 64 * 64);
        assert!(sidak.passed() && sidak.failing_fraction < 1e-3, "{sidak:?}");
    }

    #[test]
    fn sidak_rule_fails_a_bias_of_three_sigma() {
        // 3σ of the per-pixel noise of p̄ − m̄: each pixel's |z| exceeds the Šidák level
        // (|z| > 4.71 for 4096 pixels) 4.4 % of the time with exact variances (measured here:
        // 4.8 %), far above the 0.25 % allowed.
        let (test_a, test_b, ref_a, ref_b, variance) = sidak_case(3.0 * SIDAK_CASE_SIGMA);
        let sidak = sidak_of(&test_a, &test_b, &ref_a, &ref_b, &variance);
        assert!(!sidak.passed() && sidak.failing_fraction > 0.005, "{sidak:?}");
    }

    #[test]
    fn sidak_rule_fails_nan_pixels() {
        let (mut test_a, test_b, ref_a, ref_b, variance) = sidak_case(0.0);
        let clean = sidak_of(&test_a, &test_b, &ref_a, &ref_b, &variance);
        // One NaN pixel fails its test (its p-value is not above α)…
        test_a.data[0][64 * 32 + 32] = f64::NAN;
        let one = sidak_of(&test_a, &test_b, &ref_a, &ref_b, &variance);
        assert_eq!(one.failing_fraction * 4096.0, clean.failing_fraction * 4096.0 + 1.0);
        // …and NaN in 1 pixel of 64 fails the image (a single one is left to relMSE, which
        // a NaN makes NaN).
        for i in (0..64 * 64).step_by(64) {
            test_a.data[0][i] = f64::NAN;
        }
        let many = sidak_of(&test_a, &test_b, &ref_a, &ref_b, &variance);
        assert!(!many.passed(), "{many:?}");
    }

    #[test]
    fn no_sidak_rule_without_reference_variance() {
        let (test_a, test_b, ref_a, ref_b, _) = sidak_case(0.0);
        assert!(compare(&test_a, &test_b, &ref_a, &ref_b).sidak.is_none());
    }

    #[test]
    fn downsampling_averages_blocks() {
        let p = Planes { width: 4, height: 2, data: vec![vec![1.0, 3.0, 5.0, 7.0, 1.0, 3.0, 5.0, 7.0]] };
        assert_eq!(p.downsample(2).unwrap().data[0], vec![2.0, 6.0]);
        assert!(p.downsample(3).is_none());
    }
}
