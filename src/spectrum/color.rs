//! Colour spaces: CIE XYZ ↔ linear sRGB (Rec. 709 primaries, D65 white), and the sRGB transfer
//! function for previews.
//!
//! The matrices are derived at compile time, in f64, from the chromaticities of IEC 61966-2-1
//! (sRGB) = ITU-R BT.709: red (0.64, 0.33), green (0.30, 0.60), blue (0.15, 0.06), white D65
//! (0.3127, 0.3290), by the standard construction (e.g. SMPTE RP 177; Poynton, "Digital Video and
//! HD", ch. 26): the columns are the primaries' XYZ at Y = 1, scaled so that RGB (1, 1, 1) is the
//! white at Y = 1. The tests compare them with the 4-digit matrices printed in IEC 61966-2-1.

use glam::{Mat3, Vec3};

/// Chromaticities (x, y) of the sRGB / Rec. 709 red, green and blue primaries.
const PRIMARIES_XY: [[f64; 2]; 3] = [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]];
/// Chromaticity (x, y) of the sRGB white point, D65 as rounded in IEC 61966-2-1.
pub const D65_WHITE_XY: [f32; 2] = [0.3127, 0.3290];
const D65_WHITE_XY_F64: [f64; 2] = [0.3127, 0.3290];

/// XYZ at Y = 1 of the chromaticity (x, y).
const fn xyz_at_unit_y([x, y]: [f64; 2]) -> [f64; 3] {
    [x / y, 1.0, (1.0 - x - y) / y]
}

/// Inverse of the row-major 3×3 matrix `m` by cofactors (the matrices here are far from singular).
pub(crate) const fn inverse_3x3(m: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    let c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    let c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    let det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    [
        [
            c00 / det,
            (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det,
            (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det,
        ],
        [
            c01 / det,
            (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det,
            (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det,
        ],
        [
            c02 / det,
            (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det,
            (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det,
        ],
    ]
}

/// Row-major linear sRGB → XYZ matrix from the primaries and the white point, in f64 for
/// callers that solve with it (the RGB → spectrum fit).
pub(crate) const fn rgb_to_xyz_rows() -> [[f64; 3]; 3] {
    let red = xyz_at_unit_y(PRIMARIES_XY[0]);
    let green = xyz_at_unit_y(PRIMARIES_XY[1]);
    let blue = xyz_at_unit_y(PRIMARIES_XY[2]);
    let primaries = [[red[0], green[0], blue[0]], [red[1], green[1], blue[1]], [red[2], green[2], blue[2]]];
    let inverse = inverse_3x3(primaries);
    let white = xyz_at_unit_y(D65_WHITE_XY_F64);
    // Channel gains that make RGB (1, 1, 1) land on the white: gains = primaries⁻¹ · white.
    let mut gains = [0.0; 3];
    let mut row = 0;
    while row < 3 {
        gains[row] = inverse[row][0] * white[0] + inverse[row][1] * white[1] + inverse[row][2] * white[2];
        row += 1;
    }
    let mut out = [[0.0; 3]; 3];
    let mut r = 0;
    while r < 3 {
        let mut c = 0;
        while c < 3 {
            out[r][c] = primaries[r][c] * gains[c];
            c += 1;
        }
        r += 1;
    }
    out
}

/// A glam (column-major) matrix from row-major f64 rows.
const fn mat3_from_rows(rows: [[f64; 3]; 3]) -> Mat3 {
    Mat3::from_cols_array(&[
        rows[0][0] as f32,
        rows[1][0] as f32,
        rows[2][0] as f32,
        rows[0][1] as f32,
        rows[1][1] as f32,
        rows[2][1] as f32,
        rows[0][2] as f32,
        rows[1][2] as f32,
        rows[2][2] as f32,
    ])
}

/// Linear sRGB → CIE XYZ (Y = 1 for RGB white (1, 1, 1)). Row 2 is the luminance weights
/// (0.2126, 0.7152, 0.0722).
pub const LINEAR_SRGB_TO_XYZ: Mat3 = mat3_from_rows(rgb_to_xyz_rows());
/// CIE XYZ → linear sRGB, the inverse of [`LINEAR_SRGB_TO_XYZ`].
pub const XYZ_TO_LINEAR_SRGB: Mat3 = mat3_from_rows(inverse_3x3(rgb_to_xyz_rows()));

/// Linear sRGB (Rec. 709, D65) from CIE XYZ.
pub fn xyz_to_linear_srgb(xyz: Vec3) -> Vec3 {
    XYZ_TO_LINEAR_SRGB * xyz
}

/// CIE XYZ from linear sRGB (Rec. 709, D65).
pub fn linear_srgb_to_xyz(rgb: Vec3) -> Vec3 {
    LINEAR_SRGB_TO_XYZ * rgb
}

/// The sRGB opto-electronic transfer function (IEC 61966-2-1) of one linear value in [0, 1].
///
/// `12.92·v` up to v = 0.0031308, `1.055·v^(1/2.4) − 0.055` above. Values outside [0, 1] are not
/// clamped (negative values stay on the linear segment, values above 1 on the power law), so an
/// out-of-gamut value remains visible; 8-bit writers clamp after encoding.
pub fn srgb_encode(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn xyz_from_xy_luminance([x, y]: [f32; 2], luminance: f32) -> Vec3 {
        Vec3::new(x / y, 1.0, (1.0 - x - y) / y) * luminance
    }

    /// The sRGB white point D65 (x 0.3127, y 0.3290) at Y = 1 is RGB (1, 1, 1) by construction.
    #[test]
    fn d65_white_maps_to_rgb_one() {
        let rgb = xyz_to_linear_srgb(xyz_from_xy_luminance(D65_WHITE_XY, 1.0));
        assert!((rgb - Vec3::ONE).abs().max_element() < 1e-3, "{rgb}");
    }

    /// Each primary's chromaticity, at the luminance that the white's decomposition gives it
    /// (Rec. 709 luminance weights 0.2126, 0.7152, 0.0722), is a unit vector in linear sRGB.
    #[test]
    fn primaries_map_to_unit_vectors() {
        let luminances = [0.2126, 0.7152, 0.0722];
        for (channel, &luminance) in luminances.iter().enumerate() {
            let [x, y] = PRIMARIES_XY[channel];
            let rgb = xyz_to_linear_srgb(xyz_from_xy_luminance([x as f32, y as f32], luminance));
            let mut expected = Vec3::ZERO;
            expected[channel] = 1.0;
            assert!((rgb - expected).abs().max_element() < 1e-3, "channel {channel}: {rgb}");
        }
    }

    /// The derived matrices agree with the ones printed in IEC 61966-2-1:1999 (4 decimals), and
    /// are inverses of each other.
    #[test]
    fn matrices_match_iec_61966_2_1() {
        let published_rgb_to_xyz =
            Mat3::from_cols_array(&[0.4124, 0.2126, 0.0193, 0.3576, 0.7152, 0.1192, 0.1805, 0.0722, 0.9505]);
        let published_xyz_to_rgb = Mat3::from_cols_array(&[
            3.2406, -0.9689, 0.0557, -1.5372, 1.8758, -0.2040, -0.4986, 0.0415, 1.0570,
        ]);
        assert!(LINEAR_SRGB_TO_XYZ.abs_diff_eq(published_rgb_to_xyz, 1e-4));
        assert!(XYZ_TO_LINEAR_SRGB.abs_diff_eq(published_xyz_to_rgb, 1e-3));
        assert!((XYZ_TO_LINEAR_SRGB * LINEAR_SRGB_TO_XYZ).abs_diff_eq(Mat3::IDENTITY, 1e-6));
        let rgb = Vec3::new(0.2, 0.5, 0.9);
        assert!((xyz_to_linear_srgb(linear_srgb_to_xyz(rgb)) - rgb).abs().max_element() < 1e-6);
    }

    /// The two pieces of the transfer function meet at 0.0031308 (value 0.04045), and the curve
    /// hits published values: 0 → 0, 1 → 1, 0.5 → 0.735357, 0.18 (mid grey) → 0.461356,
    /// 0.214041 → 0.5.
    #[test]
    fn srgb_encode_is_continuous_and_matches_published_values() {
        let knee = 0.003_130_8_f32;
        let linear_piece = 12.92 * knee;
        let power_piece = 1.055 * knee.powf(1.0 / 2.4) - 0.055;
        assert!((linear_piece - power_piece).abs() < 1e-6);
        assert!((srgb_encode(knee) - 0.040_45).abs() < 1e-5);
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_encode(0.5) - 0.735_357).abs() < 1e-5);
        assert!((srgb_encode(0.18) - 0.461_356).abs() < 1e-5);
        assert!((srgb_encode(0.214_041) - 0.5).abs() < 1e-5);
    }
}
