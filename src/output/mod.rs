//! Writing images: OpenEXR (linear, with chromaticities and an XYZ layer) and PNG previews, both
//! through a temporary file renamed into place so a crash never leaves a broken file.

pub mod atomic;
pub mod exr;
pub mod png;

/// Why an image could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// File-system error on `path`.
    #[error("{path}: {source}")]
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
