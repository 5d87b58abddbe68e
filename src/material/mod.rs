//! Materials: how a surface scatters light in prisma's Whitted model. A closed set, dispatched by
//! `match`: diffuse surfaces take direct light, mirrors and dielectrics spawn specular branches.

pub mod dielectric;
pub mod diffuse;
pub mod mirror;

pub use dielectric::Dielectric;
pub use diffuse::Diffuse;
pub use mirror::Mirror;

/// A surface material.
#[derive(Debug, Clone)]
pub enum Material {
    /// Lambertian / Oren–Nayar: direct lighting with shadow rays.
    Diffuse(Diffuse),
    /// Perfect specular reflection.
    Mirror(Mirror),
    /// Smooth dielectric: Fresnel-weighted reflection and refraction.
    Dielectric(Dielectric),
    /// Reflects nothing (the surface of an area light).
    Black,
}
