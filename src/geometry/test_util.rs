//! Seeded random numbers for the geometry tests (tests only: every random test is reproducible).

use glam::Vec3;
use rand_core::{RngCore, SeedableRng};
use rand_pcg::Pcg64;

/// A seeded PCG-64 stream with the few draws the tests need.
pub(crate) struct Rng(Pcg64);

impl Rng {
    /// The stream for `seed`.
    pub(crate) fn new(seed: u64) -> Self {
        Self(Pcg64::seed_from_u64(seed))
    }

    /// Uniform in [`low`, `high`).
    pub(crate) fn uniform(&mut self, low: f32, high: f32) -> f32 {
        // The top 24 bits give every f32 in [0, 1) on a 2⁻²⁴ grid.
        let unit = (self.0.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32);
        low + (high - low) * unit
    }

    /// Uniform in the box [`low`, `high`).
    pub(crate) fn point_in(&mut self, low: Vec3, high: Vec3) -> Vec3 {
        Vec3::new(self.uniform(low.x, high.x), self.uniform(low.y, high.y), self.uniform(low.z, high.z))
    }

    /// Uniform on the unit sphere (Archimedes: z uniform in [−1, 1], azimuth uniform).
    pub(crate) fn unit_vector(&mut self) -> Vec3 {
        let z = self.uniform(-1.0, 1.0);
        let phi = self.uniform(0.0, std::f32::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z).normalize()
    }

    /// Uniform on the hemisphere around the unit vector `axis`.
    pub(crate) fn unit_vector_around(&mut self, axis: Vec3) -> Vec3 {
        let v = self.unit_vector();
        if v.dot(axis) < 0.0 {
            -v
        } else {
            v
        }
    }

    /// Log-uniform in [`low`, `high`): every order of magnitude equally likely.
    pub(crate) fn log_uniform(&mut self, low: f32, high: f32) -> f32 {
        (self.uniform(low.ln(), high.ln())).exp()
    }
}

/// Tolerance for comparing an f32 far-side distance with [`far_side_distance`]: 10⁻⁵ of the
/// radius, growing as the chord shortens because the exit point of a ray near tangent is
/// ill-conditioned (an error e in the discriminant moves the root by ~e/chord).
pub(crate) fn far_side_tolerance(radius: f32, expected: f64) -> f64 {
    let radius = f64::from(radius);
    1e-5 * radius * (1.0 + radius / expected)
}

/// The exact (f64) distance from `origin` along the unit `dir` to the far side of `sphere`, where
/// a ray from inside exits; `None` when the line misses the sphere. The reference for f32 hits.
pub(crate) fn far_side_distance(sphere: &crate::geometry::Sphere, origin: Vec3, dir: Vec3) -> Option<f64> {
    let f = origin.as_dvec3() - sphere.center.as_dvec3();
    let d = dir.as_dvec3();
    let b = -f.dot(d);
    let c = f.length_squared() - f64::from(sphere.radius).powi(2);
    let discriminant = b * b - c;
    (discriminant >= 0.0).then(|| b + discriminant.sqrt())
}
