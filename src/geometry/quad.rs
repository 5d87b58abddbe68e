//! [`Quad`]: a parallelogram.

use glam::Vec3;

/// The parallelogram `corner + u·edge1 + v·edge2`, u, v in [0, 1]. Its outside (normal) is along
/// `edge1 × edge2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    /// One corner.
    pub corner: Vec3,
    /// First edge from the corner.
    pub edge1: Vec3,
    /// Second edge from the corner.
    pub edge2: Vec3,
}

impl Quad {
    /// Unit normal along `edge1 × edge2`.
    pub fn normal(&self) -> Vec3 {
        self.edge1.cross(self.edge2).normalize()
    }
    /// Area (scene units²).
    pub fn area(&self) -> f32 {
        self.edge1.cross(self.edge2).length()
    }
    /// The point at parameters (u, v) in [0, 1]².
    pub fn point_at(&self, u: f32, v: f32) -> Vec3 {
        self.corner + u * self.edge1 + v * self.edge2
    }
}
