//! `prisma polviz` on real renders: a tiny glass plane at Brewster's angle reflecting an area
//! light, rendered polarised by the binary, then mapped. Light reflected at Brewster's angle is
//! purely s-polarised: DoLP ≈ 1, and its field is horizontal in the image (AoLP 0°, the red of
//! the angle wheel). Bad inputs get exit code 2, one line on stderr, and no PNG.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The camera looks at the origin of a glass half-space (n = 1.5) from (0, 1, −1.5), i.e. at
/// atan(1.5) = 56.3° from the normal, Brewster's angle; with a 10° field every pixel is within
/// 5° of it, where (Rs − Rp)/(Rs + Rp) > 0.99. What the camera sees reflected is a large
/// downward-facing quad light; the refracted branch escapes into a black background.
const BREWSTER: &str = r#"
background = 0

[camera]
position = [0, 1, -1.5]
look_at = [0, 0, 0]
fov_y_deg = 10
width = 16
height = 12

[render]
spp = 2

[materials.glass]
type = "dielectric"
ior = 1.5

[[shapes]]
type = "plane"
point = [0, 0, 0]
normal = [0, 1, 0]
material = "glass"

[[lights]]
type = "quad"
corner = [-3, 2, 0]
edge1 = [6, 0, 0]
edge2 = [0, 0, 6]
radiance = 1
emit = "edge1_cross_edge2"   # x × z = −y: downwards
"#;

fn prisma() -> Command {
    Command::new(env!("CARGO_BIN_EXE_prisma"))
}

/// Renders the Brewster scene into `dir` with `extra` flags; returns the EXR path.
fn render(dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let scene = dir.join("brewster.toml");
    std::fs::write(&scene, BREWSTER).unwrap();
    let exr = dir.join(format!("{name}.exr"));
    let output =
        prisma().arg("render").arg(&scene).arg("-o").arg(&exr).arg("--quiet").args(extra).output().unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    exr
}

fn polviz(input: &Path, output: &Path, extra: &[&str]) -> Output {
    prisma().arg("polviz").arg(input).arg("-o").arg(output).args(extra).output().unwrap()
}

/// The number after "largest DoLP" in polviz's summary line.
fn largest_dolp(stdout: &[u8]) -> f32 {
    let text = String::from_utf8_lossy(stdout);
    let after = text.split("largest DoLP ").nth(1).unwrap_or_else(|| panic!("no summary in {text}"));
    after.split([',', ' ']).next().unwrap().parse().unwrap()
}

#[test]
fn brewster_reflection_maps_to_full_horizontal_polarisation() {
    let dir = tempfile::tempdir().unwrap();
    let exr = render(dir.path(), "colour", &[]);
    let png = dir.path().join("maps/colour.png");
    let output = polviz(&exr, &png, &[]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(largest_dolp(&output.stdout) > 0.99, "{}", String::from_utf8_lossy(&output.stdout));

    let figure = image::open(&png).unwrap().to_rgb8();
    // Four panels side by side; the 16 × 12 image magnified 20× to 320 × 240 in each.
    let panel_width = figure.width() / 4;
    assert_eq!(figure.width() % 4, 0);
    assert!(figure.height() > 240 && panel_width > 320, "{}×{}", figure.width(), figure.height());
    // The AoLP panel is the third; the map's centre, 18 px in and 30 px down, shows 0°: red.
    let centre = figure.get_pixel(2 * panel_width + 18 + 160, 30 + 120).0;
    assert!(centre[0] > centre[1] + 40 && centre[0] > centre[2] + 40, "AoLP 0° is red, got {centre:?}");
}

#[test]
fn single_wavelength_and_spectral_band_renders_map_too() {
    let dir = tempfile::tempdir().unwrap();
    let mono = render(dir.path(), "mono", &["--wavelength", "550"]);
    let output = polviz(&mono, &dir.path().join("mono.png"), &[]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(largest_dolp(&output.stdout) > 0.99);

    let bands = render(dir.path(), "bands", &["--spectral-bands", "4", "--spectral-range", "400-700"]);
    let output = polviz(&bands, &dir.path().join("band.png"), &["--wavelength", "560"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(largest_dolp(&output.stdout) > 0.99);
    let output = polviz(&bands, &dir.path().join("red.png"), &["--channel", "R"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
}

/// Exit code 2, a single line naming `mentions`, and no PNG.
fn assert_rejected(output: &Output, png: &Path, mentions: &str) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains(mentions), "expected \"{mentions}\" in: {stderr}");
    assert!(!png.exists(), "{} was written", png.display());
}

#[test]
fn bad_inputs_are_one_line_errors_with_exit_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("out.png");

    let unpolarised = render(dir.path(), "unpolarised", &["--unpolarized"]);
    assert_rejected(&polviz(&unpolarised, &png, &[]), &png, "unpolarised render");

    let mono_unpolarised = render(dir.path(), "mono_unpolarised", &["--unpolarized", "--wavelength", "550"]);
    assert_rejected(&polviz(&mono_unpolarised, &png, &[]), &png, "unpolarised render");

    let text = dir.path().join("notes.exr");
    std::fs::write(&text, "not an image").unwrap();
    assert_rejected(&polviz(&text, &png, &[]), &png, "not a readable OpenEXR image");

    assert_rejected(&polviz(&dir.path().join("missing.exr"), &png, &[]), &png, "no such file");

    let colour = render(dir.path(), "colour", &[]);
    let jpeg = dir.path().join("out.jpg");
    assert_rejected(&polviz(&colour, &jpeg, &[]), &jpeg, "must be a .png file");

    // A directory where a file is in the way cannot be created.
    let blocked = dir.path().join("notes.exr/out.png");
    assert_rejected(&polviz(&colour, &blocked, &[]), &blocked, "is not a directory");

    let mono = render(dir.path(), "mono", &["--wavelength", "550"]);
    assert_rejected(&polviz(&mono, &png, &["--channel", "G"]), &png, "--channel needs the RGB Stokes layers");

    // No temporary file of the atomic write was left behind either.
    let temporaries: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.starts_with('.'))
        .collect();
    assert!(temporaries.is_empty(), "{temporaries:?}");
}
