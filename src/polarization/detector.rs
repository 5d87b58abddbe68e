//! [`Detector`]: what a depolarising receiver (a diffuse surface) reads of unpolarised light that
//! reached it through a chain of elements: the row vector e₀ᵀ·M₁·R₁₂·M₂·…, built from the
//! receiver outwards, so that a shadow ray can apply the elements in the order it meets them.

use super::mueller::JonesDiagonal;
use super::Rotation;

/// A row vector r of a Stokes functional: the receiver reads r·S of the light S arriving in the
/// frame r is written in. Starts as e₀ᵀ (a detector of radiance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detector {
    row: [f32; 4],
}

impl Default for Detector {
    fn default() -> Self {
        Self::RADIANCE
    }
}

impl Detector {
    /// A radiance detector: reads S0.
    pub const RADIANCE: Self = Self { row: [1.0, 0.0, 0.0, 0.0] };

    /// The detector seen through `element` (r ← r·M), in the element's frame.
    #[inline]
    pub fn through(self, element: &JonesDiagonal) -> Self {
        let [r0, r1, r2, r3] = self.row;
        let JonesDiagonal { a, b, w_re, w_im } = *element;
        Self { row: [r0 * a + r1 * b, r0 * b + r1 * a, r2 * w_re - r3 * w_im, r2 * w_im + r3 * w_re] }
    }

    /// The detector written in another frame (r ← r·R): `rotation` takes Stokes vectors from the
    /// new frame to the detector's current one.
    #[inline]
    pub fn rotated(self, rotation: Rotation) -> Self {
        let [r0, r1, r2, r3] = self.row;
        let (c, s) = (rotation.cos_2theta, rotation.sin_2theta);
        Self { row: [r0, r1 * c - r2 * s, r1 * s + r2 * c, r3] }
    }

    /// What it reads of unpolarised light of unit radiance: r₀.
    #[inline]
    pub fn unpolarized_response(&self) -> f32 {
        self.row[0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polarization::{Mueller, Stokes};
    use crate::spectrum::SampledSpectrum;

    /// Malus's law through two polarisers at relative angle θ: ½·cos²θ of unpolarised light.
    #[test]
    fn two_polarisers_follow_malus() {
        for theta_deg in [0.0f32, 30.0, 45.0, 60.0, 90.0] {
            let theta = theta_deg.to_radians();
            // The first polariser (nearest the receiver) along x; the second turned by θ. Its
            // frame's x axis is the first's turned by θ: Stokes vectors go from it to the first
            // frame by turning by −θ.
            let polariser = JonesDiagonal::linear_polarizer(1.0);
            let read = Detector::RADIANCE
                .through(&polariser)
                .rotated(Rotation::by_angle(-theta))
                .through(&polariser)
                .unpolarized_response();
            let expected = 0.5 * theta.cos().powi(2);
            assert!((read - expected).abs() < 1e-6, "{theta_deg}°: {read} vs {expected}");
        }
    }

    /// The row vector reads what the column-vector product gives, for elements with phases.
    #[test]
    fn reads_what_the_mueller_product_gives() {
        let elements = [
            JonesDiagonal::linear_retarder(0.7),
            JonesDiagonal::linear_polarizer(0.8),
            JonesDiagonal::real(0.9, -0.4),
        ];
        let rotations = [Rotation::by_angle(0.3), Rotation::by_angle(-1.1)];
        let mut detector = Detector::RADIANCE.through(&elements[0]);
        detector = detector.rotated(rotations[0]).through(&elements[1]);
        detector = detector.rotated(rotations[1]).through(&elements[2]);
        // The light: unpolarised at the far end, then element 2, rotation 1, element 1, ...
        let mut light = Stokes::unpolarized(SampledSpectrum::splat(1.0));
        light = Mueller::splat(elements[2]).apply(&light).rotated(rotations[1]);
        light = Mueller::splat(elements[1]).apply(&light).rotated(rotations[0]);
        light = Mueller::splat(elements[0]).apply(&light);
        assert!((detector.unpolarized_response() - light.s[0][0]).abs() < 1e-6);
    }
}
