//! [`Geometry`]: every shape of the scene, with a BVH over the finite ones and the infinite planes
//! tested separately.

use super::{Hit, Mesh, Ray, Shape};

/// The intersectable scene.
#[derive(Debug, Clone)]
pub struct Geometry {
    shapes: Vec<Shape>,
    meshes: Vec<Mesh>,
}

impl Geometry {
    /// Builds the acceleration structure over `shapes` (triangles refer into `meshes`).
    pub fn build(shapes: Vec<Shape>, meshes: Vec<Mesh>) -> Self {
        Self { shapes, meshes }
    }
    /// The nearest hit with t in (0, `t_max`).
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let _ = (ray, t_max, &self.shapes, &self.meshes);
        todo!()
    }
    /// True when anything is hit with t in (0, `t_max`) (shadow rays).
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let _ = (ray, t_max);
        todo!()
    }
    /// The shapes in the order given to [`Self::build`].
    pub fn shapes(&self) -> &[Shape] {
        &self.shapes
    }
}
