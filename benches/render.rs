//! A small full render on one thread: the cost of a camera sample through the whole pipeline
//! (wavelength sampling, camera ray, Whitted recursion with glass, dispersion, mirror, diffuse
//! shading with point- and area-light shadow rays, XYZ accumulation).
//!
//! The scene is inline: a dispersive prism and glass sphere, a mirror sphere and a diffuse floor
//! and back wall, lit by a point light and a quad light, 96×64 pixels at 4 samples per pixel.
//! Criterion's "elements/s" is camera samples per second; the rays per sample are printed once.
//! `cargo bench --bench render`.

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use prisma::render::{render, Job};

const SCENE: &str = r#"
background = { rgb = [0.2, 0.25, 0.3] }

[camera]
position = [0, 1.2, -7]
look_at = [0, 0.3, 0]
up = [0, 1, 0]
fov_y_deg = 45
width = 96
height = 64

[render]
spp = 4
max_depth = 12
wavelengths = 4
seed = 7
area_light_samples = 4

[materials.flint]
type = "dielectric"
ior = { glass = "N-SF11" }

[materials.crown]
type = "dielectric"
ior = 1.5

[materials.mirror]
type = "mirror"

[materials.floor]
type = "diffuse"
albedo = { rgb = [0.6, 0.55, 0.5] }

[materials.wall]
type = "diffuse"
albedo = { rgb = [0.3, 0.4, 0.7] }
roughness_deg = 20

[[shapes]]
type = "prism"
apex_angle_deg = 60
side_length = 1.6
length = 2.0
rotate_deg = [0, 30, 0]
position = [1.6, 0.2, 0]
material = "flint"

[[shapes]]
type = "sphere"
center = [-1.5, 0.3, 0.5]
radius = 0.9
material = "crown"

[[shapes]]
type = "sphere"
center = [0, 0.5, 2.5]
radius = 1.0
material = "mirror"

[[shapes]]
type = "plane"
point = [0, -0.8, 0]
normal = [0, 1, 0]
material = "floor"

[[shapes]]
type = "quad"
corner = [-6, -0.8, 5]
edge1 = [12, 0, 0]
edge2 = [0, 6, 0]
material = "wall"

[[lights]]
type = "point"
position = [2, 4, -3]
intensity = { illuminant = "D65", scale = 40 }

[[lights]]
type = "quad"
corner = [-1, 3.5, -1]
edge1 = [2, 0, 0]
edge2 = [0, 0, 2]
radiance = { illuminant = "D65", scale = 5 }
emit = "edge1_cross_edge2"
"#;

fn render_benchmark(c: &mut Criterion) {
    let scene = prisma::scene::parse(SCENE, Path::new("bench_scene.toml")).expect("the bench scene is valid");
    let job = Job { threads: 1, ..Job::new(scene.settings.clone()) };
    let (_, stats) = render(&scene, &job).expect("render");
    eprintln!(
        "small render: {} camera samples, {} rays ({:.2} rays per camera sample)",
        stats.samples,
        stats.rays,
        stats.rays as f64 / stats.samples as f64
    );
    let mut group = c.benchmark_group("render");
    group.sample_size(20);
    group.throughput(Throughput::Elements(stats.samples));
    group.bench_function("small_scene_1_thread", |b| b.iter(|| render(&scene, &job).expect("render")));
    group.finish();
}

criterion_group!(benches, render_benchmark);
criterion_main!(benches);
