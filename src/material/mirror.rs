//! [`Mirror`]: a perfect specular reflector, `f = ρ(λ, θ) δ(ω_o − reflect(ω_i))`: an ideal mirror
//! (a perfect electric conductor: every polarisation reflected whole, with the phases
//! r_s = −1, r_p = +1), or a conductor of complex index n + ik, tabulated for real metals or
//! given as a constant, whose s and p amplitudes follow the conductor Fresnel equations; either
//! times the optional reflectance spectrum.
//!
//! ```toml
//! [materials.silvered]
//! type = "mirror"
//! reflectance = 0.95      # optional, 1 by default; any spectrum
//!
//! [materials.gold]
//! type = "mirror"
//! metal = "gold"          # silver, aluminium, gold, copper (data/metals/)
//!
//! [materials.gold_at_550]
//! type = "mirror"
//! complex_ior = [0.35, 2.71]   # a constant n + ik (n > 0, k ≥ 0)
//!
//! [materials.protected_silver]
//! type = "mirror"
//! metal = "silver"
//! coating = [{ ior = 1.46, thickness_nm = 94 }]   # optional, outside (air) side first
//! ```
//!
//! A **coating** on a metal (issue 41) replaces the bare conductor amplitudes by those of the
//! stack on the metal substrate, the transfer-matrix method of [`crate::optics::thin_film`]
//! with the metal's complex index as the substrate (vacuum the ambient; the same from either
//! face, as mirrors reflect on both sides): diag(r_s, r_p) with their relative phase in the
//! Mueller matrix, (R_s + R_p)/2 unpolarised. The layers are those of a dielectric's coating
//! ([`crate::material::dielectric::CoatingLayer`]: real or absorbing). The perfect conductor
//! takes no coating (the scene refuses one; here it would be ignored).

use num_complex::Complex32;

use num_complex::Complex64;

use crate::material::dielectric::{coating_amplitudes, narrow, CoatingFault, CoatingLayer};
use crate::optics::conductor::{fresnel_conductor, fresnel_conductor_amplitudes};
use crate::optics::metals::MetalEntry;
use crate::polarization::mueller::{JonesDiagonal, Mueller};
use crate::spectrum::{DenseSpectrum, SampledSpectrum, SampledWavelengths, N_LAMBDA};

/// What a mirror's surface is made of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Conductor {
    /// An ideal mirror: a perfect electric conductor.
    Perfect,
    /// A metal of the catalogue, with its tabulated n + ik(λ).
    Metal(&'static MetalEntry),
    /// A constant complex index n + ik (relative to the vacuum outside).
    Index(Complex32),
}

impl Conductor {
    /// The complex index n + ik at `lambda_nm`, or `None` for the perfect conductor.
    #[inline]
    pub fn eta(&self, lambda_nm: f32) -> Option<Complex32> {
        match self {
            Conductor::Perfect => None,
            Conductor::Metal(metal) => Some(metal.eta(lambda_nm)),
            Conductor::Index(eta) => Some(*eta),
        }
    }
}

/// A perfect mirror.
#[derive(Debug, Clone)]
pub struct Mirror {
    /// Fraction of radiance reflected, per wavelength (multiplies the conductor's Fresnel term).
    pub reflectance: DenseSpectrum,
    /// The conductor whose Fresnel amplitudes apply.
    pub conductor: Conductor,
    /// Layers on the conductor from the outside inwards; empty for a bare metal. Ignored on
    /// [`Conductor::Perfect`].
    pub coating: Vec<CoatingLayer>,
}

impl Mirror {
    /// True when a coating applies (a coating on a real conductor).
    #[inline]
    pub fn is_coated(&self) -> bool {
        !self.coating.is_empty() && self.conductor != Conductor::Perfect
    }

    /// Reflectance of unpolarised light at the lanes of `wavelengths` for incidence at
    /// `cos_theta_i` (|cos θ| is used: mirrors reflect on both sides); `fault` is `None` but in
    /// validation.
    #[inline]
    pub fn reflectance(
        &self,
        cos_theta_i: f32,
        wavelengths: &SampledWavelengths,
        fault: Option<CoatingFault>,
    ) -> SampledSpectrum {
        let base = self.reflectance.sample(wavelengths);
        if self.conductor == Conductor::Perfect {
            return base;
        }
        let cos = cos_theta_i.abs().min(1.0);
        if self.is_coated() {
            let elements = self.coated_elements(cos, wavelengths, fault);
            return base * SampledSpectrum { values: elements.map(|e| e.a) };
        }
        base * SampledSpectrum {
            values: std::array::from_fn(|i| match self.conductor.eta(wavelengths.lambda_nm(i)) {
                Some(eta) => fresnel_conductor(cos, eta).reflectance,
                None => 1.0,
            }),
        }
    }

    /// The Mueller matrix of the reflection in the s/p frame of the incidence (x = s), at the
    /// lanes of `wavelengths`, for incidence at `cos_theta_i`; `fault` is `None` but in
    /// validation.
    pub fn mueller(
        &self,
        cos_theta_i: f32,
        wavelengths: &SampledWavelengths,
        fault: Option<CoatingFault>,
    ) -> Mueller {
        let base = self.reflectance.sample(wavelengths);
        if self.is_coated() {
            let elements = self.coated_elements(cos_theta_i.abs().min(1.0), wavelengths, fault);
            return Mueller::from_lanes(&elements).scaled(base);
        }
        let elements: [JonesDiagonal; N_LAMBDA] = match self.conductor {
            Conductor::Perfect => [JonesDiagonal::PERFECT_CONDUCTOR; N_LAMBDA],
            Conductor::Index(eta) => {
                let (r_s, r_p) = fresnel_conductor_amplitudes(cos_theta_i, eta);
                [JonesDiagonal::new(r_s, r_p); N_LAMBDA]
            }
            Conductor::Metal(metal) => std::array::from_fn(|i| {
                let (r_s, r_p) =
                    fresnel_conductor_amplitudes(cos_theta_i, metal.eta(wavelengths.lambda_nm(i)));
                JonesDiagonal::new(r_s, r_p)
            }),
        };
        Mueller::from_lanes(&elements).scaled(base)
    }

    /// The coated metal's diag(r_s, r_p) at every lane, for `cos` in [0, 1]: the stack with
    /// vacuum as the ambient and the metal as the substrate, evaluated once per distinct
    /// wavelength (a monochromatic render's lanes share theirs).
    fn coated_elements(
        &self,
        cos: f32,
        wavelengths: &SampledWavelengths,
        fault: Option<CoatingFault>,
    ) -> [JonesDiagonal; N_LAMBDA] {
        let mut elements = [JonesDiagonal::PERFECT_CONDUCTOR; N_LAMBDA];
        for lane in 0..N_LAMBDA {
            let lambda_nm = wavelengths.lambda_nm(lane);
            if lane > 0 && wavelengths.lambda_nm(lane - 1) == lambda_nm {
                elements[lane] = elements[lane - 1];
                continue;
            }
            let Some(eta) = self.conductor.eta(lambda_nm) else { continue };
            let substrate = Complex64::new(f64::from(eta.re), f64::from(eta.im));
            let stack = coating_amplitudes(&self.coating, false, 1.0, substrate, lambda_nm, cos, fault);
            elements[lane] = JonesDiagonal::new(narrow(stack.r_s), narrow(stack.r_p));
        }
        elements
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::metals;

    fn at(metal: &str, lambda_nm: f32, cos_theta: f32) -> f32 {
        let entry = metals::metal(metal).unwrap_or_else(|| panic!("{metal} missing from the catalogue"));
        let mirror = Mirror {
            reflectance: DenseSpectrum::constant(1.0),
            conductor: Conductor::Metal(entry),
            coating: Vec::new(),
        };
        mirror.reflectance(cos_theta, &SampledWavelengths::monochromatic(lambda_nm), None)[0]
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
        let mirror = Mirror {
            reflectance: DenseSpectrum::constant(0.7),
            conductor: Conductor::Perfect,
            coating: Vec::new(),
        };
        let wavelengths = SampledWavelengths::monochromatic(500.0);
        assert_eq!(mirror.reflectance(0.2, &wavelengths, None)[0], 0.7);
        assert_eq!(mirror.reflectance(-1.0, &wavelengths, None)[0], 0.7);
    }

    /// The Mueller matrix's unpolarised part is the reflectance, for metals and ideal mirrors.
    #[test]
    fn mueller_intensity_is_the_reflectance() {
        let wavelengths = SampledWavelengths::sample_visible(0.3, 8);
        for conductor in [
            Conductor::Perfect,
            Conductor::Index(Complex32::new(0.35, 2.71)),
            Conductor::Metal(metals::metal("gold").unwrap()),
        ] {
            let mirror = Mirror { reflectance: DenseSpectrum::constant(0.9), conductor, coating: Vec::new() };
            for cos in [1.0f32, 0.6, 0.1] {
                let m = mirror.mueller(cos, &wavelengths, None);
                let r = mirror.reflectance(cos, &wavelengths, None);
                for lane in 0..N_LAMBDA {
                    assert!((m.a[lane] - r[lane]).abs() < 1e-5, "{conductor:?} cos {cos}");
                }
            }
        }
    }

    fn coated(conductor: Conductor, layers: &[(f32, f32)]) -> Mirror {
        let coating = layers
            .iter()
            .map(|&(n, d)| CoatingLayer::dielectric(crate::optics::Ior::Constant(n), d))
            .collect();
        Mirror { reflectance: DenseSpectrum::constant(1.0), conductor, coating }
    }

    /// A layer of the vacuum's own index on a metal only delays both amplitudes alike: the
    /// reflectances and the Mueller matrix's a, b (and |w|) are the bare metal's.
    #[test]
    fn a_vacuum_layer_on_a_metal_changes_no_power() {
        let wavelengths = SampledWavelengths::sample_visible(0.7, 8);
        for conductor in
            [Conductor::Index(Complex32::new(0.18, 3.43)), Conductor::Metal(metals::metal("silver").unwrap())]
        {
            let bare = coated(conductor, &[]);
            let vacuum = coated(conductor, &[(1.0, 180.0)]);
            for cos in [1.0_f32, 0.7, 0.2] {
                let (m_bare, m_vacuum) =
                    (bare.mueller(cos, &wavelengths, None), vacuum.mueller(cos, &wavelengths, None));
                for lane in 0..N_LAMBDA {
                    assert!((m_bare.a[lane] - m_vacuum.a[lane]).abs() < 1e-5, "{conductor:?} cos {cos}");
                    assert!((m_bare.b[lane] - m_vacuum.b[lane]).abs() < 1e-5, "{conductor:?} cos {cos}");
                }
            }
        }
    }

    /// A quarter wave of n₁ on a substrate n_s + ik_s at normal incidence reflects
    /// |(n₁² − ñ_s)/(n₁² + ñ_s)|² (Macleod §2.5, the quarter wave's admittance n₁²/ñ_s): 1.46
    /// on 0.18 + 3.43i at 550 nm reflects 0.9103 where the bare metal reflects 0.9453; the
    /// unpolarised reflectance is the Mueller a, and the perfect conductor ignores a coating.
    #[test]
    fn a_quarter_wave_on_a_metal_meets_the_closed_form() {
        let eta = Complex32::new(0.18, 3.43);
        let mirror = coated(Conductor::Index(eta), &[(1.46, 550.0 / (4.0 * 1.46))]);
        let wavelengths = SampledWavelengths::monochromatic(550.0);
        let n1_sqr = 1.46_f64 * 1.46;
        // In the e^{+iωt} convention the substrate's index is n − ik; |·| is the same either way.
        let substrate = num_complex::Complex64::new(0.18, -3.43);
        let expected = ((n1_sqr - substrate) / (n1_sqr + substrate)).norm_sqr();
        let seen = mirror.reflectance(1.0, &wavelengths, None)[0];
        // f32 rounding of the index, thickness and result: ~1e-7.
        assert!((f64::from(seen) - expected).abs() < 1e-6, "{seen} vs {expected}");
        assert!((expected - 0.910_292_5).abs() < 1e-7, "{expected}");
        assert!((mirror.mueller(1.0, &wavelengths, None).a[0] - seen).abs() < 1e-7);
        let perfect = coated(Conductor::Perfect, &[(1.46, 94.2)]);
        assert_eq!(perfect.mueller(0.5, &wavelengths, None).a[0], 1.0);
    }
}
