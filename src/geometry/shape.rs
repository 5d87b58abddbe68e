//! [`Shape`]: the closed set of primitives, with one-line dispatch to each variant.

use super::aabb::Aabb;
use super::triangle::ShearedRay;
use super::{Hit, Mesh, Plane, Quad, Sphere};

/// One primitive of the scene. A triangle is an index into a mesh, not a copy of its vertices.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A sphere.
    Sphere(Sphere),
    /// An infinite plane (not in the BVH).
    Plane(Plane),
    /// A parallelogram.
    Quad(Quad),
    /// Triangle `tri` of mesh `mesh` (indices into the meshes given to [`super::Geometry::build`]).
    Triangle {
        /// Mesh index.
        mesh: u32,
        /// Triangle index within the mesh.
        tri: u32,
    },
}

impl Shape {
    /// The bounding box, or `None` for an infinite plane. Triangles look their vertices up in
    /// `meshes`.
    ///
    /// # Panics
    /// If a triangle's mesh, triangle or vertex index is out of range.
    pub fn bounds(&self, meshes: &[Mesh]) -> Option<Aabb> {
        match self {
            Shape::Sphere(sphere) => Some(sphere.bounds()),
            Shape::Plane(_) => None,
            Shape::Quad(quad) => Some(quad.bounds()),
            Shape::Triangle { mesh, tri } => Some(meshes[*mesh as usize].triangle_bounds(*tri)),
        }
    }

    /// The nearest intersection with t in (0, `t_max`); `prim` is copied into the hit.
    ///
    /// # Panics
    /// As [`Self::bounds`].
    #[inline]
    pub fn intersect(&self, meshes: &[Mesh], ray: &ShearedRay, t_max: f32, prim: u32) -> Option<Hit> {
        match self {
            Shape::Sphere(sphere) => sphere.intersect(&ray.ray, t_max, prim),
            Shape::Plane(plane) => plane.intersect(&ray.ray, t_max, prim),
            Shape::Quad(quad) => quad.intersect(ray, t_max, prim),
            Shape::Triangle { mesh, tri } => {
                meshes[*mesh as usize].intersect_triangle(*tri, ray, t_max, prim)
            }
        }
    }
}
