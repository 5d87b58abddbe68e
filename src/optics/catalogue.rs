//! The glass catalogue of `data/glasses.toml`: named transparent dielectrics (SCHOTT N-BK7,
//! N-SF11 and F2 from their data sheets; fused silica after Malitson 1965; water after Daimon &
//! Masumura 2007; diamond after Peter 1923; PMMA after Beadie et al. 2015), each with its
//! published dispersion formula, the source, and what prisma derives from it: n_d, the Abbe
//! number V_d and a least-squares Cauchy fit over 400–700 nm (see [`crate::optics::dispersion`]).
//!
//! In a scene file: `ior = { glass = "N-SF11" }`.
//!
//! The file is embedded in the binary and parsed once, on first use. Names are matched ignoring
//! case, spaces, `-` and `_`, so `"n-bk7"`, `"NBK7"` and `"fused silica"` all resolve.

use std::sync::OnceLock;

use serde::Deserialize;

use super::dispersion::{CauchyFit, DispersionFormula};
use super::Ior;

/// The catalogue's text, embedded at build time.
const GLASSES_TOML: &str = include_str!("../../data/glasses.toml");

/// One glass of the catalogue.
#[derive(Clone, Debug, PartialEq)]
pub struct GlassEntry {
    name: String,
    source: String,
    valid_range_nm: (f64, f64),
    formula: DispersionFormula,
    ior: Ior,
    cauchy_fit: CauchyFit,
}

impl GlassEntry {
    /// The catalogue name, e.g. `"N-BK7"`.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Where the dispersion formula is published.
    pub fn source(&self) -> &str {
        &self.source
    }
    /// Wavelength range (nm) over which the source states its formula; rendering beyond it
    /// extrapolates.
    pub fn valid_range_nm(&self) -> (f64, f64) {
        self.valid_range_nm
    }
    /// The published dispersion formula, in f64.
    pub fn formula(&self) -> &DispersionFormula {
        &self.formula
    }
    /// The renderer's index model ([`DispersionFormula::to_ior`]).
    pub fn ior(&self) -> &Ior {
        &self.ior
    }
    /// n_d, the index at the helium d line, 587.5618 nm.
    pub fn n_d(&self) -> f64 {
        self.formula.n_d()
    }
    /// Abbe number V_d = (n_d − 1) / (n_F − n_C).
    pub fn abbe_vd(&self) -> f64 {
        self.formula.abbe_vd()
    }
    /// The stored least-squares Cauchy fit over 400–700 nm, with its largest error.
    pub fn cauchy_fit(&self) -> &CauchyFit {
        &self.cauchy_fit
    }
}

/// Every glass of the built-in catalogue, in file order.
///
/// # Panics
/// If the embedded `data/glasses.toml` is malformed, which the catalogue's tests rule out.
pub fn glasses() -> &'static [GlassEntry] {
    static CATALOGUE: OnceLock<Vec<GlassEntry>> = OnceLock::new();
    CATALOGUE.get_or_init(|| match parse_catalogue(GLASSES_TOML) {
        Ok(glasses) => glasses,
        Err(message) => panic!("built-in data/glasses.toml: {message}"),
    })
}

/// Looks up a named glass, ignoring case, spaces, `-` and `_`.
pub fn glass(name: &str) -> Option<&'static GlassEntry> {
    let key = lookup_key(name);
    glasses().iter().find(|glass| lookup_key(&glass.name) == key)
}

/// Looks up a named glass (case-insensitive, e.g. `"N-SF11"`) in the built-in catalogue.
pub fn glass_ior(name: &str) -> Option<Ior> {
    glass(name).map(|glass| glass.ior.clone())
}

/// Names of every glass in the built-in catalogue.
pub fn glass_names() -> Vec<&'static str> {
    glasses().iter().map(|glass| glass.name.as_str()).collect()
}

fn lookup_key(name: &str) -> String {
    name.chars().filter(|c| !matches!(c, ' ' | '-' | '_')).flat_map(char::to_lowercase).collect()
}

/// The file as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CatalogueDesc {
    glass: Vec<GlassDesc>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GlassDesc {
    name: String,
    source: String,
    valid_nm: [f64; 2],
    sellmeier: Option<SellmeierDesc>,
    power_series: Option<PowerSeriesDesc>,
    cauchy_fit: CauchyFit,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PowerSeriesDesc {
    a: f64,
    coefficients: Vec<f64>,
    exponents: Vec<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SellmeierDesc {
    b: Vec<f64>,
    c_um2: Option<Vec<f64>>,
    resonance_um: Option<Vec<f64>>,
}

/// Parses and checks a catalogue: names unique and non-empty, sources given, one C per B, an
/// index valid over the rendered range.
fn parse_catalogue(text: &str) -> Result<Vec<GlassEntry>, String> {
    let desc: CatalogueDesc = toml::from_str(text).map_err(|err| err.to_string())?;
    let mut glasses: Vec<GlassEntry> = Vec::with_capacity(desc.glass.len());
    for glass in desc.glass {
        let context = format!("glass \"{}\"", glass.name);
        if lookup_key(&glass.name).is_empty() || glass.source.trim().is_empty() {
            return Err(format!("{context}: a glass needs a name and a source"));
        }
        if glasses.iter().any(|other| lookup_key(&other.name) == lookup_key(&glass.name)) {
            return Err(format!("{context} appears twice"));
        }
        let formula = match (glass.sellmeier, glass.power_series) {
            (Some(sellmeier), None) => sellmeier_formula(sellmeier).map_err(|e| format!("{context}: {e}"))?,
            (None, Some(PowerSeriesDesc { a, coefficients, exponents })) => {
                if coefficients.is_empty() || coefficients.len() != exponents.len() {
                    return Err(format!(
                        "{context}: {} coefficients but {} exponents",
                        coefficients.len(),
                        exponents.len()
                    ));
                }
                DispersionFormula::PowerSeries { a, coefficients, exponents }
            }
            _ => return Err(format!("{context}: give exactly one of sellmeier and power_series")),
        };
        let ior = formula.to_ior();
        ior.validate().map_err(|err| format!("{context}: {err}"))?;
        let [first, last] = glass.valid_nm;
        glasses.push(GlassEntry {
            name: glass.name,
            source: glass.source,
            valid_range_nm: (first, last),
            formula,
            ior,
            cauchy_fit: glass.cauchy_fit,
        });
    }
    Ok(glasses)
}

fn sellmeier_formula(desc: SellmeierDesc) -> Result<DispersionFormula, String> {
    let SellmeierDesc { b, c_um2, resonance_um } = desc;
    let c_um2 = match (c_um2, resonance_um) {
        (Some(c_um2), None) => c_um2,
        (None, Some(resonance_um)) => resonance_um.iter().map(|l| l * l).collect(),
        _ => return Err("give exactly one of c_um2 and resonance_um".to_owned()),
    };
    if b.is_empty() || b.len() != c_um2.len() {
        return Err(format!("{} B but {} C coefficients", b.len(), c_um2.len()));
    }
    Ok(DispersionFormula::Sellmeier { b, c_um2 })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::dispersion::{
        fit_cauchy, CAUCHY_FIT_RANGE_NM, CAUCHY_FIT_STEP_NM, LAMBDA_C_NM, LAMBDA_F_NM,
    };

    fn entry(name: &str) -> &'static GlassEntry {
        glass(name).unwrap_or_else(|| panic!("{name} is in the catalogue"))
    }

    /// Checks n_d and V_d against published values with the stated tolerances.
    fn check(name: &str, n_d: f64, n_d_tolerance: f64, v_d: f64, v_d_tolerance: f64) {
        let glass = entry(name);
        assert!(
            (glass.n_d() - n_d).abs() <= n_d_tolerance,
            "{name}: n_d = {} vs published {n_d}",
            glass.n_d()
        );
        assert!(
            (glass.abbe_vd() - v_d).abs() <= v_d_tolerance,
            "{name}: V_d = {} vs published {v_d}",
            glass.abbe_vd()
        );
    }

    #[test]
    fn schott_glasses_match_their_data_sheets() {
        // SCHOTT data sheets quote n_d to 5 decimals and V_d to 2: the Sellmeier formula
        // reproduces them to their rounding (±5e-6, ±0.005), plus a little for the formula's
        // own fit residual (SCHOTT TIE-29: ~1e-5).
        check("N-BK7", 1.51680, 1e-5, 64.17, 0.01);
        check("N-SF11", 1.78472, 1e-5, 25.68, 0.01);
        check("F2", 1.62004, 1e-5, 36.37, 0.01);
        // The glasses of the shipped lenses (data/lenses/).
        check("SF5", 1.67270, 1e-5, 32.21, 0.01);
        check("N-BAF10", 1.67003, 1e-5, 47.11, 0.01);
        check("N-SF15", 1.69892, 1e-5, 30.20, 0.01);
        check("F5", 1.60342, 1e-5, 38.03, 0.01);
        check("N-SSK5", 1.65844, 1e-5, 50.88, 0.01);
    }

    #[test]
    fn ohara_glasses_match_their_data_sheets() {
        // OHARA data sheets quote n_d to 5 decimals and V_d to 2 (their catalogue file to 6
        // and 6: 1.717004, 47.927969), so the same tolerances as SCHOTT's.
        check("S-LAM3", 1.71700, 1e-5, 47.93, 0.01);
    }

    #[test]
    fn fused_silica_matches_its_data_sheets() {
        // Fused silica: n_d = 1.4585, V_d = 67.8 (Heraeus and Corning data sheets; Malitson's
        // own table gives 1.45846 at 587.6 nm).
        check("fused silica", 1.4585, 1e-4, 67.8, 0.1);
    }

    #[test]
    fn water_matches_the_handbook() {
        // The IAPWS R9-97 formulation (Harvey et al., J. Phys. Chem. Ref. Data 27, 761 (1998)),
        // an independent fit to a century of measurements, evaluated at 20 °C and 0.1 MPa
        // (ρ = 998.206 kg m⁻³): n_d = 1.333403, n_F = 1.337490, n_C = 1.331514, V_d = 55.78.
        // IAPWS states ~1e-5 uncertainty in the visible.
        check("water", 1.333_403, 3e-5, 55.78, 0.1);
    }

    #[test]
    fn diamond_matches_the_gemmological_values() {
        // Diamond: n = 2.4175 at 589 nm (Crystran diamond data sheet), and the C–F dispersion
        // n_F − n_C = 0.025 of gemmological tables (given to 3 decimals, so ±0.0005; Peter's
        // 1923 measurements are older and ~1e-3 coarser).
        let diamond = entry("diamond");
        let n_589 = diamond.formula().n_at_nm(589.0);
        assert!((n_589 - 2.4175).abs() < 5e-4, "n(589 nm) = {n_589}");
        let formula = diamond.formula();
        let dispersion = formula.n_at_nm(LAMBDA_F_NM) - formula.n_at_nm(LAMBDA_C_NM);
        assert!((dispersion - 0.025).abs() < 1e-3, "n_F − n_C = {dispersion}");
    }

    #[test]
    fn pmma_matches_the_plastics_tables() {
        // Optical-grade PMMA: n_d ≈ 1.491–1.4925 and V_d ≈ 57–59.5 across makers' data sheets
        // and measurements; the catalogue's source, Beadie et al. 2015, states its own absolute
        // accuracy as 2e-4.
        check("PMMA", 1.4918, 1.5e-3, 58.0, 1.5);
    }

    #[test]
    fn stored_cauchy_fits_match_a_refit() {
        // The fits in data/glasses.toml were computed by fit_cauchy; refitting must give the
        // same numbers, and the stated error must be the true largest error of the stored fit.
        for glass in glasses() {
            let refit = fit_cauchy(|l| glass.formula.n_at_nm(l), CAUCHY_FIT_RANGE_NM, CAUCHY_FIT_STEP_NM)
                .expect("every catalogue glass can be fitted");
            let stored = glass.cauchy_fit();
            let close = |x: f64, y: f64| (x - y).abs() <= 1e-10 * (1.0 + y.abs());
            assert!(
                close(stored.a, refit.a)
                    && close(stored.b_um2, refit.b_um2)
                    && close(stored.c_um4, refit.c_um4)
                    && close(stored.max_abs_error, refit.max_abs_error),
                "{}: stored {stored:?}, refit gives\ncauchy_fit = {{ a = {}, b_um2 = {}, c_um4 = {}, max_abs_error = {} }}",
                glass.name, refit.a, refit.b_um2, refit.c_um4, refit.max_abs_error
            );
            // A three-term Cauchy law is a good visible-range model: every fit is within 1e-3.
            assert!(stored.max_abs_error < 1e-3, "{}: {stored:?}", glass.name);
        }
    }

    #[test]
    fn the_cauchy_fit_ior_stays_within_its_stated_error() {
        // Evaluated in f32, the fit's Ior follows the formula to max_abs_error plus f32 rounding
        // (n ~ 2 has an ulp of 2.4e-7) between the 1 nm samples it was fitted on.
        for glass in glasses() {
            let fit = glass.cauchy_fit();
            let ior = fit.to_ior();
            for i in 0..=600 {
                let lambda_nm = 400.0 + 0.5 * i as f64;
                let error = (ior.eval(lambda_nm as f32) as f64 - glass.formula.n_at_nm(lambda_nm)).abs();
                assert!(error <= fit.max_abs_error + 1e-6, "{} at {lambda_nm} nm: {error}", glass.name);
            }
        }
    }

    #[test]
    fn every_glass_is_usable_and_has_a_source() {
        for glass in glasses() {
            assert!(glass.ior().validate().is_ok(), "{}", glass.name);
            assert!(glass.ior().is_dispersive());
            assert!(!glass.source().is_empty());
            let (first, last) = glass.valid_range_nm();
            assert!(first < last);
            // The renderer's f32 model follows the f64 formula to f32 precision.
            for lambda_nm in [360.0_f64, 486.1327, 587.5618, 656.2725, 830.0] {
                let n = glass.formula().n_at_nm(lambda_nm);
                assert!((glass.ior().eval(lambda_nm as f32) as f64 - n).abs() < 1e-6);
            }
        }
        assert!(glass_names().len() >= 7);
    }

    #[test]
    fn lookups_ignore_case_and_separators() {
        for name in ["N-BK7", "n-bk7", "NBK7", "n_bk7"] {
            assert_eq!(glass(name).map(GlassEntry::name), Some("N-BK7"), "{name}");
        }
        assert_eq!(glass("Fused Silica").map(GlassEntry::name), Some("fused-silica"));
        assert!(glass_ior("n-sf11").is_some());
        assert_eq!(glass_ior("unobtainium"), None);
        assert!(glass_names().contains(&"F2"));
    }

    #[test]
    fn flint_disperses_more_than_crown() {
        // The defining contrast of optical glasses: a dense flint (N-SF11, V_d 25.7) spreads
        // F to C over 2.5 times the range of a crown (N-BK7, V_d 64.2).
        assert!(entry("N-SF11").abbe_vd() * 2.0 < entry("N-BK7").abbe_vd());
    }

    #[test]
    fn malformed_catalogues_are_rejected_with_reasons() {
        let glass = |extra: &str| {
            format!(
                "[[glass]]\nname = \"X\"\nsource = \"s\"\nvalid_nm = [400.0, 700.0]\n{extra}\n\
                 cauchy_fit = {{ a = 1.5, b_um2 = 0.0, c_um4 = 0.0, max_abs_error = 0.0 }}\n"
            )
        };
        let error = |text: &str| parse_catalogue(text).expect_err("must be rejected");
        let neither = glass("");
        assert!(error(&neither).contains("exactly one of sellmeier and power_series"));
        let series = glass("power_series = { a = 2.0, coefficients = [0.01], exponents = [] }");
        assert!(error(&series).contains("1 coefficients but 0 exponents"));
        let both = glass("sellmeier = { b = [1.0], c_um2 = [0.01], resonance_um = [0.1] }");
        assert!(error(&both).contains("exactly one of c_um2 and resonance_um"));
        let mismatch = glass("sellmeier = { b = [1.0, 0.2], c_um2 = [0.01] }");
        assert!(error(&mismatch).contains("2 B but 1 C"));
        let pole = glass("sellmeier = { b = [1.0], resonance_um = [0.5] }");
        assert!(error(&pole).contains("pole"));
        let good = glass("sellmeier = { b = [1.0], c_um2 = [0.01] }");
        assert!(error(&format!("{good}{good}")).contains("appears twice"));
        assert!(parse_catalogue(&good).is_ok());
    }
}
