//! [`Mirror`]: a perfect specular reflector, `f = ρ(λ, θ) δ(ω_o − reflect(ω_i))`: either a
//! constant-per-angle reflectance spectrum, or a real metal whose reflectance follows the
//! conductor Fresnel equations for its tabulated complex index n + ik (times the optional
//! reflectance spectrum).
//!
//! ```toml
//! [materials.silvered]
//! type = "mirror"
//! reflectance = 0.95      # optional, 1 by default; any spectrum
//!
//! [materials.gold]
//! type = "mirror"
//! metal = "gold"          # silver, aluminium, gold, copper (data/metals/)
//! ```

use crate::optics::conductor::fresnel_conductor;
use crate::optics::metals::MetalEntry;
use crate::spectrum::{DenseSpectrum, SampledSpectrum, SampledWavelengths};

/// A perfect mirror.
#[derive(Debug, Clone)]
pub struct Mirror {
    /// Fraction of radiance reflected, per wavelength (multiplies the metal's Fresnel term).
    pub reflectance: DenseSpectrum,
    /// A metal whose Fresnel reflectance applies, if any.
    pub metal: Option<&'static MetalEntry>,
}

impl Mirror {
    /// Reflectance at the lanes of `wavelengths` for incidence at `cos_theta_i` (|cos θ| is
    /// used: mirrors reflect on both sides).
    #[inline]
    pub fn reflectance(&self, cos_theta_i: f32, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        let base = self.reflectance.sample(wavelengths);
        match self.metal {
            None => base,
            Some(metal) => {
                let cos = cos_theta_i.abs().min(1.0);
                base * SampledSpectrum {
                    values: std::array::from_fn(|i| {
                        fresnel_conductor(cos, metal.eta(wavelengths.lambda_nm(i))).reflectance
                    }),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::metals;

    fn at(metal: &str, lambda_nm: f32, cos_theta: f32) -> f32 {
        let mirror = Mirror { reflectance: DenseSpectrum::constant(1.0), metal: metals::metal(metal) };
        assert!(mirror.metal.is_some(), "{metal} missing from the catalogue");
        mirror.reflectance(cos_theta, &SampledWavelengths::monochromatic(lambda_nm))[0]
    }

    /// Published normal-incidence reflectances (Johnson & Christy 1972 data as plotted in
    /// Hecht, *Optics*, fig. 4.69, and Bass, *Handbook of Optics* vol. IV): silver ≈ 0.96–0.98
    /// across the visible, gold dark in the blue (≈ 0.38 at 450 nm) and bright in the red (≈ 0.96
    /// at 700 nm).
    #[test]
    fn metals_reflect_their_published_colours() {
        assert!((0.95..0.99).contains(&at("silver", 550.0, 1.0)));
        assert!(at("gold", 450.0, 1.0) < 0.45);
        assert!(at("gold", 700.0, 1.0) > 0.94);
        // Grazing incidence reflects everything, whatever the metal.
        assert!(at("copper", 500.0, 1e-4) > 0.999);
    }

    #[test]
    fn plain_mirror_ignores_angle() {
        let mirror = Mirror { reflectance: DenseSpectrum::constant(0.7), metal: None };
        let wavelengths = SampledWavelengths::monochromatic(500.0);
        assert_eq!(mirror.reflectance(0.2, &wavelengths)[0], 0.7);
        assert_eq!(mirror.reflectance(-1.0, &wavelengths)[0], 0.7);
    }
}
