//! Every scene shipped in scenes/ loads and renders at a small size with no NaN or infinite pixel.

use prisma::render::{render, Job};

#[test]
fn every_shipped_scene_renders_finite() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let mut scene = prisma::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        scene.camera = scene.camera.with_resolution(40, 30).unwrap();
        let mut settings = scene.settings.clone();
        settings.spp = 2;
        // Scenes with caustics trace hundreds of thousands of light paths per pass at full
        // size; a few thousand show that they work.
        settings.light_paths = settings.light_paths.map(|_| 4000);
        let job = Job { threads: 2, ..Job::new(settings) };
        let (film, stats) = render(&scene, &job).unwrap();
        assert!(stats.rays >= 40 * 30 * 2, "{}", path.display());
        let bad = film.xyz().iter().filter(|p| !p.is_finite()).count();
        assert_eq!(bad, 0, "{}: {bad} non-finite pixels", path.display());
        let lit = film.xyz().iter().filter(|p| p.y > 0.0).count();
        assert!(lit > 0, "{}: black image", path.display());
        count += 1;
    }
    assert!(count >= 11, "only {count} scenes found");
}
