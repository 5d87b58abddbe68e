//! [`Mirror`]: a perfect specular reflector, `f = ρ(λ) δ(ω_o − reflect(ω_i))`.
//!
//! ```toml
//! [materials.silvered]
//! type = "mirror"
//! reflectance = 0.95      # optional, 1 by default; any spectrum
//! ```

use crate::spectrum::Spectrum;

/// A perfect mirror with a spectral reflectance in [0, 1].
#[derive(Debug, Clone)]
pub struct Mirror {
    /// Fraction of radiance reflected, per wavelength.
    pub reflectance: Spectrum,
}
