//! Lights that illuminate diffuse surfaces through shadow rays and that the light tracer emits
//! from: isotropic point lights, spot lights, one-sided quad area lights and collimated beams.
//! (The background radiance is not a light in Whitted's model: it is seen only by rays that
//! escape.)

pub mod beam;
pub mod point;
pub mod quad;
pub mod spot;

use glam::Vec3;

pub use beam::BeamLight;
pub use point::PointLight;
pub use quad::QuadLight;
pub use spot::SpotLight;

use crate::spectrum::DenseSpectrum;

/// A light source.
#[derive(Debug, Clone)]
pub enum Light {
    /// An isotropic point light.
    Point(PointLight),
    /// A one-sided parallelogram area light.
    Quad(QuadLight),
    /// A point light emitting into a cone.
    Spot(SpotLight),
    /// A collimated beam leaving a parallelogram along its normal.
    Beam(BeamLight),
}

impl Light {
    /// The emitted spectrum that a [`LightSample::weight`] scales: the intensity of a point or
    /// spot light (W·sr⁻¹·nm⁻¹), the radiance of a quad light (W·m⁻²·sr⁻¹·nm⁻¹), the irradiance
    /// across a beam (W·m⁻²·nm⁻¹).
    pub fn emitted(&self) -> &DenseSpectrum {
        match self {
            Light::Point(point) => &point.intensity,
            Light::Quad(quad) => &quad.radiance,
            Light::Spot(spot) => &spot.intensity,
            Light::Beam(beam) => &beam.irradiance,
        }
    }
}

/// One sample of incident light at a shading point, before visibility.
#[derive(Debug, Clone, Copy)]
pub struct LightSample {
    /// Unit direction from the shading point toward the light sample.
    pub to_light: Vec3,
    /// Distance to the light sample (scene units).
    pub distance: f32,
    /// What the sample contributes per unit of the light's emitted spectrum and of cos θ at the
    /// receiver: the incident irradiance over cos θ is `weight` times the light's
    /// [`Light::emitted`] spectrum. `1/d²` (m⁻²) for a point light of intensity I (so I/d²),
    /// `falloff/d²` for a spot light, `cos θ_l·A/(d²·n)` (sr) for one of `n` samples of a quad
    /// light of radiance L, and 1 inside a beam. The spectrum is left out so that it is looked
    /// up once per light, and only when a sample is unoccluded.
    pub weight: f32,
}
