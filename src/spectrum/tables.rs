//! The embedded CIE tables, parsed once on first use.
//!
//! - `data/cie1931_2deg.csv`: CIE 1931 2° colour-matching functions, ISO 11664-1:2007 /
//!   CIE S 014-1:2006, 360–830 nm at 1 nm.
//! - `data/cie_d65.csv`: CIE standard illuminant D65, ISO 11664-2:2007 / CIE S 014-2:2006,
//!   360–830 nm at 1 nm (relative, 100 at 560 nm).
//!
//! Each file's header names the package and version its numbers were extracted from. Both tables
//! share one wavelength grid, [`GRID_LEN`] points from [`LAMBDA_MIN_NM`] in steps of 1 nm, which
//! the parser checks. A malformed embedded table is a programming error, so parsing panics with
//! a message naming the file and line; the tests below parse both tables.

use std::sync::OnceLock;

use glam::Vec3A;

use super::{LAMBDA_MIN_NM, N_LAMBDA};
use crate::float_index::floor_index;

/// Number of 1 nm grid points from 360 to 830 nm inclusive.
pub(crate) const GRID_LEN: usize = 471;

/// Wavelength of grid point `i`, in nm.
#[inline]
pub(crate) fn grid_lambda_nm(i: usize) -> f32 {
    LAMBDA_MIN_NM + i as f32
}

/// Trapezoid-rule weight of grid point `i`, in nm: the exact integral of a piecewise-linear
/// function through the grid values is `Σ weight(i)·value(i)`.
#[inline]
pub(crate) fn trapezoid_weight_nm(i: usize) -> f64 {
    if i == 0 || i == GRID_LEN - 1 {
        0.5
    } else {
        1.0
    }
}

/// Where a wavelength falls on the grid: the index of the grid point below it and the weight of
/// the one above, for linear interpolation of any per-grid-point table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct GridPosition {
    /// Grid index below the wavelength, in 0..GRID_LEN − 1.
    lower: u32,
    /// Weight of grid point `lower + 1`, in [0, 1].
    t: f32,
}

impl GridPosition {
    /// The position of `lambda_nm`, clamped to 360–830 nm (so a table extends constantly beyond
    /// its ends). NaN maps to the first grid point.
    #[inline(always)]
    pub(crate) fn of(lambda_nm: f32) -> Self {
        // `max` first: it maps NaN to 0.
        let offset_nm = (lambda_nm - LAMBDA_MIN_NM).max(0.0).min((GRID_LEN - 1) as f32);
        // λ = 830 nm stays inside the last interval (t = 1).
        let lower = floor_index(offset_nm, GRID_LEN as u32 - 2);
        Self { lower, t: offset_nm - lower as f32 }
    }

    /// `table` (one value per grid point) interpolated at this position.
    #[inline(always)]
    pub(crate) fn lerp(self, table: &[f32; GRID_LEN]) -> f32 {
        lerp_at(self.lower, self.t, table)
    }

    /// `table` of 3-vectors interpolated at this position.
    #[inline(always)]
    pub(crate) fn lerp_vec3(self, table: &[Vec3A; GRID_LEN]) -> Vec3A {
        lerp_vec3_at(self.lower, self.t, table)
    }
}

/// The grid positions of the [`N_LAMBDA`] wavelengths of a camera sample, by coordinate, so that
/// finding them and every table lookup at them run lane-parallel. Computed once per camera sample
/// ([`super::SampledWavelengths`]) and shared by every table looked up for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct GridPositions {
    /// Each lane's [`GridPosition`] `lower`.
    lower: [u32; N_LAMBDA],
    /// Each lane's [`GridPosition`] `t`.
    t: [f32; N_LAMBDA],
}

impl GridPositions {
    /// The positions of `lambda_nm`, lane by lane as [`GridPosition::of`].
    #[inline]
    pub(crate) fn of(lambda_nm: &[f32; N_LAMBDA]) -> Self {
        let mut positions = Self { lower: [0; N_LAMBDA], t: [0.0; N_LAMBDA] };
        for (lane, &lambda_nm) in lambda_nm.iter().enumerate() {
            let GridPosition { lower, t } = GridPosition::of(lambda_nm);
            positions.lower[lane] = lower;
            positions.t[lane] = t;
        }
        positions
    }

    /// Lane `lane`'s position.
    #[cfg(test)]
    pub(crate) fn lane(&self, lane: usize) -> GridPosition {
        GridPosition { lower: self.lower[lane], t: self.t[lane] }
    }

    /// `table` interpolated at every lane.
    #[inline(always)]
    pub(crate) fn lerp(&self, table: &[f32; GRID_LEN]) -> [f32; N_LAMBDA] {
        std::array::from_fn(|lane| lerp_at(self.lower[lane], self.t[lane], table))
    }

    /// `Σ_lane weights[lane] · table(λ_lane)` for a table of 3-vectors.
    #[inline(always)]
    pub(crate) fn weighted_sum_vec3(&self, table: &[Vec3A; GRID_LEN], weights: &[f32; N_LAMBDA]) -> Vec3A {
        let mut sum = Vec3A::ZERO;
        for (lane, weight) in weights.iter().enumerate() {
            sum += lerp_vec3_at(self.lower[lane], self.t[lane], table) * *weight;
        }
        sum
    }
}

/// `table` interpolated between grid points `lower` and `lower + 1` with weight `t` on the upper.
/// (`lower` is clamped again so that the compiler drops the bounds checks.)
#[inline(always)]
fn lerp_at(lower: u32, t: f32, table: &[f32; GRID_LEN]) -> f32 {
    let lower = (lower as usize).min(GRID_LEN - 2);
    let (a, b) = (table[lower], table[lower + 1]);
    a + t * (b - a)
}

/// [`lerp_at`] for a table of 3-vectors.
#[inline(always)]
fn lerp_vec3_at(lower: u32, t: f32, table: &[Vec3A; GRID_LEN]) -> Vec3A {
    let lower = (lower as usize).min(GRID_LEN - 2);
    table[lower].lerp(table[lower + 1], t)
}

/// The CIE 1931 2° colour-matching functions (x̄, ȳ, z̄) at each grid point, as 16-byte vectors
/// (`Vec3A`), so that an interpolation is two vector loads and vector arithmetic.
pub(crate) fn cmf_table() -> &'static [Vec3A; GRID_LEN] {
    static TABLE: OnceLock<[Vec3A; GRID_LEN]> = OnceLock::new();
    TABLE.get_or_init(|| {
        parse_grid::<3>("data/cie1931_2deg.csv", include_str!("../../data/cie1931_2deg.csv"))
            .map(Vec3A::from_array)
    })
}

/// The relative spectral power of CIE illuminant D65 at each grid point (100 at 560 nm).
pub(crate) fn d65_table() -> &'static [f32; GRID_LEN] {
    static TABLE: OnceLock<[f32; GRID_LEN]> = OnceLock::new();
    TABLE.get_or_init(|| {
        parse_grid::<1>("data/cie_d65.csv", include_str!("../../data/cie_d65.csv")).map(|[power]| power)
    })
}

/// Parses a CSV table whose first column is the wavelength in nm on the shared grid, followed by
/// `C` value columns. Lines starting with `#` are comments; the first other line is the column
/// header. Panics (naming `file` and the line) on anything else, since the tables are embedded.
fn parse_grid<const C: usize>(file: &str, text: &str) -> [[f32; C]; GRID_LEN] {
    let mut rows = Vec::with_capacity(GRID_LEN);
    let mut header_seen = false;
    for (line_index, line) in text.lines().enumerate() {
        let line_no = line_index + 1;
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        if !header_seen {
            header_seen = true;
            continue;
        }
        let mut fields = line.split(',').map(|field| {
            field
                .trim()
                .parse::<f32>()
                .unwrap_or_else(|err| panic!("{file}:{line_no}: field {field:?} is not a number ({err})"))
        });
        let lambda_nm = fields.next().unwrap_or_else(|| panic!("{file}:{line_no}: empty row"));
        let expected_nm = grid_lambda_nm(rows.len());
        assert!(
            lambda_nm == expected_nm,
            "{file}:{line_no}: wavelength {lambda_nm} nm, expected {expected_nm} nm (1 nm grid from 360 nm)"
        );
        let mut values = [0.0; C];
        for (column, value) in values.iter_mut().enumerate() {
            *value = fields
                .next()
                .unwrap_or_else(|| panic!("{file}:{line_no}: missing value column {}", column + 1));
            assert!(value.is_finite(), "{file}:{line_no}: non-finite value {value}");
        }
        assert!(fields.next().is_none(), "{file}:{line_no}: more than {} value columns", C);
        rows.push(values);
    }
    rows.try_into().unwrap_or_else(|rows: Vec<_>| {
        panic!("{file}: {} rows, expected {GRID_LEN} (360–830 nm at 1 nm)", rows.len())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both embedded tables parse onto the 471-point grid, and spot values equal the published
    /// ones: ȳ(555 nm) = 1 (the CMFs are normalised there), x̄(600 nm) = 1.0622 and
    /// z̄(445 nm) = 1.7826 (CIE S 014-1 table); D65(560 nm) = 100 (its normalisation) and
    /// D65(830 nm) = 60.3125 (CIE S 014-2 table).
    #[test]
    fn embedded_tables_parse_and_match_published_values() {
        let cmf = cmf_table();
        assert_eq!(cmf.len(), GRID_LEN);
        assert_eq!(cmf[555 - 360].y, 1.0);
        assert!((cmf[600 - 360].x - 1.0622).abs() < 1e-4);
        assert!((cmf[445 - 360].z - 1.78260).abs() < 1e-4);
        let d65 = d65_table();
        assert_eq!(d65.len(), GRID_LEN);
        assert_eq!(d65[560 - 360], 100.0);
        assert!((d65[GRID_LEN - 1] - 60.3125).abs() < 1e-4);
    }

    /// The trapezoid weights integrate a constant 1 over 360–830 nm to the width, 470 nm.
    #[test]
    fn trapezoid_weights_integrate_the_range_width() {
        let width_nm: f64 = (0..GRID_LEN).map(trapezoid_weight_nm).sum();
        assert_eq!(width_nm, 470.0);
    }

    /// A malformed table is reported with its file and line, not silently accepted.
    #[test]
    #[should_panic(expected = "bad.csv:3: wavelength 362 nm, expected 361 nm")]
    fn parse_grid_names_the_offending_line() {
        parse_grid::<1>("bad.csv", "lambda_nm,value\n360,1\n362,2\n");
    }
}
