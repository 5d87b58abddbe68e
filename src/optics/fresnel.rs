//! Fresnel equations for a smooth interface between two dielectrics (Hecht, *Optics*, §4.6).
//!
//! Convention (the same as Mitsuba 3's `fresnel`, so that its values are directly comparable):
//! `eta` is the relative index n_interior / n_exterior, `cos_theta_i` is measured against the
//! normal on the exterior side, and a negative `cos_theta_i` means light arriving from the interior.

/// The Fresnel coefficients of one incidence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricFresnel {
    /// Amplitude reflection coefficient for s (TE) polarisation.
    pub r_s: f32,
    /// Amplitude reflection coefficient for p (TM) polarisation.
    pub r_p: f32,
    /// Reflectance (power) for s polarisation, |r_s|².
    pub reflectance_s: f32,
    /// Reflectance (power) for p polarisation, |r_p|².
    pub reflectance_p: f32,
    /// Unpolarised reflectance (R_s + R_p) / 2; 1 under total internal reflection.
    pub reflectance: f32,
    /// Cosine of the transmitted angle, signed like Mitsuba's: negative when the transmitted ray
    /// goes into the interior. 0 under total internal reflection.
    pub cos_theta_t: f32,
    /// Relative index seen by the incident ray, n_t / n_i.
    pub eta_it: f32,
}

/// Fresnel coefficients for unpolarised light hitting an interface of relative index `eta`
/// (n_interior / n_exterior, > 0) at `cos_theta_i` in [-1, 1]. Never NaN for finite inputs.
pub fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> DielectricFresnel {
    let _ = (cos_theta_i, eta);
    todo!()
}
