//! [`Dielectric`]: a smooth interface between vacuum (outside, n = 1) and a dielectric of index
//! n(λ) (inside), with Fresnel-weighted reflection and refraction (Hecht, *Optics*, §4.6) and
//! optional Beer–Lambert absorption inside.
//!
//! ```toml
//! [materials.flint]
//! type = "dielectric"
//! ior = { glass = "N-SF11" }          # or 1.5, { cauchy = [A, B, C] }, { sellmeier = { ... } }
//! absorption = { rgb = [0.0, 0.05, 0.1] }   # optional, per scene unit
//! ```

use crate::optics::Ior;
use crate::spectrum::DenseSpectrum;

/// A smooth dielectric.
#[derive(Debug, Clone)]
pub struct Dielectric {
    /// Index of refraction of the inside relative to the outside (vacuum), as a function of λ.
    pub ior: Ior,
    /// Absorption coefficient inside (per scene unit), if any.
    pub absorption: Option<DenseSpectrum>,
}
