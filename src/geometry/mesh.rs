//! [`Mesh`]: indexed triangle meshes, from OBJ files (tobj) or built in (the triangular prism).
//!
//! OBJ files are read with tobj (faces triangulated as fans, one index per vertex, points and
//! lines ignored, materials ignored: materials come from the scene file), and every object of
//! the file is merged into one mesh. Vertex normals are kept only when every vertex has one.
//! Errors name the file and what is wrong, with the line for parse errors.

use std::io::Cursor;
use std::path::Path;

use glam::{Affine3A, Mat3, Vec3};

use super::aabb::Aabb;
use super::triangle::{intersect_triangle, ShearedRay, TriangleHit};
use super::Hit;

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
    /// Unit vertex normals, one per position, when the file has them. A zero normal (some files
    /// have them) is allowed: shading falls back to the geometric normal where the interpolated
    /// normal vanishes.
    pub normals: Option<Vec<Vec3>>,
    /// Triangles as indices into `positions`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// A procedural test and benchmark mesh: a sphere of radius 1 with a 10 % bump
    /// (1 + 0.1·sin 7θ·cos 5φ), tessellated into `2·rings·segments` triangles; the pole rings are
    /// degenerate slivers, as in any UV sphere, which also exercises degenerate input.
    pub fn displaced_sphere(rings: u32, segments: u32) -> Mesh {
        let mut mesh = Mesh::default();
        for ring in 0..=rings {
            let theta = std::f32::consts::PI * ring as f32 / rings as f32;
            for segment in 0..segments {
                let phi = std::f32::consts::TAU * segment as f32 / segments as f32;
                let bump = 1.0 + 0.1 * (7.0 * theta).sin() * (5.0 * phi).cos();
                mesh.positions
                    .push(bump * Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()));
            }
        }
        for ring in 0..rings {
            for segment in 0..segments {
                let next = (segment + 1) % segments;
                let [a, b] = [ring * segments + segment, ring * segments + next];
                let [c, d] = [a + segments, b + segments];
                mesh.triangles.push([a, c, b]);
                mesh.triangles.push([b, c, d]);
            }
        }
        mesh
    }

    /// Loads every object of an OBJ file as one mesh (triangulated). Errors name the file.
    ///
    /// Errors: the file cannot be read; a line does not parse (the message gives the line); a
    /// face refers to a vertex that does not exist; the file has no triangles; a coordinate or
    /// normal is not finite.
    pub fn load_obj(path: &Path) -> Result<Mesh, MeshError> {
        let in_file = |problem: String| MeshError::Invalid(format!("{}: {problem}", path.display()));
        let bytes = std::fs::read(path).map_err(|e| in_file(format!("cannot read the file: {e}")))?;
        let mut reader = Cursor::new(bytes.as_slice());
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ignore_points: true,
            ignore_lines: true,
        };
        // `mtllib` lines are skipped: the scene file assigns materials.
        let loaded = tobj::load_obj_buf(&mut reader, &options, |_| Ok(Default::default()));
        let (models, _materials) = loaded.map_err(|error| {
            let line = line_before(&bytes, reader.position());
            in_file(describe_load_error(&error, line))
        })?;

        let mut mesh = Mesh::default();
        let mut normals = Some(Vec::new());
        for model in &models {
            let data = &model.mesh;
            let first = u32::try_from(mesh.positions.len())
                .map_err(|_| in_file("more than 2³² vertices".to_string()))?;
            let positions: Vec<Vec3> = data.positions.chunks_exact(3).map(Vec3::from_slice).collect();
            if data.normals.len() == data.positions.len() {
                if let Some(all) = normals.as_mut() {
                    all.extend(data.normals.chunks_exact(3).map(|n| Vec3::from_slice(n).normalize_or_zero()));
                }
            } else if !positions.is_empty() {
                normals = None;
            }
            for face in data.indices.chunks_exact(3) {
                let offset = |index: u32| {
                    index.checked_add(first).ok_or_else(|| {
                        in_file(format!("object '{}': vertex index {index} out of range", model.name))
                    })
                };
                mesh.triangles.push([offset(face[0])?, offset(face[1])?, offset(face[2])?]);
            }
            mesh.positions.extend(positions);
        }
        if mesh.triangles.is_empty() {
            return Err(in_file("no triangles (the file has no faces with 3 or more vertices)".to_string()));
        }
        mesh.normals = normals;
        mesh.validate().map_err(|MeshError::Invalid(problem)| in_file(problem))?;
        Ok(mesh)
    }

    /// A closed triangular prism: isosceles cross-section in the xy-plane with apex angle
    /// `apex_angle_rad` at the top (+y), the two equal faces of slant length `side_length`,
    /// extruded `length` along z, centred on the origin (the centroid of the cross-section at
    /// x = y = 0, z from -length/2 to length/2). Outward winding.
    ///
    /// 6 vertices, 8 triangles: the two caps and the three rectangular faces (2 triangles each).
    /// Without vertex normals (flat faces).
    ///
    /// # Panics
    /// When the parameters are out of range; [`Self::try_triangular_prism`] returns the error.
    pub fn triangular_prism(apex_angle_rad: f32, side_length: f32, length: f32) -> Mesh {
        match Self::try_triangular_prism(apex_angle_rad, side_length, length) {
            Ok(mesh) => mesh,
            Err(error) => panic!("{error}"),
        }
    }

    /// [`Self::triangular_prism`], or an error unless 0 < `apex_angle_rad` < π (radians) and
    /// `side_length` and `length` are positive and finite (scene units).
    pub fn try_triangular_prism(
        apex_angle_rad: f32,
        side_length: f32,
        length: f32,
    ) -> Result<Mesh, MeshError> {
        if !(apex_angle_rad > 0.0 && apex_angle_rad < std::f32::consts::PI) {
            return Err(MeshError::Invalid(format!(
                "prism apex angle must be between 0 and π rad, got {apex_angle_rad}"
            )));
        }
        for (name, value) in [("side length", side_length), ("length", length)] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(MeshError::Invalid(format!("prism {name} must be positive, got {value}")));
            }
        }
        let half_base = side_length * (0.5 * apex_angle_rad).sin();
        let height = side_length * (0.5 * apex_angle_rad).cos();
        // The centroid of a triangle is at a third of its height above the base.
        let apex_y = 2.0 * height / 3.0;
        let base_y = -height / 3.0;
        // Cross-section counter-clockwise seen from +z: apex, base left, base right.
        let section = [(0.0, apex_y), (-half_base, base_y), (half_base, base_y)];
        let half_length = 0.5 * length;
        // Vertices 0..3 at z = −length/2, 3..6 at z = +length/2.
        let positions: Vec<Vec3> = [-half_length, half_length]
            .iter()
            .flat_map(|&z| section.iter().map(move |&(x, y)| Vec3::new(x, y, z)))
            .collect();
        let mut triangles = vec![[0, 2, 1], [3, 4, 5]];
        // Each side face spans the section edge i → j at both ends; the outside of a
        // counter-clockwise polygon is to the right of its edges, which this winding faces.
        for (i, j) in [(0u32, 1u32), (1, 2), (2, 0)] {
            triangles.push([i, j, j + 3]);
            triangles.push([i, j + 3, i + 3]);
        }
        Ok(Mesh { positions, normals: None, triangles })
    }

    /// This mesh with every position (and normal) transformed by `transform`.
    ///
    /// Normals are transformed by the inverse transpose and renormalised. A mirroring
    /// transform (negative determinant) also reverses every triangle's winding so that it stays
    /// counter-clockwise seen from outside. A singular transform flattens the mesh; its normals
    /// are then dropped.
    pub fn transformed(&self, transform: &Affine3A) -> Mesh {
        let linear = Mat3::from(transform.matrix3);
        let determinant = linear.determinant();
        // Rows of the inverse times the determinant: the cofactor matrix, which maps normals
        // like the inverse transpose, up to the sign of the determinant.
        let cofactor = Mat3::from_cols(
            linear.y_axis.cross(linear.z_axis),
            linear.z_axis.cross(linear.x_axis),
            linear.x_axis.cross(linear.y_axis),
        );
        let normals = match &self.normals {
            Some(normals) if determinant != 0.0 => Some(
                normals
                    .iter()
                    .map(|&n| (determinant.signum() * (cofactor * n)).normalize_or_zero())
                    .collect(),
            ),
            _ => None,
        };
        let triangles = if determinant < 0.0 {
            self.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
        } else {
            self.triangles.clone()
        };
        Mesh {
            positions: self.positions.iter().map(|&p| transform.transform_point3(p)).collect(),
            normals,
            triangles,
        }
    }

    /// Checks what [`super::Geometry::build`] relies on: finite positions, one finite normal per
    /// position (if any), and triangle indices within `positions`.
    pub fn validate(&self) -> Result<(), MeshError> {
        let invalid = |problem: String| Err(MeshError::Invalid(problem));
        if let Some(index) = self.positions.iter().position(|p| !p.is_finite()) {
            return invalid(format!("vertex {index} has a non-finite position {}", self.positions[index]));
        }
        if let Some(normals) = &self.normals {
            if normals.len() != self.positions.len() {
                return invalid(format!("{} normals for {} vertices", normals.len(), self.positions.len()));
            }
            if let Some(index) = normals.iter().position(|n| !n.is_finite()) {
                return invalid(format!("vertex {index} has a non-finite normal {}", normals[index]));
            }
        }
        let count = self.positions.len();
        for (index, triangle) in self.triangles.iter().enumerate() {
            if let Some(vertex) = triangle.iter().find(|&&v| v as usize >= count) {
                return invalid(format!(
                    "triangle {index} refers to vertex {vertex}, but there are only {count} vertices"
                ));
            }
        }
        Ok(())
    }

    /// The three vertex positions of triangle `tri`.
    ///
    /// # Panics
    /// If `tri` or one of its indices is out of range ([`Self::validate`] checks the indices).
    #[inline]
    pub fn triangle(&self, tri: u32) -> [Vec3; 3] {
        self.triangles[tri as usize].map(|index| self.positions[index as usize])
    }

    /// The bounding box of triangle `tri`. Panics as [`Self::triangle`].
    pub fn triangle_bounds(&self, tri: u32) -> Aabb {
        Aabb::from_points(&self.triangle(tri))
    }

    /// The intersection of `ray` with triangle `tri`, for t in (0, `t_max`), from either side;
    /// `prim` is copied into the hit. The normal follows the counter-clockwise winding; the
    /// shading normal interpolates the vertex normals (when present and not vanishing), turned
    /// to the side of the normal. Panics as [`Self::triangle`].
    #[inline]
    pub fn intersect_triangle(&self, tri: u32, ray: &ShearedRay, t_max: f32, prim: u32) -> Option<Hit> {
        let vertices = self.triangle(tri);
        let hit = intersect_triangle(ray, &vertices, t_max)?;
        self.hit_record(tri, &vertices, &hit, prim)
    }

    /// The hit record of `hit` on triangle `tri`, whose vertices are `vertices`; `None` when the
    /// triangle has no normal (its edges' cross product vanishes in f32), which
    /// [`Self::intersect_triangle`] therefore never reports. Panics as [`Self::triangle`].
    #[inline]
    pub(crate) fn hit_record(
        &self,
        tri: u32,
        vertices: &[Vec3; 3],
        hit: &TriangleHit,
        prim: u32,
    ) -> Option<Hit> {
        let flat = flat_hit_record(vertices, hit, prim)?;
        let normal = flat.normal;
        let shading_normal = self
            .normals
            .as_ref()
            .and_then(|normals| {
                let [i0, i1, i2] = self.triangles[tri as usize];
                let [b0, b1, b2] = hit.barycentric;
                (b0 * normals[i0 as usize] + b1 * normals[i1 as usize] + b2 * normals[i2 as usize])
                    .try_normalize()
            })
            .map_or(normal, |n| if n.dot(normal) < 0.0 { -n } else { n });
        Some(Hit { shading_normal, ..flat })
    }
}

/// The hit record of a hit on the triangle `vertices` (shape `prim`) with the geometric normal
/// as shading normal, as for a mesh without vertex normals; `None` for a degenerate triangle.
pub(crate) fn flat_hit_record(vertices: &[Vec3; 3], hit: &TriangleHit, prim: u32) -> Option<Hit> {
    let [v0, v1, v2] = *vertices;
    let normal = (v1 - v0).cross(v2 - v0).try_normalize()?;
    Some(Hit { t: hit.t, point: hit.point(vertices), normal, shading_normal: normal, prim })
}

/// The 1-based number of the line that ends just before byte `position` (the last line tobj read).
fn line_before(bytes: &[u8], position: u64) -> usize {
    let end = usize::try_from(position).map_or(bytes.len(), |p| p.min(bytes.len()));
    1 + bytes[..end.saturating_sub(1)].iter().filter(|&&b| b == b'\n').count()
}

/// A sentence for a tobj error found after reading `line`.
fn describe_load_error(error: &tobj::LoadError, line: usize) -> String {
    use tobj::LoadError as E;
    match error {
        // tobj checks indices when an object ends, not on the face line.
        E::FaceVertexOutOfBounds
        | E::FaceNormalOutOfBounds
        | E::FaceTexCoordOutOfBounds
        | E::FaceColorOutOfBounds => {
            format!(
                "{error}: a face refers to an element that does not exist \
                 (found at line {line}, where the object holding the face ends)"
            )
        }
        E::ReadError => format!("cannot read line {line} (is the file UTF-8 text?)"),
        _ => format!("parse error at line {line}: {error}"),
    }
}

#[cfg(test)]
mod tests {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_3, PI};
    use std::io::Write;
    use std::path::PathBuf;

    use super::*;
    use crate::geometry::Ray;

    fn data(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/geometry").join(name)
    }

    fn load_text(text: &str) -> (tempfile::NamedTempFile, Result<Mesh, MeshError>) {
        let mut file = tempfile::Builder::new().suffix(".obj").tempfile().expect("temporary file");
        file.write_all(text.as_bytes()).expect("write");
        let result = Mesh::load_obj(file.path());
        (file, result)
    }

    fn error_of(text: &str) -> String {
        let (file, result) = load_text(text);
        let message = result.expect_err("load should fail").to_string();
        let name = file.path().display().to_string();
        assert!(message.starts_with(&name), "message does not name the file: {message}");
        message
    }

    fn face_normal(mesh: &Mesh, tri: u32) -> Vec3 {
        let [v0, v1, v2] = mesh.triangle(tri);
        (v1 - v0).cross(v2 - v0).normalize()
    }

    #[test]
    fn loads_and_merges_every_object() {
        // Two objects: a quad (fan-triangulated into 2 triangles) with normals and a triangle
        // with normals: 3 triangles, 7 vertices (single index), normals kept.
        let mesh = Mesh::load_obj(&data("two_objects.obj")).expect("valid file");
        assert_eq!(mesh.triangles.len(), 3);
        assert_eq!(mesh.positions.len(), 7);
        let normals = mesh.normals.as_ref().expect("normals");
        assert_eq!(normals.len(), 7);
        // The quad lies in z = 0 wound counter-clockwise seen from +z; its file normals are +z.
        assert_eq!(face_normal(&mesh, 0), Vec3::Z);
        assert!(normals.iter().take(4).all(|&n| n == Vec3::Z));
        // The second object's indices are offset past the first object's vertices.
        assert!(mesh.triangles[2].iter().all(|&i| i >= 4));
        assert_eq!(mesh.positions[mesh.triangles[2][0] as usize], Vec3::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn normals_dropped_when_some_vertices_lack_them() {
        let (_file, mesh) =
            load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\no b\nf 1 2 3\n");
        let mesh = mesh.expect("valid file");
        assert_eq!(mesh.triangles.len(), 2);
        assert_eq!(mesh.normals, None);
    }

    #[test]
    fn missing_file_is_named() {
        let path = data("does_not_exist.obj");
        let message = Mesh::load_obj(&path).expect_err("no such file").to_string();
        assert!(message.contains("does_not_exist.obj") && message.contains("cannot read"), "{message}");
    }

    #[test]
    fn parse_error_names_the_line() {
        // Line 3 has a vertex with two coordinates.
        let message = error_of("# a broken file\nv 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n");
        assert!(message.contains("line 3") && message.contains("parse"), "{message}");
    }

    #[test]
    fn no_triangles_is_an_error() {
        let message = error_of("v 0 0 0\nv 1 0 0\nl 1 2\n");
        assert!(message.contains("no triangles"), "{message}");
    }

    #[test]
    fn index_out_of_range_is_an_error() {
        // Face refers to vertex 4 of 3.
        let message = error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
        assert!(message.contains("does not exist"), "{message}");
    }

    #[test]
    fn binary_garbage_names_the_line() {
        // Line 2 is not UTF-8 text.
        let mut file = tempfile::Builder::new().suffix(".obj").tempfile().expect("temporary file");
        file.write_all(b"v 0 0 0\n\xff\xfe\n").expect("write");
        let message = Mesh::load_obj(file.path()).expect_err("not text").to_string();
        assert!(message.contains("line 2"), "{message}");
    }

    #[test]
    fn non_finite_coordinate_is_an_error() {
        // Rust parses "nan" and "inf" as floats; the mesh must refuse them.
        let message = error_of("v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
        assert!(message.contains("non-finite"), "{message}");
        let message = error_of("v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n");
        assert!(message.contains("non-finite"), "{message}");
    }

    #[test]
    fn prism_is_closed_and_outward() {
        let apex = FRAC_PI_3;
        let prism = Mesh::triangular_prism(apex, 2.0, 3.0);
        assert_eq!((prism.positions.len(), prism.triangles.len()), (6, 8));
        prism.validate().expect("valid prism");
        // Centred: the vertex centroid is the centroid of the cross-section (at the origin).
        let centroid = prism.positions.iter().sum::<Vec3>() / 6.0;
        assert!(centroid.length() < 1e-6, "centroid {centroid}");
        // Outward: every face normal points away from the centroid.
        for tri in 0..8 {
            let [v0, v1, v2] = prism.triangle(tri);
            let face_centre = (v0 + v1 + v2) / 3.0;
            assert!(face_normal(&prism, tri).dot(face_centre - centroid) > 0.0, "triangle {tri} faces in");
        }
        // Closed: every edge is shared by exactly two triangles, in opposite directions.
        for &[a, b, c] in &prism.triangles {
            for (from, to) in [(a, b), (b, c), (c, a)] {
                let reversed = prism
                    .triangles
                    .iter()
                    .filter(|t| (0..3).any(|k| t[k] == to && t[(k + 1) % 3] == from))
                    .count();
                assert_eq!(reversed, 1, "edge {from}→{to}");
            }
        }
        // Extent: z from −1.5 to 1.5; slant faces of length 2 meeting at the apex.
        let bounds = Aabb::from_points(&prism.positions);
        assert_eq!((bounds.min.z, bounds.max.z), (-1.5, 1.5));
        assert!(((prism.positions[1] - prism.positions[0]).length() - 2.0).abs() < 1e-6);
    }

    #[test]
    fn prism_apex_angle_is_the_requested_one() {
        // The slanted faces (triangles 2 and 6: edges apex→left and right→apex) meet at the
        // apex edge with an interior dihedral angle equal to the apex angle, so their outward
        // normals are π − apex apart.
        for apex in [0.3, FRAC_PI_3, FRAC_PI_2, 2.5] {
            let prism = Mesh::triangular_prism(apex, 1.0, 1.0);
            let between_normals = face_normal(&prism, 2).dot(face_normal(&prism, 6)).clamp(-1.0, 1.0).acos();
            assert!((PI - between_normals - apex).abs() < 1e-5, "apex {apex}: got {}", PI - between_normals);
        }
    }

    #[test]
    fn prism_rejects_bad_parameters() {
        assert!(Mesh::try_triangular_prism(0.0, 1.0, 1.0).is_err());
        assert!(Mesh::try_triangular_prism(PI, 1.0, 1.0).is_err());
        assert!(Mesh::try_triangular_prism(1.0, -1.0, 1.0).is_err());
        assert!(Mesh::try_triangular_prism(1.0, 1.0, f32::NAN).is_err());
    }

    #[test]
    fn transform_moves_points_and_normals() {
        // Scale x by 2 and translate by (1, 0, 0): a normal (1, 1, 0)/√2 becomes (1, 2, 0)/√5
        // (the inverse transpose scales x by 1/2, then renormalise).
        let mesh = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: Some(vec![Vec3::new(1.0, 1.0, 0.0).normalize(); 3]),
            triangles: vec![[0, 1, 2]],
        };
        let transform =
            Affine3A::from_scale_rotation_translation(Vec3::new(2.0, 1.0, 1.0), Default::default(), Vec3::X);
        let moved = mesh.transformed(&transform);
        assert_eq!(moved.positions[1], Vec3::new(3.0, 0.0, 0.0));
        let normal = moved.normals.as_ref().expect("normals")[0];
        assert!((normal - Vec3::new(1.0, 2.0, 0.0).normalize()).length() < 1e-6, "{normal}");
        assert_eq!(moved.triangles, mesh.triangles);
    }

    #[test]
    fn mirror_keeps_the_outside_outside() {
        // Mirroring x flips the winding: the prism's faces must still face outward, and
        // vertex normals must follow the mirror (not flip).
        let mut prism = Mesh::triangular_prism(1.0, 1.0, 1.0);
        prism.normals = Some(prism.positions.iter().map(|p| p.normalize()).collect());
        let mirrored = prism.transformed(&Affine3A::from_scale(Vec3::new(-1.0, 1.0, 1.0)));
        for tri in 0..8 {
            let [v0, v1, v2] = mirrored.triangle(tri);
            assert!(face_normal(&mirrored, tri).dot((v0 + v1 + v2) / 3.0) > 0.0, "triangle {tri} faces in");
        }
        let normals = mirrored.normals.as_ref().expect("normals");
        for (p, n) in mirrored.positions.iter().zip(normals) {
            assert!((p.normalize() - *n).length() < 1e-6);
        }
    }

    #[test]
    fn validate_catches_bad_meshes() {
        let bad_index = Mesh { positions: vec![Vec3::ZERO; 3], normals: None, triangles: vec![[0, 1, 3]] };
        assert!(bad_index.validate().is_err());
        let bad_normals = Mesh {
            positions: vec![Vec3::ZERO; 3],
            normals: Some(vec![Vec3::Z; 2]),
            triangles: vec![[0, 1, 2]],
        };
        assert!(bad_normals.validate().is_err());
    }

    #[test]
    fn back_side_hit_keeps_the_winding_normal() {
        // The triangle is wound counter-clockwise seen from +z. Hit from below: the hit is
        // reported (two-sided) and the normal stays +z (outward by winding).
        let mesh =
            Mesh { positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y], normals: None, triangles: vec![[0, 1, 2]] };
        let ray = ShearedRay::new(Ray::new(Vec3::new(0.2, 0.2, -1.0), Vec3::Z));
        let hit = mesh.intersect_triangle(0, &ray, f32::INFINITY, 4).expect("back side hit");
        assert_eq!((hit.t, hit.normal, hit.shading_normal, hit.prim), (1.0, Vec3::Z, Vec3::Z, 4));
        assert!((hit.point - Vec3::new(0.2, 0.2, 0.0)).length() < 1e-6);
    }

    #[test]
    fn shading_normal_interpolates_and_faces_the_normal_side() {
        // The winding normal is +z. The ray hits at weights (0.5, 0.25, 0.25), where the shading
        // normal is 0.5·(1,0,1)/√2 + 0.25·z + 0.25·z, normalised.
        let mut mesh = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: Some(vec![Vec3::new(1.0, 0.0, 1.0).normalize(), Vec3::Z, Vec3::Z]),
            triangles: vec![[0, 1, 2]],
        };
        let ray = ShearedRay::new(Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z));
        let hit = mesh.intersect_triangle(0, &ray, f32::INFINITY, 0).expect("hit");
        let expected = (0.5 * Vec3::new(1.0, 0.0, 1.0).normalize() + 0.5 * Vec3::Z).normalize();
        assert!((hit.shading_normal - expected).length() < 1e-6);
        assert_eq!(hit.normal, Vec3::Z);
        // Vertex normals on the other side are turned to the side of the geometric normal.
        mesh.normals = Some(vec![-Vec3::Z; 3]);
        let turned = mesh.intersect_triangle(0, &ray, f32::INFINITY, 0).expect("hit");
        assert_eq!(turned.shading_normal, Vec3::Z);
        // Vertex normals that cancel at the hit point (0.5·x − 0.25·x − 0.25·x = 0): the
        // geometric normal is used.
        mesh.normals = Some(vec![Vec3::X, -Vec3::X, -Vec3::X]);
        let vanishing = mesh.intersect_triangle(0, &ray, f32::INFINITY, 0).expect("hit");
        assert_eq!(vanishing.shading_normal, Vec3::Z);
    }
}
