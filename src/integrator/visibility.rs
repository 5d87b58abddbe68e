//! Shadow rays that may cross polarising sheets, shared by Whitted's direct light and the path
//! tracer's next-event estimation: a depolarising receiver reads the unpolarised light of a
//! light sample through the sheets between them ([`crate::polarization::Detector`]); any other
//! surface on the way blocks it.

use glam::Vec3;

use super::{element, rotation, Beam, Fault, TraceStats};
use crate::geometry::{spawn_origin, Ray};
use crate::material::{Material, Polarizer, Retarder};
use crate::polarization::mueller::JonesDiagonal;
use crate::polarization::Detector;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// Shadow rays stop this fraction short of the light so that an emitter's own quad never
/// occludes it (relative, so it holds at every scene scale).
pub(crate) const SHADOW_RAY_SHORTENING: f32 = 1e-4;
/// Most polarising sheets a shadow ray crosses before it counts as blocked.
const MAX_SHEETS_PER_SHADOW_RAY: usize = 16;

/// A sheet light passes straight through, met along a ray.
pub(crate) enum Sheet<'m> {
    Polarizer(&'m Polarizer),
    Retarder(&'m Retarder),
}

impl<'m> Sheet<'m> {
    /// The sheet `material` is, if it is one.
    pub(crate) fn of(material: &'m Material) -> Option<Self> {
        match material {
            Material::Polarizer(polarizer) => Some(Sheet::Polarizer(polarizer)),
            Material::Retarder(retarder) => Some(Sheet::Retarder(retarder)),
            _ => None,
        }
    }

    /// The sheet for light travelling along `forward` through it (at a surface of outward
    /// `normal`): its frame's x axis, its element (the same at every wavelength; the phase flipped
    /// under [`Fault::FlippedPhase`]) and the transmittance spectrum that scales it.
    pub(crate) fn element(
        &self,
        fault: Option<Fault>,
        normal: Vec3,
        forward: Vec3,
        wavelengths: &SampledWavelengths,
    ) -> (Vec3, JonesDiagonal, SampledSpectrum) {
        match self {
            Sheet::Polarizer(polarizer) => (
                polarizer.transmission_axis(normal, forward),
                JonesDiagonal::linear_polarizer(1.0),
                polarizer.transmittance.sample(wavelengths),
            ),
            Sheet::Retarder(retarder) => (
                retarder.fast_axis_across(normal, forward),
                element(fault, JonesDiagonal::linear_retarder(retarder.retardance_rad)),
                SampledSpectrum::splat(1.0),
            ),
        }
    }
}

/// What a depolarising receiver reads of unpolarised light of unit radiance sent toward it
/// along −`dir` from `distance` away, its shadow ray leaving `origin` (already offset off the
/// receiver) along `dir`: the detector's response (the sheets' polarisation; 1 without sheets)
/// and the product of the sheets' transmittance spectra, or `None` when something else blocks
/// it. `distance` is the full distance (infinite for the background); the ray stops
/// [`SHADOW_RAY_SHORTENING`] of it short.
pub(crate) fn through_sheets<B: Beam>(
    scene: &Scene,
    fault: Option<Fault>,
    origin: Vec3,
    dir: Vec3,
    distance: f32,
    wavelengths: &SampledWavelengths,
    stats: &mut TraceStats,
) -> Option<(f32, SampledSpectrum)> {
    let forward = -dir;
    let mut origin = origin;
    let mut remaining = distance * (1.0 - SHADOW_RAY_SHORTENING);
    let mut detector = Detector::RADIANCE;
    let mut spectrum = SampledSpectrum::splat(1.0);
    let mut detector_x: Option<Vec3> = None;
    for _ in 0..=MAX_SHEETS_PER_SHADOW_RAY {
        stats.rays += 1;
        let ray = Ray::new(origin, dir);
        let Some(blocker) = scene.geometry.intersect(&ray, remaining) else {
            return Some((detector.unpolarized_response(), spectrum));
        };
        let material = &scene.materials[scene.surfaces[blocker.prim as usize].material as usize];
        let sheet = Sheet::of(material)?;
        let (axis, element, transmittance) = sheet.element(fault, blocker.normal, forward, wavelengths);
        if B::POLARIZED {
            // The detector's frame so far is the previous sheet's: Stokes vectors come to it
            // from this sheet's frame.
            if let Some(x) = detector_x {
                detector = detector.rotated(rotation(fault, forward, axis, x));
            }
            detector = detector.through(&element);
            detector_x = Some(axis);
        } else {
            detector = detector.through(&JonesDiagonal::attenuator(element.a));
        }
        spectrum *= transmittance;
        remaining -= blocker.t;
        origin = spawn_origin(blocker.point, blocker.normal, dir);
    }
    None
}
