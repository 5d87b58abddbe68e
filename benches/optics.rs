//! Per-call cost of the spectral hot path: Fresnel for dielectrics, n(λ) of each IOR model, and
//! the sampling of a camera sample's wavelengths.
//!
//! Each iteration evaluates 1024 inputs (cos θi over [−1, 1], wavelengths over 360–830 nm), so
//! criterion's "elements/s" is calls per second and its time divided by 1024 is the time per
//! call. `cargo bench --bench optics`.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use prisma::optics::catalogue::glass_ior;
use prisma::optics::{fresnel_dielectric, fresnel_dielectric_amplitudes, Ior};
use prisma::spectrum::SampledWavelengths;

const CALLS: usize = 1024;

/// `CALLS` values evenly spread over [`low`, `high`], in a scrambled order so that branches
/// (inside/outside, total internal reflection) are not predictable from the previous call.
fn spread(low: f32, high: f32) -> Vec<f32> {
    (0..CALLS)
        .map(|i| {
            let scrambled = (i * 617) % CALLS; // 617 is prime: a permutation of 0..CALLS
            low + (high - low) * (scrambled as f32 + 0.5) / CALLS as f32
        })
        .collect()
}

fn optics_benchmarks(c: &mut Criterion) {
    let cosines = spread(-1.0, 1.0);
    let wavelengths_nm = spread(360.0, 830.0);
    let uniforms = spread(0.0, 1.0);

    let mut group = c.benchmark_group("fresnel");
    group.throughput(Throughput::Elements(CALLS as u64));
    group.bench_function("dielectric", |b| {
        b.iter(|| cosines.iter().map(|&cos| fresnel_dielectric(black_box(cos), 1.5).reflectance).sum::<f32>())
    });
    group.bench_function("dielectric_amplitudes", |b| {
        b.iter(|| {
            cosines
                .iter()
                .map(|&cos| fresnel_dielectric_amplitudes(black_box(cos), 1.5).reflectance)
                .sum::<f32>()
        })
    });
    group.finish();

    let models = [
        ("constant", Ior::Constant(1.5)),
        ("cauchy", Ior::Cauchy { a: 1.5046, b_um2: 0.0042, c_um4: 0.0 }),
        ("sellmeier_n_sf11", glass_ior("N-SF11").expect("catalogue glass")),
        ("table_water", glass_ior("water").expect("catalogue glass")),
    ];
    let mut group = c.benchmark_group("ior");
    group.throughput(Throughput::Elements(CALLS as u64));
    for (name, ior) in &models {
        group.bench_function(*name, |b| {
            b.iter(|| wavelengths_nm.iter().map(|&nm| ior.eval(black_box(nm))).sum::<f32>())
        });
    }
    group.finish();

    let mut group = c.benchmark_group("wavelengths");
    group.throughput(Throughput::Elements(CALLS as u64));
    group.bench_function("sample_visible_4", |b| {
        b.iter(|| {
            uniforms
                .iter()
                .map(|&u| SampledWavelengths::sample_visible(black_box(u.min(0.999_999)), 4).pdf_per_nm(0))
                .sum::<f32>()
        })
    });
    group.finish();
}

criterion_group!(benches, optics_benchmarks);
criterion_main!(benches);
