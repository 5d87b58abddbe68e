//! Lens files read from disk (`prisma::lens::read_lens_file`): the numbers exactly as written, the
//! same lens in both formats giving the same `LensSystem`, one-line errors naming the file and
//! line, and no panic on mangled input.

use std::path::{Path, PathBuf};

use prisma::lens::file::decode_text;
use prisma::lens::pbrt::parse_pbrt;
use prisma::lens::zmx::parse_zmx;
use prisma::lens::{read_lens_file, LensError, LensSystem, Medium, Surface};
use rand_core::{RngCore, SeedableRng};
use rand_pcg::Pcg64;

fn lens_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/lenses").join(name)
}

fn read(name: &str) -> LensSystem {
    read_lens_file(&lens_path(name)).unwrap_or_else(|err| panic!("{name}: {err}"))
}

/// The surfaces without what depends on the file (lines, how a glass is named).
fn optics_only(system: &LensSystem) -> Vec<Surface> {
    system
        .surfaces
        .iter()
        .map(|surface| {
            let medium = match &surface.medium {
                Medium::Air => Medium::Air,
                Medium::Glass { formula, .. } => {
                    Medium::Glass { name: String::new(), formula: formula.clone() }
                }
            };
            Surface { line: 0, medium, ..surface.clone() }
        })
        .collect()
}

#[test]
fn the_pbrt_singlet_reads_as_written() {
    let system = read("singlet.dat");
    let [stop, front, back] = system.surfaces.as_slice() else { panic!("three surfaces") };
    assert!(stop.is_stop);
    assert_eq!((stop.radius_mm, stop.thickness_mm, stop.semi_diameter_mm, stop.line), (0.0, 3.0, 8.0, 3));
    assert_eq!(stop.medium, Medium::Air);
    assert_eq!(
        (front.radius_mm, front.thickness_mm, front.semi_diameter_mm, front.line),
        (60.0, 4.0, 12.5, 4)
    );
    assert_eq!(front.medium.name(), "N-BK7");
    assert_eq!((back.radius_mm, back.thickness_mm, back.semi_diameter_mm, back.line), (-60.0, 56.0, 12.5, 5));
    assert_eq!(back.medium, Medium::Air);
    assert_eq!(system.source, lens_path("singlet.dat"));
}

#[test]
fn the_zemax_singlet_is_the_pbrt_singlet() {
    let dat = read("singlet.dat");
    let zmx = read("singlet.zmx");
    // CURV 0.0166666666666666666667 parses to the f64 nearest 1/60, whose inverse is 60 exactly.
    assert_eq!(optics_only(&zmx), optics_only(&dat));
    assert_eq!(zmx.surfaces.iter().map(|s| s.line).collect::<Vec<_>>(), [17, 25, 33]);
    // OpticStudio's own encoding, UTF-16LE with a byte-order mark and CRLF, reads the same.
    let utf16 = read("singlet_utf16le.zmx");
    assert_eq!(utf16.surfaces, zmx.surfaces);
}

#[test]
fn glasses_given_by_formula_are_dispersive() {
    let system = read("doublet.dat");
    let crown = &system.surfaces[1].medium;
    let flint = &system.surfaces[2].medium;
    // SCHOTT's N-BK7 data sheet: n_F = 1.52238, n_d = 1.51680, n_C = 1.51432 (5 decimals).
    for (lambda_nm, n) in [(486.1327, 1.52238), (587.5618, 1.51680), (656.2725, 1.51432)] {
        assert!((crown.n_at_nm(lambda_nm) - n).abs() < 1e-5, "{lambda_nm} nm");
    }
    // The abbe model passes through n_d and has exactly the given V_d (f64 rounding only).
    assert!((flint.n_at_nm(587.5618) - 1.62004).abs() < 1e-14);
    let v_d = (1.62004 - 1.0) / (flint.n_at_nm(486.1327) - flint.n_at_nm(656.2725));
    assert!((v_d - 36.37).abs() < 1e-9, "{v_d}");
    assert_eq!(flint.name(), "abbe:1.62004,36.37");
}

#[test]
fn pbrt_files_without_glasses_have_one_index_per_element() {
    let system = read("eta_only.dat");
    assert_eq!(system.surfaces[0].medium, Medium::constant(1.5));
    assert_eq!(system.surfaces[1].medium, Medium::Air);
    assert_eq!(system.surfaces[2].medium, Medium::Air);
    // The last thickness 0 becomes the paraxial focus for infinity: for an equiconvex thick lens
    // in air (Hecht, Optics, §6.2) 1/f = (n − 1)[2/R − (n − 1)d/(n R²)] and the back focal
    // distance is f (1 − (n − 1)d/(n R)) from the lens's last vertex; the stop 2 mm behind it
    // is the last surface here, so the image is 2 mm less behind that.
    let (n, r, d) = (1.5_f64, 50.0_f64, 5.0_f64);
    let f = 1.0 / ((n - 1.0) * (2.0 / r - (n - 1.0) * d / (n * r * r)));
    let back_focal_distance = f * (1.0 - (n - 1.0) * d / (n * r));
    let image = system.surfaces[2].thickness_mm;
    assert!((image - (back_focal_distance - 2.0)).abs() < 1e-12 * f, "{image}");
}

#[test]
fn bad_files_are_one_line_errors_naming_the_file_and_line() {
    let error = |name: &str| read_lens_file(&lens_path(name)).expect_err(name);
    let wrong_glass = error("wrong_glass.dat");
    assert_eq!(
        wrong_glass.to_string(),
        format!(
            "{}:3: column 5 (glass): N-BK7 has n_d = 1.51680 but column 3 (eta) is 1.67; they must agree \
             within 0.01 (a wrong glass?)",
            lens_path("wrong_glass.dat").display()
        )
    );
    let coordinate_break = error("coordbrk.zmx");
    assert_eq!(
        coordinate_break.to_string(),
        format!(
            "{}:5: TYPE COORDBRK: not supported (prisma reads TYPE STANDARD and TYPE EVENASPH)",
            lens_path("coordbrk.zmx").display()
        )
    );
    let crossing = error("crossing.zmx");
    assert!(matches!(crossing, LensError::System { .. }));
    // R = 20 mm at the 9 mm clear semi-diameter: each sag is 20 − √(20² − 9²) = 2.139429 mm, so
    // the 1 mm thick lens's faces cross by 2 × 2.139429 − 1 = 3.278858 mm at the rim.
    assert_eq!(
        crossing.to_string(),
        format!(
            "{}: surface 2 (line 9) and surface 3 (line 14) cross: at 9 mm from the axis the first lies \
             3.278858 mm behind the second (thickness too small for the sags)",
            lens_path("crossing.zmx").display()
        )
    );
    for error in [wrong_glass, coordinate_break, crossing] {
        assert!(!error.to_string().contains('\n'), "{error}");
    }
}

/// The shipped prescriptions of `data/lenses/` (written on their own branch): every file reads,
/// and the `.dat` and `.zmx` of the same lens give the same surfaces.
#[test]
fn shipped_lenses_read_and_agree_across_formats() {
    let directory = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/lenses");
    let Ok(entries) = std::fs::read_dir(&directory) else {
        eprintln!("{} does not exist yet: nothing to check", directory.display());
        return;
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|entry| entry.ok().map(|entry| entry.path())).collect();
    paths.sort();
    let mut pairs = 0;
    for path in &paths {
        let extension = path.extension().and_then(|ext| ext.to_str());
        if !matches!(extension, Some("dat") | Some("zmx")) {
            continue;
        }
        let system = read_lens_file(path).unwrap_or_else(|err| panic!("{err}"));
        if extension != Some("dat") {
            continue;
        }
        let zemax_path = path.with_extension("zmx");
        if !zemax_path.exists() {
            continue;
        }
        let zemax = read_lens_file(&zemax_path).unwrap_or_else(|err| panic!("{err}"));
        let (dat, zmx) = (optics_only(&system), optics_only(&zemax));
        assert_eq!(dat.len(), zmx.len(), "{}", path.display());
        for (a, b) in dat.iter().zip(&zmx) {
            // The .zmx gives CURV = 1/R in full double precision: 1/CURV comes back within an ulp
            // or two of the .dat radius.
            let radius_close = (a.radius_mm - b.radius_mm).abs() <= 4.0 * f64::EPSILON * a.radius_mm.abs();
            assert!(radius_close, "{}: radius {} vs {}", path.display(), a.radius_mm, b.radius_mm);
            assert_eq!(Surface { radius_mm: a.radius_mm, ..b.clone() }, *a, "{}", path.display());
        }
        pairs += 1;
    }
    assert!(pairs >= 1, "no .dat/.zmx pair in {}", directory.display());
}

/// The shipped `.dat` files whose header says their last thickness is the paraxial focus at the
/// d line were computed by `validation/lens/make_lenses.py` (Python, checked against rayoptics):
/// with that thickness set to 0, the reader's own y–nu trace must put the image at the same
/// place. Both are f64 traces through ~11 surfaces with the same Sellmeier formulas, so they
/// agree to rounding (measured: 0 for the singlet and the achromat, 2e-16 relative for the
/// double Gauss); 1e-9 leaves room for the printed digits.
#[test]
fn shipped_image_distances_are_the_paraxial_focus() {
    let directory = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/lenses");
    let Ok(entries) = std::fs::read_dir(&directory) else {
        eprintln!("{} does not exist yet: nothing to check", directory.display());
        return;
    };
    let mut checked = 0;
    for path in entries.filter_map(|entry| entry.ok().map(|entry| entry.path())) {
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        if path.extension().and_then(|ext| ext.to_str()) != Some("dat")
            || !text.contains("the paraxial focus at the d line")
        {
            continue;
        }
        let shipped = read_lens_file(&path).unwrap_or_else(|err| panic!("{err}"));
        let last = shipped.surfaces.last().expect("surfaces");
        // The same file with its last thickness replaced by 0.
        let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
        let mut fields: Vec<String> = lines[last.line - 1].split_whitespace().map(str::to_owned).collect();
        fields[1] = "0".to_owned();
        lines[last.line - 1] = fields.join(" ");
        let refocused = parse_pbrt(&lines.join("\n"), &path).unwrap_or_else(|err| panic!("{err}"));
        let image = refocused.surfaces.last().expect("surfaces").thickness_mm;
        assert!(
            (image - last.thickness_mm).abs() <= 1e-9 * last.thickness_mm,
            "{}: {image} vs shipped {}",
            path.display(),
            last.thickness_mm
        );
        checked += 1;
    }
    assert!(checked >= 1, "no .dat in {} states its image distance", directory.display());
}

/// Mangled versions of valid files must give Ok or an error, never a panic.
#[test]
fn mangled_files_never_panic() {
    let sources: Vec<(&str, Vec<u8>)> = ["singlet.dat", "doublet.dat", "singlet.zmx", "eta_only.dat"]
        .iter()
        .map(|name| (*name, std::fs::read(lens_path(name)).expect("test file")))
        .collect();
    let parse = |name: &str, bytes: &[u8]| -> Result<LensSystem, LensError> {
        let path = Path::new(name);
        let text =
            decode_text(bytes).map_err(|message| LensError::System { file: name.to_owned(), message })?;
        if name.ends_with(".zmx") {
            parse_zmx(&text, path)
        } else {
            parse_pbrt(&text, path)
        }
    };
    const GARBAGE: [&str; 16] = [
        "",
        "x",
        "-",
        "NaN",
        "inf",
        "-inf",
        "1e308",
        "-1e308",
        "1e-308",
        "0",
        "-0",
        "1e400",
        "INFINITY",
        "sellmeier:",
        "abbe:1,0",
        "MIRROR",
    ];
    let mut cases = 0usize;
    for (name, bytes) in &sources {
        // Every truncation.
        for end in 0..=bytes.len() {
            let _ = parse(name, &bytes[..end]);
            cases += 1;
        }
        // Every whitespace-separated token replaced by each garbage token.
        let text = String::from_utf8(bytes.clone()).expect("UTF-8 test file");
        let tokens: Vec<(usize, usize)> = token_spans(&text);
        for &(start, end) in &tokens {
            for garbage in GARBAGE {
                let mangled = format!("{}{}{}", &text[..start], garbage, &text[end..]);
                let _ = parse(name, mangled.as_bytes());
                cases += 1;
            }
        }
        // Random byte edits (seeded): overwrites with any byte, including invalid UTF-8.
        let mut rng = Pcg64::seed_from_u64(40);
        for _ in 0..2000 {
            let mut mangled = bytes.clone();
            for _ in 0..1 + rng.next_u32() % 4 {
                let at = rng.next_u32() as usize % mangled.len();
                mangled[at] = rng.next_u32() as u8;
            }
            let _ = parse(name, &mangled);
            cases += 1;
        }
    }
    assert!(cases > 10_000, "{cases}");
}

/// Byte ranges of the whitespace-separated tokens of `text`.
fn token_spans(text: &str) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = None;
    for (at, c) in text.char_indices() {
        match (c.is_whitespace(), start) {
            (true, Some(from)) => {
                spans.push((from, at));
                start = None;
            }
            (false, None) => start = Some(at),
            _ => {}
        }
    }
    if let Some(from) = start {
        spans.push((from, text.len()));
    }
    spans
}
