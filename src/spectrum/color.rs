//! Colour spaces: CIE XYZ ↔ linear sRGB (Rec. 709 primaries, D65 white), and the sRGB transfer
//! function for previews.

use glam::Vec3;

/// Linear sRGB (Rec. 709, D65) from CIE XYZ.
pub fn xyz_to_linear_srgb(xyz: Vec3) -> Vec3 {
    let _ = xyz;
    todo!()
}

/// CIE XYZ from linear sRGB (Rec. 709, D65).
pub fn linear_srgb_to_xyz(rgb: Vec3) -> Vec3 {
    let _ = rgb;
    todo!()
}

/// The sRGB opto-electronic transfer function (IEC 61966-2-1) of one linear value in [0, 1].
pub fn srgb_encode(linear: f32) -> f32 {
    let _ = linear;
    todo!()
}
