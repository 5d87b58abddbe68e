//! [`Film`]: a free-standing thin film, a soap film: a sheet of a medium (water by default) of
//! thickness d nm between air (n = 1) on both sides, whose two faces reflect coherently. Its
//! reflection and transmission amplitudes, s and p with their phases, are those of a one-layer
//! stack between two half-spaces of air ([`crate::optics::thin_film`], the transfer-matrix method
//! of Macleod, *Thin-Film Optical Filters*, §2.2–2.4; the same as Airy's single-layer sum
//! r = (r₀₁ + r₁₂e^{−2iβ})/(1 + r₀₁r₁₂e^{−2iβ}), Born & Wolf §7.6.1).
//!
//! **Geometrically infinitely thin**: the sheet is the shape's surface itself. The transmitted
//! ray goes on in the incident direction from the hit point (no refraction, no lateral shift:
//! the true shift of a plane-parallel film, d·sin(θ − θ_t)/cos θ_t, is below 1 µm for the
//! thicknesses accepted here), the reflected ray mirrors. Air on both sides, so no radiance
//! scaling (η = 1) and both faces of the sheet behave the same. Not dispersive in direction:
//! every wavelength lane stays on the same two rays; each lane has its own amplitudes (the
//! film's phase thickness 2π·n·d·cos θ_t/λ depends on λ whatever the index does).
//!
//! **Thickness**: constant, or **drained**: a vertical soap film whose liquid flows down under
//! gravity between surfaces that do not slip (Poiseuille flux q = ρ g d³/(12 μ)) thins towards
//! the top as the similarity solution d² = 4 μ x/(ρ g t) of ∂d/∂t + ∂q/∂x = 0, x the depth
//! below the top (Mysels, Shinoda & Frankel, *Soap Films: Studies of Their Thinning and a
//! Bibliography*, 1959, ch. 4): d² is linear in height. Here d² goes linearly from `top`² at the
//! highest point (along `axis`) to `bottom`² at the lowest, and is constant beyond them.
//!
//! ```toml
//! [materials.bubble]
//! type = "film"
//! ior = { glass = "water" }      # optional: water (Daimon & Masumura 2007) when absent
//! thickness_nm = 300             # or a draining film, thinnest at the top:
//! # thickness_nm = { top = 150, bottom = 900, axis = [0, 1, 0] }   # heights: the shapes' extent
//! # thickness_nm = { top = 150, bottom = 900, axis = [0, 1, 0], heights = [-1, 1] }
//! # or from a greyscale image, black = min, white = max, projected along edge1 × edge2:
//! # thickness_nm = { texture = "thickness.png", min = 150, max = 900,
//! #                 corner = [-1, -1, 0], edge1 = [2, 0, 0], edge2 = [0, 2, 0] }
//! ```
//! ([`ThicknessTexture`]: the projection, the lookup and the file's format.)

use glam::Vec3;
use num_complex::{Complex32, Complex64};

use crate::optics::{thin_film_amplitudes, Ior, Layer};
use crate::polarization::mueller::JonesDiagonal;

mod texture;
pub use texture::{ThicknessTexture, MAX_TEXTURE_SIZE};

/// A free-standing thin film in air.
#[derive(Debug, Clone)]
pub struct Film {
    /// The film's (real) index of refraction n(λ), ≥ 1 (checked at load).
    pub ior: Ior,
    /// Its thickness over the surface.
    pub thickness: Thickness,
}

/// A film's thickness over its surface, in nm.
#[derive(Debug, Clone, PartialEq)]
pub enum Thickness {
    /// The same thickness everywhere (nm).
    Constant(f32),
    /// A film drained by gravity (module documentation): d² linear in the height h = p·`axis`,
    /// `top_nm` at h ≥ `high`, `bottom_nm` at h ≤ `low`.
    Drained {
        /// Thickness at the top (nm).
        top_nm: f32,
        /// Thickness at the bottom (nm).
        bottom_nm: f32,
        /// Unit vector pointing up.
        axis: Vec3,
        /// Height of the bottom along `axis` (scene units).
        low: f32,
        /// Height of the top along `axis` (scene units), > `low`.
        high: f32,
    },
    /// Read from a greyscale image projected onto the surface ([`ThicknessTexture`]).
    Textured(ThicknessTexture),
}

impl Thickness {
    /// The thickness (nm) at the point `point` of the surface.
    #[inline]
    pub fn at(&self, point: Vec3) -> f32 {
        match *self {
            Thickness::Constant(nm) => nm,
            Thickness::Textured(ref texture) => texture.at(point),
            Thickness::Drained { top_nm, bottom_nm, axis, low, high } => {
                let depth = ((high - point.dot(axis)) / (high - low)).clamp(0.0, 1.0);
                (top_nm * top_nm + (bottom_nm * bottom_nm - top_nm * top_nm) * depth).max(0.0).sqrt()
            }
        }
    }
}

/// A film at one wavelength and incidence, as Jones elements in the s/p frame of the incidence
/// (x = s): reflection diag(r_s, r_p) and transmission diag(t_s, t_p), so that their `a` are
/// the unpolarised reflectance (R_s + R_p)/2 and transmittance (T_s + T_p)/2 (air on both
/// sides: T = |t|²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmInterface {
    /// diag(r_s, r_p).
    pub reflection: JonesDiagonal,
    /// diag(t_s, t_p).
    pub transmission: JonesDiagonal,
}

impl Film {
    /// The film of index `n_film` and `thickness_nm` (nm) for light of vacuum wavelength
    /// `lambda_nm` arriving at `cos_theta_i` against either face (its sign is ignored: the
    /// film is the same from both sides).
    pub fn interface(cos_theta_i: f32, n_film: f32, thickness_nm: f32, lambda_nm: f32) -> FilmInterface {
        let layer = [Layer::dielectric(f64::from(n_film), f64::from(thickness_nm.max(0.0)))];
        let stack = thin_film_amplitudes(
            1.0,
            &layer,
            Complex64::new(1.0, 0.0),
            f64::from(lambda_nm),
            f64::from(cos_theta_i.abs().min(1.0)),
        );
        let narrow = |z: Complex64| Complex32::new(z.re as f32, z.im as f32);
        FilmInterface {
            reflection: JonesDiagonal::new(narrow(stack.r_s), narrow(stack.r_p)),
            transmission: JonesDiagonal::new(narrow(stack.t_s), narrow(stack.t_p)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quarter-wave film at normal incidence reflects ((n² − 1)/(n² + 1))² (its two faces'
    /// reflections, −r and +r delayed by half a wave, add; Born & Wolf §7.6.1), and what it
    /// does not reflect it transmits (no absorption).
    #[test]
    fn a_quarter_wave_film_reflects_the_closed_form() {
        let n = 1.333_f32;
        let film = Film::interface(1.0, n, 550.0 / (4.0 * n), 550.0);
        let expected = ((n * n - 1.0) / (n * n + 1.0)).powi(2);
        assert!((film.reflection.a - expected).abs() < 1e-6, "{film:?}");
        assert!((film.reflection.a + film.transmission.a - 1.0).abs() < 1e-6, "{film:?}");
        // The same from the other face.
        assert_eq!(Film::interface(-1.0, n, 550.0 / (4.0 * n), 550.0), film);
    }

    /// The drained profile: `top` at the top, `bottom` at the bottom, d² halfway between at
    /// mid-height, constant beyond the ends.
    #[test]
    fn a_drained_film_thins_towards_the_top() {
        let drained =
            Thickness::Drained { top_nm: 100.0, bottom_nm: 700.0, axis: Vec3::Y, low: -1.0, high: 1.0 };
        assert_eq!(drained.at(Vec3::new(0.0, 1.0, 0.0)), 100.0);
        assert_eq!(drained.at(Vec3::new(3.0, 5.0, 0.0)), 100.0);
        assert_eq!(drained.at(Vec3::new(0.0, -1.0, 2.0)), 700.0);
        assert_eq!(drained.at(Vec3::new(0.0, -9.0, 0.0)), 700.0);
        let middle = drained.at(Vec3::ZERO);
        assert!((middle - (0.5_f32 * (100.0 * 100.0 + 700.0 * 700.0)).sqrt()).abs() < 1e-3, "{middle}");
    }
}
