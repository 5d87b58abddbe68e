//! `prisma fresnel` as a user meets it: the CSV names its interface, a metal is refused outside
//! its measured data, and the Mitsuba fixture plots have one legend line per relative index,
//! outside the plot area. Each case runs the real binary.

use std::path::Path;
use std::process::{Command, Output};

fn prisma(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_prisma")).arg("fresnel").args(args).output().unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// The value of `column` in the first data row of a `prisma fresnel` CSV.
fn first_row_field(csv: &str, column: &str) -> String {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let row: Vec<&str> = lines.next().expect("a row").split(',').collect();
    let index =
        header.iter().position(|c| *c == column).unwrap_or_else(|| panic!("no {column} in {header:?}"));
    row[index].to_owned()
}

/// Water as a plain index (the README's `--ior 1.33 -o water.csv`) is a dielectric, not glass.
#[test]
fn a_plain_index_is_a_dielectric_in_the_csv() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("water.csv");
    let output = prisma(&["--ior", "1.33", "-o", csv.to_str().unwrap()]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(first_row_field(&text, "interface"), "dielectric");
    assert_eq!(first_row_field(&text, "n"), "1.33");
}

/// Gold is tabulated over 292.4–984 nm (Johnson & Christy 1972); at 2000 nm prisma used to hold
/// the 984 nm value silently. Outside the data it refuses, as bad input, in one line.
#[test]
fn a_metal_outside_its_tabulated_data_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("au.csv");
    for wavelength in ["2000", "250"] {
        let output = prisma(&["--ior", "gold", "--wavelength", wavelength, "-o", csv.to_str().unwrap()]);
        let message = stderr(&output);
        assert_eq!(output.status.code(), Some(2), "at {wavelength} nm: {message}");
        assert_eq!(message.trim_end().lines().count(), 1, "not one line: {message}");
        for fragment in ["--wavelength", wavelength, "gold", "292.4", "984 nm"] {
            assert!(message.contains(fragment), "{fragment:?} missing from: {message}");
        }
        assert!(!csv.exists(), "a CSV was written at {wavelength} nm");
    }
    // Inside the data, and at its ends, the curves are written.
    for wavelength in ["292.4", "650", "984"] {
        let output = prisma(&["--ior", "Au", "--wavelength", wavelength, "-o", csv.to_str().unwrap()]);
        assert!(output.status.success(), "at {wavelength} nm: {}", stderr(&output));
        let text = std::fs::read_to_string(&csv).unwrap();
        assert_eq!(first_row_field(&text, "interface"), "gold");
    }
}

/// The text elements of an SVG written by plotters: (x, text).
fn svg_texts(svg: &str) -> Vec<(f64, String)> {
    svg.split("<text")
        .skip(1)
        .map(|element| {
            let x = element
                .split("x=\"")
                .nth(1)
                .and_then(|rest| rest.split('"').next())
                .and_then(|x| x.parse().ok())
                .expect("an x attribute");
            let body = element.split_once('>').expect("a tag end").1;
            (x, body.split("</text>").next().unwrap_or_default().trim().to_owned())
        })
        .collect()
}

fn fixture_plot(fixture: &str) -> Vec<(f64, String)> {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("plot.svg");
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(fixture);
    let output = prisma(&["--fixture", fixture.to_str().unwrap(), "--plot", svg.to_str().unwrap()]);
    assert!(output.status.success(), "{}", stderr(&output));
    svg_texts(&std::fs::read_to_string(&svg).unwrap())
}

/// The polarised fixture has 8 relative indices and two quantities (Rs, Rp) compared with
/// Mitsuba: 32 curves. The legend had a line per curve (32, over a third of the plot); it has one
/// per η, one per drawing style, and all of them right of the plot area (right of the x axis's
/// last tick, cos θi = 1), where they cover no curve.
#[test]
fn fixture_plot_legend_has_one_line_per_index_outside_the_plot() {
    let texts = fixture_plot("fresnel_polarized.csv");
    let etas = ["0.5", "0.6667", "0.75", "1", "1.0001", "1.33", "1.5", "2.4"];
    // "1.0" labels the top of the y axis (left) and cos θi = 1 (the right end of the x axis).
    let plot_right = texts.iter().filter(|(_, text)| text == "1.0").map(|&(x, _)| x).fold(f64::NAN, f64::max);
    assert!(plot_right > 500.0, "no x tick at cos θi = 1 ({plot_right})");
    for eta in etas {
        // Right of the y axis's tick labels (one of which reads 0.5).
        let lines: Vec<&(f64, String)> = texts.iter().filter(|(x, text)| text == eta && *x > 100.0).collect();
        assert_eq!(lines.len(), 1, "legend lines for η = {eta}: {lines:?}");
        assert!(
            lines[0].0 > plot_right,
            "η = {eta} at x = {} inside the plot (right edge {plot_right})",
            lines[0].0
        );
    }
    for style in ["prisma Rs = |r_s|²", "prisma Rp = |r_p|²", "Mitsuba 3"] {
        assert_eq!(texts.iter().filter(|(_, text)| text == style).count(), 1, "{style}");
    }
    assert!(!texts.iter().any(|(_, text)| text.contains("η = ")), "a line per curve is back");
}
