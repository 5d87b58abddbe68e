//! The small things a new user hits first (issue 16, "rough edges"): tables readable by other
//! tools, arguments checked before work, exit codes that tell bad input from failure.

use std::process::{Command, Output};

fn prisma(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_prisma")).args(args).output().expect("prisma runs")
}

#[test]
fn fresnel_csv_has_no_comment_line() {
    // pandas.read_csv takes the first line as the header: it must be the column names, with
    // the interface in columns of every row.
    let dir = tempfile::tempdir().expect("temporary directory");
    let csv = dir.path().join("water.csv");
    let output = prisma(&["fresnel", "--ior", "1.33", "-o", &csv.to_string_lossy()]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let text = std::fs::read_to_string(&csv).expect("csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    assert_eq!(header[0], "angle_deg");
    assert!(header.contains(&"n") && header.contains(&"interface"), "{header:?}");
    let first: Vec<&str> = lines.next().expect("a row").split(',').collect();
    assert_eq!(first.len(), header.len());
    // Normal incidence on water: R = ((1.33 − 1)/(1.33 + 1))² = 0.02006.
    let r: f64 = first[3].parse().expect("number");
    assert!((r - 0.020_06).abs() < 1e-4, "{r}");
    assert!(!text.contains('#'));
}

#[test]
fn bad_plot_extension_is_bad_input_before_any_work() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let plot = dir.path().join("n.jpg");
    let output = prisma(&["glass", "N-BK7", "--plot", &plot.to_string_lossy()]);
    assert_eq!(output.status.code(), Some(2), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(output.stdout.is_empty(), "the table was printed before the error");
    let output = prisma(&["fresnel", "--ior", "1.5", "--plot", &plot.to_string_lossy()]);
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(std::fs::read_dir(dir.path()).expect("dir").count(), 0);
}

#[test]
fn negative_numbers_need_no_equals_sign() {
    // `--ior -1.5` reaches prisma's own check (a negative index is refused), not clap's
    // "unexpected argument".
    let output = prisma(&["fresnel", "--ior", "-1.5"]);
    let message = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{message}");
    assert!(message.contains("--ior must be finite and > 0"), "{message}");
    let output = prisma(&["render", "x.toml", "--wavelength", "-5"]);
    assert!(String::from_utf8_lossy(&output.stderr).contains("--wavelength must be in"));
}
