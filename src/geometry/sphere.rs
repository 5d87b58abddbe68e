//! [`Sphere`].

use glam::Vec3;

/// A sphere; its outside is where the normal points away from the centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre (scene units).
    pub center: Vec3,
    /// Radius (scene units, > 0).
    pub radius: f32,
}
