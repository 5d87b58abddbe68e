//! OpenEXR output through the `exr` crate: one part of 32-bit float channels.
//!
//! A colour render holds R, G, B, A (linear sRGB: Rec. 709 primaries, D65 white, declared in the
//! `chromaticities` attribute) and an `XYZ` layer (`XYZ.X`, `XYZ.Y`, `XYZ.Z`, CIE 1931 with
//! Y = 1 for an equal-energy radiance of 1 W·m⁻²·sr⁻¹·nm⁻¹). A polarised one adds the Stokes
//! layers `S0`–`S3` with channels R, G, B each, as Mitsuba 3's `stokes` integrator writes them
//! (S0 equals the RGB image; S1–S3 are signed, in the frame of
//! [`crate::camera::Camera::stokes_x`]).
//!
//! Spectral output follows the OpenEXR spectral layout of Fichet, Pacanowski and Wilkie (JCGT
//! 10(3), 2021): channels `S<k>.<λ>nm` with a comma as decimal separator
//! (`S0.560,000000nm`), one per band and Stokes component, each the mean spectral radiance
//! over its band (W·m⁻²·sr⁻¹·nm⁻¹, although the layout's `emissiveUnits` attribute only knows
//! "W.m^-2.sr^-1"), with the attributes `spectralLayoutVersion` = "1.0", `emissiveUnits` and,
//! when polarised, `polarisationHandedness` = "right" (S3 > 0: the field turns clockwise for
//! the receiver). A monochromatic render is written as what it is: only the channels
//! `S<k>.<λ>nm` of its one wavelength, and the wavelength in the attribute `wavelengthNm`.
//!
//! A crop's data window is its pixel window and its display window the whole image. A render's
//! provenance goes in `prisma.*` text attributes ([`crate::part::header`]), and a part's exact
//! sums in `sums.*` 32-bit unsigned channels ([`crate::part::file`]).

use std::path::Path;

use ::exr::compression::Compression;
use ::exr::image::Blocks;
use ::exr::meta::attribute::{AttributeValue, Chromaticities, IntegerBounds, LineOrder, Text};
use ::exr::prelude::{
    read_all_flat_layers_from_file, AnyChannel, AnyChannels, Encoding, FlatSamples, Image, ImageAttributes,
    Layer, LayerAttributes, Vec2, WritableImage,
};
use glam::Vec3;

use super::file::{write_file, Sink};
use super::OutputError;
use crate::film::{Film, WindowSums};
use crate::part::file::{sum_channels, sums_digest};
use crate::part::header::{header_digest, HEADER_DIGEST, SUMS_FORMAT};
use crate::part::{PartHeader, PixelWindow};

/// The Fichet et al. channel name of Stokes component `k` at `lambda_nm`: `S0.560,000000nm`.
pub fn spectral_channel_name(k: usize, lambda_nm: f32) -> String {
    format!("S{k}.{}nm", format!("{lambda_nm:.6}").replace('.', ","))
}

/// The first two bands of `bands` (by number) whose channels would have the same name (centres
/// closer than the names' 10⁻⁶ nm, or equal in f32), with that name: bands that EXR cannot
/// store, refused before rendering. Names of S0, as the writer makes them; S1–S3's differ from
/// each other exactly when S0's do.
pub fn shared_band_name(bands: &crate::film::SpectralBands) -> Option<(usize, usize, String)> {
    let mut seen = std::collections::HashMap::new();
    (0..bands.count).find_map(|band| {
        let name = spectral_channel_name(0, bands.center_nm(band));
        seen.insert(name.clone(), band).map(|earlier| (earlier, band, name))
    })
}

/// Writes `film` to an EXR file at `path` (the layout is in the module documentation).
pub fn write_exr(path: &Path, film: &Film) -> Result<(), OutputError> {
    write_file(path, |sink| encode_exr(sink, path, film))
}

/// The EXR file of [`write_exr`] into `sink` (to stage it with other outputs,
/// [`super::file::Outputs::stage`]); errors name `path`.
pub fn encode_exr(sink: &mut Sink, path: &Path, film: &Film) -> Result<(), OutputError> {
    encode_exr_part(sink, path, film, None, None)
}

/// [`encode_exr`] with a render's provenance `header` (`prisma.*` attributes,
/// [`crate::part::header`]) and, for a part, its per-pixel `sums` ([`crate::part::file`]).
/// The data window is the film's window, the display window the whole image.
pub fn encode_exr_part(
    sink: &mut Sink,
    path: &Path,
    film: &Film,
    header: Option<&PartHeader>,
    sums: Option<&WindowSums>,
) -> Result<(), OutputError> {
    let layout = *film.layout();
    let components = layout.components();
    let vec3_channel = |name: String, values: &[Vec3], component: usize| {
        AnyChannel::new(name.as_str(), FlatSamples::F32(values.iter().map(|v| v[component]).collect()))
    };
    let mut channels: smallvec::SmallVec<[AnyChannel<FlatSamples>; 4]> = smallvec::SmallVec::new();
    let mut attributes: Vec<(&str, AttributeValue)> = Vec::new();
    if let Some(lambda_nm) = layout.monochromatic_nm {
        for k in 0..components {
            if let Some(xyz) = film.stokes_xyz(k) {
                channels.push(vec3_channel(spectral_channel_name(k, lambda_nm), &xyz, 0));
            }
        }
        attributes.push(("wavelengthNm", AttributeValue::F32(lambda_nm)));
    } else {
        let rgb = film.linear_srgb();
        for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
            channels.push(vec3_channel(name.into(), &rgb, c));
        }
        channels.push(AnyChannel::new("A", FlatSamples::F32(vec![1.0; rgb.len()])));
        for (c, name) in ["XYZ.X", "XYZ.Y", "XYZ.Z"].into_iter().enumerate() {
            channels.push(vec3_channel(name.into(), film.xyz(), c));
        }
        if layout.stokes {
            for k in 0..4 {
                if let Some(stokes) = film.stokes_srgb(k) {
                    for (c, colour) in ["R", "G", "B"].into_iter().enumerate() {
                        channels.push(vec3_channel(format!("S{k}.{colour}"), &stokes, c));
                    }
                }
            }
        }
        if let Some(bands) = layout.bands {
            for k in 0..components {
                for band in 0..bands.count {
                    if let Some(values) = film.band(k, band) {
                        channels.push(AnyChannel::new(
                            spectral_channel_name(k, bands.center_nm(band)).as_str(),
                            FlatSamples::F32(values),
                        ));
                    }
                }
            }
        }
    }
    if layout.monochromatic_nm.is_some() || layout.bands.is_some() {
        attributes.push(("spectralLayoutVersion", AttributeValue::Text(Text::from("1.0"))));
        attributes.push(("emissiveUnits", AttributeValue::Text(Text::from("W.m^-2.sr^-1"))));
        if layout.stokes {
            attributes.push(("polarisationHandedness", AttributeValue::Text(Text::from("right"))));
        }
    }
    let mut texts: Vec<(&str, String)> = header.map(PartHeader::attributes).unwrap_or_default();
    if let Some(sums) = sums {
        texts.push(("prisma.sumsFormat", SUMS_FORMAT.to_owned()));
        let stored = sum_channels(sums);
        texts
            .push(("prisma.sumsBlake3", sums_digest(stored.iter().map(|(n, w)| (n.as_str(), w.as_slice())))));
        for (name, words) in stored {
            channels.push(AnyChannel::new(name.as_str(), FlatSamples::U32(words)));
        }
    }
    let (x0, y0) = film.origin();
    if header.is_some() {
        let window = PixelWindow { x0, y0, x1: x0 + film.width(), y1: y0 + film.height() };
        let digest = header_digest(texts.iter().map(|(n, t)| (*n, t.as_str())), film.display(), window);
        texts.push((HEADER_DIGEST, digest));
    }
    for (name, text) in texts {
        attributes.push((name, AttributeValue::Text(Text::from(text.as_str()))));
    }
    let layer = Layer::new(
        (film.width() as usize, film.height() as usize),
        LayerAttributes { layer_position: Vec2(x0 as i32, y0 as i32), ..LayerAttributes::default() },
        // Blocks in increasing order: with the default unspecified order the crate writes the
        // blocks it compresses in parallel as they finish, so two writes of one image differed.
        // A part is written uncompressed: its sums (up to six 32-bit words per value) took
        // longer to compress and decompress than the render saved by splitting (docs/farm.md).
        match sums {
            None => Encoding { line_order: LineOrder::Increasing, ..Encoding::FAST_LOSSLESS },
            Some(_) => Encoding {
                compression: Compression::Uncompressed,
                blocks: Blocks::ScanLines,
                line_order: LineOrder::Increasing,
            },
        },
        AnyChannels::sort(channels),
    );
    let (display_width, display_height) = film.display();
    let mut image = Image::new(
        ImageAttributes::new(IntegerBounds::from_dimensions((
            display_width as usize,
            display_height as usize,
        ))),
        layer,
    );
    if layout.monochromatic_nm.is_none() {
        image.attributes.chromaticities = Some(Chromaticities {
            red: Vec2(0.64, 0.33),
            green: Vec2(0.30, 0.60),
            blue: Vec2(0.15, 0.06),
            white: Vec2(0.3127, 0.3290),
        });
    }
    for (name, value) in attributes {
        image.attributes.other.insert(Text::from(name), value);
    }
    image.write().to_buffered(sink).map_err(|e| match e {
        ::exr::error::Error::Io(source) => OutputError::Io { path: path.display().to_string(), source },
        e => OutputError::Codec { path: path.display().to_string(), message: e.to_string() },
    })
}

/// An EXR read back: size and the named channels.
#[derive(Debug, Clone)]
pub struct ExrImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    channels: Vec<(String, Vec<f32>)>,
    attributes: Vec<(String, String)>,
}

impl ExrImage {
    /// The samples of channel `name` (row-major, top row first).
    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_slice())
    }
    /// Names of every channel, sorted.
    pub fn channel_names(&self) -> impl Iterator<Item = &str> {
        self.channels.iter().map(|(n, _)| n.as_str())
    }
    /// The header attribute `name` (image-wide or of the layer) as text, if present: a text
    /// attribute as it is, a number in Rust's shortest form, anything else in debug form.
    pub fn attribute(&self, name: &str) -> Option<&str> {
        self.attributes.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_str())
    }
    /// Pixels of the channels `names[0..3]` as vectors.
    pub fn rgb(&self, names: [&str; 3]) -> Option<Vec<Vec3>> {
        let [r, g, b] = names.map(|n| self.channel(n));
        let (r, g, b) = (r?, g?, b?);
        Some((0..r.len()).map(|i| Vec3::new(r[i], g[i], b[i])).collect())
    }
}

/// Reads every channel of the first layer of an EXR file as 32-bit floats.
pub fn read_exr(path: &Path) -> Result<ExrImage, OutputError> {
    let codec = |e: ::exr::error::Error| OutputError::Codec {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let image = read_all_flat_layers_from_file(path).map_err(codec)?;
    let layer = image
        .layer_data
        .first()
        .ok_or_else(|| OutputError::Codec { path: path.display().to_string(), message: "no layer".into() })?;
    let size = layer.size;
    let channels = layer
        .channel_data
        .list
        .iter()
        .map(|c| {
            let name = c.name.to_string();
            let values = match &c.sample_data {
                FlatSamples::F16(v) => v.iter().map(|x| x.to_f32()).collect(),
                FlatSamples::F32(v) => v.clone(),
                FlatSamples::U32(v) => v.iter().map(|&x| x as f32).collect(),
            };
            (name, values)
        })
        .collect();
    let attributes = image
        .attributes
        .other
        .iter()
        .chain(layer.attributes.other.iter())
        .map(|(name, value)| {
            let text = match value {
                AttributeValue::Text(text) => text.to_string(),
                AttributeValue::F32(number) => number.to_string(),
                other => format!("{other:?}"),
            };
            (name.to_string(), text)
        })
        .collect();
    Ok(ExrImage { width: size.0 as u32, height: size.1 as u32, channels, attributes })
}
