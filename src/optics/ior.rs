//! [`Ior`]: index of refraction as a function of wavelength.

/// Why an index-of-refraction model is invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IorError {
    /// The message states the offending value and why.
    #[error("{0}")]
    Invalid(String),
}

/// Index of refraction n(λ) of a dielectric, evaluated per wavelength in nm without allocation.
#[derive(Debug, Clone, PartialEq)]
pub enum Ior {
    /// The same index at every wavelength.
    Constant(f32),
    /// Cauchy's law n = A + B/λ² + C/λ⁴ with λ in µm (B in µm², C in µm⁴).
    Cauchy {
        /// A (dimensionless).
        a: f32,
        /// B in µm².
        b_um2: f32,
        /// C in µm⁴.
        c_um4: f32,
    },
    /// Sellmeier's three-term law n² = 1 + Σ Bᵢ λ² / (λ² − Cᵢ) with λ in µm (Cᵢ in µm²).
    Sellmeier {
        /// B₁, B₂, B₃ (dimensionless).
        b: [f32; 3],
        /// C₁, C₂, C₃ in µm².
        c_um2: [f32; 3],
    },
    /// Linear interpolation in a table of (λ nm, n), strictly increasing in λ; constant beyond
    /// the end points.
    Tabulated(std::sync::Arc<[(f32, f32)]>),
}

impl Ior {
    /// n at `lambda_nm`.
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        let _ = lambda_nm;
        todo!()
    }
    /// True when n varies with wavelength.
    pub fn is_dispersive(&self) -> bool {
        !matches!(self, Ior::Constant(_))
    }
    /// Checks that n is finite and > 0 over the rendered range 360–830 nm (and that the model's
    /// own parameters are well formed).
    pub fn validate(&self) -> Result<(), IorError> {
        todo!()
    }
}
