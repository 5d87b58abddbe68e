//! How a lens file names the glass behind a surface, turned into a [`Medium`]:
//! - a catalogue name of `data/glasses.toml` (`N-BK7`, `F2`, …; case, spaces, `-` and `_` do
//!   not matter), its published dispersion formula;
//! - `sellmeier:B1,B2,B3,C1,C2,C3`: n² = 1 + Σ Bᵢλ²/(λ² − Cᵢ), λ in µm, Cᵢ in µm² (as SCHOTT
//!   data sheets print them);
//! - `abbe:nd,vd`: a glass known only by n_d and V_d, modelled by the two-term Cauchy law
//!   n(λ) = A + B/λ² (λ in µm) through n(587.5618 nm) = n_d with
//!   n(486.1327 nm) − n(656.2725 nm) = (n_d − 1)/V_d (see [`abbe_formula`]);
//! - `air`: n = 1.
//!
//! The same model stands in for a Zemax model glass (`GLAS NAME 1 0 nd vd …`) whose name is not
//! in the catalogue.

use crate::optics::catalogue;
use crate::optics::dispersion::{DispersionFormula, LAMBDA_C_NM, LAMBDA_D_NM, LAMBDA_F_NM};

use super::Medium;

/// A glass given by n_d and V_d: the two-term Cauchy law n(λ) = A + B/λ² (λ in µm) with
/// n(λ_d) = n_d at the helium d line (587.5618 nm) and n(λ_F) − n(λ_C) = (n_d − 1)/V_d between the
/// hydrogen F (486.1327 nm) and C (656.2725 nm) lines, so its own n_d and V_d are exactly the
/// ones given. Then B = (n_d − 1)/V_d / (1/λ_F² − 1/λ_C²) and A = n_d − B/λ_d².
///
/// V_d = 0 means a constant index n_d (Zemax's convention for a model glass).
///
/// # Errors
/// When n_d or V_d is not finite, n_d < 1, or V_d < 0.
pub fn abbe_formula(n_d: f64, v_d: f64) -> Result<DispersionFormula, String> {
    if !n_d.is_finite() || n_d < 1.0 {
        return Err(format!("n_d = {n_d} must be a finite number ≥ 1"));
    }
    if !v_d.is_finite() || v_d < 0.0 {
        return Err(format!("V_d = {v_d} must be a finite number > 0 (or 0 for a constant index)"));
    }
    if v_d == 0.0 {
        return Ok(DispersionFormula::Cauchy { a: n_d, b_um2: 0.0, c_um4: 0.0 });
    }
    let inverse_square_um = |lambda_nm: f64| 1.0 / (lambda_nm * 1e-3 * lambda_nm * 1e-3);
    let b_um2 = (n_d - 1.0) / v_d / (inverse_square_um(LAMBDA_F_NM) - inverse_square_um(LAMBDA_C_NM));
    let a = n_d - b_um2 * inverse_square_um(LAMBDA_D_NM);
    Ok(DispersionFormula::Cauchy { a, b_um2, c_um4: 0.0 })
}

/// The catalogue glass `name` as a [`Medium`] named as the catalogue spells it.
pub fn catalogue_medium(name: &str) -> Option<Medium> {
    catalogue::glass(name)
        .map(|glass| Medium::Glass { name: glass.name().to_owned(), formula: glass.formula().clone() })
}

/// The message for a glass name that is neither in the catalogue nor a glass description.
pub fn unknown_glass_message(name: &str) -> String {
    format!(
        "unknown glass \"{name}\": the catalogue (data/glasses.toml) has {}",
        catalogue::glass_names().join(", ")
    )
}

/// Parses a glass column of a pbrt lens file: a catalogue name, `sellmeier:B1,B2,B3,C1,C2,C3`,
/// `abbe:nd,vd` or `air` (module header).
///
/// # Errors
/// A message naming what is wrong (an unknown name, a number that does not parse, the wrong
/// count of coefficients).
pub fn parse_glass_spec(token: &str) -> Result<Medium, String> {
    let lower = token.to_ascii_lowercase();
    if lower == "air" {
        return Ok(Medium::Air);
    }
    if let Some(list) = lower.strip_prefix("sellmeier:") {
        let numbers = parse_numbers(list, "sellmeier", 6)?;
        let (b, c_um2) = numbers.split_at(3);
        return Ok(Medium::Glass {
            name: token.to_owned(),
            formula: DispersionFormula::Sellmeier { b: b.to_vec(), c_um2: c_um2.to_vec() },
        });
    }
    if let Some(list) = lower.strip_prefix("abbe:") {
        let numbers = parse_numbers(list, "abbe", 2)?;
        let formula = abbe_formula(numbers[0], numbers[1])?;
        if numbers[1] == 0.0 {
            return Err("abbe:nd,vd needs V_d > 0 (for a constant index leave the column out)".to_owned());
        }
        return Ok(Medium::Glass { name: token.to_owned(), formula });
    }
    catalogue_medium(token).ok_or_else(|| {
        format!("{}; or give sellmeier:B1,B2,B3,C1,C2,C3, abbe:nd,vd or air", unknown_glass_message(token))
    })
}

/// `count` comma-separated finite numbers.
fn parse_numbers(list: &str, form: &str, count: usize) -> Result<Vec<f64>, String> {
    let numbers: Vec<f64> = list
        .split(',')
        .map(|field| match field.trim().parse::<f64>() {
            Ok(value) if value.is_finite() => Ok(value),
            _ => Err(format!("{form}: \"{field}\" is not a finite number")),
        })
        .collect::<Result<_, _>>()?;
    if numbers.len() != count {
        return Err(format!("{form}: {} numbers given, {count} expected", numbers.len()));
    }
    Ok(numbers)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_abbe_model_reproduces_the_given_nd_and_vd() {
        // By construction n(λ_d) = n_d and (n_d − 1)/(n_F − n_C) = V_d; only f64 rounding
        // (~1e-16 relative, amplified by the F–C difference ~1e-2) separates them.
        for (n_d, v_d) in [(1.5168, 64.17), (1.78472, 25.68), (1.67, 47.0)] {
            let formula = abbe_formula(n_d, v_d).expect("valid n_d, V_d");
            assert!((formula.n_d() - n_d).abs() < 1e-14, "{n_d}: {}", formula.n_d());
            assert!((formula.abbe_vd() - v_d).abs() < 1e-10 * v_d, "{v_d}: {}", formula.abbe_vd());
        }
    }

    #[test]
    fn the_abbe_model_is_close_to_n_bk7_across_the_visible() {
        // A two-term Cauchy law through N-BK7's n_d and V_d follows its Sellmeier formula to
        // ~1e-3 over 400–700 nm (the missing λ⁻⁴ term; SCHOTT TIE-29 discusses the accuracy of
        // such two-constant models): good enough for a glass known only by n_d and V_d.
        let bk7 = catalogue::glass("N-BK7").expect("N-BK7 is in the catalogue");
        let model = abbe_formula(bk7.n_d(), bk7.abbe_vd()).expect("valid");
        for lambda_nm in [400.0, 486.1327, 550.0, 656.2725, 700.0] {
            let error = (model.n_at_nm(lambda_nm) - bk7.formula().n_at_nm(lambda_nm)).abs();
            assert!(error < 1.5e-3, "{lambda_nm} nm: {error}");
        }
    }

    #[test]
    fn specs_parse_into_media() {
        let Ok(Medium::Glass { name, formula }) = parse_glass_spec("n-bk7") else { panic!("N-BK7") };
        assert_eq!(name, "N-BK7");
        // N-BK7's data sheet n_d, to its 5 decimals.
        assert!((formula.n_d() - 1.5168).abs() < 1e-5);
        assert_eq!(parse_glass_spec("AIR"), Ok(Medium::Air));
        // SCHOTT's N-BK7 Sellmeier coefficients give its n_d = 1.51680 (data sheet, 5 decimals).
        let sellmeier = "sellmeier:1.03961212,0.231792344,1.01046945,0.00600069867,0.0200179144,103.560653";
        let medium = parse_glass_spec(sellmeier).expect("six numbers");
        assert!((medium.n_at_nm(LAMBDA_D_NM) - 1.5168).abs() < 1e-5);
        assert_eq!(medium.name(), sellmeier);
        let abbe = parse_glass_spec("abbe:1.67,47").expect("two numbers");
        assert!((abbe.n_at_nm(LAMBDA_D_NM) - 1.67).abs() < 1e-14);
    }

    #[test]
    fn bad_specs_say_why() {
        let error = |spec: &str| parse_glass_spec(spec).expect_err(spec);
        assert!(error("unobtainium").contains("unknown glass \"unobtainium\""));
        assert!(error("unobtainium").contains("N-BK7"));
        assert!(error("sellmeier:1,2,3").contains("3 numbers given, 6 expected"));
        assert!(error("sellmeier:1,2,3,x,5,6").contains("\"x\" is not a finite number"));
        assert!(error("abbe:1.5,inf").contains("\"inf\" is not a finite number"));
        assert!(error("abbe:0.9,40").contains("n_d = 0.9"));
        assert!(error("abbe:1.5,-3").contains("V_d = -3"));
        assert!(error("abbe:1.5,0").contains("V_d > 0"));
    }
}
