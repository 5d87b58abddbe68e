//! [`Ior`]: index of refraction n(λ) of a transparent dielectric, per wavelength in nm.
//!
//! Models:
//! - Cauchy's law n = A + B/λ² + C/λ⁴ (Born & Wolf, *Principles of Optics*, §2.3.4), λ in µm;
//! - Sellmeier's three-term law n² = 1 + Σ Bᵢ λ² / (λ² − Cᵢ), λ in µm, Cᵢ in µm², the form of
//!   the SCHOTT optical glass data sheets (SCHOTT TIE-29, *Refractive index and dispersion*);
//! - a table of (λ nm, n) interpolated linearly, constant beyond its end points.
//!
//! In a scene file: `ior = 1.5`, `ior = { cauchy = [1.5046, 0.0042, 0.0] }` (A, B µm², C µm⁴),
//! `ior = { sellmeier = { b = [1.0396, 0.2318, 1.0105], c_um2 = [0.0060, 0.0200, 103.56] } }`,
//! `ior = { table = [[400, 1.53], [700, 1.51]] }` (nm, n) or `ior = { glass = "N-BK7" }` for a
//! catalogue glass (see [`crate::optics::catalogue`]).
//!
//! [`Ior::eval`] never allocates; [`Ior::validate`] is meant to run once, when a scene is built,
//! and rejects any model whose n is not finite and positive over the rendered range.

/// Shortest wavelength rendered, in nm (the CIE 1931 observer's visible range starts here).
pub const LAMBDA_MIN_NM: f32 = 360.0;
/// Longest wavelength rendered, in nm.
pub const LAMBDA_MAX_NM: f32 = 830.0;

/// Spacing of the wavelengths at which [`Ior::validate`] evaluates n, in nm. One nanometre is
/// finer than any feature of a physical dispersion law in the visible; Sellmeier poles, which
/// are sharp, are also found analytically.
const VALIDATION_STEP_NM: f32 = 1.0;

/// Why an index-of-refraction model is invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IorError {
    /// The message states the offending value and why.
    #[error("{0}")]
    Invalid(String),
}

/// Index of refraction n(λ) of a dielectric, evaluated per wavelength in nm without allocation.
#[derive(Debug, Clone, PartialEq)]
pub enum Ior {
    /// The same index at every wavelength.
    Constant(f32),
    /// Cauchy's law n = A + B/λ² + C/λ⁴ with λ in µm (B in µm², C in µm⁴).
    Cauchy {
        /// A (dimensionless).
        a: f32,
        /// B in µm².
        b_um2: f32,
        /// C in µm⁴.
        c_um4: f32,
    },
    /// Sellmeier's three-term law n² = 1 + Σ Bᵢ λ² / (λ² − Cᵢ) with λ in µm (Cᵢ in µm²).
    Sellmeier {
        /// B₁, B₂, B₃ (dimensionless).
        b: [f32; 3],
        /// C₁, C₂, C₃ in µm².
        c_um2: [f32; 3],
    },
    /// Linear interpolation in a table of (λ nm, n), strictly increasing in λ; constant beyond
    /// the end points.
    Tabulated(std::sync::Arc<[(f32, f32)]>),
}

impl Ior {
    /// n at `lambda_nm` (nm). Allocation-free; a model that [`Ior::validate`] rejects may give
    /// a non-finite value (a Sellmeier law evaluated at its pole, an empty table gives NaN).
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        match self {
            Ior::Constant(n) => *n,
            Ior::Cauchy { a, b_um2, c_um4 } => cauchy(*a, *b_um2, *c_um4, lambda_nm),
            Ior::Sellmeier { b, c_um2 } => sellmeier_n_squared(b, c_um2, lambda_nm).sqrt(),
            Ior::Tabulated(table) => interpolate_table(table, lambda_nm),
        }
    }
    /// True when n varies with wavelength.
    pub fn is_dispersive(&self) -> bool {
        !matches!(self, Ior::Constant(_))
    }
    /// Checks that n is finite and > 0 over the rendered range 360–830 nm (and that the model's
    /// own parameters are well formed).
    ///
    /// n is evaluated every 1 nm from [`LAMBDA_MIN_NM`] to [`LAMBDA_MAX_NM`]. A Sellmeier term
    /// whose pole λ = √Cᵢ lies inside that range is rejected even if no sample hits it; a table
    /// must be non-empty, strictly increasing in λ, with finite wavelengths and finite n > 0.
    pub fn validate(&self) -> Result<(), IorError> {
        match self {
            Ior::Constant(n) => check_n("constant index", LAMBDA_MIN_NM, *n),
            Ior::Cauchy { a, b_um2, c_um4 } => {
                let model = format!("Cauchy law (A = {a}, B = {b_um2} µm², C = {c_um4} µm⁴)");
                check_finite_parameters(&model, &[*a, *b_um2, *c_um4])?;
                self.check_sampled(&model)
            }
            Ior::Sellmeier { b, c_um2 } => {
                let model = format!("Sellmeier law (B = {b:?}, C = {c_um2:?} µm²)");
                check_finite_parameters(&model, b)?;
                check_finite_parameters(&model, c_um2)?;
                check_sellmeier_poles(&model, b, c_um2)?;
                self.check_sampled(&model)
            }
            Ior::Tabulated(table) => validate_table("tabulated index", table),
        }
    }

    /// Evaluates n on the validation grid and rejects the first non-finite or non-positive value.
    fn check_sampled(&self, model: &str) -> Result<(), IorError> {
        validation_wavelengths_nm().try_for_each(|lambda_nm| check_n(model, lambda_nm, self.eval(lambda_nm)))
    }
}

/// Cauchy's law at `lambda_nm`, with λ converted to µm.
fn cauchy(a: f32, b_um2: f32, c_um4: f32, lambda_nm: f32) -> f32 {
    let inv_lambda_um2 = 1.0 / square(lambda_nm * 1e-3);
    a + inv_lambda_um2 * (b_um2 + c_um4 * inv_lambda_um2)
}

/// n² of Sellmeier's law at `lambda_nm`; negative or infinite at and near a pole.
fn sellmeier_n_squared(b: &[f32; 3], c_um2: &[f32; 3], lambda_nm: f32) -> f32 {
    let lambda_um2 = square(lambda_nm * 1e-3);
    1.0 + b.iter().zip(c_um2).map(|(b_i, c_i)| b_i * lambda_um2 / (lambda_um2 - c_i)).sum::<f32>()
}

fn square(x: f32) -> f32 {
    x * x
}

/// Linear interpolation of `value` in a table of (λ nm, value) sorted by λ, constant beyond the
/// end points, found by binary search. NaN for an empty table. Shared with the metal spectra of
/// [`crate::optics::metals`].
pub(crate) fn interpolate_table(table: &[(f32, f32)], lambda_nm: f32) -> f32 {
    debug_assert!(!table.is_empty(), "interpolating an empty table");
    // Index of the first sample at or beyond `lambda_nm`.
    let upper = table.partition_point(|&(lambda, _)| lambda < lambda_nm);
    match (upper.checked_sub(1), table.get(upper)) {
        (Some(lower), Some(&(lambda_1, value_1))) => {
            let (lambda_0, value_0) = table[lower];
            let t = (lambda_nm - lambda_0) / (lambda_1 - lambda_0);
            value_0 + t * (value_1 - value_0)
        }
        // At or before the first sample.
        (None, Some(&(_, first))) => first,
        // Beyond the last sample.
        (Some(last), None) => table[last].1,
        (None, None) => f32::NAN,
    }
}

/// 360, 361, … 830 nm.
fn validation_wavelengths_nm() -> impl Iterator<Item = f32> {
    let count = ((LAMBDA_MAX_NM - LAMBDA_MIN_NM) / VALIDATION_STEP_NM) as u32;
    (0..=count).map(|i| LAMBDA_MIN_NM + i as f32 * VALIDATION_STEP_NM)
}

fn check_n(model: &str, lambda_nm: f32, n: f32) -> Result<(), IorError> {
    if n.is_finite() && n > 0.0 {
        Ok(())
    } else {
        Err(IorError::Invalid(format!(
            "{model}: n = {n} at {lambda_nm} nm; an index of refraction must be finite and > 0"
        )))
    }
}

fn check_finite_parameters(model: &str, parameters: &[f32]) -> Result<(), IorError> {
    match parameters.iter().find(|p| !p.is_finite()) {
        Some(p) => Err(IorError::Invalid(format!("{model}: parameter {p} is not a finite number"))),
        None => Ok(()),
    }
}

/// A term Bᵢ λ²/(λ² − Cᵢ) with Bᵢ ≠ 0 diverges at λ = √Cᵢ; inside the rendered range that is an
/// absorption line the law cannot describe.
fn check_sellmeier_poles(model: &str, b: &[f32; 3], c_um2: &[f32; 3]) -> Result<(), IorError> {
    let range_um2 = square(LAMBDA_MIN_NM * 1e-3)..=square(LAMBDA_MAX_NM * 1e-3);
    for (term, (b_i, c_i)) in b.iter().zip(c_um2).enumerate() {
        if *b_i != 0.0 && range_um2.contains(c_i) {
            return Err(IorError::Invalid(format!(
                "{model}: term {} has a pole at λ = √C = {} nm, inside the rendered range \
                 {LAMBDA_MIN_NM}–{LAMBDA_MAX_NM} nm",
                term + 1,
                c_i.sqrt() * 1e3
            )));
        }
    }
    Ok(())
}

/// Checks a table of (λ nm, value): non-empty, finite, strictly increasing λ, value finite > 0.
pub(crate) fn validate_table(model: &str, table: &[(f32, f32)]) -> Result<(), IorError> {
    if table.is_empty() {
        return Err(IorError::Invalid(format!("{model}: the table is empty")));
    }
    for &(lambda_nm, n) in table {
        if !lambda_nm.is_finite() {
            return Err(IorError::Invalid(format!(
                "{model}: wavelength {lambda_nm} nm is not a finite number"
            )));
        }
        check_n(model, lambda_nm, n)?;
    }
    match table.windows(2).find(|pair| pair[1].0 <= pair[0].0) {
        Some(pair) => Err(IorError::Invalid(format!(
            "{model}: wavelengths must be strictly increasing, but {} nm follows {} nm",
            pair[1].0, pair[0].0
        ))),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    /// SCHOTT's published Sellmeier coefficients of N-BK7 (data sheet, catalogue 2017).
    fn n_bk7() -> Ior {
        Ior::Sellmeier {
            b: [1.03961212_f64, 0.231792344, 1.01046945].map(|b| b as f32),
            c_um2: [0.00600069867_f64, 0.0200179144, 103.560653].map(|c| c as f32),
        }
    }

    #[test]
    fn constant_is_the_same_everywhere() {
        // n = 1.5 at every wavelength, by definition.
        let ior = Ior::Constant(1.5);
        assert_eq!(ior.eval(360.0), 1.5);
        assert_eq!(ior.eval(830.0), 1.5);
        assert!(!ior.is_dispersive());
        assert!(ior.validate().is_ok());
    }

    #[test]
    fn cauchy_uses_micrometres() {
        // At λ = 500 nm = 0.5 µm: 1/λ² = 4 µm⁻², 1/λ⁴ = 16 µm⁻⁴, so
        // n = 1.5 + 0.004·4 + 0.0001·16 = 1.5176.
        let ior = Ior::Cauchy { a: 1.5, b_um2: 0.004, c_um4: 0.0001 };
        assert!((ior.eval(500.0) - 1.5176).abs() < 1e-6);
        // At 1000 nm = 1 µm the terms are just A + B + C = 1.5041.
        assert!((ior.eval(1000.0) - 1.5041).abs() < 1e-6);
        assert!(ior.is_dispersive());
        assert!(ior.validate().is_ok());
    }

    #[test]
    fn sellmeier_reproduces_the_schott_n_bk7_data_sheet() {
        // SCHOTT N-BK7 data sheet: n_d = 1.51680 at 587.5618 nm, n_F = 1.52238 at 486.1327 nm,
        // n_C = 1.51432 at 656.2725 nm (five decimals, so ±5e-6 of rounding; f32 adds ~1e-7).
        let ior = n_bk7();
        assert!((ior.eval(587.5618) - 1.51680).abs() < 1e-5);
        assert!((ior.eval(486.1327) - 1.52238).abs() < 1e-5);
        assert!((ior.eval(656.2725) - 1.51432).abs() < 1e-5);
        assert!(ior.validate().is_ok());
    }

    #[test]
    fn sellmeier_with_no_terms_is_vacuum() {
        // All Bᵢ = 0 leaves n² = 1.
        let ior = Ior::Sellmeier { b: [0.0; 3], c_um2: [0.01, 0.02, 100.0] };
        assert_eq!(ior.eval(550.0), 1.0);
    }

    #[test]
    fn tabulated_interpolates_linearly_and_clamps() {
        let ior = Ior::Tabulated(Arc::from(vec![(400.0, 1.6), (500.0, 1.5), (700.0, 1.4)]));
        // Exactly on samples.
        assert_eq!(ior.eval(400.0), 1.6);
        assert_eq!(ior.eval(500.0), 1.5);
        assert_eq!(ior.eval(700.0), 1.4);
        // Half way between 400 and 500 nm: (1.6 + 1.5)/2; a quarter of the way from 500 to 700.
        assert!((ior.eval(450.0) - 1.55).abs() < 1e-6);
        assert!((ior.eval(550.0) - 1.475).abs() < 1e-6);
        // Constant beyond the end points.
        assert_eq!(ior.eval(360.0), 1.6);
        assert_eq!(ior.eval(830.0), 1.4);
        assert!(ior.validate().is_ok());
    }

    #[test]
    fn a_single_sample_table_is_constant() {
        let ior = Ior::Tabulated(Arc::from(vec![(550.0, 1.33)]));
        assert_eq!(ior.eval(400.0), 1.33);
        assert_eq!(ior.eval(550.0), 1.33);
        assert_eq!(ior.eval(800.0), 1.33);
        assert!(ior.validate().is_ok());
    }

    fn message(result: Result<(), IorError>) -> String {
        match result {
            Err(IorError::Invalid(message)) => message,
            Ok(()) => panic!("expected an error"),
        }
    }

    #[test]
    fn validate_rejects_non_positive_or_non_finite_constants() {
        for n in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let text = message(Ior::Constant(n).validate());
            assert!(text.contains("constant index"), "{text}");
        }
    }

    #[test]
    fn validate_reports_where_cauchy_goes_negative() {
        // n = −1 + 0.2/λ² is positive only for λ² < 0.2 µm², λ < 447.2 nm: at 448 nm it is
        // −1 + 0.2/0.200704 < 0, the first failing sample.
        let ior = Ior::Cauchy { a: -1.0, b_um2: 0.2, c_um4: 0.0 };
        let text = message(ior.validate());
        assert!(text.contains("Cauchy"), "{text}");
        assert!(text.contains("448 nm"), "{text}");
    }

    #[test]
    fn validate_finds_a_sellmeier_pole_between_samples() {
        // C = 0.25050 µm² puts a pole at λ = 500.4998 nm, between the 1 nm samples.
        let ior = Ior::Sellmeier { b: [1.0, 0.0, 0.0], c_um2: [0.2505, 0.0, 0.0] };
        let text = message(ior.validate());
        assert!(text.contains("pole"), "{text}");
        assert!(text.contains("term 1"), "{text}");
        assert!(text.contains("500.49"), "{text}");
    }

    #[test]
    fn validate_accepts_a_pole_outside_the_range() {
        // N-BK7's infrared term has its pole at √103.56 µm ≈ 10.2 µm, far outside.
        assert!(n_bk7().validate().is_ok());
    }

    #[test]
    fn validate_rejects_malformed_tables() {
        let table = |rows: Vec<(f32, f32)>| Ior::Tabulated(Arc::from(rows));
        let text = message(table(vec![]).validate());
        assert!(text.contains("empty"), "{text}");
        let text = message(table(vec![(500.0, 1.5), (500.0, 1.6)]).validate());
        assert!(text.contains("strictly increasing"), "{text}");
        assert!(text.contains("500 nm follows 500 nm"), "{text}");
        let text = message(table(vec![(600.0, 1.5), (400.0, 1.6)]).validate());
        assert!(text.contains("400 nm follows 600 nm"), "{text}");
        let text = message(table(vec![(400.0, 1.5), (f32::NAN, 1.6)]).validate());
        assert!(text.contains("wavelength NaN"), "{text}");
        let text = message(table(vec![(400.0, 1.5), (500.0, -1.0)]).validate());
        assert!(text.contains("n = -1 at 500 nm"), "{text}");
    }

    #[test]
    fn validate_rejects_non_finite_parameters() {
        let ior = Ior::Sellmeier { b: [1.0, f32::NAN, 0.0], c_um2: [0.01, 0.02, 100.0] };
        assert!(message(ior.validate()).contains("not a finite number"));
        let ior = Ior::Cauchy { a: 1.5, b_um2: f32::INFINITY, c_um4: 0.0 };
        assert!(message(ior.validate()).contains("not a finite number"));
    }
}
