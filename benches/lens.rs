//! Per-lane cost of a lens-system camera ray: [`SensorSampler::sample`] through the double
//! Gauss 50 mm (`data/lenses/dgauss50.dat`, focused at 6 m, f/2.8, as
//! `scenes/lens_dgauss50.toml`), ghosts off, Fresnel on: the exit-pupil lookup, the trace
//! through every surface and the weight, for one wavelength lane.
//!
//! Each iteration traces 1024 camera rays (sensor points over the 36 × 24 mm frame,
//! pupil numbers and wavelengths over 360–830 nm, each its own), so criterion's time divided
//! by 1024 is the time per lane. `unpolarised` carries row 0 of the Mueller matrix (what an
//! unpolarised render asks for), `polarised` the whole matrix. The share of the 1024 rays
//! that pass the lens is printed once. `lens_camera_sample_8_lanes` is a camera sample's eight
//! lanes (360–830 nm), traced one by one (scalar) or together
//! ([`prisma::lens::LensTracer::trace_lanes_from_sensor`], in SIMD: what a render without ghosts
//! does), unpolarised and polarised; `lens_shared_path_7_lanes` is the shared scene path's lens
//! work per camera sample besides the hero's trace: the other 7 lanes traced back from the
//! hero's scene ray with their Mueller matrices
//! ([`prisma::lens::LensTracer::trace_lanes_back_to_sensor`], SIMD), per 1024 scene rays.
//! `cargo bench --bench lens`.

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use prisma::lens::trace::MAX_LANES;
use prisma::lens::{read_lens_file, Ray, SensorSampler, TraceOptions, LAMBDA_D_NM};

const CALLS: usize = 1024;

/// The camera's lens: dgauss50 at f/2.8, focused at 6 m (the scene's settings).
fn sampler() -> SensorSampler {
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/data/lenses/dgauss50.dat");
    let mut system = read_lens_file(Path::new(file)).expect("the shipped lens reads");
    let paraxial = system.paraxial(LAMBDA_D_NM).expect("paraxial");
    let stop = system.stop_index().expect("a stop");
    let current = system.surfaces[stop].semi_diameter_mm;
    system.surfaces[stop].semi_diameter_mm = paraxial.stop_semi_diameter_for_f_number(2.8, current);
    let last = system.surfaces.len() - 1;
    system.surfaces[last].thickness_mm = system.focus_thickness_mm(6000.0, LAMBDA_D_NM).expect("focus");
    // The 36 × 24 mm frame's half diagonal.
    SensorSampler::new(system, 0.5 * 36.0_f64.hypot(24.0), LAMBDA_D_NM)
}

/// A scrambled low-discrepancy number in [0, 1) for ray `i` and dimension `d`.
fn number(i: usize, d: usize) -> f64 {
    const STEPS: [f64; 5] =
        [0.618_033_988_7, 0.754_877_666_2, 0.569_840_290_9, 0.682_327_803_8, 0.534_992_027_8];
    ((i as f64 + 0.5) * STEPS[d]).fract()
}

fn lens_benchmarks(c: &mut Criterion) {
    let sampler = sampler();
    let rays: Vec<([f64; 2], [f64; 2], f64)> = (0..CALLS)
        .map(|i| {
            let sensor = [36.0 * (number(i, 0) - 0.5), 24.0 * (number(i, 1) - 0.5)];
            (sensor, [number(i, 2), number(i, 3)], 360.0 + 470.0 * number(i, 4))
        })
        .collect();
    // The share of camera rays that pass, over 64 × 1024 of them (binomial standard error
    // ≤ 0.2 %).
    let tested = 64 * CALLS;
    let passing = (0..tested)
        .filter(|&i| {
            let sensor = [36.0 * (number(i, 0) - 0.5), 24.0 * (number(i, 1) - 0.5)];
            let options = TraceOptions::new(360.0 + 470.0 * number(i, 4));
            sampler.sample(sensor, [number(i, 2), number(i, 3)], &options, &mut || 0.0).is_some()
        })
        .count();
    println!(
        "lens_camera_ray: {passing} of {tested} camera rays pass the lens ({:.1} %)",
        100.0 * passing as f64 / tested as f64
    );
    let mut group = c.benchmark_group("lens_camera_ray");
    group.throughput(Throughput::Elements(CALLS as u64));
    for (name, full_mueller) in [("unpolarised", false), ("polarised", true)] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut total = 0.0;
                for (sensor, u, lambda_nm) in &rays {
                    let options = TraceOptions { full_mueller, ..TraceOptions::new(*lambda_nm) };
                    if let Some(ray) =
                        sampler.sample(black_box(*sensor), black_box(*u), &options, &mut || 0.0)
                    {
                        total += ray.weight;
                    }
                }
                black_box(total)
            })
        });
    }
    group.finish();

    // A camera sample's 8 lanes: one trace per lane (ghosts on use this) against the lanes
    // traced together (the render's path without ghosts); per 1024 camera samples, 8192 lanes.
    let lanes: Vec<f64> = (0..8).map(|lane| 360.0 + 470.0 * (lane as f64 + 0.5) / 8.0).collect();
    let mut group = c.benchmark_group("lens_camera_sample_8_lanes");
    group.throughput(Throughput::Elements((8 * CALLS) as u64));
    group.bench_function("one_by_one", |b| {
        b.iter(|| {
            let mut total = 0.0;
            for (sensor, u, _) in &rays {
                for lambda_nm in &lanes {
                    let options = TraceOptions { full_mueller: false, ..TraceOptions::new(*lambda_nm) };
                    if let Some(ray) =
                        sampler.sample(black_box(*sensor), black_box(*u), &options, &mut || 0.0)
                    {
                        total += ray.weight;
                    }
                }
            }
            black_box(total)
        })
    });
    for (name, full_mueller) in [("together", false), ("together_polarised", true)] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut total = 0.0;
                let options = TraceOptions { full_mueller, ..TraceOptions::new(LAMBDA_D_NM) };
                for (sensor, u, _) in &rays {
                    let Some(pupil) = sampler.bounds.sample(black_box(*sensor), black_box(*u)) else {
                        continue;
                    };
                    let mut out = [None; MAX_LANES];
                    sampler.tracer.trace_lanes_from_sensor(
                        *sensor,
                        pupil.target_mm,
                        &lanes,
                        &options,
                        &mut out,
                    );
                    let weight = sampler.normalisation.sensor_weight(*sensor, &pupil);
                    total += out.iter().flatten().map(|sample| weight * sample.throughput).sum::<f64>();
                }
                black_box(total)
            })
        });
    }
    group.finish();

    // The shared path: the hero's scene rays (the lane at 683 nm of each camera sample that
    // passes), each traced back at the other 7 wavelengths; per 1024 scene rays, 7168 lanes.
    let hero = TraceOptions { full_mueller: false, ..TraceOptions::new(lanes[5]) };
    let exits: Vec<Ray> = rays
        .iter()
        .filter_map(|(sensor, u, _)| {
            let pupil = sampler.bounds.sample(*sensor, *u)?;
            let exit = sampler.tracer.trace_from_sensor(*sensor, pupil.target_mm, &hero, &mut || 0.0)?;
            Some(Ray { origin: exit.origin_mm, dir: exit.dir })
        })
        .cycle()
        .take(CALLS)
        .collect();
    let others: Vec<f64> = lanes.iter().enumerate().filter(|&(k, _)| k != 5).map(|(_, l)| *l).collect();
    let mut group = c.benchmark_group("lens_shared_path_7_lanes");
    group.throughput(Throughput::Elements((7 * CALLS) as u64));
    group.bench_function("back_to_sensor", |b| {
        b.iter(|| {
            let mut total = 0.0;
            for exit in &exits {
                let mut back = [None; MAX_LANES];
                sampler.tracer.trace_lanes_back_to_sensor(black_box(*exit), &others, &hero, &mut back);
                total += back.iter().flatten().map(|lane| lane.sample.throughput).sum::<f64>();
            }
            black_box(total)
        })
    });
    group.finish();
}

criterion_group!(benches, lens_benchmarks);
criterion_main!(benches);
