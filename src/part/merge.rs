//! [`merge`]: parts of one render added into the part of their union.
//!
//! Parts belong together when they come from the same renderer (version and commit), scene
//! (SHA-256), seed, image size and settings. Their windows must be equal or disjoint; parts of
//! one window must hold disjoint samples, and every window the same samples in all, so that
//! every pixel of the result has the same samples; the windows must tile a rectangle. The sums
//! are added exactly ([`crate::fixed::FixedSum`]): any number, grouping and order of parts
//! gives the same bits, those of the single render of the union.

use std::path::PathBuf;

use super::file::{read_part_header, PartError, StoredPart};
use super::{Part, PartHeader, PixelWindow, SampleSet};
use crate::film::WindowSums;

/// Why parts cannot be merged: one line naming the file(s).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct MergeError(pub String);

/// Adds `parts` (each with the file it came from, for messages) into one part. With
/// `complete`, the result must be the whole render: every pixel and samples `0..spp`.
pub fn merge(parts: &[(PathBuf, Part)], complete: bool) -> Result<Part, MergeError> {
    let headers: Vec<(&PathBuf, &PartHeader)> =
        parts.iter().map(|(path, part)| (path, &part.header)).collect();
    let header = plan(&headers, complete)?;
    let mut sums = WindowSums::new(header.window, header.layout(), header.light_paths_per_pass > 0);
    for (path, part) in parts {
        sums.add(&part.sums).map_err(|e| MergeError(format!("{}: {e}", path.display())))?;
    }
    Ok(Part { header, sums })
}

/// [`merge`] of the part files `paths`: their headers are read and checked first, then one
/// file after another is read and added, so that a merge holds one part's sums at a time
/// besides the result. Errors name the file.
pub fn merge_files(paths: &[PathBuf], complete: bool) -> Result<Part, MergeError> {
    let problem = |e: PartError| MergeError(e.to_string());
    let headers = paths
        .iter()
        .map(|path| read_part_header(path).map(|header| (path, header)))
        .collect::<Result<Vec<_>, _>>()
        .map_err(problem)?;
    let header = plan(&headers.iter().map(|(path, header)| (*path, header)).collect::<Vec<_>>(), complete)?;
    check_memory(&header)?;
    let mut sums = WindowSums::new(header.window, header.layout(), header.light_paths_per_pass > 0);
    for (path, expected) in &headers {
        let part = StoredPart::read(path).map_err(problem)?;
        if part.header != *expected {
            return Err(MergeError(format!("{}: changed while being merged", path.display())));
        }
        part.add_to(&mut sums).map_err(problem)?;
    }
    Ok(Part { header, sums })
}

/// Refuses a merge whose sums and image cannot fit in the memory this process may use
/// ([`crate::memory::available`]), before allocating them: the sums (camera and light, a
/// [`FixedSum`](crate::fixed::FixedSum) per value), the image (f32 per value and its sRGB
/// copies) and one part's channels at a time (up to six words per value and pixel).
fn check_memory(header: &PartHeader) -> Result<(), MergeError> {
    let values = header.layout().values_per_pixel() as u64;
    let sums = if header.light_paths_per_pass > 0 { 2 } else { 1 };
    let fixed = std::mem::size_of::<crate::fixed::FixedSum>() as u64;
    let per_pixel = values * (sums * fixed + 4 + sums * 24) + 64;
    let needed = (header.window.pixels() as u64).saturating_mul(per_pixel);
    let (width, height) = (header.window.width(), header.window.height());
    crate::memory::check(width, height, needed).map_err(|e| MergeError(format!("merging the parts: {e}")))
}

/// Checks that the parts with headers `parts` merge (see the module) and returns the header of
/// their union; with `complete`, that they make the whole render.
fn plan(parts: &[(&PathBuf, &PartHeader)], complete: bool) -> Result<PartHeader, MergeError> {
    let fail = |message: String| Err(MergeError(message));
    let Some((first_path, first)) = parts.first() else { return fail("no parts to merge".into()) };
    let name = |path: &PathBuf| path.display().to_string();
    for (path, part) in &parts[1..] {
        if let Some((what, mine, theirs)) = first.mismatch(part) {
            return fail(format!(
                "{}: a different {what} from {}'s ({theirs} vs {mine}): parts of different renders do not merge",
                name(path),
                name(first_path)
            ));
        }
    }
    // No pixel sample in two parts.
    for (i, (path_a, a)) in parts.iter().enumerate() {
        for (path_b, b) in &parts[i + 1..] {
            let (wa, wb) = (a.window, b.window);
            if wa.overlaps(&wb) && a.samples.overlaps(&b.samples) {
                return fail(format!(
                    "{} and {}: overlapping parts: samples {} of window {wa} and samples {} of window {wb}",
                    name(path_a),
                    name(path_b),
                    a.samples,
                    b.samples
                ));
            }
        }
    }
    // Every pixel of the bounding rectangle gets the same samples: checked on the cells that
    // the windows' edges cut the rectangle into.
    let bounds = parts.iter().skip(1).fold(first.window, |b, (_, p)| b.bounding(&p.window));
    let edges = |pick: fn(&PixelWindow) -> [u32; 2]| {
        let mut edges: Vec<u32> = parts.iter().flat_map(|(_, p)| pick(&p.window)).collect();
        edges.sort_unstable();
        edges.dedup();
        edges
    };
    let (xs, ys) = (edges(|w| [w.x0, w.x1]), edges(|w| [w.y0, w.y1]));
    let mut reference: Option<(SampleSet, PixelWindow)> = None;
    for y in ys.windows(2) {
        for x in xs.windows(2) {
            let cell = PixelWindow { x0: x[0], y0: y[0], x1: x[1], y1: y[1] };
            let samples = parts
                .iter()
                .filter(|(_, p)| p.window.contains_window(&cell))
                .fold(SampleSet::default(), |set, (_, p)| set.union(&p.samples));
            match &reference {
                None => reference = Some((samples, cell)),
                Some((expected, _)) if samples.is_empty() => {
                    return fail(format!(
                        "the parts leave pixels {cell} out: their windows must cover a rectangle ({bounds}); \
                         the others have samples {expected}"
                    ))
                }
                Some((expected, at)) if samples != *expected => {
                    return fail(format!(
                        "pixels {cell} would have samples {samples} but pixels {at} have {expected}: \
                         every pixel needs the same samples"
                    ))
                }
                Some(_) => {}
            }
        }
    }
    let samples = reference.map(|(samples, _)| samples).unwrap_or_default();
    let spp = parts.iter().map(|(_, p)| p.spp).max().unwrap_or(0);
    if complete {
        let (width, height) = first.display;
        if bounds != PixelWindow::full(width, height) {
            return fail(format!(
                "--complete: the parts cover the window {bounds}, not the whole {width}×{height} image"
            ));
        }
        let missing = samples.missing_below(spp);
        if !missing.is_empty() {
            return fail(format!("--complete: samples {missing} of 0..{spp} are missing"));
        }
    }
    Ok(PartHeader {
        samples,
        spp,
        window: bounds,
        wall_seconds: parts.iter().map(|(_, p)| p.wall_seconds).sum(),
        threads: parts.iter().map(|(_, p)| p.threads).max().unwrap_or(0),
        parts: parts
            .iter()
            .try_fold(0u32, |total, (_, p)| total.checked_add(p.parts))
            .ok_or_else(|| MergeError("the parts count more than 4294967295 merged parts".into()))?,
        ..(*first).clone()
    })
}
