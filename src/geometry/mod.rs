//! Geometry: rays, the shapes prisma can intersect (spheres, infinite planes, quads, triangles of
//! meshes), mesh loading and the built-in prism, a BVH over the finite shapes, and robust spawning
//! of secondary rays. Lengths are in scene units; directions are unit vectors.
//!
//! # Map
//! * [`ray`]: [`Ray`] and the [`Hit`] record. [`shape`]: the [`Shape`] enum dispatching to
//!   [`sphere`], [`plane`], [`quad`] and mesh triangles ([`mesh`], [`triangle`]).
//! * [`accel`]: [`Geometry`], the scene's intersector: a linear scan over the infinite planes,
//!   then the [`bvh`] (binned SAH, 8-wide nodes tested with 8-wide vector arithmetic, robust
//!   slab test) over the rest, whose leaves hold the shapes copied into 4-wide packets
//!   (`packet`). `Hit::prim` is the index of the shape in the list given to
//!   [`Geometry::build`]. [`Geometry::intersect_packet`] and [`Geometry::occluded_packet`]
//!   trace up to [`PACKET_RAYS`] coherent rays together (the BVH's packet traversal), with
//!   the same answers as ray by ray.
//! * [`offset`]: [`spawn_origin`] for secondary rays.
//!
//! # Decisions
//! * **Self-intersection is handled on both ends.** [`spawn_origin`] pushes the origin off the
//!   surface by the rounding error of the point's coordinates, and every intersection routine
//!   rejects distances that are not provably positive given its own rounding error (error
//!   bounds in the style of PBR 3rd ed. §3.9). The second part covers the error that scales with
//!   the shape's size instead of the point's coordinates, which the first cannot see from the
//!   point alone; together they let the push stay a few ULPs, so grazing rays near corners do
//!   not jump through the neighbouring wall (an integer-ULP offset of 256 ULPs, as in Wächter &
//!   Binder's method, is 0.016 at 1000 units: more than the diameter of a 0.01 sphere there).
//! * **Watertight triangles, and quads as two of them** (Woop et al. 2013): closed meshes and
//!   boxes built of quads with shared corners do not leak along edges.
//! * **Numerically careful spheres** (*Ray Tracing Gems* ch. 7): small spheres far away stay
//!   round.
//! * **Several at a time, decided exactly**: BVH nodes test eight boxes and leaf packets four
//!   triangles in one go (a scene of at most eight quads and four spheres tests all its quads'
//!   halves in one 16-wide pass, `quad_lanes`); the 4- and 16-wide triangle tests are one
//!   generic test (`triangle_lanes`) that repeats the scalar watertight test's arithmetic
//!   operation for operation and leaves the lanes it cannot decide (an edge function of
//!   exactly 0) to the scalar test, so hits (and their error bounds) are exactly those of the
//!   shapes' own routines.
//! * **Hit records are built once per ray**: the nearest-hit search keeps the distance and
//!   barycentrics of the best candidate and builds the [`Hit`] (normals, point) for the one it
//!   returns, with the shapes' own code.

pub mod aabb;
pub mod accel;
pub mod bvh;
pub(crate) mod huge_pages;
pub mod mesh;
pub mod offset;
mod packet;
pub mod plane;
pub mod quad;
mod quad_lanes;
pub mod ray;
mod rounding;
pub mod shape;
pub mod sphere;
mod sphere_lanes;
#[cfg(test)]
mod test_util;
pub mod triangle;
mod triangle_lanes;

pub use aabb::Aabb;
pub use accel::Geometry;
pub use bvh::{BvhStats, PACKET_RAYS};
pub use mesh::{Mesh, MeshError};
pub use offset::spawn_origin;
pub use plane::Plane;
pub use quad::Quad;
pub use ray::{Hit, Ray};
pub use shape::Shape;
pub use sphere::Sphere;
pub use triangle::ShearedRay;
