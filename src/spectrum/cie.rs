//! The CIE 1931 2° standard observer, loaded from `data/` (TODO(spectrum helper): source named in
//! the data file header), and the spectral → XYZ conversion of a sampled estimate.

use glam::Vec3;

use super::{SampledSpectrum, SampledWavelengths};

/// ∫ ȳ(λ) dλ over 360–830 nm of the shipped table (nm). An equal-energy spectrum of value 1 has
/// Y = 1 under prisma's (and Mitsuba 3's) convention `XYZ = ∫ L·cmf dλ / ∫ ȳ dλ`.
pub fn cie_y_integral() -> f32 {
    todo!()
}

/// The colour-matching functions (x̄, ȳ, z̄) at `lambda_nm`, linearly interpolated; zero outside
/// 360–830 nm.
pub fn cmf(lambda_nm: f32) -> Vec3 {
    let _ = lambda_nm;
    todo!()
}

/// Monte Carlo estimate of XYZ from radiance sampled at `wavelengths`: the only place where the
/// wavelength pdf is divided out. In monochromatic mode it returns (L, L, L) of lane 0 instead.
pub fn to_xyz(radiance: &SampledSpectrum, wavelengths: &SampledWavelengths) -> Vec3 {
    let _ = (radiance, wavelengths);
    todo!()
}
