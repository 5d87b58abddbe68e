//! The files a command writes (an EXR, its PNG preview, statistics), checked together before
//! any work: `render` and `merge` share them.

use std::path::{Path, PathBuf};

use anyhow::anyhow;

use super::CliError;
use prisma::output::file::{check_destination, same_file, Destination};
use prisma::output::OutputError;

/// The files a render or merge writes, checked before it starts.
pub struct Destinations {
    /// The EXR.
    pub exr: PathBuf,
    /// The EXR goes to a special file (a device, a FIFO): written in place, no part beside it.
    pub exr_special: bool,
    /// The PNG preview, if any.
    pub preview: Option<PathBuf>,
    /// The statistics JSON, if asked for.
    pub stats: Option<PathBuf>,
}

impl Destinations {
    /// Checks the outputs before any work: each can be written (not a directory, a block device,
    /// an unwritable place), the EXR is named `.exr` and the preview `.png` (unless they are
    /// special files such as /dev/null), and no two are the same file. Without `--preview` the
    /// preview goes beside the EXR with a `.png` extension, or nowhere when the EXR goes to a
    /// special file.
    pub fn check(exr: &Path, preview: Option<&Path>, stats: Option<&Path>) -> Result<Self, CliError> {
        let input = |e: OutputError| CliError::Input(e.into());
        let exr_destination = check_destination(exr).map_err(input)?;
        require_extension(&exr_destination, exr, "exr", "-o", "--preview names the PNG preview")?;
        let preview = match (preview, &exr_destination) {
            (Some(path), _) => Some(path.to_owned()),
            (None, Destination::Replace(_)) => Some(exr.with_extension("png")),
            (None, Destination::Special(_)) => None,
        };
        if let Some(path) = &preview {
            let destination = check_destination(path).map_err(input)?;
            require_extension(&destination, path, "png", "--preview", "-o names the EXR image")?;
        }
        if let Some(path) = stats {
            check_destination(path).map_err(input)?;
        }
        let named = [("-o", Some(exr)), ("--preview", preview.as_deref()), ("--stats", stats)];
        for (i, (flag_a, a)) in named.iter().enumerate() {
            for (flag_b, b) in &named[i + 1..] {
                if let (Some(a), Some(b)) = (a, b) {
                    let special = matches!(check_destination(a), Ok(Destination::Special(_)));
                    if same_file(a, b) && !special {
                        return Err(CliError::Input(anyhow!(
                            "{flag_a} and {flag_b} name the same file {}: each output needs its own",
                            a.display()
                        )));
                    }
                }
            }
        }
        let exr_special = matches!(exr_destination, Destination::Special(_));
        Ok(Self { exr: exr.to_owned(), exr_special, preview, stats: stats.map(Path::to_owned) })
    }

    /// Each output with the flag that names it.
    pub fn named(&self) -> Vec<(&str, &Path)> {
        let mut named = vec![("-o", self.exr.as_path())];
        named.extend(self.preview.as_deref().map(|path| ("--preview", path)));
        named.extend(self.stats.as_deref().map(|path| ("--stats", path)));
        named
    }
}

/// A regular file written as `format` must be named so.
fn require_extension(
    destination: &Destination,
    path: &Path,
    format: &str,
    flag: &str,
    hint: &str,
) -> Result<(), CliError> {
    let named = path.extension().is_some_and(|e| e.eq_ignore_ascii_case(format));
    if matches!(destination, Destination::Replace(_)) && !named {
        return Err(CliError::Input(anyhow!(
            "{flag} {}: the file is written as {}, so its name must end in .{format} ({hint})",
            path.display(),
            format.to_uppercase()
        )));
    }
    Ok(())
}
