//! [`Spectrum`]: a spectral quantity defined by scene data, evaluated at any wavelength.

use super::{SampledSpectrum, SampledWavelengths};

/// Why a spectrum could not be built from its description.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpectrumError {
    /// A description value is out of range or malformed; the message says which and why.
    #[error("{0}")]
    Invalid(String),
}

/// A spectral quantity (reflectance, radiance, intensity, absorption...) as a function of
/// wavelength in nm. Evaluation never allocates.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    scale: f32,
}

impl Spectrum {
    /// The same `value` at every wavelength.
    pub fn constant(value: f32) -> Self {
        let _ = value;
        todo!()
    }
    /// Piecewise-linear through `(lambda_nm, value)` points, strictly increasing in λ, values finite;
    /// held constant beyond the end points.
    pub fn table(points: &[(f32, f32)]) -> Result<Self, SpectrumError> {
        let _ = points;
        todo!()
    }
    /// A smooth reflectance spectrum whose colour (under D65) is the linear sRGB `rgb`, each
    /// component in [0, 1].
    pub fn rgb_reflectance(rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        let _ = rgb;
        todo!()
    }
    /// An emission spectrum whose colour is the linear sRGB `rgb` (components ≥ 0): a smooth
    /// spectrum times D65 normalised to Y = 1, so (1, 1, 1) appears as (1, 1, 1).
    pub fn rgb_illuminant(rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        let _ = rgb;
        todo!()
    }
    /// A named CIE illuminant normalised to Y = 1: `"D65"` or `"E"` (equal energy).
    pub fn named_illuminant(name: &str) -> Result<Self, SpectrumError> {
        let _ = name;
        todo!()
    }
    /// Planck's law for `temperature_k` kelvin, normalised so that Y = 1.
    pub fn blackbody(temperature_k: f32) -> Result<Self, SpectrumError> {
        let _ = temperature_k;
        todo!()
    }
    /// This spectrum times `factor`.
    pub fn scaled(mut self, factor: f32) -> Self {
        self.scale *= factor;
        self
    }
    /// Value at `lambda_nm`.
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        let _ = lambda_nm;
        todo!()
    }
    /// Values at every lane of `wavelengths` (inactive lanes may hold anything finite).
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum { values: std::array::from_fn(|i| self.eval(wavelengths.lambda_nm(i))) }
    }
    /// True when the value is the same at every wavelength.
    pub fn is_constant(&self) -> bool {
        todo!()
    }
}
