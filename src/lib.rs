//! prisma: a spectral Whitted ray tracer for glass and dispersion, validated against Mitsuba 3.
//!
//! See `ARCHITECTURE.md` for the data flow and the module map.
#![deny(missing_docs)]

pub mod camera;
pub mod cpu_time;
pub mod edges;
pub mod film;
pub mod fixed;
mod float_index;
pub mod geometry;
pub mod integrator;
pub mod interrupt;
pub mod lens;
pub mod light;
pub mod material;
pub mod memory;
pub mod optics;
pub mod output;
pub mod part;
pub mod polarization;
pub mod printable;
pub mod render;
pub mod sampler;
pub mod scene;
pub mod spectrum;
pub mod validate;
