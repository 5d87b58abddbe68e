//! A coated interface in a render reflects exactly what the transfer-matrix stack of
//! `prisma::optics::thin_film` says (issue 41): a glass half-space (n = 1.5, the plane's
//! outside up) with a coating, seen at 550 nm against a uniform one-sided emitter of radiance L
//! that fills every reflected direction, with nothing behind the glass (black background, and
//! the refracted branch never returns), so each pixel sees R(θ)·L with θ its own angle of
//! incidence. Checked from the outside (layers in the given order, vacuum → glass) and from the
//! inside (camera and emitter in the glass: the stack reversed, including total internal
//! reflection, R = 1 through a lossless stack), unpolarised and polarised (S0 = R·L and, for
//! unpolarised light in, a linear polarisation √(S1² + S2²) = |R_s − R_p|/2·L, S3 = 0).
//!
//! Faults that must fail: the coating dropped (bare Fresnel), the layer's phase dropped (the
//! two faces' reflectances added incoherently), the layers taken in the wrong order.

use std::path::Path;

use num_complex::Complex64;
use prisma::optics::{thin_film_amplitudes, Layer};
use prisma::render::{render, Job};

const GLASS: f64 = 1.5;
const RADIANCE: f64 = 2.0;
const LAMBDA_NM: f64 = 550.0;
const SIZE: u32 = 24;
const FOV_DEG: f64 = 20.0;
const DISTANCE: f64 = 10.0;
/// Largest accepted relative error of S0 per pixel: the pixel means come from 64 stratified
/// samples of a smooth R(θ) (a pixel spans 0.83°), compared with an 8 × 8 midpoint mean; the
/// worst pixel measured is 2.4·10⁻⁴ off (inside at 25°, where R steepens towards the critical
/// angle), and it falls with the sample count (2.3·10⁻³ at 16 samples and 4 × 4 points), so
/// the error is the pixel integration's, not the physics'.
const TOLERANCE: f64 = 1e-3;

/// A quarter-wave MgF₂ layer at 550 nm (R = 1.3 % against 4 % bare at normal incidence).
const QUARTER_WAVE: &[(f64, f64)] = &[(1.38, 550.0 / (4.0 * 1.38))];
/// Two layers whose order matters (an asymmetric stack): MgF₂ outside, a high index under it.
const TWO_LAYERS: &[(f64, f64)] = &[(1.38, 99.64), (2.1, 65.5)];

/// Which side of the coated plane (normal +y, glass below) the camera and the emitter are on.
#[derive(Clone, Copy, Debug)]
enum Side {
    Outside,
    Inside,
}

impl Side {
    fn sign(self) -> f64 {
        match self {
            Side::Outside => 1.0,
            Side::Inside => -1.0,
        }
    }
}

fn scene_text(layers: &[(f64, f64)], side: Side, theta_deg: f64, polarized: bool) -> String {
    let (sin, cos) = theta_deg.to_radians().sin_cos();
    let coating = layers
        .iter()
        .map(|(n, d)| format!("{{ ior = {n}, thickness_nm = {d} }}"))
        .collect::<Vec<_>>()
        .join(", ");
    // The emitter: a quad 60 units from the plane on the camera's side, facing the plane.
    let (emitter_y, emit) = match side {
        Side::Outside => (60.0, "edge1_cross_edge2"),
        Side::Inside => (-60.0, "edge2_cross_edge1"),
    };
    format!(
        "background = 0\n\
         [camera]\nposition = [0, {py}, {pz}]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_y_deg = {FOV_DEG}\n\
         width = {SIZE}\nheight = {SIZE}\n\
         [render]\nspp = 64\nmax_depth = 4\npolarized = {polarized}\n\
         [materials.coated]\ntype = \"dielectric\"\nior = {GLASS}\ncoating = [{coating}]\n\
         [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"coated\"\n\
         [[lights]]\ntype = \"quad\"\ncorner = [-5000, {emitter_y}, -5000]\nedge1 = [10000, 0, 0]\n\
         edge2 = [0, 0, 10000]\nradiance = {RADIANCE}\nemit = \"{emit}\"\n",
        py = side.sign() * DISTANCE * cos,
        pz = -DISTANCE * sin,
    )
}

/// The stack as light meets it from `side`: (ambient, layers in the order crossed, substrate).
fn stack(layers: &[(f64, f64)], side: Side) -> (f64, Vec<Layer>, f64) {
    let layers: Vec<Layer> = layers.iter().map(|&(n, d)| Layer::dielectric(n, d)).collect();
    match side {
        Side::Outside => (1.0, layers, GLASS),
        Side::Inside => (GLASS, layers.into_iter().rev().collect(), 1.0),
    }
}

/// (R_s, R_p) of the coated interface at `cos_theta` from `side`, at 550 nm.
fn reflectances(layers: &[(f64, f64)], side: Side, cos_theta: f64) -> (f64, f64) {
    let (ambient, layers, substrate) = stack(layers, side);
    let amplitudes =
        thin_film_amplitudes(ambient, &layers, Complex64::new(substrate, 0.0), LAMBDA_NM, cos_theta);
    (amplitudes.reflectance_s, amplitudes.reflectance_p)
}

/// cos θ of the camera ray through film position (x, y) (pixels, y down) against the plane's
/// normal: the camera's axes rebuilt as `prisma::camera::Camera` builds them (forward, up made
/// perpendicular to it); the image's x axis is perpendicular to the plane of incidence of the
/// centre column, so its sign does not matter.
fn cos_theta_at(side: Side, theta_deg: f64, x: f64, y: f64) -> f64 {
    let (sin, cos) = theta_deg.to_radians().sin_cos();
    let position = [0.0, side.sign() * DISTANCE * cos, -DISTANCE * sin];
    let forward = position.map(|c| -c / DISTANCE);
    // up' = world up − (world up · forward) forward, normalised.
    let along = forward[1];
    let up = [-along * forward[0], 1.0 - along * forward[1], -along * forward[2]];
    let up_norm = up.iter().map(|c| c * c).sum::<f64>().sqrt();
    let up = up.map(|c| c / up_norm);
    // right ⟂ forward and up: ±x here.
    let right = [1.0, 0.0, 0.0];
    let tan_half = (FOV_DEG.to_radians() / 2.0).tan();
    let ndc_x = 2.0 * x / f64::from(SIZE) - 1.0;
    let ndc_y = 1.0 - 2.0 * y / f64::from(SIZE);
    let dir: Vec<f64> =
        (0..3).map(|i| forward[i] + ndc_x * tan_half * right[i] + ndc_y * tan_half * up[i]).collect();
    let norm = dir.iter().map(|c| c * c).sum::<f64>().sqrt();
    // The plane's normal is +y; light meets it from the camera's side.
    (-side.sign() * dir[1] / norm).clamp(0.0, 1.0)
}

/// The per-pixel means of `f(R_s, R_p)` over a 4 × 4 midpoint grid of each pixel.
fn expected(side: Side, theta_deg: f64, f: impl Fn(f64) -> f64) -> Vec<f64> {
    let n = 8;
    (0..SIZE * SIZE)
        .map(|i| {
            let (x0, y0) = (f64::from(i % SIZE), f64::from(i / SIZE));
            (0..n * n)
                .map(|k| {
                    let x = x0 + (f64::from(k % n) + 0.5) / f64::from(n);
                    let y = y0 + (f64::from(k / n) + 0.5) / f64::from(n);
                    f(cos_theta_at(side, theta_deg, x, y))
                })
                .sum::<f64>()
                / f64::from(n * n)
        })
        .collect()
}

/// The rendered S0 (and, polarised, √(S1² + S2²) and |S3|) per pixel, as CIE Y at 550 nm.
struct Rendered {
    s0: Vec<f64>,
    linear: Option<Vec<f64>>,
    circular: Option<Vec<f64>>,
}

fn render_case(layers: &[(f64, f64)], side: Side, theta_deg: f64, polarized: bool) -> Rendered {
    let text = scene_text(layers, side, theta_deg, polarized);
    let scene = prisma::scene::parse(&text, Path::new("<coated_render>")).expect("the scene loads");
    let job =
        Job { threads: 2, monochromatic_nm: Some(LAMBDA_NM as f32), ..Job::new(scene.settings.clone()) };
    let film = render(&scene, &job).expect("the render succeeds").0;
    let y_of = |values: Vec<glam::Vec3>| values.iter().map(|p| f64::from(p.y)).collect::<Vec<_>>();
    let s0 = y_of(film.xyz().to_vec());
    if !polarized {
        return Rendered { s0, linear: None, circular: None };
    }
    let (s1, s2, s3) = (
        y_of(film.stokes_xyz(1).expect("S1")),
        y_of(film.stokes_xyz(2).expect("S2")),
        y_of(film.stokes_xyz(3).expect("S3")),
    );
    let linear = s1.iter().zip(&s2).map(|(a, b)| a.hypot(*b)).collect();
    Rendered { s0, linear: Some(linear), circular: Some(s3.iter().map(|v| v.abs()).collect()) }
}

/// The largest relative error of `seen` against `expected`, pixel by pixel.
fn worst_relative(seen: &[f64], expected: &[f64]) -> f64 {
    seen.iter().zip(expected).map(|(s, e)| (s / e - 1.0).abs()).fold(0.0, f64::max)
}

/// Every side, angle and stack renders R(θ)·L per pixel; polarised, the linear polarisation of
/// the reflection is |R_s − R_p|/2·L and there is no circular polarisation.
#[test]
fn a_coated_interface_reflects_the_stack_reflectance_per_pixel() {
    for layers in [QUARTER_WAVE, TWO_LAYERS] {
        // Inside, 25° stays below the critical angle (41.8°) and 60° is all total internal
        // reflection (R = 1 through a lossless stack).
        for (side, theta_deg) in
            [(Side::Outside, 15.0), (Side::Outside, 60.0), (Side::Inside, 25.0), (Side::Inside, 60.0)]
        {
            let reflectance = |cos: f64| {
                let (r_s, r_p) = reflectances(layers, side, cos);
                0.5 * (r_s + r_p) * RADIANCE
            };
            let expected_s0 = expected(side, theta_deg, reflectance);
            for polarized in [false, true] {
                let rendered = render_case(layers, side, theta_deg, polarized);
                let error = worst_relative(&rendered.s0, &expected_s0);
                eprintln!(
                    "{layers:?} {side:?} {theta_deg}° polarized={polarized}: S0 max rel error {error:.3e}"
                );
                assert!(error < TOLERANCE, "{layers:?} {side:?} {theta_deg}°: S0 off by {error:.3e}");
                if let (Some(linear), Some(circular)) = (rendered.linear, rendered.circular) {
                    let expected_linear = expected(side, theta_deg, |cos: f64| {
                        let (r_s, r_p) = reflectances(layers, side, cos);
                        0.5 * (r_s - r_p).abs() * RADIANCE
                    });
                    for ((seen, want), s0) in linear.iter().zip(&expected_linear).zip(&expected_s0) {
                        assert!(
                            (seen - want).abs() < TOLERANCE * s0,
                            "{layers:?} {side:?} {theta_deg}°: linear polarisation {seen} against {want}"
                        );
                    }
                    let worst_circular =
                        circular.iter().zip(&expected_s0).map(|(c, s0)| c / s0).fold(0.0, f64::max);
                    assert!(worst_circular < 1e-4, "circular polarisation {worst_circular:.3e} of S0");
                }
            }
        }
    }
}

/// The comparison has teeth: the expected values of three wrong renderers (no coating, the
/// layer's phase dropped, the layers in the wrong order) differ from the render by far more
/// than the tolerance.
#[test]
fn wrong_coatings_fail_the_comparison() {
    let (side, theta_deg) = (Side::Outside, 15.0);
    let rendered = render_case(QUARTER_WAVE, side, theta_deg, false).s0;
    let unpolarized = |r: (f64, f64)| 0.5 * (r.0 + r.1) * RADIANCE;

    // Bare Fresnel: 4 % where the coating gives 1.3 %.
    let bare = expected(side, theta_deg, |cos| unpolarized(reflectances(&[], side, cos)));
    let error = worst_relative(&rendered, &bare);
    eprintln!("bare interface: {error:.3e}");
    assert!(error > 50.0 * TOLERANCE, "the bare interface is only {error:.3e} away");

    // The phase dropped: the layer's two faces add their powers incoherently (all orders of
    // the internal reflections, R = (R₁ + R₂ − 2R₁R₂)/(1 − R₁R₂) per polarisation).
    let incoherent = expected(side, theta_deg, |cos| {
        let (n_layer, _) = QUARTER_WAVE[0];
        // The same two faces without interference: air → layer, then layer → glass at the
        // layer's angle (n sin θ conserved).
        let top = thin_film_amplitudes(1.0, &[], Complex64::new(n_layer, 0.0), LAMBDA_NM, cos);
        let sin_layer = (1.0 - cos * cos).sqrt() / n_layer;
        let cos_layer = (1.0 - sin_layer * sin_layer).sqrt();
        let bottom = thin_film_amplitudes(n_layer, &[], Complex64::new(GLASS, 0.0), LAMBDA_NM, cos_layer);
        let combine = |r1: f64, r2: f64| (r1 + r2 - 2.0 * r1 * r2) / (1.0 - r1 * r2);
        0.5 * (combine(top.reflectance_s, bottom.reflectance_s)
            + combine(top.reflectance_p, bottom.reflectance_p))
            * RADIANCE
    });
    let error = worst_relative(&rendered, &incoherent);
    eprintln!("incoherent layer: {error:.3e}");
    assert!(error > 50.0 * TOLERANCE, "the incoherent sum is only {error:.3e} away");

    // The two-layer stack taken from the wrong end.
    let rendered_two = render_case(TWO_LAYERS, side, theta_deg, false).s0;
    let reversed: Vec<(f64, f64)> = TWO_LAYERS.iter().rev().copied().collect();
    let wrong_order = expected(side, theta_deg, |cos| unpolarized(reflectances(&reversed, side, cos)));
    let error = worst_relative(&rendered_two, &wrong_order);
    eprintln!("reversed stack: {error:.3e}");
    assert!(error > 50.0 * TOLERANCE, "the reversed stack is only {error:.3e} away");
}

/// The refracted branches: a plane-parallel slab (n = 1.5) coated on both faces, before a
/// uniform emitter of radiance L on black, seen at incidence θ, transmits
/// L·½[(1 − R_s)/(1 + R_s) + (1 − R_p)/(1 + R_p)] with R the coating's reflectance at θ (the
/// slab is thick, so its faces add incoherently; a lossless stack reflects the same power from
/// both sides at Snell-related angles, so both faces share R, and T = 1 − R): the stack's T in
/// the camera branch, the radiance scaling n² in and 1/n² out, and the reversed stack inside.
/// Unpolarised transport averages s and p at each face, so its series is that of
/// R = (R_s + R_p)/2. The bare slab's value is far off (the fault check).
#[test]
fn a_slab_coated_on_both_faces_transmits_the_stack_series() {
    let mut worst = 0.0_f64;
    for layers in [QUARTER_WAVE, TWO_LAYERS] {
        let coating = layers
            .iter()
            .map(|(n, d)| format!("{{ ior = {n}, thickness_nm = {d} }}"))
            .collect::<Vec<_>>()
            .join(", ");
        for theta_deg in [0.0_f64, 30.0, 60.0, 80.0] {
            let (sin, cos) = theta_deg.to_radians().sin_cos();
            for polarized in [false, true] {
                let text = format!(
                    "[camera]\nposition = [{px}, 0, {pz}]\nlook_at = [0, 0, 0.5]\nfov_y_deg = 0.2\nwidth = 8\nheight = 8\n\
                     [render]\nspp = 4\nmax_depth = 20\nprune_below = 0\npolarized = {polarized}\n\
                     [materials.glass]\ntype = \"dielectric\"\nior = {GLASS}\ncoating = [{coating}]\n\
                     [[shapes]]\ntype = \"quad\"\ncorner = [-1000, -1000, 0]\nedge1 = [0, 2000, 0]\nedge2 = [2000, 0, 0]\nmaterial = \"glass\"\n\
                     [[shapes]]\ntype = \"quad\"\ncorner = [-1000, -1000, 1]\nedge1 = [2000, 0, 0]\nedge2 = [0, 2000, 0]\nmaterial = \"glass\"\n\
                     [[lights]]\ntype = \"quad\"\ncorner = [-5000, -5000, 60]\nedge1 = [10000, 0, 0]\nedge2 = [0, 10000, 0]\nradiance = {RADIANCE}\nemit = \"edge2_cross_edge1\"\n",
                    px = -10.0 * sin,
                    pz = 0.5 - 10.0 * cos,
                );
                let mut scene =
                    prisma::scene::parse(&text, Path::new("<coated_slab>")).expect("the scene loads");
                // R^64 is negligible: the slab's ray tree is a chain.
                scene.settings.max_depth = 64;
                let job = Job {
                    threads: 2,
                    monochromatic_nm: Some(LAMBDA_NM as f32),
                    ..Job::new(scene.settings.clone())
                };
                let film = render(&scene, &job).expect("the render succeeds").0;
                let seen = film.xyz().iter().map(|p| f64::from(p.y)).sum::<f64>() / film.xyz().len() as f64;
                let series =
                    |(r_s, r_p): (f64, f64)| 0.5 * ((1.0 - r_s) / (1.0 + r_s) + (1.0 - r_p) / (1.0 + r_p));
                // Unpolarised transport averages s and p at each interface (scenes/README.md):
                // its series is (1 − R)/(1 + R) of R = (R_s + R_p)/2.
                let (r_s, r_p) = reflectances(layers, Side::Outside, cos);
                let expected = if polarized {
                    RADIANCE * series((r_s, r_p))
                } else {
                    let average = 0.5 * (r_s + r_p);
                    RADIANCE * series((average, average))
                };
                let bare = RADIANCE * series(reflectances(&[], Side::Outside, cos));
                let error = (seen / expected - 1.0).abs();
                eprintln!(
                    "{layers:?} {theta_deg}° polarized={polarized}: seen {seen:.6}, expected {expected:.6} \
                     (bare {bare:.6}), rel error {error:.3e}"
                );
                assert!(error < 1e-4, "{layers:?} {theta_deg}°: transmitted {seen} against {expected}");
                if theta_deg < 70.0 {
                    assert!(
                        (bare / expected - 1.0).abs() > 100.0 * 1e-4,
                        "{layers:?} {theta_deg}°: bare too close"
                    );
                }
                worst = worst.max(error);
            }
        }
    }
    eprintln!("worst relative error of the coated slab: {worst:.3e}");
}

/// The light tracer through coated glass: a point light (I = 1 W·sr⁻¹·nm⁻¹ at 550 nm) inside a
/// coated glass sphere (n = 1.5) inside a closed cube of white (ρ = 1) walls, as the
/// `caustic_power` validation case: every light path leaves the glass (through the reversed
/// stack from inside, total internal reflection included, and the stack from outside on the
/// way back in), and a lossless stack has R + T = 1 per lane, so the six walls (read off six
/// renders sharing their light paths) receive the 4π W·nm⁻¹ emitted, to float rounding. The
/// fault that scales light paths by 1/η² at refractions, applied to the coated branch too, must
/// break it.
#[test]
fn the_light_tracer_conserves_power_through_coated_glass() {
    let received = |fault: Option<prisma::integrator::Fault>| {
        let walls: [([f64; 3], [f64; 3]); 6] = [
            ([0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
            ([0.0, 0.0, -1.0], [0.0, 1.0, 0.0]),
            ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            ([-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
            ([0.0, -1.0, 0.0], [0.0, 0.0, 1.0]),
        ];
        let fmt = |v: [f64; 3]| format!("[{}, {}, {}]", v[0], v[1], v[2]);
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
        };
        let mut shapes = String::new();
        for (normal, up) in &walls {
            let side = cross(*up, *normal);
            let corner: [f64; 3] = std::array::from_fn(|i| 3.0 * normal[i] - 3.0 * side[i] - 3.0 * up[i]);
            shapes += &format!(
                "[[shapes]]\ntype = \"quad\"\ncorner = {}\nedge1 = {}\nedge2 = {}\nmaterial = \"white\"\n",
                fmt(corner),
                fmt(side.map(|c| 6.0 * c)),
                fmt(up.map(|c| 6.0 * c)),
            );
        }
        let size = 64u32;
        let mut total = 0.0_f64;
        for (normal, up) in &walls {
            let text = format!(
                "[camera]\nposition = {p}\nlook_at = {l}\nup = {u}\nfov_y_deg = {fov}\nwidth = {size}\nheight = {size}\n\
                 [render]\nspp = 1\nmax_depth = 64\ncaustics = true\nlight_paths = 150000\nseed = 5\n\
                 [materials.glass]\ntype = \"dielectric\"\nior = {GLASS}\n\
                 coating = [{{ ior = 1.38, thickness_nm = 99.64 }}, {{ ior = 2.1, thickness_nm = 65.5 }}]\n\
                 [materials.white]\ntype = \"diffuse\"\nalbedo = 1\n\
                 [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"glass\"\n{shapes}\
                 [[lights]]\ntype = \"point\"\nposition = [0.35, 0.2, -0.25]\nintensity = 1\n",
                p = fmt(normal.map(|c| 2.0 * c)),
                l = fmt(normal.map(|c| 3.0 * c)),
                u = fmt(*up),
                fov = 2.0 * 3f64.atan().to_degrees(),
            );
            let scene = prisma::scene::parse(&text, Path::new("<coated_power>")).expect("the scene loads");
            let job = Job {
                threads: 2,
                monochromatic_nm: Some(LAMBDA_NM as f32),
                fault,
                ..Job::new(scene.settings.clone())
            };
            let film = render(&scene, &job).expect("the render succeeds").0;
            let pixel_area = (6.0 / f64::from(size)).powi(2);
            total +=
                film.xyz().iter().map(|p| std::f64::consts::PI * f64::from(p.y) * pixel_area).sum::<f64>();
        }
        total
    };
    let emitted = 4.0 * std::f64::consts::PI;
    let error = (received(None) / emitted - 1.0).abs();
    eprintln!("coated sphere: |received/emitted − 1| = {error:.3e}");
    assert!(error < 1e-4, "coated glass loses or makes power: {error:.3e}");
    let faulty = (received(Some(prisma::integrator::Fault::LightPathRadianceScaling)) / emitted - 1.0).abs();
    eprintln!("with radiance scaling on light paths: {faulty:.3e}");
    assert!(faulty > 100.0 * 1e-4, "the fault is only {faulty:.3e} off");
}
