//! `cargo build --release` and `cargo test --release` must build the same dependency graph, or
//! the README's first `cargo run --release` after `cargo test --release` recompiles prisma and
//! a dozen crates (issue 38: 1 min 23 s on 2 cores). They differ when a dev-dependency turns on
//! a feature of a crate prisma also uses; Cargo.toml turns those on for every build. This test
//! compares the features of every package in the two graphs (`cargo tree`, offline).

use std::collections::BTreeMap;
use std::process::Command;

/// Each package of the graph with `edges`, and its features.
fn features(edges: &str) -> Option<BTreeMap<String, String>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .args(["tree", "--offline", "--prefix", "none", "-f", "{p}|{f}", "-e", edges])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()
        .filter(|o| o.status.success())?;
    let text = String::from_utf8_lossy(&output.stdout).into_owned();
    Some(
        text.lines()
            .filter_map(|line| line.split_once('|'))
            .map(|(package, features)| {
                let name = package.split(" (").next().unwrap_or(package).trim().to_owned();
                (name, features.trim().trim_end_matches("(*)").trim().to_owned())
            })
            .collect(),
    )
}

#[test]
fn building_and_testing_resolve_the_same_features() {
    let (Some(build), Some(test)) = (features("normal,build"), features("normal,build,dev")) else {
        eprintln!("skipped: cargo tree cannot run offline here");
        return;
    };
    let differing: Vec<String> = build
        .iter()
        .filter_map(|(package, mine)| {
            let theirs = test.get(package)?;
            (theirs != mine).then(|| format!("{package}: [{mine}] when building, [{theirs}] when testing"))
        })
        .collect();
    assert!(
        differing.is_empty(),
        "turn these features on in Cargo.toml's [dependencies]:\n{}",
        differing.join("\n")
    );
}
