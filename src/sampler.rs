//! [`PixelRng`]: the sample values of one camera sample, an Owen-scrambled Sobol sequence
//! derived from (seed, pixel, sample index) alone, so images do not depend on tiling or thread
//! count.
//!
//! The samples of a pixel are successive points of one Sobol sequence, scrambled per pixel with
//! Burley's hash-based Owen scrambling and index shuffling (B. Burley, "Practical Hash-based Owen
//! Scrambling", JCGT 9(4), 2020; the `sobol_burley` crate). Every dimension of a pixel's samples
//! is therefore stratified across its samples, and the pixel-position pair (the first two
//! dimensions) is stratified jointly in 2D, so pixel edges and spectra converge faster than with
//! independent random numbers while each pixel's estimate stays an unbiased random variable
//! whose error is independent between pixels and seeds.
//!
//! Dimensions are handed out in order by [`PixelRng::uniform`]: the renderer takes the pixel
//! position (dimensions 0 and 1) and the wavelength (2); the integrator takes the rest (light
//! sample shifts, Russian roulette) in the order it needs them. Past the first four, dimensions
//! are "padded" as Burley recommends: each further group of four is the same 4D Sobol
//! sequence under an independent scramble and shuffle, so a group is stratified within itself
//! and randomly associated with the others. The sequence holds 2¹⁶ points; sample indices
//! beyond continue on independently scrambled sequences of 2¹⁶ points each.

/// Dimensions per padded group: one call of [`sobol_burley::sample_4d`].
const GROUP: usize = 4;
/// Points in one Sobol sequence of `sobol_burley`.
const SEQUENCE_POINTS: u32 = 1 << 16;

/// The sample values of camera sample `sample` of one pixel, handed out one dimension at a time.
pub struct PixelRng {
    /// Index of this sample in its pixel's Sobol sequence (< 2¹⁶).
    index: u32,
    /// Scramble seed of the pixel's sequence (seed, pixel and the index's high bits).
    sequence_seed: u32,
    /// Padded groups handed out so far.
    group: u32,
    /// The current group's values.
    values: [f32; GROUP],
    /// How many of `values` are handed out.
    used: usize,
}

/// What the samples of one pixel under one seed share: the key their scrambles derive from,
/// and the scramble seed of the pixel's first Sobol sequence (samples 0 to 2¹⁶ − 1), so that a
/// render hashes once per pixel rather than once per sample.
#[derive(Clone, Copy, Debug)]
pub struct PixelKey {
    key: u64,
    first_sequence_seed: u32,
}

impl PixelKey {
    /// The key of pixel (`x`, `y`) under `seed`.
    pub fn new(seed: u64, x: u32, y: u32) -> Self {
        let pixel = (u64::from(y) << 32) | u64::from(x);
        let key = mix64(mix64(seed ^ 0x51_7cc1_b727_220a) ^ pixel);
        Self { key, first_sequence_seed: Self::sequence_seed(key, 0) }
    }

    /// The scramble seed of the pixel's sequence number `sequence` (samples from
    /// `sequence`·2¹⁶ on).
    fn sequence_seed(key: u64, sequence: u32) -> u32 {
        (mix64(key ^ u64::from(sequence)) >> 32) as u32
    }
}

impl PixelRng {
    /// The values of sample `sample` of pixel (`x`, `y`) under `seed`.
    pub fn new(seed: u64, x: u32, y: u32, sample: u32) -> Self {
        Self::for_sample(PixelKey::new(seed, x, y), sample)
    }

    /// The values of sample `sample` of the pixel of `key`: the same as [`Self::new`] for that
    /// pixel and seed.
    #[inline]
    pub fn for_sample(key: PixelKey, sample: u32) -> Self {
        let sequence = sample / SEQUENCE_POINTS;
        let sequence_seed =
            if sequence == 0 { key.first_sequence_seed } else { PixelKey::sequence_seed(key.key, sequence) };
        let index = sample % SEQUENCE_POINTS;
        Self {
            index,
            sequence_seed,
            group: 0,
            values: sobol_burley::sample_4d(index, 0, sequence_seed),
            used: 0,
        }
    }

    /// The next dimension's value, uniform in [0, 1).
    #[inline]
    pub fn uniform(&mut self) -> f32 {
        if self.used == GROUP {
            self.group += 1;
            let group_seed = self.sequence_seed ^ (mix64(u64::from(self.group)) as u32);
            self.values = sobol_burley::sample_4d(self.index, 0, group_seed);
            self.used = 0;
        }
        let value = self.values[self.used];
        self.used += 1;
        debug_assert!((0.0..1.0).contains(&value), "sample value {value} outside [0, 1)");
        value
    }
}

/// A 64-bit finaliser with full avalanche (the `splitmix64` output function of Steele, Lea and
/// Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014).
fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first `dims` values of samples 0..n of one pixel.
    fn points(seed: u64, x: u32, y: u32, n: u32, dims: usize) -> Vec<Vec<f32>> {
        (0..n)
            .map(|k| {
                let mut rng = PixelRng::new(seed, x, y, k);
                (0..dims).map(|_| rng.uniform()).collect()
            })
            .collect()
    }

    #[test]
    fn values_repeat_for_equal_keys_and_differ_between_pixels_samples_and_seeds() {
        let first = |s: u64, x, y, k| PixelRng::new(s, x, y, k).uniform();
        assert_eq!(first(1, 2, 3, 4), first(1, 2, 3, 4));
        assert_ne!(first(1, 2, 3, 4), first(1, 3, 3, 4));
        assert_ne!(first(1, 2, 3, 4), first(1, 2, 4, 4));
        assert_ne!(first(1, 2, 3, 4), first(1, 2, 3, 5));
        assert_ne!(first(1, 2, 3, 4), first(2, 2, 3, 4));
        // Past the first sequence of 2¹⁶ points.
        assert_ne!(first(1, 2, 3, 4), first(1, 2, 3, 4 + SEQUENCE_POINTS));
    }

    #[test]
    fn every_dimension_is_stratified_over_a_power_of_two_of_samples() {
        // A (0, m, 1)-net in each dimension: 64 samples put exactly one value in each interval
        // [i/64, (i+1)/64), for the padded groups as well as the first.
        let pts = points(7, 10, 20, 64, 12);
        for dim in 0..12 {
            let mut cells = [0u32; 64];
            for p in &pts {
                cells[(p[dim] * 64.0) as usize] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "dimension {dim}: {cells:?}");
        }
    }

    #[test]
    fn pixel_position_is_stratified_jointly_in_2d() {
        // Sobol dimensions 0 and 1 form a (0, 2)-sequence: 256 points put one point in each of
        // the 16 × 16 cells (and in every 2^a × 2^b elementary interval with a + b = 8).
        let pts = points(3, 5, 9, 256, 2);
        for (a, b) in [(4, 4), (2, 6), (8, 0)] {
            let mut cells = vec![0u32; 256];
            for p in &pts {
                let (i, j) = ((p[0] * (1 << a) as f32) as usize, (p[1] * (1 << b) as f32) as usize);
                cells[i * (1 << b) + j] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "{a}×{b} intervals");
        }
    }

    #[test]
    fn mean_is_one_half_and_pixels_are_independent() {
        // Over many pixels with 4 samples each, every dimension has mean 1/2 (standard error
        // 1/sqrt(12·N) ≈ 0.0009 at most for independent pixels), and the first values of
        // neighbouring pixels are uncorrelated (|r| < 4/sqrt(N) ≈ 0.018).
        let pixels = 12_000u32;
        let mut sums = [0f64; 8];
        let (mut sxy, mut sx, mut sy, mut sxx, mut syy) = (0f64, 0f64, 0f64, 0f64, 0f64);
        for p in 0..pixels {
            for k in 0..4 {
                let mut rng = PixelRng::new(11, p, 0, k);
                for s in &mut sums {
                    *s += f64::from(rng.uniform());
                }
            }
            let a = f64::from(PixelRng::new(11, p, 0, 0).uniform());
            let b = f64::from(PixelRng::new(11, p + 1, 0, 0).uniform());
            (sxy, sx, sy, sxx, syy) = (sxy + a * b, sx + a, sy + b, sxx + a * a, syy + b * b);
        }
        let n = f64::from(pixels);
        for (dim, s) in sums.iter().enumerate() {
            let mean = s / (4.0 * n);
            assert!((mean - 0.5).abs() < 0.004, "dimension {dim}: mean {mean}");
        }
        let cov = sxy / n - (sx / n) * (sy / n);
        let r = cov / ((sxx / n - (sx / n).powi(2)) * (syy / n - (sy / n).powi(2))).sqrt();
        assert!(r.abs() < 4.0 / n.sqrt(), "correlation between neighbouring pixels: {r}");
    }

    #[test]
    fn stratification_beats_independent_sampling_on_a_smooth_integrand() {
        // ∫∫∫ x·y·z over the unit cube is 1/8. Averaged over 200 pixels, the squared error of a
        // 64-sample estimate must be far below the independent-sampling value Var/64, where
        // Var(xyz) = 1/27 − 1/64 ≈ 0.0214 (a scrambled net converges as O(N^-3 log² N)).
        let exact = 0.125f64;
        let mut squared_error = 0.0;
        for pixel in 0..200 {
            let estimate: f64 = points(5, pixel, 0, 64, 3)
                .iter()
                .map(|p| f64::from(p[0]) * f64::from(p[1]) * f64::from(p[2]))
                .sum::<f64>()
                / 64.0;
            squared_error += (estimate - exact).powi(2) / 200.0;
        }
        let independent = (1.0 / 27.0 - 1.0 / 64.0) / 64.0;
        assert!(squared_error < independent / 20.0, "MSE {squared_error:.3e} vs {independent:.3e}");
    }
}
