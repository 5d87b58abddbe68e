//! The shipped lenses (data/lenses/) read by prisma's parsers and traced by its optics, against
//! an optical design code: rayoptics 0.9.8 (validation/lens/fixtures/, provenance inside,
//! made by validation/lens/make_fixtures.py from the same .zmx files). Issue 40's tolerances:
//! first-order numbers and the chromatic focal shift within 1e-6 relative; real-ray intercepts
//! within 1e-6 of the lens's scale (its focal length); spot RMS on the same pupil grid.
//! Both formats of each lens are checked (the .zmx rayoptics read, and the pbrt .dat).
//! Two faults must fail: one index for every wavelength (pbrt's own double Gauss file) and a
//! lens without Fresnel losses.

use std::path::Path;

use glam::DVec3;
use prisma::lens::analysis::{normal_incidence_transmission, Analysis};
use prisma::lens::trace::{LensTracer, Ray, TraceOptions};
use prisma::lens::{read_lens_file, LensSystem};
use serde_json::Value;

const LENSES: [&str; 3] = ["singlet_nbk7", "achromat", "dgauss50"];

/// First-order numbers, relative to the focal length: far inside the 1e-6. Both sides
/// are f64 computations of the same paraxial trace, separated by rounding (measured ≤ 2e-15
/// relative by the fixture's own independent trace).
const FIRST_ORDER_RELATIVE: f64 = 1e-12;
/// Pupil positions and the exit pupil's diameter: rayoptics computes them from a chief ray on
/// an object plane 1e10 mm away, which cancels to ~1e-7 of the focal length (the fixture's
/// README); still inside the 1e-6.
const PUPIL_RELATIVE: f64 = 1e-7;

fn fixture(name: &str) -> Value {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("validation/lens/fixtures").join(format!("{name}.json"));
    serde_json::from_str(&std::fs::read_to_string(&path).expect("fixture")).expect("fixture JSON")
}

fn lens(file: &str) -> LensSystem {
    read_lens_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("data/lenses").join(file))
        .expect("a shipped lens")
}

fn f(value: &Value) -> f64 {
    value.as_f64().expect("a number")
}

fn vec3(value: &Value) -> DVec3 {
    let a = value.as_array().expect("an array");
    DVec3::new(f(&a[0]), f(&a[1]), f(&a[2]))
}

fn close(what: &str, ours: f64, theirs: f64, scale: f64) -> Result<(), String> {
    within(what, ours, theirs, scale, FIRST_ORDER_RELATIVE)
}

fn within(what: &str, ours: f64, theirs: f64, scale: f64, tolerance: f64) -> Result<(), String> {
    let error = (ours - theirs).abs() / scale;
    if error <= tolerance {
        Ok(())
    } else {
        Err(format!("{what}: prisma {ours} vs rayoptics {theirs} ({error:.2e} of {scale})"))
    }
}

/// Every first-order number at every wavelength of the fixture; the first disagreement.
fn first_order(system: &LensSystem, fixture: &Value) -> Result<(), String> {
    for row in fixture["paraxial"].as_array().expect("paraxial") {
        let lambda = f(&row["wavelength_nm"]);
        let p = system.paraxial(lambda).map_err(|e| e.to_string())?;
        let efl = f(&row["efl_mm"]);
        let scale = efl.abs();
        let at = |name: &str| format!("{name} at {lambda} nm");
        close(&at("EFL"), p.efl_mm, efl, scale)?;
        close(&at("BFL"), p.bfl_mm, f(&row["bfl_mm"]), scale)?;
        // rayoptics gives the front focus's z relative to the first vertex; prisma the
        // distance from the front focus to the first vertex.
        close(&at("FFL"), -p.ffl_mm, f(&row["ffl_mm"]), scale)?;
        within(
            &at("entrance pupil z"),
            p.entrance_pupil_z_mm,
            f(&row["entrance_pupil_z_mm"]),
            scale,
            PUPIL_RELATIVE,
        )?;
        close(
            &at("entrance pupil diameter"),
            p.entrance_pupil_diameter_mm,
            f(&row["entrance_pupil_diameter_mm"]),
            scale,
        )?;
        let exit_z = f(&row["exit_pupil_z_from_last_mm"]);
        within(&at("exit pupil z"), p.exit_pupil_z_mm, exit_z, scale, PUPIL_RELATIVE)?;
        within(
            &at("exit pupil diameter"),
            p.exit_pupil_diameter_mm,
            f(&row["exit_pupil_diameter_mm"]),
            scale,
            PUPIL_RELATIVE,
        )?;
        close(&at("f-number"), p.f_number, f(&row["f_number"]), f(&row["f_number"]))?;
        let shift = system.chromatic_focal_shift_mm(lambda, f64::INFINITY).map_err(|e| e.to_string())?;
        close(&at("focal shift"), shift, f(&row["focal_shift_mm"]), scale)?;
    }
    Ok(())
}

#[test]
fn first_order_optics_match_rayoptics_for_both_formats() {
    for name in LENSES {
        let fixture = fixture(name);
        for file in [format!("{name}.zmx"), format!("{name}.dat")] {
            let system = lens(&file);
            if let Err(e) = first_order(&system, &fixture) {
                panic!("{file}: {e}");
            }
        }
    }
}

/// Every listed real ray (chief, marginal and skew rays at 0, 0.7 and 1.0 of the field, six
/// wavelengths) traced from the same start point and direction: the image intercept and exit
/// direction within 1e-11 of the focal length (the issue asks 1e-6; measured ≤ 7e-14 mm: f64
/// rounding), and the same verdict on vignetting.
#[test]
fn real_rays_match_rayoptics() {
    for name in LENSES {
        let fixture = fixture(name);
        let system = lens(&format!("{name}.zmx"));
        let tracer = LensTracer::new(system.clone());
        let scale = f(&fixture["paraxial"][0]["efl_mm"]).abs();
        let mut worst: f64 = 0.0;
        for ray in fixture["rays"]["list"].as_array().expect("rays") {
            let lambda = f(&ray["wavelength_nm"]);
            let traced = tracer.trace_from_object(
                Ray { origin: vec3(&ray["start_mm"]), dir: vec3(&ray["direction"]) },
                lambda,
            );
            let passes = ray["passes_apertures"].as_bool().expect("passes_apertures");
            // Marginal rays aimed exactly at the stop's rim pass or not by rounding (their
            // margin is ±2e-15 mm in rayoptics): no verdict on those, only their intercepts.
            let on_rim = f(&ray["min_aperture_margin_mm"]).abs() < 1e-9;
            match traced {
                Ok(traced) => {
                    assert!(
                        passes || on_rim,
                        "{name}: prisma lets through a ray rayoptics finds vignetted: {ray}"
                    );
                    let image = [f(&ray["image_mm"][0]), f(&ray["image_mm"][1])];
                    let exit = vec3(&ray["exit_direction"]);
                    let error = (traced.ray.origin.x - image[0])
                        .abs()
                        .max((traced.ray.origin.y - image[1]).abs())
                        .max(scale * (traced.ray.dir - exit).abs().max_element());
                    worst = worst.max(error);
                    assert!(error <= 1e-11 * scale, "{name}: {error} mm off for {ray}");
                }
                Err(blocked) => {
                    assert!(!passes, "{name}: prisma blocks ({blocked:?}) a ray rayoptics passes: {ray}")
                }
            }
        }
        println!("{name}: worst real-ray difference {worst:.2e} mm");
    }
}

/// RMS spot radius about the centroid per wavelength and field, on the fixture's own pupil
/// grid (cell-centred 32×32 in the d-line entrance pupil, chief-ray aimed): the same rays, so
/// the same number to rounding, and the same count of vignetted rays.
#[test]
fn spot_radii_match_rayoptics() {
    for name in LENSES {
        let fixture = fixture(name);
        let system = lens(&format!("{name}.zmx"));
        let analysis = Analysis::new(&system).expect("a lens");
        for row in fixture["spots"]["list"].as_array().expect("spots") {
            let spot = analysis.spot(f(&row["field_angle_deg"]), f(&row["wavelength_nm"]));
            assert_eq!(spot.rays_in_pupil as u64, row["rays_in_pupil"].as_u64().expect("count"), "{name}");
            assert_eq!(
                spot.points.len() as u64,
                row["rays_passing"].as_u64().expect("count"),
                "{name}: {row}"
            );
            let theirs = f(&row["rms_radius_mm"]);
            assert!(
                (spot.rms_radius_mm / theirs - 1.0).abs() < 1e-9,
                "{name}: RMS {} vs {theirs} mm",
                spot.rms_radius_mm
            );
        }
    }
}

/// On-axis transmission of the uncoated lens at normal incidence: Π(1 − R) per wavelength, and
/// the traced transmission over the pupil near it (the marginal rays meet the surfaces up to
/// ~15° off normal at f/2, where R rises by a few per cent of itself).
#[test]
fn on_axis_transmission_is_fresnel_and_the_lossless_fault_fails() {
    for name in LENSES {
        let fixture = fixture(name);
        let system = lens(&format!("{name}.zmx"));
        for row in fixture["closed_form"]["list"].as_array().expect("closed form") {
            let lambda = f(&row["wavelength_nm"]);
            let theirs = f(&row["normal_incidence_transmission"]);
            let ours = normal_incidence_transmission(&system, lambda);
            assert!((ours - theirs).abs() < 1e-12, "{name} at {lambda} nm: {ours} vs {theirs}");
        }
        // The traced on-axis ray at the pupil centre, Fresnel on: exactly Π(1 − R) (normal
        // incidence everywhere on the axis).
        let tracer = LensTracer::new(system.clone());
        let d = prisma::lens::LAMBDA_D_NM;
        let on_axis = tracer
            .trace_from_sensor([0.0, 0.0], [0.0, 0.0], &TraceOptions::new(d), &mut || 0.0)
            .expect("axis");
        let closed = normal_incidence_transmission(&system, d);
        assert!((on_axis.throughput - closed).abs() < 1e-12, "{name}: {} vs {closed}", on_axis.throughput);
        // The fault: a lens without Fresnel losses transmits everything, and fails.
        let lossless = TraceOptions { fresnel: false, ..TraceOptions::new(d) };
        let faulty = tracer.trace_from_sensor([0.0, 0.0], [0.0, 0.0], &lossless, &mut || 0.0).expect("axis");
        assert!((faulty.throughput - closed).abs() > 0.05, "{name}: the lossless fault must fail");
    }
}

/// pbrt's own double Gauss file gives each element one index: its chromatic focal shift is
/// zero, and the comparison with the real glasses' fixture must fail on it (it is 0.12 mm at F).
#[test]
fn one_index_for_every_wavelength_fails() {
    let fixture = fixture("dgauss50");
    let pbrt = lens("dgauss50_pbrt.dat");
    let error =
        first_order(&pbrt, &fixture).expect_err("one index per element cannot match the real glasses");
    println!("the fault fails as it must: {error}");
    for lambda in [486.1327, 656.2725] {
        assert_eq!(pbrt.chromatic_focal_shift_mm(lambda, f64::INFINITY).unwrap(), 0.0);
    }
    // And pbrt's file matches its own constant-index fixture.
    first_order(&pbrt, &self::fixture("dgauss50_pbrt")).expect("pbrt's file as pbrt sees it");
}
