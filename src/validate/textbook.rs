//! Textbook formulas the analytic cases compare prisma with, in f64 and written apart from
//! prisma's own optics code, so that a fault there cannot hide in the reference. Shared by
//! [`super::analytic`] and [`super::caustics`].

/// Unpolarised Fresnel reflectance from the textbook amplitude formulas (Hecht §4.6), f64, for
/// light in a medium of index `n_i` meeting one of index `n_t` at `cos_i` (> 0).
pub fn reference_reflectance(cos_i: f64, n_i: f64, n_t: f64) -> f64 {
    let (r_s, r_p) = reference_reflectances(cos_i, n_i, n_t);
    0.5 * (r_s + r_p)
}

/// The s and p Fresnel reflectances (R_s, R_p) from the textbook amplitude formulas (Hecht §4.6),
/// f64, for light in a medium of index `n_i` meeting one of index `n_t` at `cos_i` (> 0); both 1
/// past the critical angle.
pub fn reference_reflectances(cos_i: f64, n_i: f64, n_t: f64) -> (f64, f64) {
    let sin_t = n_i / n_t * (1.0 - cos_i * cos_i).max(0.0).sqrt();
    if sin_t >= 1.0 {
        return (1.0, 1.0);
    }
    let cos_t = (1.0 - sin_t * sin_t).sqrt();
    let r_s = (n_i * cos_i - n_t * cos_t) / (n_i * cos_i + n_t * cos_t);
    let r_p = (n_t * cos_i - n_i * cos_t) / (n_t * cos_i + n_i * cos_t);
    (r_s * r_s, r_p * r_p)
}
