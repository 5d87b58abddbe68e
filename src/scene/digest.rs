//! The scene's digest: SHA-256 of the scene file's text and of every mesh file it loads, in the
//! order the file names them, then of its camera's lens file if it has one. Parts of a split render must come from the same scene: the merge
//! compares these digests (a scene file is not enough: an OBJ edited between two parts changes
//! the image).

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use super::desc::{SceneDesc, ShapeDesc};

/// Hex SHA-256 of `text` (the scene file at `path`), of each mesh file of `desc` and of its
/// lens file (`[camera] lens`), each input preceded by its length so that no two different sets
/// of inputs hash alike. A file that cannot be read adds nothing (the build then fails on it
/// anyway).
pub fn scene_digest(text: &str, path: &Path, desc: &SceneDesc) -> String {
    let mut hasher = Sha256::new();
    hasher.update((text.len() as u64).to_le_bytes());
    hasher.update(text.as_bytes());
    // A lens-system camera's prescription changes the image as a mesh does (after the meshes,
    // so that the digest of a scene without a lens is as it was).
    let lens = desc
        .camera
        .get_ref()
        .lens
        .as_ref()
        .map(|lens| path.parent().unwrap_or(Path::new(".")).join(lens.get_ref()));
    for obj in mesh_files(path, desc).into_iter().chain(lens) {
        if let Ok(bytes) = std::fs::read(obj) {
            hasher.update((bytes.len() as u64).to_le_bytes());
            hasher.update(&bytes);
        }
    }
    hex(&hasher.finalize())
}

/// The mesh files the scene file at `path` loads, in the order it names them, each as the
/// build opens it (relative to the scene file's directory).
pub fn mesh_files(path: &Path, desc: &SceneDesc) -> Vec<PathBuf> {
    desc.shapes
        .iter()
        .filter_map(|shape| match &shape.get_ref().0 {
            ShapeDesc::Mesh { file, .. } => Some(path.parent().unwrap_or(Path::new(".")).join(file)),
            _ => None,
        })
        .collect()
}

/// Lower-case hex of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
