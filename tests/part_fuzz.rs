//! Part-file fuzzing: altered parts never become an image they are not, and never crash,
//! hang or exhaust memory. Beside the scene fuzzer (`tests/fuzz_scenes.rs`).
//!
//! Three pairs of parts (a plain render split by samples, a caustic one, a polarised one with
//! spectral bands and a crop) are rendered once; each mutant alters one part of a pair and is
//! read (`read_part_header`, `read_part`) and merged with the other (`merge_files`, complete),
//! in process; one mutant in [`Config::cli_every`] also goes through the binary (`merge
//! --complete` under a 2 GB address-space limit, `info`). Mutations: bit flips (mostly in the
//! header and offset table), truncations, attribute edits (crafted values: huge, negative, NaN,
//! control characters, malformed ranges and JSON), attribute sizes, windows and chunk counts,
//! and the same edits with the header digest recomputed ("forged", as by someone editing on
//! purpose).
//!
//! Invariants: no panic; a merge that succeeds from an unforged mutant gives exactly the
//! reference's sums, samples, window and settings (a forged one may be another valid part,
//! which the digest cannot tell: `docs/farm.md`); the binary exits 0 or 2, with one line and
//! no output file on 2; the fuzzing process's peak resident memory stays under 1 GB.
//!
//! The short run is part of `cargo test --release`; the long run is one command:
//!
//! ```sh
//! PRISMA_FUZZ_MUTANTS=100000 PRISMA_FUZZ_SEED=1 cargo test --release --test part_fuzz -- --ignored --nocapture
//! ```

mod parts;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use parts::ExrFile;
use prisma::part::file::read_part_header;
use prisma::part::{merge_files, read_part, Part};
use rand_core::{RngCore, SeedableRng};
use rand_pcg::Pcg64;

/// One run's settings.
struct Config {
    seed: u64,
    mutants: u64,
    cli_every: u64,
    name: &'static str,
}

/// A pair of parts that merge into the whole render, and that render's reference merge.
struct Pair {
    files: [PathBuf; 2],
    bytes: [Vec<u8>; 2],
    reference: Part,
}

/// What one run saw.
#[derive(Default, Debug)]
struct Tally {
    accepted: u64,
    accepted_forged: u64,
    refused: u64,
    cli_runs: u64,
    findings: Vec<String>,
}

fn render(dir: &Path, args: &[&str], out: &str) -> PathBuf {
    let output = Command::new(env!("CARGO_BIN_EXE_prisma"))
        .args(args)
        .args(["-q", "-o", out])
        .current_dir(dir)
        .output()
        .expect("prisma runs");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    dir.join(out)
}

fn pairs(dir: &Path) -> Vec<Pair> {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let scene = |name: &str| scenes.join(name).to_str().expect("utf-8").to_owned();
    let plain = scene("tp6_mirror_glass.toml");
    let caustic = scene("tp6_mirror_glass_caustics.toml");
    let size = ["--width", "16", "--height", "12"];
    let specs: [(Vec<&str>, [&str; 2]); 3] = [
        (
            [&["render", plain.as_str()][..], &size, &["--spp", "4"]].concat(),
            ["--samples=0..2", "--samples=2..4"],
        ),
        (
            [&["render", caustic.as_str()][..], &size, &["--spp", "2"]].concat(),
            ["--samples=0..1", "--samples=1..2"],
        ),
        (
            [&["render", plain.as_str()][..], &size, &["--spp", "2", "--spectral-bands", "4", "--part"]]
                .concat(),
            ["--crop=0,0,16,5", "--crop=0,5,16,12"],
        ),
    ];
    specs
        .iter()
        .enumerate()
        .map(|(k, (args, halves))| {
            let files = [0, 1].map(|h| {
                let mut all = args.clone();
                all.push(halves[h]);
                render(dir, &all, &format!("pair{k}_{h}.exr"))
            });
            let reference = merge_files(&files, true).expect("the pair merges");
            let bytes = [0, 1].map(|h| std::fs::read(&files[h]).expect("part"));
            Pair { files, bytes, reference }
        })
        .collect()
}

/// Crafted values for attribute edits.
const VALUES: [&str; 22] = [
    "",
    "0",
    "1",
    "-1",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "1099511627777",
    "nan",
    "inf",
    "1e309",
    "0..0",
    "0..4294967295",
    "3..1",
    "0..1,0..1",
    "0,0,0,0",
    "0,0,100000,100000",
    "{}",
    "{\"max_depth\":1e99}",
    "\u{1b}]52;c;cHduZWQ=\u{7}",
    "null",
    "0..2,2..4",
];

/// Names of the attributes worth editing.
const ATTRIBUTES: [&str; 16] = [
    "prisma.samples",
    "prisma.spp",
    "prisma.crop",
    "prisma.settings",
    "prisma.lightPathsPerPass",
    "prisma.seed",
    "prisma.sceneSha256",
    "prisma.version",
    "prisma.commit",
    "prisma.scene",
    "prisma.wallSeconds",
    "prisma.threads",
    "prisma.parts",
    "prisma.sumsFormat",
    "prisma.sumsBlake3",
    "prisma.headerBlake3",
];

/// A mutant of `bytes`, and whether its header digest was recomputed.
fn mutate(bytes: &[u8], rng: &mut Pcg64) -> (Vec<u8>, bool, String) {
    let below = |rng: &mut Pcg64, n: usize| (rng.next_u64() % n.max(1) as u64) as usize;
    let file = ExrFile::parse(bytes);
    let header = file.header_length();
    let table = header + 8 * file.chunks;
    match below(rng, 8) {
        0 | 1 => {
            // Bit flips: 1 to 3, three in four in the header and offset table.
            let mut out = bytes.to_vec();
            let flips = 1 + below(rng, 3);
            let mut at = Vec::new();
            for _ in 0..flips {
                let limit = if below(rng, 4) < 3 { table } else { out.len() };
                let position = below(rng, limit);
                out[position] ^= 1 << below(rng, 8);
                at.push(position);
            }
            (out, false, format!("flip bytes {at:?}"))
        }
        2 => {
            let limit = if below(rng, 2) == 0 { table } else { bytes.len() };
            let length = below(rng, limit);
            (bytes[..length].to_vec(), false, format!("truncate to {length}"))
        }
        3 | 4 => {
            // Attribute edits, forged or not.
            let mut edited = file.clone();
            let name = ATTRIBUTES[below(rng, ATTRIBUTES.len())];
            let value = match below(rng, 4) {
                0 => "x".repeat(1 << below(rng, 21)),
                _ => VALUES[below(rng, VALUES.len())].to_owned(),
            };
            edited.set_text(name, &value);
            let forged = below(rng, 2) == 0;
            if forged {
                edited.forge_digest();
            }
            let shown: String = value.chars().take(40).collect();
            (edited.to_bytes(header), forged, format!("{name} = {shown:?} (forged {forged})"))
        }
        5 => {
            // Windows: a large or shifted data and display window, crop to match, forged.
            let mut edited = file.clone();
            let side = [1, 17, 4096, 32_768, 32_769, 100_000, i32::MAX][below(rng, 7)];
            let (x0, y0) = ([0, 1, -5][below(rng, 3)], [0, 3][below(rng, 2)]);
            edited.set_window("dataWindow", (x0, y0, x0 + side - 1, y0 + side - 1));
            if below(rng, 2) == 0 {
                edited.set_window("displayWindow", (0, 0, side - 1, side - 1));
            }
            edited.set_text("prisma.crop", &format!("{x0},{y0},{},{}", x0 + side, y0 + side));
            edited.forge_digest();
            (edited.to_bytes(header), true, format!("window side {side} at {x0},{y0}"))
        }
        6 => {
            // An attribute's size field.
            let mut out = bytes.to_vec();
            let index = below(rng, file.attributes.len());
            let mut position = 8;
            for (name, kind, value) in &file.attributes[..index] {
                position += name.len() + kind.len() + 6 + value.len();
            }
            let (name, kind, _) = &file.attributes[index];
            position += name.len() + kind.len() + 2;
            let size = [0i32, -1, 1 << 30, i32::MAX, 7][below(rng, 5)];
            out[position..position + 4].copy_from_slice(&size.to_le_bytes());
            (out, false, format!("size of {name} = {size}"))
        }
        _ => {
            // A chunk offset, or a run of bytes in the body moved.
            let mut out = bytes.to_vec();
            if below(rng, 2) == 0 && file.chunks > 0 {
                let entry = header + 8 * below(rng, file.chunks);
                let value = [0u64, u64::MAX, 1 << 40, bytes.len() as u64][below(rng, 4)];
                out[entry..entry + 8].copy_from_slice(&value.to_le_bytes());
                (out, false, format!("offset at {entry} = {value}"))
            } else {
                let from = table + below(rng, bytes.len() - table);
                let length = below(rng, 64).min(bytes.len() - from);
                let to = table + below(rng, bytes.len() - table - length);
                let piece = out[from..from + length].to_vec();
                out[to..to + length].copy_from_slice(&piece);
                (out, false, format!("copy {length} bytes {from} → {to}"))
            }
        }
    }
}

/// Whether `merged` is the reference render: same sums, samples, window, size and settings.
fn same_render(merged: &Part, reference: &Part) -> bool {
    let (a, b) = (&merged.header, &reference.header);
    merged.sums == reference.sums
        && a.samples == b.samples
        && a.spp == b.spp
        && a.window == b.window
        && a.display == b.display
        && a.settings == b.settings
        && a.light_paths_per_pass == b.light_paths_per_pass
}

/// The binary on the mutant: `merge --complete` under a 2 GB address-space limit, and `info`.
fn check_cli(
    dir: &Path,
    mutant: &Path,
    other: &Path,
    forged: bool,
    reference: &Part,
    what: &str,
) -> Option<String> {
    let out = dir.join("cli_out.exr");
    let _ = std::fs::remove_file(&out);
    let binary = env!("CARGO_BIN_EXE_prisma");
    let merge = format!(
        "ulimit -v 2000000; exec timeout 60 '{binary}' merge '{}' '{}' --complete --keep-sums -q -o '{}'",
        mutant.display(),
        other.display(),
        out.display()
    );
    let info = format!("ulimit -v 2000000; exec timeout 60 '{binary}' info '{}'", mutant.display());
    for (command, writes) in [(merge, true), (info, false)] {
        let output = Command::new("sh").arg("-c").arg(&command).output().expect("sh runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        match output.status.code() {
            Some(0) if writes && !forged => match read_part(&out) {
                Ok(part) if same_render(&part, reference) => {}
                _ => return Some(format!("{what}: merge exit 0 with a different image")),
            },
            Some(0) => {}
            Some(2) => {
                if stderr.lines().count() != 1 || stderr.trim_end().chars().any(char::is_control) {
                    return Some(format!("{what}: not one clean line: {stderr:?}"));
                }
                if writes && out.exists() {
                    return Some(format!("{what}: exit 2 but an output was written"));
                }
            }
            code => return Some(format!("{what}: exit {code:?}: {stderr}")),
        }
    }
    None
}

fn run(config: &Config) -> Tally {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(config.name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("work dir");
    let pairs = pairs(&dir);
    let mut rng = Pcg64::seed_from_u64(config.seed);
    let mut tally = Tally::default();
    let mutant_path = dir.join("mutant.exr");
    let start = Instant::now();
    for index in 0..config.mutants {
        let pair = &pairs[(index % pairs.len() as u64) as usize];
        let half = (index / pairs.len() as u64 % 2) as usize;
        let (bytes, forged, what) = mutate(&pair.bytes[half], &mut rng);
        let what = format!("mutant {index} (pair {}, half {half}): {what}", index % pairs.len() as u64);
        std::fs::write(&mutant_path, &bytes).expect("write mutant");
        let mut files = pair.files.clone();
        files[half] = mutant_path.clone();
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let _ = read_part_header(&mutant_path);
            let _ = read_part(&mutant_path);
            merge_files(&files, true)
        }));
        match outcome {
            Err(_) => tally.findings.push(format!("{what}: panicked")),
            Ok(Ok(merged)) if forged => {
                tally.accepted_forged += 1;
                drop(merged);
            }
            Ok(Ok(merged)) => {
                tally.accepted += 1;
                if !same_render(&merged, &pair.reference) {
                    tally.findings.push(format!("{what}: accepted, and the image differs"));
                }
            }
            Ok(Err(_)) => tally.refused += 1,
        }
        if index % config.cli_every == 0 {
            tally.cli_runs += 1;
            let other = &pair.files[1 - half];
            if let Some(finding) = check_cli(&dir, &mutant_path, other, forged, &pair.reference, &what) {
                tally.findings.push(finding);
            }
        }
        if index > 0 && index % 10_000 == 0 {
            eprintln!(
                "part fuzz: {index} of {} mutants, {:.0} s, {tally:?}",
                config.mutants,
                start.elapsed().as_secs_f64()
            );
        }
    }
    let peak = peak_resident_kilobytes();
    println!(
        "part fuzz: {} mutants (seed {}) in {:.1} s: {} refused, {} accepted (same image), {} forged accepted, \
         {} through the binary, {} findings, peak resident memory {} MB",
        config.mutants,
        config.seed,
        start.elapsed().as_secs_f64(),
        tally.refused,
        tally.accepted,
        tally.accepted_forged,
        tally.cli_runs,
        tally.findings.len(),
        peak / 1024
    );
    assert!(peak < 1 << 20, "peak resident memory {peak} kB");
    tally
}

/// The fuzzing process's peak resident memory (VmHWM), in kB.
fn peak_resident_kilobytes() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|line| line.strip_prefix("VmHWM:"))
        .and_then(|value| value.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap_or(0)
}

fn check(tally: &Tally) {
    assert!(tally.findings.is_empty(), "{} findings:\n{}", tally.findings.len(), tally.findings.join("\n"));
    // Both sides exercised: most mutants refused, and some (flips in image channels, forged
    // edits of the wall time) accepted.
    assert!(tally.refused > 0 && tally.accepted + tally.accepted_forged > 0, "{tally:?}");
}

/// The short run inside CI: 1,500 mutants, 75 of them through the binary.
#[test]
fn altered_parts_are_refused_or_merge_into_the_same_image() {
    check(&run(&Config { seed: 37, mutants: 1_500, cli_every: 20, name: "part-fuzz-short" }));
}

/// The long run: `PRISMA_FUZZ_MUTANTS` mutants (default 100,000) from `PRISMA_FUZZ_SEED`
/// (default 1), one in 200 through the binary.
#[test]
#[ignore = "long: run with --ignored (see the module doc)"]
fn part_fuzz_long_run() {
    let number =
        |name: &str, default: u64| std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default);
    check(&run(&Config {
        seed: number("PRISMA_FUZZ_SEED", 1),
        mutants: number("PRISMA_FUZZ_MUTANTS", 100_000),
        cli_every: 200,
        name: "part-fuzz",
    }));
}
