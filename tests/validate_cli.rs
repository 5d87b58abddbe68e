//! What `prisma validate` tells its user: one progress line per case on standard error (plain
//! lines when it is not a terminal, none with `-q`), the table on standard output with its header
//! and its closing line, and a report whose verdict comes before the first case, with a link
//! to each case's section.
//!
//! Small, fast cases: two analytic ones and a Mitsuba one at a quarter of its resolution. The
//! Schlick fault makes the slab's transmittance fail (the exact Fresnel equations are what it
//! checks) and leaves the white furnace passing (a lossless object is invisible whatever its
//! reflectance).

use std::process::{Command, Output};

const ANALYTIC: [&str; 2] = ["furnace_glass", "slab_transmittance"];
const WITH_IMAGES: [&str; 3] = ["furnace_glass", "slab_transmittance", "dispersion_450"];

fn validate(cases: &[&str], extra: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_prisma"));
    command.current_dir(env!("CARGO_MANIFEST_DIR")).args(["validate", "--downsample", "4", "--threads", "2"]);
    for case in cases {
        command.args(["--case", case]);
    }
    command.args(extra).output().expect("prisma runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Checks that the report in `dir` states `verdict` before its contents and its first case,
/// and that each of `cases` has one section anchored by its name and linked from the contents.
fn check_report(dir: &std::path::Path, cases: &[&str], verdict: &str) -> String {
    let html = std::fs::read_to_string(dir.join("index.html")).expect("index.html");
    let at = |needle: &str| html.find(needle).unwrap_or_else(|| panic!("no {needle} in the report"));
    let verdict = at(verdict);
    assert!(verdict < at("id=\"contents\""));
    for case in cases {
        let section = at(&format!("<section id=\"{case}\">"));
        assert!(verdict < section && at(&format!("href=\"#{case}\"")) < section, "{case}");
        assert_eq!(html.matches(&format!("id=\"{case}\"")).count(), 1, "{case}: one anchor");
    }
    html
}

#[test]
fn progress_table_and_report_lead_with_the_verdict() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let report = dir.path().join("report");
    let output = validate(&ANALYTIC, &["--fault", "schlick", "--report", &report.to_string_lossy()]);
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    assert_eq!(output.status.code(), Some(1), "{stdout}\n{stderr}");

    // Standard error is a pipe here: one plain line per case, in order, then the error; no
    // carriage return or escape sequence.
    assert!(!stderr.contains('\r') && !stderr.contains('\x1b'), "{stderr:?}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), ANALYTIC.len() + 1, "{stderr}");
    for (line, expected) in
        lines.iter().zip(["[1/2] furnace_glass      … PASS (", "[2/2] slab_transmittance … FAIL ("])
    {
        assert!(line.starts_with(expected) && line.ends_with(" s)"), "{line:?} is not {expected:?}");
    }
    assert!(lines[2].contains("validation failed: slab_transmittance"), "{stderr}");

    // The table: a header, every case, and the verdict as the last line.
    let header = stdout.lines().find(|l| l.starts_with("case")).expect("a header row");
    for column in ["kind", "metric", "value", "threshold", "result"] {
        assert!(header.contains(column), "{header}");
    }
    for case in ANALYTIC {
        assert!(stdout.lines().any(|l| l.starts_with(case)), "no row for {case}:\n{stdout}");
    }
    assert_eq!(stdout.lines().last(), Some("validate: 1 passed, 1 failed"), "{stdout}");

    // The report names and links the failure in its verdict.
    let html = check_report(&report, &ANALYTIC, "1 of 2 cases failed");
    assert!(html.contains("1 of 2 cases failed: <a href=\"#slab_transmittance\">slab_transmittance</a></p>"));
    let markdown = std::fs::read_to_string(report.join("report.md")).expect("report.md");
    assert!(
        markdown.starts_with("# prisma validation report\n\n**1 of 2 cases failed:** [slab_transmittance](#slab_transmittance)\n"),
        "{markdown}"
    );
    assert!(markdown.find("## Contents") < markdown.find("## furnace_glass"));
}

#[test]
fn quiet_prints_no_progress_but_the_table() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let report = dir.path().join("report");
    let output = validate(&WITH_IMAGES, &["-q", "--report", &report.to_string_lossy()]);
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    assert!(output.status.success(), "{stdout}\n{stderr}");
    assert_eq!(stderr, "");
    assert_eq!(stdout.lines().last(), Some("validate: 3 passed, 0 failed"), "{stdout}");
    check_report(&report, &WITH_IMAGES, "All 3 cases passed");
    assert!(report.join("dispersion_450_z.png").is_file());
}
