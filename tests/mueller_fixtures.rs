//! prisma's Mueller matrices and Stokes frame rotations against Mitsuba 3.9.1's own functions,
//! row by row (fixtures written by `validation/mitsuba/mueller_fixtures.py`, whose docstring
//! records the columns and conventions; float32, `scalar_rgb`).
//!
//! Conventions mapped explicitly:
//! - `mi.mueller.specular_reflection(cos θi, η)` is written in the s frame of the incidence, as
//!   prisma's reflection matrices are (`JonesDiagonal::dielectric_reflection` for real η,
//!   `JonesDiagonal::new` of `fresnel_conductor_amplitudes` for complex η given as n + ik):
//!   identity mapping, phases of total internal reflection and of metals included.
//! - `mi.mueller.specular_transmission` is the flux matrix without the 1/η² radiance factor, as
//!   `JonesDiagonal::dielectric_transmission`.
//! - `mi.fresnel_polarized` with complex η: prisma's `fresnel_conductor_amplitudes` (both take
//!   n + ik and use n − ik inside, the e^{+iωt} convention).
//! - `mi.mueller.rotate_stokes_basis(forward, current, target)`: prisma's
//!   `Rotation::between(forward, current, target)`; `mi.mueller.rotator(θ)`:
//!   `Rotation::by_angle(θ)`.
//! - `mi.mueller.rotated_element(θ, M)` = Rᵀ(θ)·M·R(θ): prisma turns the frame by θ, applies the
//!   element, and turns back. Mitsuba 3.9.1's `linear_retarder(δ)` is
//!   [[1,0,0,0],[0,1,0,0],[0,0,cos δ,sin δ],[0,0,−sin δ,cos δ]]: prisma's retarder with its fast
//!   axis along x, the field along x leading by δ (older Mitsuba sources documented the fast axis
//!   as vertical, with the opposite sign of sin δ; the fixture is what 3.9.1 computes).
//! - The ideal mirror: Mitsuba's conductor of η = 0 + 10¹⁴i, the parameterisation the translation
//!   gives Mitsuba for prisma's perfect conductor, against `JonesDiagonal::PERFECT_CONDUCTOR`
//!   (prisma's scenes bound |n + ik| by 1000, far from where its float32 formulas overflow).

mod common;

use common::{read_fixture, read_fixture_fields, Comparison};
use glam::Vec3;
use num_complex::Complex32;
use prisma::optics::{fresnel_conductor_amplitudes, fresnel_dielectric};
use prisma::polarization::mueller::JonesDiagonal;
use prisma::polarization::{Mueller, Rotation, Stokes};
use prisma::spectrum::SampledSpectrum;

/// Largest absolute difference on any matrix entry: float32 arithmetic in both.
const TOLERANCE: f32 = 2e-5;
/// Rows whose k exceeds this stand for the ideal mirror (see the module documentation).
const PERFECT_CONDUCTOR_K: f32 = 1e6;

fn matrix_columns() -> String {
    (0..16).map(|i| format!("m{}{}", i / 4, i % 4)).collect::<Vec<_>>().join(",")
}

/// The 4×4 matrix of a linear map of Stokes vectors, column by column from the basis vectors.
fn matrix_of(map: impl Fn(Stokes) -> Stokes) -> [[f32; 4]; 4] {
    let mut matrix = [[0.0; 4]; 4];
    for column in 0..4 {
        let mut basis = Stokes::zero();
        basis.s[column] = SampledSpectrum::splat(1.0);
        let image = map(basis);
        for (row, line) in matrix.iter_mut().enumerate() {
            line[column] = image.s[row][0];
        }
    }
    matrix
}

fn compare_matrix(comparison: &mut Comparison, prisma: [[f32; 4]; 4], mitsuba: &[f32], context: &str) {
    const NAMES: [&str; 16] = [
        "m00", "m01", "m02", "m03", "m10", "m11", "m12", "m13", "m20", "m21", "m22", "m23", "m30", "m31",
        "m32", "m33",
    ];
    for (index, name) in NAMES.iter().enumerate() {
        comparison.check(name, prisma[index / 4][index % 4], mitsuba[index], context);
    }
    comparison.rows += 1;
}

/// Within a few ulps of the critical angle cos θt = √(cos² θt) turns one rounding into errors
/// of 1e-3 whatever the evaluation (Mitsuba's own `fresnel` and `fresnel_polarized` disagree
/// there, `tests/fresnel_fixtures.rs`); those rows are compared with a tolerance of 2e-3.
fn near_critical(cos_theta_i: f32, eta: f32) -> bool {
    let eta_it = if cos_theta_i >= 0.0 { eta } else { 1.0 / eta };
    eta_it < 1.0 && ((1.0 - cos_theta_i * cos_theta_i).sqrt() - eta_it).abs() < 1e-4
}

#[test]
fn reflection_matrices_match_mitsuba() {
    let rows =
        read_fixture("mueller_reflection.csv", &format!("cos_theta_i,eta_re,eta_im,{}", matrix_columns()));
    let mut comparison = Comparison::new(TOLERANCE);
    let mut critical = Comparison::new(2e-3);
    for row in &rows {
        let (cos_theta_i, eta_re, eta_im) = (row[0], row[1], row[2]);
        let context = format!("cos θi = {cos_theta_i}, η = {eta_re} + {eta_im}i");
        let element = if eta_im == 0.0 {
            JonesDiagonal::dielectric_reflection(cos_theta_i, &fresnel_dielectric(cos_theta_i, eta_re))
        } else if eta_im > PERFECT_CONDUCTOR_K {
            JonesDiagonal::PERFECT_CONDUCTOR
        } else {
            let (r_s, r_p) = fresnel_conductor_amplitudes(cos_theta_i, Complex32::new(eta_re, eta_im));
            JonesDiagonal::new(r_s, r_p)
        };
        let target =
            if eta_im == 0.0 && near_critical(cos_theta_i, eta_re) { &mut critical } else { &mut comparison };
        compare_matrix(target, Mueller::splat(element).matrix(0), &row[3..], &context);
    }
    comparison.finish("mueller_reflection.csv");
    critical.finish("mueller_reflection.csv (within 1e-4 of the critical angle)");
}

#[test]
fn transmission_matrices_match_mitsuba() {
    let rows = read_fixture("mueller_transmission.csv", &format!("cos_theta_i,eta,{}", matrix_columns()));
    let mut comparison = Comparison::new(TOLERANCE);
    let mut critical = Comparison::new(2e-3);
    for row in &rows {
        let (cos_theta_i, eta) = (row[0], row[1]);
        let context = format!("cos θi = {cos_theta_i}, η = {eta}");
        let element = JonesDiagonal::dielectric_transmission(&fresnel_dielectric(cos_theta_i, eta));
        let target = if near_critical(cos_theta_i, eta) { &mut critical } else { &mut comparison };
        compare_matrix(target, Mueller::splat(element).matrix(0), &row[2..], &context);
    }
    comparison.finish("mueller_transmission.csv");
    critical.finish("mueller_transmission.csv (within 1e-4 of the critical angle)");
}

#[test]
fn conductor_amplitudes_match_mitsuba() {
    let rows = read_fixture(
        "fresnel_conductor_amplitudes.csv",
        "cos_theta_i,eta_re,eta_im,a_s_re,a_s_im,a_p_re,a_p_im,cos_theta_t,eta_it_re,eta_it_im,eta_ti_re,eta_ti_im",
    );
    let mut comparison = Comparison::new(TOLERANCE);
    for row in rows.iter().filter(|row| row[2] <= PERFECT_CONDUCTOR_K) {
        let (cos_theta_i, eta) = (row[0], Complex32::new(row[1], row[2]));
        let context = format!("cos θi = {cos_theta_i}, η = {eta}");
        let (r_s, r_p) = fresnel_conductor_amplitudes(cos_theta_i, eta);
        comparison.check("Re r_s", r_s.re, row[3], &context);
        comparison.check("Im r_s", r_s.im, row[4], &context);
        comparison.check("Re r_p", r_p.re, row[5], &context);
        comparison.check("Im r_p", r_p.im, row[6], &context);
        comparison.rows += 1;
    }
    comparison.finish("fresnel_conductor_amplitudes.csv");
}

#[test]
fn frame_rotations_match_mitsuba() {
    let rows = read_fixture("mueller_rotator.csv", &format!("theta_rad,{}", matrix_columns()));
    let mut comparison = Comparison::new(TOLERANCE);
    for row in &rows {
        let rotation = Rotation::by_angle(row[0]);
        compare_matrix(
            &mut comparison,
            matrix_of(|s| s.rotated(rotation)),
            &row[1..],
            &format!("θ = {}", row[0]),
        );
    }
    comparison.finish("mueller_rotator.csv");

    let columns = "forward_x,forward_y,forward_z,current_x,current_y,current_z,target_x,target_y,target_z";
    let rows = read_fixture("mueller_rotations.csv", &format!("{columns},{}", matrix_columns()));
    let mut comparison = Comparison::new(TOLERANCE);
    for row in &rows {
        let vector = |i: usize| Vec3::new(row[i], row[i + 1], row[i + 2]);
        let (forward, current, target) = (vector(0), vector(3), vector(6));
        let rotation = Rotation::between(forward, current, target);
        let context = format!("forward {forward}, {current} → {target}");
        compare_matrix(&mut comparison, matrix_of(|s| s.rotated(rotation)), &row[9..], &context);
    }
    comparison.finish("mueller_rotations.csv");
}

#[test]
fn polariser_and_retarder_match_mitsuba() {
    let rows = read_fixture_fields(
        "mueller_elements.csv",
        &format!("element,parameter,theta_rad,{}", matrix_columns()),
        1,
    );
    let mut comparison = Comparison::new(TOLERANCE);
    for (names, row) in &rows {
        let (parameter, theta) = (row[0], row[1]);
        let jones = match names[0].as_str() {
            "linear_polarizer" => JonesDiagonal::linear_polarizer(parameter),
            "linear_retarder" => JonesDiagonal::linear_retarder(parameter),
            other => panic!("mueller_elements.csv: unknown element {other}"),
        };
        let (turn_in, turn_out) = (Rotation::by_angle(theta), Rotation::by_angle(-theta));
        let prisma = matrix_of(|s| Mueller::splat(jones).apply(&s.rotated(turn_in)).rotated(turn_out));
        compare_matrix(
            &mut comparison,
            prisma,
            &row[2..],
            &format!("{}, {parameter}, θ = {theta}", names[0]),
        );
    }
    comparison.finish("mueller_elements.csv");
}
