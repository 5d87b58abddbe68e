//! [`QuadLight`]: a one-sided parallelogram of uniform radiance L(λ) (W·m⁻²·sr⁻¹·nm⁻¹), emitting
//! only on the side its file names. Direct light from it is estimated by area sampling with a
//! stratified point set (a Hammersley set under a random Cranley–Patterson rotation): with `n`
//! points y_k on a quad of area A, the irradiance at x is estimated as
//! `E ≈ A/n · Σ L · cos θ_x · cos θ_y / |x − y_k|²` (Pharr et al., *PBR* 4th ed., §12.2).
//!
//! ```toml
//! [[lights]]
//! type = "quad"
//! corner = [1, 5, -2]
//! edge1 = [-2, 0, 0]
//! edge2 = [0, 1, 2]
//! radiance = { illuminant = "D65", scale = 10 }
//! emit = "edge2_cross_edge1"       # the side light leaves from
//! albedo = 0.5                     # optional: the quad's surface is diffuse, not black
//! ```
//!
//! The quad is also a surface of the scene: black by default (it absorbs all light falling on
//! it), or a Lambertian reflector of the given `albedo` (a reflectance in [0, 1], either side),
//! so that a closed enclosure of emitting walls can interreflect (the emitting-box case of
//! `prisma validate`, whose every pixel is Le/(1 − ρ) in full transport).

use glam::Vec3;

use super::LightSample;
use crate::geometry::Quad;
use crate::spectrum::DenseSpectrum;

/// A one-sided quad area light.
#[derive(Debug, Clone)]
pub struct QuadLight {
    /// The emitting parallelogram.
    pub quad: Quad,
    /// Unit normal of the emitting side.
    pub emit_normal: Vec3,
    /// Emitted radiance, W·m⁻²·sr⁻¹·nm⁻¹.
    pub radiance: DenseSpectrum,
}

impl QuadLight {
    /// Sample `index` of `count` stratified points, rotated by the random offsets `shift` in
    /// [0, 1)², as seen from `point`. `None` when the sample faces away from `point`.
    pub fn sample(&self, point: Vec3, index: u32, count: u32, shift: (f32, f32)) -> Option<LightSample> {
        let (u, v) = hammersley(index, count, shift);
        let on_light = self.quad.point_at(u, v);
        let offset = on_light - point;
        let distance_sq = offset.length_squared();
        if distance_sq <= 0.0 || !distance_sq.is_finite() {
            return None;
        }
        let distance = distance_sq.sqrt();
        let to_light = offset / distance;
        let cos_light = -self.emit_normal.dot(to_light);
        if cos_light <= 0.0 {
            return None;
        }
        let solid_angle = self.quad.area() * cos_light / (distance_sq * count as f32);
        Some(LightSample { to_light, distance, weight: solid_angle })
    }

    /// True when a ray travelling along `dir` sees the emitting side.
    #[inline]
    pub fn faces(&self, dir: Vec3) -> bool {
        self.emit_normal.dot(dir) < 0.0
    }
}

/// Point `index` of an `count`-point Hammersley set in [0, 1)², rotated by `shift` modulo 1.
#[inline]
fn hammersley(index: u32, count: u32, shift: (f32, f32)) -> (f32, f32) {
    let u = (index as f32 + 0.5) / count as f32;
    let v = index.reverse_bits() as f32 * (1.0 / 4_294_967_296.0);
    (wrap(u + shift.0), wrap(v + shift.1))
}

#[inline]
fn wrap(x: f32) -> f32 {
    let f = x - x.floor();
    // x - floor(x) can round up to 1.0 for tiny negative x.
    if f >= 1.0 {
        0.0
    } else {
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Irradiance on a patch parallel to an a × b rectangle of radiance L, at distance h under
    /// one of its corners: E = π·L·F with the differential form factor of Howell's catalogue
    /// (case B-3), F = (1/2π)·[X/√(1+X²)·atan(Y/√(1+X²)) + Y/√(1+Y²)·atan(X/√(1+Y²))],
    /// X = a/h, Y = b/h.
    #[test]
    fn irradiance_matches_form_factor() {
        let (a, b, h) = (1.0f32, 2.0f32, 0.7f32);
        let light = QuadLight {
            quad: Quad {
                corner: Vec3::new(0.0, 0.0, h),
                edge1: Vec3::new(a, 0.0, 0.0),
                edge2: Vec3::new(0.0, b, 0.0),
            },
            emit_normal: Vec3::new(0.0, 0.0, -1.0),
            radiance: DenseSpectrum::constant(1.0),
        };
        let (x, y) = (f64::from(a / h), f64::from(b / h));
        let form_factor = (x / (1.0 + x * x).sqrt() * (y / (1.0 + x * x).sqrt()).atan()
            + y / (1.0 + y * y).sqrt() * (x / (1.0 + y * y).sqrt()).atan())
            / (2.0 * std::f64::consts::PI);
        let expected = std::f64::consts::PI * form_factor;
        let count = 4096;
        let mut irradiance = 0.0f64;
        for k in 0..count {
            if let Some(s) = light.sample(Vec3::ZERO, k, count, (0.3, 0.7)) {
                irradiance += f64::from(light.radiance.eval(550.0) * s.weight * s.to_light.z);
            }
        }
        assert!((irradiance - expected).abs() < 1e-3 * expected, "{irradiance} vs {expected}");
    }

    #[test]
    fn back_side_is_dark() {
        let light = QuadLight {
            quad: Quad { corner: Vec3::new(-1.0, -1.0, 1.0), edge1: Vec3::X * 2.0, edge2: Vec3::Y * 2.0 },
            emit_normal: Vec3::Z,
            radiance: DenseSpectrum::constant(1.0),
        };
        assert!(light.sample(Vec3::ZERO, 0, 1, (0.0, 0.0)).is_none());
        assert!(light.sample(Vec3::new(0.0, 0.0, 2.0), 0, 1, (0.0, 0.0)).is_some());
    }
}
