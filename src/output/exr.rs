//! OpenEXR output through the `exr` crate: one part, 32-bit float channels R, G, B, A (linear
//! sRGB: Rec. 709 primaries, D65 white, declared in the `chromaticities` attribute) and an `XYZ`
//! layer (channels `XYZ.X`, `XYZ.Y`, `XYZ.Z`, CIE 1931 with Y = 1 for an equal-energy radiance of
//! 1 W·m⁻²·sr⁻¹·nm⁻¹). In a monochromatic render every channel holds the spectral radiance.

use std::path::Path;

use ::exr::meta::attribute::{Chromaticities, LineOrder};
use ::exr::prelude::{
    read_all_flat_layers_from_file, AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer,
    LayerAttributes, Vec2, WritableImage,
};
use glam::Vec3;

use super::file::{write_file, Sink};
use super::OutputError;

/// Writes `rgb` (linear sRGB) and `xyz` (row-major, top row first) to an EXR file.
pub fn write_exr(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[Vec3],
    xyz: &[Vec3],
) -> Result<(), OutputError> {
    write_file(path, |sink| encode_exr(sink, path, width, height, rgb, xyz))
}

/// The EXR file of [`write_exr`] into `sink` (to stage it with other outputs,
/// [`super::file::Outputs::stage`]); errors name `path`.
pub fn encode_exr(
    sink: &mut Sink,
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[Vec3],
    xyz: &[Vec3],
) -> Result<(), OutputError> {
    let channel = |name: &str, values: &[Vec3], component: usize| {
        AnyChannel::new(name, FlatSamples::F32(values.iter().map(|v| v[component]).collect()))
    };
    let channels = AnyChannels::sort(smallvec::smallvec![
        channel("R", rgb, 0),
        channel("G", rgb, 1),
        channel("B", rgb, 2),
        AnyChannel::new("A", FlatSamples::F32(vec![1.0; rgb.len()])),
        channel("XYZ.X", xyz, 0),
        channel("XYZ.Y", xyz, 1),
        channel("XYZ.Z", xyz, 2),
    ]);
    let layer = Layer::new(
        (width as usize, height as usize),
        LayerAttributes::default(),
        // Blocks in increasing order: with the default unspecified order the crate writes the
        // blocks it compresses in parallel as they finish, so two writes of one image differed.
        Encoding { line_order: LineOrder::Increasing, ..Encoding::FAST_LOSSLESS },
        channels,
    );
    let mut image = Image::from_layer(layer);
    image.attributes.chromaticities = Some(Chromaticities {
        red: Vec2(0.64, 0.33),
        green: Vec2(0.30, 0.60),
        blue: Vec2(0.15, 0.06),
        white: Vec2(0.3127, 0.3290),
    });
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
}

impl ExrImage {
    /// The samples of channel `name` (row-major, top row first).
    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_slice())
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
    Ok(ExrImage { width: size.0 as u32, height: size.1 as u32, channels })
}
