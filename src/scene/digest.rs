//! The scene's digest: SHA-256 of the scene file's text and of every mesh file it loads, in the
//! order the file names them, then of its camera's lens file if it has one, then of its films'
//! thickness textures. Parts of a split render must come from the same scene: the merge
//! compares these digests (a scene file is not enough: an OBJ edited between two parts changes
//! the image).

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use super::desc::{MaterialDesc, SceneDesc, ShapeDesc};

/// Hex SHA-256 of `text` (the scene file at `path`), of each mesh file of `desc` and of its
/// lens file (`[camera] lens`), each input preceded by its length so that no two different sets
/// of inputs hash alike. A file that cannot be read adds nothing (the build then fails on it
/// anyway).
pub fn scene_digest(text: &str, path: &Path, desc: &SceneDesc) -> String {
    let mut hasher = Sha256::new();
    hasher.update((text.len() as u64).to_le_bytes());
    hasher.update(text.as_bytes());
    // A lens-system camera's prescription changes the image as a mesh does (after the meshes,
    // so that the digest of a scene without a lens is as it was); then the films' thickness
    // textures (after the lens, so that the digest of a scene without one is as it was).
    for (obj, _) in input_files(path, desc) {
        if let Ok(bytes) = std::fs::read(obj) {
            hasher.update((bytes.len() as u64).to_le_bytes());
            hasher.update(&bytes);
        }
    }
    hex(&hasher.finalize())
}

/// Every file besides itself that the scene file at `path` reads, each as the build opens it
/// (relative to the scene file's directory) with what it is: its meshes in the order it names
/// them, the lens-system camera's prescription, the films' thickness textures in the order of
/// the materials' names. The digest hashes them in this order; no output may replace them.
pub fn input_files(path: &Path, desc: &SceneDesc) -> Vec<(PathBuf, &'static str)> {
    let lens = desc
        .camera
        .get_ref()
        .lens
        .as_ref()
        .map(|lens| path.parent().unwrap_or(Path::new(".")).join(lens.get_ref()));
    let meshes = mesh_files(path, desc).into_iter().map(|file| (file, "a mesh the scene loads"));
    let lens = lens.into_iter().map(|file| (file, "the lens file the scene loads"));
    let textures = texture_files(path, desc).into_iter().map(|file| (file, "a texture the scene loads"));
    meshes.chain(lens).chain(textures).collect()
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

/// The films' thickness textures the scene file at `path` loads, in the order of the
/// materials' names, each as the build opens it (relative to the scene file's directory).
pub fn texture_files(path: &Path, desc: &SceneDesc) -> Vec<PathBuf> {
    desc.materials
        .values()
        .filter_map(|material| match &material.get_ref().0 {
            MaterialDesc::Film { thickness_nm, .. } => thickness_nm.0.texture.as_ref(),
            _ => None,
        })
        .map(|file| path.parent().unwrap_or(Path::new(".")).join(file))
        .collect()
}

/// Lower-case hex of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
