//! Spectra: sampled wavelengths and values that travel with a camera sample, spectra defined by
//! scene data (constants, RGB colours, tables, named illuminants, blackbodies), and the CIE 1931
//! colour-matching functions that turn a spectral estimate into XYZ and linear sRGB.
//!
//! Wavelengths are in nanometres everywhere; the renderer works over [`LAMBDA_MIN_NM`, `LAMBDA_MAX_NM`].

pub mod cie;
pub mod color;
pub mod curve;
pub mod dense;
pub mod rgb_upsample;
pub mod sampled;
mod tables;
pub mod wavelengths;

pub use curve::{Spectrum, SpectrumError};
pub use dense::DenseSpectrum;
pub use sampled::SampledSpectrum;
pub use wavelengths::SampledWavelengths;

/// Number of wavelength lanes a camera sample carries.
pub const N_LAMBDA: usize = 8;
/// Shortest wavelength rendered, in nm (the CIE 1931 tables start here).
pub const LAMBDA_MIN_NM: f32 = 360.0;
/// Longest wavelength rendered, in nm (the CIE 1931 tables end here).
pub const LAMBDA_MAX_NM: f32 = 830.0;
