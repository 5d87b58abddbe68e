//! Bounds on floating-point rounding error, shared by the intersection routines and by
//! [`super::spawn_origin`].
//!
//! Every f32 operation rounds its exact result by a relative error of at most the unit roundoff
//! u = 2⁻²⁴; a value that went through n roundings is off by a relative error of at most
//! γ(n) = n·u / (1 − n·u). Source: N. J. Higham, *Accuracy and Stability of Numerical
//! Algorithms*, 2nd ed. (SIAM 2002), §3.1, Lemma 3.1; applied to ray intersection in M. Pharr,
//! W. Jakob, G. Humphreys, *Physically Based Rendering*, 3rd ed. (2016), §3.9.

/// The unit roundoff of f32: half the distance from 1 to the next float.
const UNIT_ROUNDOFF: f32 = f32::EPSILON * 0.5;

/// γ(n) = n·u / (1 − n·u): the relative error bound after `n` successive f32 roundings
/// (meaningful while n·u < 1, i.e. for every n used here).
#[inline]
pub(crate) const fn gamma(n: u32) -> f32 {
    let n_u = n as f32 * UNIT_ROUNDOFF;
    n_u / (1.0 - n_u)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_matches_its_definition() {
        // γ(1) = u / (1 − u) with u = 2⁻²⁴: just above 2⁻²⁴ ≈ 5.96e-8.
        let u = 2f32.powi(-24);
        assert_eq!(gamma(1), u / (1.0 - u));
        // γ grows about linearly for small n: γ(10) ≈ 10·u to within a relative 1e-6.
        assert!((gamma(10) / (10.0 * u) - 1.0).abs() < 1e-6);
    }
}
