//! [`Retarder`]: an ideal linear retarder sheet (a wave plate, Mitsuba 3's `retarder`): light
//! passes straight through and its field component along the fast axis leads the other by
//! the retardance (90°: a quarter-wave plate, 180°: a half-wave plate), the same at every
//! wavelength (an achromatic plate).
//!
//! At oblique incidence the fast axis is projected onto the wavefront; the retardance is kept
//! (Mitsuba scales it by |cos θ|; both agree at normal incidence, where validation uses it).
//! Only flat shapes (quads and planes) take it.
//!
//! ```toml
//! [materials.quarter_wave]
//! type = "retarder"
//! fast_axis = [1, 1, 0]     # world space, projected onto the sheet
//! retardance_deg = 90
//! ```

use glam::Vec3;

use super::sheet_axis;
use crate::polarization::frame::any_perpendicular;

/// An ideal linear retarder.
#[derive(Debug, Clone, PartialEq)]
pub struct Retarder {
    /// The fast axis, world space, unit length (projected onto the sheet at each hit).
    pub fast_axis: Vec3,
    /// Phase lead of the fast-axis component, in radians.
    pub retardance_rad: f32,
}

impl Retarder {
    /// The effective fast axis for light travelling along `forward` through the sheet of normal
    /// `normal`: a unit vector perpendicular to `forward`.
    #[inline]
    pub fn fast_axis_across(&self, normal: Vec3, forward: Vec3) -> Vec3 {
        let fast = sheet_axis(self.fast_axis, normal);
        let across = fast - fast.dot(forward) * forward;
        let length_squared = across.length_squared();
        if length_squared > 1e-12 {
            across / length_squared.sqrt()
        } else {
            any_perpendicular(forward)
        }
    }
}
