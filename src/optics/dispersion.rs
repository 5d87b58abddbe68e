//! Published dispersion formulas in double precision, and what the glass catalogue derives from
//! them: the refractive index n_d and Abbe number V_d (ISO 7944, *Optics and optical
//! instruments — Reference wavelengths*; SCHOTT TIE-29 *Refractive index and dispersion*), and
//! a least-squares Cauchy fit.
//!
//! A [`DispersionFormula`] keeps a formula exactly as a paper or data sheet publishes it, with
//! any number of Sellmeier terms (water needs four) or as a power series in λ (PMMA); the
//! renderer's [`Ior`] is built from it by [`DispersionFormula::to_ior`].
//!
//! Abbe number: V_d = (n_d − 1) / (n_F − n_C), with the helium d line (587.5618 nm) and the
//! hydrogen F (486.1327 nm) and C (656.2725 nm) lines. A low V_d means strong dispersion.
//!
//! Cauchy fit: n(λ) ≈ A + B/λ² + C/λ⁴ (λ in µm) minimising the squared error over 400–700 nm
//! sampled every 1 nm, solved through the 3 × 3 normal equations in f64 (their condition number
//! is about 5·10⁴ here, harmless in f64).

use std::sync::Arc;

use super::ior::{LAMBDA_MAX_NM, LAMBDA_MIN_NM};
use super::Ior;

/// The helium d line, 587.5618 nm, where n_d is quoted.
pub const LAMBDA_D_NM: f64 = 587.5618;
/// The hydrogen F line, 486.1327 nm (blue end of the Abbe number).
pub const LAMBDA_F_NM: f64 = 486.1327;
/// The hydrogen C line, 656.2725 nm (red end of the Abbe number).
pub const LAMBDA_C_NM: f64 = 656.2725;

/// Wavelength range of the catalogue's Cauchy fits, in nm: the visible core, where a
/// three-term Cauchy law is accurate to ~10⁻⁴ for optical glasses.
pub const CAUCHY_FIT_RANGE_NM: (f64, f64) = (400.0, 700.0);
/// Spacing of the samples of the Cauchy fit, in nm.
pub const CAUCHY_FIT_STEP_NM: f64 = 1.0;

/// Spacing, in nm, of the table that stands in for a Sellmeier formula of more than three terms
/// (which [`Ior::Sellmeier`] cannot hold). Linear interpolation errs by at most
/// h² max|n''| / 8 ≈ 10⁻⁹ for water at h = 1 nm.
pub const TABULATION_STEP_NM: f64 = 1.0;

/// A dispersion formula as published, evaluated in f64 with λ in µm.
#[derive(Clone, Debug, PartialEq)]
pub enum DispersionFormula {
    /// n² = 1 + Σ Bᵢ λ² / (λ² − Cᵢ), any number of terms (Cᵢ in µm²); `b` and `c_um2` have
    /// the same length.
    Sellmeier {
        /// Bᵢ (dimensionless).
        b: Vec<f64>,
        /// Cᵢ in µm².
        c_um2: Vec<f64>,
    },
    /// n² = A + Σ Dᵢ λ^pᵢ, the polynomial form of e.g. Beadie et al. 2015 for PMMA (Dᵢ in
    /// µm^−pᵢ); `coefficients` and `exponents` have the same length.
    PowerSeries {
        /// A (dimensionless).
        a: f64,
        /// Dᵢ, in µm^−pᵢ.
        coefficients: Vec<f64>,
        /// pᵢ, the power of λ (µm) of each coefficient.
        exponents: Vec<f64>,
    },
    /// n = A + B/λ² + C/λ⁴ (B in µm², C in µm⁴).
    Cauchy {
        /// A (dimensionless).
        a: f64,
        /// B in µm².
        b_um2: f64,
        /// C in µm⁴.
        c_um4: f64,
    },
}

impl DispersionFormula {
    /// n at `lambda_nm` (nm). NaN where a formula gives n² < 0.
    pub fn n_at_nm(&self, lambda_nm: f64) -> f64 {
        let lambda_um = lambda_nm * 1e-3;
        let lambda_um2 = lambda_um * lambda_um;
        match self {
            DispersionFormula::Sellmeier { b, c_um2 } => (1.0
                + b.iter().zip(c_um2).map(|(b_i, c_i)| b_i * lambda_um2 / (lambda_um2 - c_i)).sum::<f64>())
            .sqrt(),
            DispersionFormula::PowerSeries { a, coefficients, exponents } => (a + coefficients
                .iter()
                .zip(exponents)
                .map(|(d_i, p_i)| d_i * lambda_um.powf(*p_i))
                .sum::<f64>())
            .sqrt(),
            DispersionFormula::Cauchy { a, b_um2, c_um4 } => {
                a + b_um2 / lambda_um2 + c_um4 / (lambda_um2 * lambda_um2)
            }
        }
    }

    /// n_d, the index at the helium d line ([`LAMBDA_D_NM`]).
    pub fn n_d(&self) -> f64 {
        self.n_at_nm(LAMBDA_D_NM)
    }

    /// Abbe number V_d = (n_d − 1) / (n_F − n_C).
    pub fn abbe_vd(&self) -> f64 {
        (self.n_d() - 1.0) / (self.n_at_nm(LAMBDA_F_NM) - self.n_at_nm(LAMBDA_C_NM))
    }

    /// The renderer's f32 model: the formula itself when [`Ior`] can hold it (a Cauchy law or a
    /// Sellmeier law of at most three terms, padded with B = 0), otherwise (more Sellmeier
    /// terms, a power series) a table every [`TABULATION_STEP_NM`] over the rendered range
    /// 360–830 nm.
    pub fn to_ior(&self) -> Ior {
        match self {
            DispersionFormula::Sellmeier { b, c_um2 } if b.len() <= 3 && b.len() == c_um2.len() => {
                let mut b3 = [0.0_f32; 3];
                let mut c3 = [0.0_f32; 3];
                for (i, (b_i, c_i)) in b.iter().zip(c_um2).enumerate() {
                    b3[i] = *b_i as f32;
                    c3[i] = *c_i as f32;
                }
                Ior::Sellmeier { b: b3, c_um2: c3 }
            }
            DispersionFormula::Cauchy { a, b_um2, c_um4 } => {
                Ior::Cauchy { a: *a as f32, b_um2: *b_um2 as f32, c_um4: *c_um4 as f32 }
            }
            DispersionFormula::Sellmeier { .. } | DispersionFormula::PowerSeries { .. } => {
                let (first, last) = (f64::from(LAMBDA_MIN_NM), f64::from(LAMBDA_MAX_NM));
                let count = ((last - first) / TABULATION_STEP_NM).round() as usize;
                let table: Arc<[(f32, f32)]> = (0..=count)
                    .map(|i| first + i as f64 * TABULATION_STEP_NM)
                    .map(|lambda_nm| (lambda_nm as f32, self.n_at_nm(lambda_nm) as f32))
                    .collect();
                Ior::Tabulated(table)
            }
        }
    }
}

/// A least-squares Cauchy law n ≈ A + B/λ² + C/λ⁴ (λ in µm) and how well it fits.
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CauchyFit {
    /// A (dimensionless).
    pub a: f64,
    /// B in µm².
    pub b_um2: f64,
    /// C in µm⁴.
    pub c_um4: f64,
    /// Largest |n_fit − n| over the fitted samples.
    pub max_abs_error: f64,
}

impl CauchyFit {
    /// The fit as a renderer [`Ior::Cauchy`].
    pub fn to_ior(&self) -> Ior {
        Ior::Cauchy { a: self.a as f32, b_um2: self.b_um2 as f32, c_um4: self.c_um4 as f32 }
    }

    /// n of the fitted law at `lambda_nm`.
    pub fn n_at_nm(&self, lambda_nm: f64) -> f64 {
        DispersionFormula::Cauchy { a: self.a, b_um2: self.b_um2, c_um4: self.c_um4 }.n_at_nm(lambda_nm)
    }
}

/// Least-squares fit of Cauchy's law to `n_at_nm` sampled every `step_nm` from `range_nm.0` to
/// `range_nm.1` (both included, nm). `None` with fewer than three samples, a non-positive or
/// non-finite step or range, non-finite n, or singular normal equations.
pub fn fit_cauchy(n_at_nm: impl Fn(f64) -> f64, range_nm: (f64, f64), step_nm: f64) -> Option<CauchyFit> {
    let (first, last) = range_nm;
    if !(step_nm > 0.0 && first > 0.0 && last.is_finite() && last >= first) {
        return None;
    }
    let count = ((last - first) / step_nm + 1e-9).floor() as usize + 1;
    let samples: Vec<(f64, f64)> = (0..count)
        .map(|i| first + i as f64 * step_nm)
        .map(|lambda_nm| (lambda_nm, n_at_nm(lambda_nm)))
        .collect();
    if samples.len() < 3 || samples.iter().any(|(_, n)| !n.is_finite()) {
        return None;
    }
    // Normal equations MᵀM x = Mᵀn with rows (1, u, u²), u = 1/λ² in µm⁻².
    let mut normal = [[0.0_f64; 3]; 3];
    let mut rhs = [0.0_f64; 3];
    for &(lambda_nm, n) in &samples {
        let u = 1.0 / (lambda_nm * 1e-3).powi(2);
        let row = [1.0, u, u * u];
        for i in 0..3 {
            rhs[i] += row[i] * n;
            for j in 0..3 {
                normal[i][j] += row[i] * row[j];
            }
        }
    }
    let [a, b_um2, c_um4] = solve_3x3(normal, rhs)?;
    let mut fit = CauchyFit { a, b_um2, c_um4, max_abs_error: 0.0 };
    fit.max_abs_error =
        samples.iter().map(|&(lambda_nm, n)| (fit.n_at_nm(lambda_nm) - n).abs()).fold(0.0, f64::max);
    Some(fit)
}

/// Gaussian elimination with partial pivoting; `None` for a singular matrix.
fn solve_3x3(mut m: [[f64; 3]; 3], mut rhs: [f64; 3]) -> Option<[f64; 3]> {
    for column in 0..3 {
        let pivot = (column..3).max_by(|&i, &j| m[i][column].abs().total_cmp(&m[j][column].abs()))?;
        if m[pivot][column] == 0.0 {
            return None;
        }
        m.swap(column, pivot);
        rhs.swap(column, pivot);
        let (pivot_row, pivot_rhs) = (m[column], rhs[column]);
        for row in column + 1..3 {
            let factor = m[row][column] / pivot_row[column];
            for (value, pivot_value) in m[row].iter_mut().zip(pivot_row).skip(column) {
                *value -= factor * pivot_value;
            }
            rhs[row] -= factor * pivot_rhs;
        }
    }
    let mut x = [0.0; 3];
    for row in (0..3).rev() {
        let known: f64 = (row + 1..3).map(|k| m[row][k] * x[k]).sum();
        x[row] = (rhs[row] - known) / m[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SCHOTT N-BK7 data sheet coefficients.
    fn n_bk7() -> DispersionFormula {
        DispersionFormula::Sellmeier {
            b: vec![1.03961212, 0.231792344, 1.01046945],
            c_um2: vec![0.00600069867, 0.0200179144, 103.560653],
        }
    }

    #[test]
    fn n_bk7_matches_its_data_sheet() {
        // SCHOTT N-BK7: n_d = 1.51680, V_d = 64.17 (data sheet, rounded to the last digit).
        let glass = n_bk7();
        assert!((glass.n_d() - 1.51680).abs() < 5e-6, "{}", glass.n_d());
        assert!((glass.abbe_vd() - 64.17).abs() < 0.005, "{}", glass.abbe_vd());
    }

    #[test]
    fn abbe_number_of_a_pure_cauchy_law() {
        // For n = A + B/λ², V_d = (A + B/λd² − 1) / (B (1/λF² − 1/λC²)), computed by hand:
        // 1/λd² = 2.896629, 1/λF² = 4.231461, 1/λC² = 2.321836 µm⁻² (λ in µm), so
        // V_d = 0.51448315 / 0.00954813 = 53.8832.
        let law = DispersionFormula::Cauchy { a: 1.5, b_um2: 0.005, c_um4: 0.0 };
        assert!((law.abbe_vd() - 53.8832).abs() < 1e-3, "{}", law.abbe_vd());
    }

    #[test]
    fn cauchy_fit_recovers_an_exact_cauchy_law() {
        // Fitting data that follow Cauchy's law exactly returns the law, with zero error.
        let law = DispersionFormula::Cauchy { a: 1.5, b_um2: 0.004, c_um4: 0.0001 };
        let fit = fit_cauchy(|l| law.n_at_nm(l), CAUCHY_FIT_RANGE_NM, CAUCHY_FIT_STEP_NM)
            .expect("a well-posed fit");
        assert!((fit.a - 1.5).abs() < 1e-10, "{fit:?}");
        assert!((fit.b_um2 - 0.004).abs() < 1e-10, "{fit:?}");
        assert!((fit.c_um4 - 0.0001).abs() < 1e-10, "{fit:?}");
        assert!(fit.max_abs_error < 1e-12, "{fit:?}");
    }

    #[test]
    fn cauchy_fit_of_a_crown_glass_is_good_to_a_few_1e5() {
        // Over 400–700 nm a three-term Cauchy law follows an optical crown to a few 10⁻⁵
        // (SCHOTT TIE-29 notes that Cauchy-type laws hold in the visible only); it is not exact,
        // because N-BK7's infrared resonance bends n(λ) away from a power series in 1/λ².
        let glass = n_bk7();
        let fit = fit_cauchy(|l| glass.n_at_nm(l), CAUCHY_FIT_RANGE_NM, CAUCHY_FIT_STEP_NM)
            .expect("a well-posed fit");
        assert!(fit.max_abs_error > 1e-7 && fit.max_abs_error < 1e-4, "{fit:?}");
        // The two-term values usually quoted for BK7, A ≈ 1.5046 and B ≈ 0.00420 µm² (e.g. the
        // table in Wikipedia's "Cauchy's equation"); the third term moves them slightly.
        assert!((fit.a - 1.5046).abs() < 2e-3 && (fit.b_um2 - 0.0042).abs() < 5e-4, "{fit:?}");
    }

    #[test]
    fn cauchy_fit_rejects_degenerate_input() {
        let law = |_: f64| 1.5;
        assert_eq!(fit_cauchy(law, (500.0, 501.0), 1.0), None, "two samples");
        assert_eq!(fit_cauchy(law, (400.0, 700.0), 0.0), None, "zero step");
        assert_eq!(fit_cauchy(law, (700.0, 400.0), 1.0), None, "reversed range");
        assert_eq!(fit_cauchy(|_| f64::NAN, (400.0, 700.0), 1.0), None, "NaN data");
    }

    #[test]
    fn a_four_term_sellmeier_law_is_tabulated_faithfully() {
        // Daimon & Masumura (2007), water at 20 °C, four terms: the table must follow the
        // formula to ~1e-7 between its 1 nm knots (f32 rounding dominates).
        let water = DispersionFormula::Sellmeier {
            b: vec![5.684027565e-1, 1.726177391e-1, 2.086189578e-2, 1.130748688e-1],
            c_um2: vec![5.101829712e-3, 1.821153936e-2, 2.620722293e-2, 1.069792721e1],
        };
        let ior = water.to_ior();
        assert!(matches!(ior, Ior::Tabulated(_)));
        for lambda_nm in [360.0_f64, 400.25, 550.5, 589.3, 700.75, 830.0] {
            let error = (ior.eval(lambda_nm as f32) as f64 - water.n_at_nm(lambda_nm)).abs();
            assert!(error < 2e-7, "{lambda_nm} nm: {error}");
        }
        // IAPWS R9-97 (Harvey et al., J. Phys. Chem. Ref. Data 27, 761 (1998)) evaluated at
        // 20 °C and 0.1 MPa (ρ = 998.206 kg m⁻³) gives n = 1.333349 at 589.3 nm.
        assert!((water.n_at_nm(589.3) - 1.333_349).abs() < 3e-5);
    }

    #[test]
    fn a_three_term_law_stays_a_sellmeier_law() {
        match n_bk7().to_ior() {
            Ior::Sellmeier { b, c_um2 } => {
                assert_eq!(b[0], 1.03961212_f64 as f32);
                assert_eq!(c_um2[2], 103.560653_f64 as f32);
            }
            other => panic!("expected a Sellmeier law, got {other:?}"),
        }
    }
}
