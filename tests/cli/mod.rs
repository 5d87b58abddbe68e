//! Shared by the tests that run the `prisma` binary on scenes they write (`output_safety.rs`,
//! `reliability.rs`): the command, a scene in a temporary directory, a quiet render, and the
//! rule for a refused input (exit 2, one line naming what is wrong).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The `prisma` binary cargo built for these tests.
pub fn prisma() -> Command {
    Command::new(env!("CARGO_BIN_EXE_prisma"))
}

/// A temporary directory holding `scene.toml` with `text`.
pub fn scene_dir(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temporary directory");
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, text).expect("scene");
    (dir, scene)
}

/// `prisma render SCENE --quiet ARGS…`, run to its end.
pub fn render(scene: &Path, args: &[&str]) -> Output {
    prisma().arg("render").arg(scene).arg("--quiet").args(args).output().expect("prisma runs")
}

/// What the run wrote to standard error.
pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// The run was refused as bad input: exit 2 and one line holding every one of `fragments`.
pub fn assert_refused(output: &Output, fragments: &[&str]) {
    let message = stderr(output);
    assert_eq!(output.status.code(), Some(2), "{message}");
    assert_eq!(message.trim_end().lines().count(), 1, "not one line: {message}");
    for fragment in fragments {
        assert!(message.contains(fragment), "{fragment:?} missing: {message}");
    }
}
