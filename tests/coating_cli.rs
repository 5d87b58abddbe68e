//! `prisma fresnel --coating` and `--film-colours` as a user meets them: the CSV of a
//! quarter-wave MgF₂ layer on N-BK7 against the closed form, a film's colour chart against the
//! bounds physics sets, and bad coatings refused in one line with exit code 2 and no output.
//! Each case runs the real binary.

use std::path::Path;
use std::process::{Command, Output};

use prisma::optics::catalogue;

fn prisma(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_prisma")).arg("fresnel").args(args).output().unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// The CSV at `path` as (header, rows of numbers).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(str::to_owned).collect();
    let rows = lines.map(|line| line.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header.iter().position(|c| c == name).unwrap_or_else(|| panic!("no {name} in {header:?}"))
}

/// n of N-BK7 at 550 nm, from the catalogue the binary uses (1.5185).
fn n_bk7_550() -> f64 {
    f64::from(catalogue::glass("N-BK7").unwrap().ior().eval(550.0))
}

/// A quarter-wave layer n₁ = 1.38 (MgF₂) on N-BK7 at 550 nm, normal incidence: the layer turns
/// the substrate's admittance n_s into n₁²/n_s (Macleod §3.2), so
/// R = ((n₀ n_s − n₁²)/(n₀ n_s + n₁²))², 1.27 %, against ((n_s − 1)/(n_s + 1))² = 4.24 % bare;
/// s and p agree at 0°, ψ = 45°, Δ = 180° (r_p = −r_s), and T = 1 − R (no absorption).
#[test]
fn a_quarter_wave_mgf2_layer_on_n_bk7_matches_the_closed_form() {
    let dir = tempfile::tempdir().unwrap();
    let ns = n_bk7_550();
    let n1: f64 = 1.38;
    let quarter_wave = format!("1.38:{}", 550.0 / (4.0 * n1));
    let coated = ((ns - n1 * n1) / (ns + n1 * n1)).powi(2);
    let bare = ((ns - 1.0) / (ns + 1.0)).powi(2);
    assert!((coated - 0.0127).abs() < 2e-4 && (bare - 0.0424).abs() < 2e-4, "{coated} {bare}");
    for (against, x_column, x) in [("angle", "angle_deg", 0.0), ("wavelength", "wavelength_nm", 550.0)] {
        let csv = dir.path().join(format!("{against}.csv"));
        let output = prisma(&[
            "--ior",
            "N-BK7",
            "--coating",
            &quarter_wave,
            "--wavelength",
            "550",
            "--against",
            against,
            "-o",
            csv.to_str().unwrap(),
        ]);
        assert!(output.status.success(), "{}", stderr(&output));
        let (header, rows) = read_csv(&csv);
        assert_eq!(rows.len(), if against == "angle" { 361 } else { 471 });
        let row = rows.iter().find(|row| row[column(&header, x_column)] == x).expect("the design row");
        let value = |name: &str| row[column(&header, name)];
        for name in ["rs", "rp", "r"] {
            assert!((value(name) - coated).abs() < 1e-9, "{against}: {name} = {} vs {coated}", value(name));
        }
        assert!((value("r_bare") - bare).abs() < 1e-9, "{against}: bare {}", value("r_bare"));
        assert!((value("t") - (1.0 - coated)).abs() < 1e-9);
        assert!((value("psi_deg") - 45.0).abs() < 1e-6);
        assert!((value("delta_deg").abs() - 180.0).abs() < 1e-6);
        // Lossless layers and substrate: R + T = 1 in every row, for s and p.
        for row in &rows {
            for (r, t) in [("rs", "ts"), ("rp", "tp")] {
                let sum = row[column(&header, r)] + row[column(&header, t)];
                assert!((sum - 1.0).abs() < 1e-9, "{against}: R + T = {sum}");
            }
        }
    }
}

/// A layer of zero thickness is no layer: the coated curves are the bare interface's, at every
/// angle, Brewster's angle (R_p = 0 at atan n_s) included.
#[test]
fn a_layer_of_zero_thickness_is_the_bare_interface() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("bare.csv");
    let output = prisma(&[
        "--ior",
        "N-BK7",
        "--coating",
        "1.38:0",
        "--wavelength",
        "550",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let (header, rows) = read_csv(&csv);
    let (r, r_bare, rp) = (column(&header, "r"), column(&header, "r_bare"), column(&header, "rp"));
    for row in &rows {
        assert!((row[r] - row[r_bare]).abs() < 1e-12, "{row:?}");
    }
    let brewster = n_bk7_550().atan().to_degrees();
    let nearest =
        rows.iter().min_by(|a, b| (a[0] - brewster).abs().total_cmp(&(b[0] - brewster).abs())).unwrap();
    assert!(nearest[rp] < 1e-5, "R_p = {} at {}° (Brewster {brewster}°)", nearest[rp], nearest[0]);
}

/// Each bad coating: one line naming `--coating` and the item at fault, exit code 2, and
/// neither the CSV nor the plot written.
#[test]
fn bad_coatings_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("c.csv");
    let plot = dir.path().join("c.png");
    let too_many = vec!["1.38:10"; 65].join(",");
    for (coating, fragment) in [
        ("1.38:-5", "1.38:-5"),
        ("1.38:1e9", "1.38:1e9"),
        ("1.38:inf", "1.38:inf"),
        (too_many.as_str(), "65 layers"),
        ("unobtainium:10", "unobtainium"),
        ("1.38:99.64,MgF2-ish:10", "MgF2-ish"),
        ("1.38-99", "1.38-99"),
        ("1.38:ten", "ten"),
        ("", "expected INDEX:THICKNESS_NM"),
    ] {
        let output = prisma(&[
            "--ior",
            "N-BK7",
            "--coating",
            coating,
            "-o",
            csv.to_str().unwrap(),
            "--plot",
            plot.to_str().unwrap(),
        ]);
        let message = stderr(&output);
        assert_eq!(output.status.code(), Some(2), "{coating}: {message}");
        assert_eq!(message.trim_end().lines().count(), 1, "{coating}: not one line: {message}");
        assert!(message.contains("--coating"), "{coating}: {message}");
        assert!(message.contains(fragment), "{coating}: {fragment:?} missing from {message}");
        assert!(!csv.exists() && !plot.exists(), "{coating}: an output was written");
    }
}

/// The soap-film chart: 1501 thicknesses; black at d = 0 (the two reflections cancel); Y never
/// above the film's largest reflectance ((n² − 1)/(n² + 1))² = 7.8 % for n = 1.333, reached at
/// the quarter wave (Y is a weighted mean of R(λ)); and the plot written beside it.
#[test]
fn the_film_colour_chart_is_black_when_thin_and_bounded_by_the_quarter_wave() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("soap.csv");
    let plot = dir.path().join("soap.png");
    let output = prisma(&[
        "--film-colours",
        "--ior",
        "1.333",
        "-o",
        csv.to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(plot.exists());
    let (header, rows) = read_csv(&csv);
    assert_eq!(header, ["thickness_nm", "X", "Y", "Z", "R", "G", "B"]);
    assert_eq!(rows.len(), 1501);
    assert!(rows[0][1..].iter().all(|&v| v == 0.0), "{:?}", rows[0]);
    let n: f64 = 1.333;
    let bound = ((n * n - 1.0) / (n * n + 1.0)).powi(2);
    let brightest = rows.iter().map(|row| row[2]).fold(0.0, f64::max);
    assert!(brightest <= bound + 1e-6 && brightest > 0.9 * bound, "Y max {brightest} vs {bound}");
}
