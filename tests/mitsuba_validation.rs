//! Every case of validation/cases.toml, caustic_cases.toml and transport_cases.toml, at the references' resolution
//! and a modest sample count, agrees with its committed Mitsuba 3 references; and a deliberately
//! wrong renderer (Schlick's approximation, indices 1 % too high, a light tracer without the
//! receiver's cosine) fails the cases that can see the error.
//! CI never runs Mitsuba: the references are committed files.

use std::path::Path;

use prisma::integrator::Fault;
use prisma::validate::cases;
use prisma::validate::mitsuba::{run_case, RunOptions};

const TEST_SPP: u32 = 128;

fn validation_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("validation")
}

fn options(fault: Option<Fault>) -> RunOptions {
    RunOptions { downsample: 1, spp: Some(TEST_SPP), threads: 2, fault }
}

fn report(name: &str, result: &prisma::validate::CaseResult) {
    for check in &result.checks {
        eprintln!(
            "{name}: {} = {:.4e} (≤ {:.1e}) {}",
            check.metric,
            check.value,
            check.threshold,
            if check.passed() { "PASS" } else { "FAIL" }
        );
    }
}

#[test]
fn every_case_agrees_with_mitsuba() {
    let all = cases::load(&validation_dir()).unwrap();
    assert!(all.len() >= 8, "only {} cases", all.len());
    let mut failed = Vec::new();
    for case in &all {
        let (result, _) = run_case(&validation_dir(), case, &options(None)).unwrap();
        report(&case.name, &result);
        if !result.passed() {
            failed.push(case.name.clone());
        }
    }
    assert!(failed.is_empty(), "failed: {failed:?}");
}

#[test]
fn wrong_renderers_fail() {
    let all = cases::load(&validation_dir()).unwrap();
    let find = |name: &str| all.iter().find(|c| c.name == name).unwrap_or_else(|| panic!("no case {name}"));
    for (name, fault) in [
        ("specular_spheres_prisma_cmf", Fault::SchlickFresnel),
        ("specular_spheres_prisma_cmf", Fault::IorScale(1.01)),
        ("specular_prism_prisma_cmf", Fault::IorScale(1.01)),
        // Polarisation: the averaged Fresnel fails the polarised references where paths cross
        // two or more interfaces, and the Stokes cases catch wrong frames and phases.
        ("specular_spheres_polarized", Fault::Unpolarized),
        ("stokes_rolled_30", Fault::TransposedRotation),
        ("stokes_two_mirrors_skew", Fault::TransposedRotation),
        ("stokes_gold_pair", Fault::FlippedPhase),
        ("stokes_tir_prism", Fault::FlippedPhase),
        ("dispersion_550", Fault::IorScale(1.01)),
        // Caustics against Mitsuba's particle tracer: the floor and the screen are seen
        // obliquely, and the prism's band of light moves with the index.
        ("caustic_sphere_550", Fault::NoReceiverCosine),
        ("caustic_prism_550", Fault::IorScale(1.01)),
        // Full transport (transport_cases.toml): the path tracer's MIS and diffuse bounces,
        // the sky as a light, and the partition of path space with the light tracer: a path
        // counted twice (the camera side keeps the light tracer's paths too) or never (the light
        // tracer stops at its first diffuse vertex).
        ("tp6_quad_path_550", Fault::MisWeightsUnnormalized),
        ("tp6_quad_path_prisma_cmf", Fault::NoDiffuseCosine),
        ("stokes_room_path", Fault::DarkBackground),
        ("stokes_room_path", Fault::TransposedRotation),
        ("stokes_room_path_caustics", Fault::CausticsCountedTwice),
        ("stokes_room_path_caustics", Fault::CausticsCountedNever),
        ("transport_room_spot", Fault::CausticsCountedNever),
        ("transport_room_spot_polarised", Fault::CausticsCountedNever),
    ] {
        let (result, _) = run_case(&validation_dir(), find(name), &options(Some(fault))).unwrap();
        report(&format!("{name} with {fault:?}"), &result);
        assert!(!result.passed(), "{name} did not catch {fault:?}");
    }
}
