//! The scene's digest: SHA-256 of the scene file's text and of every mesh file it loads, in the
//! order the file names them. Parts of a split render must come from the same scene: the merge
//! compares these digests (a scene file is not enough: an OBJ edited between two parts changes
//! the image).

use std::path::Path;

use sha2::{Digest, Sha256};

use super::desc::{SceneDesc, ShapeDesc};

/// Hex SHA-256 of `text` (the scene file at `path`) and of each mesh file of `desc`, each input
/// preceded by its length so that no two different sets of inputs hash alike. A mesh file that
/// cannot be read adds nothing (the build then fails on it anyway).
pub fn scene_digest(text: &str, path: &Path, desc: &SceneDesc) -> String {
    let mut hasher = Sha256::new();
    hasher.update((text.len() as u64).to_le_bytes());
    hasher.update(text.as_bytes());
    for shape in &desc.shapes {
        if let ShapeDesc::Mesh { file, .. } = &shape.get_ref().0 {
            let obj = path.parent().unwrap_or(Path::new(".")).join(file);
            if let Ok(bytes) = std::fs::read(obj) {
                hasher.update((bytes.len() as u64).to_le_bytes());
                hasher.update(&bytes);
            }
        }
    }
    hex(&hasher.finalize())
}

/// Lower-case hex of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
