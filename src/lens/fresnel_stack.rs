//! Exact s/p Fresnel coefficients of one lens interface in f64, and the 4×4 Mueller matrices
//! that chain them along a traced path through the lens.
//!
//! The coefficients follow the conventions of [`crate::optics::fresnel`] (Hecht, *Optics*,
//! 5th ed., §4.6; the "Verdet" signs, r_p = −r_s at normal incidence; the decaying root
//! cos θt = −i√(sin²θt − 1) under total internal reflection), written here with the indices
//! n_i (incident side) and n_t (transmitted side) rather than a relative index, and in f64 so
//! that Π(1 − R) over a dozen surfaces and the Snell residuals of a trace stay at 1e-15.
//! `tests` check them against the f32 functions.
//!
//! # Mueller frames
//! A Stokes vector belongs to a beam travelling along the unit vector `f` (the direction the
//! light travels) and a unit x axis ⟂ f, y = f × x (see [`crate::polarization`]). At an
//! interface of normal n the s axis is normalize(n × f), the same before and after the
//! interface for the reflected and the refracted beam; there the element is the diagonal Jones
//! matrix diag(a_s, a_p) of [`crate::polarization::mueller`]'s form. A path's matrix is the
//! product, in the order the light meets them, of (rotation into the interface's s frame) ·
//! (diagonal element), starting from the frame the light arrives in and ending with a rotation
//! into the frame it is recorded in.

use glam::DVec3;
use num_complex::Complex64;

/// Below this squared length n × f is treated as zero: normal incidence, where every frame is
/// an s frame (rounding of unit vectors leaves ~1e-32 there; any real tilt is far above).
const PARALLEL_SQUARED: f64 = 1e-28;

/// The Fresnel coefficients of one incidence on an interface from index `n_i` to `n_t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterfaceFresnel {
    /// Amplitude reflection coefficient r⊥ (s); of modulus 1 under total internal reflection.
    pub r_s: Complex64,
    /// Amplitude reflection coefficient r∥ (p), Hecht's sign.
    pub r_p: Complex64,
    /// Amplitude transmission coefficient t⊥ (s).
    pub t_s: Complex64,
    /// Amplitude transmission coefficient t∥ (p).
    pub t_p: Complex64,
    /// |r_s|².
    pub reflectance_s: f64,
    /// |r_p|².
    pub reflectance_p: f64,
    /// (n_t cos θt / n_i cos θi)|t_s|² = 1 − R_s; 0 under total internal reflection.
    pub transmittance_s: f64,
    /// (n_t cos θt / n_i cos θi)|t_p|² = 1 − R_p.
    pub transmittance_p: f64,
    /// cos θt ≥ 0 (unsigned); 0 under total internal reflection.
    pub cos_theta_t: f64,
    /// Whether sin θt would exceed 1.
    pub total_internal_reflection: bool,
}

impl InterfaceFresnel {
    /// Unpolarised reflectance (R_s + R_p)/2.
    pub fn reflectance(&self) -> f64 {
        0.5 * (self.reflectance_s + self.reflectance_p)
    }

    /// Unpolarised transmittance (T_s + T_p)/2.
    pub fn transmittance(&self) -> f64 {
        0.5 * (self.transmittance_s + self.transmittance_p)
    }
}

/// The Fresnel coefficients for light in index `n_i` meeting index `n_t` at the unsigned
/// cosine of incidence `cos_theta_i` in [0, 1]. Never NaN for finite positive indices.
pub fn interface_fresnel(cos_theta_i: f64, n_i: f64, n_t: f64) -> InterfaceFresnel {
    debug_assert!(n_i > 0.0 && n_t > 0.0, "indices {n_i}, {n_t}");
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    let eta_it = n_t / n_i;
    let sin_t_sqr = (1.0 - cos_i * cos_i) / (eta_it * eta_it);
    let cos_t_sqr = 1.0 - sin_t_sqr;
    let total_internal_reflection = cos_t_sqr < 0.0;
    if !total_internal_reflection && n_i != n_t {
        if let Some(real) = real_interface_fresnel(cos_i, eta_it, cos_t_sqr.sqrt()) {
            return real;
        }
    }
    let cos_t = if total_internal_reflection {
        Complex64::new(0.0, -(-cos_t_sqr).sqrt())
    } else {
        Complex64::new(cos_t_sqr.sqrt(), 0.0)
    };
    let denominator_s = cos_i + eta_it * cos_t;
    let denominator_p = eta_it * cos_i + cos_t;
    if n_i == n_t || denominator_s.norm_sqr() == 0.0 || denominator_p.norm_sqr() == 0.0 {
        // Index-matched: no interface at all (the denominators vanish only for eta = 1 at
        // grazing incidence).
        let one = Complex64::new(1.0, 0.0);
        return InterfaceFresnel {
            r_s: Complex64::new(0.0, 0.0),
            r_p: Complex64::new(0.0, 0.0),
            t_s: one,
            t_p: one,
            reflectance_s: 0.0,
            reflectance_p: 0.0,
            transmittance_s: 1.0,
            transmittance_p: 1.0,
            cos_theta_t: cos_i,
            total_internal_reflection: false,
        };
    }
    let r_s = (cos_i - eta_it * cos_t) / denominator_s;
    let r_p = (eta_it * cos_i - cos_t) / denominator_p;
    let t_s = 2.0 * cos_i / denominator_s;
    let t_p = 2.0 * cos_i / denominator_p;
    let (transmittance_s, transmittance_p) = if total_internal_reflection {
        (0.0, 0.0)
    } else {
        // eta_it (cos θt / cos θi)|t|² without dividing by cos θi (grazing gives 0, not 0/0).
        let flux = 4.0 * cos_i * eta_it * cos_t.re;
        (flux / denominator_s.norm_sqr(), flux / denominator_p.norm_sqr())
    };
    InterfaceFresnel {
        r_s,
        r_p,
        t_s,
        t_p,
        reflectance_s: r_s.norm_sqr(),
        reflectance_p: r_p.norm_sqr(),
        transmittance_s,
        transmittance_p,
        cos_theta_t: if total_internal_reflection { 0.0 } else { cos_t.re },
        total_internal_reflection,
    }
}

/// The Fresnel coefficients of an interface from index `n_i` to `n_t` carrying `coating`, for
/// a ray at the unsigned cosine `cos_theta_i` in [0, 1] and vacuum wavelength `lambda_nm` (nm),
/// travelling toward the image (`toward_image`, the layers crossed as listed) or the object:
/// the stack's amplitudes and powers ([`super::coating::Coating::amplitudes`]), with the
/// refraction angle and total internal reflection of the bare interface (the layers are thin
/// and parallel: n sin θ carries through them). The stack's t_s and t_p share the bare flux
/// factor n_t cos θt / (n_i cos θi), which [`transmission_mueller`] recovers as T_s/|t_s|².
pub fn coated_interface_fresnel(
    cos_theta_i: f64,
    n_i: f64,
    n_t: f64,
    coating: &super::coating::Coating,
    toward_image: bool,
    lambda_nm: f64,
) -> InterfaceFresnel {
    let bare = interface_fresnel(cos_theta_i, n_i, n_t);
    let stack = coating.amplitudes(toward_image, n_i, n_t, lambda_nm, cos_theta_i.clamp(0.0, 1.0));
    InterfaceFresnel {
        r_s: stack.r_s,
        r_p: stack.r_p,
        t_s: stack.t_s,
        t_p: stack.t_p,
        reflectance_s: stack.reflectance_s,
        reflectance_p: stack.reflectance_p,
        transmittance_s: stack.transmittance_s,
        transmittance_p: stack.transmittance_p,
        ..bare
    }
}

/// [`interface_fresnel`] outside total internal reflection, where every coefficient is real,
/// in real arithmetic, with one division per polarisation (the reciprocal of its denominator)
/// where the complex path makes six: the same formulas, equal to the complex path's numbers
/// within a few ulps (rounding; the tests compare them). `None` where a denominator vanishes
/// (the caller's index-matched case).
#[inline]
fn real_interface_fresnel(cos_i: f64, eta_it: f64, cos_t: f64) -> Option<InterfaceFresnel> {
    let denominator_s = cos_i + eta_it * cos_t;
    let denominator_p = eta_it * cos_i + cos_t;
    if denominator_s == 0.0 || denominator_p == 0.0 {
        return None;
    }
    let (inverse_s, inverse_p) = (1.0 / denominator_s, 1.0 / denominator_p);
    let r_s = (cos_i - eta_it * cos_t) * inverse_s;
    let r_p = (eta_it * cos_i - cos_t) * inverse_p;
    let two_cos_i = 2.0 * cos_i;
    let t_s = two_cos_i * inverse_s;
    let t_p = two_cos_i * inverse_p;
    // T = n_t cos θt/(n_i cos θi)|t|² = 4 cos θi η cos θt / D².
    let flux = 4.0 * cos_i * eta_it * cos_t;
    let real = |value: f64| Complex64::new(value, 0.0);
    Some(InterfaceFresnel {
        r_s: real(r_s),
        r_p: real(r_p),
        t_s: real(t_s),
        t_p: real(t_p),
        reflectance_s: r_s * r_s,
        reflectance_p: r_p * r_p,
        transmittance_s: flux * inverse_s * inverse_s,
        transmittance_p: flux * inverse_p * inverse_p,
        cos_theta_t: cos_t,
        total_internal_reflection: false,
    })
}

/// A 4×4 Mueller matrix, row-major, acting on (S0, S1, S2, S3).
pub type Mueller4 = [[f64; 4]; 4];

/// The identity.
pub const MUELLER_IDENTITY: Mueller4 =
    [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];

/// The product `left · right` (apply `right` first).
pub fn mueller_mul(left: &Mueller4, right: &Mueller4) -> Mueller4 {
    let mut out = [[0.0; 4]; 4];
    for (row, out_row) in out.iter_mut().enumerate() {
        for (col, value) in out_row.iter_mut().enumerate() {
            *value = (0..4).map(|k| left[row][k] * right[k][col]).sum();
        }
    }
    out
}

/// `matrix` applied to the Stokes vector `stokes`.
pub fn mueller_apply(matrix: &Mueller4, stokes: [f64; 4]) -> [f64; 4] {
    let mut out = [0.0; 4];
    for (row, value) in out.iter_mut().enumerate() {
        *value = (0..4).map(|k| matrix[row][k] * stokes[k]).sum();
    }
    out
}

/// Every entry times `factor`.
pub fn mueller_scaled(matrix: &Mueller4, factor: f64) -> Mueller4 {
    matrix.map(|row| row.map(|value| value * factor))
}

/// The Mueller matrix of the diagonal Jones matrix diag(`a_x`, `a_y`) in its own frame (the
/// form of [`crate::polarization::mueller`]: a = (|A_x|² + |A_y|²)/2,
/// b = (|A_x|² − |A_y|²)/2, w = A_x·conj(A_y)), scaled by the flux factor `flux` (for a
/// transmitted beam, n_t cos θt / (n_i cos θi), so that its (0,0) entry is (T_s + T_p)/2).
pub fn jones_diagonal(a_x: Complex64, a_y: Complex64, flux: f64) -> Mueller4 {
    DiagonalElement::of_jones(a_x, a_y, flux).matrix()
}

/// The four numbers of a diagonal element's Mueller matrix [[a, b, 0, 0], [b, a, 0, 0],
/// [0, 0, w_re, w_im], [0, 0, −w_im, w_re]] ([`jones_diagonal`]), so that a path's rows can be
/// carried through it without the 4×4 product ([`rotate_then_element`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DiagonalElement {
    pub(crate) a: f64,
    pub(crate) b: f64,
    pub(crate) w_re: f64,
    pub(crate) w_im: f64,
}

impl DiagonalElement {
    /// The element of the diagonal Jones matrix diag(`a_x`, `a_y`) scaled by `flux`, as
    /// [`jones_diagonal`] describes it.
    #[inline]
    fn of_jones(a_x: Complex64, a_y: Complex64, flux: f64) -> Self {
        let (power_x, power_y) = (a_x.norm_sqr() * flux, a_y.norm_sqr() * flux);
        let w = a_x * a_y.conj() * flux;
        Self { a: 0.5 * (power_x + power_y), b: 0.5 * (power_x - power_y), w_re: w.re, w_im: w.im }
    }

    /// The transmitted beam's element ([`transmission_mueller`]).
    #[inline]
    pub(crate) fn transmission(fresnel: &InterfaceFresnel) -> Self {
        if fresnel.total_internal_reflection {
            return Self { a: 0.0, b: 0.0, w_re: 0.0, w_im: 0.0 };
        }
        // Flux factor: T_s / |t_s|² (the same for p); |t_s| > 0 outside TIR and grazing.
        let t_s_sqr = fresnel.t_s.norm_sqr();
        let flux = if t_s_sqr > 0.0 { fresnel.transmittance_s / t_s_sqr } else { 0.0 };
        Self::of_jones(fresnel.t_s, fresnel.t_p, flux)
    }

    /// The reflected beam's element ([`reflection_mueller`]).
    #[inline]
    pub(crate) fn reflection(fresnel: &InterfaceFresnel) -> Self {
        Self::of_jones(fresnel.r_s, fresnel.r_p, 1.0)
    }

    /// Its 4×4 Mueller matrix.
    fn matrix(&self) -> Mueller4 {
        let Self { a, b, w_re, w_im } = *self;
        [[a, b, 0.0, 0.0], [b, a, 0.0, 0.0], [0.0, 0.0, w_re, w_im], [0.0, 0.0, -w_im, w_re]]
    }
}

/// cos 2θ and sin 2θ of the Stokes rotation of [`rotation_mueller`] (1 and 0 where it is the
/// identity).
#[inline]
pub(crate) fn rotation_angle(forward: DVec3, from: DVec3, to: DVec3) -> (f64, f64) {
    let cos_theta = from.dot(to);
    let sin_theta = forward.dot(from.cross(to));
    let norm = cos_theta * cos_theta + sin_theta * sin_theta;
    if norm <= 0.0 {
        return (1.0, 0.0);
    }
    let inverse = 1.0 / norm;
    ((cos_theta * cos_theta - sin_theta * sin_theta) * inverse, 2.0 * sin_theta * cos_theta * inverse)
}

/// The row vector `row` times the rotation of angle (`cos_2`, `sin_2`) ([`rotation_angle`]),
/// then times `element`: one row of `mueller_mul(&mueller_mul(path, rotation), element)`,
/// with the same products summed in the same order (the 4×4 products' other terms are exact
/// zeros), so the same numbers to the bit, in 12 multiplications instead of 128 for the row.
#[inline]
pub(crate) fn rotate_then_element(
    row: [f64; 4],
    cos_2: f64,
    sin_2: f64,
    element: &DiagonalElement,
) -> [f64; 4] {
    let [q0, q1, q2, q3] = rotate_row(row, cos_2, sin_2);
    let DiagonalElement { a, b, w_re, w_im } = *element;
    [q0 * a + q1 * b, q0 * b + q1 * a, q2 * w_re + q3 * -w_im, q2 * w_im + q3 * w_re]
}

/// The row vector `row` times the rotation of angle (`cos_2`, `sin_2`) ([`rotation_angle`]).
#[inline]
pub(crate) fn rotate_row(row: [f64; 4], cos_2: f64, sin_2: f64) -> [f64; 4] {
    let [r0, r1, r2, r3] = row;
    [r0, r1 * cos_2 + r2 * -sin_2, r1 * sin_2 + r2 * cos_2, r3]
}

/// The Mueller matrix of the transmitted beam in its s/p frame, with (0,0) = (T_s + T_p)/2:
/// amplitudes t_s, t_p with the flux factor T/|t|² (real, positive outside total internal
/// reflection). Zero under total internal reflection.
pub fn transmission_mueller(fresnel: &InterfaceFresnel) -> Mueller4 {
    DiagonalElement::transmission(fresnel).matrix()
}

/// The Mueller matrix of the reflected beam in its s/p frame.
pub fn reflection_mueller(fresnel: &InterfaceFresnel) -> Mueller4 {
    DiagonalElement::reflection(fresnel).matrix()
}

/// The Stokes rotation from x axis `from` to x axis `to` for light travelling along `forward`
/// (all unit, `from`, `to` ⟂ `forward`): S1' = cos 2θ S1 + sin 2θ S2,
/// S2' = −sin 2θ S1 + cos 2θ S2 with cos θ = from·to, sin θ = forward·(from × to), as
/// [`crate::polarization::Rotation::between`].
pub fn rotation_mueller(forward: DVec3, from: DVec3, to: DVec3) -> Mueller4 {
    let (cos_2, sin_2) = rotation_angle(forward, from, to);
    [[1.0, 0.0, 0.0, 0.0], [0.0, cos_2, sin_2, 0.0], [0.0, -sin_2, cos_2, 0.0], [0.0, 0.0, 0.0, 1.0]]
}

/// The s axis normalize(normal × forward) of an interface, or `fallback` (⟂ `forward`) at
/// normal incidence, where every frame is an s frame.
pub fn s_axis(normal: DVec3, forward: DVec3, fallback: DVec3) -> DVec3 {
    let s = normal.cross(forward);
    let length_squared = s.length_squared();
    if length_squared > PARALLEL_SQUARED {
        s * length_squared.sqrt().recip()
    } else {
        fallback
    }
}

/// The Stokes frame x axis normalize(`dir` × `up`) of a camera ray of direction `dir` (the
/// convention of [`crate::camera::Camera::stokes_x`]); light travels along −`dir`. Falls back
/// to a perpendicular of `dir` when `dir` ∥ `up`.
pub fn camera_stokes_x(dir: DVec3, up: DVec3) -> DVec3 {
    let x = dir.cross(up);
    let length_squared = x.length_squared();
    if length_squared > PARALLEL_SQUARED {
        x / length_squared.sqrt()
    } else {
        dir.any_orthonormal_vector()
    }
}

/// Degree of linear polarisation √(S1² + S2²)/S0 (0 for S0 = 0).
pub fn degree_of_linear_polarization(stokes: [f64; 4]) -> f64 {
    if stokes[0] > 0.0 {
        (stokes[1] * stokes[1] + stokes[2] * stokes[2]).sqrt() / stokes[0]
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::{fresnel_dielectric, fresnel_dielectric_amplitudes};

    #[test]
    fn agrees_with_the_f32_reference_functions() {
        // The f32 functions of crate::optics::fresnel (tested against Hecht and Mitsuba) take
        // eta = n_interior / n_exterior and a signed cosine; here exterior = incident side,
        // so eta = n_t / n_i and cos θi > 0. Their f32 rounding (~1e-7 per term, amplified
        // by up to ~25 where |cos θt| > 0.1, see their tests; under TIR the imaginary
        // cos θt amplifies it more, so there only |cos θt| > 0.2 is compared) bounds the
        // agreement: 3e-6.
        for (n_i, n_t) in [(1.0, 1.5), (1.5, 1.0), (1.0, 1.9), (1.62, 1.5), (1.33, 1.0)] {
            for step in 0..=40 {
                let cos_i = step as f64 / 40.0;
                let f = interface_fresnel(cos_i, n_i, n_t);
                let eta = (n_t / n_i) as f32;
                let reference = fresnel_dielectric(cos_i as f32, eta);
                let amplitudes = fresnel_dielectric_amplitudes(cos_i as f32, eta);
                let context = format!("{n_i}→{n_t}, cos θi {cos_i}: {f:?} vs {amplitudes:?}");
                // Away from the critical angle: |cos θt| > 0.1 (real) or > 0.2 (imaginary).
                let cos_t_sqr = 1.0 - (1.0 - cos_i * cos_i) * (n_i / n_t).powi(2);
                if !(-0.04..=0.01).contains(&cos_t_sqr) {
                    assert!((f.reflectance() - f64::from(reference.reflectance)).abs() < 3e-6, "{context}");
                    for (ours, theirs) in [
                        (f.r_s, amplitudes.r_s),
                        (f.r_p, amplitudes.r_p),
                        (f.t_s, amplitudes.t_s),
                        (f.t_p, amplitudes.t_p),
                    ] {
                        let theirs = Complex64::new(theirs.re.into(), theirs.im.into());
                        assert!((ours - theirs).norm() < 3e-6, "{context}");
                    }
                    assert!((f.transmittance_s - f64::from(amplitudes.transmittance_s)).abs() < 3e-6);
                    assert!((f.transmittance_p - f64::from(amplitudes.transmittance_p)).abs() < 3e-6);
                }
                // Energy, in f64: R + T = 1 per polarisation to rounding.
                assert!((f.reflectance_s + f.transmittance_s - 1.0).abs() < 1e-14, "{context}");
                assert!((f.reflectance_p + f.transmittance_p - 1.0).abs() < 1e-14, "{context}");
            }
        }
    }

    #[test]
    fn normal_incidence_reflects_the_textbook_fraction() {
        // Hecht §4.6.4: R = ((n_t − n_i)/(n_t + n_i))², r_p = −r_s.
        let f = interface_fresnel(1.0, 1.0, 1.5);
        assert!((f.reflectance() - 0.04).abs() < 1e-15);
        assert!((f.r_s + f.r_p).norm() < 1e-15 && f.r_s.re < 0.0);
    }

    #[test]
    fn transmission_mueller_is_the_flux_form() {
        // Outside TIR the transmitted Mueller has a = (T_s + T_p)/2, b = (T_s − T_p)/2 and
        // w = √(T_s T_p) (t_s, t_p real positive), as crate::polarization's f32 form.
        let f = interface_fresnel(0.6, 1.0, 1.5);
        let m = transmission_mueller(&f);
        assert!((m[0][0] - f.transmittance()).abs() < 1e-15);
        assert!((m[0][1] - 0.5 * (f.transmittance_s - f.transmittance_p)).abs() < 1e-15);
        assert!((m[2][2] - (f.transmittance_s * f.transmittance_p).sqrt()).abs() < 1e-15);
        let r = reflection_mueller(&f);
        // Energy per polarisation: the first rows of R and T add to (1, 0).
        assert!((m[0][0] + r[0][0] - 1.0).abs() < 1e-15 && (m[0][1] + r[0][1]).abs() < 1e-15);
    }

    #[test]
    fn real_coefficients_are_the_complex_formulas() {
        // Outside TIR the real-arithmetic path must give Hecht's complex formulas' numbers
        // (evaluated here in Complex64 as interface_fresnel did before it had the real path),
        // to rounding: a few ulps of numbers ≤ 2 (1e-15).
        for (n_i, n_t) in [(1.0, 1.5168), (1.7, 1.0), (1.62, 1.52)] {
            for step in 0..=40 {
                let cos_i = step as f64 / 40.0;
                let f = interface_fresnel(cos_i, n_i, n_t);
                if f.total_internal_reflection || cos_i == 0.0 {
                    continue;
                }
                let eta = n_t / n_i;
                let cos_t = Complex64::new((1.0 - (1.0 - cos_i * cos_i) / (eta * eta)).sqrt(), 0.0);
                let (d_s, d_p) = (cos_i + eta * cos_t, eta * cos_i + cos_t);
                let r_s = (cos_i - eta * cos_t) / d_s;
                let r_p = (eta * cos_i - cos_t) / d_p;
                let (t_s, t_p) = (2.0 * cos_i / d_s, 2.0 * cos_i / d_p);
                for (ours, theirs) in [(f.r_s, r_s), (f.r_p, r_p), (f.t_s, t_s), (f.t_p, t_p)] {
                    assert!((ours - theirs).norm() < 1e-15, "{n_i}→{n_t} cos {cos_i}: {ours} vs {theirs}");
                }
                let flux = 4.0 * cos_i * eta * cos_t.re;
                assert!((f.transmittance_s - flux / d_s.norm_sqr()).abs() < 1e-15);
                assert!((f.transmittance_p - flux / d_p.norm_sqr()).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn row_steps_are_the_matrix_products_to_the_bit() {
        // r·Rot·E computed row by row must be row r of mueller_mul(mueller_mul(P, Rot), E):
        // the same products in the same order, the 4×4 products' other terms exact zeros.
        let forward = DVec3::new(0.2, -0.4, 0.9).normalize();
        let from = forward.any_orthonormal_vector();
        let to = (from * 0.3 + forward.cross(from) * 0.8).normalize();
        let f = interface_fresnel(0.7, 1.0, 1.6);
        let path: Mueller4 = [
            [0.9, 0.05, -0.02, 0.001],
            [0.04, 0.8, 0.1, -0.003],
            [-0.01, 0.2, 0.7, 0.05],
            [0.002, -0.01, 0.04, 0.6],
        ];
        let (cos_2, sin_2) = rotation_angle(forward, from, to);
        for (element, matrix) in [
            (DiagonalElement::transmission(&f), transmission_mueller(&f)),
            (DiagonalElement::reflection(&f), reflection_mueller(&f)),
        ] {
            let full = mueller_mul(&mueller_mul(&path, &rotation_mueller(forward, from, to)), &matrix);
            for (row, expected) in path.iter().zip(full) {
                assert_eq!(rotate_then_element(*row, cos_2, sin_2, &element), expected);
            }
        }
        let rotated = mueller_mul(&path, &rotation_mueller(forward, from, to));
        for (row, expected) in path.iter().zip(rotated) {
            assert_eq!(rotate_row(*row, cos_2, sin_2), expected);
        }
    }

    #[test]
    fn rotation_matches_the_f32_rotation() {
        let forward = DVec3::new(0.3, -0.5, 0.81).normalize();
        let from = forward.any_orthonormal_vector();
        let y = forward.cross(from);
        let angle = 0.7_f64;
        let to = from * angle.cos() + y * angle.sin();
        let m = rotation_mueller(forward, from, to);
        let reference = crate::polarization::Rotation::by_angle(angle as f32);
        assert!((m[1][1] - f64::from(reference.cos_2theta)).abs() < 1e-6);
        assert!((m[1][2] - f64::from(reference.sin_2theta)).abs() < 1e-6);
    }
}
