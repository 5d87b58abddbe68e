//! RGB → smooth spectrum upsampling: W. Jakob and J. Hanika, "A Low-Dimensional Function Space
//! for Efficient Spectral Upsampling", Computer Graphics Forum 38(2), 2019 (Eurographics).
//!
//! A reflectance is `s(λ) = S(c0·x² + c1·x + c2)` with the sigmoid `S(z) = 1/2 + z / (2√(1 + z²))`,
//! which maps any quadratic into (0, 1): the spectra are smooth, bounded and energy-conserving.
//! Unlike the paper (and Mitsuba 3 / pbrt-v4), which precompute a 3D coefficient table offline,
//! prisma fits the three coefficients per colour when a scene is built, by Levenberg–Marquardt on
//! the CIELAB difference (paper §4) between the target and the colour of `s` under D65:
//!
//! - the quadratic is in the normalised wavelength `x = (λ − 595 nm) / 235 nm ∈ [−1, 1]` rather
//!   than in nm, so the three coefficients have comparable scale and the normal equations are
//!   well conditioned;
//! - the colour of `s` is `M⁻¹·∫ s·D65·cmf dλ / ∫ D65·ȳ dλ` (1 nm trapezoid quadrature) followed by
//!   a per-channel gain that makes `s ≡ 1` exactly white (1, 1, 1): the tabulated D65 is a hair
//!   (~1e-4) off the rounded sRGB white point (0.3127, 0.3290);
//! - CIELAB is taken relative to that white; the Jacobian is analytic;
//! - the start is the grey of the target's luminance. From there LM converges for every colour
//!   of the [0, 1]³ cube (measured on a 41³ grid and 200 000 random colours biased to the faces),
//!   so the paper's continuation across a table is not needed for one colour at a time.
//!
//! Edges: grey targets (all components equal, including black and white) are solved in closed
//! form as constant spectra. The sRGB primaries and secondaries are reachable (residual < 1e-4
//! ΔE). Targets no reflectance in [0, 1] produces (outside the cube) are fitted best-effort and
//! carry their CIELAB residual. Scene colours reach this module through
//! `Spectrum::rgb_reflectance` and `Spectrum::rgb_illuminant`.

use std::sync::OnceLock;

use glam::Vec3;

use super::color::{inverse_3x3, rgb_to_xyz_rows};
use super::tables::{cmf_table, d65_table, grid_lambda_nm, trapezoid_weight_nm, GRID_LEN};

/// Centre of the normalised wavelength used by the quadratic, in nm (middle of 360–830 nm).
const NORMALISED_CENTRE_NM: f32 = 595.0;
/// Half-width of the normalised wavelength range, in nm: x = ±1 at 360 and 830 nm.
const NORMALISED_HALF_WIDTH_NM: f32 = 235.0;

/// Fit stops when the CIELAB residual ‖ΔLab‖ falls below this: 1e-5 ΔE is at most 2.6e-7 in Y
/// (dL*/dY ≥ 38.7, its value at Y = 1), far below any visible or measurable difference.
const CONVERGED_DELTA_E: f64 = 1e-5;
/// Residual evaluations (≈ 5 µs each) per fit. Most colours converge in under 10; the cap bounds
/// the time spent on the darkest saturated ones (components ~1e-5), whose residual then creeps
/// down slowly while already below 1e-3 ΔE, and on unreachable targets.
const MAX_EVALUATIONS: usize = 200;
/// Coefficient magnitude bound: |c| = 1e4 already gives a sigmoid edge ~1e-4 of the range wide
/// (< 0.05 nm), a box spectrum for all purposes; beyond it the colour cannot change.
const MAX_COEFFICIENT: f64 = 1e4;

/// The Jakob–Hanika sigmoid `S(z) = 1/2 + z / (2√(1 + z²))`, in [0, 1] (open interval
/// mathematically; f32 rounds to 1 beyond z ≈ 3000); S(−∞) = 0 and S(+∞) = 1.
#[inline]
pub fn sigmoid(z: f32) -> f32 {
    // S(−|z|) = 1 / (2√(1+z²)(√(1+z²) + |z|)) has no cancellation, unlike 1/2 − |z|/(2√(1+z²)),
    // so dark reflectances keep their relative precision; it is also exact at ±∞.
    let root = (1.0 + z * z).sqrt();
    let lower_tail = 0.5 / (root * (root + z.abs()));
    if z >= 0.0 {
        1.0 - lower_tail
    } else {
        lower_tail
    }
}

/// [`sigmoid`] and its derivative `S'(z) = 1 / (2 (1 + z²)^(3/2))`, in f64 for the fit.
#[inline]
fn sigmoid_and_slope_f64(z: f64) -> (f64, f64) {
    let one_plus_z2 = 1.0 + z * z;
    let root = one_plus_z2.sqrt();
    let lower_tail = 0.5 / (root * (root + z.abs()));
    let value = if z >= 0.0 { 1.0 - lower_tail } else { lower_tail };
    (value, 0.5 / (one_plus_z2 * root))
}

/// The wavelength `lambda_nm` mapped to [−1, 1] over 360–830 nm.
#[inline]
fn normalised_wavelength(lambda_nm: f32) -> f32 {
    (lambda_nm - NORMALISED_CENTRE_NM) / NORMALISED_HALF_WIDTH_NM
}

/// `s(λ) = S(c0·x² + c1·x + c2)` with `x = (λ − 595 nm) / 235 nm`: a smooth reflectance in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SigmoidPolynomial {
    /// (c0, c1, c2), coefficients of x², x and 1 in the normalised wavelength x.
    coefficients: [f32; 3],
}

impl SigmoidPolynomial {
    /// The constant reflectance `value` in [0, 1] (0 and 1 use an infinite c2, which
    /// [`sigmoid`] maps to exactly 0 and 1).
    pub fn constant(value: f32) -> Self {
        debug_assert!((0.0..=1.0).contains(&value), "constant reflectance {value}");
        // Inverse of S: z = (2v − 1) / (2√(v(1 − v))).
        let c2 = (2.0 * value - 1.0) / (2.0 * (value * (1.0 - value)).sqrt());
        Self { coefficients: [0.0, 0.0, c2] }
    }
    /// The coefficients (c0, c1, c2) of x², x and 1, with x = (λ − 595 nm) / 235 nm.
    pub fn coefficients(&self) -> [f32; 3] {
        self.coefficients
    }
    /// The reflectance at `lambda_nm`, in [0, 1].
    #[inline]
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        let x = normalised_wavelength(lambda_nm);
        let [c0, c1, c2] = self.coefficients;
        sigmoid((c0 * x + c1) * x + c2)
    }
    /// True when the quadratic is constant, hence the reflectance too.
    pub fn is_constant(&self) -> bool {
        self.coefficients[0] == 0.0 && self.coefficients[1] == 0.0
    }
}

/// The outcome of [`fit_reflectance`]: the spectrum and how well it reproduces the target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SigmoidFit {
    /// The fitted reflectance.
    pub polynomial: SigmoidPolynomial,
    /// CIELAB distance (ΔE*ab 1976, white = RGB (1, 1, 1)) between the target and the fitted
    /// spectrum's colour under D65, for the stored f32 coefficients: below 2e-4 everywhere in
    /// the [0, 1]³ cube (measured), ≳ 1 for targets no reflectance in [0, 1] produces.
    pub residual_delta_e: f32,
}

/// Precomputed quadrature for the fit: per grid point, the normalised wavelength and the XYZ
/// that a reflectance of 1 there contributes under D65 (including the white-balancing gain).
struct FitTables {
    x: Vec<f64>,
    weights_xyz: Vec<[f64; 3]>,
    /// Linear sRGB of `s ≡ 1` under the tabulated D65 before the gain; ≈ (1, 1, 1).
    white_gains: [f64; 3],
    rgb_to_xyz: [[f64; 3]; 3],
    xyz_to_rgb: [[f64; 3]; 3],
    /// XYZ of RGB (1, 1, 1): the CIELAB reference white.
    white_xyz: [f64; 3],
}

fn mat_vec(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

fn fit_tables() -> &'static FitTables {
    static TABLES: OnceLock<FitTables> = OnceLock::new();
    TABLES.get_or_init(|| {
        let cmf = cmf_table();
        let d65 = d65_table();
        let rgb_to_xyz = rgb_to_xyz_rows();
        let xyz_to_rgb = inverse_3x3(rgb_to_xyz);
        let d65_y: f64 =
            (0..GRID_LEN).map(|i| trapezoid_weight_nm(i) * d65[i] as f64 * cmf[i].y as f64).sum();
        let raw: Vec<[f64; 3]> = (0..GRID_LEN)
            .map(|i| {
                let weight = trapezoid_weight_nm(i) * d65[i] as f64 / d65_y;
                [cmf[i].x as f64 * weight, cmf[i].y as f64 * weight, cmf[i].z as f64 * weight]
            })
            .collect();
        let raw_white_xyz = raw.iter().fold([0.0; 3], |acc, w| [acc[0] + w[0], acc[1] + w[1], acc[2] + w[2]]);
        let white_gains = mat_vec(&xyz_to_rgb, raw_white_xyz);
        // weights = M · diag(1/gains) · M⁻¹ · raw, so that Σ weights = M · (1, 1, 1).
        let weights_xyz = raw
            .iter()
            .map(|&w| {
                let rgb = mat_vec(&xyz_to_rgb, w);
                mat_vec(&rgb_to_xyz, std::array::from_fn(|c| rgb[c] / white_gains[c]))
            })
            .collect();
        FitTables {
            x: (0..GRID_LEN).map(|i| normalised_wavelength(grid_lambda_nm(i)) as f64).collect(),
            weights_xyz,
            white_gains,
            rgb_to_xyz,
            xyz_to_rgb,
            white_xyz: mat_vec(&rgb_to_xyz, [1.0; 3]),
        }
    })
}

/// Linear sRGB of the tabulated D65 (normalised to Y = 1) before the white-balancing gain,
/// ≈ (1, 1, 1) within ~1e-4: an emission `S·D65` shows the fit colour times these gains.
pub(crate) fn d65_white_gains() -> Vec3 {
    let gains = fit_tables().white_gains;
    Vec3::new(gains[0] as f32, gains[1] as f32, gains[2] as f32)
}

/// Linear sRGB colour under D65 of the reflectance `reflectance(λ)` (λ in nm): the colour the fit
/// matches, with `s ≡ 1` exactly (1, 1, 1). Same 1 nm quadrature as the fit.
pub fn reflectance_linear_srgb(reflectance: impl Fn(f32) -> f32) -> Vec3 {
    let tables = fit_tables();
    let mut xyz = [0.0_f64; 3];
    for (i, weight) in tables.weights_xyz.iter().enumerate() {
        let value = reflectance(grid_lambda_nm(i)) as f64;
        for c in 0..3 {
            xyz[c] += value * weight[c];
        }
    }
    let rgb = mat_vec(&tables.xyz_to_rgb, xyz);
    Vec3::new(rgb[0] as f32, rgb[1] as f32, rgb[2] as f32)
}

/// CIELAB's companding function f(t) and its derivative (CIE 15:2004 §8.2.1), with the linear
/// segment below (6/29)³ so it is defined (and smooth) for every real t, negative included.
fn lab_f_and_slope(t: f64) -> (f64, f64) {
    const DELTA: f64 = 6.0 / 29.0;
    if t > DELTA * DELTA * DELTA {
        let cbrt = t.cbrt();
        (cbrt, 1.0 / (3.0 * cbrt * cbrt))
    } else {
        let slope = 1.0 / (3.0 * DELTA * DELTA);
        (t * slope + 4.0 / 29.0, slope)
    }
}

/// CIELAB of `xyz` relative to `white_xyz`, and ∂Lab/∂XYZ (row-major).
fn lab_and_jacobian(xyz: [f64; 3], white_xyz: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let (fx, dfx) = lab_f_and_slope(xyz[0] / white_xyz[0]);
    let (fy, dfy) = lab_f_and_slope(xyz[1] / white_xyz[1]);
    let (fz, dfz) = lab_f_and_slope(xyz[2] / white_xyz[2]);
    let (dx, dy, dz) = (dfx / white_xyz[0], dfy / white_xyz[1], dfz / white_xyz[2]);
    (
        [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)],
        [[0.0, 116.0 * dy, 0.0], [500.0 * dx, -500.0 * dy, 0.0], [0.0, 200.0 * dy, -200.0 * dz]],
    )
}

/// The residual Lab(s_c) − Lab(target) of coefficients `c` and its Jacobian ∂residual/∂c.
fn residual_and_jacobian(
    tables: &FitTables,
    coefficients: [f64; 3],
    target_lab: [f64; 3],
) -> ([f64; 3], [[f64; 3]; 3]) {
    let [c0, c1, c2] = coefficients;
    let mut xyz = [0.0; 3];
    // ∂XYZ/∂c, row-major: row = X/Y/Z, column = c0/c1/c2.
    let mut xyz_jacobian = [[0.0; 3]; 3];
    for (&x, weight) in tables.x.iter().zip(&tables.weights_xyz) {
        let (value, slope) = sigmoid_and_slope_f64((c0 * x + c1) * x + c2);
        let basis = [x * x, x, 1.0];
        for row in 0..3 {
            xyz[row] += value * weight[row];
            let scaled = slope * weight[row];
            for column in 0..3 {
                xyz_jacobian[row][column] += scaled * basis[column];
            }
        }
    }
    let (lab, lab_per_xyz) = lab_and_jacobian(xyz, tables.white_xyz);
    let residual = std::array::from_fn(|k| lab[k] - target_lab[k]);
    let jacobian = std::array::from_fn(|r| {
        std::array::from_fn(|c| (0..3).map(|k| lab_per_xyz[r][k] * xyz_jacobian[k][c]).sum())
    });
    (residual, jacobian)
}

fn norm_squared(v: [f64; 3]) -> f64 {
    v.iter().map(|x| x * x).sum()
}

/// Solves the 3×3 system `a·x = b` by Cramer's rule; `None` when (nearly) singular.
fn solve_3x3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let det_a = det(a);
    let scale = a.iter().flatten().fold(0.0_f64, |acc, v| acc.max(v.abs()));
    // Relative threshold: a determinant this small against the entries' scale means the damped
    // system is numerically singular and the LM loop should damp harder.
    if det_a.is_nan() || det_a.abs() <= 1e-300_f64.max(1e-14 * scale * scale * scale) {
        return None;
    }
    Some(std::array::from_fn(|column| {
        let mut replaced = a;
        for row in 0..3 {
            replaced[row][column] = b[row];
        }
        det(replaced) / det_a
    }))
}

/// Levenberg–Marquardt (Marquardt's diagonal scaling) from `start` towards `target_lab`, until
/// the residual is below [`CONVERGED_DELTA_E`] or [`MAX_EVALUATIONS`] are spent; returns the
/// final coefficients and residual norm (ΔE).
fn levenberg_marquardt(tables: &FitTables, start: [f64; 3], target_lab: [f64; 3]) -> ([f64; 3], f64) {
    let mut coefficients = start;
    let (mut residual, mut jacobian) = residual_and_jacobian(tables, coefficients, target_lab);
    let mut cost = norm_squared(residual);
    let mut damping = 1e-4;
    let mut evaluations = 1;
    // Damping this large means the gradient vanishes here: a (local) minimum.
    while cost.sqrt() >= CONVERGED_DELTA_E && evaluations < MAX_EVALUATIONS && damping < 1e12 {
        let normal: [[f64; 3]; 3] = std::array::from_fn(|r| {
            std::array::from_fn(|c| (0..3).map(|k| jacobian[k][r] * jacobian[k][c]).sum())
        });
        let descent: [f64; 3] =
            std::array::from_fn(|r| -(0..3).map(|k| jacobian[k][r] * residual[k]).sum::<f64>());
        let mut damped = normal;
        for d in 0..3 {
            // The floor keeps the damped system regular where a coefficient has no effect.
            damped[d][d] += damping * normal[d][d].max(1e-12);
        }
        let Some(step) = solve_3x3(damped, descent) else {
            damping *= 10.0;
            continue;
        };
        let candidate: [f64; 3] =
            std::array::from_fn(|k| (coefficients[k] + step[k]).clamp(-MAX_COEFFICIENT, MAX_COEFFICIENT));
        let (candidate_residual, candidate_jacobian) = residual_and_jacobian(tables, candidate, target_lab);
        evaluations += 1;
        let candidate_cost = norm_squared(candidate_residual);
        if candidate_cost < cost {
            coefficients = candidate;
            residual = candidate_residual;
            jacobian = candidate_jacobian;
            cost = candidate_cost;
            damping = (damping * 0.1).max(1e-12);
        } else {
            damping *= 10.0;
        }
    }
    (coefficients, cost.sqrt())
}

/// Fits a sigmoid-polynomial reflectance whose colour under D65 is the linear sRGB `rgb`, each
/// component expected in [0, 1] (the caller validates user data; values outside are fitted
/// best-effort and come back with a large residual). Grey targets are exact constants.
/// About 30 µs per colour in a release build (p99 ~200 µs; the evaluation budget bounds the
/// worst case near 1 ms).
pub fn fit_reflectance(rgb: Vec3) -> SigmoidFit {
    debug_assert!(rgb.is_finite(), "rgb {rgb}");
    if rgb.x == rgb.y && rgb.y == rgb.z {
        return SigmoidFit {
            polynomial: SigmoidPolynomial::constant(rgb.x.clamp(0.0, 1.0)),
            residual_delta_e: 0.0,
        };
    }
    let tables = fit_tables();
    let target_xyz = mat_vec(&tables.rgb_to_xyz, [rgb.x as f64, rgb.y as f64, rgb.z as f64]);
    let target_lab = lab_and_jacobian(target_xyz, tables.white_xyz).0;
    // Start from the grey of the target's luminance (kept inside (0, 1) so c2 is finite).
    let grey = (target_xyz[1] / tables.white_xyz[1]).clamp(1e-3, 1.0 - 1e-3);
    let grey_c2 = (2.0 * grey - 1.0) / (2.0 * (grey * (1.0 - grey)).sqrt());
    let (coefficients, _) = levenberg_marquardt(tables, [0.0, 0.0, grey_c2], target_lab);
    let polynomial = SigmoidPolynomial { coefficients: coefficients.map(|c| c as f32) };
    // Report the residual of the f32 coefficients actually used.
    let used = polynomial.coefficients.map(f64::from);
    let residual_delta_e = norm_squared(residual_and_jacobian(tables, used, target_lab).0).sqrt();
    SigmoidFit { polynomial, residual_delta_e: residual_delta_e as f32 }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Linear sRGB round trip of `rgb` through the fit: the fitted spectrum's colour under D65.
    fn round_trip(fit: &SigmoidFit) -> Vec3 {
        reflectance_linear_srgb(|lambda_nm| fit.polynomial.eval(lambda_nm))
    }

    /// Smallest and largest value of the fitted reflectance on a 0.5 nm grid over 360–830 nm.
    fn value_range(polynomial: &SigmoidPolynomial) -> (f32, f32) {
        (0..=940)
            .map(|k| polynomial.eval(360.0 + 0.5 * k as f32))
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(low, high), v| (low.min(v), high.max(v)))
    }

    /// S(0) = 1/2, S(−z) = 1 − S(z), the limits are exactly 0 and 1, and the far tail keeps its
    /// relative precision: S(−1000) = 1/(4·10⁶) to first order (S(−z) ≈ 1/(4z²) for large z).
    #[test]
    fn sigmoid_is_symmetric_bounded_and_precise_in_the_tail() {
        assert_eq!(sigmoid(0.0), 0.5);
        for z in [0.1_f32, 1.0, 3.0, 40.0] {
            assert!((sigmoid(-z) - (1.0 - sigmoid(z))).abs() < 1e-6);
            assert!((0.0..=1.0).contains(&sigmoid(z)) && (0.0..=1.0).contains(&sigmoid(-z)));
        }
        assert_eq!(sigmoid(f32::INFINITY), 1.0);
        assert_eq!(sigmoid(f32::NEG_INFINITY), 0.0);
        assert!((sigmoid(-1000.0) / 2.5e-7 - 1.0).abs() < 1e-5);
        assert!(sigmoid(f32::NAN).is_nan());
    }

    /// A reflectance of 1 everywhere is white, (1, 1, 1), by the normalisation; 0.5 everywhere
    /// is (0.5, 0.5, 0.5) since the colour is linear in the spectrum. The gains that the
    /// normalisation removes are within 3e-4 of 1: the tabulated D65 is at (0.31272, 0.32903),
    /// a hair off the sRGB white (0.3127, 0.3290).
    #[test]
    fn unit_reflectance_is_white() {
        assert!((reflectance_linear_srgb(|_| 1.0) - Vec3::ONE).abs().max_element() < 1e-6);
        assert!((reflectance_linear_srgb(|_| 0.5) - Vec3::splat(0.5)).abs().max_element() < 1e-6);
        assert!((d65_white_gains() - Vec3::ONE).abs().max_element() < 3e-4);
    }

    /// Grey targets are constant spectra in closed form: black is exactly 0, white exactly 1.
    #[test]
    fn grey_targets_are_exact_constants() {
        for value in [0.0_f32, 0.18, 0.5, 0.9, 1.0] {
            let fit = fit_reflectance(Vec3::splat(value));
            assert!(fit.polynomial.is_constant());
            assert_eq!(fit.residual_delta_e, 0.0);
            let (low, high) = value_range(&fit.polynomial);
            assert!((low - value).abs() < 1e-6 && (high - value).abs() < 1e-6, "{value}");
        }
        assert_eq!(fit_reflectance(Vec3::ZERO).polynomial.eval(555.0), 0.0);
        assert_eq!(fit_reflectance(Vec3::ONE).polynomial.eval(555.0), 1.0);
    }

    /// Round trip of the 17³ grid over [0, 1]³ (steps of 1/16, corners and faces included):
    /// every fitted spectrum lies in [0, 1] and reproduces its colour within 1e-4 in linear sRGB
    /// (measured: ≤ 3e-7 at the grid colours; the sRGB cube is inside the sigmoid space, as
    /// Jakob & Hanika report), with a CIELAB residual below 1e-3.
    #[test]
    fn grid_round_trip_reproduces_colours() {
        const STEPS: usize = 16;
        let mut max_error = 0.0_f32;
        let mut max_residual = 0.0_f32;
        let start = std::time::Instant::now();
        let mut fits = 0;
        for r in 0..=STEPS {
            for g in 0..=STEPS {
                for b in 0..=STEPS {
                    let rgb = Vec3::new(r as f32, g as f32, b as f32) / STEPS as f32;
                    let fit = fit_reflectance(rgb);
                    fits += 1;
                    let error = (round_trip(&fit) - rgb).abs().max_element();
                    assert!(error < 1e-4, "{rgb}: error {error}, fit {fit:?}");
                    assert!(fit.residual_delta_e < 1e-3, "{rgb}: {fit:?}");
                    let (low, high) = value_range(&fit.polynomial);
                    assert!(low >= 0.0 && high <= 1.0, "{rgb}: range [{low}, {high}]");
                    max_error = max_error.max(error);
                    max_residual = max_residual.max(fit.residual_delta_e);
                }
            }
        }
        let micros_per_fit = start.elapsed().as_secs_f64() * 1e6 / fits as f64;
        eprintln!(
            "rgb_upsample grid 17³: max linear sRGB error {max_error:.2e}, max ΔE {max_residual:.2e}, \
             {micros_per_fit:.1} µs per fit (with round-trip check)"
        );
    }

    /// The sRGB primaries and secondaries, the most saturated colours a scene can ask for, are
    /// reachable: each round-trips within 1e-5 and its spectrum is a smooth band (red rises
    /// towards long wavelengths, blue towards short ones, green peaks in the middle).
    #[test]
    fn primaries_and_secondaries_are_reachable() {
        for rgb in [Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 1.0)] {
            let fit = fit_reflectance(rgb);
            assert!((round_trip(&fit) - rgb).abs().max_element() < 1e-5, "{rgb}: {fit:?}");
            assert!(fit.residual_delta_e < 1e-4, "{rgb}: {fit:?}");
        }
        let red = fit_reflectance(Vec3::X).polynomial;
        assert!(red.eval(700.0) > 0.9 && red.eval(450.0) < 0.1);
        let green = fit_reflectance(Vec3::Y).polynomial;
        assert!(green.eval(530.0) > 0.9 && green.eval(450.0) < 0.1 && green.eval(650.0) < 0.1);
        let blue = fit_reflectance(Vec3::Z).polynomial;
        assert!(blue.eval(440.0) > 0.9 && blue.eval(600.0) < 0.1);
    }

    /// A target no reflectance in [0, 1] can produce (red at 1.5× white) is fitted best-effort:
    /// the spectrum stays in [0, 1] and the large residual says the fit failed.
    #[test]
    fn unreachable_target_reports_its_residual() {
        let fit = fit_reflectance(Vec3::new(1.5, 0.0, 0.0));
        assert!(fit.residual_delta_e > 1.0, "{fit:?}");
        let (low, high) = value_range(&fit.polynomial);
        assert!(low >= 0.0 && high <= 1.0);
    }
}
