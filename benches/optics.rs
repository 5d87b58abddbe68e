//! Per-call cost of the spectral hot path: Fresnel for dielectrics, n(λ) of each IOR model, and
//! the sampling of a camera sample's wavelengths.
//!
//! Each iteration evaluates 1024 inputs (cos θi over [−1, 1], wavelengths over 360–830 nm), so
//! criterion's "elements/s" is calls per second and its time divided by 1024 is the time per
//! call. `cargo bench --bench optics`.
//!
//! The `interface` group is what a render does at a dielectric interface per wavelength lane
//! (issue 41's speed target: a coated interface at most 2× a bare one per lane), one lane per
//! call: `bare` is the bare path's Fresnel terms and the reflection and transmission Jones
//! elements built from them; `coated_1` and `coated_4` are [`Dielectric::coated_interface`]
//! (one lane alone) with a quarter-wave MgF₂ layer and a four-layer stack, which returns the
//! same two elements. Each call takes its own cos θi (both sides, [−1, 1]) and wavelength
//! (360–830 nm); the glass's n(λ) is given, as the integrators evaluate it once per lane for
//! both paths.
//!
//! The `lanes` group is the same per lane with the eight lanes of a vertex together, as the
//! integrators now evaluate a coating (`Dielectric::coated_interfaces`, whose Mueller matrices
//! `integrator::coated_matrices` returns as they are): `bare` eight bare evaluations (a
//! dispersive glass), `coated_*` one call for eight lanes; elements are lanes. The `vertex`
//! group is a whole vertex's interface work in the polarised path tracer: both Mueller matrices
//! and the branch choice, for a non-dispersive bare glass (one Fresnel for all lanes), a
//! dispersive one (eight) and the coatings; elements are vertices.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use prisma::material::{CoatingLayer, Dielectric};
use prisma::optics::catalogue::glass_ior;
use prisma::optics::{fresnel_dielectric, fresnel_dielectric_amplitudes, Ior};
use prisma::polarization::mueller::{JonesDiagonal, Mueller};
use prisma::spectrum::{SampledSpectrum, SampledWavelengths, N_LAMBDA};

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

    let coated = |layers: &[(f32, f32)]| Dielectric {
        ior: Ior::Constant(1.5),
        absorption: None,
        coating: layers
            .iter()
            .map(|&(n, thickness_nm)| CoatingLayer::dielectric(Ior::Constant(n), thickness_nm))
            .collect(),
    };
    // Quarter-wave MgF₂ at 550 nm; a four-layer stack (quarter, half, quarter, quarter waves of
    // MgF₂, ZrO₂ 2.05, Al₂O₃ 1.62, MgF₂ outermost first at 550 nm).
    let coated_1 = coated(&[(1.38, 99.64)]);
    let coated_4 = coated(&[(1.38, 99.64), (2.05, 134.15), (1.62, 84.88), (1.38, 99.64)]);
    let n_glass = 1.5168_f32;
    // Per lane, one lane per call: the bare Fresnel terms and the two Jones elements; the
    // coating lane by lane (`coated_interface`, what the integrators did before the lanes went
    // together).
    let mut group = c.benchmark_group("interface");
    group.throughput(Throughput::Elements(CALLS as u64));
    group.bench_function("bare", |b| {
        b.iter(|| {
            cosines
                .iter()
                .zip(&wavelengths_nm)
                .map(|(&cos, &_nm)| {
                    let f = fresnel_dielectric(black_box(cos), black_box(n_glass));
                    let r = JonesDiagonal::dielectric_reflection(cos, &f);
                    let t = JonesDiagonal::dielectric_transmission(&f);
                    r.a + r.w_im + t.a + t.w_re
                })
                .sum::<f32>()
        })
    });
    for (name, dielectric) in [("coated_1", &coated_1), ("coated_4", &coated_4)] {
        group.bench_function(name, |b| {
            b.iter(|| {
                cosines
                    .iter()
                    .zip(&wavelengths_nm)
                    .map(|(&cos, &nm)| {
                        let i = dielectric.coated_interface(black_box(cos), black_box(n_glass), nm, None);
                        i.reflection.a + i.reflection.w_im + i.transmission.a + i.transmission.w_re
                    })
                    .sum::<f32>()
            })
        });
    }
    group.finish();

    // Per lane, the eight lanes of a vertex together (one cos θi, eight wavelengths and glass
    // indices, as a dispersive glass has them): `bare` is eight bare evaluations (the
    // integrators' dispersive path), `coated_*` one `coated_interfaces`. Elements are lanes:
    // time ÷ 8192 is the time per lane.
    let vertex_lambdas: Vec<[f32; N_LAMBDA]> =
        (0..CALLS).map(|v| std::array::from_fn(|lane| wavelengths_nm[(v + lane * 128) % CALLS])).collect();
    let glass = glass_ior("N-BK7").expect("catalogue glass");
    let vertex_indices: Vec<[f32; N_LAMBDA]> =
        vertex_lambdas.iter().map(|lambdas| lambdas.map(|nm| glass.eval(nm))).collect();
    let all_live = (1u32 << N_LAMBDA) - 1;
    let mut group = c.benchmark_group("lanes");
    group.throughput(Throughput::Elements((CALLS * N_LAMBDA) as u64));
    group.bench_function("bare", |b| {
        b.iter(|| {
            cosines
                .iter()
                .zip(&vertex_indices)
                .map(|(&cos, indices)| {
                    let mut sum = 0.0;
                    for &n in indices {
                        let f = fresnel_dielectric(black_box(cos), black_box(n));
                        let r = JonesDiagonal::dielectric_reflection(cos, &f);
                        let t = JonesDiagonal::dielectric_transmission(&f);
                        sum += r.a + r.w_im + t.a + t.w_re;
                    }
                    sum
                })
                .sum::<f32>()
        })
    });
    for (name, dielectric) in [("coated_1", &coated_1), ("coated_4", &coated_4)] {
        group.bench_function(name, |b| {
            b.iter(|| {
                cosines
                    .iter()
                    .zip(&vertex_indices)
                    .zip(&vertex_lambdas)
                    .map(|((&cos, indices), lambdas)| {
                        let (r, t) = dielectric.coated_interfaces(
                            black_box(cos),
                            black_box(indices),
                            lambdas,
                            all_live,
                            None,
                        );
                        (r.a + r.w_im + t.a + t.w_re).values.iter().sum::<f32>()
                    })
                    .sum::<f32>()
            })
        });
    }
    group.finish();

    // A whole vertex's interface work in the polarised path tracer (what
    // `integrator::path` does at a dielectric, but the rays): the Mueller matrices of reflection
    // and transmission at every lane and the branch choice (probability ∝ the lanes' summed
    // a, the chosen matrix divided by it). `bare_splat`: a non-dispersive glass, one Fresnel
    // for all lanes; `bare_dispersive`: eight; `coated_*`: the coating at every lane. Elements
    // are vertices.
    let choose = |reflection: Mueller, transmission: Mueller, u: f32| {
        let (reflected, transmitted) =
            (reflection.a.values.iter().sum::<f32>(), transmission.a.values.iter().sum::<f32>());
        let p_reflect = reflected / (reflected + transmitted);
        let (chosen, p) =
            if u < p_reflect { (reflection, p_reflect) } else { (transmission, 1.0 - p_reflect) };
        chosen.scaled(SampledSpectrum::splat(1.0 / p)).a.values[0]
    };
    let mut group = c.benchmark_group("vertex");
    group.throughput(Throughput::Elements(CALLS as u64));
    group.bench_function("bare_splat", |b| {
        b.iter(|| {
            cosines
                .iter()
                .zip(&uniforms)
                .map(|(&cos, &u)| {
                    let f = fresnel_dielectric(black_box(cos), black_box(n_glass));
                    let r = Mueller::splat(JonesDiagonal::dielectric_reflection(cos, &f));
                    let t = Mueller::splat(JonesDiagonal::dielectric_transmission(&f));
                    choose(r, t, u)
                })
                .sum::<f32>()
        })
    });
    group.bench_function("bare_dispersive", |b| {
        b.iter(|| {
            cosines
                .iter()
                .zip(&vertex_indices)
                .zip(&uniforms)
                .map(|((&cos, indices), &u)| {
                    let fresnel = indices.map(|n| fresnel_dielectric(black_box(cos), black_box(n)));
                    let r =
                        Mueller::from_lanes(&fresnel.map(|f| JonesDiagonal::dielectric_reflection(cos, &f)));
                    let t = Mueller::from_lanes(&fresnel.map(|f| JonesDiagonal::dielectric_transmission(&f)));
                    choose(r, t, u)
                })
                .sum::<f32>()
        })
    });
    for (name, dielectric) in [("coated_1", &coated_1), ("coated_4", &coated_4)] {
        group.bench_function(name, |b| {
            b.iter(|| {
                cosines
                    .iter()
                    .zip(&vertex_indices)
                    .zip(&vertex_lambdas)
                    .zip(&uniforms)
                    .map(|(((&cos, indices), lambdas), &u)| {
                        let (r, t) = dielectric.coated_interfaces(
                            black_box(cos),
                            black_box(indices),
                            lambdas,
                            all_live,
                            None,
                        );
                        choose(r, t, u)
                    })
                    .sum::<f32>()
            })
        });
    }
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
