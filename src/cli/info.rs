//! `prisma info`: what an EXR prisma wrote says about itself (the `prisma.*` header of
//! [`prisma::part::header`]), its windows, and a digest of its image channels, for comparing two
//! renders bit for bit whatever their headers say (wall time, threads).

use std::path::PathBuf;

use anyhow::anyhow;
use clap::Args;
use sha2::{Digest, Sha256};

use super::{say, CliError};
use prisma::output::exr::read_exr;
use prisma::part::file::read_summary;
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
    // The header's own order (that of `PartHeader::attributes`), then the rest by name.
    const ORDER: [&str; 15] = [
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
    ];
    prisma
        .sort_by_key(|(name, _)| (ORDER.iter().position(|o| o == name).unwrap_or(ORDER.len()), name.clone()));
    say!("file: {}", args.file.display());
    for (name, value) in prisma {
        say!("{}: {value}", name.trim_start_matches("prisma."));
    }
    let image_channels: Vec<&String> = summary.channels.iter().filter(|c| !c.starts_with("sums.")).collect();
    let sum_channels = summary.channels.len() - image_channels.len();
    say!("displayWindow: 0,0,{},{}", summary.display.0, summary.display.1);
    say!("dataWindow: {}", summary.window);
    say!(
        "channels: {} image ({}), {} of sums",
        image_channels.len(),
        image_channels.iter().map(|c| c.as_str()).collect::<Vec<_>>().join(" "),
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
    Ok(())
}
