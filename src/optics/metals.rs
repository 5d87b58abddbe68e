//! Measured complex refractive indices n + ik of metals, tabulated in `data/metals/*.csv`:
//! silver, gold and copper from Johnson & Christy, Phys. Rev. B 6, 4370 (1972); aluminium from
//! Rakić, Appl. Opt. 34, 4755 (1995). Each file names its source in its `#` header; n and k are
//! interpolated linearly in wavelength (nm), constant beyond the table's ends (about
//! 290–1000 nm, wider than the rendered 360–830 nm, so that renders never leave the data;
//! `prisma fresnel` refuses wavelengths outside [`MetalEntry::wavelength_range_nm`]).
//!
//! Feed [`MetalEntry::eta`] (divided by the exterior index when that is not vacuum) to
//! [`crate::optics::conductor::fresnel_conductor`].
//!
//! The files are embedded in the binary and parsed once, on first use. Names are matched
//! ignoring case; the chemical symbol works too (`"silver"`, `"Ag"`).

use std::sync::{Arc, OnceLock};

use num_complex::Complex32;

use super::ior::{interpolate_table, validate_table};

/// (name, chemical symbol, file contents) of every built-in metal.
const METAL_FILES: [(&str, &str, &str); 4] = [
    ("silver", "Ag", include_str!("../../data/metals/ag.csv")),
    ("aluminium", "Al", include_str!("../../data/metals/al.csv")),
    ("gold", "Au", include_str!("../../data/metals/au.csv")),
    ("copper", "Cu", include_str!("../../data/metals/cu.csv")),
];

/// The column header every metal file carries after its comments.
const COLUMNS: &str = "wavelength_nm,n,k";

/// A metal's measured n(λ) and k(λ).
#[derive(Clone, Debug, PartialEq)]
pub struct MetalEntry {
    name: &'static str,
    symbol: &'static str,
    source: String,
    /// (λ nm, n), strictly increasing in λ.
    n: Arc<[(f32, f32)]>,
    /// (λ nm, k), on the same wavelengths.
    k: Arc<[(f32, f32)]>,
}

impl MetalEntry {
    /// The name, e.g. `"silver"`.
    pub fn name(&self) -> &'static str {
        self.name
    }
    /// The chemical symbol, e.g. `"Ag"`.
    pub fn symbol(&self) -> &'static str {
        self.symbol
    }
    /// The publication the table comes from.
    pub fn source(&self) -> &str {
        &self.source
    }
    /// The complex index n + ik against vacuum at `lambda_nm` (nm), linearly interpolated.
    pub fn eta(&self, lambda_nm: f32) -> Complex32 {
        Complex32::new(interpolate_table(&self.n, lambda_nm), interpolate_table(&self.k, lambda_nm))
    }
    /// The shortest and the longest tabulated wavelength, in nm: beyond them [`Self::eta`] holds
    /// the end values, which are not data.
    pub fn wavelength_range_nm(&self) -> (f32, f32) {
        // The table is non-empty and sorted (checked when it is parsed).
        (self.n[0].0, self.n[self.n.len() - 1].0)
    }
    /// The measured samples (λ nm, n, k).
    pub fn samples(&self) -> impl Iterator<Item = (f32, f32, f32)> + '_ {
        self.n.iter().zip(self.k.iter()).map(|(&(lambda_nm, n), &(_, k))| (lambda_nm, n, k))
    }
}

/// Every built-in metal.
///
/// # Panics
/// If an embedded `data/metals/*.csv` is malformed, which the tests of this module rule out.
pub fn metals() -> &'static [MetalEntry] {
    static METALS: OnceLock<Vec<MetalEntry>> = OnceLock::new();
    METALS.get_or_init(|| {
        METAL_FILES
            .iter()
            .map(|&(name, symbol, text)| match parse_metal(name, symbol, text) {
                Ok(metal) => metal,
                Err(message) => panic!("built-in data/metals file of {name}: {message}"),
            })
            .collect()
    })
}

/// Looks up a metal by name or chemical symbol, ignoring case.
pub fn metal(name: &str) -> Option<&'static MetalEntry> {
    metals()
        .iter()
        .find(|metal| metal.name.eq_ignore_ascii_case(name) || metal.symbol.eq_ignore_ascii_case(name))
}

/// Names of every built-in metal.
pub fn metal_names() -> Vec<&'static str> {
    metals().iter().map(MetalEntry::name).collect()
}

/// Parses `# comment` lines (one starting `# Source:`), the [`COLUMNS`] header and rows of
/// `λ nm, n, k`; n must be > 0 and k ≥ 0, λ strictly increasing.
fn parse_metal(name: &'static str, symbol: &'static str, text: &str) -> Result<MetalEntry, String> {
    let mut source = None;
    let mut header_seen = false;
    let (mut n, mut k) = (Vec::new(), Vec::new());
    for (number, line) in text.lines().enumerate().map(|(i, line)| (i + 1, line.trim())) {
        if let Some(comment) = line.strip_prefix('#') {
            if let Some(text) = comment.trim().strip_prefix("Source:") {
                source = Some(text.trim().to_owned());
            }
            continue;
        }
        if line.is_empty() {
            continue;
        }
        if !header_seen {
            if line != COLUMNS {
                return Err(format!("line {number}: expected the header \"{COLUMNS}\""));
            }
            header_seen = true;
            continue;
        }
        let values: Vec<f32> = line
            .split(',')
            .map(|field| field.trim().parse::<f32>())
            .collect::<Result<_, _>>()
            .map_err(|err| format!("line {number}: {err} in \"{line}\""))?;
        let &[lambda_nm, n_value, k_value] = values.as_slice() else {
            return Err(format!("line {number}: expected 3 values, found {}", values.len()));
        };
        if !(k_value >= 0.0 && k_value.is_finite()) {
            return Err(format!("line {number}: k = {k_value} must be finite and ≥ 0"));
        }
        n.push((lambda_nm, n_value));
        k.push((lambda_nm, k_value));
    }
    validate_table(&format!("{name} n"), &n).map_err(|err| err.to_string())?;
    let source = source.ok_or("no \"# Source:\" line")?;
    Ok(MetalEntry { name, symbol, source, n: n.into(), k: k.into() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::conductor::fresnel_conductor;

    fn normal_reflectance(name: &str, lambda_nm: f32) -> f32 {
        let metal = metal(name).unwrap_or_else(|| panic!("{name} is built in"));
        fresnel_conductor(1.0, metal.eta(lambda_nm)).reflectance
    }

    #[test]
    fn every_metal_parses_and_names_its_source() {
        assert_eq!(metal_names(), ["silver", "aluminium", "gold", "copper"]);
        for metal in metals() {
            assert!(metal.source().contains("Johnson") || metal.source().contains("Rakić"));
            let samples: Vec<_> = metal.samples().collect();
            // The tables bracket the rendered range, so nothing is extrapolated.
            assert!(samples[0].0 <= 360.0 && samples[samples.len() - 1].0 >= 830.0);
        }
    }

    #[test]
    fn johnson_christy_silver_at_548_6_nm() {
        // Johnson & Christy (1972) table, silver at 2.26 eV (548.6 nm): n = 0.06, k = 3.586.
        let eta = metal("Ag").map(|m| m.eta(548.6));
        assert_eq!(eta, Some(Complex32::new(0.06, 3.586)));
    }

    #[test]
    fn silver_is_the_best_visible_mirror() {
        // Measured normal-incidence reflectance of fresh evaporated silver: above 0.95 from
        // 450 nm to the near infrared (the reflectance curves of metal films in Hecht §4.8 and
        // in the handbooks, e.g. Bass, Handbook of Optics, "Optical properties of metals").
        for lambda_nm in [450.0, 550.0, 650.0, 800.0] {
            let r = normal_reflectance("silver", lambda_nm);
            assert!(r > 0.95, "silver at {lambda_nm} nm: {r}");
        }
    }

    #[test]
    fn aluminium_reflects_about_ninety_percent() {
        // Evaporated aluminium: ~0.92 at 550 nm, with the interband dip to ~0.87 near 830 nm
        // (Bass, Handbook of Optics, "Optical properties of metals"; Rakić 1995).
        let r_550 = normal_reflectance("aluminium", 550.0);
        assert!((0.90..0.94).contains(&r_550), "{r_550}");
        let r_830 = normal_reflectance("aluminium", 830.0);
        assert!((0.84..0.89).contains(&r_830) && r_830 < r_550, "{r_830}");
    }

    #[test]
    fn gold_and_copper_are_coloured() {
        // Gold and copper absorb blue-green (interband transitions from the d bands) and reflect
        // red: gold < 0.5 at 450 nm but > 0.9 at 700 nm, copper < 0.65 at 500 nm but > 0.9 at
        // 700 nm (Johnson & Christy 1972; Bass, Handbook of Optics).
        let gold = (normal_reflectance("gold", 450.0), normal_reflectance("gold", 700.0));
        assert!(gold.0 < 0.5 && gold.1 > 0.9, "{gold:?}");
        let copper = (normal_reflectance("copper", 500.0), normal_reflectance("copper", 700.0));
        assert!(copper.0 < 0.65 && copper.1 > 0.9, "{copper:?}");
    }

    #[test]
    fn lookups_accept_names_and_symbols() {
        assert_eq!(metal("GOLD").map(MetalEntry::symbol), Some("Au"));
        assert_eq!(metal("cu").map(MetalEntry::name), Some("copper"));
        assert_eq!(metal("unobtainium"), None);
    }

    #[test]
    fn malformed_files_are_rejected_with_line_numbers() {
        let parse = |text: &str| parse_metal("test", "Te", text);
        let header = "# Source: somewhere\nwavelength_nm,n,k\n";
        assert!(parse(&format!("{header}400,0.1,3\n500,0.2,4\n")).is_ok());
        let error = parse(&format!("{header}400,0.1\n")).expect_err("two columns");
        assert!(error.contains("line 3") && error.contains("3 values"), "{error}");
        let error = parse(&format!("{header}400,0.1,x\n")).expect_err("not a number");
        assert!(error.contains("line 3"), "{error}");
        let error = parse(&format!("{header}400,0.1,-1\n")).expect_err("negative k");
        assert!(error.contains("k = -1"), "{error}");
        let error = parse(&format!("{header}500,0.1,3\n400,0.2,4\n")).expect_err("decreasing");
        assert!(error.contains("strictly increasing"), "{error}");
        let error = parse("wavelength_nm,n,k\n400,0.1,3\n").expect_err("no source");
        assert!(error.contains("Source"), "{error}");
        let error = parse("# Source: s\nlambda,n,k\n").expect_err("bad header");
        assert!(error.contains("header"), "{error}");
    }
}
