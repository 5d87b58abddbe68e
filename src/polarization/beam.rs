//! [`Beam`]: what a branch of the ray tree carries back to the camera. Polarised renders carry
//! [`Stokes`] vectors; unpolarised renders carry radiance alone ([`SampledSpectrum`]), with
//! every interaction reduced to its effect on unpolarised light (the first entry of its Mueller
//! matrix: the s/p-averaged Fresnel reflectance, half of a polariser). The integrator is written
//! once, generic over the two.

use super::{Mueller, Rotation, Stokes};
use crate::spectrum::SampledSpectrum;

/// Light arriving along a ray, at every wavelength lane.
pub trait Beam: Copy + std::ops::Add<Output = Self> + std::ops::AddAssign {
    /// True when the beam keeps track of polarisation (frames and rotations matter).
    const POLARIZED: bool;
    /// No light.
    fn zero() -> Self;
    /// Unpolarised light of radiance `radiance`.
    fn unpolarized(radiance: SampledSpectrum) -> Self;
    /// Multiplied lane-wise by a non-polarising factor.
    fn scaled(self, weight: SampledSpectrum) -> Self;
    /// Only lane `lane` kept.
    fn only_lane(self, lane: usize) -> Self;
    /// Re-expressed in a frame turned by `rotation`.
    fn rotated(self, rotation: Rotation) -> Self;
    /// After the element `mueller` (in the frame the beam is expressed in).
    fn through(self, mueller: &Mueller) -> Self;
    /// The Stokes components carried: one (radiance) or four (S0..S3).
    fn components(&self) -> &[SampledSpectrum];
}

impl Beam for SampledSpectrum {
    const POLARIZED: bool = false;
    #[inline]
    fn zero() -> Self {
        SampledSpectrum::zero()
    }
    #[inline]
    fn unpolarized(radiance: SampledSpectrum) -> Self {
        radiance
    }
    #[inline]
    fn scaled(self, weight: SampledSpectrum) -> Self {
        self * weight
    }
    #[inline]
    fn only_lane(self, lane: usize) -> Self {
        SampledSpectrum::only_lane(self, lane)
    }
    #[inline]
    fn rotated(self, _rotation: Rotation) -> Self {
        self
    }
    #[inline]
    fn through(self, mueller: &Mueller) -> Self {
        mueller.a * self
    }
    #[inline]
    fn components(&self) -> &[SampledSpectrum] {
        std::slice::from_ref(self)
    }
}

impl Beam for Stokes {
    const POLARIZED: bool = true;
    #[inline]
    fn zero() -> Self {
        Stokes::zero()
    }
    #[inline]
    fn unpolarized(radiance: SampledSpectrum) -> Self {
        Stokes::unpolarized(radiance)
    }
    #[inline]
    fn scaled(self, weight: SampledSpectrum) -> Self {
        Stokes::scaled(self, weight)
    }
    #[inline]
    fn only_lane(self, lane: usize) -> Self {
        Stokes::only_lane(self, lane)
    }
    #[inline]
    fn rotated(self, rotation: Rotation) -> Self {
        Stokes::rotated(self, rotation)
    }
    #[inline]
    fn through(self, mueller: &Mueller) -> Self {
        mueller.apply(&self)
    }
    #[inline]
    fn components(&self) -> &[SampledSpectrum] {
        &self.s
    }
}
