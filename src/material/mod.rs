//! Materials: how a surface scatters light in prisma's Whitted model. A closed set, dispatched by
//! `match`: diffuse surfaces take direct light, mirrors and dielectrics spawn specular branches,
//! polarisers and retarders (sheets that only change the polarisation) let light through, and
//! free-standing films (soap films) reflect and transmit without bending the ray.

pub mod dielectric;
pub mod diffuse;
pub mod film;
pub mod mirror;
pub mod polarizer;
pub mod retarder;

use glam::Vec3;

pub use dielectric::{
    CoatedInterface, CoatingFault, CoatingLayer, Dielectric, LayerIndex, MAX_COATING_LAYERS,
};
pub use diffuse::Diffuse;
pub use film::{Film, FilmInterface, Thickness};
pub use mirror::{Conductor, Mirror};
pub use polarizer::Polarizer;
pub use retarder::Retarder;

/// A surface material.
#[derive(Debug, Clone)]
pub enum Material {
    /// Lambertian / Oren–Nayar: direct lighting with shadow rays.
    Diffuse(Diffuse),
    /// Perfect specular reflection.
    Mirror(Mirror),
    /// Smooth dielectric: Fresnel-weighted reflection and refraction.
    Dielectric(Dielectric),
    /// Ideal linear polariser sheet: light passes straight through, filtered.
    Polarizer(Polarizer),
    /// Ideal linear retarder sheet (wave plate): light passes straight through, retarded.
    Retarder(Retarder),
    /// Free-standing thin film (a soap film): coherent reflection and straight transmission.
    Film(Film),
    /// Reflects nothing (the surface of an area light).
    Black,
}

impl Material {
    /// True for the sheets light passes straight through (polarisers and retarders): they let
    /// shadow rays through and never end a path.
    #[inline]
    pub fn is_filter(&self) -> bool {
        matches!(self, Material::Polarizer(_) | Material::Retarder(_))
    }
}

/// `axis` projected onto the plane of normal `normal`, unit length. The scene checks when it is
/// built that the axis is not along the normal of the flat shapes that use it.
#[inline]
fn sheet_axis(axis: Vec3, normal: Vec3) -> Vec3 {
    (axis - axis.dot(normal) * normal).normalize_or(axis)
}
