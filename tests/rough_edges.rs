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

/// Issue 38: `--spp -4` said "unexpected argument"; a missing argument was not named.
#[test]
fn negative_counts_and_missing_arguments_are_named() {
    let output = prisma(&["render", "scenes/tp6_point.toml", "--spp", "-4"]);
    let message = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{message}");
    assert!(message.contains("-4 is not in 1..="), "{message}");
    let output = prisma(&["merge", "a.exr"]);
    let message = String::from_utf8_lossy(&output.stderr);
    assert_eq!(message.lines().count(), 1, "{message}");
    assert!(message.contains("not provided: --output <OUT.exr>"), "{message}");
}

/// Issue 38: the README's caustic render of a scene replaced its Whitted render at the same
/// default name. Caustics turned on (or off) by a flag now name the output, and a default output
/// that holds a render of other settings is replaced with a warning.
#[test]
fn default_outputs_of_different_settings_do_not_collide_silently() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/tp6_mirror_glass.toml");
    let run = |extra: &[&str]| {
        let mut args = vec!["render", scene, "--width", "16", "--height", "12", "--spp", "1", "-q"];
        args.extend_from_slice(extra);
        let output = Command::new(env!("CARGO_BIN_EXE_prisma"))
            .args(&args)
            .current_dir(dir.path())
            .output()
            .expect("runs");
        assert!(output.status.success(), "{output:?}");
        String::from_utf8_lossy(&output.stderr).into_owned()
    };
    assert_eq!(run(&[]), "");
    assert_eq!(run(&["--caustics", "--light-paths", "1000"]), "");
    for name in ["tp6_mirror_glass.exr", "tp6_mirror_glass_with_caustics.exr"] {
        assert!(dir.path().join("out").join(name).exists(), "{name}");
    }
    let warned = run(&["--seed", "7"]);
    assert!(
        warned.contains("warning: replacing out/tp6_mirror_glass.exr, a render of other seed"),
        "{warned}"
    );
    assert_eq!(run(&["--seed", "7"]), "", "the same settings again: no warning");
}
