//! `prisma info`: what an EXR prisma wrote says about itself (the `prisma.*` header of
//! [`prisma::part::header`]), its windows, and a digest of its image channels, for comparing two
//! renders bit for bit whatever their headers say (wall time, threads). Header text is a file's:
//! it is printed escaped ([`prisma::printable::quote`]), and the header's digest is checked.

use std::path::PathBuf;

use anyhow::anyhow;
use clap::Args;
use sha2::{Digest, Sha256};

use super::{say, CliError};
use prisma::output::exr::read_exr;
use prisma::part::file::{read_summary, ExrSummary, PartError, StoredPart, HEADER_ALTERED};
use prisma::part::header::HEADER_DIGEST;
use prisma::part::PartHeader;
use prisma::printable::quote;
use prisma::scene::digest::hex;

/// Arguments of `prisma info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// An EXR written by prisma.
    #[arg(value_name = "FILE.exr")]
    file: PathBuf,
}

/// Runs `prisma info`.
pub fn run(args: &InfoArgs) -> Result<(), CliError> {
    let summary = read_summary(&args.file).map_err(|e| CliError::Input(e.into()))?;
    let mut prisma: Vec<&(String, String)> =
        summary.attributes.iter().filter(|(name, _)| name.starts_with("prisma.")).collect();
    if prisma.is_empty() {
        return Err(CliError::Input(anyhow!(
            "{}: no prisma.* attributes: not written by prisma",
            args.file.display()
        )));
    }
    // The header is checked as merge and --resume check it: a part whole (header, digests,
    // sums), another render's header field by field and against its digest where it has one.
    let has_sums = summary.attribute("prisma.sumsFormat").is_some();
    let input = |e: PartError| CliError::Input(e.into());
    if has_sums {
        StoredPart::read(&args.file).map_err(input)?;
    } else {
        check_render_header(&summary)
            .map_err(|problem| input(PartError { path: args.file.display().to_string(), problem }))?;
    }
    // The header's own order (that of `PartHeader::attributes`), then the rest by name.
    const ORDER: [&str; 16] = [
        "prisma.version",
        "prisma.commit",
        "prisma.scene",
        "prisma.sceneSha256",
        "prisma.seed",
        "prisma.samples",
        "prisma.spp",
        "prisma.crop",
        "prisma.settings",
        "prisma.lightPathsPerPass",
        "prisma.wallSeconds",
        "prisma.threads",
        "prisma.parts",
        "prisma.sumsFormat",
        "prisma.sumsBlake3",
        HEADER_DIGEST,
    ];
    prisma
        .sort_by_key(|(name, _)| (ORDER.iter().position(|o| o == name).unwrap_or(ORDER.len()), name.clone()));
    say!("file: {}", quote(&args.file.display().to_string()));
    for (name, value) in prisma {
        say!("{}: {}", quote(name.trim_start_matches("prisma.")), quote(value));
    }
    say!(
        "header: {}",
        match (summary.attribute(HEADER_DIGEST), has_sums) {
            (None, _) => "no digest (written by an earlier prisma)",
            (Some(_), true) => "matches its digest, and the sums theirs",
            (Some(_), false) => "matches its digest",
        }
    );
    let image_channels: Vec<&String> = summary.channels.iter().filter(|c| !c.starts_with("sums.")).collect();
    let sum_channels = summary.channels.len() - image_channels.len();
    say!("displayWindow: 0,0,{},{}", summary.display.0, summary.display.1);
    say!("dataWindow: {}", summary.window);
    say!(
        "channels: {} image ({}), {} of sums",
        image_channels.len(),
        quote(&image_channels.iter().map(|c| c.as_str()).collect::<Vec<_>>().join(" ")),
        sum_channels
    );
    // A digest of the image channels' values: two renders with the same pixels have the same.
    let image = read_exr(&args.file).map_err(|e| CliError::Input(e.into()))?;
    let mut hasher = Sha256::new();
    for name in image_channels {
        if let Some(values) = image.channel(name) {
            hasher.update(name.as_bytes());
            for value in values {
                hasher.update(value.to_bits().to_le_bytes());
            }
        }
    }
    say!("imageSha256: {}", hex(&hasher.finalize()));
    // The image's mean CIE XYZ (and the Stokes components' means, when polarised): what a user
    // compares two renders of one scene by (Whitted's share of the full light, for instance).
    let means = |names: [&str; 3]| -> Option<[f64; 3]> {
        let mut mean = [0.0; 3];
        for (slot, name) in mean.iter_mut().zip(names) {
            let values = image.channel(name)?;
            let count = values.len().max(1) as f64;
            *slot = values.iter().map(|&v| f64::from(v)).sum::<f64>() / count;
        }
        Some(mean)
    };
    if let Some([x, y, z]) = means(["XYZ.X", "XYZ.Y", "XYZ.Z"]) {
        say!("meanXYZ: {x:.6} {y:.6} {z:.6}");
    }
    Ok(())
}

/// Checks the `prisma.*` header of a render without sums: its fields, and its digest where it
/// has one (renders of earlier versions do not).
fn check_render_header(summary: &ExrSummary) -> Result<(), String> {
    if summary.header_intact() == Some(false) {
        return Err(HEADER_ALTERED.into());
    }
    PartHeader::from_attributes(|name| summary.attribute(name), summary.display).map(|_| ())
}
