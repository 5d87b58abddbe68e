//! Part files: a render's EXR (the image of its window, [`crate::output::exr`]) with its
//! per-pixel sums added as 32-bit unsigned channels, up to six per value (the words of a
//! [`FixedSum`], least significant first): `sums.c0000.w0` … `sums.c0000.w5` for the camera
//! samples' value 0 (XYZ of S0, then of S1–S3, then the bands, as
//! [`crate::film::FilmLayout::values_per_pixel`] orders them; a monochromatic render's radiance
//! in place of each XYZ), and `sums.l…` for the light
//! tracer's. A word channel is left out when every pixel's word is implied ([`implied_word`]):
//! zero for word 0, the sign extension of the word below for the others. Part files are written
//! uncompressed: compressing the sums cost more time than splitting a render may add. The
//! header ([`PartHeader`]) says which samples and window they hold, and `prisma.sumsBlake3` (of
//! the stored channels, names and words: [`sums_digest`])
//! guards them: a part whose sums do not match it is refused as corrupt. The header itself is
//! guarded by `prisma.headerBlake3` ([`super::header::header_digest`]), which covers
//! `prisma.sumsBlake3` too.
//!
//! **A part is input.** Before any pixel is read the file must be a regular file, its header
//! must check ([`PartHeader::from_attributes`]) and match its digest, and it must be
//! uncompressed scan lines whose pixels fit in the file's length ([`ExrSummary::check_size`]),
//! so that reading a part costs memory in proportion to its bytes, whatever its header claims.

use std::fs::File;
use std::io::{BufReader, Seek, SeekFrom};
use std::path::Path;

use ::exr::compression::Compression;
use ::exr::meta::attribute::AttributeValue;
use ::exr::meta::BlockDescription;
use ::exr::prelude::{read, FlatSamples, ReadChannels, ReadLayers};

use super::header::{header_digest, HEADER_DIGEST, SUMS_FORMAT};
use super::{PartHeader, PixelWindow};
use crate::film::WindowSums;
use crate::fixed::FixedSum;
use crate::printable::quote;
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

/// The camera-or-light flag, value and word of a channel named as [`sum_channel_name`] names
/// them (and only so: `sums.c00000.w0` is not value 0).
fn parse_sum_channel_name(name: &str) -> Option<(bool, usize, usize)> {
    let rest = name.strip_prefix("sums.")?;
    let light = match rest.as_bytes().first()? {
        b'c' => false,
        b'l' => true,
        _ => return None,
    };
    let (value, word) = rest.get(1..)?.split_once(".w")?;
    let (value, word): (usize, usize) = (value.parse().ok()?, word.parse().ok()?);
    (word < 6 && sum_channel_name(light, value, word) == name).then_some((light, value, word))
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

/// The word channels of `sums` as a part file stores them, in name order: each channel's
/// name and its words (one per pixel of the window), implied channels left out
/// ([`implied_word`]).
pub fn sum_channels(sums: &WindowSums) -> Vec<(String, Vec<u32>)> {
    let mut channels = Vec::new();
    for (light, values) in [(false, sums.camera()), (true, sums.light())] {
        if values.is_empty() {
            continue;
        }
        let stride = if light { sums.light_stride() } else { sums.stride() };
        // Channels are named by the value's index in the full layout (light sums of S0 alone
        // leave out S1–S3, whose channels would all be implied zeros).
        let index_of = |value: usize| if light { sums.light_value_index(value) } else { value };
        let pixels = values.len() / stride;
        // Which channels hold a word that is not implied: only those are built.
        let mut needed = vec![false; stride * 6];
        for sums in values.chunks_exact(stride) {
            for (value, sum) in sums.iter().enumerate() {
                let w = sum.to_words();
                for (k, &word) in w.iter().enumerate() {
                    needed[value * 6 + k] |= word != implied_word(&w, k);
                }
            }
        }
        let mut words: Vec<Option<Vec<u32>>> =
            needed.iter().map(|&needed| needed.then(|| Vec::with_capacity(pixels))).collect();
        for sums in values.chunks_exact(stride) {
            for (value, sum) in sums.iter().enumerate() {
                for (channel, word) in words[value * 6..value * 6 + 6].iter_mut().zip(sum.to_words()) {
                    if let Some(channel) = channel {
                        channel.push(word);
                    }
                }
            }
        }
        for (index, words) in words.into_iter().enumerate() {
            if let Some(words) = words {
                channels.push((sum_channel_name(light, index_of(index / 6), index % 6), words));
            }
        }
    }
    // Names sort as the EXR sorts its channels: the digest sees them in the file's order.
    channels.sort_by(|a, b| a.0.cmp(&b.0));
    channels
}

/// BLAKE3 (hex) of stored sum channels, in the given order: each channel's name, a zero byte,
/// and its words little-endian. Naming the channels makes a channel dropped, added or renamed
/// as visible as a word changed. (BLAKE3, not SHA-256 as for scenes: a merge hashes every part
/// and its result, hundreds of MB for an 800×450 render, and BLAKE3 did it about 5× faster
/// here; docs/farm.md.)
pub fn sums_digest<'a>(channels: impl IntoIterator<Item = (&'a str, &'a [u32])>) -> String {
    let mut hasher = blake3::Hasher::new();
    // Fed in large pieces: the hasher's SIMD paths want many kilobytes at a time.
    let mut bytes = Vec::with_capacity(1 << 16);
    for (name, words) in channels {
        hasher.update(name.as_bytes());
        hasher.update(&[0u8]);
        for chunk in words.chunks(1 << 14) {
            bytes.clear();
            bytes.extend(chunk.iter().flat_map(|word| word.to_le_bytes()));
            hasher.update(&bytes);
        }
    }
    hex(hasher.finalize().as_bytes())
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
    /// Bytes the pixels of every channel take decoded.
    pub decoded_bytes: u64,
    /// The file's length in bytes.
    pub file_bytes: u64,
    /// Stored uncompressed, in scan lines (as parts are).
    pub uncompressed_scanlines: bool,
}

/// The largest ratio of decoded to stored bytes an EXR's compression reaches (deflate's limit
/// is about 1032 to 1; the others' are lower), for [`ExrSummary::check_size`].
pub const MAX_COMPRESSION_RATIO: u64 = 1100;

/// What a header that does not match its digest is told.
pub const HEADER_ALTERED: &str =
    "corrupt: the header does not match its BLAKE3 digest (prisma.headerBlake3): \
     a prisma.* attribute, the display window or the data window was altered";

impl ExrSummary {
    /// Whether the `prisma.*` header matches its digest ([`header_digest`]); `None` when it has
    /// none (not a prisma render, or one of an earlier version).
    pub fn header_intact(&self) -> Option<bool> {
        let stored = self.attribute(HEADER_DIGEST)?;
        let attributes = self.attributes.iter().map(|(name, text)| (name.as_str(), text.as_str()));
        Some(stored == header_digest(attributes, self.display, self.window))
    }

    /// The text of attribute `name`.
    pub fn attribute(&self, name: &str) -> Option<String> {
        self.attributes.iter().find(|(n, _)| n == name).map(|(_, value)| value.clone())
    }

    /// Refuses an image whose pixels cannot be in the file: uncompressed, they must fit in its
    /// length; compressed, in [`MAX_COMPRESSION_RATIO`] times it. Decoding it then costs memory
    /// in proportion to the file, not to what its header claims (a 2 KB file claiming
    /// 20000×20000 pixels asked for 115 GB).
    pub fn check_size(&self) -> Result<(), String> {
        let (stored, bound) = if self.uncompressed_scanlines {
            ("uncompressed", self.file_bytes)
        } else {
            ("compressed", self.file_bytes.saturating_mul(MAX_COMPRESSION_RATIO))
        };
        if self.decoded_bytes > bound {
            return Err(format!(
                "truncated or corrupt: its {} pixels of {} channels take {} bytes, more than {} {stored} bytes hold",
                self.window.pixels(),
                self.channels.len(),
                self.decoded_bytes,
                self.file_bytes
            ));
        }
        Ok(())
    }
}

/// Opens `path` for reading if it is a regular file (a FIFO would block, a directory or device
/// is no image), with its length.
fn open_regular(path: &Path) -> Result<(File, u64), String> {
    let not_found = |e: std::io::Error| match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".to_string(),
        _ => format!("cannot be read ({e})"),
    };
    // Checked before opening: opening a FIFO for reading waits for a writer.
    if !std::fs::metadata(path).map_err(not_found)?.is_file() {
        return Err("is not a regular file (a directory, FIFO or device is not an image)".into());
    }
    let file = File::open(path).map_err(not_found)?;
    let meta = file.metadata().map_err(not_found)?;
    if !meta.is_file() {
        return Err("is not a regular file".into());
    }
    Ok((file, meta.len()))
}

/// Reads the header of the EXR at `path` (see [`ExrSummary`]), checked with
/// [`ExrSummary::check_size`].
pub fn read_summary(path: &Path) -> Result<ExrSummary, PartError> {
    let error = |problem: String| PartError { path: path.display().to_string(), problem };
    let (file, file_bytes) = open_regular(path).map_err(error)?;
    summary_of(&file, file_bytes).map_err(error)
}

/// The summary of the EXR open as `file`, of `file_bytes` bytes, read from its start.
fn summary_of(mut file: &File, file_bytes: u64) -> Result<ExrSummary, String> {
    file.seek(SeekFrom::Start(0)).map_err(|e| format!("cannot be read ({e})"))?;
    let meta = ::exr::meta::MetaData::read_from_buffered(BufReader::new(file), true).map_err(exr_problem)?;
    let header = meta.headers.first().ok_or_else(|| "no image in the file".to_string())?;
    let attributes = header
        .shared_attributes
        .other
        .iter()
        .chain(header.own_attributes.other.iter())
        .map(|(name, value)| (name.to_string(), attribute_text(value)))
        .collect();
    let display_window = header.shared_attributes.display_window;
    let (display, window) = windows(display_window, header.own_attributes.layer_position, header.layer_size)?;
    let channels = header.channels.list.iter().map(|c| c.name.to_string()).collect();
    let decoded_bytes = (window.pixels() as u64).saturating_mul(header.channels.bytes_per_pixel as u64);
    let uncompressed_scanlines = header.compression == Compression::Uncompressed
        && matches!(header.blocks, BlockDescription::ScanLines)
        && !header.deep
        && meta.headers.len() == 1;
    let summary = ExrSummary {
        attributes,
        display,
        window,
        channels,
        decoded_bytes,
        file_bytes,
        uncompressed_scanlines,
    };
    summary.check_size()?;
    Ok(summary)
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
        e => format!("not a readable EXR image ({})", quote(&e.to_string())),
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
    let stored = StoredPart::read(path)?;
    let header = stored.header.clone();
    let mut sums = WindowSums::new(header.window, header.layout(), header.light_paths_per_pass > 0);
    stored.add_to(&mut sums)?;
    Ok(Part { header, sums })
}

/// Reads the header of the part at `path` without its pixels: what [`read_part`] would say of
/// the file's header, so that parts can be checked against each other before any is read.
pub fn read_part_header(path: &Path) -> Result<PartHeader, PartError> {
    let error = |problem: String| PartError { path: path.display().to_string(), problem };
    let summary = read_summary(path)?;
    check_part_header(&summary).map_err(error)
}

/// The part header of the file `summary` describes, checked: every field
/// ([`PartHeader::from_attributes`]), the digest of the header, its crop against the data
/// window, the sums' format, and the storage a part has (uncompressed scan lines).
fn check_part_header(summary: &ExrSummary) -> Result<PartHeader, String> {
    let attribute = |name: &str| summary.attribute(name);
    if attribute("prisma.sumsFormat").is_none() {
        return Err("has no per-pixel sums: only renders made with --part, --samples, --crop or \
                     --resume (and interrupted ones) can be merged or resumed"
            .into());
    }
    match attribute("prisma.sumsFormat") {
        Some(format) if format != SUMS_FORMAT => {
            return Err(format!("sums in format {}, this prisma reads {SUMS_FORMAT}", quote(&format)))
        }
        _ => {}
    }
    match summary.header_intact() {
        None => return Err(format!("no {HEADER_DIGEST} attribute (written by an older prisma, or altered)")),
        Some(false) => return Err(HEADER_ALTERED.into()),
        Some(true) => {}
    }
    if !summary.uncompressed_scanlines {
        return Err("is compressed or tiled: prisma writes parts as uncompressed scan lines".into());
    }
    let header = PartHeader::from_attributes(attribute, summary.display)?;
    if header.window != summary.window {
        return Err(format!("prisma.crop {} is not the data window {}", header.window, summary.window));
    }
    Ok(header)
}

/// A part file read and checked, its sums still as the file stores them (word channels):
/// [`StoredPart::add_to`] adds them to other sums without building the part's own.
pub struct StoredPart {
    /// The file, for messages.
    path: String,
    /// Its header.
    pub header: PartHeader,
    /// The stored sum channels: (camera or light, value, word) and the words of every pixel.
    channels: Vec<((bool, usize, usize), Vec<u32>)>,
}

impl StoredPart {
    /// Reads the part at `path` and checks it as [`read_part`] does.
    pub fn read(path: &Path) -> Result<Self, PartError> {
        let name = path.display().to_string();
        let error = |problem: String| PartError { path: name.clone(), problem };
        // One open file for the header's checks and the pixels, so that what was checked is what
        // is read.
        let (file, file_bytes) = open_regular(path).map_err(error)?;
        let summary = summary_of(&file, file_bytes).map_err(error)?;
        let header = check_part_header(&summary).map_err(error)?;
        let digest = summary
            .attribute("prisma.sumsBlake3")
            .ok_or_else(|| error("no prisma.sumsBlake3 attribute".into()))?;
        let mut reader = BufReader::new(&file);
        reader.seek(SeekFrom::Start(0)).map_err(|e| error(format!("cannot be read ({e})")))?;
        let image = read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .first_valid_layer()
            .all_attributes()
            .pedantic()
            .from_buffered(reader)
            .map_err(|e| error(exr_problem(e)))?;
        let mut layer = image.layer_data;
        let (display, window) =
            windows(image.attributes.display_window, layer.attributes.layer_position, layer.size)
                .map_err(error)?;
        if (display, window) != (summary.display, summary.window) {
            return Err(error("changed while being read".into()));
        }
        // The stored sum channels, in the file's order: the digest first, then their names.
        let pixels = window.pixels();
        let mut stored = Vec::new();
        for channel in std::mem::take(&mut layer.channel_data.list) {
            let name = channel.name.to_string();
            if !name.starts_with("sums.") {
                continue;
            }
            match channel.sample_data {
                FlatSamples::U32(words) if words.len() == pixels => stored.push((name, words)),
                _ => return Err(error(format!("channel {name} is not 32-bit unsigned of {pixels} pixels"))),
            }
        }
        if sums_digest(stored.iter().map(|(name, words)| (name.as_str(), words.as_slice()))) != digest {
            return Err(error(
                "corrupt: the sums do not match their BLAKE3 digest (prisma.sumsBlake3)".into(),
            ));
        }
        let values = header.layout().values_per_pixel();
        let has_light = header.light_paths_per_pass > 0;
        let channels = stored
            .into_iter()
            .map(|(name, words)| match parse_sum_channel_name(&name) {
                Some((true, _, _)) if !has_light => Err(error(format!(
                    "channel {name} holds light-tracer sums but prisma.lightPathsPerPass is 0"
                ))),
                Some(key) if key.1 < values => Ok((key, words)),
                Some(_) => Err(error(format!("channel {name} is beyond the {values} values per pixel"))),
                None => Err(error(format!(
                    "channel {} is not a sum channel of format {SUMS_FORMAT}",
                    quote(&name)
                ))),
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { path: name, header, channels })
    }

    /// Adds the part's sums to `sums`, whose window must hold the part's and whose layout must
    /// be the part's (parts of one render). A word channel left out holds the implied word in
    /// every pixel ([`implied_word`]; the digest, which names the channels, says that it was
    /// left out when written).
    pub fn add_to(&self, sums: &mut WindowSums) -> Result<(), PartError> {
        let values = self.header.layout().values_per_pixel();
        let has_light = self.header.light_paths_per_pass > 0;
        for light in [false, true].into_iter().filter(|&light| !light || has_light) {
            let mut words: Vec<[Option<&[u32]>; 6]> = vec![[None; 6]; values];
            for ((kind, value, word), data) in &self.channels {
                if *kind == light {
                    words[*value][*word] = Some(data);
                }
            }
            // The sums' own numbering of values (light values by their slot) to the file's.
            let count = if light { sums.light_stride() } else { sums.stride() };
            let index_of: Vec<usize> =
                (0..count).map(|slot| if light { sums.light_value_index(slot) } else { slot }).collect();
            if light {
                if let Some(((_, value, _), _)) = self.channels.iter().find(|((kind, value, _), data)| {
                    *kind && !index_of.contains(value) && data.iter().any(|&word| word != 0)
                }) {
                    return Err(PartError {
                        path: self.path.clone(),
                        problem: format!("light value {value} is polarised where this render's light is not"),
                    });
                }
            }
            let sum = |pixel: usize, slot: usize| {
                let value = index_of[slot];
                let mut pixel_words = [0u32; 6];
                for (w, channel) in words[value].iter().enumerate() {
                    pixel_words[w] = match channel {
                        Some(channel) => channel[pixel],
                        None => implied_word(&pixel_words, w),
                    };
                }
                FixedSum::from_words(pixel_words)
            };
            sums.add_with(self.header.window, light, sum)
                .map_err(|e| PartError { path: self.path.clone(), problem: e.to_string() })?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_names_parse_only_as_written() {
        assert_eq!(parse_sum_channel_name("sums.c0003.w2"), Some((false, 3, 2)));
        assert_eq!(parse_sum_channel_name("sums.l0012.w5"), Some((true, 12, 5)));
        for name in ["sums.c00003.w2", "sums.c0003.w6", "sums.x0003.w2", "sums.c3.w2", "S0.R", "sums.c0003"] {
            assert_eq!(parse_sum_channel_name(name), None, "{name}");
        }
    }

    #[test]
    fn the_digest_sees_a_word_a_name_and_a_channel_dropped() {
        let (a, b) = (vec![1u32, 2, 3], vec![0u32, 7, 0]);
        let digest = |channels: &[(&str, &[u32])]| sums_digest(channels.iter().copied());
        let base = digest(&[("sums.c0000.w0", &a), ("sums.c0000.w1", &b)]);
        let mut changed = b.clone();
        changed[1] ^= 1 << 20;
        for other in [
            digest(&[("sums.c0000.w0", &a), ("sums.c0000.w1", &changed)]),
            digest(&[("sums.c0000.w0", &a), ("sums.c0000.w2", &b)]),
            digest(&[("sums.c0000.w0", &a)]),
            // Words moved across the boundary of two channels.
            digest(&[("sums.c0000.w0", &a[..2]), ("sums.c0000.w1", &[3, 0, 7, 0])]),
        ] {
            assert_ne!(other, base);
        }
        assert_eq!(digest(&[("sums.c0000.w0", &a), ("sums.c0000.w1", &b)]), base);
    }

    #[test]
    fn stored_channels_leave_implied_words_out_and_keep_the_rest() {
        let layout = crate::film::FilmLayout { stokes: false, bands: None, monochromatic_nm: None };
        let window = PixelWindow { x0: 0, y0: 0, x1: 2, y1: 1 };
        let mut sums = WindowSums::new(window, layout, false);
        let values = [0.5, -0.25, 3.0, 1.0, 2.0, 7.5];
        for (sum, value) in sums.camera_mut().iter_mut().zip(values) {
            *sum = FixedSum::from_f64(value).expect("representable");
        }
        let channels = sum_channels(&sums);
        let names: Vec<&str> = channels.iter().map(|(name, _)| name.as_str()).collect();
        // In 2⁻⁶⁴ quanta: 0.5 and 7.5 set word 1, whole numbers word 2; -0.25's words above 1
        // are the sign extension of word 1 (implied), and no value has bits in word 0.
        assert_eq!(
            names,
            [
                "sums.c0000.w1",
                "sums.c0000.w2",
                "sums.c0001.w1",
                "sums.c0001.w2",
                "sums.c0002.w1",
                "sums.c0002.w2"
            ]
        );
        let word = |name: &str| &channels.iter().find(|(n, _)| n == name).expect("stored").1;
        assert_eq!(word("sums.c0001.w1"), &[0xC000_0000, 0]);
        assert_eq!(word("sums.c0001.w2"), &[u32::MAX, 2]);
        assert_eq!(word("sums.c0002.w2"), &[3, 7]);
    }
}
