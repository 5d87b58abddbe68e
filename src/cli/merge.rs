//! `prisma merge`: parts of a split render (sample ranges, crops, interrupted and resumed runs)
//! added into one EXR, bit-identical to the single render of their union ([`prisma::part`]),
//! with a PNG preview beside it as a render has.
//!
//! The merged EXR keeps the exact sums (it is a part: it can be merged again or resumed),
//! except with `--complete`, where it is the finished image and is written as a render writes
//! one (image channels and provenance, a tenth of the size) unless `--keep-sums`.

use std::path::PathBuf;

use anyhow::{anyhow, Context};
use clap::Args;

use super::destinations::Destinations;
use super::{say, CliError};
use prisma::output::exr::encode_exr_part;
use prisma::output::file::{check_not_inputs, check_regular_input, same_file, Outputs};
use prisma::output::png::encode_png;
use prisma::part::merge_files;

/// Arguments of `prisma merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The parts: EXRs written by `prisma render` with --samples, --crop, --part or --resume, or
    /// by an interrupted render, in any order.
    #[arg(required = true, value_name = "PART.exr")]
    parts: Vec<PathBuf>,
    /// The merged EXR: a part (it can be merged again or resumed), or with --complete the
    /// finished image.
    #[arg(short, long, value_name = "OUT.exr")]
    output: PathBuf,
    /// PNG preview path [default: the EXR path with a .png extension].
    #[arg(long, value_name = "OUT.png")]
    preview: Option<PathBuf>,
    /// Exposure of the PNG preview in stops (the EXR is never scaled).
    #[arg(long, default_value_t = 0.0, value_name = "STOPS", allow_negative_numbers = true)]
    exposure: f32,
    /// Refuse unless the parts make the whole render (every pixel, samples 0..spp), and write
    /// the finished image without the per-pixel sums.
    #[arg(long)]
    complete: bool,
    /// With --complete, keep the per-pixel sums too (to add samples later with --resume).
    #[arg(long, requires = "complete")]
    keep_sums: bool,
    /// Do not print the summary.
    #[arg(short, long)]
    quiet: bool,
}

/// Runs `prisma merge`.
pub fn run(args: &MergeArgs) -> Result<(), CliError> {
    let input = CliError::Input;
    let destinations = Destinations::check(&args.output, args.preview.as_deref(), None)?;
    for path in &args.parts {
        check_regular_input(path, "the part being merged").map_err(|e| input(anyhow!(e)))?;
    }
    let parts: Vec<(&std::path::Path, &str)> =
        args.parts.iter().map(|part| (part.as_path(), "the part being merged")).collect();
    check_not_inputs(destinations.named(), &parts).map_err(|e| input(e.into()))?;
    for (i, path) in args.parts.iter().enumerate() {
        if args.parts[..i].iter().any(|earlier| same_file(earlier, path)) {
            return Err(input(anyhow!("{}: given twice (its samples would count twice)", path.display())));
        }
    }
    keep_freed_memory();
    let merged = merge_files(&args.parts, args.complete).map_err(|e| input(e.into()))?;
    let header = &merged.header;
    let film = merged.sums.film(header.samples.len(), header.light_paths_per_pass, header.display);
    film.check_finite().map_err(|e| input(anyhow::Error::from(e).context("the merged image")))?;
    let sums = (!args.complete || args.keep_sums).then_some(&merged.sums);
    let rgb = film.linear_srgb();
    let (width, height) = (header.window.width(), header.window.height());
    let mut outputs = Outputs::new();
    outputs
        .stage(&destinations.exr, |sink| encode_exr_part(sink, &destinations.exr, &film, Some(header), sums))
        .and_then(|()| match &destinations.preview {
            Some(png) => outputs.stage(png, |sink| encode_png(sink, png, width, height, &rgb, args.exposure)),
            None => Ok(()),
        })
        .and_then(|()| outputs.commit())
        .context("writing the merged image (nothing was written)")
        .map_err(CliError::Failed)?;
    if !args.quiet {
        let what = if sums.is_some() { "a part, with its sums" } else { "the finished image" };
        let mut wrote = vec![destinations.exr.display().to_string()];
        wrote.extend(destinations.preview.iter().map(|p| p.display().to_string()));
        say!(
            "merged {} parts: samples {} of 0..{}, window {} of {}×{} → {} ({what})",
            args.parts.len(),
            header.samples,
            header.spp,
            header.window,
            header.display.0,
            header.display.1,
            wrote.join(", ")
        );
    }
    Ok(())
}

/// Asks the allocator to keep the memory of one part for the next instead of returning it to
/// the kernel: a part's decoded channels (dozens of buffers of 0.7 MB and more, above glibc's
/// initial mmap threshold of 128 KiB) were returned when freed and the next part's faulted in
/// again page by page; keeping them cut the showcase merge's system time from 0.45 to 0.16 s.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only changes glibc's allocation policy; it is called before any of the
    // merge's allocations, from the one thread that allocates, and a refusal (0) is harmless.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, i32::MAX);
        libc::mallopt(libc::M_TRIM_THRESHOLD, i32::MAX);
    }
}
