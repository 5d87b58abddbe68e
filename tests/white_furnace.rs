//! White furnace: inside a uniform background, a lossless object is invisible. A dielectric sphere
//! (constant and dispersive IOR) and a perfect mirror sphere must render exactly as the empty
//! background does with the same seed.
//!
//! Pruning is off and the depth cap is 400 bounces: a ray that enters near grazing incidence
//! keeps at most R^D of its weight after D internal reflections, and max over R of (1 − R)·R^D is
//! about 1/(e·(D + 1)) ≈ 9·10⁻⁴ for D = 400, under the 10⁻³ per-pixel bound.

use std::path::Path;

use prisma::render::{render, Job};
use prisma::scene::parse;

fn furnace_scene(material: &str) -> String {
    format!(
        r#"
background = {{ rgb = [0.8, 0.6, 0.4] }}

[camera]
position = [0, 0, -4]
look_at = [0, 0, 0]
fov_y_deg = 40
width = 48
height = 48

[render]
spp = 4
max_depth = 400
prune_below = 0
seed = 11

[materials.object]
{material}

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "object"
"#
    )
}

fn mean_and_max_difference(with_object: &str) -> (f64, f64, f64) {
    let scene = parse(&furnace_scene(with_object), Path::new("furnace.toml")).unwrap();
    let mut empty = scene.clone();
    empty.geometry = prisma::geometry::Geometry::build(Vec::new(), Vec::new());
    empty.surfaces.clear();
    let job = Job { threads: 2, monochromatic_nm: None, ..Job::new(scene.settings.clone()) };
    let (film, _) = render(&scene, &job).unwrap();
    let (reference, _) = render(&empty, &job).unwrap();
    let (mut sum, mut sum_ref, mut max) = (0f64, 0f64, 0f64);
    for (a, b) in film.linear_srgb().iter().zip(reference.linear_srgb()) {
        for c in 0..3 {
            sum += f64::from(a[c]);
            sum_ref += f64::from(b[c]);
            max = max.max(f64::from((a[c] - b[c]).abs()));
        }
    }
    let n = (film.xyz().len() * 3) as f64;
    (sum / n, sum_ref / n, max)
}

fn assert_invisible(material: &str) {
    let (mean, mean_ref, max) = mean_and_max_difference(material);
    // The background is visibly non-zero, so an object that absorbs or adds light would show.
    assert!(mean_ref > 0.3, "{mean_ref}");
    assert!((mean - mean_ref).abs() < 1e-4, "image mean {mean} vs background {mean_ref}");
    assert!(max < 1e-3, "largest pixel difference {max}");
}

#[test]
fn constant_ior_glass_sphere_is_invisible() {
    assert_invisible("type = \"dielectric\"\nior = 1.5");
}

#[test]
fn dispersive_glass_sphere_is_invisible() {
    assert_invisible("type = \"dielectric\"\nior = { glass = \"N-SF11\" }");
}

#[test]
fn perfect_mirror_sphere_is_invisible() {
    assert_invisible("type = \"mirror\"\nreflectance = 1");
}

/// The furnace must be able to fail: an absorbing glass darkens the image by far more than the
/// thresholds above.
#[test]
fn absorbing_glass_is_visible() {
    let (mean, mean_ref, _) = mean_and_max_difference("type = \"dielectric\"\nior = 1.5\nabsorption = 0.5");
    assert!(mean_ref - mean > 1e-2, "{mean} vs {mean_ref}");
}
