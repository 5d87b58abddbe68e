//! Part files: a render's EXR (the image of its window, [`crate::output::exr`]) with its
//! per-pixel sums added as 32-bit unsigned channels, up to six per value (the words of a
//! [`FixedSum`], least significant first): `sums.c0000.w0` … `sums.c0000.w5` for the camera
//! samples' value 0 (XYZ of S0, then of S1–S3, then the bands, as
//! [`crate::film::FilmLayout::values_per_pixel`] orders them), and `sums.l…` for the light
//! tracer's. A word channel is left out when every pixel's word is implied ([`implied_word`]):
//! zero for word 0, the sign extension of the word below for the others. Part files are written
//! uncompressed: compressing the sums cost more time than splitting a render may add. The
//! header ([`PartHeader`]) says which samples and window they hold, and `prisma.sumsSha256`
//! guards them: a part whose sums do not match it is refused as corrupt.

use std::path::Path;

use ::exr::meta::attribute::AttributeValue;
use ::exr::prelude::{read, FlatSamples, ReadChannels, ReadLayers};
use sha2::{Digest, Sha256};

use super::header::SUMS_FORMAT;
use super::{PartHeader, PixelWindow};
use crate::film::WindowSums;
use crate::fixed::FixedSum;
use crate::scene::digest::hex;

/// A part read back: what it is, and its sums.
#[derive(Debug, Clone)]
pub struct Part {
    /// Its header.
    pub header: PartHeader,
    /// Its per-pixel sums.
    pub sums: WindowSums,
}

/// Why a file is not a usable part: one line naming the file.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {problem}")]
pub struct PartError {
    /// The file.
    pub path: String,
    /// What is wrong.
    pub problem: String,
}

/// The name of word `word` of sum value `value`, camera (`light` false) or light tracer.
pub fn sum_channel_name(light: bool, value: usize, word: usize) -> String {
    format!("sums.{}{value:04}.w{word}", if light { 'l' } else { 'c' })
}

/// The value word `word` of a sum whose words are `words` takes when its channel is left out:
/// 0 for the lowest, else all ones or all zeros as the top bit of the word below.
#[inline]
pub fn implied_word(words: &[u32; 6], word: usize) -> u32 {
    match word {
        0 => 0,
        w => {
            if words[w - 1] >> 31 == 1 {
                u32::MAX
            } else {
                0
            }
        }
    }
}

/// SHA-256 (hex) of the sums' words, camera then light, little-endian.
pub fn sums_digest(sums: &WindowSums) -> String {
    let mut hasher = Sha256::new();
    // Fed in large pieces: four bytes at a time, the hasher's bookkeeping cost more than hashing.
    let mut bytes = Vec::with_capacity(1 << 16);
    for sum in sums.camera().iter().chain(sums.light()) {
        for word in sum.to_words() {
            bytes.extend_from_slice(&word.to_le_bytes());
        }
        if bytes.len() >= 1 << 16 {
            hasher.update(&bytes);
            bytes.clear();
        }
    }
    hasher.update(&bytes);
    hex(&hasher.finalize())
}

/// The header attributes, the display and data windows, and the channel names of an EXR,
/// without decoding its pixels.
pub struct ExrSummary {
    /// `prisma.*` and other text attributes, by name.
    pub attributes: Vec<(String, String)>,
    /// Size of the display window.
    pub display: (u32, u32),
    /// The data window.
    pub window: PixelWindow,
    /// Channel names.
    pub channels: Vec<String>,
}

/// Reads the header of the EXR at `path` (see [`ExrSummary`]).
pub fn read_summary(path: &Path) -> Result<ExrSummary, PartError> {
    let error = |problem: String| PartError { path: path.display().to_string(), problem };
    let meta = ::exr::meta::MetaData::read_from_file(path, true).map_err(|e| error(exr_problem(e)))?;
    let header = meta.headers.first().ok_or_else(|| error("no image in the file".into()))?;
    let attributes = header
        .shared_attributes
        .other
        .iter()
        .chain(header.own_attributes.other.iter())
        .map(|(name, value)| (name.to_string(), attribute_text(value)))
        .collect();
    let display_window = header.shared_attributes.display_window;
    let (display, window) =
        windows(display_window, header.own_attributes.layer_position, header.layer_size).map_err(error)?;
    let channels = header.channels.list.iter().map(|c| c.name.to_string()).collect();
    Ok(ExrSummary { attributes, display, window, channels })
}

fn attribute_text(value: &AttributeValue) -> String {
    match value {
        AttributeValue::Text(text) => text.to_string(),
        AttributeValue::F32(number) => number.to_string(),
        other => format!("{other:?}"),
    }
}

fn exr_problem(error: ::exr::error::Error) -> String {
    match error {
        ::exr::error::Error::Io(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
            "truncated: the file ends inside the image".into()
        }
        ::exr::error::Error::Io(e) if e.kind() == std::io::ErrorKind::NotFound => "no such file".into(),
        e => format!("not a readable EXR image ({e})"),
    }
}

/// The display size and the data window in image coordinates, from the EXR's display window,
/// layer position and layer size; an error unless the display window starts at (0, 0) and
/// holds the data window.
fn windows(
    display: ::exr::meta::attribute::IntegerBounds,
    position: ::exr::math::Vec2<i32>,
    size: ::exr::math::Vec2<usize>,
) -> Result<((u32, u32), PixelWindow), String> {
    let display_size = (display.size.0 as u32, display.size.1 as u32);
    let (x0, y0) = (position.0 - display.position.0, position.1 - display.position.1);
    if display.position.0 != 0 || display.position.1 != 0 || x0 < 0 || y0 < 0 {
        return Err("the data window is not inside a display window starting at 0,0".into());
    }
    let window = PixelWindow {
        x0: x0 as u32,
        y0: y0 as u32,
        x1: x0 as u32 + size.0 as u32,
        y1: y0 as u32 + size.1 as u32,
    };
    if window.x1 > display_size.0 || window.y1 > display_size.1 {
        return Err("the data window is not inside the display window".into());
    }
    Ok((display_size, window))
}

/// Reads the part at `path`: its header and its sums, checked against their digest.
///
/// Errors (one line naming the file): not an EXR, truncated or corrupt, not a prisma render,
/// a render without sums (written without `--part`), sums missing, of the wrong size or not
/// matching their digest.
pub fn read_part(path: &Path) -> Result<Part, PartError> {
    let error = |problem: String| PartError { path: path.display().to_string(), problem };
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .pedantic()
        .from_file(path)
        .map_err(|e| error(exr_problem(e)))?;
    let layer = &image.layer_data;
    let (display, window) =
        windows(image.attributes.display_window, layer.attributes.layer_position, layer.size)
            .map_err(error)?;
    let attribute = |name: &str| {
        image
            .attributes
            .other
            .iter()
            .chain(layer.attributes.other.iter())
            .find(|(n, _)| *n == name)
            .map(|(_, v)| attribute_text(v))
    };
    let header = PartHeader::from_attributes(attribute, display).map_err(error)?;
    if header.window != window {
        return Err(error(format!("prisma.crop {} is not the data window {window}", header.window)));
    }
    match attribute("prisma.sumsFormat") {
        None => {
            return Err(error(
                "has no per-pixel sums: only renders made with --part, --samples, --crop or \
                 --resume (and interrupted ones) can be merged or resumed"
                    .into(),
            ))
        }
        Some(format) if format != SUMS_FORMAT => {
            return Err(error(format!("sums in format {format}, this prisma reads {SUMS_FORMAT}")))
        }
        Some(_) => {}
    }
    let layout = header.layout();
    let values = layout.values_per_pixel();
    let pixels = window.pixels();
    let channel = |name: &str| -> Result<&[u32], String> {
        let found = layer.channel_data.list.iter().find(|c| c.name.to_string() == name);
        match found.map(|c| &c.sample_data) {
            Some(FlatSamples::U32(words)) if words.len() == pixels => Ok(words.as_slice()),
            Some(_) => Err(format!("channel {name} is not 32-bit unsigned of {pixels} pixels")),
            None => Err(format!("channel {name} is missing")),
        }
    };
    // A word channel left out holds the implied word in every pixel (the digest below checks
    // that it was meant to be left out).
    let read_sums = |light: bool| -> Result<Vec<FixedSum>, String> {
        let mut sums = vec![FixedSum::ZERO; pixels * values];
        for value in 0..values {
            let words: Vec<Option<&[u32]>> = (0..6)
                .map(|word| match channel(&sum_channel_name(light, value, word)) {
                    Err(missing) if missing.ends_with("is missing") => Ok(None),
                    found => found.map(Some),
                })
                .collect::<Result<_, _>>()?;
            for pixel in 0..pixels {
                let mut pixel_words = [0u32; 6];
                for (w, channel) in words.iter().enumerate() {
                    pixel_words[w] = match channel {
                        Some(channel) => channel[pixel],
                        None => implied_word(&pixel_words, w),
                    };
                }
                sums[pixel * values + value] = FixedSum::from_words(pixel_words);
            }
        }
        Ok(sums)
    };
    let camera = read_sums(false).map_err(error)?;
    let light = if header.light_paths_per_pass > 0 { read_sums(true).map_err(error)? } else { Vec::new() };
    let sums = WindowSums::from_values(window, layout, camera, light)
        .ok_or_else(|| error("the sums do not match the window".into()))?;
    let digest =
        attribute("prisma.sumsSha256").ok_or_else(|| error("no prisma.sumsSha256 attribute".into()))?;
    if sums_digest(&sums) != digest {
        return Err(error("corrupt: the sums do not match their SHA-256 (prisma.sumsSha256)".into()));
    }
    Ok(Part { header, sums })
}
