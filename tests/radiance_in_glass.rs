//! The refracted branch scales radiance by (n_i/n_t)² as seen from the camera: radiance inside a
//! medium of index n is n² times the radiance outside (L/n² is invariant along a ray; Nicodemus,
//! "Radiance", Am. J. Phys. 31, 1963). A camera at the centre of a large, clear glass sphere sees
//! every ray leave at normal incidence; summing the internal reflections, T·(1 + R + R² + …) = 1,
//! so it sees exactly n²·L_background.

use std::path::Path;

use prisma::render::{render, Job};
use prisma::scene::parse;

fn inside_sphere(ior: &str, background: f32, wavelength_nm: f32) -> f64 {
    let text = format!(
        r#"
background = {background}

[camera]
position = [0, 0, 0]
look_at = [0, 0, 1]
fov_y_deg = 30
width = 16
height = 16

[render]
spp = 2
max_depth = 20
prune_below = 0

[materials.glass]
type = "dielectric"
ior = {ior}

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 50
material = "glass"
"#
    );
    let scene = parse(&text, Path::new("inside.toml")).unwrap();
    let job = Job { threads: 2, monochromatic_nm: Some(wavelength_nm), ..Job::new(scene.settings.clone()) };
    let (film, _) = render(&scene, &job).unwrap();
    film.xyz().iter().map(|p| f64::from(p.y)).sum::<f64>() / film.xyz().len() as f64
}

#[test]
fn camera_inside_glass_sees_n_squared_times_the_background() {
    let seen = inside_sphere("1.5", 2.0, 550.0);
    assert!((seen - 2.0 * 2.25).abs() < 1e-3, "{seen}");
}

#[test]
fn the_n_squared_law_holds_per_wavelength_for_dispersive_glass() {
    // N-BK7 (Schott datasheet): n = 1.53024 at 404.66 nm (h line), 1.51432 at 656.27 nm (C line).
    for (nm, n) in [(404.66f32, 1.53024f64), (656.27, 1.51432)] {
        let seen = inside_sphere("{ glass = \"N-BK7\" }", 1.0, nm);
        assert!((seen - n * n).abs() < 2e-4, "{nm} nm: {seen} vs {}", n * n);
    }
}
