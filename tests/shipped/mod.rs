//! Shared by the render tests: a shipped scene (scenes/) at a test's own resolution.

use std::path::Path;

use prisma::scene::Scene;

/// `scenes/<name>` rendered at `width`×`height`.
pub fn scene(name: &str, width: u32, height: u32) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
    let mut scene = prisma::scene::load(&path).unwrap();
    scene.camera = scene.camera.with_resolution(width, height).unwrap();
    scene
}
