//! `prisma render --samples/--crop/--part/--resume`, `prisma merge` and `prisma info` as users
//! run them: parts merge into the single render's pixels, every refusal is one line with exit
//! code 2 and no output, and an interrupted render (a test hook, and a real SIGINT) leaves an
//! earlier output intact, writes a part and resumes into the uninterrupted image.

use std::path::Path;
use std::process::{Command, Output, Stdio};

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/showcase.toml");

fn prisma(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_prisma")).args(args).output().expect("prisma runs")
}

fn ok(args: &[&str]) -> String {
    let output = prisma(args);
    assert!(output.status.success(), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// The `prisma info` line starting with `key:`.
fn info(path: &Path, key: &str) -> String {
    let text = ok(&["info", path.to_str().unwrap()]);
    text.lines()
        .find_map(|line| line.strip_prefix(&format!("{key}: ")))
        .unwrap_or_else(|| panic!("no {key} in {text}"))
        .to_owned()
}

fn render(dir: &Path, name: &str, extra: &[&str]) -> std::path::PathBuf {
    let out = dir.join(name);
    let mut args = vec!["render", SCENE, "--width", "48", "--height", "27", "--spp", "6", "-q", "-o"];
    args.push(out.to_str().unwrap());
    args.extend_from_slice(extra);
    ok(&args);
    out
}

/// `prisma render` of the test scene into `out`, stopped after its first sample block as
/// Ctrl-C would stop it (the test hook).
fn interrupted_render(out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_prisma"))
        .args(["render", SCENE, "--width", "48", "--height", "27", "--spp", "6", "-o", out.to_str().unwrap()])
        .env("PRISMA_TEST_STOP_AFTER_BLOCKS", "1")
        .output()
        .unwrap()
}

/// `prisma render --resume PARTIAL -o OUT` of the test scene; what it printed.
fn resume(partial: &Path, out: &Path) -> String {
    let (partial, out) = (partial.to_str().unwrap(), out.to_str().unwrap());
    ok(&["render", SCENE, "--width", "48", "--height", "27", "--resume", partial, "-o", out])
}

fn refused(args: &[&str], expected: &str) {
    let output = prisma(args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    assert!(stderr.contains(expected), "{args:?}: expected \"{expected}\" in {stderr}");
}

#[test]
fn parts_merge_into_the_single_render_and_info_tells_what_they_are() {
    let dir = tempfile::tempdir().unwrap();
    let single = render(dir.path(), "single.exr", &["--part"]);
    let a = render(dir.path(), "a.exr", &["--samples", "0..2"]);
    let b = render(dir.path(), "b.exr", &["--samples", "2..6", "--crop", "0,0,48,10", "--threads", "1"]);
    let c = render(dir.path(), "c.exr", &["--samples", "2..6", "--crop", "0,10,48,27"]);
    let merged = dir.path().join("merged.exr");
    let summary = ok(&[
        "merge",
        "--complete",
        "--keep-sums",
        c.to_str().unwrap(),
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "-o",
        merged.to_str().unwrap(),
    ]);
    assert!(summary.contains("merged 3 parts: samples 0..6 of 0..6"), "{summary}");
    for key in ["imageSha256", "sumsBlake3", "samples", "crop"] {
        assert_eq!(info(&merged, key), info(&single, key), "{key}");
    }
    // A plain render has the same pixels (it keeps no sums).
    let plain = render(dir.path(), "plain.exr", &[]);
    assert_eq!(info(&plain, "imageSha256"), info(&single, "imageSha256"));
    // What info prints: provenance, samples, window, settings, windows.
    let text = ok(&["info", b.to_str().unwrap()]);
    for expected in [
        "version: ",
        "commit: ",
        "sceneSha256: ",
        "seed: 1",
        "samples: 2..6",
        "spp: 6",
        "crop: 0,0,48,10",
        "\"max_depth\":12",
        "\"prune_below\":0.01",
        "\"wavelengths\":4",
        "\"polarized\":true",
        "\"caustics\":false",
        "wallSeconds: ",
        "threads: 1",
        "displayWindow: 0,0,48,27",
        "dataWindow: 0,0,48,10",
    ] {
        assert!(text.contains(expected), "no \"{expected}\" in:\n{text}");
    }
    assert_eq!(info(&merged, "parts"), "3");
}

#[test]
fn merge_refusals_are_one_line_exit_2_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let a = render(dir.path(), "a.exr", &["--samples", "0..3"]);
    let b = render(dir.path(), "b.exr", &["--samples", "2..6"]);
    let seeded = render(dir.path(), "seeded.exr", &["--samples", "3..6", "--seed", "9"]);
    let plain = render(dir.path(), "plain.exr", &[]);
    let out = dir.path().join("out.exr");
    let (a, b, seeded, plain, o) = (
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        seeded.to_str().unwrap(),
        plain.to_str().unwrap(),
        out.to_str().unwrap(),
    );
    refused(&["merge", a, b, "-o", o], "overlapping parts");
    refused(&["merge", a, seeded, "-o", o], "different seed");
    refused(&["merge", a, "--complete", "-o", o], "samples 3..6 of 0..6 are missing");
    refused(&["merge", a, plain, "-o", o], "has no per-pixel sums");
    refused(&["merge", a, a, "-o", o], "given twice");
    // A truncated file and a corrupt one.
    let bytes = std::fs::read(a).unwrap();
    let truncated = dir.path().join("truncated.exr");
    std::fs::write(&truncated, &bytes[..bytes.len() * 2 / 3]).unwrap();
    refused(&["merge", truncated.to_str().unwrap(), "-o", o], "truncated.exr");
    let mut flipped = bytes.clone();
    let at = flipped.len() - 40;
    flipped[at] ^= 0x5a;
    let corrupt = dir.path().join("corrupt.exr");
    std::fs::write(&corrupt, &flipped).unwrap();
    // The last bytes are the last row of the last channel, a sum word (`sums.*` sort last).
    refused(&["merge", corrupt.to_str().unwrap(), "-o", o], "corrupt.exr: corrupt: the sums do not match");
    refused(&["merge", dir.path().join("none.exr").to_str().unwrap(), "-o", o], "none.exr");
    assert!(!out.exists(), "no output after a refusal");
    // Render-side refusals.
    refused(&["render", SCENE, "--samples", "4..2", "-o", o], "--samples");
    refused(&["render", SCENE, "--spp", "8", "--samples", "0..9", "-o", o], "goes past");
    refused(&["render", SCENE, "--crop", "0,0,900,10", "-o", o], "--crop");
    refused(
        &["render", SCENE, "--width", "48", "--height", "27", "--resume", plain, "-o", o],
        "has no per-pixel sums",
    );
}

/// The test hook stops a render after its first sample block as Ctrl-C would: exit code 130, a
/// part beside the output (whose earlier version is untouched), and `--resume` renders the rest
/// into the uninterrupted image.
#[test]
fn an_interrupted_render_writes_a_part_and_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let whole = render(dir.path(), "whole.exr", &["--part"]);
    let out = dir.path().join("image.exr");
    std::fs::write(&out, "an earlier render").unwrap();
    let output = interrupted_render(&out);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted: wrote samples 0..1 of 0..6"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "an earlier render", "the earlier output is intact");
    let partial = dir.path().join("image.partial.exr");
    assert_eq!(info(&partial, "samples"), "0..1");
    let resumed = dir.path().join("resumed.exr");
    resume(&partial, &resumed);
    assert_eq!(info(&resumed, "samples"), "0..6");
    assert_eq!(info(&resumed, "parts"), "2");
    for key in ["imageSha256", "sumsBlake3"] {
        assert_eq!(info(&resumed, key), info(&whole, key), "{key}");
    }
    // Resuming a part that is already whole renders nothing.
    refused(
        &[
            "render",
            SCENE,
            "--width",
            "48",
            "--height",
            "27",
            "--resume",
            resumed.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        "nothing to render",
    );
}

/// A real SIGINT in the middle of a long render: it stops at the end of its sample block,
/// writes its part and exits with 130.
#[cfg(unix)]
#[test]
fn sigint_stops_a_render_at_a_block_boundary_and_keeps_its_samples() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("long.exr");
    let child = Command::new(env!("CARGO_BIN_EXE_prisma"))
        .args([
            "render",
            SCENE,
            "--width",
            "32",
            "--height",
            "18",
            "--spp",
            "1000000",
            "--threads",
            "1",
            "-o",
            out.to_str().unwrap(),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let killed = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(killed.success());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted: stopping to write the samples done"), "{stderr}");
    let partial = dir.path().join("long.partial.exr");
    let samples = info(&partial, "samples");
    let count: u32 = samples.strip_prefix("0..").and_then(|n| n.parse().ok()).expect("0..N");
    assert!((1..1_000_000).contains(&count), "{samples}");
    assert!(!out.exists());
}

/// A batch render (no terminal: tests pipe stderr) logs its progress with the time left after
/// its first second, so that even a short part's log says how long it expects to take.
#[test]
fn a_part_without_a_terminal_logs_its_progress_and_time_left() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("part.exr");
    // About 2–4 s on one thread of the machines this runs on.
    let args = [
        "render",
        SCENE,
        "--width",
        "400",
        "--height",
        "225",
        "--spp",
        "16",
        "--samples",
        "0..16",
        "--threads",
        "1",
        "-o",
    ];
    let output = prisma(&[&args[..], &[out.to_str().unwrap()]].concat());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let line =
        stderr.lines().find(|line| line.starts_with("progress: ")).unwrap_or_else(|| panic!("{stderr}"));
    assert!(line.contains(" elapsed, about 0:0") && line.ends_with(" left"), "{line}");
}

/// A monochromatic render keeps one sum per Stokes component and pixel (its XYZ is (L, L, L)):
/// its parts, with caustics and split by samples and by rows, still merge into the single
/// render's pixels through the part files.
#[test]
fn monochromatic_caustic_parts_merge_into_the_single_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/validation/scenes/caustic_sphere.toml");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let mut args =
            vec!["render", scene, "--width", "32", "--height", "24", "--spp", "4", "--wavelength", "550"];
        args.extend_from_slice(&["--light-paths", "600", "-q", "-o", out.to_str().unwrap()]);
        args.extend_from_slice(extra);
        ok(&args);
        out
    };
    let single = render("single.exr", &["--part"]);
    let a = render("a.exr", &["--samples", "0..1"]);
    let b = render("b.exr", &["--samples", "1..4", "--crop", "0,0,32,9"]);
    let c = render("c.exr", &["--samples", "1..4", "--crop", "0,9,32,24", "--threads", "1"]);
    let merged = dir.path().join("merged.exr");
    let paths = [&c, &a, &b].map(|p| p.to_str().unwrap().to_owned());
    ok(&[
        "merge",
        "--complete",
        "--keep-sums",
        &paths[0],
        &paths[1],
        &paths[2],
        "-o",
        merged.to_str().unwrap(),
    ]);
    for key in ["imageSha256", "sumsBlake3", "samples"] {
        assert_eq!(info(&merged, key), info(&single, key), "{key}");
    }
    assert!(ok(&["info", single.to_str().unwrap()]).contains("\"caustics\":true"));
}

/// A polarised render with caustics and no polarising sheet keeps its light sums for S0 alone
/// (its splats are unpolarised), bands included: interrupted, written as a part and resumed (the part read back
/// with full light sums, the new samples' added to them), it still gives the single render's
/// pixels and sums.
#[test]
fn a_polarised_caustic_render_resumes_into_the_single_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/validation/scenes/caustic_sphere.toml");
    // With spectral bands, whose S0 values follow every component's colour in a pixel.
    let base = [
        "render",
        scene,
        "--width",
        "32",
        "--height",
        "24",
        "--spp",
        "4",
        "--light-paths",
        "600",
        "--spectral-bands",
        "4",
    ];
    let whole = dir.path().join("whole.exr");
    let mut args = base.to_vec();
    args.extend_from_slice(&["-q", "--part", "-o", whole.to_str().unwrap()]);
    ok(&args);
    assert!(ok(&["info", whole.to_str().unwrap()]).contains("\"polarized\":true"));
    let out = dir.path().join("image.exr");
    let output = Command::new(env!("CARGO_BIN_EXE_prisma"))
        .args(base)
        .args(["-o", out.to_str().unwrap()])
        .env("PRISMA_TEST_STOP_AFTER_BLOCKS", "1")
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(130), "{}", String::from_utf8_lossy(&output.stderr));
    let partial = dir.path().join("image.partial.exr");
    assert_eq!(info(&partial, "samples"), "0..1");
    let resumed = dir.path().join("resumed.exr");
    let mut args = base.to_vec();
    args.extend_from_slice(&["-q", "--resume", partial.to_str().unwrap(), "-o", resumed.to_str().unwrap()]);
    ok(&args);
    assert_eq!(info(&resumed, "samples"), "0..4");
    for key in ["imageSha256", "sumsBlake3"] {
        assert_eq!(info(&resumed, key), info(&whole, key), "{key}");
    }
}

/// A complete merge is the finished image: written as a render writes one (no sums, a PNG
/// preview beside it), with the single render's pixels; `--keep-sums` keeps the sums (the file
/// then merges and resumes again). Before, every merge wrote a part of sums (79 MB for the
/// showcase) and no preview.
#[test]
fn a_complete_merge_writes_the_finished_image_and_its_preview() {
    let dir = tempfile::tempdir().unwrap();
    let single = render(dir.path(), "single.exr", &[]);
    let a = render(dir.path(), "a.exr", &["--samples", "0..2"]);
    let b = render(dir.path(), "b.exr", &["--samples", "2..6"]);
    let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
    let final_exr = dir.path().join("final.exr");
    let said = ok(&["merge", a, b, "--complete", "-o", final_exr.to_str().unwrap()]);
    assert!(said.contains("final.png") && said.contains("the finished image"), "{said}");
    assert!(dir.path().join("final.png").exists(), "no preview");
    assert_eq!(info(&final_exr, "imageSha256"), info(&single, "imageSha256"));
    let text = ok(&["info", final_exr.to_str().unwrap()]);
    assert!(!text.contains("sumsFormat") && text.contains("0 of sums"), "{text}");
    assert!(std::fs::metadata(&final_exr).unwrap().len() < std::fs::metadata(a).unwrap().len());
    let kept = dir.path().join("kept.exr");
    ok(&[
        "merge",
        a,
        b,
        "--complete",
        "--keep-sums",
        "--preview",
        dir.path().join("k.png").to_str().unwrap(),
        "-o",
        kept.to_str().unwrap(),
    ]);
    assert_eq!(info(&kept, "samples"), "0..6");
    assert!(dir.path().join("k.png").exists());
    assert!(!dir.path().join("kept.png").exists());
    // A merge short of the whole render stays a part, so that it can be merged again.
    let partial = dir.path().join("partial.exr");
    let said = ok(&["merge", a, "-o", partial.to_str().unwrap()]);
    assert!(said.contains("a part, with its sums"), "{said}");
    assert!(ok(&["info", partial.to_str().unwrap()]).contains("sumsFormat"));
    refused(&["merge", a, b, "--keep-sums", "-o", partial.to_str().unwrap()], "--complete");
}

/// A render resumed from its own `OUT.partial.exr` into `OUT.exr` removes the partial file once
/// every sample is in the output, and says so; a part resumed into another name is left alone.
#[test]
fn a_finished_resume_removes_its_own_partial_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("image.exr");
    let interrupted = interrupted_render(&out);
    assert_eq!(interrupted.status.code(), Some(130));
    let stderr = String::from_utf8_lossy(&interrupted.stderr);
    assert!(!stderr.contains("error:"), "an interrupt is not an error: {stderr}");
    let partial = dir.path().join("image.partial.exr");
    let copy = dir.path().join("copy.exr");
    std::fs::copy(&partial, &copy).unwrap();
    let said = resume(&partial, &out);
    assert!(said.contains("removed") && !partial.exists(), "{said}");
    assert_eq!(info(&out, "samples"), "0..6");
    let other = dir.path().join("other.exr");
    resume(&copy, &other);
    assert!(copy.exists(), "a part resumed into another name is kept");
}
