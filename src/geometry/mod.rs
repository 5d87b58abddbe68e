//! Geometry: rays, the shapes prisma can intersect (spheres, infinite planes, quads, triangles of
//! meshes), mesh loading and the built-in prism, a BVH over the finite shapes, and robust spawning
//! of secondary rays. Lengths are in scene units; directions are unit vectors.

pub mod aabb;
pub mod accel;
pub mod bvh;
pub mod mesh;
pub mod offset;
pub mod plane;
pub mod quad;
pub mod ray;
pub mod shape;
pub mod sphere;
pub mod triangle;

pub use accel::Geometry;
pub use mesh::{Mesh, MeshError};
pub use offset::spawn_origin;
pub use plane::Plane;
pub use quad::Quad;
pub use ray::{Hit, Ray};
pub use shape::Shape;
pub use sphere::Sphere;
