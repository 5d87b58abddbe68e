//! [`BeamLight`]: a collimated beam, Mitsuba 3's `directionalarea` emitter: a parallelogram that
//! emits only along its normal, with irradiance E(λ) (W·m⁻²·nm⁻¹) on a plane perpendicular to the
//! beam, so that its power is E·A. A surface inside the beam, at a point whose projection along
//! the beam falls on the parallelogram, receives `E·cos θ_x`; everything else receives nothing
//! from it. Its parallelogram is a black surface, as a quad light's is (it blocks light and the
//! camera sees it dark: no direction but the normal carries any radiance).
//!
//! A narrow beam is a slit of white light, as in Newton's prism experiment.
//!
//! ```toml
//! [[lights]]
//! type = "beam"
//! corner = [-4, 0.95, -0.5]
//! edge1 = [0, 0.1, 0]          # a slit 0.1 high
//! edge2 = [0, 0, 1]            # and 1 long
//! irradiance = { illuminant = "D65", scale = 50 }   # W·m⁻²·nm⁻¹ across the beam
//! emit = "edge2_cross_edge1"   # the direction the beam travels
//! ```

use glam::Vec3;

use super::LightSample;
use crate::geometry::Quad;
use crate::spectrum::DenseSpectrum;

/// A collimated beam leaving a parallelogram along its normal.
#[derive(Debug, Clone)]
pub struct BeamLight {
    /// The emitting parallelogram.
    pub quad: Quad,
    /// Unit direction of the beam (a normal of the parallelogram).
    pub emit_normal: Vec3,
    /// Irradiance on a plane perpendicular to the beam, W·m⁻²·nm⁻¹.
    pub irradiance: DenseSpectrum,
}

impl BeamLight {
    /// The beam arriving at `point`: from the direction opposite to the beam, with weight 1
    /// (the irradiance per unit cos θ is the beam's), when `point` lies in front of the
    /// parallelogram and inside its projection along the beam; else `None`.
    pub fn sample(&self, point: Vec3) -> Option<LightSample> {
        let distance = (point - self.quad.corner).dot(self.emit_normal);
        if !(distance > 0.0 && distance.is_finite()) {
            return None;
        }
        let foot = point - distance * self.emit_normal;
        let (u, v) = self.parameters(foot)?;
        ((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)).then_some(LightSample {
            to_light: -self.emit_normal,
            distance,
            weight: 1.0,
        })
    }

    /// The parallelogram parameters (u, v) of a point in its plane.
    fn parameters(&self, point: Vec3) -> Option<(f32, f32)> {
        let (e1, e2) = (self.quad.edge1, self.quad.edge2);
        let d = point - self.quad.corner;
        let (a, b, c) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let det = a * c - b * b;
        if det <= 0.0 {
            return None;
        }
        let (p, q) = (d.dot(e1), d.dot(e2));
        Some(((c * p - b * q) / det, (a * q - b * p) / det))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beam() -> BeamLight {
        BeamLight {
            quad: Quad { corner: Vec3::new(-1.0, -0.5, 0.0), edge1: Vec3::X * 2.0, edge2: Vec3::Y },
            emit_normal: Vec3::Z,
            irradiance: DenseSpectrum::constant(1.0),
        }
    }

    #[test]
    fn lights_only_its_own_projection_in_front() {
        let light = beam();
        let lit = light.sample(Vec3::new(0.5, 0.2, 3.0)).unwrap();
        assert_eq!(lit.to_light, -Vec3::Z);
        assert!((lit.distance - 3.0).abs() < 1e-6);
        assert_eq!(lit.weight, 1.0);
        assert!(light.sample(Vec3::new(1.5, 0.0, 3.0)).is_none(), "beside the beam");
        assert!(light.sample(Vec3::new(0.0, 0.0, -3.0)).is_none(), "behind the emitter");
    }
}
