//! `prisma lens FILE`: the printed first-order numbers are the lens's (the values rayoptics
//! gives for the shipped double Gauss, validation/lens/fixtures/dgauss50.json, to the printed
//! digits), the plot and its CSV are written, and bad input is one line with exit code 2.

use std::path::Path;
use std::process::Command;

fn prisma() -> Command {
    Command::new(env!("CARGO_BIN_EXE_prisma"))
}

fn lens_file(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/lenses").join(name)
}

#[test]
fn prints_the_double_gauss_and_writes_its_plot_and_csv() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let plot = dir.path().join("dgauss.png");
    let output =
        prisma().arg("lens").arg(lens_file("dgauss50.dat")).arg("--plot").arg(&plot).output().expect("runs");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let text = String::from_utf8_lossy(&output.stdout);
    // rayoptics at the d line: EFL 50.350816626711065, BFL 36.09873605197498, f/2.02975;
    // F − C focal shift −0.12265 − 0.08450 = −0.20715 mm.
    for expected in ["50.350817 mm", "36.098736 mm", "2.0297", "F − C: -0.207150 mm"] {
        assert!(text.contains(expected), "missing {expected:?} in:\n{text}");
    }
    assert!(std::fs::metadata(&plot).expect("plot").len() > 10_000);
    let csv = std::fs::read_to_string(plot.with_extension("csv")).expect("csv");
    assert!(csv.starts_with("curve,field_deg,wavelength_nm,x,y\n"));
    for curve in ["spot_mm,", "focal_shift_mm,", "relative_illumination,", "transmission,"] {
        assert!(csv.contains(curve), "no {curve} rows");
    }
}

#[test]
fn pbrt_s_own_file_has_no_chromatic_focal_shift() {
    let output = prisma().arg("lens").arg(lens_file("dgauss50_pbrt.dat")).output().expect("runs");
    assert!(output.status.success());
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(text.contains("F − C: +0.000000 mm"), "{text}");
}

#[test]
fn bad_input_is_one_line_and_exit_2() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let bad = dir.path().join("bad.dat");
    std::fs::write(&bad, "10 2 1.5\n").expect("write");
    let missing = dir.path().join("missing.dat");
    let plot = dir.path().join("plot.txt");
    let cases: Vec<(Vec<std::ffi::OsString>, &str)> = vec![
        (vec![bad.clone().into()], "bad.dat:1"),
        (vec![missing.into()], "cannot open"),
        (vec![lens_file("achromat.zmx").into(), "--field-deg".into(), "95".into()], "--field-deg"),
        (vec![lens_file("achromat.zmx").into(), "--plot".into(), plot.clone().into()], ".svg or .png"),
    ];
    for (args, needle) in cases {
        let output = prisma().arg("lens").args(&args).output().expect("runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
    }
    assert!(!plot.exists(), "no output for bad input");
}
