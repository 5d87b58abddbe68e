//! `prisma render --stats` writes the render's figures as JSON, consistent with the job.

use std::process::Command;

#[test]
fn stats_file_holds_the_jobs_figures() {
    let dir = tempfile::tempdir().unwrap();
    let stats = dir.path().join("stats.json");
    let output = Command::new(env!("CARGO_BIN_EXE_prisma"))
        .args(["render", "validation/scenes/specular_spheres.toml", "--width", "20", "--spp", "4", "--quiet"])
        .args(["--edge-samples", "4"])
        .arg("-o")
        .arg(dir.path().join("image.exr"))
        .arg("--stats")
        .arg(&stats)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let figures: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    // 20 × 15 pixels (the scene is 4:3), 4 passes each, edge pixels 4 samples per pass; every
    // sample casts its camera ray.
    assert_eq!(figures["width"], 20);
    assert_eq!(figures["height"], 15);
    let edge_pixels = figures["edge_pixels"].as_u64().unwrap();
    assert!(edge_pixels > 0 && edge_pixels < 20 * 15, "{edge_pixels} edge pixels");
    let samples = 20 * 15 * 4 + edge_pixels * 3 * 4;
    assert_eq!(figures["samples"], samples);
    assert!(figures["rays"].as_u64().unwrap() >= samples);
    let seconds = figures["render_seconds"].as_f64().unwrap();
    assert!(seconds > 0.0 && seconds.is_finite(), "{seconds}");
    let rate = figures["samples_per_second"].as_f64().unwrap();
    let samples = samples as f64;
    assert!((rate * seconds - samples).abs() < 1e-6 * samples, "{rate} samples/s over {seconds} s");
}
