//! Every command the docs show runs: the `sh` blocks of README.md, docs/farm.md, scenes/README.md
//! and validation/README.md, in order, in a scratch directory laid out like the source tree
//! (`scenes/`, `tests/` and `validation/`'s files linked, `out/` and `validation/report` its own),
//! so that a flag renamed, a scene or case removed, or an output moved fails here instead of on
//! a new user's first hour.
//!
//! Each `prisma …` or `cargo run --release [-- …]` line runs as written but for its cost, which
//! CI cannot pay for every render: renders get `--width 48 --height 27 --spp 1` (replacing
//! those flags where the line has them). `validate` runs as written (about a minute for every
//! case): every case must pass, and with `--fault` the command must fail. What is checked: the
//! exit code, and every `out/…` file a line's comment says it writes.
//! `scene.toml`, the docs' stand-in for the user's own scene, is `scenes/tp6_point.toml` at
//! 800×450 and 256 samples per pixel (the sizes the docs' crops and sample ranges assume). A
//! line that crops keeps the image's size, and one that picks samples keeps the sample count.

use std::path::{Path, PathBuf};
use std::process::Command;

const DOCS: [&str; 4] = ["README.md", "docs/farm.md", "scenes/README.md", "validation/README.md"];

/// A documented command: the file and line it is on, its arguments, the outputs its comment
/// names.
#[derive(Debug)]
struct Documented {
    place: String,
    args: Vec<String>,
    outputs: Vec<String>,
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The `prisma` and `cargo run` lines of `text`'s shell blocks.
fn commands(name: &str, text: &str) -> Vec<Documented> {
    let mut found = Vec::new();
    let mut in_block = false;
    for (number, line) in text.lines().enumerate() {
        if line.starts_with("```") {
            in_block = !in_block && matches!(line.trim_start_matches('`'), "" | "sh" | "bash" | "console");
            continue;
        }
        if !in_block {
            continue;
        }
        let (command, comment) = match line.find(" #") {
            Some(at) => (&line[..at], &line[at..]),
            None => (line, ""),
        };
        let words: Vec<String> = command.split_whitespace().map(str::to_owned).collect();
        let args = match words.first().map(String::as_str) {
            Some("prisma") => words[1..].to_vec(),
            Some("cargo") if words.get(1..3) == Some(&["run".into(), "--release".into()]) => {
                words.iter().skip(3).skip_while(|w| *w == "--").cloned().collect()
            }
            _ => continue,
        };
        let outputs = comment
            .split(|c: char| c.is_whitespace() || c == ',' || c == '(' || c == ')')
            .filter(|word| word.starts_with("out/") && word.len() > 4)
            .map(|word| word.trim_end_matches(['.', ';', ':']).to_owned())
            .collect();
        found.push(Documented { place: format!("{name}:{}", number + 1), args, outputs });
    }
    found
}

/// `args` at a cost CI can pay (see the module doc).
fn affordable(args: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    // A line that picks samples keeps the render's sample count (its ranges must fit in it).
    let keeps_spp = args.iter().any(|w| w.starts_with("--samples") || w.starts_with("--resume"));
    // A line that crops keeps the image's size (its window must fit in it).
    let keeps_size = args.iter().any(|w| w.starts_with("--crop") || w.starts_with("--resume"));
    let is_render = args.first().is_some_and(|a| a == "render");
    let replaced = |flag: &str| {
        is_render
            && (["--width", "--height"].contains(&flag) && !keeps_size || (flag == "--spp" && !keeps_spp))
    };
    let mut words = args.iter();
    while let Some(word) = words.next() {
        if replaced(word) {
            words.next();
        } else if !(word.starts_with("--")
            && word.contains('=')
            && replaced(word.split('=').next().unwrap_or("")))
        {
            out.push(word.clone());
        }
    }
    match out.first().map(String::as_str) {
        Some("render") if !out.iter().any(|w| w == "--help") => {
            if !keeps_size {
                out.extend(["--width", "48", "--height", "27"].map(String::from));
            }
            if !keeps_spp {
                out.extend(["--spp", "1"].map(String::from));
            }
        }
        _ => {}
    }
    out
}

/// A scratch directory laid out like the source tree.
fn scratch() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    let root = root();
    for name in ["scenes", "tests", "data"] {
        std::os::unix::fs::symlink(root.join(name), dir.path().join(name)).expect("link");
    }
    // validation/ is a directory of its own, so that `--report validation/report` stays here.
    let validation = dir.path().join("validation");
    std::fs::create_dir(&validation).expect("validation dir");
    for entry in std::fs::read_dir(root.join("validation")).expect("validation/") {
        let entry = entry.expect("entry");
        if entry.file_name() != "report" {
            std::os::unix::fs::symlink(entry.path(), validation.join(entry.file_name())).expect("link");
        }
    }
    // The docs' own scene: 800×450 (their crops), 256 samples per pixel (their sample ranges).
    let scene = std::fs::read_to_string(root.join("scenes/tp6_point.toml")).expect("scene");
    let stand_in = scene
        .replace("spp = 16", "spp = 256")
        .replace("width = 600\nheight = 400", "width = 800\nheight = 450");
    assert!(
        stand_in.contains("spp = 256") && stand_in.contains("height = 450"),
        "tp6_point.toml changed: update this stand-in"
    );
    std::fs::write(dir.path().join("scene.toml"), stand_in).expect("scene.toml");
    dir
}

fn run_documented(doc: &str) -> Vec<String> {
    let text = std::fs::read_to_string(root().join(doc)).expect("doc");
    let dir = scratch();
    let mut problems = Vec::new();
    for command in commands(doc, &text) {
        let args = affordable(&command.args);
        let output = Command::new(env!("CARGO_BIN_EXE_prisma"))
            .args(&args)
            .current_dir(dir.path())
            .env_remove("PRISMA_THREADS")
            .output()
            .expect("prisma runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        let validate = args.first().is_some_and(|a| a == "validate");
        let fault = args.iter().any(|a| a == "--fault");
        let expected: &[i32] = match (validate, fault) {
            (true, true) => &[1],
            (true, false) => &[0],
            _ => &[0],
        };
        match output.status.code() {
            Some(code) if expected.contains(&code) => {}
            code => problems.push(format!(
                "{}: `prisma {}` exited {code:?}: {}",
                command.place,
                args.join(" "),
                stderr.lines().last().unwrap_or("")
            )),
        }
        for written in &command.outputs {
            if !dir.path().join(written).exists() {
                problems.push(format!(
                    "{}: the comment says it writes {written}, which is not there",
                    command.place
                ));
            }
        }
    }
    problems
}

#[test]
fn the_readmes_commands_run_as_written() {
    let problems = run_documented("README.md");
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_other_docs_commands_run_as_written() {
    let mut problems = Vec::new();
    for doc in &DOCS[1..] {
        problems.extend(run_documented(doc));
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_extraction_finds_what_the_docs_show() {
    let text = "x\n```sh\nprisma render scenes/a.toml --spp 64   # out/a.exr + .png\ncargo run --release -- validate --case b\ncargo run --release\nls\n```\nprisma not-in-a-block\n";
    let found = commands("T.md", text);
    assert_eq!(found.len(), 3, "{found:?}");
    assert_eq!(found[0].args, ["render", "scenes/a.toml", "--spp", "64"]);
    assert_eq!(found[0].outputs, ["out/a.exr"]);
    assert_eq!(found[1].args, ["validate", "--case", "b"]);
    assert!(found[2].args.is_empty());
    assert_eq!(
        affordable(&found[0].args),
        ["render", "scenes/a.toml", "--width", "48", "--height", "27", "--spp", "1"]
    );
    let root = root();
    for doc in DOCS {
        let text = std::fs::read_to_string(root.join(doc)).expect("doc");
        let _ = Path::new(doc);
        assert!(
            doc == "scenes/README.md" || doc == "validation/README.md" || !commands(doc, &text).is_empty(),
            "{doc}"
        );
    }
}
