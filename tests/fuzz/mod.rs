//! A mutation fuzzer for scene files, run against the real binary.
//!
//! Why mutation of the shipped scenes, and why the binary:
//! - The inputs that find bugs are near-valid scenes with one extreme value (a radius of 1e20,
//!   an apex angle of 1e-44°, an emission whose `scale` overflows), not random text. Mutating
//!   the shipped scenes (`scenes/`, `validation/scenes/`) keeps them valid almost everywhere,
//!   which a grammar-driven `proptest` generator would have to re-encode for every table, and a
//!   byte-level `cargo fuzz` target would reach only slowly (it also needs a nightly
//!   toolchain, which CI does not have). Shrinking, proptest's strength, matters little: every
//!   finding here was one changed value, and each mutant is reproducible from (seed, index).
//! - The invariants are about the process: exit codes, one-line messages, no output file on
//!   failure, no hang. Running `prisma render` as a child process checks exactly those and
//!   contains hangs (the child is killed) and panics (exit 101).
//!
//! Invariants for every mutant, rendered at 16×12, 1 spp, at most 4096 light paths, one thread
//! (the scene's own `light_paths` is still parsed and checked, then overridden: a caustic scene's
//! light paths do not scale with the resolution, and 960 000 of them took longer than the bound
//! on a loaded machine): it finishes within
//! [`Config::time_bound`]; it exits 0 with an EXR and a PNG whose pixels are all finite, or
//! exits 2 with exactly one `error:` line (warnings aside) and no output file; nothing else
//! (exit 1, 101, a signal) and no stray file beside the scene.
//!
//! The mutators are those of `../shared/cases/reliability/fuzz_scenes.py`, in Rust: numbers
//! swapped for extreme ones, extreme geometry, camera, spectra, IORs, render settings, meshes
//! (broken, huge, degenerate OBJ files), wrong types, duplicated or deleted lines, truncation,
//! random bytes, deep nesting, Unicode and very long keys and strings.

#![allow(dead_code)] // shared by the short and the long run; each uses part of it

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use rand_core::{RngCore, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// Numbers that broke or nearly broke parsers and renderers: limits of f32, u32, u64, zero
/// signs, NaN, infinities, and TOML forms (hex, underscores) and non-numbers.
const NUMS: &[&str] = &[
    "0",
    "-0.0",
    "-1",
    "1e-45",
    "1e-38",
    "1e-30",
    "1e-20",
    "1e-7",
    "0.5",
    "2",
    "179.9999",
    "180",
    "360",
    "1e7",
    "1e20",
    "1e30",
    "1e36",
    "3.4e38",
    "3.5e38",
    "1e39",
    "1e308",
    "-1e30",
    "-3.4e38",
    "nan",
    "-nan",
    "inf",
    "-inf",
    "+inf",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "18446744073709551616",
    "-9223372036854775808",
    "9223372036854775807",
    "1_000",
    "0x10",
    "0o7",
    "0b1",
    "\"str\"",
    "true",
    "[]",
    "{}",
    "1979-05-27T07:32:00Z",
    "999999999999999999999999999",
    "65536",
    "65537",
    "1048576",
    "1048577",
    "4096",
    "4097",
    "32768",
    "32769",
    "8",
    "9",
];
/// The numeric part of [`NUMS`] (the first 30), for places that must stay numbers.
const NUMERIC: &[&str] = NUMS.split_at(30).0;
const UNICODE: &[&str] = &[
    "ü", "\u{202e}", "🌈", "\\u0000", "e\u{301}", "\u{feff}", "名前", "\u{200b}", "\\uD800", "ɪᴏʀ", "\u{7f}",
    "\\\\", "\"", "'",
];
const TYPES: &[&str] = &[
    "sphere",
    "plane",
    "quad",
    "mesh",
    "prism",
    "diffuse",
    "mirror",
    "dielectric",
    "point",
    "cone",
    "",
    "SPHERE",
];
const GEOMETRY_KEYS: &[&str] = &[
    "radius",
    "center",
    "point",
    "normal",
    "corner",
    "edge1",
    "edge2",
    "apex_angle_deg",
    "side_length",
    "length",
    "rotate_deg",
    "position",
];
const EXTREMES: &[&str] = &[
    "1e-30",
    "1e-20",
    "1e-38",
    "1e-45",
    "1e20",
    "1e30",
    "3e38",
    "-3e38",
    "179.99999",
    "1e-7",
    "0.0001",
    "1e10",
    "-1e10",
    "1e-10",
];
const JUNK_KEYS: &[&str] = &[
    "radius",
    "scale",
    "foo",
    "ior",
    "albedo",
    "spp",
    "width",
    "type",
    "material",
    "emit",
    "wavelengths",
    "background",
    "roughness_deg",
    "metal",
    "absorption",
    "up",
    "fov_y_deg",
];

/// Seeded random choices.
pub struct Rng(Pcg64Mcg);

impl Rng {
    /// A generator for mutant `index` of the run seeded `seed`: every mutant is reproducible alone.
    pub fn for_mutant(seed: u64, index: u64) -> Self {
        Self(Pcg64Mcg::seed_from_u64(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ index))
    }
    fn below(&mut self, n: usize) -> usize {
        (self.0.next_u64() % n.max(1) as u64) as usize
    }
    fn chance(&mut self, p: f64) -> bool {
        (self.0.next_u64() >> 11) as f64 / (1u64 << 53) as f64 <= p
    }
    fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[self.below(items.len())]
    }
    fn uniform(&mut self, low: f64, high: f64) -> f64 {
        low + (high - low) * ((self.0.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// A mutant: text (usually) or bytes, and the mutators that made it.
pub struct Mutant {
    /// The scene file's bytes.
    pub bytes: Vec<u8>,
    /// Names of the mutations applied, for reports.
    pub mutations: Vec<&'static str>,
}

/// The byte ranges of number tokens in `text` (not inside identifiers or strings).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut found = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        let previous = if i == 0 { b' ' } else { bytes[i - 1] };
        let starts = c.is_ascii_digit()
            || ((c == b'-' || c == b'+' || c == b'.') && bytes.get(i + 1).is_some_and(u8::is_ascii_digit));
        if starts
            && !(previous.is_ascii_alphanumeric() || previous == b'_' || previous == b'"' || previous == b'.')
        {
            let mut j = i + 1;
            while j < bytes.len() && (bytes[j].is_ascii_digit() || b"eE+-._".contains(&bytes[j])) {
                j += 1;
            }
            if !(j < bytes.len() && (bytes[j].is_ascii_alphabetic() || bytes[j] == b'"')) {
                found.push((i, j));
            }
            i = j;
        } else {
            i += 1;
        }
    }
    found
}

/// Lines of `text` of the form `key = value`: (start of value, end of line, key).
fn assignments(text: &str) -> Vec<(usize, usize, String)> {
    let mut found = Vec::new();
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let content = line.trim_end_matches(['\n', '\r']);
        if let Some((key, _)) = content.split_once('=') {
            let key = key.trim();
            if !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.') {
                let value_start = offset + content.find('=').unwrap_or(0) + 1;
                found.push((value_start, offset + content.len(), key.to_owned()));
            }
        }
        offset += line.len();
    }
    found
}

fn replace(text: &str, (start, end): (usize, usize), with: &str) -> String {
    format!("{}{with}{}", &text[..start], &text[end..])
}

/// Replaces the value of a random assignment whose key satisfies `wanted`.
fn replace_value(text: &str, rng: &mut Rng, wanted: impl Fn(&str) -> bool, value: &str) -> String {
    let candidates: Vec<_> = assignments(text).into_iter().filter(|(_, _, k)| wanted(k)).collect();
    if candidates.is_empty() {
        return text.to_owned();
    }
    let (start, end, _) = &candidates[rng.below(candidates.len())];
    replace(text, (*start, *end), &format!(" {value}"))
}

fn m_num(text: &str, rng: &mut Rng) -> String {
    let found = numbers(text);
    if found.is_empty() {
        return text.to_owned();
    }
    replace(text, found[rng.below(found.len())], rng.pick(NUMS))
}

fn m_nums_many(text: &str, rng: &mut Rng) -> String {
    let mut text = text.to_owned();
    for _ in 0..2 + rng.below(7) {
        text = m_num(&text, rng);
    }
    text
}

fn m_del_lines(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<&str> = text.split('\n').collect();
    for _ in 0..1 + rng.below(5) {
        if !lines.is_empty() {
            let at = rng.below(lines.len());
            lines.remove(at);
        }
    }
    lines.join("\n")
}

fn m_dup_table(text: &str, rng: &mut Rng) -> String {
    let lines: Vec<&str> = text.split('\n').collect();
    let heads: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].trim_start().starts_with('[')).collect();
    if heads.is_empty() {
        return text.to_owned();
    }
    let start = heads[rng.below(heads.len())];
    let end =
        (start + 1..lines.len()).find(|&j| lines[j].trim_start().starts_with('[')).unwrap_or(lines.len());
    let at = if rng.chance(0.5) { end } else { lines.len() };
    let mut out: Vec<&str> = lines[..at].to_vec();
    out.extend_from_slice(&lines[start..end]);
    out.extend_from_slice(&lines[at..]);
    out.join("\n")
}

fn m_truncate(text: &str, rng: &mut Rng) -> String {
    let mut end = rng.below(text.len() + 1);
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    text[..end].to_owned()
}

fn m_deep(text: &str, rng: &mut Rng) -> String {
    let depth = [10, 100, 127, 128, 129, 1000, 10000, 100000][rng.below(8)];
    let value = match rng.below(3) {
        0 => format!("{}1{}", "[".repeat(depth), "]".repeat(depth)),
        1 => format!("{}1{}", "{a=".repeat(depth), "}".repeat(depth)),
        _ => "[".repeat(depth),
    };
    replace_value(text, rng, |_| true, &value)
}

fn m_unicode(text: &str, rng: &mut Rng) -> String {
    let u = rng.pick(UNICODE).repeat(1 + rng.below(3));
    match rng.below(4) {
        0 => match text.find('"') {
            Some(at) => format!("{}\"{u}{}", &text[..at], &text[at + 1..]),
            None => text.to_owned(),
        },
        1 => format!("\u{feff}{text}"),
        2 => text.replacen("[materials.", &format!("[materials.\"{u}\""), 1),
        _ => {
            let mut at = rng.below(text.len() + 1);
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            format!("{}{u}{}", &text[..at], &text[at..])
        }
    }
}

fn m_long(text: &str, rng: &mut Rng) -> String {
    let n = [1000, 100_000, 1_000_000, 5_000_000][rng.below(4)];
    match rng.below(3) {
        0 => {
            match (text.find('"'), text.find('"').and_then(|a| text[a + 1..].find('"').map(|b| a + 1 + b))) {
                (Some(a), Some(b)) => format!("{}\"{}\"{}", &text[..a], "A".repeat(n), &text[b + 1..]),
                _ => text.to_owned(),
            }
        }
        1 => format!("{text}\n{} = 1\n", "k".repeat(n)),
        _ => format!("{text}\n# {}\n", "c".repeat(n)),
    }
}

fn m_type(text: &str, rng: &mut Rng) -> String {
    let kind = format!("\"{}\"", rng.pick(TYPES));
    replace_value(text, rng, |k| k == "type", &kind)
}

fn m_array_len(text: &str, rng: &mut Rng) -> String {
    let lines: Vec<&str> = text.split('\n').collect();
    let candidates: Vec<usize> = (0..lines.len())
        .filter(|&i| {
            lines[i].contains('[') && lines[i].contains(',') && !lines[i].trim_start().starts_with('[')
        })
        .collect();
    if candidates.is_empty() {
        return text.to_owned();
    }
    let index = candidates[rng.below(candidates.len())];
    let line = lines[index];
    let (Some(open), Some(close)) = (line.rfind('['), line.rfind(']')) else { return text.to_owned() };
    if close < open {
        return text.to_owned();
    }
    let mut items: Vec<String> = line[open + 1..close].split(',').map(|s| s.trim().to_owned()).collect();
    match rng.below(3) {
        0 => {
            items.pop();
        }
        1 => items.push(rng.pick(NUMS).to_owned()),
        _ => items.clear(),
    }
    let new_line = format!("{}[{}]{}", &line[..open], items.join(", "), &line[close + 1..]);
    let mut out = lines.clone();
    out[index] = &new_line;
    out.join("\n")
}

fn m_key_junk(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.split('\n').map(str::to_owned).collect();
    let heads: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].trim_start().starts_with('[')).collect();
    let at = if heads.is_empty() { 0 } else { heads[rng.below(heads.len())] + 1 };
    lines.insert(at.min(lines.len()), format!("{} = {}", rng.pick(JUNK_KEYS), rng.pick(NUMS)));
    lines.join("\n")
}

fn random_table(rng: &mut Rng, values: (f64, f64)) -> String {
    let count = [0, 1, 2, 3, 5, 20][rng.below(6)];
    let mut xs: Vec<f64> = (0..count).map(|_| rng.uniform(300.0, 900.0).round()).collect();
    if rng.chance(0.7) {
        xs.sort_by(f64::total_cmp);
    }
    if rng.chance(0.2) {
        if let Some(&last) = xs.last() {
            xs.push(last);
        }
    }
    let points: Vec<String> = xs
        .iter()
        .map(|x| {
            let value = if rng.chance(0.5) {
                format!("{:.4}", rng.uniform(values.0, values.1))
            } else {
                rng.pick(NUMERIC).to_owned()
            };
            format!("[{x}, {value}]")
        })
        .collect();
    format!("[{}]", points.join(", "))
}

fn random_spectrum(rng: &mut Rng) -> String {
    let scale = if rng.chance(0.4) { format!(", scale = {}", rng.pick(NUMERIC)) } else { String::new() };
    match rng.below(8) {
        0 => rng.pick(NUMERIC).to_owned(),
        1 => format!("{{ value = {}{scale} }}", rng.pick(NUMERIC)),
        2 => {
            let c = ["0", "1", "0.5", "1e-30", "0.999999", "1.000001", "-1", "1e30", "nan"];
            format!("{{ rgb = [{}, {}, {}]{scale} }}", rng.pick(&c), rng.pick(&c), rng.pick(&c))
        }
        3 => format!("{{ table = {}{scale} }}", random_table(rng, (0.0, 2.0))),
        4 => format!("{{ illuminant = \"{}\"{scale} }}", rng.pick(&["D65", "E", "A", "d65", "", "D50"])),
        5 => format!(
            "{{ blackbody_k = {}{scale} }}",
            rng.pick(&[
                "0", "1", "10", "100", "300", "1000", "6500", "1e5", "1e9", "1e30", "-5", "nan", "inf"
            ])
        ),
        6 => "{ value = 1, rgb = [1, 1, 1] }".to_owned(),
        _ => "{ }".to_owned(),
    }
}

fn m_spectrum(text: &str, rng: &mut Rng) -> String {
    let spectrum = random_spectrum(rng);
    replace_value(
        text,
        rng,
        |k| ["background", "albedo", "reflectance", "absorption", "radiance", "intensity"].contains(&k),
        &spectrum,
    )
}

fn random_ior(rng: &mut Rng) -> String {
    match rng.below(6) {
        0 => rng
            .pick(&[
                "1",
                "1.0000001",
                "0.999",
                "1e-30",
                "1e-6",
                "0.5",
                "2.4",
                "10",
                "1e6",
                "1e30",
                "3.4e38",
                "0.01",
                "100",
                "-1",
            ])
            .to_owned(),
        1 => {
            let c = ["1.5", "0", "-1", "0.01", "1", "1e10", "-0.5", "1e-30"];
            format!("{{ cauchy = [{}, {}, {}] }}", rng.pick(&c), rng.pick(&c), rng.pick(&c))
        }
        2 => {
            let b = ["1.03961212", "0.231792344", "1.01046945", "0", "-1", "1e10", "100"];
            let c =
                ["0.00600069867", "0.0200179144", "103.560653", "0.16", "0.2025", "0.36", "0.5", "0", "-1"];
            format!(
                "{{ sellmeier = {{ b = [{}, {}, {}], c_um2 = [{}, {}, {}] }} }}",
                rng.pick(&b),
                rng.pick(&b),
                rng.pick(&b),
                rng.pick(&c),
                rng.pick(&c),
                rng.pick(&c)
            )
        }
        3 => format!(
            "{{ glass = \"{}\" }}",
            rng.pick(&[
                "N-BK7",
                "N-SF11",
                "F2",
                "fused-silica",
                "water",
                "diamond",
                "PMMA",
                "n-bk7",
                "BK7",
                "",
                "ü"
            ])
        ),
        4 => format!("{{ table = {} }}", random_table(rng, (0.5, 3.0))),
        _ => "{ value = 1.5, glass = \"N-BK7\" }".to_owned(),
    }
}

fn m_ior(text: &str, rng: &mut Rng) -> String {
    let ior = random_ior(rng);
    replace_value(text, rng, |k| k == "ior", &ior)
}

fn m_render(text: &str, rng: &mut Rng) -> String {
    let settings: [(&str, &[&str]); 7] = [
        ("spp", NUMS),
        ("max_depth", &["1", "4096", "4097", "0", "16", "100", "1000", "-1"]),
        ("wavelengths", &["0", "1", "2", "3", "7", "8", "9", "16", "-1"]),
        ("seed", NUMS),
        ("area_light_samples", &["0", "1", "2", "3", "1000", "65536", "65537"]),
        ("prune_below", &["0", "0.5", "0.999999", "1", "-0.1", "nan", "1e-30", "inf"]),
        ("edge_samples", &["0", "1", "2", "4", "64", "65", "-1", "1e9"]),
    ];
    let mut body = String::new();
    for (key, values) in settings {
        if rng.chance(0.5) {
            let _ = writeln!(body, "{key} = {}", rng.pick(values));
        }
    }
    // Drop an existing [render] table (up to the next table) and append the new one.
    let mut kept = Vec::new();
    let mut skipping = false;
    for line in text.split('\n') {
        if line.trim_start().starts_with('[') {
            skipping = line.trim() == "[render]";
        }
        if !skipping {
            kept.push(line);
        }
    }
    format!("{}\n[render]\n{body}", kept.join("\n"))
}

fn m_camera(text: &str, rng: &mut Rng) -> String {
    let vector = |rng: &mut Rng| {
        let c = ["0", "1", "-1", "1e-40", "1e-20", "1e30", "3e38", "1e-45", "0.5", "1e10"];
        format!("[{}, {}, {}]", rng.pick(&c), rng.pick(&c), rng.pick(&c))
    };
    match rng.below(5) {
        0 => {
            let fov = rng.pick(&[
                "1e-30",
                "1e-7",
                "0.0001",
                "179.999",
                "179.9999999",
                "180",
                "0",
                "-40",
                "90",
                "nan",
                "1e-45",
            ]);
            replace_value(text, rng, |k| k == "fov_y_deg", fov)
        }
        1 => {
            let v = vector(rng);
            replace_value(text, rng, |k| k == "look_at", &v)
        }
        2 => {
            let v = vector(rng);
            replace_value(text, rng, |k| k == "position", &v)
        }
        3 => {
            let v = vector(rng);
            replace_value(text, rng, |k| k == "up", &v)
        }
        _ => {
            let text = replace_value(text, rng, |k| k == "look_at", "[0, 0, 1e-40]");
            replace_value(&text, rng, |k| k == "position", "[0, 0, 0]")
        }
    }
}

fn m_geometry(text: &str, rng: &mut Rng) -> String {
    let key = rng.pick(GEOMETRY_KEYS);
    let value = if ["radius", "apex_angle_deg", "side_length", "length"].contains(&key) {
        rng.pick(EXTREMES).to_owned()
    } else {
        format!("[{}, {}, {}]", rng.pick(EXTREMES), rng.pick(&["0", "1", "-1"]), rng.pick(EXTREMES))
    };
    replace_value(text, rng, |k| k == key, &value)
}

fn m_mesh(text: &str, rng: &mut Rng, assets: &Path) -> String {
    let files = [
        "good.obj",
        "cube.obj",
        "empty.obj",
        "nan.obj",
        "ovf.obj",
        "bigtri.obj",
        "tinytri.obj",
        "degen.obj",
        "badidx.obj",
        "zeroidx.obj",
        "lines.obj",
        "poly.obj",
        "badnormals.obj",
        "junk.obj",
        "rand.obj",
        "dir.obj",
        "missing.obj",
    ];
    let odd = ["", ".", "/", "/dev/null", "/etc/passwd", "../", "scene.toml", "ü🌈.obj", "/proc/self/status"];
    let file = if rng.chance(0.8) {
        assets.join(rng.pick(&files)).to_string_lossy().into_owned()
    } else if rng.chance(0.1) {
        format!("{}.obj", "a".repeat(5000))
    } else {
        rng.pick(&odd).to_owned()
    };
    let material = text
        .split('\n')
        .find_map(|l| l.strip_prefix("[materials.").and_then(|r| r.strip_suffix(']')))
        .unwrap_or("m")
        .to_owned();
    let mut shape = format!("\n[[shapes]]\ntype = \"mesh\"\nfile = {file:?}\nmaterial = \"{material}\"\n");
    if rng.chance(0.4) {
        let _ = writeln!(shape, "scale = {}", rng.pick(NUMERIC));
    }
    if rng.chance(0.4) {
        let _ = writeln!(
            shape,
            "rotate_deg = [{}, {}, {}]",
            rng.pick(NUMERIC),
            rng.pick(NUMERIC),
            rng.pick(NUMERIC)
        );
    }
    if rng.chance(0.4) {
        let _ = writeln!(
            shape,
            "position = [{}, {}, {}]",
            rng.pick(NUMERIC),
            rng.pick(NUMERIC),
            rng.pick(NUMERIC)
        );
    }
    format!("{text}{shape}")
}

/// Writes the OBJ files the mesh mutator points at into `assets` (the good, the broken and the
/// extreme), as the Python fuzzer did.
pub fn write_assets(assets: &Path, project: &Path) {
    std::fs::create_dir_all(assets.join("dir.obj")).expect("assets");
    let write = |name: &str, text: &[u8]| std::fs::write(assets.join(name), text).expect("asset");
    write("good.obj", &std::fs::read(project.join("tests/data/geometry/two_objects.obj")).expect("good.obj"));
    write("empty.obj", b"");
    write("nan.obj", b"v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write("ovf.obj", b"v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write("bigtri.obj", b"v 3e38 0 0\nv -3e38 0 0\nv 0 3e38 0\nf 1 2 3\n");
    write("tinytri.obj", b"v 0 0 0\nv 1e-30 0 0\nv 0 1e-30 0\nf 1 2 3\n");
    write("degen.obj", b"v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n");
    write("badidx.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    write("zeroidx.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    write("lines.obj", b"v 0 0 0\nv 1 0 0\nl 1 2\np 1\n");
    write("poly.obj", b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\nf 1 2 3 4 5\n");
    write("badnormals.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nvn nan 0 1\nf 1//1 2//2 3//1\n");
    write("junk.obj", b"v 0 0\nv a b c\nf x y z\n");
    let mut rng = Rng::for_mutant(0, 0);
    let random: Vec<u8> = (0..4000).map(|_| rng.0.next_u32() as u8).collect();
    write("rand.obj", &random);
    write(
        "cube.obj",
        b"v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
          f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
    );
}

/// Mutant `index` of a run seeded `seed`, from one of `bases` (the special cases first: empty,
/// comments only, a byte-order mark, CRLF line ends).
pub fn mutant(bases: &[String], seed: u64, index: u64, assets: &Path) -> Mutant {
    let mut rng = Rng::for_mutant(seed, index);
    let base = &bases[rng.below(bases.len())];
    let special = |text: String, name| Mutant { bytes: text.into_bytes(), mutations: vec![name] };
    match index {
        0 => return special(String::new(), "empty"),
        1 => return special("\n\n\n# only comments\n".into(), "comments_only"),
        2 => return special(format!("\u{feff}{base}"), "bom"),
        3 => return special(base.replace('\n', "\r\n"), "crlf"),
        _ => {}
    }
    let mut text = base.clone();
    let mut bytes: Option<Vec<u8>> = None;
    let mut mutations = Vec::new();
    for _ in 0..[1, 1, 1, 2, 2, 3][rng.below(6)] {
        // Weights as in the Python fuzzer: value mutations most often.
        let roll = rng.below(100);
        let (name, next): (&'static str, String) = match roll {
            0..=11 => ("num", m_num(&text, &mut rng)),
            12..=17 => ("nums_many", m_nums_many(&text, &mut rng)),
            18..=21 => ("del_lines", m_del_lines(&text, &mut rng)),
            22..=24 => ("dup_table", m_dup_table(&text, &mut rng)),
            25..=27 => ("truncate", m_truncate(&text, &mut rng)),
            28..=31 => {
                let mut raw = bytes.take().unwrap_or_else(|| text.clone().into_bytes());
                let count = 1 + rng.below(40);
                let at = rng.below(raw.len() + 1);
                let junk: Vec<u8> = (0..count).map(|_| rng.0.next_u32() as u8).collect();
                if rng.chance(0.5) {
                    raw.splice(at..at, junk);
                } else {
                    let end = (at + count).min(raw.len());
                    raw.splice(at..end, junk);
                }
                mutations.push("rand_bytes");
                bytes = Some(raw);
                continue;
            }
            32..=34 => ("deep", m_deep(&text, &mut rng)),
            35..=38 => ("unicode", m_unicode(&text, &mut rng)),
            39..=41 => ("long", m_long(&text, &mut rng)),
            42..=49 => ("mesh", m_mesh(&text, &mut rng, assets)),
            50..=53 => ("type", m_type(&text, &mut rng)),
            54..=57 => ("array_len", m_array_len(&text, &mut rng)),
            58..=61 => ("key_junk", m_key_junk(&text, &mut rng)),
            62..=69 => ("spectrum", m_spectrum(&text, &mut rng)),
            70..=76 => ("ior", m_ior(&text, &mut rng)),
            77..=80 => ("render", m_render(&text, &mut rng)),
            81..=85 => ("camera", m_camera(&text, &mut rng)),
            _ => ("geometry", m_geometry(&text, &mut rng)),
        };
        if bytes.is_some() {
            continue; // text mutators do not apply to random bytes
        }
        mutations.push(name);
        text = next;
    }
    Mutant { bytes: bytes.unwrap_or_else(|| text.into_bytes()), mutations }
}

/// The shipped scenes, the fuzzer's starting points.
pub fn bases(project: &Path) -> Vec<String> {
    let mut bases = Vec::new();
    for dir in ["scenes", "validation/scenes"] {
        let mut paths: Vec<PathBuf> = std::fs::read_dir(project.join(dir))
            .expect("scene directory")
            .map(|e| e.expect("entry").path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        paths.sort();
        bases.extend(paths.iter().map(|p| std::fs::read_to_string(p).expect("scene")));
    }
    bases
}

/// How a run goes.
pub struct Config {
    /// The prisma binary.
    pub binary: PathBuf,
    /// Seed of the run.
    pub seed: u64,
    /// Mutants to try.
    pub count: u64,
    /// Longest a mutant may run before it counts as a hang.
    pub time_bound: Duration,
    /// Renders at once.
    pub workers: usize,
    /// Where mutants run and findings are kept.
    pub work_dir: PathBuf,
}

/// What one mutant did, when it broke an invariant.
#[derive(Debug)]
pub struct Finding {
    /// Its index (with the seed, enough to make it again).
    pub index: u64,
    /// The mutations applied.
    pub mutations: Vec<&'static str>,
    /// Which invariant broke.
    pub problem: String,
    /// Where its scene file was kept.
    pub kept: PathBuf,
}

/// Figures of a run.
#[derive(Debug, Default)]
pub struct Summary {
    /// Mutants run.
    pub mutants: u64,
    /// Rendered (exit 0).
    pub rendered: u64,
    /// Refused (exit 2).
    pub refused: u64,
    /// Mutants that printed a warning.
    pub warned: u64,
    /// Slowest mutant.
    pub slowest: Duration,
    /// Broken invariants.
    pub findings: Vec<Finding>,
}

/// Runs `config.count` mutants and checks every invariant (see the module doc).
pub fn run(config: &Config, project: &Path) -> Summary {
    let assets = config.work_dir.join("assets");
    write_assets(&assets, project);
    let bases = bases(project);
    let next = AtomicUsize::new(0);
    let summary = Mutex::new(Summary::default());
    let start = Instant::now();
    std::thread::scope(|scope| {
        for worker in 0..config.workers {
            let (bases, assets, next, summary) = (&bases, &assets, &next, &summary);
            scope.spawn(move || {
                let dir = config.work_dir.join(format!("worker{worker}"));
                loop {
                    let index = next.fetch_add(1, Ordering::Relaxed) as u64;
                    if index >= config.count {
                        break;
                    }
                    let mutant = mutant(bases, config.seed, index, assets);
                    let outcome = check_one(config, &dir, &mutant);
                    let mut summary = summary.lock().unwrap_or_else(|p| p.into_inner());
                    summary.mutants += 1;
                    summary.slowest = summary.slowest.max(outcome.elapsed);
                    match outcome.code {
                        Some(0) => summary.rendered += 1,
                        Some(2) => summary.refused += 1,
                        _ => {}
                    }
                    summary.warned += u64::from(outcome.warned);
                    if let Some(problem) = outcome.problem {
                        let kept = config
                            .work_dir
                            .join("findings")
                            .join(format!("seed{}_{index}.toml", config.seed));
                        let _ = std::fs::create_dir_all(kept.parent().unwrap_or(Path::new(".")));
                        let _ = std::fs::write(&kept, &mutant.bytes);
                        summary.findings.push(Finding { index, mutations: mutant.mutations, problem, kept });
                    }
                    if summary.mutants % 10_000 == 0 {
                        eprintln!("{} mutants in {:.0} s", summary.mutants, start.elapsed().as_secs_f64());
                    }
                }
            });
        }
    });
    summary.into_inner().unwrap_or_else(|p| p.into_inner())
}

struct Outcome {
    code: Option<i32>,
    elapsed: Duration,
    warned: bool,
    problem: Option<String>,
}

/// Renders one mutant in a clean `dir` and checks the invariants.
fn check_one(config: &Config, dir: &Path, mutant: &Mutant) -> Outcome {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).expect("work directory");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, &mutant.bytes).expect("mutant");
    let out = dir.join("out");
    let start = Instant::now();
    let mut child = Command::new(&config.binary)
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(out.join("o.exr"))
        .args([
            "--width",
            "16",
            "--height",
            "12",
            "--spp",
            "1",
            "--light-paths",
            "4096",
            "--quiet",
            "--threads",
            "1",
        ])
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("prisma runs");
    // Read stderr on a thread so a chatty child never blocks on a full pipe.
    let mut pipe = child.stderr.take().expect("stderr");
    let reader = std::thread::spawn(move || {
        let mut text = Vec::new();
        let _ = std::io::Read::read_to_end(&mut pipe, &mut text);
        text
    });
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break Some(status);
        }
        if start.elapsed() > config.time_bound {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(1));
    };
    let elapsed = start.elapsed();
    let stderr = String::from_utf8_lossy(&reader.join().unwrap_or_default()).into_owned();
    let warned = stderr.lines().any(|l| l.starts_with("warning:"));
    let files: Vec<String> = match std::fs::read_dir(&out) {
        Ok(entries) => {
            let mut names: Vec<String> =
                entries.map(|e| e.expect("entry").file_name().to_string_lossy().into_owned()).collect();
            names.sort();
            names
        }
        Err(_) => Vec::new(),
    };
    let stray: Vec<String> = std::fs::read_dir(dir)
        .expect("work directory")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n != "scene.toml" && n != "out")
        .collect();
    let code = status.and_then(|s| s.code());
    let errors: Vec<&str> = stderr.lines().filter(|l| !l.starts_with("warning:")).collect();
    let problem = match (status, code) {
        (None, _) => Some(format!("no exit within {:?}", config.time_bound)),
        _ if stderr.contains("panicked") => Some(format!("panic: {}", first_line(&stderr))),
        _ if !stray.is_empty() => Some(format!("stray files beside the scene: {stray:?}")),
        (_, Some(0)) if files != ["o.exr", "o.png"] => Some(format!("exit 0 with outputs {files:?}")),
        (_, Some(0)) => non_finite(&out.join("o.exr")),
        (_, Some(2)) if errors.len() != 1 || !errors[0].starts_with("error: ") => {
            Some(format!("exit 2 without a one-line error: {:?}", first_line(&stderr)))
        }
        (_, Some(2)) if !files.is_empty() => Some(format!("exit 2 left outputs {files:?}")),
        (_, Some(2)) => None,
        (Some(status), _) => Some(format!("{status}: {}", first_line(&stderr))),
    };
    Outcome { code, elapsed, warned, problem }
}

fn first_line(text: &str) -> String {
    let line = text.lines().find(|l| !l.starts_with("warning:")).unwrap_or("");
    line.chars().take(300).collect()
}

/// A problem when the EXR has a non-finite sample or cannot be read.
fn non_finite(path: &Path) -> Option<String> {
    match prisma::output::exr::read_exr(path) {
        Err(error) => Some(format!("unreadable EXR: {error}")),
        Ok(image) => ["R", "G", "B", "XYZ.X", "XYZ.Y", "XYZ.Z"]
            .iter()
            .find(|c| image.channel(c).is_some_and(|v| v.iter().any(|x| !x.is_finite())))
            .map(|c| format!("non-finite samples in channel {c}")),
    }
}

/// A report of `summary` for the test output.
pub fn report(config: &Config, summary: &Summary, elapsed: Duration) -> String {
    let mut text = format!(
        "fuzz seed {}: {} mutants in {:.1} s: {} rendered, {} refused (exit 2), {} warned, slowest {:.2} s, {} findings",
        config.seed,
        summary.mutants,
        elapsed.as_secs_f64(),
        summary.rendered,
        summary.refused,
        summary.warned,
        summary.slowest.as_secs_f64(),
        summary.findings.len()
    );
    for finding in summary.findings.iter().take(20) {
        let _ = write!(
            text,
            "\n  mutant {} {:?}: {} (kept as {})",
            finding.index,
            finding.mutations,
            finding.problem,
            finding.kept.display()
        );
    }
    text
}
