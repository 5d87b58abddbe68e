//! PNG previews: linear sRGB times 2^exposure, clamped to [0, 1], sRGB-encoded to 8 bits.

use std::path::Path;

use glam::Vec3;

use super::atomic::write_atomically;
use super::OutputError;
use crate::spectrum::color::srgb_encode;

/// Writes an 8-bit sRGB preview of the linear sRGB pixels `rgb` (row-major, top row first),
/// scaled by 2^`exposure_ev`.
pub fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[Vec3],
    exposure_ev: f32,
) -> Result<(), OutputError> {
    let scale = exposure_ev.exp2();
    let bytes: Vec<u8> = rgb
        .iter()
        .flat_map(|p| (*p * scale).to_array())
        .map(|v| {
            // The renderer never produces NaN; `as u8` saturates (NaN → 0), which keeps the
            // preview writer total anyway.
            (srgb_encode(v.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8
        })
        .collect();
    write_atomically(path, |tmp| {
        image::save_buffer_with_format(
            tmp,
            &bytes,
            width,
            height,
            image::ColorType::Rgb8,
            image::ImageFormat::Png,
        )
        .map_err(|e| OutputError::Codec { path: path.display().to_string(), message: e.to_string() })
    })
}
