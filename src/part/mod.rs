//! Split renders: the parts a render can be cut into, the file a part is kept in, and the
//! merge that adds parts back into the render they split.
//!
//! A render is a function of (scene, seed, sample indices, pixel window). A **part** is the
//! render of a [`SampleSet`] over a [`PixelWindow`]: its exact per-pixel sums
//! ([`crate::film::WindowSums`]) and a [`PartHeader`] saying what it is (scene digest, seed,
//! settings, samples, window, provenance). Because the sums are exact integers, adding parts
//! in any number, grouping and order gives the sums, and so the image, of the single render of
//! their union, bit for bit ([`merge`]).
//!
//! The light tracer splats anywhere in the image, so it is split by samples (each sample is one
//! pass of light paths), not by windows: a part over a window traces all the light paths of its
//! samples and keeps the splats that land in its window. Splitting a caustic render by windows
//! is exact but repeats the light tracing in every window.

pub mod file;
pub mod header;
pub mod merge;
pub mod samples;

/// Re-exported from the film, which owns the type: the film below the parts needs it too.
pub use crate::film::PixelWindow;
pub use file::{read_part, Part, PartError};
pub use header::PartHeader;
pub use merge::{merge, merge_files, MergeError};
pub use samples::SampleSet;
