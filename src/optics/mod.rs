//! Optics as pure functions of angles and indices: Fresnel equations for dielectrics and
//! conductors, mirror reflection and Snell refraction, index-of-refraction models, published
//! dispersion formulas and the glass catalogue shipped in `data/glasses.toml`, and measured
//! n + ik of metals in `data/metals/`. Nothing here knows about rays, scenes or spectra beyond
//! a wavelength in nm.

pub mod catalogue;
pub mod conductor;
pub mod dispersion;
pub mod fresnel;
pub mod ior;
pub mod metals;
pub mod snell;

pub use conductor::{fresnel_conductor, fresnel_conductor_amplitudes, ConductorFresnel};
pub use fresnel::{
    fresnel_dielectric, fresnel_dielectric_amplitudes, DielectricAmplitudes, DielectricFresnel,
};
pub use ior::{Ior, IorError};
pub use snell::{reflect, refract};
