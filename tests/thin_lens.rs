//! The thin-lens camera in images: the circle of confusion of a small emitter against the
//! closed form, and the light tracer's connection to the lens against the camera's own paths
//! (the adjoint check of tests/adjoint_transport.rs, through a lens).

mod adjoint;

use adjoint::passes;
use prisma::film::Film;
use prisma::render::{render, Job};
use prisma::scene::{IntegratorKind, Scene};
use prisma::spectrum::SampledSpectrum;
use prisma::validate::metrics::{compare_with, Comparison, Options, Planes};

/// The wavelength of every render, nm.
const LAMBDA_NM: f32 = 550.0;
/// Threads for each render (the test's budget is two cores).
const THREADS: usize = 2;
/// Camera samples per pixel of the circle-of-confusion renders.
const SPP_POINT: u32 = 256;

fn parse(text: &str) -> Scene {
    prisma::scene::parse(text, std::path::Path::new("thin_lens.toml")).expect("the scene parses")
}

/// The radiance image (W·m⁻²·sr⁻¹·nm⁻¹ at [`LAMBDA_NM`]) of `film`, row-major.
fn radiance(film: &Film) -> Vec<f64> {
    film.xyz().iter().map(|v| f64::from(v.y)).collect()
}

/// `scene`'s camera side rendered at [`LAMBDA_NM`] with `spp` samples per pixel and `seed`.
fn camera_side(scene: &Scene, seed: u64, spp: u32) -> Vec<f64> {
    let mut settings = scene.settings.clone();
    settings.spp = spp;
    settings.seed = seed;
    let job = Job { threads: THREADS, monochromatic_nm: Some(LAMBDA_NM), ..Job::new(settings) };
    let (film, _) = render(scene, &job).expect("the scene renders");
    radiance(&film)
}

/// A square emitter of side `side` facing the camera at depth `depth` on the axis of a camera
/// at the origin looking down +z (vertical field of view 30°, 256 × 256 pixels), through a lens
/// of radius 0.2 focused at depth 4; nothing else, a black background.
fn point_scene(depth: f32, side: f32) -> String {
    let half = side / 2.0;
    format!(
        r#"
background = 0.0

[camera]
position = [0, 0, 0]
look_at = [0, 0, 1]
fov_y_deg = 30
width = 256
height = 256
aperture_radius = 0.2
focus_distance = 4

[render]
wavelengths = 1
polarized = false

[[lights]] # edge2 × edge1 = -z: toward the camera
type = "quad"
corner = [{}, {}, {depth}]
edge1 = [{side}, 0, 0]
edge2 = [0, {side}, 0]
radiance = 1.0
emit = "edge2_cross_edge1"
"#,
        -half, -half
    )
}

/// The circle of confusion: a point at depth d seen through a thin lens of radius a focused at
/// depth f is spread uniformly over a disc of diameter 2·a·|d − f|/d on the plane of focus
/// (similar triangles through the conjugate point), that is of radius
/// R = a·|d − f|/d · H/(2·f·tan(fov/2)) pixels on a film H pixels high. A small square emitter
/// of side s (its central image a square of s·f/d on that plane, s_img pixels) makes that disc
/// convolved with the square, whose second moment about the centre is ⟨r²⟩ = R²/2 + s_img²/6;
/// read at pixel centres from pixel means, 1/6 pixel² less (the box of a pixel, 1/12 per
/// axis). Checked for a point nearer than the focus and one farther: the radius from ⟨r²⟩, and
/// that no light lands farther out than R plus the square's half-diagonal (and a pixel). Also the
/// image's total: defocus spreads the light, it does not lose it. Through every lens point the
/// square lands on the plane of focus as a square of side s·f/d (the map from the square to the
/// plane of focus is a scaling about the lens point), so the sum of the pixels is exactly the
/// pinhole's, L·(s/d)²/A_pixel, with A_pixel a pixel's area on the image plane at unit distance.
#[test]
fn circle_of_confusion_matches_the_closed_form() {
    let (aperture, focus, height) = (0.2f64, 4.0f64, 256.0f64);
    let tan_half = 15f64.to_radians().tan();
    let pixels_per_unit_on_focus_plane = height / (2.0 * focus * tan_half);
    for (depth, side) in [(2.0f64, 0.06f64), (8.0, 0.24)] {
        let scene = parse(&point_scene(depth as f32, side as f32));
        let image = camera_side(&scene, 7, SPP_POINT);
        let radius = aperture * (depth - focus).abs() / depth * pixels_per_unit_on_focus_plane;
        let square = side * focus / depth * pixels_per_unit_on_focus_plane;
        let (mut total, mut moment, mut farthest) = (0.0, 0.0, 0.0f64);
        for (i, &value) in image.iter().enumerate() {
            // Pixel centres relative to the image centre (the emitter's image, a pixel corner).
            let (x, y) = ((i % 256) as f64 + 0.5 - 128.0, (i / 256) as f64 + 0.5 - 128.0);
            let r_sq = x * x + y * y;
            total += value;
            moment += value * r_sq;
            if value > 0.0 {
                farthest = farthest.max(r_sq.sqrt());
            }
        }
        let mean_r_sq = moment / total;
        let measured = (2.0 * (mean_r_sq + 1.0 / 6.0 - square * square / 6.0)).sqrt();
        eprintln!(
            "depth {depth}: circle of confusion radius {measured:.3} px measured, {radius:.3} px \
             expected; farthest lit pixel centre {farthest:.2} px"
        );
        // Monte Carlo noise: the image holds N ≈ π(R + 7)²·spp·p camera samples on the square
        // (p = its share of the blurred disc, about s_img²/(πR²)), N ≈ 1.5e5 here; ⟨r²⟩ of a
        // disc has a relative standard deviation √(1/(3N)) ≈ 0.15 %, R half that (stratified
        // samples do better). 1 % is many times it.
        assert!((measured / radius - 1.0).abs() < 0.01, "{measured} vs {radius}");
        // A pixel centre lit lies within half a pixel's diagonal of a lit film point.
        assert!(farthest <= radius + square / 2f64.sqrt() + 0.71, "{farthest}");
        assert!(farthest >= radius, "{farthest}: the disc must reach its rim");
        let pixel_area = (2.0 * tan_half / height).powi(2);
        let expected_total = side * side / (depth * depth) / pixel_area;
        eprintln!("depth {depth}: image total {total:.2}, expected {expected_total:.2}");
        // A share p of N' = (pixels in the disc)·spp samples hits: relative standard deviation
        // √((1 − p)/(p·N')) ≈ 0.3 % without credit for stratification (four seeds at each depth
        // gave totals 0.4 % either side); 1.5 % is four times that.
        assert!((total / expected_total - 1.0).abs() < 0.015, "{total} vs {expected_total}");
    }
}

/// A closed room of diffuse walls with two diffuse spheres at different depths, lit by a quad
/// light under the ceiling and one on the back wall facing the camera (seen directly, out of
/// focus), seen through a thin lens (radius 0.15, focused at depth 4 on the near sphere, the far
/// one and the back light blurred). Every surface is diffuse, so the light tracer alone counts
/// every path the camera does, at every pixel. Background black: no light the light side
/// cannot start.
fn room() -> String {
    let head = r#"
background = 0.0

[camera]
position = [0, 1.6, -3.5]
look_at = [0, 1.2, 3]
fov_y_deg = 50
width = 48
height = 32
aperture_radius = 0.15
focus_distance = 4

[render]
integrator = "path"
caustics = false
max_depth = 64
wavelengths = 1
polarized = false

[materials.floor]
type = "diffuse"
albedo = 0.6

[materials.wall]
type = "diffuse"
albedo = 0.5

[materials.ball]
type = "diffuse"
albedo = 0.8

"#;
    let tail = r#"
[[shapes]] # in focus
type = "sphere"
center = [0.9, 0.6, 0.6]
radius = 0.6
material = "ball"

[[shapes]] # far, blurred
type = "sphere"
center = [-1.2, 0.8, 4.5]
radius = 0.8
material = "ball"

[[lights]] # edge1 × edge2 = -y: emits down
type = "quad"
corner = [-0.75, 3.2, 1.5]
edge1 = [1.5, 0, 0]
edge2 = [0, 0, 1.5]
radiance = 8.0
emit = "edge1_cross_edge2"

[[lights]] # on the back wall, facing the camera (edge2 × edge1 = -z)
type = "quad"
corner = [0.2, 1.6, 5.95]
edge1 = [1.2, 0, 0]
edge2 = [0, 0.8, 0]
radiance = 3.0
emit = "edge2_cross_edge1"
"#;
    format!("{head}{}{tail}", adjoint::room_walls(["floor", "wall", "wall", "floor", "wall"]))
}

/// The light tracer alone ([`LightTracer::counting_everything`]), seed `seed`: `paths` light
/// paths over [`THREADS`] threads, divided by `paths`.
fn light_side(scene: &Scene, seed: u64, paths: u64) -> Vec<f64> {
    radiance(&adjoint::light_side_film::<SampledSpectrum>(scene, (LAMBDA_NM, None), seed, paths, THREADS))
}

fn planes(scene: &Scene, data: Vec<f64>) -> Planes {
    Planes { width: scene.camera.width() as usize, height: scene.camera.height() as usize, data: vec![data] }
}

/// `prisma validate`'s comparison of the light side's pair with the camera side's pair, over the
/// whole image.
fn compare(scene: &Scene, light: [Vec<f64>; 2], camera: [Vec<f64>; 2]) -> Comparison {
    let [light_a, light_b] = light.map(|data| planes(scene, data));
    let [camera_a, camera_b] = camera.map(|data| planes(scene, data));
    let comparison = compare_with(
        &light_a,
        &light_b,
        &camera_a,
        &camera_b,
        &Options { mask: None, reference_variance: None, mean_tolerance: 0.0 },
    );
    eprintln!(
        "outliers {:.4} (null {:.4}), |z| of means {:.2}, mean ratio (light/camera) {:.4}, relMSE beyond \
         noise {:.2e}",
        comparison.outlier_fraction,
        comparison.null_outlier_fraction,
        comparison.mean_z,
        comparison.mean_ratio[0],
        comparison.rel_mse_excess,
    );
    comparison
}

/// The light tracer's connection to the thin lens (a lens point drawn uniformly, the film point
/// through the plane of focus, the pinhole's sensitivity from that lens point) and the path
/// tracer's lens rays estimate the same image: on the diffuse room [`room`], the light tracer
/// alone and the path tracer alone (two seeds each) pass `prisma validate`'s bias checks over
/// every pixel, the blurred light on the back wall and the blurred sphere included. The same
/// light side against the camera side through a pinhole at the lens centre (aperture 0: the
/// blur a light side that ignored the lens would miss) fails them: the test sees the lens.
#[test]
fn the_light_tracer_and_the_path_tracer_agree_through_a_thin_lens() {
    let scene = parse(&room());
    assert_eq!(scene.settings.integrator, IntegratorKind::Path);
    assert!(matches!(scene.camera, prisma::camera::Camera::ThinLens(_)));
    let pixels = u64::from(scene.camera.width() * scene.camera.height());
    let light = [light_side(&scene, 11, 1024 * pixels), light_side(&scene, 12, 1024 * pixels)];
    let camera = [camera_side(&scene, 1, 512), camera_side(&scene, 2, 512)];
    eprint!("light alone vs camera alone, both through the lens: ");
    assert!(passes(&compare(&scene, light.clone(), camera)));

    let pinhole = parse(&room().replace("aperture_radius = 0.15", "aperture_radius = 0"));
    assert!(matches!(pinhole.camera, prisma::camera::Camera::Pinhole(_)));
    let sharp = [camera_side(&pinhole, 1, 512), camera_side(&pinhole, 2, 512)];
    eprint!("the light side through the lens vs a pinhole camera side: ");
    assert!(!passes(&compare(&scene, light, sharp)));
}

/// Same seed, same bits: the shipped thin-lens scene (full transport with caustics: the lens
/// sample on both sides) renders to the same image on one thread and on two.
#[test]
fn a_thin_lens_render_is_the_same_bits_on_any_thread_count() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/thin_lens_dof.toml");
    let mut scene = prisma::scene::load(&path).expect("the shipped scene loads");
    assert!(matches!(scene.camera, prisma::camera::Camera::ThinLens(_)));
    scene.camera = scene.camera.with_resolution(40, 30).expect("a valid size");
    let mut settings = scene.settings.clone();
    assert!(settings.caustics);
    settings.spp = 2;
    settings.light_paths = Some(4000);
    let image = |threads: usize| {
        let (film, _) = render(&scene, &Job { threads, ..Job::new(settings.clone()) }).expect("renders");
        film.xyz().iter().flat_map(|v| v.to_array().map(f32::to_bits)).collect::<Vec<u32>>()
    };
    assert_eq!(image(1), image(2));
}
