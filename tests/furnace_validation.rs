//! The closed forms of full transport (`src/validate/furnace.rs`) fail when the path tracer's
//! physics is deliberately broken: a diffuse bounce without its cosine (the throughput grows by
//! 2ρ per bounce instead of ρ: the series diverges at ρ ≥ ½), multiple-importance weights that
//! count direct light twice (quad lights and the sky are both sampled and hit), and a background
//! that lights nothing. That they pass without a fault is checked with every analytic case
//! (`tests/analytic_validation.rs`); the Whitted cases must pass whatever the path tracer does.

use prisma::integrator::Fault;
use prisma::validate::analytic;

fn passes(name: &str, fault: Option<Fault>) -> bool {
    let result = analytic::run(name, 2, fault).unwrap();
    for check in &result.checks {
        eprintln!("{name} {fault:?}: {} = {:.4e} (≤ {:.1e})", check.metric, check.value, check.threshold);
    }
    result.passed()
}

/// Without the cosine the expected weight of a diffuse bounce is 2ρ (E[1/cos θ] = 2 under
/// cosine sampling): the interreflection series of the closed sphere and of the emitting box
/// diverges (measured: means 712 and 2 146 times too bright at the cases' depth cap of 32), and the sphere under the sky is 51 %
/// too bright.
#[test]
fn a_diffuse_bounce_without_its_cosine_is_caught() {
    for name in ["closed_sphere_point_light", "emitting_box", "sphere_under_sky"] {
        assert!(!passes(name, Some(Fault::NoDiffuseCosine)), "{name} did not catch the missing cosine");
    }
}

/// Weights that do not add up to one count each bounce's direct light from the walls twice:
/// the box is 55 % too bright. A point light has no MIS (no BSDF sample can hit it), nor has
/// the background (gathered by the cosine-sampled bounce alone, `integrator/path.rs`): the
/// closed sphere and the sphere under the sky cannot see this fault, and pass with it.
#[test]
fn mis_weights_that_do_not_add_up_to_one_are_caught() {
    assert!(
        !passes("emitting_box", Some(Fault::MisWeightsUnnormalized)),
        "the box did not catch the weights"
    );
    assert!(passes("sphere_under_sky", Some(Fault::MisWeightsUnnormalized)));
}

/// A background that lights nothing leaves the sphere under the sky black.
#[test]
fn a_dark_background_is_caught() {
    assert!(!passes("sphere_under_sky", Some(Fault::DarkBackground)));
}

/// Whitted's cases check Whitted: the path tracer's faults leave them passing.
#[test]
fn the_whitted_cases_ignore_the_path_tracers_faults() {
    for fault in [Fault::NoDiffuseCosine, Fault::MisWeightsUnnormalized, Fault::DarkBackground] {
        for name in ["closed_sphere_point_light_whitted", "emitting_box_whitted"] {
            assert!(passes(name, Some(fault)), "{name} failed under {fault:?}");
        }
    }
}
