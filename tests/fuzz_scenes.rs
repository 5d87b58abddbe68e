//! Scene-file fuzzing (see `tests/fuzz/mod.rs` for the method and the invariants).
//!
//! The short run is part of `cargo test --release` (a few hundred mutants, seconds). The long
//! run is one command:
//!
//! ```sh
//! PRISMA_FUZZ_MUTANTS=100000 PRISMA_FUZZ_SEED=1 cargo test --release --test fuzz_scenes -- --ignored --nocapture
//! ```
//!
//! Each finding's scene file is kept under `target/tmp/fuzz-scenes/findings/` (the short run's
//! under `target/tmp/fuzz-scenes-short/`) and listed in the report with its mutations.

mod fuzz;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn config(seed: u64, count: u64, name: &str) -> fuzz::Config {
    fuzz::Config {
        binary: PathBuf::from(env!("CARGO_BIN_EXE_prisma")),
        seed,
        count,
        // A mutant renders 16×12 pixels at 1 spp in milliseconds; anything near this bound is
        // a hang, even on a loaded CI machine.
        time_bound: Duration::from_secs(30),
        workers: 2,
        work_dir: Path::new(env!("CARGO_TARGET_TMPDIR")).join(name),
    }
}

fn run_and_check(config: &fuzz::Config) {
    let start = Instant::now();
    let summary = fuzz::run(config, Path::new(env!("CARGO_MANIFEST_DIR")));
    let report = fuzz::report(config, &summary, start.elapsed());
    println!("{report}");
    assert_eq!(summary.mutants, config.count);
    assert!(summary.findings.is_empty(), "{report}");
    // The mutants must exercise both sides: some render, most are refused.
    assert!(summary.rendered > 0 && summary.refused > 0, "{report}");
}

/// The short run inside CI: fixed seed, 400 mutants (about 10 s on 2 cores).
#[test]
fn fuzzed_scenes_render_or_are_refused_cleanly() {
    run_and_check(&config(16, 400, "fuzz-scenes-short"));
}

/// The long run: `PRISMA_FUZZ_MUTANTS` mutants (default 100 000) from `PRISMA_FUZZ_SEED`
/// (default 1).
#[test]
#[ignore = "long: run with --ignored (see the module doc)"]
fn fuzz_long_run() {
    let number =
        |name: &str, default: u64| std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default);
    run_and_check(&config(
        number("PRISMA_FUZZ_SEED", 1),
        number("PRISMA_FUZZ_MUTANTS", 100_000),
        "fuzz-scenes",
    ));
}
