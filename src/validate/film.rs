//! The soap-film colour (issue 41): a flat free-standing film of water (n = 1.333) seen at normal
//! incidence against a uniform white emitter (radiance 1 at every wavelength, behind the camera)
//! on black has the colour of its reflectance spectrum: XYZ = ∫ R(λ)·(x̄, ȳ, z̄)(λ) dλ under
//! prisma's normalisation (an equal-energy radiance of 1 has Y = 1), with R from Airy's sum for
//! one layer in air at normal incidence (Born & Wolf §7.6.1), written here in f64 apart from
//! prisma's transfer matrices:
//!
//! ```text
//! r = (n − 1)/(n + 1) at each face (−r at the front, +r at the back, seen from the air)
//! r_film = −r (1 − e^{−2iβ}) / (1 − r² e^{−2iβ}),   β = 2π n d / λ,   R = |r_film|²
//! ```
//!
//! Five thicknesses from the first-order white to the fifth-order pinks; the render samples
//! wavelengths (8 lanes × 256 samples per pixel, stratified over the visible), the reference
//! integrates by quadrature at every whole nm, and the difference is the sampling's.

use std::f64::consts::TAU;
use std::path::Path;

use super::{CaseResult, Check, ValidateError};
use crate::integrator::Fault;
use crate::render::{render, Job};
use crate::scene::parse;
use crate::spectrum::cie::xyz_by_quadrature;

/// Names of the film cases, in the order [`run`] runs them.
pub const CASES: [&str; 1] = ["soap_film_colour"];

/// The film's index (constant, so that the reference needs no dispersion law).
const WATER: f64 = 1.333;
/// Film thicknesses checked, in nm: first-order white, purple, second-order green, blue, pink.
const THICKNESSES_NM: [f64; 5] = [120.0, 200.0, 300.0, 450.0, 700.0];
/// The brightest a water film gets, ((n² − 1)/(n² + 1))²: the scale of the colour errors.
fn brightest() -> f64 {
    ((WATER * WATER - 1.0) / (WATER * WATER + 1.0)).powi(2)
}

/// Runs the film case `name` with `threads` threads and an optional injected `fault`.
pub fn run(name: &str, threads: usize, fault: Option<Fault>) -> Result<CaseResult, ValidateError> {
    match name {
        "soap_film_colour" => soap_film_colour(name, threads, fault),
        _ => Err(ValidateError::Input(format!("unknown film case \"{name}\"; known: {}", CASES.join(", ")))),
    }
}

/// Airy's reflectance of the water film of `thickness_nm` at normal incidence and `lambda_nm`.
fn reference_reflectance(thickness_nm: f64, lambda_nm: f64) -> f64 {
    let r = (WATER - 1.0) / (WATER + 1.0);
    let beta = TAU * WATER * thickness_nm / lambda_nm;
    // e^{−2iβ} as (cos 2β, −sin 2β); r_film = −r (1 − e) / (1 − r² e).
    let (e_re, e_im) = ((2.0 * beta).cos(), -(2.0 * beta).sin());
    let (num_re, num_im) = (-r * (1.0 - e_re), r * e_im);
    let (den_re, den_im) = (1.0 - r * r * e_re, -r * r * e_im);
    (num_re * num_re + num_im * num_im) / (den_re * den_re + den_im * den_im)
}

fn soap_film_colour(name: &str, threads: usize, fault: Option<Fault>) -> Result<CaseResult, ValidateError> {
    let mut worst = 0.0_f64;
    for thickness_nm in THICKNESSES_NM {
        // The camera looks along +z at the film on z = 0 through a 1° view (cos θ ≥ 0.99996: the
        // film's phase differs from normal incidence's by < 10⁻³ rad); the emitter faces the
        // film from behind the camera, which does not block it.
        let text = format!(
            "background = 0\n[camera]\nposition = [0, 0, -10]\nlook_at = [0, 0, 0]\nfov_y_deg = 1\nwidth = 8\nheight = 8\n\
             [render]\nspp = 256\nmax_depth = 4\nprune_below = 0\nseed = 3\n\
             [materials.soap]\ntype = \"film\"\nior = {WATER}\nthickness_nm = {thickness_nm}\n\
             [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, -1]\nmaterial = \"soap\"\n\
             [[lights]]\ntype = \"quad\"\ncorner = [-5000, -5000, -20]\nedge1 = [10000, 0, 0]\nedge2 = [0, 10000, 0]\n\
             radiance = 1\nemit = \"edge1_cross_edge2\"\n"
        );
        let scene =
            parse(&text, Path::new(&format!("<{name}>"))).map_err(|e| ValidateError::Input(e.to_string()))?;
        let job = Job { threads, fault, ..Job::new(scene.settings.clone()) };
        let film = render(&scene, &job)?.0;
        let count = film.xyz().len() as f64;
        let mean = film.xyz().iter().fold([0.0_f64; 3], |sum, p| {
            [
                sum[0] + f64::from(p.x) / count,
                sum[1] + f64::from(p.y) / count,
                sum[2] + f64::from(p.z) / count,
            ]
        });
        let expected =
            xyz_by_quadrature(|lambda_nm| reference_reflectance(thickness_nm, f64::from(lambda_nm)) as f32);
        let expected = [f64::from(expected.x), f64::from(expected.y), f64::from(expected.z)];
        let error =
            (0..3).map(|k| (mean[k] - expected[k]).abs()).fold(0.0_f64, |a, b| a.max(b)) / brightest();
        // NaN counts as a failure.
        worst = if error.is_nan() { f64::INFINITY } else { worst.max(error) };
    }
    Ok(CaseResult {
        name: name.into(),
        checks: vec![Check {
            metric: "max |ΔXYZ| / brightest Y".into(),
            value: worst,
            // Measured 7.9·10⁻⁵ (wavelength sampling); an index 1 % high moves the 700 nm
            // film's phase by 0.2 rad: 7.6·10⁻² (`--fault ior-plus1-percent`).
            threshold: 2e-3,
        }],
        why: "a water film (n = 1.333) at normal incidence against a white emitter: XYZ of Airy's R(λ), 120–700 nm thick"
            .into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference: zero for a vanishing film, ((n² − 1)/(n² + 1))² at a quarter wave, zero
    /// again at a half wave (Born & Wolf §7.6.1).
    #[test]
    fn the_reference_meets_its_limits() {
        assert_eq!(reference_reflectance(0.0, 550.0), 0.0);
        let quarter = reference_reflectance(550.0 / (4.0 * WATER), 550.0);
        assert!((quarter - brightest()).abs() < 1e-15, "{quarter}");
        assert!(reference_reflectance(550.0 / (2.0 * WATER), 550.0) < 1e-20);
    }
}
