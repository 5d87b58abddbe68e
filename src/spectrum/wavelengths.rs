//! [`SampledWavelengths`]: the wavelengths one camera sample carries and their sampling densities.
//!
//! TODO(spectrum helper): hero wavelength + stratified rotations, importance-sampled over the
//! visible range with the density used by Mitsuba 3 and pbrt-v4 (538 nm centred 1/cosh² law).

use super::{SampledSpectrum, N_LAMBDA};

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
        let _ = u;
        todo!("count {count}")
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
