//! [`PointLight`]: an isotropic point source of radiant intensity I(λ) in W·sr⁻¹·nm⁻¹. The
//! irradiance it gives a surface at distance d is `E = I·cos θ / d²` (Mitsuba 3's `point`
//! emitter uses the same `intensity` convention).
//!
//! ```toml
//! [[lights]]
//! type = "point"
//! position = [0, 5, 0]
//! intensity = { illuminant = "D65", scale = 100 }
//! ```

use glam::Vec3;

use super::LightSample;
use crate::spectrum::DenseSpectrum;

/// An isotropic point light.
#[derive(Debug, Clone)]
pub struct PointLight {
    /// Position (scene units).
    pub position: Vec3,
    /// Radiant intensity, W·sr⁻¹·nm⁻¹.
    pub intensity: DenseSpectrum,
}

impl PointLight {
    /// The light arriving at `point`; `None` when `point` is at the light's position.
    pub fn sample(&self, point: Vec3) -> Option<LightSample> {
        let offset = self.position - point;
        let distance_sq = offset.length_squared();
        if distance_sq <= 0.0 || !distance_sq.is_finite() {
            return None;
        }
        let distance = distance_sq.sqrt();
        Some(LightSample { to_light: offset / distance, distance, weight: 1.0 / distance_sq })
    }
}
