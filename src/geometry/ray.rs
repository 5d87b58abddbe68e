//! [`Ray`] and the [`Hit`] record of an intersection.

use glam::Vec3;

/// A half-line `origin + t·dir`, t > 0, with `dir` a unit vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point (scene units).
    pub origin: Vec3,
    /// Unit travel direction.
    pub dir: Vec3,
}

impl Ray {
    /// A ray from `origin` along the unit vector `dir`.
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        debug_assert!((dir.length_squared() - 1.0).abs() < 1e-3, "ray direction not unit: {dir}");
        Self { origin, dir }
    }
    /// The point at distance `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}

/// The nearest intersection of a ray with the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray (scene units, since `dir` is unit).
    pub t: f32,
    /// The hit point, on the surface as closely as the shape can place it.
    pub point: Vec3,
    /// Unit geometric normal pointing to the shape's outside (for planes and quads, their stated
    /// normal; for meshes, by counter-clockwise winding), whatever side the ray came from.
    pub normal: Vec3,
    /// Unit shading normal (interpolated vertex normals of meshes; else equal to `normal`), on the
    /// same side as `normal`.
    pub shading_normal: Vec3,
    /// Index of the hit shape in the list given to [`super::Geometry::build`].
    pub prim: u32,
}
