//! prisma's Fresnel functions against Mitsuba 3.9.1's, row by row.
//!
//! The fixtures in `tests/fixtures/fresnel_*.csv` were written by
//! `validation/mitsuba/fresnel_fixtures.py` (Mitsuba's `scalar_rgb` variant, float32); each file's
//! `#` header records the versions, the date and the command. Every row must agree to within
//! [`TOLERANCE`] (absolute). Run with `cargo test --test fresnel_fixtures -- --nocapture` to see
//! the largest difference of each quantity and the row where it occurs.
//!
//! Conventions mapped explicitly:
//! - `mi.fresnel` returns (F, cos_theta_t, eta_it, eta_ti); prisma's `fresnel_dielectric`
//!   returns the same F, signed cos_theta_t and eta_it (eta_ti = 1/eta_it). Identity mapping.
//! - `mi.fresnel_polarized` returns amplitudes a_s, a_p in the "Verdet convention",
//!   a_p = (eta_it cos θi − cos θt)/(eta_it cos θi + cos θt), which is Hecht's r∥; a_s is
//!   Hecht's r⊥. prisma uses Hecht's signs, so a_s ↦ r_s and a_p ↦ r_p with no sign change
//!   (`P_SIGN_MITSUBA_TO_PRISMA` = +1 below). Under total internal reflection both take
//!   cos θt = −i √(…), so the complex phases agree too.
//! - `mi.fresnel_conductor(cos θi, η)` returns the unpolarised reflectance for η = n + ik;
//!   prisma's `fresnel_conductor(cos θi, η).reflectance`. Identity mapping.
//!
//! Near the critical angle R and cos θt are so ill-conditioned that Mitsuba's own `fresnel` and
//! `fresnel_polarized` disagree with each other by up to 1e-3 (they round cos² θt differently).
//! prisma's `fresnel_dielectric` rounds like the former and `fresnel_dielectric_amplitudes` like
//! the latter, which is why every row of both fixtures can be held to 1e-5. The real-valued
//! `DielectricFresnel::r_s`/`r_p` have no Mitsuba counterpart with their rounding; they are
//! compared with `fresnel_polarized` where that rounding cannot matter (see the test).

mod common;

use common::{read_fixture, Comparison};
use num_complex::Complex32;
use prisma::optics::{fresnel_conductor, fresnel_dielectric, fresnel_dielectric_amplitudes};

/// Largest absolute difference allowed on any quantity of any row.
const TOLERANCE: f32 = 1e-5;

#[test]
fn dielectric_reflectance_matches_mitsuba() {
    let rows =
        read_fixture("fresnel_dielectric.csv", "cos_theta_i,eta,reflectance,cos_theta_t,eta_it,eta_ti");
    let mut comparison = Comparison::new(TOLERANCE);
    for row in &rows {
        let &[cos_theta_i, eta, reflectance, cos_theta_t, eta_it, eta_ti] = row.as_slice() else {
            unreachable!("read_fixture checks the row width")
        };
        let context = format!("cos θi = {cos_theta_i}, eta = {eta}");
        let fresnel = fresnel_dielectric(cos_theta_i, eta);
        comparison.check("R", fresnel.reflectance, reflectance, &context);
        comparison.check("cos θt", fresnel.cos_theta_t, cos_theta_t, &context);
        comparison.check("eta_it", fresnel.eta_it, eta_it, &context);
        comparison.check("eta_ti", 1.0 / fresnel.eta_it, eta_ti, &context);
        comparison.rows += 1;
    }
    comparison.finish("fresnel_dielectric.csv");
}

#[test]
fn polarized_amplitudes_match_mitsuba() {
    let rows = read_fixture(
        "fresnel_polarized.csv",
        "cos_theta_i,eta,a_s_re,a_s_im,a_p_re,a_p_im,cos_theta_t,eta_it,eta_ti",
    );
    // Mitsuba's Verdet-convention a_p is Hecht's r∥, prisma's r_p: the sign factor is +1.
    const P_SIGN_MITSUBA_TO_PRISMA: f32 = 1.0;
    let mut comparison = Comparison::new(TOLERANCE);
    let mut total_internal_reflections = 0;
    let mut real_summaries = 0;
    for row in &rows {
        let &[cos_theta_i, eta, a_s_re, a_s_im, a_p_re, a_p_im, cos_theta_t, eta_it, eta_ti] = row.as_slice()
        else {
            unreachable!("read_fixture checks the row width")
        };
        let context = format!("cos θi = {cos_theta_i}, eta = {eta}");
        let a_s = Complex32::new(a_s_re, a_s_im);
        let a_p = Complex32::new(a_p_re, a_p_im) * P_SIGN_MITSUBA_TO_PRISMA;
        let amplitudes = fresnel_dielectric_amplitudes(cos_theta_i, eta);
        comparison.check("Re r_s", amplitudes.r_s.re, a_s.re, &context);
        comparison.check("Im r_s", amplitudes.r_s.im, a_s.im, &context);
        comparison.check("Re r_p", amplitudes.r_p.re, a_p.re, &context);
        comparison.check("Im r_p", amplitudes.r_p.im, a_p.im, &context);
        let reflectance = 0.5 * (a_s.norm_sqr() + a_p.norm_sqr());
        comparison.check("R", amplitudes.reflectance, reflectance, &context);
        comparison.check("cos θt", amplitudes.cos_theta_t, cos_theta_t, &context);
        comparison.check("eta_it", amplitudes.eta_it, eta_it, &context);
        comparison.check("eta_ti", amplitudes.eta_ti, eta_ti, &context);
        if a_s.im != 0.0 {
            total_internal_reflections += 1;
        }

        // The real-valued summary rounds cos² θt like mi.fresnel, so it is compared where that
        // rounding cannot matter. The two roundings differ by δ ≲ 4e-7 (a few float32 roundings
        // of terms ≤ 1); that moves cos θt by δ/(2|cos θt|) and r by |∂r/∂cos θt| ≤ 1/(2|cos θt|)
        // times that (the maximum over cos θi of 2 eta cos θi/(cos θi + eta cos θt)², likewise
        // for r_p): with |cos θt| > 0.1, by at most 25 δ ≲ 1e-5. Deep in total internal
        // reflection (cos θt = 0 for both, a clearly imaginary Mitsuba cos θt) both moduli are 1.
        let fresnel = fresnel_dielectric(cos_theta_i, eta);
        if fresnel.cos_theta_t == 0.0 && a_s.im.abs() > 1e-3 {
            real_summaries += 1;
            comparison.check("|r_s| under TIR", fresnel.r_s, a_s.norm(), &context);
            comparison.check("|r_p| under TIR", fresnel.r_p, a_p.norm(), &context);
        } else if fresnel.cos_theta_t.abs() > 0.1 {
            real_summaries += 1;
            comparison.check("r_s (real)", fresnel.r_s, a_s.re, &context);
            comparison.check("r_p (real)", fresnel.r_p, a_p.re, &context);
        }
        comparison.rows += 1;
    }
    assert!(total_internal_reflections > 100, "the fixture must exercise TIR");
    assert!(real_summaries > rows.len() * 3 / 4, "{real_summaries} real summaries compared");
    comparison.finish("fresnel_polarized.csv");
}

#[test]
fn conductor_reflectance_matches_mitsuba() {
    let rows = read_fixture("fresnel_conductor.csv", "cos_theta_i,eta_re,eta_im,reflectance");
    let mut comparison = Comparison::new(TOLERANCE);
    for row in &rows {
        let &[cos_theta_i, eta_re, eta_im, reflectance] = row.as_slice() else {
            unreachable!("read_fixture checks the row width")
        };
        let context = format!("cos θi = {cos_theta_i}, eta = {eta_re}+{eta_im}i");
        let fresnel = fresnel_conductor(cos_theta_i, Complex32::new(eta_re, eta_im));
        comparison.check("R", fresnel.reflectance, reflectance, &context);
        comparison.rows += 1;
    }
    comparison.finish("fresnel_conductor.csv");
}
