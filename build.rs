//! Embeds the git commit the binary is built from as `PRISMA_COMMIT` (for the provenance in
//! every EXR header): `git rev-parse HEAD`, with `-dirty` when tracked files differ from it, or
//! "unknown" outside a git checkout (a source tarball), never failing the build.

use std::path::Path;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let output = Command::new("git").args(args).output().ok()?;
    output.status.success().then(|| String::from_utf8_lossy(&output.stdout).trim().to_owned())
}

fn main() {
    let manifest_dir = std::env::var("CARGO_MANIFEST_DIR").unwrap_or_default();
    // Only this package's own checkout: a tarball unpacked inside another repository must not
    // take that repository's commit.
    let own = git(&["rev-parse", "--show-toplevel"]).is_some_and(|top| {
        Path::new(&top).canonicalize().ok() == Path::new(&manifest_dir).canonicalize().ok()
    });
    let commit = own.then(|| git(&["rev-parse", "HEAD"])).flatten();
    let commit = match commit {
        Some(hash) => {
            // --no-optional-locks: a plain `git status` refreshes and rewrites .git/index, and a
            // build that rewrote a file it watched made the next cargo command rebuild prisma
            // (the first `cargo run` after `cargo test` recompiled it, issue 38).
            let dirty = git(&["--no-optional-locks", "status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty());
            if dirty {
                format!("{hash}-dirty")
            } else {
                hash
            }
        }
        None => "unknown".to_owned(),
    };
    println!("cargo:rustc-env=PRISMA_COMMIT={commit}");
    // Run again when HEAD moves or the sources change (for the -dirty mark). Not on
    // .git/index: every `git status`, `git add` and editor plugin touches it, and each touch
    // rebuilt prisma with the same commit.
    if let Some(file) = own.then(|| git(&["rev-parse", "--git-path", "HEAD"])).flatten() {
        println!("cargo:rerun-if-changed={file}");
    }
    if let Some(reference) = own.then(|| git(&["symbolic-ref", "-q", "HEAD"])).flatten() {
        if let Some(file) = git(&["rev-parse", "--git-path", &reference]) {
            println!("cargo:rerun-if-changed={file}");
        }
    }
    for path in ["build.rs", "src", "Cargo.toml", "scenes"] {
        println!("cargo:rerun-if-changed={path}");
    }
}
