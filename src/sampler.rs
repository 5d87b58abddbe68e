//! [`PixelRng`]: the random stream of one camera sample, derived from (seed, pixel, sample index)
//! alone, so images do not depend on tiling or thread count.

use rand_core::RngCore;
use rand_pcg::Pcg32;

/// A PCG32 stream (O'Neill 2014) keyed by (seed, pixel, sample).
pub struct PixelRng(Pcg32);

impl PixelRng {
    /// The stream of sample `sample` of pixel (`x`, `y`) under `seed`.
    pub fn new(seed: u64, x: u32, y: u32, sample: u32) -> Self {
        // The pixel picks the PCG stream (increment); seed and sample pick the state.
        let pixel = (u64::from(y) << 32) | u64::from(x);
        let state = seed ^ (u64::from(sample).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        Self(Pcg32::new(state, pixel))
    }

    /// A uniform float in [0, 1).
    #[inline]
    pub fn uniform(&mut self) -> f32 {
        // 24 random bits: every value is exactly representable and < 1.
        (self.0.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_differ_between_pixels_and_samples_and_repeat_for_equal_keys() {
        let first = |s: u64, x, y, k| PixelRng::new(s, x, y, k).uniform();
        assert_eq!(first(1, 2, 3, 4), first(1, 2, 3, 4));
        assert_ne!(first(1, 2, 3, 4), first(1, 3, 3, 4));
        assert_ne!(first(1, 2, 3, 4), first(1, 2, 4, 4));
        assert_ne!(first(1, 2, 3, 4), first(1, 2, 3, 5));
        assert_ne!(first(1, 2, 3, 4), first(2, 2, 3, 4));
    }

    #[test]
    fn uniform_mean_is_one_half() {
        let mut rng = PixelRng::new(7, 0, 0, 0);
        let n = 100_000;
        let mean: f64 = (0..n).map(|_| f64::from(rng.uniform())).sum::<f64>() / f64::from(n);
        // Standard error 1/sqrt(12 n) ≈ 0.0009.
        assert!((mean - 0.5).abs() < 0.004, "{mean}");
    }
}
