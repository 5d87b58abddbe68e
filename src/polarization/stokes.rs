//! [`Stokes`]: a Stokes vector at every wavelength lane of a camera sample, in one frame shared
//! by the lanes (conventions in [`crate::polarization`]).

use super::frame::Rotation;
use crate::spectrum::SampledSpectrum;

/// Stokes vectors (S0, S1, S2, S3) of a beam at the [`crate::spectrum::N_LAMBDA`] lanes of a
/// camera sample, in units of radiance (W·m⁻²·sr⁻¹·nm⁻¹), stored component by component so
/// that lane arithmetic vectorises. The frame is implicit: whoever holds a `Stokes` knows the
/// beam's direction and x axis.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Stokes {
    /// S0, S1, S2, S3, each over the lanes.
    pub s: [SampledSpectrum; 4],
}

impl Stokes {
    /// No light.
    pub const fn zero() -> Self {
        Self { s: [SampledSpectrum::zero(); 4] }
    }

    /// Unpolarised light of radiance `radiance`: (L, 0, 0, 0), the same in every frame.
    #[inline]
    pub fn unpolarized(radiance: SampledSpectrum) -> Self {
        Self { s: [radiance, SampledSpectrum::zero(), SampledSpectrum::zero(), SampledSpectrum::zero()] }
    }

    /// The radiance S0.
    #[inline]
    pub fn intensity(&self) -> SampledSpectrum {
        self.s[0]
    }

    /// Every component multiplied lane-wise by `weight` (a non-polarising attenuation).
    #[inline]
    pub fn scaled(self, weight: SampledSpectrum) -> Self {
        Self { s: self.s.map(|component| component * weight) }
    }

    /// Only lane `lane` kept, the others zero.
    #[inline]
    pub fn only_lane(self, lane: usize) -> Self {
        Self { s: self.s.map(|component| component.only_lane(lane)) }
    }

    /// The same light described in a frame turned by `rotation` about the beam's direction.
    #[inline]
    pub fn rotated(self, rotation: Rotation) -> Self {
        let [s0, s1, s2, s3] = self.s;
        let (c, s) = (rotation.cos_2theta, rotation.sin_2theta);
        Self { s: [s0, s1 * c + s2 * s, s2 * c - s1 * s, s3] }
    }

    /// True when every lane of every component is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.s.iter().all(SampledSpectrum::is_finite)
    }
}

impl std::ops::Add for Stokes {
    type Output = Self;
    #[inline]
    fn add(self, rhs: Self) -> Self {
        Self { s: std::array::from_fn(|k| self.s[k] + rhs.s[k]) }
    }
}

impl std::ops::AddAssign for Stokes {
    #[inline]
    fn add_assign(&mut self, rhs: Self) {
        *self = *self + rhs;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unpolarised_light_is_the_same_in_every_frame() {
        let light = Stokes::unpolarized(SampledSpectrum::splat(2.0));
        let turned = light.rotated(Rotation::by_angle(0.7));
        for k in 0..4 {
            for lane in 0..crate::spectrum::N_LAMBDA {
                assert!((turned.s[k][lane] - light.s[k][lane]).abs() < 1e-6);
            }
        }
    }

    /// Linear polarisation at 20° from x, seen in a frame turned by 50°, is at −30°:
    /// S1/S0 = cos(−60°) = 0.5, S2/S0 = sin(−60°) ≈ −0.866.
    #[test]
    fn a_turned_frame_sees_the_angle_of_polarisation_reduced_by_the_turn() {
        let phi = 20f32.to_radians();
        let light = Stokes {
            s: [
                SampledSpectrum::splat(1.0),
                SampledSpectrum::splat((2.0 * phi).cos()),
                SampledSpectrum::splat((2.0 * phi).sin()),
                SampledSpectrum::splat(0.25),
            ],
        };
        let turned = light.rotated(Rotation::by_angle(50f32.to_radians()));
        assert!((turned.s[1][0] - 0.5).abs() < 1e-6);
        assert!((turned.s[2][0] + 0.75f32.sqrt()).abs() < 1e-6);
        assert_eq!(turned.s[3][0], 0.25, "S3 does not depend on the frame's x axis");
    }
}
