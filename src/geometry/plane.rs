//! [`Plane`]: an infinite plane.

use glam::Vec3;

/// The infinite plane through `point` with unit `normal`; its outside is the side `normal` points to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point of the plane.
    pub point: Vec3,
    /// Unit normal.
    pub normal: Vec3,
}
