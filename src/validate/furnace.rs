//! Closed forms of full light transport: scenes where every bounce of light is summed in one
//! geometric series, so that the whole image is known without a reference renderer (pbrt-v4
//! tests its integrators on the first, `src/pbrt/cpu/integrators_test.cpp`).
//!
//! - **A point light inside a closed diffuse sphere** (albedo ρ, intensity I at the centre,
//!   radius r): the direct irradiance is I/r² everywhere on the wall, and a sphere's wall sees
//!   every other area element of itself with the same form factor dA/(4πr²), so each bounce
//!   spreads the light evenly and multiplies it by ρ. Every pixel is ρI/(πr²)·Σρᵏ =
//!   ρI/(πr²(1 − ρ)) (1.0 for ρ = ½, I = π, r = 1). Whitted's model stops after the first
//!   term, ρI/(πr²): checked too, so that the fraction it leaves out (ρ) is measured.
//! - **A closed enclosure emitting Le with albedo ρ** (here a cube of six inward quad lights
//!   with `albedo`): every point sees only the walls, whose radiance L is uniform, so the
//!   irradiance is πL and L = Le + ρL, L = Le/(1 − ρ), whatever the shape. Whitted adds one
//!   bounce of direct light: Le(1 + ρ), checked too.
//! - **A convex diffuse object under a uniform sky** (albedo ρ, background radiance L_bg): every
//!   point of a convex surface sees the sky over its whole hemisphere, irradiance π·L_bg, so the
//!   object is ρ·L_bg everywhere and the background L_bg.
//!
//! Each case is spectral (albedo, intensity and emission are tables over wavelength) and
//! polarised: the expected XYZ integrates the closed form at every whole nm against prisma's
//! CIE 1931 table ([`xyz_by_quadrature`]), evaluated from the tables written here in f64, and
//! S1–S3 must vanish (diffuse surfaces depolarise and the lights are unpolarised). Thresholds
//! come from the measured noise (`validation/README.md`, "Full transport: closed forms").

use std::path::Path;

use glam::Vec3;

use super::{CaseResult, Check, ValidateError};
use crate::film::Film;
use crate::integrator::Fault;
use crate::render::{render, Job};
use crate::scene::{parse, Scene};
use crate::spectrum::cie::xyz_by_quadrature;

/// Names of the closed-form cases of full transport, in the order [`run`] runs them.
pub const CASES: [&str; 5] = [
    "closed_sphere_point_light",
    "closed_sphere_point_light_whitted",
    "emitting_box",
    "emitting_box_whitted",
    "sphere_under_sky",
];

/// Runs the closed-form case `name` with `threads` threads and an optional injected `fault`.
pub fn run(name: &str, threads: usize, fault: Option<Fault>) -> Result<CaseResult, ValidateError> {
    let ctx = Context { threads, fault };
    match name {
        "closed_sphere_point_light" => ctx.sphere_point_light(name, Integrator::Path),
        "closed_sphere_point_light_whitted" => ctx.sphere_point_light(name, Integrator::Whitted),
        "emitting_box" => ctx.emitting_box(name, Integrator::Path),
        "emitting_box_whitted" => ctx.emitting_box(name, Integrator::Whitted),
        "sphere_under_sky" => ctx.sphere_under_sky(name),
        _ => Err(ValidateError::Input(format!(
            "unknown closed-form case \"{name}\"; known: {}",
            CASES.join(", ")
        ))),
    }
}

/// The albedo ρ(λ) of every diffuse surface: 0.3 in the violet to 0.7 in the red, so that the
/// series Σρᵏ differs by a factor of 2.3 across the spectrum (a renderer that summed it for one
/// mean albedo, or mixed the lanes, would be off in X and Z against Y).
const ALBEDO: [(f64, f64); 5] = [(360.0, 0.3), (450.0, 0.35), (550.0, 0.5), (650.0, 0.65), (830.0, 0.7)];
/// The point light's intensity I(λ), W·sr⁻¹·nm⁻¹ (π at 550 nm, as in the numbers).
const INTENSITY: [(f64, f64); 3] = [(360.0, 4.0), (550.0, std::f64::consts::PI), (830.0, 2.0)];
/// The box's emitted radiance Le(λ), W·m⁻²·sr⁻¹·nm⁻¹.
const EMISSION: [(f64, f64); 3] = [(360.0, 0.5), (500.0, 1.2), (830.0, 0.8)];
/// The sky's radiance L_bg(λ), W·m⁻²·sr⁻¹·nm⁻¹.
const SKY: [(f64, f64); 3] = [(360.0, 1.5), (560.0, 0.6), (830.0, 1.0)];

/// A piecewise-linear table's value at `lambda_nm`, held constant beyond its ends (as scene
/// files read `table` spectra), evaluated here in f64 independently of prisma's spectra.
fn table_at(table: &[(f64, f64)], lambda_nm: f64) -> f64 {
    let (first, last) = (table[0], table[table.len() - 1]);
    if lambda_nm <= first.0 {
        return first.1;
    }
    if lambda_nm >= last.0 {
        return last.1;
    }
    let right = table.iter().position(|&(l, _)| l >= lambda_nm).unwrap_or(table.len() - 1);
    let ((l0, v0), (l1, v1)) = (table[right - 1], table[right]);
    v0 + (v1 - v0) * (lambda_nm - l0) / (l1 - l0)
}

/// The table as a scene file's spectrum.
fn table_text(table: &[(f64, f64)]) -> String {
    let points: Vec<String> = table.iter().map(|(l, v)| format!("[{l}, {v}]")).collect();
    format!("{{ table = [{}] }}", points.join(", "))
}

/// The XYZ of the spectral closed form `radiance(λ)` (λ in nm), by the trapezoid rule at every
/// whole nm against prisma's CIE table.
fn expected_xyz(radiance: impl Fn(f64) -> f64) -> [f64; 3] {
    let xyz = xyz_by_quadrature(|lambda_nm| radiance(f64::from(lambda_nm)) as f32);
    [f64::from(xyz.x), f64::from(xyz.y), f64::from(xyz.z)]
}

/// The estimator a case renders with.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Integrator {
    Path,
    Whitted,
}

impl Integrator {
    fn name(self) -> &'static str {
        match self {
            Integrator::Path => "path",
            Integrator::Whitted => "whitted",
        }
    }
}

/// What a region of the image may differ from its closed form, from the measured noise (the
/// causes are written in `validation/README.md`).
#[derive(Clone, Copy)]
struct Tolerance {
    /// Largest |mean/expected − 1| of the region's mean, per X, Y, Z.
    mean: f64,
    /// Largest |Y/expected − 1| of any one pixel; `None` where the noise has no useful bound
    /// (heavy tails, see [`Context::emitting_box`]).
    pixel: Option<f64>,
}

/// Largest |z| of a region's mean against its closed form, the noise being measured from the
/// pixels' spread (every pixel of a region has the same expectation): the image-wide mean
/// test of the Mitsuba cases, with no allowance.
const MAX_MEAN_Z: f64 = 5.0;

/// Largest |S_k|/S0 (k = 1–3, in Y) of any pixel: diffuse surfaces depolarise and every light
/// is unpolarised, so S1–S3 are zero but for float rounding (a polarised beam that leaked
/// through a diffuse vertex would show at 10⁻² and more).
const MAX_POLARIZATION: f64 = 1e-6;

/// The deepest path: the light of the bounces beyond it is at most ρ_max³¹ = 0.7³¹ ≈ 1.6·10⁻⁵
/// of the answer, 20 times below the noise of the means (Russian roulette ends nearly every
/// path long before), and under a fault that inflates the throughput (`no-diffuse-cosine`:
/// roulette then never ends a path) the cap bounds the cost. Whitted reads it as its specular
/// depth, of which these scenes have none.
const MAX_DEPTH: u32 = 32;

struct Context {
    threads: usize,
    fault: Option<Fault>,
}

impl Context {
    /// Renders the scene `text` in colour, or at the one wavelength `monochromatic_nm`.
    fn render(&self, text: &str, name: &str, monochromatic_nm: Option<f32>) -> Result<Film, ValidateError> {
        let scene: Scene =
            parse(text, Path::new(&format!("<{name}>"))).map_err(|e| ValidateError::Input(e.to_string()))?;
        let job = Job {
            threads: self.threads,
            fault: self.fault,
            monochromatic_nm,
            ..Job::new(scene.settings.clone())
        };
        Ok(render(&scene, &job)?.0)
    }

    /// A point light at the centre of a closed diffuse sphere (r = 1), seen from inside.
    fn sphere_point_light(&self, name: &str, integrator: Integrator) -> Result<CaseResult, ValidateError> {
        let radius = 1.0f64;
        let (spp, tolerance) = match integrator {
            Integrator::Path => (256, Tolerance { mean: 2e-3, pixel: Some(0.06) }),
            Integrator::Whitted => (16, Tolerance { mean: 1e-4, pixel: Some(1e-3) }),
        };
        let text = format!(
            "[camera]\nposition = [0.2, -0.1, -0.3]\nlook_at = [0.5, 0.3, 1]\nfov_y_deg = 90\nwidth = 32\nheight = 32\n\
             [render]\nintegrator = \"{integrator}\"\nspp = {spp}\nmax_depth = {MAX_DEPTH}\nseed = 7\n\
             [materials.wall]\ntype = \"diffuse\"\nalbedo = {albedo}\n\
             [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = {radius}\nmaterial = \"wall\"\n\
             [[lights]]\ntype = \"point\"\nposition = [0, 0, 0]\nintensity = {intensity}\n",
            integrator = integrator.name(),
            albedo = table_text(&ALBEDO),
            intensity = table_text(&INTENSITY),
        );
        let film = self.render(&text, name, None)?;
        let direct = |l: f64| {
            table_at(&ALBEDO, l) * table_at(&INTENSITY, l) / (std::f64::consts::PI * radius * radius)
        };
        let full = |l: f64| direct(l) / (1.0 - table_at(&ALBEDO, l));
        let all: Vec<usize> = (0..film.xyz().len()).collect();
        let mut checks = Vec::new();
        let why = match integrator {
            Integrator::Path => {
                checks.extend(compare("wall", &film, &all, expected_xyz(full), tolerance));
                "a point light at the centre of a closed diffuse sphere, full transport: every pixel \
                 ρI/(πr²(1 − ρ)), per wavelength (ρ 0.3–0.7, I 2–4), in XYZ"
                    .to_owned()
            }
            Integrator::Whitted => {
                let expected = expected_xyz(direct);
                checks.extend(compare("wall", &film, &all, expected, tolerance));
                // The fraction of the full answer Whitted leaves out, measured in Y.
                let mean_y = all.iter().map(|&i| f64::from(film.xyz()[i].y)).sum::<f64>() / all.len() as f64;
                let left_out = 1.0 - mean_y / expected_xyz(full)[1];
                format!(
                    "a point light at the centre of a closed diffuse sphere, Whitted: the direct term \
                     ρI/(πr²) alone, per wavelength, in XYZ; it leaves out {:.1} % of the light in Y \
                     (the full answer is ρI/(πr²(1 − ρ)))",
                    100.0 * left_out
                )
            }
        };
        checks.push(polarization(&film, &all));
        // The numbers at one wavelength: ρ(550 nm) = ½ and I(550 nm) = π make the full
        // answer exactly 1 and Whitted's ½.
        let mono = self.render(&text, name, Some(550.0))?;
        // The path tracer's one-wavelength noise is Russian roulette's alone, 1.6 % per pixel
        // (more than the colour render's 0.9 %); Whitted's direct term has none (f32 rounding).
        let (at_550, tolerance) = match integrator {
            Integrator::Path => (full(550.0), Tolerance { mean: 3e-3, pixel: Some(0.1) }),
            Integrator::Whitted => (direct(550.0), Tolerance { mean: 1e-6, pixel: Some(1e-6) }),
        };
        checks.extend(compare("550 nm", &mono, &all, [at_550; 3], tolerance));
        Ok(CaseResult { name: name.into(), checks, why })
    }

    /// A closed cube [−1, 1]³ of six quad lights emitting Le inward, each of albedo ρ, seen from
    /// inside (a corner in view, where three walls meet).
    fn emitting_box(&self, name: &str, integrator: Integrator) -> Result<CaseResult, ValidateError> {
        let (spp, tolerance) = match integrator {
            Integrator::Path => (128, Tolerance { mean: 2e-3, pixel: Some(0.06) }),
            // Whitted samples each wall by area: near the edge a wall shares with another, the
            // other's 1/d² makes the estimate heavy-tailed (pixels on the edges 1.5× off at 16
            // spp), so only the mean is bounded.
            Integrator::Whitted => (16, Tolerance { mean: 1e-2, pixel: None }),
        };
        // (outward normal, up) per wall; edge1 × edge2 is the outward normal, so the walls emit
        // along edge2 × edge1.
        let walls: [([i32; 3], [i32; 3]); 6] = [
            ([0, 0, 1], [0, 1, 0]),
            ([0, 0, -1], [0, 1, 0]),
            ([1, 0, 0], [0, 1, 0]),
            ([-1, 0, 0], [0, 1, 0]),
            ([0, 1, 0], [0, 0, 1]),
            ([0, -1, 0], [0, 0, 1]),
        ];
        let mut lights = String::new();
        for (n, up) in walls {
            let side =
                [up[1] * n[2] - up[2] * n[1], up[2] * n[0] - up[0] * n[2], up[0] * n[1] - up[1] * n[0]];
            let corner: Vec<i32> = (0..3).map(|k| n[k] - side[k] - up[k]).collect();
            lights += &format!(
                "[[lights]]\ntype = \"quad\"\ncorner = {corner:?}\nedge1 = {:?}\nedge2 = {:?}\nradiance = {}\n\
                 emit = \"edge2_cross_edge1\"\nalbedo = {}\n",
                side.map(|c| 2 * c),
                up.map(|c| 2 * c),
                table_text(&EMISSION),
                table_text(&ALBEDO),
            );
        }
        let text = format!(
            "[camera]\nposition = [0.2, 0.1, -0.4]\nlook_at = [1, 1, 1]\nfov_y_deg = 100\nwidth = 32\nheight = 32\n\
             [render]\nintegrator = \"{integrator}\"\nspp = {spp}\nmax_depth = {MAX_DEPTH}\nseed = 7\n{lights}",
            integrator = integrator.name(),
        );
        let film = self.render(&text, name, None)?;
        let all: Vec<usize> = (0..film.xyz().len()).collect();
        let (expected, why) = match integrator {
            Integrator::Path => (
                expected_xyz(|l| table_at(&EMISSION, l) / (1.0 - table_at(&ALBEDO, l))),
                "a closed cube of six quad lights emitting Le inward with albedo ρ, full transport: \
                 every pixel Le/(1 − ρ), per wavelength (ρ 0.3–0.7), in XYZ",
            ),
            Integrator::Whitted => (
                expected_xyz(|l| table_at(&EMISSION, l) * (1.0 + table_at(&ALBEDO, l))),
                "a closed cube of six quad lights emitting Le inward with albedo ρ, Whitted: the \
                 emission and one bounce of direct light, Le(1 + ρ), per wavelength, in XYZ",
            ),
        };
        let mut checks = compare("walls", &film, &all, expected, tolerance);
        checks.push(polarization(&film, &all));
        Ok(CaseResult { name: name.into(), checks, why: why.into() })
    }

    /// A diffuse sphere (r = 1) alone under a uniform sky, seen from 4 units away: the pixels
    /// wholly on the sphere and wholly on the sky are compared, those the silhouette crosses
    /// are left out.
    fn sphere_under_sky(&self, name: &str) -> Result<CaseResult, ValidateError> {
        let (size, fov_y_deg, distance, radius) = (32u32, 40.0f64, 4.0f64, 1.0f64);
        let text = format!(
            "background = {sky}\n\
             [camera]\nposition = [0, 0, -{distance}]\nlook_at = [0, 0, 0]\nfov_y_deg = {fov_y_deg}\nwidth = {size}\nheight = {size}\n\
             [render]\nintegrator = \"path\"\nspp = 256\nmax_depth = {MAX_DEPTH}\nseed = 7\n\
             [materials.ball]\ntype = \"diffuse\"\nalbedo = {albedo}\n\
             [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = {radius}\nmaterial = \"ball\"\n",
            sky = table_text(&SKY),
            albedo = table_text(&ALBEDO),
        );
        let film = self.render(&text, name, None)?;
        // The sphere's silhouette is the cone of half-angle asin(r/d) about the view axis; a
        // pixel's rays lie within the tangent-plane size of a pixel of its centre's ray
        // (angles grow no faster than their tangents).
        let tan_half = (fov_y_deg.to_radians() / 2.0).tan();
        let pixel_tan = 2.0 * tan_half / f64::from(size);
        let silhouette = (radius / distance).asin();
        let (mut ball, mut sky) = (Vec::new(), Vec::new());
        for i in 0..film.xyz().len() {
            let (x, y) = ((i % size as usize) as f64 + 0.5, (i / size as usize) as f64 + 0.5);
            let u = (2.0 * x / f64::from(size) - 1.0) * tan_half;
            let v = (1.0 - 2.0 * y / f64::from(size)) * tan_half;
            let angle = (u * u + v * v).sqrt().atan();
            if angle < silhouette - pixel_tan {
                ball.push(i);
            } else if angle > silhouette + pixel_tan {
                sky.push(i);
            }
        }
        if ball.is_empty() || sky.is_empty() {
            return Err(ValidateError::Input(format!("{name}: no pixel wholly on the sphere or the sky")));
        }
        let mut checks = compare(
            "sphere",
            &film,
            &ball,
            expected_xyz(|l| table_at(&ALBEDO, l) * table_at(&SKY, l)),
            Tolerance { mean: 2e-3, pixel: Some(0.06) },
        );
        checks.extend(compare(
            "sky",
            &film,
            &sky,
            expected_xyz(|l| table_at(&SKY, l)),
            // Only the wavelengths' sampling is noisy on the sky.
            Tolerance { mean: 1e-4, pixel: Some(1e-3) },
        ));
        let all: Vec<usize> = ball.iter().chain(&sky).copied().collect();
        checks.push(polarization(&film, &all));
        Ok(CaseResult {
            name: name.into(),
            checks,
            why: "a diffuse sphere alone under a uniform sky, full transport: ρ·L_bg on the sphere \
                  (irradiance π·L_bg over a convex surface), L_bg on the sky, per wavelength, in XYZ"
                .into(),
        })
    }
}

/// The checks of the pixels `pixels` of `film` against the closed form `expected` (XYZ): the
/// region's mean relative to it and as a z-score of the noise measured from the pixels' spread,
/// and the worst pixel in Y.
fn compare(
    label: &str,
    film: &Film,
    pixels: &[usize],
    expected: [f64; 3],
    tolerance: Tolerance,
) -> Vec<Check> {
    let xyz = film.xyz();
    let component = |p: Vec3, k: usize| f64::from(p[k]);
    let count = pixels.len() as f64;
    let (mut worst_relative, mut worst_z) = (0.0f64, 0.0f64);
    for (k, &expected_k) in expected.iter().enumerate() {
        let mean = pixels.iter().map(|&i| component(xyz[i], k)).sum::<f64>() / count;
        let variance = pixels.iter().map(|&i| (component(xyz[i], k) - mean).powi(2)).sum::<f64>()
            / (count - 1.0).max(1.0);
        // The standard error of the mean, with a floor for f32 rounding of noiseless pixels.
        let standard_error = (variance / count + (1e-6 * expected_k).powi(2)).sqrt();
        let relative = (mean / expected_k - 1.0).abs();
        let z = ((mean - expected_k) / standard_error).abs();
        worst_relative = worst_relative.max(if relative.is_nan() { f64::INFINITY } else { relative });
        worst_z = worst_z.max(if z.is_nan() { f64::INFINITY } else { z });
    }
    let worst_pixel = pixels
        .iter()
        .map(|&i| {
            let error = (f64::from(xyz[i].y) / expected[1] - 1.0).abs();
            if error.is_nan() {
                f64::INFINITY
            } else {
                error
            }
        })
        .fold(0.0, f64::max);
    let mut checks = vec![
        Check {
            metric: format!("{label}: max |mean/expected − 1| (X, Y, Z)"),
            value: worst_relative,
            threshold: tolerance.mean,
        },
        Check {
            metric: format!("{label}: max |z| of the mean (X, Y, Z)"),
            value: worst_z,
            threshold: MAX_MEAN_Z,
        },
    ];
    if let Some(threshold) = tolerance.pixel {
        checks.push(Check {
            metric: format!("{label}: max pixel |Y/expected − 1|"),
            value: worst_pixel,
            threshold,
        });
    }
    checks
}

/// The largest |S_k|/S0 (k = 1–3, in Y) over `pixels`: infinite when the film holds no Stokes
/// components (a polarised render was asked for).
fn polarization(film: &Film, pixels: &[usize]) -> Check {
    let s0 = film.xyz();
    let mut worst = 0.0f64;
    for k in 1..4 {
        let Some(component) = film.stokes_xyz(k) else {
            worst = f64::INFINITY;
            break;
        };
        for &i in pixels {
            // A black pixel (S0 = 0) is unpolarised when S1–S3 are zero too.
            let (s_k, s_0) = (f64::from(component[i].y), f64::from(s0[i].y));
            let ratio = if s_k == 0.0 { 0.0 } else { (s_k / s_0).abs() };
            worst = worst.max(if ratio.is_nan() { f64::INFINITY } else { ratio });
        }
    }
    Check {
        metric: "max |S1|, |S2|, |S3| / S0 (Y, any pixel)".into(),
        value: worst,
        threshold: MAX_POLARIZATION,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tables are read as scene files read them: linear between points, constant beyond.
    #[test]
    fn tables_are_piecewise_linear_and_held_beyond_their_ends() {
        assert_eq!(table_at(&ALBEDO, 300.0), 0.3);
        assert_eq!(table_at(&ALBEDO, 900.0), 0.7);
        assert!((table_at(&ALBEDO, 500.0) - 0.425).abs() < 1e-12);
        assert_eq!(table_at(&ALBEDO, 550.0), 0.5);
    }

    /// An equal-energy spectrum of 1 has XYZ ≈ (1, 1, 1) under prisma's normalisation (Y exactly
    /// 1; X and Z within 0.1 %: the E illuminant's white point), and the closed form scales it.
    #[test]
    fn expected_xyz_of_a_flat_spectrum() {
        let [x, y, z] = expected_xyz(|_| 2.0);
        assert!((y - 2.0).abs() < 1e-5, "{y}");
        assert!((x / 2.0 - 1.0).abs() < 2e-3 && (z / 2.0 - 1.0).abs() < 2e-3, "{x} {z}");
    }
}
