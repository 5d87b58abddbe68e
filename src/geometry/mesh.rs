//! [`Mesh`]: indexed triangle meshes, from OBJ files (tobj) or built in (the triangular prism).

use std::path::Path;

use glam::{Affine3A, Vec3};

/// Why a mesh could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The message names the file and the problem (and the line where the parser gives one).
    #[error("{0}")]
    Invalid(String),
}

/// An indexed triangle mesh in scene space.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Mesh {
    /// Vertex positions (scene units).
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position, when the file has them.
    pub normals: Option<Vec<Vec3>>,
    /// Triangles as indices into `positions`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// Loads every object of an OBJ file as one mesh (triangulated). Errors name the file.
    pub fn load_obj(path: &Path) -> Result<Mesh, MeshError> {
        let _ = path;
        todo!()
    }
    /// A closed triangular prism: isosceles cross-section in the xy-plane with apex angle
    /// `apex_angle_rad` at the top (+y), the two equal faces of slant length `side_length`,
    /// extruded `length` along z, centred on the origin (the centroid of the cross-section at
    /// x = y = 0, z from -length/2 to length/2). Outward winding.
    pub fn triangular_prism(apex_angle_rad: f32, side_length: f32, length: f32) -> Mesh {
        let _ = (apex_angle_rad, side_length, length);
        todo!()
    }
    /// This mesh with every position (and normal) transformed by `transform`.
    pub fn transformed(&self, transform: &Affine3A) -> Mesh {
        let _ = transform;
        todo!()
    }
}
