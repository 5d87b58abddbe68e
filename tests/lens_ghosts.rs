//! Ghost reflections through a lens camera, unbiased: with `lens_ghosts` on, camera rays are
//! aimed by a mixture of the transmitted light's exit-pupil bounds and the whole rear element
//! (`prisma::lens::pupil::GhostMixture`), so that ghost paths whose first segment from the
//! sensor leaves the bounds are drawn too. Checked against a brute-force estimate that aims
//! uniformly over the whole rear disc (every camera ray through the lens, ghost or not, must
//! meet the rear surface inside its clear aperture, so that estimate misses nothing); the
//! bounds alone (the sampler before the mixture) must fail the same check.

use std::path::{Path, PathBuf};

use prisma::camera::Camera;
use prisma::lens::{SensorSampler, TraceOptions};
use rand_core::{RngCore, SeedableRng};
use rand_pcg::Pcg64;

/// The wavelength of the traces (nm).
const LAMBDA_NM: f64 = 550.0;

/// A path inside the repository.
fn repo(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// A uniform number in [0, 1) (53 bits).
fn uniform(rng: &mut Pcg64) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The sampler of the double Gauss camera (36 × 24 mm sensor, focused at infinity) with the
/// extra camera lines `camera` and two ghost reflections allowed, as a scene builds it.
fn double_gauss_sampler(camera: &str) -> SensorSampler {
    let text = format!(
        "background = 1\n\n[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, 10]\n\
         lens = \"../data/lenses/dgauss50.dat\"\nsensor_height_mm = 24\nwidth = 36\nheight = 24\n\
         lens_ghosts = 2\n{camera}\n\n[render]\nspp = 1\n"
    );
    let scene = prisma::scene::parse(&text, &repo("tests/lens_ghosts.toml")).expect("the scene parses");
    let Camera::Lens(lens) = &scene.camera else { panic!("not a lens camera") };
    lens.sampler().clone()
}

/// Where an estimator aims its camera rays.
#[derive(Clone, Copy, Debug)]
enum Aim {
    /// Uniformly over the whole rear disc (brute force).
    RearDisc,
    /// Inside the exit-pupil bounds only (the sampler without the mixture).
    Bounds,
    /// The camera's sampler with ghosts on (the mixture).
    Camera,
}

/// Mean and standard error of the transmitted and of the ghost light (paths with two
/// reflections) reaching the sensor point `sensor_mm` under a uniform unpolarised radiance 1,
/// in the camera's normalised units: `n` camera rays aimed per `aim`, ghost branches drawn by
/// the tracer's estimator.
fn estimate(sampler: &SensorSampler, sensor_mm: [f64; 2], aim: Aim, n: usize, seed: u64) -> [(f64, f64); 2] {
    let options = TraceOptions { max_ghost_reflections: 2, ..TraceOptions::new(LAMBDA_NM) };
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut sums = [[0.0_f64; 2]; 2];
    for _ in 0..n {
        let u = [uniform(&mut rng), uniform(&mut rng)];
        let mut next = || uniform(&mut rng);
        let ray = match aim {
            Aim::Camera => sampler.sample(sensor_mm, u, &options, &mut next),
            Aim::RearDisc | Aim::Bounds => {
                let pupil = if let Aim::Bounds = aim {
                    sampler.bounds.sample(sensor_mm, u)
                } else {
                    Some(sampler.rear.sample(sensor_mm, u))
                };
                pupil.and_then(|pupil| {
                    let out =
                        sampler.tracer.trace_from_sensor(sensor_mm, pupil.target_mm, &options, &mut next)?;
                    let sensor_weight = sampler.normalisation.sensor_weight(sensor_mm, &pupil);
                    Some(prisma::lens::CameraRay {
                        sample: out,
                        sensor_weight,
                        weight: sensor_weight * out.throughput,
                    })
                })
            }
        };
        if let Some(ray) = ray {
            let class = usize::from(ray.sample.reflections >= 2);
            sums[class][0] += ray.weight;
            sums[class][1] += ray.weight * ray.weight;
        }
    }
    sums.map(|[sum, squares]| {
        let mean = sum / n as f64;
        (mean, ((squares / n as f64 - mean * mean) / (n as f64 - 1.0)).sqrt())
    })
}

/// The double Gauss stopped down to f/5.6, on axis: 13 % of its ghost light (paths that
/// reflect twice between its surfaces, ≈ 0.049 of a uniform radiance's image; 0.042 through
/// the bounds alone when measured) starts outside the exit-pupil bounds of the transmitted
/// light, on rays that would be cut by the small stop but are reflected back before they get
/// there. The camera's mixture estimate of the ghost light equals the brute-force rear-disc
/// estimate within 4 standard errors of their difference (Monte Carlo noise of two independent
/// estimates; no other approximation: both are unbiased for the same integral), and the
/// bounds-only estimate lies more than 4 below it. The transmitted light, which the bounds hold
/// entirely, agrees among all three within the same noise bound.
#[test]
fn ghost_light_through_the_mixture_equals_the_whole_rear_disc_and_the_bounds_miss_some() {
    let sampler = double_gauss_sampler("f_number = 5.6");
    let sensor = [0.0, 0.0];
    let disc = estimate(&sampler, sensor, Aim::RearDisc, 1_200_000, 1);
    let bounds = estimate(&sampler, sensor, Aim::Bounds, 400_000, 2);
    let camera = estimate(&sampler, sensor, Aim::Camera, 600_000, 3);
    for (what, [transmitted, ghost]) in [("rear disc", disc), ("bounds", bounds), ("camera", camera)] {
        eprintln!(
            "{what:9}: transmitted {:.5} ± {:.5}, ghosts {:.5} ± {:.5}",
            transmitted.0, transmitted.1, ghost.0, ghost.1
        );
    }
    let sigma = |a: (f64, f64), b: (f64, f64)| a.1.hypot(b.1);
    for other in [bounds, camera] {
        let (t, reference) = (other[0], disc[0]);
        assert!((t.0 - reference.0).abs() < 4.0 * sigma(t, reference), "transmitted {t:?} vs {reference:?}");
    }
    let (ghost, reference) = (camera[1], disc[1]);
    assert!(
        (ghost.0 - reference.0).abs() < 4.0 * sigma(ghost, reference),
        "ghosts {ghost:?} vs {reference:?}"
    );
    let missed = reference.0 - bounds[1].0;
    assert!(
        missed > 4.0 * sigma(bounds[1], reference),
        "the bounds alone should miss ghost light: {:?} vs {reference:?}",
        bounds[1]
    );
}

/// With ghosts off the camera aims inside the exit-pupil bounds exactly as before the mixture:
/// the same target, weight and ray bits for the same numbers.
#[test]
fn without_ghosts_the_camera_aims_inside_the_bounds_as_before() {
    let sampler = double_gauss_sampler("");
    let options = TraceOptions::new(LAMBDA_NM);
    let mut rng = Pcg64::seed_from_u64(5);
    let mut passed = 0;
    for _ in 0..2000 {
        let sensor = [24.0 * uniform(&mut rng) - 12.0, 16.0 * uniform(&mut rng) - 8.0];
        let u = [uniform(&mut rng), uniform(&mut rng)];
        let camera = sampler.sample(sensor, u, &options, &mut || 0.5);
        let before = sampler.bounds.sample(sensor, u).and_then(|pupil| {
            let out = sampler.tracer.trace_from_sensor(sensor, pupil.target_mm, &options, &mut || 0.5)?;
            Some((out, sampler.normalisation.sensor_weight(sensor, &pupil)))
        });
        match (camera, before) {
            (Some(ray), Some((out, sensor_weight))) => {
                assert_eq!(ray.sample, out);
                assert_eq!(ray.sensor_weight.to_bits(), sensor_weight.to_bits());
                passed += 1;
            }
            (None, None) => {}
            other => panic!("the camera and the bounds differ: {other:?}"),
        }
    }
    assert!(passed > 1000, "{passed} of 2000 passed");
}

/// The mixture's density is the density of what it draws: every point the exit-pupil bounds
/// draw for a sensor point at any azimuth lies inside the region `pdf_per_mm2` turns back to
/// the +x axis (so the bounds' part of the density is never lost to a wrong rotation), and
/// the density integrates to 1 over the rear vertex plane: a grid of 800² cell centres over a
/// square 1.6× the rear disc's (the bounds are measured for the outer radius of their band and
/// widened by two test cells, so off axis they reach past the disc of the sensor point's own
/// radius; rays aimed there are blocked and add 0). Tolerance 1 %: the cells cut by the
/// regions' edges, a few thousand of the ~250 000 inside, each at most half wrong.
#[test]
fn the_mixtures_density_is_normalised_and_matches_its_draws() {
    let sampler = double_gauss_sampler("f_number = 2.8");
    let mixture = sampler.ghost_mixture();
    let mut rng = Pcg64::seed_from_u64(9);
    for _ in 0..20_000 {
        let (radius, azimuth) = (21.0 * uniform(&mut rng), std::f64::consts::TAU * uniform(&mut rng));
        let sensor = [radius * azimuth.cos(), radius * azimuth.sin()];
        let u = [uniform(&mut rng), uniform(&mut rng)];
        if let Some(drawn) = sampler.bounds.sample(sensor, u) {
            assert_eq!(
                sampler.bounds.pdf_per_mm2(sensor, drawn.target_mm),
                drawn.pdf_per_mm2,
                "{sensor:?} {drawn:?}"
            );
        }
    }
    for sensor in [[0.0, 0.0], [9.0, -4.0], [-3.0, 17.0], [-14.0, -14.0]] {
        let reach = sampler.rear.radius_mm(f64::hypot(sensor[0], sensor[1]));
        let (cells, half) = (800, 1.6 * reach);
        let cell = 2.0 * half / cells as f64;
        let mut total = 0.0;
        for i in 0..cells {
            for j in 0..cells {
                let target = [-half + (i as f64 + 0.5) * cell, -half + (j as f64 + 0.5) * cell];
                total += mixture.pdf_per_mm2(sensor, target) * cell * cell;
            }
        }
        eprintln!("sensor {sensor:?}: the mixture's density integrates to {total:.5}");
        assert!((total - 1.0).abs() < 0.01, "sensor {sensor:?}: ∫ pdf = {total}");
    }
}
