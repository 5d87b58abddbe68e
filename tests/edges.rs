//! Edge refinement (src/edges.rs) against plain sampling: a refined pixel's pass is the mean of
//! its samples, so after N passes of m samples it holds exactly what plain sampling holds after
//! N·m samples (the same points of its sequence), and every other pixel keeps plain sampling's
//! bits. Together with the unit tests' choice that never looks at a pixel's own value, this is
//! what makes the refined image an unbiased estimate.

mod shipped;

use prisma::render::{render, Job, RenderStats};
use prisma::scene::Scene;
use shipped::scene;

fn image(scene: &Scene, spp: u32, edge_samples: u32) -> (Vec<glam::Vec3>, RenderStats) {
    let mut job = Job::new(scene.settings.clone());
    job.settings.spp = spp;
    job.settings.edge_samples = edge_samples;
    job.settings.caustics = false;
    job.threads = 2;
    job.progress = false;
    let (film, stats) = render(scene, &job).unwrap();
    (film.xyz().to_vec(), stats)
}

/// TP6's quad light: soft and hard shadow borders, the mirror and glass spheres' silhouettes.
#[test]
fn a_refined_pass_holds_its_samples_of_plain_sampling() {
    let scene = scene("tp6_quad.toml", 48, 36);
    let (passes, m) = (3, 4);
    let (refined, stats) = image(&scene, passes, m);
    let (plain, plain_stats) = image(&scene, passes, 1);
    let (plain_more, _) = image(&scene, passes * m, 1);
    assert_eq!(plain_stats.edge_pixels, 0);
    let mut edges = 0;
    for (i, ((r, p), q)) in refined.iter().zip(&plain).zip(&plain_more).enumerate() {
        if r.to_array().map(f32::to_bits) == p.to_array().map(f32::to_bits) {
            continue;
        }
        edges += 1;
        // The pass means are rounded to the sums' quantum (2⁻⁶⁴) before they add up.
        let close = (*r - *q).abs().max_element() <= 1e-5 * q.abs().max_element().max(1e-3);
        assert!(close, "pixel {i}: refined {r}, plain with {} samples {q}", passes * m);
    }
    assert!(edges > 0, "no pixel was refined");
    // An edge pixel whose samples all see the same (a dark pixel beside a lit one) keeps plain
    // sampling's bits too: at most the map's edge pixels differ, and nearly all of them do.
    assert!(
        edges <= stats.edge_pixels && edges * 10 >= stats.edge_pixels * 9,
        "{edges} pixels differ from plain sampling, {} edge pixels",
        stats.edge_pixels
    );
    assert!(edges * 4 < refined.len(), "{edges} of {} pixels refined: not only edges", refined.len());
}

/// The image stays the same bits whatever the thread count, edge pixels included.
#[test]
fn refinement_is_deterministic() {
    let scene = scene("tp6_mirror_glass.toml", 40, 30);
    let mut job = Job::new(scene.settings.clone());
    job.settings.spp = 2;
    job.settings.edge_samples = 4;
    job.progress = false;
    let images: Vec<Vec<glam::Vec3>> = [1, 2, 3]
        .into_iter()
        .map(|threads| render(&scene, &Job { threads, ..job.clone() }).unwrap().0.xyz().to_vec())
        .collect();
    assert!(images.windows(2).all(|w| w[0] == w[1]));
}
