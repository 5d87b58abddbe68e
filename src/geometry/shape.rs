//! [`Shape`]: the closed set of primitives.

use super::{Plane, Quad, Sphere};

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
