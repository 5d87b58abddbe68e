//! The optics of lens systems against closed forms: thin- and thick-lens formulas, Newton's
//! imaging equation, the paraxial limit of real rays, Π(1 − R) on axis, Fresnel through a tilted
//! plate (transmission and degree of polarisation), the ghost estimator's expectation, a lens of
//! index 1 that must image like a pinhole at its stop, and pupil sampling that must agree with
//! the plain disc. Systems are built in code (conventions in `prisma::lens`).
//!
//! Run with `--nocapture` to see the measured shares of camera rays that pass the lenses.

use glam::DVec3;
use prisma::lens::fresnel_stack::{degree_of_linear_polarization, mueller_apply};
use prisma::lens::{
    ExitPupilBounds, LensSystem, LensTracer, Medium, Normalisation, PupilSample, Ray, RearDisc, Surface,
    TraceOptions, LAMBDA_D_NM,
};
use prisma::optics::catalogue::glass;
use rand_core::{RngCore, SeedableRng};
use rand_pcg::Pcg64;

/// The Fraunhofer F and C lines (nm).
const LAMBDA_F_NM: f64 = 486.1327;
const LAMBDA_C_NM: f64 = 656.2725;

fn surface(
    radius_mm: f64,
    thickness_mm: f64,
    medium: Medium,
    semi_diameter_mm: f64,
    is_stop: bool,
) -> Surface {
    Surface::spherical(radius_mm, thickness_mm, medium, semi_diameter_mm, is_stop)
}

fn catalogue(name: &str) -> Medium {
    let entry = glass(name).unwrap_or_else(|| panic!("{name} is in data/glasses.toml"));
    Medium::Glass { name: name.into(), formula: entry.formula().clone() }
}

fn system(surfaces: Vec<Surface>) -> LensSystem {
    LensSystem { surfaces, source: Default::default() }
}

/// The last thickness set to the paraxial focus of an object at infinity at the d line.
fn focused(mut lens: LensSystem) -> LensSystem {
    let bfl = lens.focus_thickness_mm(f64::INFINITY, LAMBDA_D_NM).unwrap();
    lens.surfaces.last_mut().unwrap().thickness_mm = bfl;
    lens
}

/// A biconvex N-BK7 singlet, f ≈ 49 mm, the stop on its front surface.
fn singlet() -> LensSystem {
    focused(system(vec![
        surface(50.0, 5.0, catalogue("N-BK7"), 8.0, true),
        surface(-50.0, 0.0, Medium::Air, 8.0, false),
    ]))
}

/// A cemented N-BK7 / F2 doublet, f ≈ 100 mm, the stop 5 mm in front of it.
fn doublet() -> LensSystem {
    focused(system(vec![
        surface(0.0, 5.0, Medium::Air, 10.0, true),
        surface(61.0, 6.0, catalogue("N-BK7"), 12.7, false),
        surface(-44.0, 2.5, catalogue("F2"), 12.7, false),
        surface(-129.0, 0.0, Medium::Air, 12.7, false),
    ]))
}

/// pbrt-v4's `dgauss.50mm.dat` (D-GAUSS F/2 22° HFOV, US 2,673,491, scaled to 50 mm; radius,
/// thickness, index, aperture diameter), with its one index per element.
fn double_gauss() -> LensSystem {
    let rows = [
        (29.475, 3.76, 1.67, 25.2),
        (84.83, 0.12, 1.0, 25.2),
        (19.275, 4.025, 1.67, 23.0),
        (40.77, 3.275, 1.699, 23.0),
        (12.75, 5.705, 1.0, 18.0),
        (0.0, 4.5, 1.0, 17.1),
        (-14.495, 1.18, 1.603, 17.0),
        (40.77, 6.065, 1.658, 20.0),
        (-20.385, 0.19, 1.0, 20.0),
        (437.065, 3.22, 1.717, 20.0),
        (-39.73, 0.0, 1.0, 20.0),
    ];
    let surfaces = rows
        .iter()
        .enumerate()
        .map(|(index, &(radius, thickness, n, diameter))| {
            let medium = if n == 1.0 { Medium::Air } else { Medium::constant(n) };
            surface(radius, thickness, medium, diameter / 2.0, index == 5)
        })
        .collect();
    focused(system(surfaces))
}

fn uniform(rng: &mut Pcg64) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Mean and standard error of `values`.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

#[test]
fn thin_singlet_focal_length_tends_to_the_lensmakers_formula() {
    // 1/f = (n(λ) − 1)(1/R1 − 1/R2) for a lens of no thickness (Hecht §5.2.3). The thick lens
    // adds (n − 1)² d/(n R1 R2) to 1/f, so f/f_thin − 1 = −(n − 1)d/(n R1 R2 (1/R1 − 1/R2))
    // to first order in d: the gap must shrink in proportion to d.
    let (r1, r2) = (50.0, -50.0);
    for lambda in [LAMBDA_F_NM, LAMBDA_D_NM, LAMBDA_C_NM] {
        let n = catalogue("N-BK7").n_at_nm(lambda);
        let f_thin = 1.0 / ((n - 1.0) * (1.0 / r1 - 1.0 / r2));
        for d in [1e-2, 1e-4, 1e-6] {
            let lens = system(vec![
                surface(r1, d, catalogue("N-BK7"), 5.0, true),
                surface(r2, 40.0, Medium::Air, 5.0, false),
            ]);
            let f = lens.paraxial(lambda).unwrap().efl_mm;
            let first_order = -(n - 1.0) * d / (n * r1 * r2 * (1.0 / r1 - 1.0 / r2));
            // The remainder is second order, (first_order)² (1.2e-9 at d = 1e-2), plus rounding.
            let remainder = f / f_thin - 1.0 - first_order;
            assert!(
                remainder.abs() < 2.0 * first_order * first_order + 1e-14,
                "λ {lambda}, d {d}: {f} vs {f_thin}"
            );
        }
    }
}

#[test]
fn thick_singlet_paraxial_values_match_the_thick_lens_formulas() {
    // Hecht §6.2: 1/f = (n−1)[1/R1 − 1/R2 + (n−1)d/(n R1 R2)], BFL = f(1 − (n−1)d/(n R1)),
    // FFL = f(1 + (n−1)d/(n R2)); relative 1e-12 (a few roundings of numbers of order 1).
    // The stop on the front surface is the entrance pupil (z = 0, diameter 2a); the exit pupil
    // is the front surface imaged by the back one: n′/z′ − n/z = (n′ − n)/R2 with the object at
    // z = −d in glass, magnification n z′/(n′ z).
    let lens = singlet();
    let (r1, r2, d, a) = (50.0, -50.0, 5.0, 8.0);
    for lambda in [LAMBDA_F_NM, LAMBDA_D_NM, LAMBDA_C_NM, 400.0, 700.0] {
        let n = catalogue("N-BK7").n_at_nm(lambda);
        let p = lens.paraxial(lambda).unwrap();
        let f = 1.0 / ((n - 1.0) * (1.0 / r1 - 1.0 / r2 + (n - 1.0) * d / (n * r1 * r2)));
        let bfl = f * (1.0 - (n - 1.0) * d / (n * r1));
        let ffl = f * (1.0 + (n - 1.0) * d / (n * r2));
        let z_exit = 1.0 / ((1.0 - n) / r2 + n / -d);
        let magnification = n * z_exit / -d;
        let checks = [
            ("EFL", p.efl_mm, f),
            ("BFL", p.bfl_mm, bfl),
            ("FFL", p.ffl_mm, ffl),
            ("EP diameter", p.entrance_pupil_diameter_mm, 2.0 * a),
            ("XP z", p.exit_pupil_z_mm, z_exit),
            ("XP diameter", p.exit_pupil_diameter_mm, 2.0 * a * magnification.abs()),
            ("f-number", p.f_number, f / (2.0 * a)),
        ];
        for (name, got, want) in checks {
            assert!((got / want - 1.0).abs() < 1e-12, "λ {lambda}: {name} {got} vs {want}");
        }
        assert_eq!(p.entrance_pupil_z_mm, 0.0);
        // Longitudinal chromatic focal shift: the thick-lens BFL at λ minus at d; absolute
        // 1e-11 mm (rounding of two ~50 mm numbers).
        let n_d = catalogue("N-BK7").n_at_nm(LAMBDA_D_NM);
        let f_d = 1.0 / ((n_d - 1.0) * (1.0 / r1 - 1.0 / r2 + (n_d - 1.0) * d / (n_d * r1 * r2)));
        let bfl_d = f_d * (1.0 - (n_d - 1.0) * d / (n_d * r1));
        let shift = lens.chromatic_focal_shift_mm(lambda, f64::INFINITY).unwrap();
        assert!((shift - (bfl - bfl_d)).abs() < 1e-11, "λ {lambda}: shift {shift} vs {}", bfl - bfl_d);
    }
    // N-BK7 disperses normally: blue focuses nearer the lens than red.
    let shift_f = lens.chromatic_focal_shift_mm(LAMBDA_F_NM, f64::INFINITY).unwrap();
    let shift_c = lens.chromatic_focal_shift_mm(LAMBDA_C_NM, f64::INFINITY).unwrap();
    println!("singlet: F − d focus {shift_f:.4} mm, C − d {shift_c:.4} mm");
    assert!(shift_f < 0.0 && shift_c > 0.0);
}

#[test]
fn focusing_a_finite_object_follows_newtons_equation() {
    // Newton (Hecht §5.2.3), object and image in air: x x′ = −f², x the object's position
    // from the front focus, x′ the image's from the back focus. The sensor distance the camera
    // sets is the image's distance from the last vertex: BFL + x′.
    for lens in [singlet(), doublet(), double_gauss()] {
        for lambda in [LAMBDA_F_NM, LAMBDA_D_NM, LAMBDA_C_NM] {
            let p = lens.paraxial(lambda).unwrap();
            for distance in [300.0, 1000.0, 1e5] {
                let x = -(distance - p.ffl_mm);
                let expected = p.bfl_mm - p.efl_mm * p.efl_mm / x;
                let got = lens.focus_thickness_mm(distance, lambda).unwrap();
                assert!((got / expected - 1.0).abs() < 1e-11, "D {distance}: {got} vs {expected}");
            }
            let at_infinity = lens.focus_thickness_mm(f64::INFINITY, lambda).unwrap();
            assert!((at_infinity / p.bfl_mm - 1.0).abs() < 1e-15);
        }
    }
}

#[test]
fn stopping_down_gives_the_asked_f_number() {
    let mut lens = double_gauss();
    let stop = lens.stop_index().unwrap();
    let p = lens.paraxial(LAMBDA_D_NM).unwrap();
    println!(
        "double Gauss: EFL {:.4} mm, BFL {:.4}, FFL {:.4}, EP z {:.4} Ø {:.4}, XP z {:.4} Ø {:.4}, f/{:.4}",
        p.efl_mm,
        p.bfl_mm,
        p.ffl_mm,
        p.entrance_pupil_z_mm,
        p.entrance_pupil_diameter_mm,
        p.exit_pupil_z_mm,
        p.exit_pupil_diameter_mm,
        p.f_number
    );
    for f_number in [2.8, 5.6, 16.0] {
        lens.surfaces[stop].semi_diameter_mm =
            p.stop_semi_diameter_for_f_number(f_number, double_gauss().surfaces[stop].semi_diameter_mm);
        let stopped = lens.paraxial(LAMBDA_D_NM).unwrap();
        assert!((stopped.f_number / f_number - 1.0).abs() < 1e-12, "{}", stopped.f_number);
    }
}

/// The z where an image-space ray in the y–z plane crosses the axis.
fn axis_crossing(ray: &Ray) -> f64 {
    ray.origin.z - ray.origin.y * ray.dir.z / ray.dir.y
}

#[test]
fn real_rays_converge_to_the_paraxial_focus() {
    // A ray parallel to the axis at height h crosses it after the lens at BFL + Δ(h) with
    // Δ ∝ h² (third-order spherical aberration, Welford §7): Δ(h)/h² settles to a constant and
    // Δ vanishes as the aperture does. At h = 1e-3 of the pupil the f64 rounding of the trace
    // (~1e-13 mm in the height, amplified by BFL/h) is far below the 1e-6 relative asked.
    for (name, lens) in [("singlet", singlet()), ("doublet", doublet()), ("double Gauss", double_gauss())] {
        let tracer = LensTracer::new(lens.clone());
        let last_vertex = tracer.rear_vertex_z_mm();
        let scale = lens.paraxial(LAMBDA_D_NM).unwrap().efl_mm;
        for lambda in [LAMBDA_F_NM, LAMBDA_D_NM, LAMBDA_C_NM] {
            let p = lens.paraxial(lambda).unwrap();
            let semi = p.entrance_pupil_diameter_mm / 2.0;
            let aberration = |h: f64| {
                let ray = Ray { origin: DVec3::new(0.0, h, -10.0), dir: DVec3::Z };
                let traced = tracer.trace_from_object(ray, lambda).expect("passes");
                axis_crossing(&traced.ray) - last_vertex - p.bfl_mm
            };
            let coefficients: Vec<f64> =
                [0.1, 0.01, 0.001].iter().map(|f| aberration(f * semi) / (f * semi).powi(2)).collect();
            assert!(
                (coefficients[1] / coefficients[2] - 1.0).abs() < 1e-3,
                "{name} λ {lambda}: Δ/h² {coefficients:?}"
            );
            assert!(aberration(1e-3 * semi).abs() < 1e-6 * scale, "{name} λ {lambda}");
        }
        // Image height of a distant point at a small field angle θ through the pupil's centre:
        // EFL·tan θ (distortion is O(θ³)); a ray going up comes from a point below the axis,
        // whose image is above it.
        let p = lens.paraxial(LAMBDA_D_NM).unwrap();
        let theta: f64 = 1e-4;
        let dir = DVec3::new(0.0, theta.sin(), theta.cos());
        let start = DVec3::new(0.0, 0.0, p.entrance_pupil_z_mm) - 20.0 * dir;
        let traced = tracer.trace_from_object(Ray { origin: start, dir }, LAMBDA_D_NM).unwrap();
        let height = traced.ray.origin.y;
        assert!((height / (p.efl_mm * theta.tan()) - 1.0).abs() < 1e-6, "{name}: {height}");
    }
}

#[test]
fn a_ray_through_the_stop_centre_is_the_chief_ray() {
    // The chief ray, the one through the centre of the stop, comes from the centre of the
    // entrance pupil in object space and leaves toward the centre of the exit pupil in image
    // space; for real rays that holds in the limit of small field angles (pupil aberration
    // is O(θ²)). Found by the secant method on its height at the first vertex.
    let lens = double_gauss();
    let tracer = LensTracer::new(lens.clone());
    let stop = lens.stop_index().unwrap();
    let p = lens.paraxial(LAMBDA_D_NM).unwrap();
    let last_vertex = tracer.rear_vertex_z_mm();
    let mut errors = vec![];
    for theta in [1e-2_f64, 1e-3] {
        let dir = DVec3::new(0.0, theta.sin(), theta.cos());
        let stop_height = |y0: f64| {
            let traced = tracer
                .trace_from_object(Ray { origin: DVec3::new(0.0, y0, -1.0), dir }, LAMBDA_D_NM)
                .unwrap();
            let at_stop = traced.interactions.iter().find(|i| i.surface == stop).unwrap();
            (at_stop.point.y, traced.ray)
        };
        let (mut a, mut b) = (0.0, -0.1);
        for _ in 0..50 {
            let (fa, fb) = (stop_height(a).0, stop_height(b).0);
            if fb == fa {
                break;
            }
            let next = b - fb * (b - a) / (fb - fa);
            a = b;
            b = next;
        }
        let (residual, image_ray) = stop_height(b);
        assert!(residual.abs() < 1e-12, "stop height {residual}");
        // Object space: the ray (0, b, −1) + s·dir crosses the axis at −1 − b/tan θ.
        let entrance = -1.0 - b / theta.tan();
        let exit = axis_crossing(&image_ray) - last_vertex;
        errors.push((entrance - p.entrance_pupil_z_mm, exit - p.exit_pupil_z_mm));
    }
    println!("chief ray pupil errors at θ = 1e-2, 1e-3: {errors:?}");
    // O(θ²): a tenth of the angle, a hundredth of the error (to 2%, the next order).
    for (coarse, fine) in [(errors[0].0, errors[1].0), (errors[0].1, errors[1].1)] {
        assert!((fine / coarse * 100.0 - 1.0).abs() < 0.02, "{errors:?}");
    }
    assert!(errors[1].0.abs() < 1e-4 && errors[1].1.abs() < 1e-4, "{errors:?}");
}

#[test]
fn refraction_obeys_snells_law_at_every_surface() {
    // The vector form of Snell's law: n (d × N) = n′ (d′ × N) (tangential momentum), d′ a unit
    // vector in the plane of d and N. Residuals at f64 rounding (1e-15 of n).
    let lens = doublet();
    let tracer = LensTracer::new(lens.clone());
    let mut rng = Pcg64::seed_from_u64(7);
    let mut checked = 0;
    for lambda in [LAMBDA_F_NM, LAMBDA_D_NM, LAMBDA_C_NM] {
        for _ in 0..200 {
            let origin = DVec3::new(8.0 * (uniform(&mut rng) - 0.5), 8.0 * (uniform(&mut rng) - 0.5), -5.0);
            let dir =
                DVec3::new(0.2 * (uniform(&mut rng) - 0.5), 0.2 * (uniform(&mut rng) - 0.5), 1.0).normalize();
            let Ok(traced) = tracer.trace_from_object(Ray { origin, dir }, lambda) else { continue };
            for i in &traced.interactions {
                let residual =
                    (i.n_in * i.dir_in.cross(i.normal) - i.n_other * i.dir_out.cross(i.normal)).length();
                assert!(residual < 4e-15 * i.n_in.max(i.n_other), "{i:?}: {residual}");
                assert!(i.dir_in.cross(i.normal).dot(i.dir_out).abs() < 1e-15);
                assert!((i.dir_out.length() - 1.0).abs() < 1e-15);
                checked += 1;
            }
        }
    }
    assert!(checked > 1000, "{checked}");
}

#[test]
fn on_axis_transmission_of_an_uncoated_lens_is_the_product_of_one_minus_r() {
    // Along the axis every surface is met at normal incidence: T = Π(1 − ((n − n′)/(n + n′))²)
    // (Hecht §4.6.4), exactly (1e-14: a dozen roundings), ghosts off. With Fresnel off: 1.
    for (name, lens) in [("singlet", singlet()), ("doublet", doublet()), ("double Gauss", double_gauss())] {
        let tracer = LensTracer::new(lens.clone());
        for lambda in [LAMBDA_F_NM, LAMBDA_D_NM, LAMBDA_C_NM] {
            let mut expected = 1.0;
            for (index, s) in lens.surfaces.iter().enumerate() {
                let (n, n_after) = (lens.medium_before(index).n_at_nm(lambda), s.medium.n_at_nm(lambda));
                expected *= 1.0 - ((n - n_after) / (n + n_after)).powi(2);
            }
            let sample = tracer
                .trace_from_sensor([0.0, 0.0], [0.0, 0.0], &TraceOptions::new(lambda), &mut || 0.5)
                .unwrap();
            assert!(
                (sample.throughput - expected).abs() < 1e-14,
                "{name}: {} vs {expected}",
                sample.throughput
            );
            // Unpolarised in, unpolarised out on the axis.
            let out = mueller_apply(&sample.mueller, [1.0, 0.0, 0.0, 0.0]);
            assert!(degree_of_linear_polarization(out) < 1e-14);
            if lambda == LAMBDA_D_NM {
                println!("{name}: on-axis transmission at d {expected:.4}");
            }
            let lossless = TraceOptions { fresnel: false, ..TraceOptions::new(lambda) };
            assert_eq!(
                tracer.trace_from_sensor([0.0, 0.0], [0.0, 0.0], &lossless, &mut || 0.5).unwrap().throughput,
                1.0
            );
        }
    }
}

/// A plane-parallel plate of index `n`, 5 mm thick, 20 mm in front of the sensor.
fn plate(n: f64) -> LensSystem {
    system(vec![
        surface(0.0, 5.0, Medium::constant(n), 100.0, true),
        surface(0.0, 20.0, Medium::Air, 100.0, false),
    ])
}

/// Hecht's angle forms (§4.6.3) of the power coefficients entering glass of index n at θi.
fn hecht_power(theta_i: f64, n: f64) -> (f64, f64) {
    let theta_t = (theta_i.sin() / n).asin();
    let r_s = -(theta_i - theta_t).sin() / (theta_i + theta_t).sin();
    let r_p = (theta_i - theta_t).tan() / (theta_i + theta_t).tan();
    (r_s * r_s, r_p * r_p)
}

#[test]
fn a_tilted_plate_polarises_unpolarised_light_as_fresnel_says() {
    // Through a plate at θ both surfaces transmit T_s = 1 − R_s and T_p = 1 − R_p (the inner
    // angle is the same, and T is reciprocal): unpolarised light leaves with
    // S0 = (T_s² + T_p²)/2 and DoLP = |T_s² − T_p²|/(T_s² + T_p²), polarised along p (s is
    // reflected more). In the sensor's frame (x = d × up, up = +y) a ray tilted in x–z has x
    // along p, in the plane of incidence (S1 = (T_p² − T_s²)/2 > 0), one tilted in y–z has x
    // along s (S1 = (T_s² − T_p²)/2 < 0). 1e-13: f64 rounding.
    let n = 1.5;
    let lens = plate(n);
    let tracer = LensTracer::new(lens.clone());
    for degrees in [10.0_f64, 30.0, 56.31, 70.0] {
        let theta = degrees.to_radians();
        let (reflectance_s, reflectance_p) = hecht_power(theta, n);
        let (t_s, t_p) = (1.0 - reflectance_s, 1.0 - reflectance_p);
        let s0 = 0.5 * (t_s * t_s + t_p * t_p);
        let dolp = (t_s * t_s - t_p * t_p) / (t_s * t_s + t_p * t_p);
        let offset = 20.0 * theta.tan();
        for (target, sign) in [([-offset, 0.0], -1.0), ([0.0, -offset], 1.0)] {
            let sample = tracer
                .trace_from_sensor([0.0, 0.0], target, &TraceOptions::new(LAMBDA_D_NM), &mut || 0.5)
                .unwrap();
            let out = mueller_apply(&sample.mueller, [1.0, 0.0, 0.0, 0.0]);
            let context = format!("{degrees}°, target {target:?}: {out:?} vs S0 {s0}, DoLP {dolp}");
            assert!((out[0] - s0).abs() < 1e-13, "{context}");
            assert!((degree_of_linear_polarization(out) - dolp.abs()).abs() < 1e-13, "{context}");
            assert!((out[1] - sign * dolp * s0).abs() < 1e-13 && out[2].abs() < 1e-13, "{context}");
            assert!(out[3].abs() < 1e-13, "{context}");
            // The plate displaces the ray but keeps its direction.
            let sensor_dir = (DVec3::new(target[0], target[1], -20.0)).normalize();
            assert!((sample.dir - sensor_dir).length() < 1e-14);
        }
    }
}

#[test]
fn the_ghost_estimator_sums_the_reflected_paths() {
    // A plate of index n at incidence θ: the transmitted path carries T_s², T_p²; the path
    // with two reflections inside (back face, then front face) T² R², and so on: with a budget
    // of 2k reflections the expected Mueller (0,0) entry is ½ Σ_{s,p} T²(1 + R² + … + R^{2k}).
    // Paths that reflect once end on the sensor. The estimator (module `lens::trace`) draws
    // reflection with probability R; its mean over 400 000 seeded samples must agree within
    // 4.5 standard errors.
    let n = 3.0;
    let lens = plate(n);
    let tracer = LensTracer::new(lens.clone());
    let mut rng = Pcg64::seed_from_u64(40);
    for degrees in [0.0_f64, 40.0] {
        let theta = degrees.to_radians();
        let (rs, rp) = hecht_power(theta.max(1e-9), n);
        let target = [-20.0 * theta.tan(), 0.0];
        for budget in [0_u32, 2, 4] {
            let series = |r: f64| (0..=budget / 2).map(|k| r.powi(2 * k as i32)).sum::<f64>();
            let expected = 0.5 * ((1.0 - rs).powi(2) * series(rs) + (1.0 - rp).powi(2) * series(rp));
            let options = TraceOptions { max_ghost_reflections: budget, ..TraceOptions::new(LAMBDA_D_NM) };
            let weights: Vec<f64> = (0..400_000)
                .map(|_| {
                    tracer
                        .trace_from_sensor([0.0, 0.0], target, &options, &mut || uniform(&mut rng))
                        .map_or(0.0, |sample| sample.throughput)
                })
                .collect();
            let (mean, error) = mean_and_error(&weights);
            let context = format!("θ {degrees}°, budget {budget}: {mean} ± {error} vs {expected}");
            if budget == 0 {
                assert!((mean - expected).abs() < 1e-10, "{context}"); // rounding of the 400 000-term sum
            } else {
                assert!((mean - expected).abs() < 4.5 * error, "{context}");
                // The ghosts' share is resolved: the test would see them missing.
                let without = 0.5 * ((1.0 - rs).powi(2) + (1.0 - rp).powi(2));
                assert!((mean - without).abs() > 10.0 * error, "{context}");
            }
        }
    }
}

/// The sensor irradiance estimate (in units of the normalisation) at `sensor` from `samples`
/// camera rays drawn by `draw`, Fresnel off; and the share of rays that pass.
fn irradiance(
    tracer: &LensTracer,
    normalisation: &Normalisation,
    sensor: [f64; 2],
    samples: usize,
    rng: &mut Pcg64,
    draw: &dyn Fn([f64; 2], [f64; 2]) -> Option<PupilSample>,
) -> (f64, f64, f64) {
    let options = TraceOptions { fresnel: false, ..TraceOptions::new(LAMBDA_D_NM) };
    let mut passed = 0;
    let weights: Vec<f64> = (0..samples)
        .map(|_| {
            let u = [uniform(rng), uniform(rng)];
            let Some(pupil) = draw(sensor, u) else { return 0.0 };
            match tracer.trace_from_sensor(sensor, pupil.target_mm, &options, &mut || 0.5) {
                Some(sample) => {
                    passed += 1;
                    normalisation.sensor_weight(sensor, &pupil) * sample.throughput
                }
                None => 0.0,
            }
        })
        .collect();
    let (mean, error) = mean_and_error(&weights);
    (mean, error, passed as f64 / samples as f64)
}

#[test]
fn exit_pupil_bounds_sample_the_same_irradiance_as_the_rear_disc_with_fewer_misses() {
    // Both samplers are unbiased estimators of the same integral (module `lens::pupil`), so
    // their irradiances agree within noise (4.5 combined standard errors); at the centre an
    // ideal lossless lens reads 1 by the normalisation's definition. The shares of rays that
    // pass are printed (run with --nocapture).
    let cases =
        [("singlet", singlet(), 10.0), ("doublet", doublet(), 12.0), ("double Gauss", double_gauss(), 21.6)];
    let mut rng = Pcg64::seed_from_u64(4040);
    for (name, lens, half_diagonal) in cases {
        let tracer = LensTracer::new(lens.clone());
        let normalisation = Normalisation::measure(&tracer, LAMBDA_D_NM);
        let disc = RearDisc::new(&tracer);
        let bounds = ExitPupilBounds::measure(&tracer, half_diagonal, 16, 64);
        for fraction in [0.0, 0.5, 1.0] {
            let sensor = [fraction * half_diagonal * 0.6, fraction * half_diagonal * 0.8];
            let (e_disc, err_disc, share_disc) =
                irradiance(&tracer, &normalisation, sensor, 40_000, &mut rng, &|p, u| {
                    Some(disc.sample(p, u))
                });
            let (e_bounds, err_bounds, share_bounds) =
                irradiance(&tracer, &normalisation, sensor, 40_000, &mut rng, &|p, u| bounds.sample(p, u));
            println!(
                "{name} at {fraction} of the half-diagonal: pass {:.1}% (rear disc) vs {:.1}% (exit-pupil bounds); \
                 E/K {e_disc:.4} ± {err_disc:.4} vs {e_bounds:.4} ± {err_bounds:.4}",
                100.0 * share_disc,
                100.0 * share_bounds
            );
            let combined = err_disc.hypot(err_bounds);
            assert!((e_disc - e_bounds).abs() < 4.5 * combined, "{name} at {fraction}");
            if fraction == 0.0 {
                assert!((e_bounds - 1.0).abs() < 4.5 * err_bounds, "{name}: centre reads {e_bounds}");
            }
            // Off axis the double Gauss vignettes, and aiming at the rear disc wastes most rays.
            if name == "double Gauss" && fraction > 0.0 {
                assert!(share_bounds > share_disc + 0.1, "{name} at {fraction}");
            }
        }
    }
}

/// The irradiance at distance h off axis on a plane parallel to a Lambertian disc of radius a
/// at distance d, in units of L (Moon 1936; Hecht-free closed form of the configuration
/// factor): E = (π/2)[1 − (h² + d² − a²)/√((h² + d² + a²)² − 4a²h²)].
fn disc_irradiance(h: f64, d: f64, a: f64) -> f64 {
    let sum = h * h + d * d;
    0.5 * std::f64::consts::PI * (1.0 - (sum - a * a) / ((sum + a * a).powi(2) - 4.0 * a * a * h * h).sqrt())
}

#[test]
fn a_lens_of_index_one_images_like_a_pinhole_at_its_stop() {
    // With every index 1 the rays go straight: the entrance pupil is the stop itself, each ray
    // leaves the lens along the line from the sensor point through its crossing of the stop
    // (inside the stop), and with a small stop every ray leaves toward the pinhole's direction
    // within a/distance. The image is then that of a pinhole camera: irradiance from a uniform
    // sky is the disc's configuration factor (cos⁴ for small stops), normalised to 1 at the
    // centre.
    let mut lens = double_gauss();
    for s in &mut lens.surfaces {
        s.medium = Medium::Air;
    }
    let stop = lens.stop_index().unwrap();
    let a = 1.0;
    lens.surfaces[stop].semi_diameter_mm = a;
    lens.surfaces.last_mut().unwrap().thickness_mm = 40.0;
    let tracer = LensTracer::new(lens.clone());
    let p = lens.paraxial(LAMBDA_D_NM);
    assert!(p.is_err(), "an index-1 lens has no power: {p:?}");
    let stop_z = tracer.vertex_z_mm[stop];
    let d = tracer.image_z_mm() - stop_z;
    let normalisation = Normalisation::measure(&tracer, LAMBDA_D_NM);
    // K = π sin²α for the cone on the stop: π a²/(a² + d²), to the bisection's 1e-12.
    let cone = std::f64::consts::PI * a * a / (a * a + d * d);
    assert!((normalisation.projected_solid_angle_sr / cone - 1.0).abs() < 1e-9);
    let bounds = ExitPupilBounds::measure(&tracer, 15.0, 8, 64);
    let mut rng = Pcg64::seed_from_u64(1);
    for sensor in [[0.0, 0.0], [5.0, 3.0], [-9.0, -7.0]] {
        let origin = DVec3::new(sensor[0], sensor[1], tracer.image_z_mm());
        let pinhole = (DVec3::new(0.0, 0.0, stop_z) - origin).normalize();
        let mut passed = 0;
        for _ in 0..2000 {
            let Some(pupil) = bounds.sample(sensor, [uniform(&mut rng), uniform(&mut rng)]) else { continue };
            let Some(sample) = tracer.trace_from_sensor(
                sensor,
                pupil.target_mm,
                &TraceOptions::new(LAMBDA_D_NM),
                &mut || 0.5,
            ) else {
                continue;
            };
            passed += 1;
            let s = (stop_z - origin.z) / sample.dir.z;
            let crossing = origin + s * sample.dir;
            assert!(crossing.x.hypot(crossing.y) <= a * (1.0 + 1e-12), "{crossing}");
            let target = DVec3::new(pupil.target_mm[0], pupil.target_mm[1], tracer.rear_vertex_z_mm());
            assert!((sample.dir - (target - origin).normalize()).length() < 1e-14, "straight on");
            assert!(sample.dir.angle_between(pinhole) <= (a / (origin.z - stop_z)).asin() * (1.0 + 1e-9));
            assert_eq!(sample.throughput, 1.0);
            let identity =
                [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];
            for (row, want) in sample.mueller.iter().zip(identity) {
                for (got, want) in row.iter().zip(want) {
                    assert!((got - want).abs() < 1e-14, "{:?}", sample.mueller);
                }
            }
        }
        assert!(passed > 500, "{passed}");
        let h = sensor[0].hypot(sensor[1]);
        let expected = disc_irradiance(h, d, a) / disc_irradiance(0.0, d, a);
        let (mean, error, _) =
            irradiance(&tracer, &normalisation, sensor, 40_000, &mut rng, &|p, u| bounds.sample(p, u));
        assert!((mean - expected).abs() < 4.5 * error, "h {h}: {mean} ± {error} vs {expected}");
        let cos_theta = d / (h * h + d * d).sqrt();
        println!(
            "pinhole at h = {h:.2} mm: E/E0 {mean:.4} ± {error:.4}, disc formula {expected:.4}, cos⁴ {:.4}",
            cos_theta.powi(4)
        );
    }
}

#[test]
fn total_internal_reflection_blocks_the_transmitted_branch() {
    // From glass of index 1.5 toward air, sin θc = 1/1.5 (θc = 41.81°): a ray at 45° cannot
    // leave; at 40° it leaves at asin(1.5 sin 40°) = 74.62° (Snell).
    let lens = system(vec![surface(0.0, 20.0, Medium::constant(1.5), 100.0, true)]);
    let tracer = LensTracer::new(lens.clone());
    let from_sensor = |degrees: f64| {
        let theta = degrees.to_radians();
        Ray { origin: DVec3::new(0.0, 0.0, 20.0), dir: DVec3::new(theta.sin(), 0.0, -theta.cos()) }
    };
    assert_eq!(
        tracer.trace_to_object(from_sensor(45.0), LAMBDA_D_NM),
        Err(prisma::lens::Blocked::TotalInternalReflection(0))
    );
    let out = tracer.trace_to_object(from_sensor(40.0), LAMBDA_D_NM).unwrap();
    let expected = (1.5 * 40f64.to_radians().sin()).asin();
    assert!((out.ray.dir.x.asin() - expected).abs() < 1e-14, "{:?}", out.ray);
    // Under total internal reflection R = 1: a ghost budget makes the ray reflect, back to the
    // sensor (no scene light), with no random number deciding it otherwise.
    let options = TraceOptions { max_ghost_reflections: 2, ..TraceOptions::new(LAMBDA_D_NM) };
    let target = [-20.0 * 45f64.to_radians().tan(), 0.0];
    assert!(tracer.trace_from_sensor([0.0, 0.0], target, &options, &mut || 0.999_999).is_none());
}

#[test]
fn an_uncoated_lens_reads_darker_than_its_lossless_twin_by_its_transmission() {
    // The camera's sampler: at the image centre a uniform radiance 1 reads 1 through the ideal
    // lossless lens (the normalisation) and the Fresnel-weighted transmission averaged over the
    // pupil through the uncoated lens: between the on-axis Π(1 − R) (normal incidence, the
    // least loss) and ~1% below it (the marginal rays of an f/2 lens meet the surfaces at up
    // to ~30°, where R grows by a few tenths of a percent per surface). 4.5 standard errors.
    let lens = double_gauss();
    let sampler = prisma::lens::SensorSampler::new(lens.clone(), 21.6, LAMBDA_D_NM);
    let on_axis = sampler
        .tracer
        .trace_from_sensor([0.0, 0.0], [0.0, 0.0], &TraceOptions::new(LAMBDA_D_NM), &mut || 0.5)
        .unwrap()
        .throughput;
    let mut rng = Pcg64::seed_from_u64(11);
    for (fresnel, low, high) in [(false, 1.0, 1.0), (true, on_axis * 0.99, on_axis)] {
        let options = TraceOptions { fresnel, ..TraceOptions::new(LAMBDA_D_NM) };
        let weights: Vec<f64> = (0..40_000)
            .map(|_| {
                let u = [uniform(&mut rng), uniform(&mut rng)];
                sampler.sample([0.0, 0.0], u, &options, &mut || 0.5).map_or(0.0, |ray| {
                    assert_eq!(ray.weight, ray.sensor_weight * ray.sample.throughput);
                    ray.weight
                })
            })
            .collect();
        let (mean, error) = mean_and_error(&weights);
        println!("double Gauss centre, Fresnel {fresnel}: reads {mean:.4} ± {error:.4} (on-axis Π(1 − R) {on_axis:.4})");
        assert!(mean > low - 4.5 * error && mean < high + 4.5 * error, "Fresnel {fresnel}: {mean} ± {error}");
    }
}
