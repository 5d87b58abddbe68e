//! Lights that illuminate diffuse surfaces through shadow rays: isotropic point lights and
//! one-sided quad area lights. (The background radiance is not a light in Whitted's model: it is
//! seen only by rays that escape.)

pub mod point;
pub mod quad;

use glam::Vec3;

pub use point::PointLight;
pub use quad::QuadLight;

use crate::spectrum::SampledSpectrum;

/// A light source.
#[derive(Debug, Clone)]
pub enum Light {
    /// An isotropic point light.
    Point(PointLight),
    /// A one-sided parallelogram area light.
    Quad(QuadLight),
}

/// One sample of incident light at a shading point, before visibility.
#[derive(Debug, Clone, Copy)]
pub struct LightSample {
    /// Unit direction from the shading point toward the light sample.
    pub to_light: Vec3,
    /// Distance to the light sample (scene units).
    pub distance: f32,
    /// Irradiance contribution divided by cos θ at the receiver, i.e. the incident radiance times
    /// the solid angle this sample stands for (W·m⁻²·nm⁻¹ per unit cos θ): `I/d²` for a point
    /// light, `L·cos θ_l·A/(d²·n)` for one of `n` quad samples.
    pub incident: SampledSpectrum,
}
