//! Writing files: OpenEXR images (linear, with chromaticities and an XYZ layer), PNG previews,
//! and every other output of the commands, all through [`file`]: checked before any work,
//! staged in temporary files and put in place together, so a failure never leaves a broken or
//! partial file.

pub mod exr;
pub mod file;
pub mod png;

/// Why an output could not be written (or an image read).
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The path cannot receive an output (a directory, a block device, an unwritable directory):
    /// bad input, found before any work.
    #[error("{path}: {problem}")]
    Destination {
        /// The path as given (after the flag that named it, where the flag helps).
        path: String,
        /// What is wrong with it.
        problem: String,
    },
    /// File-system error on `path`; the OS error follows in the error chain.
    #[error("cannot write {path}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// The encoder or decoder failed on `path`.
    #[error("{path}: {message}")]
    Codec {
        /// The file.
        path: String,
        /// The cause.
        message: String,
    },
}
