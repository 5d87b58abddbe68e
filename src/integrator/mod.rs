//! Integrators: estimators of the radiance arriving along a camera ray. prisma has Whitted's
//! (`whitted`); a path tracer would sit beside it.

pub mod beam;
pub mod whitted;

pub use beam::Beam;
pub use whitted::Whitted;

/// Counters an integrator accumulates while tracing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TraceStats {
    /// Rays cast: camera, specular branches and shadow rays.
    pub rays: u64,
}

/// A deliberate error injected into the physics, so that validation can prove it would catch a
/// wrong renderer (`prisma validate --fault ...`). Never used by a normal render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fault {
    /// Schlick's approximation R ≈ R₀ + (1 − R₀)(1 − cos θ)⁵ instead of the exact Fresnel
    /// equations (and no total internal reflection beyond what Snell's law forces).
    SchlickFresnel,
    /// Every dielectric's index of refraction multiplied by this factor (e.g. 1.01).
    IorScale(f32),
    /// Every change of Stokes frame turned the wrong way: a rotation matrix built transposed
    /// (glam's column-major constructors fed a row-major literal).
    TransposedRotation,
    /// The sign of every phase term flipped (the wrong time convention, or `atan2(x, y)` for
    /// `atan2(y, x)`): circular polarisation of the wrong handedness.
    FlippedPhase,
    /// Polarisation dropped: an unpolarised render where a polarised one was asked for, each
    /// interface's reflectance averaged over s and p.
    Unpolarized,
}
