//! Optics as pure functions of angles and indices: Fresnel equations for dielectrics and
//! conductors, mirror reflection and Snell refraction, index-of-refraction models, published
//! dispersion formulas and the glass catalogue shipped in `data/glasses.toml`, measured n + ik
//! of metals in `data/metals/`, and thin-film stacks (transfer matrices). Nothing here knows
//! about rays, scenes or spectra beyond a wavelength in nm.

pub mod catalogue;
pub mod conductor;
pub mod dispersion;
pub mod fresnel;
pub mod ior;
pub mod metals;
pub mod snell;
pub mod thin_film;

pub use conductor::{fresnel_conductor, fresnel_conductor_amplitudes, ConductorFresnel};
pub use fresnel::{
    fresnel_dielectric, fresnel_dielectric_amplitudes, DielectricAmplitudes, DielectricFresnel,
};
pub use ior::{Ior, IorError};
pub use snell::{reflect, refract};
pub use thin_film::{thin_film_amplitudes, Layer, ThinFilmAmplitudes};
