//! Every malformed scene gets a one-line error naming the file and the line or field, exit code 2,
//! and no output file. Each case runs the real binary.

use std::path::Path;
use std::process::Command;

const GOOD: &str = r#"
background = 0.5

[camera]
position = [0, 0, -5]
look_at = [0, 0, 0]
fov_y_deg = 40
width = 8
height = 6

[render]
spp = 1

[materials.glass]
type = "dielectric"
ior = 1.5

[materials.white]
type = "diffuse"
albedo = 0.8

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "glass"

[[lights]]
type = "point"
position = [0, 5, 0]
intensity = 10
"#;

/// Runs `prisma render` on `scene_text`; returns (exit code, stderr, whether an output appeared).
fn render_text(scene_text: &str, extra: &[&str]) -> (i32, String, bool) {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, scene_text).unwrap();
    render_file(&scene, dir.path(), extra)
}

fn render_file(scene: &Path, dir: &Path, extra: &[&str]) -> (i32, String, bool) {
    let out = dir.join("out/image.exr");
    let output = Command::new(env!("CARGO_BIN_EXE_prisma"))
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(&out)
        .arg("--quiet")
        .args(extra)
        .output()
        .unwrap();
    let produced = dir.join("out").exists() && std::fs::read_dir(dir.join("out")).unwrap().count() > 0;
    (output.status.code().unwrap_or(-1), String::from_utf8_lossy(&output.stderr).into_owned(), produced)
}

/// `scene.toml:N:` for the 1-based line of `needle` in `text`.
fn at_line_of(text: &str, needle: &str) -> String {
    let line = text.lines().position(|l| l.contains(needle)).expect("needle in text") + 1;
    format!("scene.toml:{line}:")
}

/// Asserts a clean rejection: exit 2, one line, mentioning every fragment, no output file.
fn assert_rejected(scene_text: &str, fragments: &[&str]) {
    let (code, stderr, produced) = render_text(scene_text, &[]);
    assert_eq!(code, 2, "exit code for {fragments:?}; stderr: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "not one line: {stderr}");
    assert!(stderr.contains("scene.toml"), "file not named: {stderr}");
    for fragment in fragments {
        assert!(stderr.contains(fragment), "missing {fragment:?} in: {stderr}");
    }
    assert!(!produced, "an output file was written for {fragments:?}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn the_good_scene_renders() {
    let (code, stderr, produced) = render_text(GOOD, &[]);
    assert_eq!(code, 0, "{stderr}");
    assert!(produced);
}

#[test]
fn toml_syntax_error_names_the_line() {
    let text = GOOD.replace("radius = 1\n", "radius = = 1\n");
    assert_rejected(&text, &[&at_line_of(&text, "radius = = 1")]);
}

#[test]
fn unknown_key() {
    assert_rejected(&GOOD.replace("radius = 1\n", "radius = 1\nradiu = 2\n"), &["radiu"]);
}

#[test]
fn missing_field() {
    assert_rejected(&GOOD.replace("radius = 1\n", ""), &["radius"]);
}

#[test]
fn wrong_type() {
    let text = GOOD.replace("width = 8", "width = \"eight\"");
    assert_rejected(&text, &[&at_line_of(&text, "eight"), "expected u32"]);
}

#[test]
fn undefined_material() {
    assert_rejected(
        &GOOD.replace("material = \"glass\"", "material = \"gold\""),
        &["shapes[0].material", "gold"],
    );
}

#[test]
fn negative_or_zero_radius() {
    assert_rejected(
        &GOOD.replace("radius = 1\n", "radius = -1\n"),
        &["shapes[0].radius", "must lie in [1e-10"],
    );
    assert_rejected(&GOOD.replace("radius = 1\n", "radius = 0\n"), &["shapes[0].radius"]);
}

#[test]
fn zero_length_normal_and_edges() {
    let plane =
        "[[shapes]]\ntype = \"plane\"\npoint = [0, -1, 0]\nnormal = [0, 0, 0]\nmaterial = \"white\"\n";
    assert_rejected(&format!("{GOOD}\n{plane}"), &["shapes[1].normal", "non-zero"]);
    let quad = "[[shapes]]\ntype = \"quad\"\ncorner = [0, 0, 0]\nedge1 = [1, 0, 0]\nedge2 = [2, 0, 0]\nmaterial = \"white\"\n";
    assert_rejected(&format!("{GOOD}\n{quad}"), &["shapes[1]", "parallel"]);
    let light = "[[lights]]\ntype = \"quad\"\ncorner = [0, 0, 0]\nedge1 = [0, 0, 0]\nedge2 = [1, 0, 0]\nradiance = 1\nemit = \"edge1_cross_edge2\"\n";
    assert_rejected(&format!("{GOOD}\n{light}"), &["lights[1].edge1"]);
}

#[test]
fn degenerate_camera() {
    assert_rejected(&GOOD.replace("look_at = [0, 0, 0]", "look_at = [0, 0, -5]"), &["camera", "look_at"]);
    assert_rejected(
        &GOOD.replace("fov_y_deg = 40", "fov_y_deg = 40\nup = [0, 0, 1]"),
        &["camera", "parallel"],
    );
}

/// A thin lens's radius and focus distance: negative, NaN, infinite, zero focus, one without
/// the other; each names the field and its line.
#[test]
fn bad_thin_lens() {
    let lens = |radius: &str, focus: &str| {
        GOOD.replace(
            "height = 6",
            &format!("height = 6\naperture_radius = {radius}\nfocus_distance = {focus}"),
        )
    };
    for (radius, focus, field, needle) in [
        ("-0.1", "5", "camera.aperture_radius", "aperture_radius"),
        ("nan", "5", "camera.aperture_radius", "aperture_radius"),
        ("inf", "5", "camera.aperture_radius", "aperture_radius"),
        ("0.1", "-5", "camera.focus_distance", "focus_distance"),
        ("0.1", "nan", "camera.focus_distance", "focus_distance"),
        ("0.1", "0", "camera.focus_distance", "focus_distance"),
    ] {
        let text = lens(radius, focus);
        assert_rejected(&text, &[field, &at_line_of(&text, needle)]);
    }
    let focus_alone = GOOD.replace("height = 6", "height = 6\nfocus_distance = 5");
    assert_rejected(&focus_alone, &["camera.focus_distance", "aperture_radius"]);
    let radius_alone = GOOD.replace("height = 6", "height = 6\naperture_radius = 0.1");
    assert_rejected(&radius_alone, &["camera.focus_distance", "required"]);
}

#[test]
fn bad_ior() {
    assert_rejected(&GOOD.replace("ior = 1.5", "ior = 0"), &["materials.glass.ior"]);
    assert_rejected(&GOOD.replace("ior = 1.5", "ior = -1.2"), &["materials.glass.ior"]);
    assert_rejected(&GOOD.replace("ior = 1.5", "ior = nan"), &["materials.glass.ior"]);
    assert_rejected(
        &GOOD.replace("ior = 1.5", "ior = { glass = \"unobtainium\" }"),
        &["unobtainium", "N-BK7"],
    );
}

#[test]
fn dispersion_law_with_non_positive_index_in_range() {
    // n = 1.5 − 0.6/λ² is below zero for λ < 632 nm.
    assert_rejected(
        &GOOD.replace("ior = 1.5", "ior = { cauchy = [1.5, -0.6, 0.0] }"),
        &["materials.glass.ior"],
    );
    // A Sellmeier pole at λ² = C = 0.25 µm² (500 nm) lies inside 360–830 nm.
    assert_rejected(
        &GOOD.replace("ior = 1.5", "ior = { sellmeier = { b = [1.0, 0.0, 0.0], c_um2 = [0.25, 0.0, 0.0] } }"),
        &["materials.glass.ior"],
    );
}

#[test]
fn nan_in_a_spectrum_or_a_position() {
    assert_rejected(&GOOD.replace("albedo = 0.8", "albedo = nan"), &["materials.white.albedo"]);
    assert_rejected(&GOOD.replace("center = [0, 0, 0]", "center = [0, nan, 0]"), &["shapes[0].center"]);
    assert_rejected(
        &GOOD.replace("intensity = 10", "intensity = { rgb = [1, inf, 1] }"),
        &["lights[0].intensity"],
    );
}

#[test]
fn missing_and_malformed_obj() {
    let mesh = "[[shapes]]\ntype = \"mesh\"\nfile = \"missing.obj\"\nmaterial = \"white\"\n";
    assert_rejected(&format!("{GOOD}\n{mesh}"), &["shapes[1].file", "missing.obj"]);

    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 7\n").unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, format!("{GOOD}\n{}", mesh.replace("missing.obj", "broken.obj"))).unwrap();
    let (code, stderr, produced) = render_file(&scene, dir.path(), &[]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("broken.obj") && stderr.contains("shapes[1].file"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(!produced);
}

#[test]
fn zero_or_absurd_resolution_and_samples() {
    assert_rejected(&GOOD.replace("width = 8", "width = 0"), &["camera.width"]);
    assert_rejected(&GOOD.replace("height = 6", "height = 100000"), &["camera.height"]);
    assert_rejected(&GOOD.replace("spp = 1", "spp = 0"), &["render.spp"]);
    assert_rejected(&GOOD.replace("spp = 1", "spp = 4000000000"), &["render.spp"]);
    let text = GOOD.replace("spp = 1", "spp = -3");
    assert_rejected(&text, &[&at_line_of(&text, "spp = -3")]);
    assert_rejected(&GOOD.replace("spp = 1", "spp = 1\nwavelengths = 9"), &["render.wavelengths"]);
}

#[test]
fn bad_flags_exit_2() {
    for flags in [&["--spp", "0"][..], &["--width", "0"], &["--wavelength", "200"], &["--threads", "0"]] {
        let (code, stderr, produced) = render_text(GOOD, flags);
        assert_eq!(code, 2, "{flags:?}: {stderr}");
        assert!(!produced, "{flags:?}");
        // One line, as every input error (clap's usage block is left to --help).
        assert_eq!(stderr.trim_end().lines().count(), 1, "{flags:?}: {stderr}");
        assert!(stderr.starts_with("error: "), "{stderr}");
    }
}

#[test]
fn missing_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    let (code, stderr, produced) = render_file(&dir.path().join("nope.toml"), dir.path(), &[]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("nope.toml"), "{stderr}");
    assert!(!produced);
}

/// Spot lights and beams: a cone of no angle or more than a half-space, a core wider than the
/// cone, no axis, no power, a beam of no area: each a one-line error naming the field.
#[test]
fn bad_spots_and_beams_are_rejected() {
    let spot = |fields: &str| {
        GOOD.replace(
            "[[lights]]\ntype = \"point\"\nposition = [0, 5, 0]\nintensity = 10",
            &format!("[[lights]]\ntype = \"spot\"\nposition = [0, 5, 0]\n{fields}"),
        )
    };
    let beam = |fields: &str| {
        GOOD.replace(
            "[[lights]]\ntype = \"point\"\nposition = [0, 5, 0]\nintensity = 10",
            &format!(
                "[[lights]]\ntype = \"beam\"\ncorner = [0, 5, 0]\nemit = \"edge1_cross_edge2\"\n{fields}"
            ),
        )
    };
    let good_spot = "look_at = [0, 0, 0]\nintensity = 10\ncutoff_deg = 20";
    assert!(render_text(&spot(good_spot), &[]).0 == 0, "a good spot renders");
    for (fields, fragment) in [
        ("look_at = [0, 0, 0]\nintensity = 10\ncutoff_deg = 0", "lights[0].cutoff_deg"),
        ("look_at = [0, 0, 0]\nintensity = 10\ncutoff_deg = -5", "lights[0].cutoff_deg"),
        ("look_at = [0, 0, 0]\nintensity = 10\ncutoff_deg = 180", "lights[0].cutoff_deg"),
        (
            "look_at = [0, 0, 0]\nintensity = 10\ncutoff_deg = 20\nbeam_width_deg = 30",
            "lights[0].beam_width_deg",
        ),
        (
            "look_at = [0, 0, 0]\nintensity = 10\ncutoff_deg = 20\nbeam_width_deg = 0",
            "lights[0].beam_width_deg",
        ),
        ("look_at = [0, 5, 0]\nintensity = 10\ncutoff_deg = 20", "lights[0].look_at"),
        ("look_at = [0, 0, 0]\nintensity = 0\ncutoff_deg = 20", "lights[0].intensity"),
        ("look_at = [0, 0, 0]\nintensity = -1\ncutoff_deg = 20", "lights[0].intensity"),
    ] {
        let text = spot(fields);
        assert_rejected(&text, &[fragment, &at_line_of(&text, "[[lights]]")]);
    }
    let good_beam = "edge1 = [1, 0, 0]\nedge2 = [0, 0, 1]\nirradiance = 5";
    assert!(render_text(&beam(good_beam), &[]).0 == 0, "a good beam renders");
    for (fields, fragment) in [
        ("edge1 = [1, 0, 0]\nedge2 = [2, 0, 0]\nirradiance = 5", "lights[0].edge2"),
        ("edge1 = [0, 0, 0]\nedge2 = [0, 0, 1]\nirradiance = 5", "lights[0].edge1"),
        ("edge1 = [1, 0, 0]\nedge2 = [0, 0, 1]\nirradiance = 0", "lights[0].irradiance"),
        ("edge1 = [1, 0, 0]\nedge2 = [0, 0, 1]\nirradiance = -2", "lights[0].irradiance"),
    ] {
        assert_rejected(&beam(fields), &[fragment]);
    }
}

/// Light paths per pass must be a positive count, in the file and on the command line.
#[test]
fn bad_light_path_counts_are_rejected() {
    let text = GOOD.replace("spp = 1", "spp = 1\ncaustics = true\nlight_paths = 0");
    assert_rejected(&text, &["render.light_paths"]);
    let (code, stderr, produced) = render_text(GOOD, &["--caustics", "--light-paths", "0"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(!produced);
}

/// Edge refinement's samples per pass must be 1..=64, in the file and on the command line.
#[test]
fn bad_edge_sample_counts_are_rejected() {
    for bad in ["0", "65"] {
        let text = GOOD.replace("spp = 1", &format!("spp = 1\nedge_samples = {bad}"));
        assert_rejected(&text, &["render.edge_samples", bad]);
        let (code, stderr, produced) = render_text(GOOD, &["--edge-samples", bad]);
        assert_eq!(code, 2, "{stderr}");
        assert!(!produced);
    }
}

/// Issue 41: a coating's layers are checked at load, each error naming the layer's field.
#[test]
fn bad_coatings_are_rejected() {
    let coated = |coating: &str| GOOD.replace("ior = 1.5", &format!("ior = 1.5\ncoating = {coating}"));
    let line = at_line_of(GOOD, "[materials.glass]");
    for thickness in ["0", "-5", "nan", "inf", "1e6"] {
        assert_rejected(
            &coated(&format!("[{{ ior = 1.38, thickness_nm = {thickness} }}]")),
            &[&line, "materials.glass.coating[0].thickness_nm"],
        );
    }
    assert_rejected(
        &coated("[{ ior = 1.38, thickness_nm = 100 }, { ior = 0, thickness_nm = 100 }]"),
        &[&line, "materials.glass.coating[1].ior"],
    );
    assert_rejected(
        &coated("[{ ior = { glass = \"unobtainium\" }, thickness_nm = 100 }]"),
        &["materials.glass.coating[0].ior", "unobtainium"],
    );
    assert_rejected(&coated("[{ ior = 1.38 }]"), &["thickness_nm"]);
    assert_rejected(&coated("[{ ior = 1.38, thickness_nm = 100, colour = 1 }]"), &["colour"]);
    let many = vec!["{ ior = 1.38, thickness_nm = 100 }"; 65].join(", ");
    assert_rejected(&coated(&format!("[{many}]")), &[&line, "materials.glass.coating", "at most 64"]);
    // 64 layers of the largest thickness load and render.
    let most = vec!["{ ior = 1.38, thickness_nm = 1e5 }"; 64].join(", ");
    let (code, stderr, produced) = render_text(&coated(&format!("[{most}]")), &[]);
    assert_eq!(code, 0, "{stderr}");
    assert!(produced);
}

/// Issue 41: a free-standing film's thickness and index are checked at load, each error naming
/// the field (a negative, non-finite or absurd thickness, a drained film missing a part, an
/// index below the air's, an unknown one, a drained film over a plane without heights).
#[test]
fn bad_films_are_rejected() {
    let film =
        |body: &str| GOOD.replace("type = \"dielectric\"\nior = 1.5", &format!("type = \"film\"\n{body}"));
    let line = at_line_of(GOOD, "[materials.glass]");
    for thickness in ["-5", "nan", "inf", "1e6"] {
        assert_rejected(
            &film(&format!("thickness_nm = {thickness}")),
            &[&line, "materials.glass.thickness_nm", "100 µm"],
        );
    }
    let drained = |fields: &str| film(&format!("thickness_nm = {{ {fields} }}"));
    assert_rejected(
        &drained("top = -1, bottom = 500, axis = [0, 1, 0]"),
        &[&line, "materials.glass.thickness_nm.top"],
    );
    assert_rejected(
        &drained("top = 100, bottom = 2e5, axis = [0, 1, 0]"),
        &[&line, "materials.glass.thickness_nm.bottom"],
    );
    assert_rejected(&drained("top = 100, bottom = 500"), &["materials.glass.thickness_nm", "axis"]);
    assert_rejected(&drained("value = 100, top = 100"), &["materials.glass.thickness_nm", "give a number,"]);
    assert_rejected(
        &drained("top = 100, bottom = 500, axis = [0, 0, 0]"),
        &["materials.glass.thickness_nm.axis"],
    );
    assert_rejected(
        &drained("top = 100, bottom = 500, axis = [0, 1, 0], heights = [1, -1]"),
        &["materials.glass.thickness_nm.heights", "bottom < top"],
    );
    assert_rejected(&drained("top = 100, bottom = 500, axis = [0, 1, 0], colour = 1"), &["colour"]);
    assert_rejected(&film("ior = 0.8\nthickness_nm = 300"), &[&line, "materials.glass.ior", "n ≥ 1"]);
    assert_rejected(
        &film("ior = { glass = \"unobtainium\" }\nthickness_nm = 300"),
        &["materials.glass.ior", "unobtainium"],
    );
    assert_rejected(&film(""), &["thickness_nm"]);
    // A plane has no top: a drained film on one needs its heights.
    let on_plane = drained("top = 100, bottom = 500, axis = [0, 1, 0]").replace(
        "type = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1",
        "type = \"plane\"\npoint = [0, -1, 0]\nnormal = [0, 1, 0]",
    );
    assert_rejected(&on_plane, &["materials.glass.thickness_nm.heights", "plane"]);
    // The thinnest and thickest films load and render, as does a drained bubble.
    for body in [
        "thickness_nm = 0",
        "thickness_nm = 1e5",
        "thickness_nm = { top = 0, bottom = 1e5, axis = [0, 1, 0] }",
    ] {
        let (code, stderr, produced) = render_text(&film(body), &[]);
        assert_eq!(code, 0, "{body}: {stderr}");
        assert!(produced);
    }
}

/// An unknown integrator names the valid ones; a setting of Whitted's alone in a path scene is
/// an error naming it (issue 39).
#[test]
fn unknown_integrator_and_settings_of_the_other_integrator() {
    let with = |extra: &str| GOOD.replace("spp = 1\n", &format!("spp = 1\n{extra}\n"));
    assert_rejected(
        &with("integrator = \"bdpt\""),
        &["render.integrator", "unknown integrator \"bdpt\"", "\"whitted\"", "\"path\""],
    );
    assert_rejected(&with("integrator = \"path\"\nprune_below = 0.01"), &["render.prune_below", "whitted"]);
    assert_rejected(
        &with("integrator = \"path\"\narea_light_samples = 8"),
        &["render.area_light_samples", "whitted"],
    );
    let (code, stderr, produced) = render_text(GOOD, &["--integrator", "bdpt"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("--integrator") && stderr.contains("\"path\""), "{stderr}");
    assert!(!produced);
    // The path tracer itself renders the good scene, and so does Whitted's scene switched to it.
    let (code, stderr, produced) = render_text(&with("integrator = \"path\""), &[]);
    assert_eq!((code, produced), (0, true), "{stderr}");
    let (code, stderr, produced) = render_text(GOOD, &["--integrator", "path"]);
    assert_eq!((code, produced), (0, true), "{stderr}");
}
