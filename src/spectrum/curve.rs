//! [`Spectrum`]: a spectral quantity defined by scene data, evaluated at any wavelength.
//!
//! A closed set of kinds behind one type (constant, table, RGB reflectance, RGB emission, CIE D65,
//! blackbody), each times a scale factor. The conventions follow Mitsuba 3's spectral mode, so a
//! scene means the same in both renderers:
//!
//! - an RGB reflectance is a Jakob–Hanika sigmoid polynomial ([`super::rgb_upsample`]) whose
//!   colour under D65 is the RGB (Mitsuba's `srgb` spectrum);
//! - an RGB emission is `2·max(rgb) · sigmoid(rgb / (2·max)) · D65`, with D65 normalised to
//!   Y = 1, so RGB (1, 1, 1) emits about D65 at unit luminance and shows as (1, 1, 1)
//!   (Mitsuba 3's scheme for RGB emitters in spectral modes, `srgb_d65`);
//! - named illuminants and blackbodies are normalised to `Y = ∫ L·ȳ dλ / ∫ ȳ dλ = 1`, the
//!   luminance of an equal-energy spectrum of value 1, so their scale is their luminance.
//!
//! Values are dimensionless for reflectances and in the unit of the quantity (e.g. radiance in
//! W·m⁻²·sr⁻¹·nm⁻¹) for emissions; wavelengths are in nm. Construction validates its inputs and
//! does the expensive work (fitting, normalising); [`Spectrum::eval`] is a few arithmetic
//! operations and never allocates.

use std::sync::{Arc, OnceLock};

use glam::Vec3;

use super::cie::xyz_by_quadrature;
use super::rgb_upsample::{d65_white_gains, fit_reflectance, SigmoidPolynomial};
use super::tables::{d65_table, GridPosition};
use super::{SampledSpectrum, SampledWavelengths, LAMBDA_MAX_NM, LAMBDA_MIN_NM};

/// Why a spectrum could not be built from its description.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpectrumError {
    /// A description value is out of range or malformed; the message says which and why.
    #[error("{0}")]
    Invalid(String),
}

/// Names accepted by [`Spectrum::named_illuminant`].
pub const NAMED_ILLUMINANTS: [&str; 2] = ["D65", "E"];

/// Second radiation constant c₂ = h·c/k_B in nm·K (CODATA 2018, exact in the 2019 SI):
/// 1.438776877e-2 m·K.
const SECOND_RADIATION_CONSTANT_NM_K: f64 = 1.438_776_877e7;
/// Wien's displacement constant b in nm·K (CODATA 2018): Planck's law in wavelength peaks at
/// λ = b / T.
const WIEN_DISPLACEMENT_NM_K: f64 = 2.897_771_955e6;

/// What a [`Spectrum`] is, before its scale.
#[derive(Debug, Clone, PartialEq)]
enum Kind {
    /// 1 at every wavelength.
    Constant,
    /// Piecewise-linear through (λ nm, value) points with strictly increasing λ, constant beyond.
    Table(Arc<[(f32, f32)]>),
    /// A Jakob–Hanika sigmoid-polynomial reflectance.
    Sigmoid(SigmoidPolynomial),
    /// A sigmoid polynomial times D65 normalised to Y = 1: an RGB emission.
    SigmoidTimesD65(SigmoidPolynomial),
    /// CIE D65 normalised to Y = 1.
    D65,
    /// Planck's law at `temperature_k`, divided by its value at `reference_nm` (its maximum over
    /// 360–830 nm, so no value overflows) and multiplied by `exp(log_norm)` (Y = 1).
    Blackbody { temperature_k: f64, reference_nm: f64, log_norm: f64 },
}

/// A spectral quantity (reflectance, radiance, intensity, absorption...) as a function of
/// wavelength in nm. Evaluation never allocates.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    kind: Kind,
    scale: f32,
}

/// Luminance Y of the tabulated D65 (relative units, 100 at 560 nm) under prisma's normalisation.
fn d65_table_luminance() -> f32 {
    static LUMINANCE: OnceLock<f32> = OnceLock::new();
    *LUMINANCE.get_or_init(|| xyz_by_quadrature(d65_relative).y)
}

/// The tabulated D65 (100 at 560 nm) at `lambda_nm`, linearly interpolated, held constant beyond
/// 360–830 nm; NaN for a NaN wavelength.
fn d65_relative(lambda_nm: f32) -> f32 {
    if lambda_nm.is_nan() {
        return f32::NAN;
    }
    GridPosition::of(lambda_nm).lerp(d65_table())
}

/// D65 normalised to Y = 1.
fn d65_normalised(lambda_nm: f32) -> f32 {
    d65_relative(lambda_nm) / d65_table_luminance()
}

/// `ln(B(λ, T) / B(λ_ref, T))` for Planck's law `B ∝ λ⁻⁵ / (exp(c₂/(λT)) − 1)`, written so that it
/// stays accurate for any positive temperature: the exponent difference is formed directly, and
/// `ln(exp(x) − 1) = x + ln(1 − exp(−x))` with the second term from `ln_1p`/`exp_m1`.
fn planck_log_ratio(lambda_nm: f64, reference_nm: f64, temperature_k: f64) -> f64 {
    let c2_over_t = SECOND_RADIATION_CONSTANT_NM_K / temperature_k;
    let log_one_minus_exp_neg = |x: f64| {
        if x > std::f64::consts::LN_2 {
            (-(-x).exp()).ln_1p()
        } else {
            (-(-x).exp_m1()).ln()
        }
    };
    let x = c2_over_t / lambda_nm;
    let x_reference = c2_over_t / reference_nm;
    -5.0 * (lambda_nm / reference_nm).ln()
        - c2_over_t * (reference_nm - lambda_nm) / (lambda_nm * reference_nm)
        - (log_one_minus_exp_neg(x) - log_one_minus_exp_neg(x_reference))
}

/// Name of RGB component `index` for messages.
fn channel_name(index: usize) -> &'static str {
    ["red", "green", "blue"][index]
}

impl Spectrum {
    /// The same `value` at every wavelength. (A non-finite value is not rejected here: the scene
    /// builder validates numbers it reads.)
    pub fn constant(value: f32) -> Self {
        Self { kind: Kind::Constant, scale: value }
    }
    /// Piecewise-linear through `(lambda_nm, value)` points, strictly increasing in λ, values finite;
    /// held constant beyond the end points.
    pub fn table(points: &[(f32, f32)]) -> Result<Self, SpectrumError> {
        if points.is_empty() {
            return Err(SpectrumError::Invalid(
                "a spectrum table needs at least one (wavelength_nm, value) point".into(),
            ));
        }
        for (index, &(lambda_nm, value)) in points.iter().enumerate() {
            if !lambda_nm.is_finite() {
                return Err(SpectrumError::Invalid(format!(
                    "spectrum table point {index}: wavelength {lambda_nm} nm is not finite"
                )));
            }
            if !value.is_finite() {
                return Err(SpectrumError::Invalid(format!(
                    "spectrum table point {index} ({lambda_nm} nm): value {value} is not finite"
                )));
            }
            if index > 0 && lambda_nm <= points[index - 1].0 {
                return Err(SpectrumError::Invalid(format!(
                    "spectrum table point {index}: wavelength {lambda_nm} nm does not exceed the \
                     previous {} nm (wavelengths must strictly increase)",
                    points[index - 1].0
                )));
            }
        }
        Ok(Self { kind: Kind::Table(points.into()), scale: 1.0 })
    }
    /// A smooth reflectance spectrum whose colour (under D65) is the linear sRGB `rgb`, each
    /// component in [0, 1].
    ///
    /// Equal components give a constant; otherwise the Jakob–Hanika sigmoid polynomial is fitted
    /// now (tens of µs). Every colour of the [0, 1]³ cube is reproduced within 1e-4 (see the
    /// tests of [`super::rgb_upsample`]).
    pub fn rgb_reflectance(rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        for (index, &component) in rgb.iter().enumerate() {
            if !(0.0..=1.0).contains(&component) {
                return Err(SpectrumError::Invalid(format!(
                    "rgb reflectance {} component {component} is outside [0, 1]",
                    channel_name(index)
                )));
            }
        }
        if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
            return Ok(Self::constant(rgb[0]));
        }
        let fit = fit_reflectance(Vec3::from_array(rgb));
        Ok(Self { kind: Kind::Sigmoid(fit.polynomial), scale: 1.0 })
    }
    /// An emission spectrum whose colour is the linear sRGB `rgb` (components ≥ 0): a smooth
    /// spectrum times D65 normalised to Y = 1, so (1, 1, 1) appears as (1, 1, 1).
    ///
    /// With `m = max(rgb)`: zero if `m = 0`, else `2m · s(λ) · D65(λ)` where the reflectance `s`
    /// is fitted to `rgb / 2m` (corrected by the ~1e-4 offset of the tabulated D65 from the
    /// sRGB white), so the XYZ of the result converts back to `rgb`. Components may exceed 1.
    pub fn rgb_illuminant(rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        for (index, &component) in rgb.iter().enumerate() {
            if !(component.is_finite() && component >= 0.0) {
                return Err(SpectrumError::Invalid(format!(
                    "rgb illuminant {} component {component} must be finite and ≥ 0",
                    channel_name(index)
                )));
            }
        }
        let max_component = rgb[0].max(rgb[1]).max(rgb[2]);
        if max_component == 0.0 {
            return Ok(Self::constant(0.0));
        }
        // Fitting at half the maximum keeps the reflectance away from 1, where the sigmoid
        // saturates; the scale carries the brightness (Mitsuba's scheme).
        let scale = 2.0 * max_component;
        let target = Vec3::from_array(rgb) / (scale * d65_white_gains());
        let fit = fit_reflectance(target);
        Ok(Self { kind: Kind::SigmoidTimesD65(fit.polynomial), scale })
    }
    /// A named CIE illuminant normalised to Y = 1: `"D65"` or `"E"` (equal energy).
    pub fn named_illuminant(name: &str) -> Result<Self, SpectrumError> {
        match name {
            "D65" => {
                // Parse and normalise now, not on the first evaluation during rendering.
                d65_table_luminance();
                Ok(Self { kind: Kind::D65, scale: 1.0 })
            }
            // ∫ 1·ȳ dλ / ∫ ȳ dλ = 1: the constant 1 is already normalised.
            "E" => Ok(Self::constant(1.0)),
            _ => Err(SpectrumError::Invalid(format!(
                "unknown illuminant {name:?}; known illuminants: {}",
                NAMED_ILLUMINANTS.join(", ")
            ))),
        }
    }
    /// Planck's law for `temperature_k` kelvin, normalised so that Y = 1.
    ///
    /// Uses c₂ = 1.438776877e-2 m·K (CODATA 2018). Accurate for any finite positive temperature
    /// (cold ones are a narrow rise at 830 nm, hot ones approach λ⁻⁴).
    pub fn blackbody(temperature_k: f32) -> Result<Self, SpectrumError> {
        if !(temperature_k.is_finite() && temperature_k > 0.0) {
            return Err(SpectrumError::Invalid(format!(
                "blackbody temperature {temperature_k} K must be finite and > 0"
            )));
        }
        let temperature_k = f64::from(temperature_k);
        // Planck's law is unimodal: clamping its peak to the range gives its maximum there.
        let reference_nm = (WIEN_DISPLACEMENT_NM_K / temperature_k)
            .clamp(f64::from(LAMBDA_MIN_NM), f64::from(LAMBDA_MAX_NM));
        let luminance = xyz_by_quadrature(|lambda_nm| {
            planck_log_ratio(f64::from(lambda_nm), reference_nm, temperature_k).exp() as f32
        })
        .y;
        Ok(Self {
            kind: Kind::Blackbody { temperature_k, reference_nm, log_norm: -f64::from(luminance).ln() },
            scale: 1.0,
        })
    }
    /// This spectrum times `factor`.
    pub fn scaled(mut self, factor: f32) -> Self {
        self.scale *= factor;
        self
    }
    /// Value at `lambda_nm`.
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        debug_assert!(lambda_nm.is_finite(), "wavelength {lambda_nm} nm");
        let unscaled = match &self.kind {
            Kind::Constant => 1.0,
            Kind::Table(points) => eval_table(points, lambda_nm),
            Kind::Sigmoid(polynomial) => polynomial.eval(lambda_nm),
            Kind::SigmoidTimesD65(polynomial) => polynomial.eval(lambda_nm) * d65_normalised(lambda_nm),
            Kind::D65 => d65_normalised(lambda_nm),
            Kind::Blackbody { temperature_k, reference_nm, log_norm } => (log_norm
                + planck_log_ratio(f64::from(lambda_nm), *reference_nm, *temperature_k))
            .exp() as f32,
        };
        self.scale * unscaled
    }
    /// Values at every lane of `wavelengths` (inactive lanes may hold anything finite).
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum { values: std::array::from_fn(|i| self.eval(wavelengths.lambda_nm(i))) }
    }
    /// True when the value is the same at every wavelength.
    pub fn is_constant(&self) -> bool {
        self.scale == 0.0
            || match &self.kind {
                Kind::Constant => true,
                Kind::Table(points) => points.iter().all(|&(_, value)| value == points[0].1),
                Kind::Sigmoid(polynomial) => polynomial.is_constant(),
                Kind::SigmoidTimesD65(_) | Kind::D65 | Kind::Blackbody { .. } => false,
            }
    }
}

/// Piecewise-linear interpolation through `points` (validated: non-empty, strictly increasing),
/// constant beyond the end points.
fn eval_table(points: &[(f32, f32)], lambda_nm: f32) -> f32 {
    let upper = points.partition_point(|&(point_nm, _)| point_nm <= lambda_nm);
    if upper == 0 {
        return points[0].1;
    }
    if upper == points.len() {
        return points[upper - 1].1;
    }
    let (lambda0, value0) = points[upper - 1];
    let (lambda1, value1) = points[upper];
    value0 + (value1 - value0) * ((lambda_nm - lambda0) / (lambda1 - lambda0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::cie::chromaticity;
    use crate::spectrum::color::xyz_to_linear_srgb;
    use crate::spectrum::rgb_upsample::reflectance_linear_srgb;
    use crate::spectrum::N_LAMBDA;

    /// XYZ of `spectrum` as an emission, by quadrature.
    fn xyz(spectrum: &Spectrum) -> Vec3 {
        xyz_by_quadrature(|lambda_nm| spectrum.eval(lambda_nm))
    }

    fn message(result: Result<Spectrum, SpectrumError>) -> String {
        match result {
            Err(SpectrumError::Invalid(message)) => message,
            Ok(spectrum) => panic!("expected an error, got {spectrum:?}"),
        }
    }

    fn assert_close(actual: f32, expected: f32, tolerance: f32, what: &str) {
        assert!(
            (actual - expected).abs() <= tolerance,
            "{what}: {actual}, expected {expected} ± {tolerance}"
        );
    }

    /// A constant is flat and scales linearly; zero is constant whatever its kind.
    #[test]
    fn constant_and_scale() {
        let spectrum = Spectrum::constant(0.25);
        assert!(spectrum.is_constant());
        assert_eq!(spectrum.eval(400.0), 0.25);
        assert_eq!(spectrum.clone().scaled(4.0).eval(700.0), 1.0);
        let wavelengths = SampledWavelengths::sample_visible(0.3, 4);
        assert_eq!(spectrum.sample(&wavelengths).values, [0.25; N_LAMBDA]);
        let d65 = Spectrum::named_illuminant("D65").expect("D65 is known");
        assert!(!d65.is_constant());
        assert!(d65.scaled(0.0).is_constant());
    }

    /// A table interpolates linearly between its points and holds its end values beyond them.
    #[test]
    fn table_interpolates_and_extrapolates_constantly() {
        let spectrum = Spectrum::table(&[(400.0, 1.0), (500.0, 3.0), (600.0, 2.0)]).expect("valid table");
        assert_eq!(spectrum.eval(450.0), 2.0);
        assert_eq!(spectrum.eval(500.0), 3.0);
        assert_eq!(spectrum.eval(575.0), 2.25);
        assert_eq!(spectrum.eval(300.0), 1.0);
        assert_eq!(spectrum.eval(900.0), 2.0);
        assert!(!spectrum.is_constant());
        let single = Spectrum::table(&[(550.0, 0.7)]).expect("one point is enough");
        assert_eq!(single.eval(380.0), 0.7);
        assert!(single.is_constant());
    }

    /// Invalid tables are rejected with a message naming the offending point and value.
    #[test]
    fn table_errors_name_the_offending_point() {
        assert!(message(Spectrum::table(&[])).contains("at least one"));
        let m = message(Spectrum::table(&[(400.0, 1.0), (500.0, f32::NAN)]));
        assert!(m.contains("point 1") && m.contains("NaN"), "{m}");
        let m = message(Spectrum::table(&[(f32::INFINITY, 1.0)]));
        assert!(m.contains("point 0") && m.contains("inf"), "{m}");
        let m = message(Spectrum::table(&[(400.0, 1.0), (500.0, 1.0), (500.0, 2.0)]));
        assert!(m.contains("point 2") && m.contains("500 nm") && m.contains("strictly increase"), "{m}");
    }

    /// An RGB reflectance reproduces its colour under D65, both through the fit's own colour
    /// functional (within 1e-5) and through independent colorimetry (XYZ of reflectance × D65
    /// converted to sRGB, within 1e-3: the two differ only by the ~1e-4 D65 table offset).
    #[test]
    fn rgb_reflectance_round_trips() {
        let rgb = [0.2, 0.5, 0.9];
        let spectrum = Spectrum::rgb_reflectance(rgb).expect("in range");
        assert!(!spectrum.is_constant());
        let target = Vec3::from_array(rgb);
        let own = reflectance_linear_srgb(|lambda_nm| spectrum.eval(lambda_nm));
        assert!((own - target).abs().max_element() < 1e-5, "{own}");
        let d65 = Spectrum::named_illuminant("D65").expect("D65 is known");
        let lit = xyz_to_linear_srgb(xyz_by_quadrature(|l| spectrum.eval(l) * d65.eval(l)));
        assert!((lit - target).abs().max_element() < 1e-3, "{lit}");
        let grey = Spectrum::rgb_reflectance([0.4; 3]).expect("in range");
        assert!(grey.is_constant());
        assert_eq!(grey.eval(612.0), 0.4);
    }

    /// Reflectance components outside [0, 1] (or NaN) are errors naming the channel and value.
    #[test]
    fn rgb_reflectance_rejects_out_of_range_components() {
        let m = message(Spectrum::rgb_reflectance([0.5, 1.2, 0.5]));
        assert!(m.contains("green") && m.contains("1.2") && m.contains("[0, 1]"), "{m}");
        assert!(message(Spectrum::rgb_reflectance([-0.1, 0.5, 0.5])).contains("red"));
        assert!(message(Spectrum::rgb_reflectance([0.5, 0.5, f32::NAN])).contains("blue"));
    }

    /// The defining property of an RGB emission: its XYZ, converted to linear sRGB, is the RGB it
    /// was made from; white (1, 1, 1) is D65-like at unit luminance; HDR values work; black is 0.
    #[test]
    fn rgb_illuminant_round_trips() {
        for rgb in [[1.0, 1.0, 1.0], [0.2, 0.5, 0.9], [4.0, 2.0, 0.5], [0.0, 0.0, 3.0]] {
            let spectrum = Spectrum::rgb_illuminant(rgb).expect("valid emission");
            let back = xyz_to_linear_srgb(xyz(&spectrum));
            let target = Vec3::from_array(rgb);
            // Measured ≤ 2e-7 relative; the bound leaves room for f32 rounding only.
            let tolerance = 1e-4 * target.max_element();
            assert!((back - target).abs().max_element() < tolerance, "{target} → {back}");
        }
        let white = Spectrum::rgb_illuminant([1.0; 3]).expect("valid emission");
        assert_close(xyz(&white).y, 1.0, 1e-4, "Y of RGB white emission");
        let black = Spectrum::rgb_illuminant([0.0; 3]).expect("valid emission");
        assert!(black.is_constant());
        assert_eq!(black.eval(500.0), 0.0);
        let m = message(Spectrum::rgb_illuminant([0.5, -1.0, 0.5]));
        assert!(m.contains("green") && m.contains("-1"), "{m}");
        assert!(message(Spectrum::rgb_illuminant([f32::INFINITY, 0.0, 0.0])).contains("red"));
    }

    /// D65 normalised has Y = 1 and the chromaticity of the tabulated D65, (0.31272, 0.32903)
    /// (CIE 15:2004 Table T.3); E has Y = 1 and (1/3, 1/3). Unknown names list the known ones.
    #[test]
    fn named_illuminants_are_normalised() {
        let d65 = Spectrum::named_illuminant("D65").expect("D65 is known");
        let d65_xyz = xyz(&d65);
        assert_close(d65_xyz.y, 1.0, 1e-5, "Y of D65");
        let [x, y] = chromaticity(d65_xyz);
        assert_close(x, 0.31272, 1e-3, "D65 x");
        assert_close(y, 0.32903, 1e-3, "D65 y");
        // Constant extrapolation: the value at 830 nm is held beyond.
        assert_eq!(d65.eval(900.0), d65.eval(830.0));
        let e = Spectrum::named_illuminant("E").expect("E is known");
        assert!(e.is_constant());
        assert_close(xyz(&e).y, 1.0, 1e-5, "Y of E");
        let m = message(Spectrum::named_illuminant("F2"));
        assert!(m.contains("\"F2\"") && m.contains("D65, E"), "{m}");
    }

    /// A blackbody at 2856 K is CIE illuminant A, whose chromaticity is (0.44757, 0.40745)
    /// (CIE 15:2004 Table T.3; A was defined with c₂ = 1.435e-2 m·K rather than today's
    /// 1.4388e-2, which moves it by ~1e-4: measured (0.44754, 0.40743)); at 6504 K (D65's
    /// correlated colour temperature) it is (0.3135, 0.3236), 0.005 below D65 in y (daylight lies
    /// a little above the Planckian locus). Both have Y = 1. Tolerance 5e-4: the references have
    /// 4–5 digits.
    #[test]
    fn blackbody_chromaticities_match_published_values() {
        for (temperature_k, expected_x, expected_y) in [(2856.0, 0.44757, 0.40745), (6504.0, 0.3135, 0.3236)]
        {
            let spectrum = Spectrum::blackbody(temperature_k).expect("valid temperature");
            let blackbody_xyz = xyz(&spectrum);
            assert_close(blackbody_xyz.y, 1.0, 1e-5, "Y of blackbody");
            let [x, y] = chromaticity(blackbody_xyz);
            assert_close(x, expected_x, 5e-4, &format!("x at {temperature_k} K"));
            assert_close(y, expected_y, 5e-4, &format!("y at {temperature_k} K"));
        }
    }

    /// Planck's law in wavelength peaks at Wien's λ = 2.897771955e6 nm·K / T (579.55 nm at
    /// 5000 K), and the ratio of two values is the closed form (λ₂/λ₁)⁵ (e^{c₂/λ₂T} − 1) /
    /// (e^{c₂/λ₁T} − 1), computed here directly in f64.
    #[test]
    fn blackbody_follows_plancks_law() {
        let spectrum = Spectrum::blackbody(5000.0).expect("valid temperature");
        let peak = spectrum.eval(579.55);
        assert!(peak > spectrum.eval(578.0) && peak > spectrum.eval(581.0));
        let planck = |lambda_nm: f64| {
            lambda_nm.powi(-5) / ((SECOND_RADIATION_CONSTANT_NM_K / (lambda_nm * 5000.0)).exp() - 1.0)
        };
        let expected_ratio = (planck(450.0) / planck(700.0)) as f32;
        assert_close(
            spectrum.eval(450.0) / spectrum.eval(700.0),
            expected_ratio,
            1e-5 * expected_ratio,
            "ratio",
        );
    }

    /// Extreme temperatures stay finite and normalised; invalid ones are errors.
    #[test]
    fn blackbody_handles_extreme_and_invalid_temperatures() {
        for temperature_k in [1.0, 100.0, 1e6, 1e9] {
            let spectrum = Spectrum::blackbody(temperature_k).expect("valid temperature");
            assert!((360..=830).all(|l| spectrum.eval(l as f32).is_finite()), "{temperature_k} K");
            assert_close(xyz(&spectrum).y, 1.0, 1e-4, &format!("Y at {temperature_k} K"));
        }
        for temperature_k in [0.0, -300.0, f32::NAN, f32::INFINITY] {
            let m = message(Spectrum::blackbody(temperature_k));
            assert!(m.contains("finite and > 0"), "{m}");
        }
    }
}
