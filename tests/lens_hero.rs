//! The lens camera's shared scene path (`lens_lanes = "shared"`: one path per camera sample for
//! all the wavelength lanes, hero-wavelength spectral MIS through the lens's inverse map,
//! `prisma::camera::LensCamera::sample_shared_path`) against the default per-lane estimator
//! (each lane its own ray and scene path, `LanePaths::PerLane`): the same expected image, through the
//! N-BK7 singlet (strong longitudinal colour: its F and C foci 1.5 mm apart, so the lanes'
//! preimages of one scene ray fall up to ~0.2 mm apart on the sensor, two pixels here) and the
//! double Gauss; the fault `LensHeroPdfOnly` (each lane weighted by the hero's density alone)
//! fails the same comparison; the same bits on one thread and two; and `lens_lanes` refuses
//! what it cannot do.

use std::path::Path;

use prisma::camera::{Camera, LanePaths};
use prisma::integrator::Fault;
use prisma::render::{render, Job};
use prisma::scene::Scene;

/// Threads for each render (the test's budget is two cores).
const THREADS: usize = 2;
/// Independent renders (seeds) per estimator: the regions' standard errors come from their
/// spread.
const SEEDS: u64 = 16;
/// Samples per pixel of each render.
const SPP: u32 = 4;
/// Side of the square regions whose means are compared (pixels).
const REGION: usize = 4;
/// The largest |z| of a region's difference that passes. Each z is a difference of two means
/// of 16 independent renders over their standard errors: Student-like with ~30 degrees of
/// freedom, for which |z| > 4.5 has probability ~1e-4; over the 3 × 64 regions of the test
/// that is ~2 % (the seeds are fixed, so the outcome is too). The fault's regions sit at
/// |z| of tens.
const Z_MAX: f64 = 4.5;

/// `text` parsed as if it were the file tests/lens_hero.toml (so that `../data/lenses/…` names
/// the shipped lenses).
fn parse(text: &str) -> Scene {
    let here = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/lens_hero.toml");
    prisma::scene::parse(text, &here).expect("the scene parses")
}

/// A 32 × 32 image through `lens` (its camera lines) of a grey background with a bright quad
/// light over part of the field and a dim one across the middle: edges for the lanes'
/// preimages to fall across, at the centre and off axis; `lens_lanes` as the camera's.
fn scene(lens: &str, lens_lanes: &str) -> Scene {
    parse(&format!(
        "background = 0.4\n\n[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, 10]\n{lens}\n\
         lens_lanes = \"{lens_lanes}\"\nwidth = 32\n\
         height = 32\n\n[render]\nintegrator = \"path\"\nmax_depth = 2\nspp = {SPP}\npolarized = false\n\n\
         [[lights]]\ntype = \"quad\"\ncorner = [-0.05, -0.3, 10]\nedge1 = [0.5, 0, 0]\nedge2 = [0, 0.25, 0]\n\
         radiance = 3\nemit = \"edge2_cross_edge1\"\n\n\
         [[lights]]\ntype = \"quad\"\ncorner = [-0.4, -0.02, 9]\nedge1 = [0.8, 0, 0]\nedge2 = [0, 0.04, 0]\n\
         radiance = 1.5\nemit = \"edge2_cross_edge1\"\n"
    ))
}

/// The singlet (f = 100 mm at f/8, focused at infinity at the d line) on a 3.2 mm sensor:
/// 0.1 mm pixels, about the blur its longitudinal colour gives the F and C lines.
const SINGLET: &str = "lens = \"../data/lenses/singlet_nbk7.dat\"\nsensor_height_mm = 3.2";
/// The double Gauss 50 mm wide open (f/2) on a 6.4 mm sensor: 0.2 mm pixels.
const DGAUSS: &str = "lens = \"../data/lenses/dgauss50.dat\"\nsensor_height_mm = 6.4";

/// `scene` with its lens camera's lanes finding their paths as `lane_paths` says.
fn with_lane_paths(scene: &Scene, lane_paths: LanePaths) -> Scene {
    let Camera::Lens(lens) = &scene.camera else { panic!("not a lens camera") };
    let mut scene = scene.clone();
    scene.camera = Camera::Lens(lens.with_lane_paths(lane_paths));
    scene
}

/// Each region's mean luminance Y over [`SEEDS`] renders of `scene` (seeds `first_seed..`),
/// with its standard error.
fn region_means(scene: &Scene, first_seed: u64, fault: Option<Fault>) -> Vec<(f64, f64)> {
    let (width, height) = (32usize, 32usize);
    let regions = (width / REGION) * (height / REGION);
    let mut per_seed = vec![Vec::with_capacity(SEEDS as usize); regions];
    for seed in first_seed..first_seed + SEEDS {
        let mut settings = scene.settings.clone();
        settings.seed = seed;
        let job = Job { threads: THREADS, fault, ..Job::new(settings) };
        let (film, _) = render(scene, &job).expect("the scene renders");
        let mut sums = vec![0.0; regions];
        for (index, xyz) in film.xyz().iter().enumerate() {
            let (x, y) = (index % width, index / width);
            sums[(y / REGION) * (width / REGION) + x / REGION] += f64::from(xyz.y);
        }
        for (values, sum) in per_seed.iter_mut().zip(sums) {
            values.push(sum / (REGION * REGION) as f64);
        }
    }
    per_seed
        .iter()
        .map(|values| {
            let n = values.len() as f64;
            let mean = values.iter().sum::<f64>() / n;
            let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
            (mean, (variance / n).sqrt())
        })
        .collect()
}

/// The largest |z| of the regions' differences, and the mean relative difference of `a` from
/// `b`.
fn compare(a: &[(f64, f64)], b: &[(f64, f64)]) -> (f64, f64) {
    let worst = a
        .iter()
        .zip(b)
        .map(|(&(mean_a, error_a), &(mean_b, error_b))| (mean_a - mean_b).abs() / error_a.hypot(error_b))
        .fold(0.0, f64::max);
    let total = |v: &[(f64, f64)]| v.iter().map(|r| r.0).sum::<f64>();
    (worst, total(a) / total(b) - 1.0)
}

/// The shared path and the per-lane paths agree region by region through both lenses, the
/// renders of each with their own seeds, so the two are independent; the fault
/// `LensHeroPdfOnly` does not. The polarised singlet runs the polarised branch (each lane's
/// Mueller matrix on the Stokes vector): nothing in the scene polarises the light it sends, so
/// it reads what the unpolarised render reads (the same numbers, as the output shows).
#[test]
fn the_shared_path_is_unbiased_and_the_hero_pdf_alone_is_not() {
    for (name, lens, polarized) in
        [("singlet", SINGLET, false), ("double Gauss", DGAUSS, false), ("singlet, polarised", SINGLET, true)]
    {
        let mut per_lane = scene(lens, "per_lane");
        let mut shared = scene(lens, "shared");
        per_lane.settings.polarized = polarized;
        shared.settings.polarized = polarized;
        let Camera::Lens(camera) = &shared.camera else { panic!("not a lens camera") };
        assert!(camera.shares_scene_path(), "{name}: lens_lanes = \"shared\" shares the scene path");
        let Camera::Lens(camera) = &per_lane.camera else { panic!("not a lens camera") };
        assert_eq!(with_lane_paths(&per_lane, LanePaths::PerLane).camera, per_lane.camera, "the default");
        assert!(!camera.shares_scene_path());
        let reference = region_means(&per_lane, 1, None);
        let (worst, relative) = compare(&region_means(&shared, 1001, None), &reference);
        eprintln!("{name}: shared path against per-lane paths: max |z| {worst:.2}, mean {relative:+.4}");
        assert!(worst < Z_MAX, "{name}: max |z| {worst}");
        if name == "singlet" {
            let (worst, relative) =
                compare(&region_means(&shared, 2001, Some(Fault::LensHeroPdfOnly)), &reference);
            eprintln!("{name}: the fault against per-lane paths: max |z| {worst:.2}, mean {relative:+.4}");
            assert!(worst > Z_MAX, "{name}: the fault passes (max |z| {worst})");
        }
    }
}

/// A shared-path render is the same bits on one thread and on two, polarised and not: the hero
/// lane and the scene path draw from the pixel's own sequence.
#[test]
fn the_shared_path_is_the_same_bits_on_any_thread_count() {
    for polarized in [false, true] {
        let mut scene = scene(SINGLET, "shared");
        scene.settings.polarized = polarized;
        let films: Vec<Vec<[u32; 3]>> = [1, 2]
            .into_iter()
            .map(|threads| {
                let job = Job { threads, ..Job::new(scene.settings.clone()) };
                let (film, _) = render(&scene, &job).expect("renders");
                film.xyz().iter().map(|v| v.to_array().map(f32::to_bits)).collect()
            })
            .collect();
        assert_eq!(films[0], films[1], "polarized {polarized}");
        assert!(films[0].iter().any(|p| f32::from_bits(p[1]) > 0.0));
    }
}

/// `lens_lanes` takes "per_lane" or "shared", the latter without ghosts, and needs a lens:
/// anything else is one error naming the field.
#[test]
fn lens_lanes_refuses_what_it_cannot_do() {
    let here = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/lens_hero.toml");
    let text = |camera: &str| {
        format!("background = 0.4\n\n[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, 10]\n{camera}\nwidth = 8\nheight = 8\n")
    };
    for (camera, needle) in [
        (format!("{SINGLET}\nlens_lanes = \"both\""), "must be \"per_lane\" or \"shared\""),
        (format!("{SINGLET}\nlens_ghosts = 2\nlens_lanes = \"shared\""), "needs lens_ghosts = 0"),
        ("fov_y_deg = 30\nlens_lanes = \"shared\"".to_string(), "needs a lens system"),
    ] {
        let error = prisma::scene::parse(&text(&camera), &here).expect_err("refused").to_string();
        assert!(error.contains("camera.lens_lanes") && error.contains(needle), "{error}");
        assert_eq!(error.lines().count(), 1, "{error}");
    }
}
