//! prisma: a spectral Whitted ray tracer for glass and dispersion, validated against Mitsuba 3.
//!
//! See `ARCHITECTURE.md` for the data flow and the module map.
#![deny(missing_docs)]

pub mod geometry;
pub mod optics;
pub mod spectrum;
