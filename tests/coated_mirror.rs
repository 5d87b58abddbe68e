//! Coated metal mirrors and absorbing coating layers in renders (issue 41), pixel by pixel and
//! in all four Stokes parameters: a coated plane (normal +y) seen at 550 nm against a uniform
//! one-sided emitter of radiance L that fills every reflected direction, optionally through an
//! ideal linear polariser sheet at 45° to the central plane of incidence (so that the coating's
//! phase difference between s and p turns the light elliptical and S3 shows its sign).
//!
//! The expected Stokes vector of each pixel is the mean over an 8 × 8 grid of directions in
//! the pixel of what the electric-field tracer `prisma::validate::field` (world-space complex
//! fields, the opposite time convention, no Stokes frames or Mueller matrices) makes of the
//! path emitter → sheet → coated surface → camera, with the coated surface's r_s, r_p from the
//! transfer-matrix stack `prisma::optics::thin_film_amplitudes` at that direction's angle
//! (itself checked against the `tmm` package in tests/thin_film_fixtures.rs; the
//! `coated_reflection` validation case, run here too, uses tmm's amplitudes directly).
//!
//! Faults that must fail: the layers' phase dropped, s and p swapped, the phase's sign flipped.

use std::path::Path;

use glam::DVec3;
use num_complex::Complex64;
use prisma::integrator::Fault;
use prisma::optics::{metals, thin_film_amplitudes, Layer};
use prisma::render::{render, Job};
use prisma::validate::field::{self, Element};

const RADIANCE: f64 = 2.0;
const LAMBDA_NM: f64 = 550.0;
const SIZE: u32 = 16;
const FOV_DEG: f64 = 20.0;
const DISTANCE: f64 = 10.0;
/// Largest error of S0 relative to the expected and of each S_k/S0 (k = 1..3) in absolute
/// terms, per pixel. The pixels are means of 64 stratified samples of smooth functions of the
/// angle (a pixel spans 1.25°) compared with 8 × 8 midpoint means: tests/coated_render.rs
/// measured 2.4·10⁻⁴ for that integration error on dielectric stacks; the f32 transport adds
/// ~10⁻⁶.
const TOLERANCE: f64 = 1e-3;

/// The polariser's axis, horizontal at 45° to the central plane of incidence (the yz plane).
fn polarizer_axis() -> DVec3 {
    DVec3::new(1.0, 0.0, 1.0).normalize()
}

/// A coated surface: the scene's material body and the stack the reference evaluates.
struct Surface {
    material: String,
    /// Layers from the air side, n + ik and nm.
    layers: Vec<Layer>,
    substrate: Complex64,
}

/// 100 nm of SiO₂ on gold of constant index 0.18 + 3.43i (the tmm fixture's stack).
fn silica_on_gold() -> Surface {
    Surface {
        material:
            "type = \"mirror\"\ncomplex_ior = [0.18, 3.43]\ncoating = [{ ior = 1.46, thickness_nm = 100 }]"
                .into(),
        layers: vec![Layer::dielectric(1.46, 100.0)],
        substrate: Complex64::new(0.18, 3.43),
    }
}

/// Tabulated silver under MgF₂ and TiO₂-like layers (a protected, enhanced mirror).
fn enhanced_silver() -> Surface {
    let silver = metals::metal("silver").expect("silver is in the catalogue").eta(LAMBDA_NM as f32);
    Surface {
        material: "type = \"mirror\"\nmetal = \"silver\"\n\
                   coating = [{ ior = 2.3, thickness_nm = 60 }, { ior = 1.38, thickness_nm = 99.6 }]"
            .into(),
        layers: vec![Layer::dielectric(2.3, 60.0), Layer::dielectric(1.38, 99.6)],
        substrate: Complex64::new(f64::from(silver.re), f64::from(silver.im)),
    }
}

/// Glass (n = 1.5) under an absorbing layer: 12 nm of tabulated gold, then 80 nm of SiO₂
/// (a metal-dielectric beam splitter coating; the transmitted light leaves the picture).
fn gold_film_on_glass() -> Surface {
    let gold = metals::metal("gold").expect("gold is in the catalogue").eta(LAMBDA_NM as f32);
    Surface {
        material: "type = \"dielectric\"\nior = 1.5\n\
                   coating = [{ ior = 1.46, thickness_nm = 80 }, { metal = \"gold\", thickness_nm = 12 }]"
            .into(),
        layers: vec![
            Layer::dielectric(1.46, 80.0),
            Layer { index: Complex64::new(f64::from(gold.re), f64::from(gold.im)), thickness_nm: 12.0 },
        ],
        substrate: Complex64::new(1.5, 0.0),
    }
}

/// A constant complex layer index on a plain glass (n + ik = 2.0 + 0.5i, 30 nm).
fn lossy_layer_on_glass() -> Surface {
    Surface {
        material:
            "type = \"dielectric\"\nior = 1.5\ncoating = [{ complex_ior = [2.0, 0.5], thickness_nm = 30 }]"
                .into(),
        layers: vec![Layer { index: Complex64::new(2.0, 0.5), thickness_nm: 30.0 }],
        substrate: Complex64::new(1.5, 0.0),
    }
}

fn camera_position(theta_deg: f64) -> DVec3 {
    let (sin, cos) = theta_deg.to_radians().sin_cos();
    DVec3::new(0.0, DISTANCE * cos, -DISTANCE * sin)
}

fn scene_text(surface: &Surface, theta_deg: f64, polarized: bool, sheet: bool) -> String {
    let position = camera_position(theta_deg);
    let sheet_text = if sheet {
        let axis = polarizer_axis();
        format!(
            "[materials.sheet]\ntype = \"polarizer\"\naxis = [{}, {}, {}]\n\
             [[shapes]]\ntype = \"quad\"\ncorner = [-5000, 30, -5000]\nedge1 = [10000, 0, 0]\nedge2 = [0, 0, 10000]\nmaterial = \"sheet\"\n",
            axis.x, axis.y, axis.z
        )
    } else {
        String::new()
    };
    format!(
        "background = 0\n\
         [camera]\nposition = [{}, {}, {}]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_y_deg = {FOV_DEG}\n\
         width = {SIZE}\nheight = {SIZE}\n\
         [render]\nspp = 64\nmax_depth = 4\nprune_below = 0\npolarized = {polarized}\n\
         [materials.coated]\n{}\n\
         [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"coated\"\n{sheet_text}\
         [[lights]]\ntype = \"quad\"\ncorner = [-5000, 60, -5000]\nedge1 = [10000, 0, 0]\n\
         edge2 = [0, 0, 10000]\nradiance = {RADIANCE}\nemit = \"edge1_cross_edge2\"\n",
        position.x, position.y, position.z, surface.material,
    )
}

/// The camera's axes as `prisma::camera::Camera` builds them: forward, right = forward × up
/// (normalised), up' = right × forward.
fn camera_axes(theta_deg: f64) -> (DVec3, DVec3, DVec3) {
    let forward = (-camera_position(theta_deg)).normalize();
    let right = forward.cross(DVec3::Y).normalize();
    let up = right.cross(forward);
    (forward, right, up)
}

/// The expected Stokes vector of the light arriving along camera direction `dir`.
fn expected_along(surface: &Surface, dir: DVec3, up: DVec3, sheet: bool) -> [f64; 4] {
    let cos_theta = -dir.y;
    let stack = thin_film_amplitudes(1.0, &surface.layers, surface.substrate, LAMBDA_NM, cos_theta);
    // The field tracer writes fields e^{i(k·r − ωt)}: the conjugates of prisma's amplitudes.
    let coated = Element::Amplitudes { normal: DVec3::Y, r_s: stack.r_s.conj(), r_p: stack.r_p.conj() };
    let reflected = dir - 2.0 * dir.dot(DVec3::Y) * DVec3::Y;
    let mut elements = Vec::new();
    if sheet {
        elements.push(Element::Polarizer { normal: DVec3::Y, axis: polarizer_axis() });
    }
    elements.push(coated);
    field::unpolarized_through(RADIANCE, -reflected, &elements, |k: DVec3| (-k).cross(up).normalize())
}

/// The per-pixel means of the expected Stokes vector over an 8 × 8 midpoint grid.
fn expected(surface: &Surface, theta_deg: f64, sheet: bool) -> Vec<[f64; 4]> {
    let (forward, right, up) = camera_axes(theta_deg);
    let tan_half = (FOV_DEG.to_radians() / 2.0).tan();
    let n = 8;
    (0..SIZE * SIZE)
        .map(|i| {
            let (x0, y0) = (f64::from(i % SIZE), f64::from(i / SIZE));
            let mut mean = [0.0; 4];
            for k in 0..n * n {
                let x = x0 + (f64::from(k % n) + 0.5) / f64::from(n);
                let y = y0 + (f64::from(k / n) + 0.5) / f64::from(n);
                let ndc_x = 2.0 * x / f64::from(SIZE) - 1.0;
                let ndc_y = 1.0 - 2.0 * y / f64::from(SIZE);
                let dir = (forward + ndc_x * tan_half * right + ndc_y * tan_half * up).normalize();
                let stokes = expected_along(surface, dir, up, sheet);
                for (m, s) in mean.iter_mut().zip(stokes) {
                    *m += s / f64::from(n * n);
                }
            }
            mean
        })
        .collect()
}

/// The rendered Stokes vectors per pixel (S1–S3 zero when unpolarised).
fn rendered(
    surface: &Surface,
    theta_deg: f64,
    polarized: bool,
    sheet: bool,
    fault: Option<Fault>,
) -> Vec<[f64; 4]> {
    let text = scene_text(surface, theta_deg, polarized, sheet);
    let scene = prisma::scene::parse(&text, Path::new("<coated_mirror>")).expect("the scene loads");
    let job = Job {
        threads: 2,
        monochromatic_nm: Some(LAMBDA_NM as f32),
        fault,
        ..Job::new(scene.settings.clone())
    };
    let film = render(&scene, &job).expect("the render succeeds").0;
    let planes: Vec<Vec<f64>> = (0..4)
        .map(|k| match film.stokes_xyz(k) {
            Some(pixels) => pixels.iter().map(|p| f64::from(p.y)).collect(),
            None => vec![0.0; (SIZE * SIZE) as usize],
        })
        .collect();
    (0..(SIZE * SIZE) as usize).map(|i| [planes[0][i], planes[1][i], planes[2][i], planes[3][i]]).collect()
}

/// The worst error per pixel: |S0/S0' − 1| and |S_k/S0 − S_k'/S0'| (k = 1..3, when polarised).
fn worst(seen: &[[f64; 4]], expected: &[[f64; 4]], polarized: bool) -> (f64, f64) {
    let mut worst_s0 = 0.0_f64;
    let mut worst_ratio = 0.0_f64;
    for (s, e) in seen.iter().zip(expected) {
        worst_s0 = worst_s0.max((s[0] / e[0] - 1.0).abs());
        if polarized {
            for k in 1..4 {
                worst_ratio = worst_ratio.max((s[k] / s[0] - e[k] / e[0]).abs());
            }
        }
    }
    (worst_s0, worst_ratio)
}

/// Every surface at 40° and 75°, polarised (S0–S3) with and without the sheet, and unpolarised
/// without it (S0 = (R_s + R_p)/2·L; with the sheet an unpolarised render is an approximation:
/// the sheet's axis is at 45° to the plane of incidence only in the central column).
#[test]
fn coated_surfaces_reflect_the_stack_per_pixel_in_all_four_stokes_parameters() {
    for (name, surface) in [
        ("SiO₂ on gold", silica_on_gold()),
        ("enhanced silver", enhanced_silver()),
        ("gold film on glass", gold_film_on_glass()),
        ("lossy layer on glass", lossy_layer_on_glass()),
    ] {
        for theta_deg in [40.0, 75.0] {
            for sheet in [false, true] {
                let reference = expected(&surface, theta_deg, sheet);
                if sheet {
                    // The case has teeth: the coating turns the light elliptical.
                    let circular = reference.iter().map(|e| (e[3] / e[0]).abs()).fold(0.0, f64::max);
                    eprintln!("{name} {theta_deg}°: |S3/S0| up to {circular:.3}");
                }
                let modes: &[bool] = if sheet { &[true] } else { &[false, true] };
                for &polarized in modes {
                    let seen = rendered(&surface, theta_deg, polarized, sheet, None);
                    let (s0, ratio) = worst(&seen, &reference, polarized);
                    eprintln!(
                        "{name} {theta_deg}° sheet={sheet} polarized={polarized}: S0 {s0:.2e}, S_k/S0 {ratio:.2e}"
                    );
                    assert!(s0 < TOLERANCE, "{name} {theta_deg}° sheet={sheet}: S0 off by {s0:.3e}");
                    assert!(
                        ratio < TOLERANCE,
                        "{name} {theta_deg}° sheet={sheet}: S_k/S0 off by {ratio:.3e}"
                    );
                }
            }
        }
    }
}

/// The sign of S3: through the sheet, 100 nm of SiO₂ on gold turns light at 45° elliptical of
/// one handedness below about 52° and of the other above (tmm's Δ at 550 nm passes through
/// ±180° there: −178.9° at 40°, +156.7° at 75°, tests/fixtures/thin_film_sio2_on_gold.csv);
/// the rendered S3 has the field tracer's sign at every pixel on both sides.
#[test]
fn the_sign_of_s3_from_a_coating_is_the_field_tracers() {
    let surface = silica_on_gold();
    let mut signs = Vec::new();
    for (theta_deg, at_least) in [(40.0, 0.01), (75.0, 0.1)] {
        let reference = expected(&surface, theta_deg, true);
        let seen = rendered(&surface, theta_deg, true, true, None);
        // Wherever |S3/S0| is ten times the worst S_k/S0 error measured (~10⁻⁴), the signs
        // agree; in at least half of the pixels it is at least `at_least`.
        let mut elliptical = 0;
        for (s, e) in seen.iter().zip(&reference) {
            if (e[3] / e[0]).abs() > 1e-3 {
                assert_eq!(s[3].signum(), e[3].signum(), "{theta_deg}°: S3 {s:?} against {e:?}");
            }
            elliptical += usize::from((e[3] / e[0]).abs() > at_least);
        }
        assert!(2 * elliptical >= reference.len(), "{theta_deg}°: {elliptical} elliptical pixels");
        let centre = reference[(SIZE / 2 * SIZE + SIZE / 2) as usize];
        signs.push(centre[3].signum());
    }
    assert_ne!(signs[0], signs[1], "the handedness must change between 40° and 75°");
}

/// Each fault moves some pixel far beyond the tolerance.
#[test]
fn coating_faults_fail_the_comparison() {
    let surface = silica_on_gold();
    let reference = expected(&surface, 75.0, true);
    for fault in [Fault::CoatingPhaseDropped, Fault::CoatingSpSwapped, Fault::FlippedPhase] {
        let seen = rendered(&surface, 75.0, true, true, Some(fault));
        let (s0, ratio) = worst(&seen, &reference, true);
        eprintln!("{fault:?}: S0 {s0:.2e}, S_k/S0 {ratio:.2e}");
        assert!(s0.max(ratio) > 50.0 * TOLERANCE, "{fault:?} is only {s0:.3e} / {ratio:.3e} away");
    }
}

/// `prisma validate`'s `coated_reflection` (tmm's amplitudes, not prisma's stack) passes, and
/// fails under each coating fault and under the flipped phase.
#[test]
fn the_coated_validation_case_passes_and_catches_the_faults() {
    let passes = |fault: Option<Fault>| {
        let result = prisma::validate::analytic::run("coated_reflection", 2, fault).expect("the case runs");
        for check in &result.checks {
            eprintln!("{fault:?}: {} = {:.3e} (≤ {:.0e})", check.metric, check.value, check.threshold);
        }
        result.passed()
    };
    assert!(passes(None));
    for fault in
        [Fault::CoatingPhaseDropped, Fault::CoatingSpSwapped, Fault::FlippedPhase, Fault::Unpolarized]
    {
        assert!(!passes(Some(fault)), "{fault:?} was not caught");
    }
}

/// Bad coatings on mirrors and bad absorbing layers are one-line load errors naming the field.
#[test]
fn bad_metal_coatings_are_rejected() {
    let scene = |material: &str| {
        format!(
            "[camera]\nposition = [0, 1, -5]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\nwidth = 4\nheight = 4\n\
             [materials.coated]\n{material}\n\
             [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"coated\"\n"
        )
    };
    let layer = |body: &str| format!("type = \"mirror\"\nmetal = \"gold\"\ncoating = [{{ {body} }}]");
    for (material, expected) in [
        (
            "type = \"mirror\"\ncoating = [{ ior = 1.38, thickness_nm = 100 }]".to_string(),
            "materials.coated.coating",
        ),
        (layer("metal = \"unobtainium\", thickness_nm = 10"), "materials.coated.coating[0].metal"),
        (layer("complex_ior = [0.2, -1], thickness_nm = 10"), "materials.coated.coating[0].complex_ior"),
        (layer("complex_ior = [0, 3], thickness_nm = 10"), "materials.coated.coating[0].complex_ior"),
        (layer("ior = 1.4, metal = \"gold\", thickness_nm = 10"), "materials.coated.coating[0]"),
        (layer("thickness_nm = 10"), "materials.coated.coating[0]"),
        (layer("metal = \"silver\", thickness_nm = -1"), "materials.coated.coating[0].thickness_nm"),
        (
            "type = \"dielectric\"\nior = 1.5\ncoating = [{ metal = \"au\", thickness_nm = 2e5 }]"
                .to_string(),
            "materials.coated.coating[0].thickness_nm",
        ),
    ] {
        let error = match prisma::scene::parse(&scene(&material), Path::new("bad.toml")) {
            Ok(_) => panic!("accepted: {material}"),
            Err(error) => error.to_string(),
        };
        assert!(error.contains(expected) && !error.contains('\n'), "{material}: {error}");
    }
    // The chemical symbol names a metal too, in a layer as in a mirror.
    let good = scene("type = \"dielectric\"\nior = 1.5\ncoating = [{ metal = \"Au\", thickness_nm = 10 }]");
    assert!(prisma::scene::parse(&good, Path::new("good.toml")).is_ok());
}
