//! [`Polarizer`]: an ideal linear polariser sheet (Mitsuba 3's `polarizer`): light passes
//! straight through, keeping the fraction `transmittance` of its field component along the
//! transmission axis and none of the other. Unpolarised light keeps half its power.
//!
//! At oblique incidence the sheet acts as a dichroic film whose absorbing axis a = n × t lies in
//! its plane (Korger et al., "The polarization properties of a tilted polarizer", Opt. Express
//! 21, 2013, as Mitsuba does): the field component along a's projection onto the wavefront is
//! absorbed, so the effective transmission axis is f × normalize(a − (a·f) f) for light
//! travelling along f. At normal incidence it is the axis itself.
//!
//! Only flat shapes (quads and planes) take it; the axis is given in world space and projected
//! onto the sheet's plane.
//!
//! ```toml
//! [materials.analyser]
//! type = "polarizer"
//! axis = [1, 0, 0]          # transmission axis (world space, projected onto the sheet)
//! transmittance = 1         # optional spectrum, 1 by default
//! ```

use glam::Vec3;

use super::sheet_axis;
use crate::polarization::frame::any_perpendicular;
use crate::spectrum::DenseSpectrum;

/// An ideal linear polariser.
#[derive(Debug, Clone)]
pub struct Polarizer {
    /// The transmission axis, world space, unit length (projected onto the sheet at each hit).
    pub axis: Vec3,
    /// Fraction of the field power along the axis that is transmitted, per wavelength.
    pub transmittance: DenseSpectrum,
}

impl Polarizer {
    /// The effective transmission axis for light travelling along `forward` through the sheet
    /// of normal `normal`: a unit vector perpendicular to `forward`.
    #[inline]
    pub fn transmission_axis(&self, normal: Vec3, forward: Vec3) -> Vec3 {
        let absorbing = normal.cross(sheet_axis(self.axis, normal));
        let across = absorbing - absorbing.dot(forward) * forward;
        let length_squared = across.length_squared();
        if length_squared > 1e-12 {
            forward.cross(across / length_squared.sqrt())
        } else {
            // Light travelling along the absorbing axis has no field along it.
            any_perpendicular(forward)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_normal_incidence_the_transmission_axis_is_the_axis() {
        let polarizer = Polarizer {
            axis: Vec3::new(1.0, 1.0, 0.0).normalize(),
            transmittance: DenseSpectrum::constant(1.0),
        };
        for forward in [Vec3::Z, -Vec3::Z] {
            let axis = polarizer.transmission_axis(Vec3::Z, forward);
            assert!((axis.dot(polarizer.axis).abs() - 1.0).abs() < 1e-6, "{axis}");
        }
    }

    /// Tilting the sheet about its transmission axis leaves that axis in the wavefront: the
    /// effective axis is still the axis.
    #[test]
    fn tilting_about_the_axis_keeps_the_axis() {
        let polarizer = Polarizer { axis: Vec3::X, transmittance: DenseSpectrum::constant(1.0) };
        let normal = Vec3::new(0.0, 0.5, 1.0).normalize();
        let axis = polarizer.transmission_axis(normal, Vec3::Z);
        assert!((axis.dot(Vec3::X).abs() - 1.0).abs() < 1e-6, "{axis}");
    }
}
