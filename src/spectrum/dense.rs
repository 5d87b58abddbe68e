//! [`DenseSpectrum`]: a spectrum in the form the renderer evaluates it, one value per whole
//! nanometre over 360–830 nm, linearly interpolated (pbrt-v4's `DenselySampledSpectrum`, *PBR*
//! 4th ed. §4.5.1).
//!
//! Scene spectra are defined many ways ([`Spectrum`]: RGB sigmoids, tables, illuminants,
//! blackbodies); a scene build tabulates each once, so that a lookup in the hot path is the same
//! two loads and one interpolation per lane, at the grid positions the camera sample computed
//! once for all its lookups ([`SampledWavelengths`]). Before, evaluating RGB sigmoids, D65 and
//! table searches per lane and per hit took 13 % of a TP6 render's instructions.
//!
//! Exactness: at whole nanometres the values are [`Spectrum::eval`]'s; between them the
//! interpolation of a smooth spectrum differs from it by h²/8·|f''| with h = 1 nm (below 3e-4
//! relative for the RGB sigmoids and blackbodies), D65 (given at 1 nm) is reproduced exactly,
//! and a table whose knots lie on whole nanometres is reproduced exactly; one with knots between
//! whole nanometres is rounded off within 1 nm of each knot. This 1 nm table is also exactly
//! what `prisma export` gives Mitsuba for the validation references.
//!
//! Scene file: every spectrum (`albedo`, `reflectance`, `radiance`, `intensity`, `background`,
//! `absorption`) becomes one of these; nothing is written differently.

use super::tables::{grid_lambda_nm, GridPosition, GRID_LEN};
use super::{SampledSpectrum, SampledWavelengths, Spectrum};

/// A spectrum tabulated at every whole nm from 360 to 830 nm, or a constant.
#[derive(Clone, Debug, PartialEq)]
pub enum DenseSpectrum {
    /// The same value at every wavelength (no lookup).
    Constant(f32),
    /// The value at each whole nm, 360 nm first.
    Table(Box<[f32; GRID_LEN]>),
}

impl DenseSpectrum {
    /// The constant spectrum `value`.
    pub fn constant(value: f32) -> Self {
        Self::Constant(value)
    }

    /// `spectrum` tabulated at every whole nm (a constant stays a constant).
    pub fn new(spectrum: &Spectrum) -> Self {
        if spectrum.is_constant() {
            return Self::Constant(spectrum.eval(grid_lambda_nm(0)));
        }
        Self::Table(Box::new(std::array::from_fn(|i| spectrum.eval(grid_lambda_nm(i)))))
    }

    /// The value at `lambda_nm` (interpolated between whole nm; the end values beyond
    /// 360–830 nm).
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        match self {
            Self::Constant(value) => *value,
            Self::Table(table) => GridPosition::of(lambda_nm).lerp(table),
        }
    }

    /// Values at every lane of `wavelengths` (inactive lanes hold the hero wavelength's).
    #[inline]
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Self::Constant(value) => SampledSpectrum::splat(*value),
            Self::Table(table) => {
                let grid = wavelengths.grid();
                SampledSpectrum { values: grid.lerp(table) }
            }
        }
    }

    /// The tabulated values (one for a constant): every value the renderer can interpolate
    /// lies between two of them, so their range is the spectrum's range (the scene builder
    /// checks it).
    pub fn values(&self) -> &[f32] {
        match self {
            Self::Constant(value) => std::slice::from_ref(value),
            Self::Table(table) => table.as_slice(),
        }
    }

    /// ∫ value dλ over 360–830 nm (units of the spectrum times nm), by the trapezoid rule on the
    /// 1 nm table: exact for the piecewise-linear function [`Self::eval`] interpolates.
    pub fn integral_nm(&self) -> f64 {
        match self {
            Self::Constant(value) => {
                f64::from(*value) * f64::from(grid_lambda_nm(GRID_LEN - 1) - grid_lambda_nm(0))
            }
            Self::Table(table) => table.windows(2).map(|w| 0.5 * (f64::from(w[0]) + f64::from(w[1]))).sum(),
        }
    }

    /// True when the value is the same at every wavelength.
    pub fn is_constant(&self) -> bool {
        match self {
            Self::Constant(_) => true,
            Self::Table(table) => table.iter().all(|&value| value == table[0]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::N_LAMBDA;

    /// At whole nanometres the table holds the defining spectrum's values exactly; between them
    /// a smooth spectrum (an RGB sigmoid, a blackbody) is within 3e-4 relative, and D65 (defined
    /// at 1 nm and linear between) is exact up to rounding.
    #[test]
    fn tabulation_reproduces_the_spectrum() {
        let spectra = [
            Spectrum::rgb_reflectance([0.7, 0.08, 0.06]).unwrap(),
            Spectrum::rgb_illuminant([0.1, 0.25, 0.95]).unwrap().scaled(2.0),
            Spectrum::blackbody(3200.0).unwrap(),
            Spectrum::named_illuminant("D65").unwrap(),
        ];
        for (k, spectrum) in spectra.iter().enumerate() {
            let dense = DenseSpectrum::new(spectrum);
            assert!(!dense.is_constant());
            for i in 0..GRID_LEN {
                let lambda_nm = grid_lambda_nm(i);
                assert_eq!(dense.eval(lambda_nm), spectrum.eval(lambda_nm), "spectrum {k} at {lambda_nm} nm");
            }
            for tenth in 3600..8300 {
                let lambda_nm = tenth as f32 / 10.0;
                let (exact, ours) = (spectrum.eval(lambda_nm), dense.eval(lambda_nm));
                assert!(
                    (ours - exact).abs() <= 3e-4 * exact.abs() + 1e-7,
                    "spectrum {k} at {lambda_nm} nm: {ours} vs {exact}"
                );
            }
        }
    }

    /// A table with knots on whole nanometres is reproduced at every wavelength, not only at the
    /// knots (the validation's emitters rely on this); constants stay constants.
    #[test]
    fn whole_nm_tables_and_constants_are_exact() {
        let table = Spectrum::table(&[(400.0, 0.05), (480.0, 0.2), (520.0, 1.4), (600.0, 0.5)]).unwrap();
        let dense = DenseSpectrum::new(&table);
        for tenth in 3600..8300 {
            let lambda_nm = tenth as f32 / 10.0;
            assert!((dense.eval(lambda_nm) - table.eval(lambda_nm)).abs() < 1e-6, "{lambda_nm} nm");
        }
        assert_eq!(DenseSpectrum::new(&Spectrum::constant(0.25)), DenseSpectrum::Constant(0.25));
        assert!(DenseSpectrum::new(&Spectrum::rgb_reflectance([0.5, 0.5, 0.5]).unwrap()).is_constant());
    }

    /// `sample` interpolates each lane at its own wavelength.
    #[test]
    fn sample_matches_eval_per_lane() {
        let dense = DenseSpectrum::new(&Spectrum::blackbody(5000.0).unwrap());
        let wavelengths = SampledWavelengths::sample_visible(0.37, N_LAMBDA);
        let sampled = dense.sample(&wavelengths);
        for lane in 0..N_LAMBDA {
            assert_eq!(sampled[lane], dense.eval(wavelengths.lambda_nm(lane)));
        }
    }
}
