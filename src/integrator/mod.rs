//! Integrators: estimators of the radiance arriving along a camera ray. prisma has Whitted's
//! (`whitted`); a path tracer would sit beside it.

pub mod whitted;

pub use whitted::Whitted;

/// Counters an integrator accumulates while tracing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TraceStats {
    /// Rays cast: camera, specular branches and shadow rays.
    pub rays: u64,
}
