//! The analytic validation cases (white furnaces, slab transmittance, prism minimum deviation,
//! Snell's window, and the polarisation cases against the field reference) pass, and each fails
//! when the physics it checks is deliberately broken: a check that cannot fail proves nothing.

use prisma::integrator::Fault;
use prisma::validate::analytic::{self, CASES};

fn passes(name: &str, fault: Option<Fault>) -> bool {
    let result = analytic::run(name, 2, fault).unwrap();
    for check in &result.checks {
        eprintln!("{name} {fault:?}: {} = {:.4e} (≤ {:.1e})", check.metric, check.value, check.threshold);
    }
    result.passed()
}

#[test]
fn every_analytic_case_passes() {
    for name in CASES {
        assert!(passes(name, None), "{name} failed");
    }
}

#[test]
fn schlick_instead_of_exact_fresnel_is_caught() {
    assert!(!passes("slab_transmittance", Some(Fault::SchlickFresnel)));
    assert!(!passes("snell_window", Some(Fault::SchlickFresnel)));
}

/// The exact slab answer needs s and p carried through both faces: the per-interface average
/// (polarisation off) is 0.5 % low at 50° for n = 1.5, and more for flint and grazing angles.
#[test]
fn polarisation_off_is_caught_by_the_slab() {
    assert!(!passes("slab_transmittance", Some(Fault::Unpolarized)));
}

#[test]
fn an_index_one_percent_too_high_is_caught() {
    for name in ["slab_transmittance", "prism_minimum_deviation", "snell_window"] {
        assert!(!passes(name, Some(Fault::IorScale(1.01))), "{name} did not catch the fault");
    }
}

/// The white furnace can fail: absorbing glass or a 95 % mirror are visible.
#[test]
fn lossy_objects_are_visible_in_the_furnace() {
    for material in
        ["type = \"dielectric\"\nior = 1.5\nabsorption = 0.5", "type = \"mirror\"\nreflectance = 0.95"]
    {
        assert!(!analytic::furnace(material, 2).unwrap().passed(), "{material}");
    }
}

/// Every polarisation case needs polarisation: with it off, S1–S3 vanish (and Malus's law
/// through crossed sheets turns into a quarter).
#[test]
fn polarisation_off_fails_every_polarisation_case() {
    for name in prisma::validate::polarization::CASES {
        assert!(!passes(name, Some(Fault::Unpolarized)), "{name} did not catch polarisation off");
    }
}

/// A transposed rotation turns Stokes frames the wrong way: the sign of S2 in a rolled camera,
/// the second of two skew reflections, sheets at an angle to the image axes.
#[test]
fn a_transposed_rotation_is_caught() {
    for name in ["camera_roll", "skew_reflections", "conductor_pair", "polarizer_chain"] {
        assert!(
            !passes(name, Some(Fault::TransposedRotation)),
            "{name} did not catch the transposed rotation"
        );
    }
    // A single reflection seen upright needs no rotation: that case cannot see it.
    assert!(passes("one_reflection", Some(Fault::TransposedRotation)));
}

/// A flipped phase sign turns circular polarisation the wrong way: total internal reflection,
/// metals, the quarter-wave plate.
#[test]
fn a_flipped_phase_is_caught() {
    for name in ["tir_retardance", "conductor_pair", "polarizer_chain"] {
        assert!(!passes(name, Some(Fault::FlippedPhase)), "{name} did not catch the flipped phase");
    }
}

/// The light tracer's refraction must carry flux: scaling it like radiance (1/η² per refraction)
/// shows wherever light leaves glass it did not enter, as from a light inside a glass sphere.
#[test]
fn radiance_scaling_on_light_paths_is_caught() {
    assert!(!passes("caustic_power", Some(Fault::LightPathRadianceScaling)));
}

/// The cosine at the diffuse receiver toward the camera: without it a wall seen obliquely
/// appears to receive more power than the light emits.
#[test]
fn a_missing_receiver_cosine_is_caught() {
    assert!(!passes("caustic_power", Some(Fault::NoReceiverCosine)));
}

/// The caustics' positions depend on the index: the spectral lines of the prism and the ball
/// lens's focus move with it.
#[test]
fn an_index_one_percent_too_high_moves_the_caustics() {
    for name in ["newton_lines", "prism_band_edges", "ball_lens_focus"] {
        assert!(!passes(name, Some(Fault::IorScale(1.01))), "{name} did not catch the fault");
    }
}

/// The band edges are read to a few thousandths of a pixel of 10⁻⁴ units: an index 2 ppm too
/// high at both faces moves them about 0.2 px, four times the threshold.
#[test]
fn an_index_two_ppm_too_high_moves_the_band_edges() {
    assert!(!passes("prism_band_edges", Some(Fault::IorScale(1.000_002))));
}

/// The light tracer carries polarisation through the prism: the flux in the spectral lines is
/// ½(T_s1·T_s2 + T_p1·T_p2) of the beam's, 3.3 % more than the s/p-averaged product.
#[test]
fn polarisation_off_dims_the_newton_lines() {
    assert!(!passes("newton_lines", Some(Fault::Unpolarized)));
}
