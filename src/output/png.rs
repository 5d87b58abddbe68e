//! PNG previews: linear sRGB times 2^exposure, clamped to [0, 1], sRGB-encoded to 8 bits.

use std::path::Path;

use glam::Vec3;
use image::ImageEncoder;

use super::file::{write_file, Sink};
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
    write_file(path, |sink| encode_png(sink, path, width, height, rgb, exposure_ev))
}

/// The PNG file of [`write_png`] into `sink` (to stage it with other outputs,
/// [`super::file::Outputs::stage`]); errors name `path`.
pub fn encode_png(
    sink: &mut Sink,
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
        // Renders are checked finite before they are written (`Film::check_finite`); `as u8`
        // saturates (NaN → 0), which keeps this encoder total for any caller.
        .map(|v| (srgb_encode(v.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8)
        .collect();
    encode_png_bytes(sink, path, width, height, &bytes)
}

/// Encodes 8-bit RGB `bytes` (row-major, top row first) as PNG into `sink`.
pub fn encode_png_bytes(
    sink: &mut Sink,
    path: &Path,
    width: u32,
    height: u32,
    bytes: &[u8],
) -> Result<(), OutputError> {
    image::codecs::png::PngEncoder::new(sink)
        .write_image(bytes, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|e| match e {
            image::ImageError::IoError(source) => {
                OutputError::Io { path: path.display().to_string(), source }
            }
            e => OutputError::Codec { path: path.display().to_string(), message: e.to_string() },
        })
}
