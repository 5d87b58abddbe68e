//! Optics as pure functions of angles and indices: Fresnel equations for dielectrics and
//! conductors, mirror reflection and Snell refraction, index-of-refraction models and the glass
//! catalogue shipped in `data/glasses.toml`. Nothing here knows about rays, scenes or spectra
//! beyond a wavelength in nm.

pub mod catalogue;
pub mod conductor;
pub mod fresnel;
pub mod ior;
pub mod snell;

pub use fresnel::{fresnel_dielectric, DielectricFresnel};
pub use ior::{Ior, IorError};
pub use snell::{reflect, refract};
