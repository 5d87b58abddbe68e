//! A free-standing film (`type = "film"`, issue 41) in a render reflects and transmits exactly
//! what a single-layer film does, per pixel, per wavelength and in all four Stokes components:
//!
//! - **against `tmm`** (tests/fixtures/thin_film_soap_film.csv: water n = 1.333, 500 nm, air on
//!   both sides): a flat film seen at the fixture's angles and wavelengths, lit through an ideal
//!   linear polariser at 45° to the plane of incidence by a uniform emitter, in reflection and
//!   in transmission. With E = (A_s, A_p)/√2 · √(L/2) arriving in the s/p frame, the camera
//!   records (L/2)·[(|A_s|² + |A_p|²)/2, (|A_s|² − |A_p|²)/2, Re(A_s A_p*), −Im(A_s A_p*)] in
//!   its frame (x = s, y = k × x: prisma's `polarization` conventions, S3 = −2 Im(E_x E_y*)),
//!   so the phases of r_s, r_p (t_s, t_p) and which is s show, with their signs;
//! - **against Airy's formula**, written here on its own: r = (r₀₁ + r₁₂e^{−2iβ})/(1 +
//!   r₀₁r₁₂e^{−2iβ}), t = t₀₁t₁₂e^{−iβ}/(1 + r₀₁r₁₂e^{−2iβ}), β = 2π n d cos θ_t/λ (Born & Wolf
//!   §7.6.1 in the e^{+iωt} convention), checked against the fixture and then per pixel of a
//!   wider view (each pixel its own angle), unpolarised light in;
//! - **energy**: R + T = 1 lane by lane, and a bubble inside a uniform background (a white
//!   furnace) is invisible;
//! - **colour**: a film at normal incidence under a D65 emitter has the XYZ of the interference
//!   colour chart of `prisma fresnel --film-colours` at its thickness.
//!
//! Faults that must fail: the phase of the film dropped (its two faces added incoherently),
//! s and p swapped, the sign of the phases flipped.

mod film_chart;

use std::path::Path;

use num_complex::Complex64;
use prisma::render::{render, Job};

const WATER: f64 = 1.333;
const THICKNESS_NM: f64 = 500.0;
const RADIANCE: f64 = 2.0;
const DISTANCE: f64 = 10.0;

/// Airy's single-layer sum for a film of index `n` and thickness `d` (nm) in air at vacuum
/// wavelength `lambda` (nm) and incidence cos θ = `cos_i`: (r_s, r_p, t_s, t_p), Hecht's signs
/// (r_p = −r_s at normal incidence), fields e^{+iωt} (a delay is e^{−iφ}).
fn airy(n: f64, d: f64, lambda: f64, cos_i: f64) -> [Complex64; 4] {
    let sin_t = (1.0 - cos_i * cos_i).sqrt() / n;
    let cos_t = (1.0 - sin_t * sin_t).sqrt();
    // Air → film (01) and film → air (12), Hecht §4.6.
    let r01_s = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    let r01_p = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    let t01_s = 2.0 * cos_i / (cos_i + n * cos_t);
    let t01_p = 2.0 * cos_i / (n * cos_i + cos_t);
    let t12_s = 2.0 * n * cos_t / (n * cos_t + cos_i);
    let t12_p = 2.0 * n * cos_t / (cos_t + n * cos_i);
    let beta = std::f64::consts::TAU * n * d * cos_t / lambda;
    let round_trip = Complex64::from_polar(1.0, -2.0 * beta);
    let single = Complex64::from_polar(1.0, -beta);
    // r₁₂ = −r₀₁ for both polarisations (Stokes relations).
    let r = |r01: f64| (r01 - r01 * round_trip) / (1.0 - r01 * r01 * round_trip);
    let t = |r01: f64, t01: f64, t12: f64| t01 * t12 * single / (1.0 - r01 * r01 * round_trip);
    [r(r01_s), r(r01_p), t(r01_s, t01_s, t12_s), t(r01_p, t01_p, t12_p)]
}

/// One row of the `tmm` fixture: (λ nm, θ degrees, r_s, r_p, t_s, t_p).
struct FixtureRow {
    lambda_nm: f64,
    theta_deg: f64,
    amplitudes: [Complex64; 4],
}

fn fixture() -> Vec<FixtureRow> {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/thin_film_soap_film.csv"),
    )
    .expect("the soap-film fixture is in the repository");
    text.lines()
        .filter(|line| !line.starts_with('#') && !line.starts_with("wavelength"))
        .map(|line| {
            let v: Vec<f64> = line.split(',').map(|x| x.parse().expect("a number")).collect();
            let c = |i: usize| Complex64::new(v[i], v[i + 1]);
            FixtureRow { lambda_nm: v[0], theta_deg: v[1], amplitudes: [c(8), c(10), c(12), c(14)] }
        })
        .collect()
}

/// The test's own Airy formula is the fixture's physics: every row, amplitudes and phases.
#[test]
fn airy_formula_matches_the_tmm_fixture() {
    let rows = fixture();
    assert_eq!(rows.len(), 26 * 19, "26 wavelengths × 19 angles");
    for row in &rows {
        let cos_i = row.theta_deg.to_radians().cos();
        let airy = airy(WATER, THICKNESS_NM, row.lambda_nm, cos_i);
        for (a, b) in airy.iter().zip(&row.amplitudes) {
            // Both in f64 from the same closed forms: rounding only.
            assert!((a - b).norm() < 1e-12, "{} nm {}°: {a} vs {b}", row.lambda_nm, row.theta_deg);
        }
    }
}

/// Which side of the film the emitter is on.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Seen {
    /// Emitter above, on the camera's side: the camera sees the reflection.
    Reflected,
    /// Emitter below: the camera sees through the film.
    Transmitted,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    a.map(|c| c * s)
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn normalize(a: [f64; 3]) -> [f64; 3] {
    scale(a, 1.0 / dot(a, a).sqrt())
}
fn fmt(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

/// A scene: the film on the plane y = 0 (normal +y), the camera at `DISTANCE` looking at the
/// origin at `theta_deg` from the normal, a uniform one-sided emitter of radiance `RADIANCE`
/// on the side `seen` asks for (nothing else: a black background), and with `polarizer` an
/// ideal linear polariser across the light's way 40 units from the film at 45° to the plane of
/// incidence. `film` is the material's body.
fn scene_text(
    film: &str,
    seen: Seen,
    theta_deg: f64,
    fov_deg: f64,
    size: u32,
    polarizer: bool,
    polarized: bool,
) -> String {
    let (sin, cos) = theta_deg.to_radians().sin_cos();
    let position = [0.0, DISTANCE * cos, -DISTANCE * sin];
    let up = if theta_deg == 0.0 { [0.0, 0.0, 1.0] } else { [0.0, 1.0, 0.0] };
    let dir = normalize(scale(position, -1.0));
    // Where the camera's central ray goes after the film: mirrored or straight on.
    let onward = match seen {
        Seen::Reflected => [dir[0], -dir[1], dir[2]],
        Seen::Transmitted => dir,
    };
    let (emitter_y, emit) = match seen {
        Seen::Reflected => (60.0, "edge1_cross_edge2"),
        Seen::Transmitted => (-60.0, "edge2_cross_edge1"),
    };
    let mut text = format!(
        "background = 0\n\
         [camera]\nposition = {p}\nlook_at = [0, 0, 0]\nup = {u}\nfov_y_deg = {fov_deg}\n\
         width = {size}\nheight = {size}\n\
         [render]\nspp = 64\nmax_depth = 6\nprune_below = 0\npolarized = {polarized}\n\
         [materials.soap]\n{film}\n\
         [materials.polaroid]\ntype = \"polarizer\"\naxis = {axis}\n\
         [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"soap\"\n\
         [[lights]]\ntype = \"quad\"\ncorner = [-5000, {emitter_y}, -5000]\nedge1 = [10000, 0, 0]\n\
         edge2 = [0, 0, 10000]\nradiance = {RADIANCE}\nemit = \"{emit}\"\n",
        p = fmt(position),
        u = fmt(up),
        axis = fmt(polarizer_axis(seen, theta_deg)),
    );
    if polarizer {
        // A square of side 6 across the light's way, 40 units out: clear of the film plane and
        // of the camera's rays to the film at every angle used.
        let centre = scale(onward, 40.0);
        let e1 = [1.0, 0.0, 0.0];
        let e2 = cross(onward, e1);
        let corner = sub(sub(centre, scale(e1, 3.0)), scale(e2, 3.0));
        text += &format!(
            "[[shapes]]\ntype = \"quad\"\ncorner = {}\nedge1 = {}\nedge2 = {}\nmaterial = \"polaroid\"\n",
            fmt(corner),
            fmt(scale(e1, 6.0)),
            fmt(scale(e2, 6.0)),
        );
    }
    text
}

/// The camera's Stokes x axis for its central ray (`Camera::stokes_x`: dir × up, normalised).
fn camera_x(theta_deg: f64) -> ([f64; 3], [f64; 3]) {
    let (sin, cos) = theta_deg.to_radians().sin_cos();
    let dir = [0.0, -cos, sin];
    let up = if theta_deg == 0.0 { [0.0, 0.0, 1.0] } else { [0.0, 1.0, 0.0] };
    (dir, normalize(cross(dir, up)))
}

/// The polariser's axis: at 45° between the camera's x (= ±s) and k_i × x, k_i the direction
/// the light travels onto the film, so that the light arrives as (1, 1)/√2 in the frame
/// (x, k_i × x).
fn polarizer_axis(seen: Seen, theta_deg: f64) -> [f64; 3] {
    let (dir, x) = camera_x(theta_deg);
    let k_in = match seen {
        Seen::Reflected => [-dir[0], dir[1], -dir[2]],
        Seen::Transmitted => scale(dir, -1.0),
    };
    normalize([x[0] + cross(k_in, x)[0], x[1] + cross(k_in, x)[1], x[2] + cross(k_in, x)[2]])
}

/// The mean S0–S3 (CIE Y at the one wavelength rendered) over the image.
fn mean_stokes(text: &str, lambda_nm: f64, fault: Option<prisma::integrator::Fault>) -> [f64; 4] {
    let scene = prisma::scene::parse(text, Path::new("<soap_film>")).expect("the scene loads");
    let polarized = scene.settings.polarized;
    let job = Job {
        threads: 2,
        monochromatic_nm: Some(lambda_nm as f32),
        fault,
        ..Job::new(scene.settings.clone())
    };
    let film = render(&scene, &job).expect("the render succeeds").0;
    let mean =
        |values: &[glam::Vec3]| values.iter().map(|p| f64::from(p.y)).sum::<f64>() / values.len() as f64;
    let mut stokes = [mean(film.xyz()), 0.0, 0.0, 0.0];
    if polarized {
        for (k, slot) in stokes.iter_mut().enumerate().skip(1) {
            *slot = mean(&film.stokes_xyz(k).expect("a polarised render has S1–S3"));
        }
    }
    stokes
}

/// What the camera records of light (L/2)(1, 0, 1, 0) in the frame (x, k_i × x) after the
/// element diag(`a_s`, `a_p`): (L/2)·[(|A_s|² + |A_p|²)/2, (|A_s|² − |A_p|²)/2, Re(A_s A_p*),
/// −Im(A_s A_p*)].
fn expected_stokes(a_s: Complex64, a_p: Complex64) -> [f64; 4] {
    let w = a_s * a_p.conj();
    let half = 0.5 * RADIANCE;
    [
        half * 0.5 * (a_s.norm_sqr() + a_p.norm_sqr()),
        half * 0.5 * (a_s.norm_sqr() - a_p.norm_sqr()),
        half * w.re,
        -half * w.im,
    ]
}

/// Largest accepted difference of each Stokes component, relative to S0: the view spans
/// 0.02° (a few 10⁻⁴ rad), over which the film's phase 2β moves by < 10⁻³ rad at 80°, and the
/// renderer computes the amplitudes in f64 and narrows them to f32 (10⁻⁷); the worst measured
/// is printed.
const NARROW_TOLERANCE: f64 = 1e-4;

/// The film seen through a polariser at the fixture's angles and wavelengths: S0–S3 of the
/// reflection (r_s, r_p) and of the transmission (t_s, t_p) against `tmm`'s amplitudes.
#[test]
fn a_flat_film_renders_the_tmm_amplitudes_in_all_four_stokes_components() {
    let film = format!("type = \"film\"\nior = {WATER}\nthickness_nm = {THICKNESS_NM}");
    let rows = fixture();
    let mut worst = 0.0_f64;
    for &(lambda_nm, theta_deg) in
        &[(460.0, 0.0), (560.0, 30.0), (660.0, 45.0), (400.0, 60.0), (760.0, 80.0), (550.0, 70.0)]
    {
        let row = rows
            .iter()
            .find(|r| r.lambda_nm == lambda_nm && r.theta_deg == theta_deg)
            .expect("the fixture has this row");
        let [r_s, r_p, t_s, t_p] = row.amplitudes;
        for (seen, a_s, a_p) in [(Seen::Reflected, r_s, r_p), (Seen::Transmitted, t_s, t_p)] {
            let text = scene_text(&film, seen, theta_deg, 0.02, 4, true, true);
            let stokes = mean_stokes(&text, lambda_nm, None);
            let expected = expected_stokes(a_s, a_p);
            let error = (0..4).map(|k| (stokes[k] - expected[k]).abs()).fold(0.0, f64::max) / expected[0];
            eprintln!("{seen:?} {lambda_nm} nm {theta_deg}°: {stokes:?} vs {expected:?}, error {error:.2e}");
            assert!(
                error < NARROW_TOLERANCE,
                "{seen:?} {lambda_nm} nm {theta_deg}°: {stokes:?} vs {expected:?}"
            );
            worst = worst.max(error);
            // Unpolarised transport: the s/p average alone.
            let text = scene_text(&film, seen, theta_deg, 0.02, 4, false, false);
            let s0 = mean_stokes(&text, lambda_nm, None)[0];
            let average = RADIANCE * 0.5 * (a_s.norm_sqr() + a_p.norm_sqr());
            assert!((s0 / average - 1.0).abs() < NARROW_TOLERANCE, "unpolarised {seen:?}: {s0} vs {average}");
        }
    }
    eprintln!("worst Stokes error of the flat film against tmm: {worst:.2e} of S0");
}

/// The comparison has teeth: s and p swapped, the phases' sign flipped (the `FlippedPhase`
/// fault in the renderer), or the film's phase dropped (its faces' powers added incoherently)
/// are each far from the render.
#[test]
fn wrong_films_fail_the_comparison() {
    let film = format!("type = \"film\"\nior = {WATER}\nthickness_nm = {THICKNESS_NM}");
    let (lambda_nm, theta_deg) = (560.0_f64, 30.0_f64);
    let [r_s, r_p, ..] = airy(WATER, THICKNESS_NM, lambda_nm, theta_deg.to_radians().cos());
    let text = scene_text(&film, Seen::Reflected, theta_deg, 0.02, 4, true, true);
    let rendered = mean_stokes(&text, lambda_nm, None);
    let distance = |expected: [f64; 4]| {
        (0..4).map(|k| (rendered[k] - expected[k]).abs()).fold(0.0, f64::max) / expected[0]
    };
    let swapped = distance(expected_stokes(r_p, r_s));
    let flipped = distance(expected_stokes(r_s.conj(), r_p.conj()));
    // Incoherent faces: R = 2R₁/(1 + R₁) per polarisation (two equal faces, all orders).
    let incoherent = |r: Complex64| {
        let cos_i = theta_deg.to_radians().cos();
        let sin_t = (1.0 - cos_i * cos_i).sqrt() / WATER;
        let cos_t = (1.0 - sin_t * sin_t).sqrt();
        let one = if r == r_s {
            ((cos_i - WATER * cos_t) / (cos_i + WATER * cos_t)).powi(2)
        } else {
            ((WATER * cos_i - cos_t) / (WATER * cos_i + cos_t)).powi(2)
        };
        (2.0 * one / (1.0 + one)).sqrt()
    };
    let dropped =
        distance(expected_stokes(Complex64::new(incoherent(r_s), 0.0), Complex64::new(incoherent(r_p), 0.0)));
    eprintln!("swapped {swapped:.3}, flipped phase {flipped:.3}, incoherent {dropped:.3}");
    for (what, off) in [("s and p swapped", swapped), ("phase flipped", flipped), ("incoherent", dropped)] {
        assert!(off > 100.0 * NARROW_TOLERANCE, "{what} is only {off:.2e} away");
    }
    // The renderer's own phase fault moves S3 by as much.
    let faulty = mean_stokes(&text, lambda_nm, Some(prisma::integrator::Fault::FlippedPhase));
    let expected = expected_stokes(r_s, r_p);
    let off = (faulty[3] - expected[3]).abs() / expected[0];
    assert!(off > 100.0 * NARROW_TOLERANCE, "FlippedPhase moves S3 by only {off:.2e}");
}

/// Per pixel, each its own angle: a 12° view at 40° incidence, unpolarised light in, S0 of
/// every pixel against the pixel's mean of Airy's (R_s + R_p)/2·L (or T) over a 16 × 16
/// midpoint grid, spectral lanes of 450, 550 and 650 nm, and a drained film whose thickness
/// varies across the view.
#[test]
fn every_pixel_sees_the_film_at_its_own_angle() {
    const SIZE: u32 = 16;
    const FOV_DEG: f64 = 12.0;
    const THETA_DEG: f64 = 40.0;
    // Pixel means of a function of R that turns by ≈ 1 rad of film phase across a pixel
    // (0.75° at 500 nm of water near 40°: 2β moves 2.5 rad per rad) from 64 stratified samples
    // against a 16 × 16 midpoint mean: the worst measured is 1.2·10⁻³ (1.6·10⁻³ against an 8 × 8
    // mean, 2.2·10⁻³ at 16 samples), so it is the pixel integration's, not the film's.
    const TOLERANCE: f64 = 2e-3;
    let (sin, cos) = THETA_DEG.to_radians().sin_cos();
    let position = [0.0, DISTANCE * cos, -DISTANCE * sin];
    let forward = normalize(scale(position, -1.0));
    let up = normalize(sub([0.0, 1.0, 0.0], scale(forward, forward[1])));
    let right = cross(up, forward);
    let tan_half = (FOV_DEG.to_radians() / 2.0).tan();
    // The camera ray through film position (x, y) (pixels, y down) and where it meets y = 0.
    let ray = |x: f64, y: f64| {
        let ndc_x = 2.0 * x / f64::from(SIZE) - 1.0;
        let ndc_y = 1.0 - 2.0 * y / f64::from(SIZE);
        // The image's x sign does not matter: the scene is symmetric about x = 0.
        let d: [f64; 3] =
            std::array::from_fn(|i| forward[i] + ndc_x * tan_half * right[i] + ndc_y * tan_half * up[i]);
        let d = normalize(d);
        let t = -position[1] / d[1];
        (-d[1], std::array::from_fn::<f64, 3, _>(|i| position[i] + t * d[i]))
    };
    let films = [
        ("constant".to_owned(), format!("type = \"film\"\nior = {WATER}\nthickness_nm = {THICKNESS_NM}")),
        (
            "drained".to_owned(),
            format!(
                "type = \"film\"\nior = {WATER}\n\
                 thickness_nm = {{ top = 300, bottom = 700, axis = [0, 0, 1], heights = [-4, 4] }}"
            ),
        ),
    ];
    // The drained law, written here: d² linear in height from 700² at z = −4 to 300² at 4 (the
    // view spans z ≈ −0.9…1.1: some 7 nm of thickness per pixel, 0.2 rad of film phase).
    let thickness = |name: &str, point: [f64; 3]| {
        if name == "constant" {
            return THICKNESS_NM;
        }
        let depth = ((4.0 - point[2]) / 8.0).clamp(0.0, 1.0);
        (300.0_f64.powi(2) + (700.0_f64.powi(2) - 300.0_f64.powi(2)) * depth).sqrt()
    };
    let mut worst = 0.0_f64;
    for (name, film) in &films {
        for seen in [Seen::Reflected, Seen::Transmitted] {
            for lambda_nm in [450.0, 550.0, 650.0] {
                let text = scene_text(film, seen, THETA_DEG, FOV_DEG, SIZE, false, false);
                let scene = prisma::scene::parse(&text, Path::new("<soap_film>")).expect("the scene loads");
                let job = Job {
                    threads: 2,
                    monochromatic_nm: Some(lambda_nm as f32),
                    ..Job::new(scene.settings.clone())
                };
                let image = render(&scene, &job).expect("the render succeeds").0;
                let n = 16;
                for (i, pixel) in image.xyz().iter().enumerate() {
                    let (x0, y0) = ((i as u32 % SIZE) as f64, (i as u32 / SIZE) as f64);
                    let expected = (0..n * n)
                        .map(|k| {
                            let (cos_i, point) = ray(
                                x0 + ((k % n) as f64 + 0.5) / n as f64,
                                y0 + ((k / n) as f64 + 0.5) / n as f64,
                            );
                            let [r_s, r_p, t_s, t_p] = airy(WATER, thickness(name, point), lambda_nm, cos_i);
                            match seen {
                                Seen::Reflected => 0.5 * (r_s.norm_sqr() + r_p.norm_sqr()),
                                Seen::Transmitted => 0.5 * (t_s.norm_sqr() + t_p.norm_sqr()),
                            }
                        })
                        .sum::<f64>()
                        / f64::from(n * n)
                        * RADIANCE;
                    // Relative to the larger of the pixel's value and a reflectance of 1 %.
                    let error = (f64::from(pixel.y) - expected).abs() / expected.max(0.01 * RADIANCE);
                    assert!(
                        error < TOLERANCE,
                        "{name} {seen:?} {lambda_nm} nm, pixel {i}: {} vs {expected}",
                        pixel.y
                    );
                    worst = worst.max(error);
                }
            }
        }
    }
    eprintln!("worst per-pixel error against Airy: {worst:.2e}");
}

/// R + T = 1 for a film that does not absorb, at every angle, wavelength and thickness (in
/// f32, the amplitudes narrowed from f64: rounding only).
#[test]
fn a_lossless_film_reflects_what_it_does_not_transmit() {
    for thickness_nm in [0.0_f32, 10.0, 120.0, 500.0, 2000.0, 1e5] {
        for lambda_nm in [360.0_f32, 450.0, 550.0, 700.0, 830.0] {
            for i in 0..=20 {
                let cos_i = i as f32 / 20.0;
                for sign in [1.0_f32, -1.0] {
                    let film =
                        prisma::material::Film::interface(sign * cos_i, 1.333, thickness_nm, lambda_nm);
                    let sum = film.reflection.a + film.transmission.a;
                    assert!(
                        (sum - 1.0).abs() < 1e-6,
                        "{thickness_nm} nm at {lambda_nm} nm, cos {cos_i}: {sum}"
                    );
                    // Per polarisation too: a ± b is 2R_s or 2R_p.
                    let s = film.reflection.a + film.reflection.b + film.transmission.a + film.transmission.b;
                    assert!((s - 1.0).abs() < 1e-6, "s: {s}");
                }
            }
        }
    }
}

/// A lossless film is invisible in a white furnace: a bubble (constant, and drained over its
/// height) inside a uniform background renders as the background (`prisma validate`'s furnace,
/// 400 bounces).
#[test]
fn a_bubble_in_a_white_furnace_is_invisible() {
    for material in [
        "type = \"film\"\nthickness_nm = 400",
        "type = \"film\"\nthickness_nm = { top = 50, bottom = 1200, axis = [0, 1, 0] }",
    ] {
        let result = prisma::validate::analytic::furnace(material, 2).expect("the furnace runs");
        for check in &result.checks {
            eprintln!(
                "{material:?}: {} = {:.2e} (threshold {:.0e})",
                check.metric, check.value, check.threshold
            );
            assert!(check.passed(), "{material:?}: {check:?}");
        }
    }
}

/// The colour of a film at normal incidence against a D65 emitter, as XYZ relative to the
/// emitter's Y (a perfect mirror's render of the same emitter, same seed), equals the row of
/// `prisma fresnel --film-colours --ior 1.333` (D65 normalised to Y = 1) at its thickness. The
/// render samples wavelengths (16 × 8 per pixel, stratified), the chart integrates by 1 nm
/// quadrature: the worst difference measured, printed, is the wavelength sampling's.
#[test]
fn a_film_has_the_colour_of_the_interference_chart() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let chart = film_chart::water_film_chart(dir.path());
    let render_xyz = |material: &str| {
        // The emitter behind the camera (one-sided, facing the film); the camera looks along
        // +z at the film on z = 0 through a 1° view (cos θ ≥ 0.99996).
        let text = format!(
            "background = 0\n[camera]\nposition = [0, 0, -10]\nlook_at = [0, 0, 0]\nfov_y_deg = 1\nwidth = 8\nheight = 8\n\
             [render]\nspp = 256\nmax_depth = 4\nprune_below = 0\n[materials.film]\n{material}\n\
             [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, -1]\nmaterial = \"film\"\n\
             [[lights]]\ntype = \"quad\"\ncorner = [-5000, -5000, -20]\nedge1 = [10000, 0, 0]\nedge2 = [0, 10000, 0]\n\
             radiance = {{ illuminant = \"D65\" }}\nemit = \"edge1_cross_edge2\"\n"
        );
        let scene = prisma::scene::parse(&text, Path::new("<film_colour>")).expect("the scene loads");
        let image =
            render(&scene, &Job { threads: 2, ..Job::new(scene.settings.clone()) }).expect("renders").0;
        let count = image.xyz().len() as f64;
        image.xyz().iter().fold([0.0; 3], |sum, p| {
            [
                sum[0] + f64::from(p.x) / count,
                sum[1] + f64::from(p.y) / count,
                sum[2] + f64::from(p.z) / count,
            ]
        })
    };
    let white = render_xyz("type = \"mirror\"")[1];
    assert!(white.is_finite() && white > 0.0, "the mirror shows the emitter: Y = {white}");
    let mut worst = 0.0_f64;
    for thickness in [0usize, 60, 120, 200, 300, 450, 700, 1200] {
        let row = chart[thickness];
        assert_eq!(row[0], thickness as f64);
        let xyz = render_xyz(&format!("type = \"film\"\nior = 1.333\nthickness_nm = {thickness}"));
        let seen = xyz.map(|v| v / white);
        // Relative to the chart's brightest Y (7.8 %): dark thicknesses are compared in
        // absolute terms at that scale.
        let error = (0..3).map(|k| (seen[k] - row[k + 1]).abs()).fold(0.0, f64::max) / 0.078;
        eprintln!("{thickness} nm: rendered XYZ {seen:?}, chart {:?}, error {error:.2e}", &row[1..]);
        // The worst measured is 1.4·10⁻⁴; the bound leaves room for other seeds' sampling.
        assert!(error < 1e-3, "{thickness} nm: {seen:?} against the chart's {:?}", &row[1..]);
        worst = worst.max(error);
    }
    eprintln!("worst colour error against the chart: {worst:.2e} of the brightest Y");
}

/// `prisma validate`'s soap-film case passes, and fails with every index 1 % too high (the
/// film's phase 2β moves by 1 %: 0.2 rad at 700 nm of water).
#[test]
fn the_validate_case_passes_and_catches_a_wrong_index() {
    use prisma::integrator::Fault;
    use prisma::validate::analytic;
    let passes =
        |fault: Option<Fault>| analytic::run("soap_film_colour", 2, fault).expect("the case runs").passed();
    assert!(passes(None));
    assert!(!passes(Some(Fault::IorScale(1.01))));
}

/// The path tracer chooses one branch at a film with probability proportional to R or T summed
/// over the lanes, and divides by it: through a lossless film a path of one wavelength keeps its
/// weight exactly, so a bubble (drained) inside a uniform background renders as the background
/// pixel by pixel, to float rounding, at one wavelength and unpolarised; with eight lanes each
/// lane's weight is R_λ/p, and polarised the choice ignores the path's polarisation (unbiased,
/// not exact: noise), and the image's mean matches the background's.
#[test]
fn the_path_tracer_sees_a_bubble_vanish_in_a_furnace() {
    let text = |polarized: bool, spp: u32| {
        format!(
            "background = {{ rgb = [0.8, 0.6, 0.4] }}\n[camera]\nposition = [0, 0, -4]\nlook_at = [0, 0, 0]\n\
             fov_y_deg = 40\nwidth = 24\nheight = 24\n[render]\nintegrator = \"path\"\nspp = {spp}\nmax_depth = 400\n\
             polarized = {polarized}\nseed = 11\n\
             [materials.soap]\ntype = \"film\"\nthickness_nm = {{ top = 50, bottom = 1200, axis = [0, 1, 0] }}\n\
             [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"soap\"\n"
        )
    };
    let with_and_without = |text: &str, monochromatic_nm: Option<f32>| {
        let scene = prisma::scene::parse(text, Path::new("<film_furnace>")).expect("the scene loads");
        let mut empty = scene.clone();
        empty.geometry = prisma::geometry::Geometry::build(Vec::new(), Vec::new());
        empty.surfaces.clear();
        let job = Job { threads: 2, monochromatic_nm, ..Job::new(scene.settings.clone()) };
        (render(&scene, &job).expect("renders").0, render(&empty, &job).expect("renders").0)
    };
    // Unpolarised, one wavelength: R/p = 1 exactly at every film hit.
    for lambda_nm in [450.0, 550.0, 650.0] {
        let (with, without) = with_and_without(&text(false, 4), Some(lambda_nm));
        let worst = with
            .xyz()
            .iter()
            .zip(without.xyz())
            .map(|(a, b)| ((*a - *b).abs() / b.max_element()).max_element())
            .fold(0.0_f32, f32::max);
        eprintln!("{lambda_nm} nm: worst relative pixel difference {worst:.2e}");
        // f32 rounding of the per-hit weights R/p and T/(1 − p) over a few hits.
        assert!(worst < 1e-5, "{lambda_nm} nm: the bubble shows, {worst:.2e}");
    }
    // Polarised, the choice is by the unpolarised R and T while the path's light is polarised
    // after its first reflection (as for glass): unbiased, not exact; and spectral.
    for polarized in [true, false] {
        let (with, without) = with_and_without(&text(polarized, 64), None);
        let mean = |image: &prisma::film::Film| {
            image.xyz().iter().fold(glam::Vec3::ZERO, |sum, p| sum + *p) / image.xyz().len() as f32
        };
        let difference = ((mean(&with) - mean(&without)) / mean(&without)).abs().max_element();
        eprintln!("polarized = {polarized}, spectral: relative difference of the means {difference:.2e}");
        // The noise of the branch choice averaged over 576 pixels × 64 samples: 8·10⁻⁴ measured.
        assert!(difference < 5e-3, "polarized = {polarized}: spectral means differ by {difference:.2e}");
    }
}

/// The light tracer handles a film as glass (caustic paths through it): a point light (I = 1
/// W·sr⁻¹·nm⁻¹ at 550 nm) inside a drained soap bubble inside a closed cube of white (ρ = 1)
/// walls: every light path leaves the bubble keeping its flux (R + T = 1 per lane, one branch
/// chosen by flux), so the six walls (six renders sharing their light paths) receive the 4π
/// W·nm⁻¹ emitted, to float rounding, as `tests/coated_render.rs` checks for coated glass
/// (without the light guide, whose learned emission density would make the total an estimate).
#[test]
fn the_light_tracer_conserves_power_through_a_bubble() {
    let walls: [([f64; 3], [f64; 3]); 6] = [
        ([0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, -1.0], [0.0, 1.0, 0.0]),
        ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
        ([0.0, -1.0, 0.0], [0.0, 0.0, 1.0]),
    ];
    let mut shapes = String::new();
    for (normal, up) in &walls {
        let side = cross(*up, *normal);
        let corner: [f64; 3] = std::array::from_fn(|i| 3.0 * normal[i] - 3.0 * side[i] - 3.0 * up[i]);
        shapes += &format!(
            "[[shapes]]\ntype = \"quad\"\ncorner = {}\nedge1 = {}\nedge2 = {}\nmaterial = \"white\"\n",
            fmt(corner),
            fmt(scale(side, 6.0)),
            fmt(scale(*up, 6.0)),
        );
    }
    let size = 32u32;
    let mut total = 0.0_f64;
    for (normal, up) in &walls {
        let text = format!(
            "[camera]\nposition = {p}\nlook_at = {l}\nup = {u}\nfov_y_deg = {fov}\nwidth = {size}\nheight = {size}\n\
             [render]\nspp = 1\nmax_depth = 64\ncaustics = true\nlight_paths = 20000\nlight_guide = false\nseed = 5\n\
             [materials.soap]\ntype = \"film\"\nthickness_nm = {{ top = 80, bottom = 900, axis = [0, 1, 0] }}\n\
             [materials.white]\ntype = \"diffuse\"\nalbedo = 1\n\
             [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"soap\"\n{shapes}\
             [[lights]]\ntype = \"point\"\nposition = [0.35, 0.2, -0.25]\nintensity = 1\n",
            p = fmt(scale(*normal, 2.0)),
            l = fmt(scale(*normal, 3.0)),
            u = fmt(*up),
            fov = 2.0 * 3f64.atan().to_degrees(),
        );
        let mut scene = prisma::scene::parse(&text, Path::new("<film_power>")).expect("the scene loads");
        // No Russian roulette: a thin film's reflection (R < 1 % near its top) would go through
        // it, which is unbiased but not exact.
        scene.settings.prune_below = 0.0;
        let job = Job { threads: 2, monochromatic_nm: Some(550.0), ..Job::new(scene.settings.clone()) };
        let image = render(&scene, &job).expect("the render succeeds").0;
        let pixel_area = (6.0 / f64::from(size)).powi(2);
        total += image.xyz().iter().map(|p| std::f64::consts::PI * f64::from(p.y) * pixel_area).sum::<f64>();
    }
    let error = (total / (4.0 * std::f64::consts::PI) - 1.0).abs();
    eprintln!("bubble: |received/emitted − 1| = {error:.3e}");
    assert!(error < 1e-4, "the film loses or makes power: {error:.3e}");
}
