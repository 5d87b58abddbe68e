//! A coating at every wavelength lane of a vertex at once (`optics::thin_film::lanes`, the path
//! the renderer takes for coatings of lossless layers, issue 41's speed work) against the exact
//! evaluation (`optics::thin_film_amplitudes`: complex transfer matrices, tested against `tmm`
//! in `tests/thin_film_fixtures.rs`), and against the `tmm` fixtures themselves.
//!
//! Bounds:
//! - Lanes against the exact evaluation: every part of r_s, r_p and of the flux amplitudes
//!   within [`ROUNDING`] = 1e-12 absolute (values ≤ 1). Both are f64 evaluations of the same
//!   matrix products, in another order (the lanes scale each layer's matrix by its admittance,
//!   use fused multiply-adds and `wide`'s sin/cos/sinh/cosh, which are within 2.2e-16 and
//!   5e-16 of the library's); rounding grows with the entries of the products (cosh of layers
//!   past their critical angle) and the number of layers, and near grazing incidence from the
//!   inside the problem itself is ill-conditioned (a change of the glass index in its last
//!   place moves r by 1e-11): the worst measured is printed (`-- --nocapture`), 9.6e-13 with one
//!   lane in a million beyond 1e-12 and held to the exact evaluation's own spread instead
//!   ([`CONDITIONING_ULPS`]).
//! - The Mueller elements of `Dielectric::coated_interfaces` against `coated_interface` lane by
//!   lane: within [`F32_ROUNDING`] = 1e-6 (each element a sum of two products of amplitudes ≤ 1
//!   rounded to f32, ≤ 4·2⁻²⁴ ≈ 2.4e-7 apart).
//! - Against `tmm`: the fixture test's tolerances (R, T within 1e-6, issue 41; amplitudes within
//!   1e-9).

use num_complex::Complex64;
use prisma::material::{CoatedInterface, CoatingLayer, Dielectric, LayerIndex};
use prisma::optics::catalogue::glass_ior;
use prisma::optics::metals::metal;
use prisma::optics::thin_film::lanes::{lossless_stack_lanes, Lanes, LayerLanes, LANES};
use prisma::optics::{thin_film_amplitudes, Ior, Layer};
use std::f64::consts::TAU;
use std::path::Path;

/// Largest difference allowed between the lanes and the exact evaluation (module documentation).
const ROUNDING: f64 = 1e-12;
/// Where the lanes and the exact evaluation differ by more than [`ROUNDING`] (near grazing
/// incidence from the inside, where a change of the ambient index in its last place moves r by
/// 1e-11), the difference must stay within [`ROUNDING`] plus the exact evaluation's own change
/// when the ambient index moves by this many units in the last place: the lanes are then as
/// exact as the inputs' rounding allows.
const CONDITIONING_ULPS: f64 = 4.0;
/// Largest difference allowed between the two f32 Mueller evaluations (module documentation).
const F32_ROUNDING: f32 = 1e-6;
/// `tmm`: R and T (issue 41) and the amplitudes, as `tests/thin_film_fixtures.rs`.
const POWER_TOLERANCE: f64 = 1e-6;
const AMPLITUDE_TOLERANCE: f64 = 1e-9;

/// The coatings the scenes and the benchmark use, as (n, thickness in nm) from the outside in.
fn shipped_coatings() -> Vec<(&'static str, Vec<(Ior, f32)>)> {
    let constant = |layers: &[(f32, f32)]| layers.iter().map(|&(n, d)| (Ior::Constant(n), d)).collect();
    let mut mirror = [(2.4, 57.29), (1.46, 94.18)].repeat(7);
    mirror.push((2.4, 57.29));
    vec![
        ("MgF₂ quarter wave", constant(&[(1.38, 99.64)])),
        (
            "four-layer AR (benchmark)",
            constant(&[(1.38, 99.64), (2.05, 134.15), (1.62, 84.88), (1.38, 99.64)]),
        ),
        ("four-layer AR (fixture)", constant(&[(1.38, 99.64), (2.05, 134.15), (1.38, 30.0), (2.05, 15.0)])),
        ("dichroic mirror (TiO₂/SiO₂)", constant(&mirror)),
        ("SiO₂ 94 nm", constant(&[(1.46, 94.0)])),
        (
            "dispersive MgF₂ (Cauchy) under ZrO₂",
            vec![
                (Ior::Cauchy { a: 1.37, b_um2: 0.0035, c_um4: 0.0 }, 99.64),
                (Ior::Cauchy { a: 2.0, b_um2: 0.02, c_um4: 0.0 }, 134.0),
            ],
        ),
    ]
}

/// The flux amplitude t·√(T/|t|²) of an exact evaluation (0 where t is).
fn flux(t: Complex64, transmittance: f64) -> Complex64 {
    if t.norm_sqr() > 0.0 {
        t * (transmittance / t.norm_sqr()).sqrt()
    } else {
        Complex64::new(0.0, 0.0)
    }
}

/// Largest difference of the real or imaginary parts.
fn difference(a: Complex64, b: Complex64) -> f64 {
    (a.re - b.re).abs().max((a.im - b.im).abs())
}

/// 48 wavelengths over 360–830 nm in six groups of eight lanes.
fn wavelength_groups() -> Vec<[f32; LANES]> {
    (0..6).map(|group| std::array::from_fn(|l| 360.0 + 470.0 * (group * LANES + l) as f32 / 47.0)).collect()
}

/// Every shipped coating on N-BK7 and on the dense flint N-SF11 (n ≈ 1.78: from the inside its
/// MgF₂ and SiO₂ layers are past their critical angles from 50° on, and the substrate behind
/// them from 34°), from both sides, at 0–89.9° by 0.1° and 48 wavelengths over 360–830 nm:
/// each lane's r_s, r_p and flux amplitudes equal the exact evaluation's within [`ROUNDING`],
/// and no lane is refused.
#[test]
fn shipped_coatings_at_every_lane_equal_the_exact_evaluation() {
    let (mut worst, mut lanes_compared, mut past_critical, mut behind_critical) = (0.0_f64, 0, 0, 0);
    let (mut ill_conditioned, mut worst_conditioned) = (0, 0.0_f64);
    for glass_name in ["N-BK7", "N-SF11"] {
        let glass = glass_ior(glass_name).expect("catalogue glass");
        for (name, coating) in shipped_coatings() {
            for lambdas in wavelength_groups() {
                let n_glass: Lanes = lambdas.map(|nm| f64::from(glass.eval(nm)));
                let wavenumber: Lanes = lambdas.map(|nm| TAU / f64::from(nm));
                let outside: Vec<LayerLanes> = coating
                    .iter()
                    .map(|(ior, d)| LayerLanes {
                        index: lambdas.map(|nm| f64::from(ior.eval(nm))),
                        thickness_nm: f64::from(*d),
                    })
                    .collect();
                let inside: Vec<LayerLanes> = outside.iter().rev().copied().collect();
                for tenth_deg in 0..900 {
                    let cos_i = (f64::from(tenth_deg) / 10.0).to_radians().cos();
                    for from_inside in [false, true] {
                        let (ambient, layers, substrate) = if from_inside {
                            (n_glass, &inside, [1.0; LANES])
                        } else {
                            ([1.0; LANES], &outside, n_glass)
                        };
                        let stack = lossless_stack_lanes(&ambient, layers, &substrate, &wavenumber, cos_i);
                        assert_eq!(
                            stack.refused, 0,
                            "{name} on {glass_name}, cos {cos_i}, inside {from_inside}"
                        );
                        for l in 0..LANES {
                            let scalar: Vec<Layer> = layers
                                .iter()
                                .map(|layer| Layer::dielectric(layer.index[l], layer.thickness_nm))
                                .collect();
                            let exact = thin_film_amplitudes(
                                ambient[l],
                                &scalar,
                                Complex64::new(substrate[l], 0.0),
                                f64::from(lambdas[l]),
                                cos_i,
                            );
                            let lane = |parts: &[Lanes; 2]| Complex64::new(parts[0][l], parts[1][l]);
                            let quantities = |a: &prisma::optics::ThinFilmAmplitudes| {
                                [a.r_s, a.r_p, flux(a.t_s, a.transmittance_s), flux(a.t_p, a.transmittance_p)]
                            };
                            let ours = [
                                lane(&stack.r_s),
                                lane(&stack.r_p),
                                lane(&stack.flux_s),
                                lane(&stack.flux_p),
                            ];
                            let exact_values = quantities(&exact);
                            let d = ours
                                .iter()
                                .zip(&exact_values)
                                .map(|(a, b)| difference(*a, *b))
                                .fold(0.0, f64::max);
                            if d > ROUNDING {
                                // Ill-conditioned here (near grazing from the inside): the exact
                                // evaluation itself moves this much when the ambient index moves
                                // by CONDITIONING_ULPS units in its last place.
                                let spread = [1.0, -1.0]
                                    .map(|sign| {
                                        let n0 = ambient[l] * (1.0 + sign * CONDITIONING_ULPS * f64::EPSILON);
                                        let moved = thin_film_amplitudes(
                                            n0,
                                            &scalar,
                                            Complex64::new(substrate[l], 0.0),
                                            f64::from(lambdas[l]),
                                            cos_i,
                                        );
                                        quantities(&moved)
                                            .iter()
                                            .zip(&exact_values)
                                            .map(|(a, b)| difference(*a, *b))
                                            .fold(0.0, f64::max)
                                    })
                                    .into_iter()
                                    .fold(0.0, f64::max);
                                ill_conditioned += 1;
                                worst_conditioned = worst_conditioned.max(d / spread);
                                assert!(
                                    d <= ROUNDING + spread,
                                    "{name} on {glass_name}, {} nm, θ {}°, inside {from_inside}: {ours:?} vs \
                                     {exact_values:?}, beyond the spread {spread:e}",
                                    lambdas[l],
                                    f64::from(tenth_deg) / 10.0
                                );
                            } else {
                                worst = worst.max(d);
                            }
                            let invariant = ambient[l] * ambient[l] * (1.0 - cos_i * cos_i);
                            past_critical +=
                                usize::from(scalar.iter().any(|layer| layer.index.re.powi(2) < invariant));
                            behind_critical += usize::from(substrate[l] * substrate[l] < invariant);
                            lanes_compared += 1;
                        }
                    }
                }
            }
        }
    }
    println!(
        "worst difference {worst:.2e} over {lanes_compared} lanes ({past_critical} with a layer past its critical \
         angle, {behind_critical} with the substrate past its); {ill_conditioned} lanes beyond {ROUNDING:e}, at \
         most {worst_conditioned:.2} times the exact evaluation's own spread"
    );
    // Near grazing incidence only: a small part of the lanes.
    assert!(ill_conditioned * 100 < lanes_compared, "{ill_conditioned} of {lanes_compared}");
    assert!(past_critical > 100_000 && behind_critical > 100_000, "{past_critical}, {behind_critical}");
}

/// `Dielectric::coated_interfaces` (all lanes together, the renderer's call) against
/// `Dielectric::coated_interface` (one lane, through the exact evaluation) for the shipped
/// coatings and for those it hands back to the exact path (a film on gold, an absorbing
/// layer), with some lanes not live: the Mueller elements within [`F32_ROUNDING`].
#[test]
fn the_vertex_call_is_each_lane_alone() {
    let gold = metal("gold").expect("catalogue metal");
    let mut coatings: Vec<(&str, Vec<CoatingLayer>)> = shipped_coatings()
        .into_iter()
        .map(|(name, layers)| {
            (name, layers.into_iter().map(|(ior, d)| CoatingLayer::dielectric(ior, d)).collect())
        })
        .collect();
    coatings.push((
        "SiO₂ over 12 nm of gold",
        vec![
            CoatingLayer::dielectric(Ior::Constant(1.46), 80.0),
            CoatingLayer { index: LayerIndex::Metal(gold), thickness_nm: 12.0 },
        ],
    ));
    coatings.push((
        "an absorbing layer",
        vec![CoatingLayer {
            index: LayerIndex::Complex(num_complex::Complex32::new(2.0, 0.5)),
            thickness_nm: 30.0,
        }],
    ));
    let glass = glass_ior("N-SF11").expect("catalogue glass");
    let mut worst = 0.0_f32;
    for (name, coating) in coatings {
        let dielectric = Dielectric { ior: glass.clone(), absorption: None, coating };
        for lambdas in wavelength_groups() {
            let n_glass = lambdas.map(|nm| glass.eval(nm));
            for step in 0..=360 {
                // cos θ over [−1, 1] (both sides), 0 itself included.
                let cos_theta_i = -1.0 + step as f32 / 180.0;
                let live = if step % 3 == 0 { 0b1101_0111 } else { (1 << LANES) - 1 };
                let (reflection, transmission) =
                    dielectric.coated_interfaces(cos_theta_i, &n_glass, &lambdas, live, None);
                for l in 0..LANES {
                    let expected = if live & (1 << l) != 0 {
                        dielectric.coated_interface(cos_theta_i, n_glass[l], lambdas[l], None)
                    } else {
                        let zero = prisma::polarization::mueller::JonesDiagonal {
                            a: 0.0,
                            b: 0.0,
                            w_re: 0.0,
                            w_im: 0.0,
                        };
                        CoatedInterface { reflection: zero, transmission: zero }
                    };
                    for (matrix, element) in
                        [(&reflection, expected.reflection), (&transmission, expected.transmission)]
                    {
                        let got = [matrix.a, matrix.b, matrix.w_re, matrix.w_im].map(|c| c.values[l]);
                        for (a, b) in got.into_iter().zip([element.a, element.b, element.w_re, element.w_im])
                        {
                            worst = worst.max((a - b).abs());
                            assert!(
                                (a - b).abs() <= F32_ROUNDING,
                                "{name}: cos {cos_theta_i}, {} nm: {got:?} vs {element:?}",
                                lambdas[l]
                            );
                        }
                    }
                }
            }
        }
    }
    println!("worst difference {worst:.2e}");
}

/// One `tmm` fixture: its stack (from its header) and its rows (λ, θ, R_s, R_p, T_s, T_p, and
/// r_s, r_p, t_s, t_p in prisma's conventions; see `tests/thin_film_fixtures.rs`).
struct Fixture {
    ambient: f64,
    layers: Vec<(f64, f64)>,
    substrate: f64,
    rows: Vec<Vec<f64>>,
}

fn read(case: &str) -> Fixture {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(format!("thin_film_{case}.csv"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|err| panic!("{}: {err}", path.display()));
    let numbers = |text: &str| -> Vec<f64> {
        text.split_whitespace()
            .map(|field| field.parse().unwrap_or_else(|err| panic!("{case}: {err}")))
            .collect()
    };
    let header = |key: &str| {
        text.lines()
            .find_map(|line| line.strip_prefix(&format!("# {key}: ")))
            .unwrap_or_else(|| panic!("{case}: no '# {key}:' line"))
    };
    let real = |values: Vec<f64>| {
        assert_eq!(values[1], 0.0, "{case}: the lanes take lossless media only");
        values[0]
    };
    let layers = header("layers")
        .split(';')
        .map(|layer| {
            let values = numbers(layer);
            assert_eq!(values[1], 0.0, "{case}: the lanes take lossless layers only");
            (values[0], values[2])
        })
        .collect();
    let rows = text
        .lines()
        .filter(|line| !line.starts_with('#'))
        .skip(1)
        .map(|line| {
            line.split(',').map(|field| field.parse().unwrap_or_else(|err| panic!("{case}: {err}"))).collect()
        })
        .collect();
    Fixture {
        ambient: real(numbers(header("ambient"))),
        layers,
        substrate: real(numbers(header("substrate"))),
        rows,
    }
}

/// The lossless `tmm` fixtures (the MgF₂ layer, the four-layer AR, the 16-layer mirror, the soap
/// film; the film on gold has an absorbing substrate and takes the exact path, checked by
/// `tests/thin_film_fixtures.rs`) through the lanes, eight wavelengths of one angle per call:
/// R and T within 1e-6, r_s, r_p and the flux amplitudes t·√(T/|t|²) within 1e-9.
#[test]
fn lanes_match_the_tmm_fixtures() {
    let mut rows_compared = 0;
    for case in ["mgf2_on_bk7", "ar4_on_bk7", "mirror_tio2_sio2", "soap_film"] {
        let fixture = read(case);
        let mut angles: Vec<f64> = fixture.rows.iter().map(|row| row[1]).collect();
        angles.dedup();
        angles.sort_by(f64::total_cmp);
        angles.dedup();
        let (mut worst_power, mut worst_amplitude) = (0.0_f64, 0.0_f64);
        for theta_deg in angles {
            let rows: Vec<&Vec<f64>> = fixture.rows.iter().filter(|row| row[1] == theta_deg).collect();
            for group in rows.chunks(LANES) {
                // Lanes past the group's end repeat its last row.
                let row = |l: usize| group[l.min(group.len() - 1)];
                let wavenumber: Lanes = std::array::from_fn(|l| TAU / row(l)[0]);
                let layers: Vec<LayerLanes> = fixture
                    .layers
                    .iter()
                    .map(|&(n, d)| LayerLanes { index: [n; LANES], thickness_nm: d })
                    .collect();
                let stack = lossless_stack_lanes(
                    &[fixture.ambient; LANES],
                    &layers,
                    &[fixture.substrate; LANES],
                    &wavenumber,
                    theta_deg.to_radians().cos(),
                );
                assert_eq!(stack.refused, 0, "{case} at {theta_deg}°");
                for (l, expected) in group.iter().enumerate() {
                    let part = |i: usize| Complex64::new(expected[8 + 2 * i], expected[9 + 2 * i]);
                    let lane = |parts: &[Lanes; 2]| Complex64::new(parts[0][l], parts[1][l]);
                    let (r_s, r_p, flux_s, flux_p) =
                        (lane(&stack.r_s), lane(&stack.r_p), lane(&stack.flux_s), lane(&stack.flux_p));
                    let context = format!("{case}: {} nm, {theta_deg}°", expected[0]);
                    for (ours, theirs) in
                        [r_s.norm_sqr(), r_p.norm_sqr(), flux_s.norm_sqr(), flux_p.norm_sqr()]
                            .into_iter()
                            .zip(&expected[2..6])
                    {
                        worst_power = worst_power.max((ours - theirs).abs());
                        assert!((ours - theirs).abs() <= POWER_TOLERANCE, "{context}: {ours} vs {theirs}");
                    }
                    for (ours, theirs) in [
                        (r_s, part(0)),
                        (r_p, part(1)),
                        (flux_s, flux(part(2), expected[4])),
                        (flux_p, flux(part(3), expected[5])),
                    ] {
                        worst_amplitude = worst_amplitude.max(difference(ours, theirs));
                        assert!(
                            difference(ours, theirs) <= AMPLITUDE_TOLERANCE,
                            "{context}: {ours} vs {theirs}"
                        );
                    }
                    rows_compared += 1;
                }
            }
        }
        println!("{case}: worst |ΔR|, |ΔT| {worst_power:.2e}, worst amplitude {worst_amplitude:.2e}");
    }
    // 4 cases × 26 wavelengths × 19 angles.
    assert_eq!(rows_compared, 4 * 26 * 19);
}
