//! An independent reference for polarised light along a specular path: the electric field as a
//! complex 3-vector in world space (polarisation ray tracing in the manner of Chipman's 3×3
//! method), f64, in the physicist's time convention `E·e^{i(k·r − ωt)}`.
//!
//! It shares nothing with the renderer's polarisation code: no Stokes vectors until the very
//! end, no frames or rotations, the opposite time convention (absorbing media have n + ik, an
//! evanescent wave has η·cos θt = +i·√(sin²θi − η²)), and the Fresnel amplitudes written out
//! here from Hecht §4.6. Each element acts on the field itself:
//! - reflection: E' = r_s (E·s) s + r_p (E·p_in) p_out, with s = n × k_in normalised, p = k × s
//!   for the incident and reflected directions (Hecht's signs: r_p = −r_s at normal incidence,
//!   where p_out = −p_in);
//! - an ideal linear polariser sheet (Korger et al. 2013): the field along the absorbing axis
//!   a = normal × t, projected onto the wavefront, is removed;
//! - an ideal retarder: the field along the slow axis (the wavefront direction perpendicular to
//!   the projected fast axis) is delayed by φ, a factor e^{+iφ} in this convention.
//!
//! Unpolarised light is the incoherent sum of two orthogonal linear polarisations of half the
//! power each. The Stokes vector is read at the end in a frame (x, y = k × x) from the field
//! components, with S3 > 0 when the field turns clockwise for the receiver (here
//! S3 = 2·Im(E_x·conj(E_y)); the tests check that sense against E(t)).

use glam::DVec3;
use num_complex::Complex64;

/// A complex field vector in world space.
pub type Field = [Complex64; 3];

/// An element a ray meets along a specular path.
#[derive(Debug, Clone, Copy)]
pub enum Element {
    /// Reflection off an interface of normal `normal` (either side) into a medium of relative
    /// index `eta` = n_beyond/n_here (complex n + ik for conductors; real past which total
    /// internal reflection may happen).
    Reflection {
        /// Surface normal (either orientation).
        normal: DVec3,
        /// Relative index of the medium beyond the surface.
        eta: Complex64,
    },
    /// Reflection with given amplitudes (Hecht's signs, this module's `e^{−iωt}` convention),
    /// e.g. a coated surface's from an external transfer-matrix code.
    Amplitudes {
        /// Surface normal (either orientation).
        normal: DVec3,
        /// r_s.
        r_s: Complex64,
        /// r_p.
        r_p: Complex64,
    },
    /// A perfect electric conductor: r_s = −1, r_p = +1.
    PerfectMirror {
        /// Surface normal (either orientation).
        normal: DVec3,
    },
    /// An ideal linear polariser sheet of normal `normal` and transmission axis `axis` (in its
    /// plane).
    Polarizer {
        /// Sheet normal.
        normal: DVec3,
        /// Transmission axis.
        axis: DVec3,
    },
    /// An ideal linear retarder of normal `normal` whose fast-axis field leads by `retardance`.
    Retarder {
        /// Sheet normal.
        normal: DVec3,
        /// Fast axis (in the sheet's plane).
        fast_axis: DVec3,
        /// Retardance, radians.
        retardance: f64,
    },
}

fn dot(field: &Field, v: DVec3) -> Complex64 {
    field[0] * v.x + field[1] * v.y + field[2] * v.z
}

fn scaled(v: DVec3, amplitude: Complex64) -> Field {
    [amplitude * v.x, amplitude * v.y, amplitude * v.z]
}

fn add(a: Field, b: Field) -> Field {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Hecht's amplitude reflection coefficients (r_s, r_p) for incidence at `cos_i` on a medium of
/// relative index `eta`, with η·cos θt = √(η² − sin²θi) taken with Im ≥ 0 (the transmitted
/// wave decays in the `e^{−iωt}` convention).
pub fn reflection_amplitudes(cos_i: f64, eta: Complex64) -> (Complex64, Complex64) {
    let cos_i = cos_i.abs();
    let sin_sqr = 1.0 - cos_i * cos_i;
    let mut w = (eta * eta - sin_sqr).sqrt();
    if w.im < 0.0 || (w.im == 0.0 && w.re < 0.0) {
        w = -w;
    }
    let r_s = (cos_i - w) / (cos_i + w);
    let r_p = (eta * eta * cos_i - w) / (eta * eta * cos_i + w);
    (r_s, r_p)
}

/// The field after `element`, for light travelling along unit `k`; returns the new field and
/// direction.
pub fn apply(field: Field, k: DVec3, element: &Element) -> (Field, DVec3) {
    match *element {
        Element::Reflection { normal, eta } => {
            let (r_s, r_p) = reflection_amplitudes(k.dot(normal), eta);
            reflect(field, k, normal, r_s, r_p)
        }
        Element::Amplitudes { normal, r_s, r_p } => reflect(field, k, normal, r_s, r_p),
        Element::PerfectMirror { normal } => {
            reflect(field, k, normal, Complex64::new(-1.0, 0.0), Complex64::new(1.0, 0.0))
        }
        Element::Polarizer { normal, axis } => {
            let absorbing = normal.cross(axis);
            let across = (absorbing - absorbing.dot(k) * k).normalize();
            let removed = scaled(across, -dot(&field, across));
            (add(field, removed), k)
        }
        Element::Retarder { normal, fast_axis, retardance } => {
            let in_plane = fast_axis - fast_axis.dot(normal) * normal;
            let fast = (in_plane - in_plane.dot(k) * k).normalize();
            let slow = k.cross(fast);
            let delay = Complex64::from_polar(1.0, retardance);
            (add(scaled(fast, dot(&field, fast)), scaled(slow, dot(&field, slow) * delay)), k)
        }
    }
}

fn reflect(field: Field, k: DVec3, normal: DVec3, r_s: Complex64, r_p: Complex64) -> (Field, DVec3) {
    let k_out = k - 2.0 * k.dot(normal) * normal;
    let cross = normal.cross(k);
    let s = if cross.length_squared() > 1e-24 { cross.normalize() } else { k.any_orthonormal_vector() };
    let (p_in, p_out) = (k.cross(s), k_out.cross(s));
    (add(scaled(s, r_s * dot(&field, s)), scaled(p_out, r_p * dot(&field, p_in))), k_out)
}

/// Stokes vector (S0, S1, S2, S3) of `field` travelling along `k`, read in the frame of x axis
/// `x` (perpendicular to `k`), y = k × x.
pub fn stokes(field: &Field, k: DVec3, x: DVec3) -> [f64; 4] {
    let y = k.cross(x);
    let (ex, ey) = (dot(field, x), dot(field, y));
    let cross = ex * ey.conj();
    [ex.norm_sqr() + ey.norm_sqr(), ex.norm_sqr() - ey.norm_sqr(), 2.0 * cross.re, 2.0 * cross.im]
}

/// The Stokes vector reaching a receiver from unpolarised light of radiance `radiance` that
/// leaves along `k0` and meets `elements` in order, read in the frame of x axis `x_at(k)` for
/// the final direction k. Two orthogonal linear polarisations of half the power each, traced
/// separately and summed incoherently.
pub fn unpolarized_through(
    radiance: f64,
    k0: DVec3,
    elements: &[Element],
    x_at: impl Fn(DVec3) -> DVec3,
) -> [f64; 4] {
    let first = k0.any_orthonormal_vector();
    let second = k0.cross(first);
    let amplitude = (0.5 * radiance).sqrt();
    let mut total = [0.0; 4];
    for polarisation in [first, second] {
        let mut field = scaled(polarisation, Complex64::new(amplitude, 0.0));
        let mut k = k0;
        for element in elements {
            (field, k) = apply(field, k, element);
        }
        for (sum, value) in total.iter_mut().zip(stokes(&field, k, x_at(k))) {
            *sum += value;
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    /// In this convention E(t) = Re[E·e^{−iωt}]: E = (1, i) turns from x towards y
    /// (counter-clockwise for the receiver), and must read S3 < 0.
    #[test]
    fn s3_sign_follows_the_field_rotation() {
        let k = DVec3::Z;
        let field: Field = [Complex64::new(1.0, 0.0), Complex64::new(0.0, 1.0), Complex64::new(0.0, 0.0)];
        let at = |t: f64| {
            let phase = Complex64::from_polar(1.0, -t);
            ((field[0] * phase).re, (field[1] * phase).re)
        };
        let (e0, e1) = (at(0.0), at(0.01));
        assert!(e0.0 * e1.1 - e0.1 * e1.0 > 0.0, "counter-clockwise in the x-right, y-up view");
        assert!(stokes(&field, k, DVec3::X)[3] < 0.0);
    }

    /// Normal-incidence reflectance ((n − 1)² + k²)/((n + 1)² + k²) and Brewster's zero.
    #[test]
    fn amplitudes_give_textbook_reflectances() {
        let (r_s, r_p) = reflection_amplitudes(1.0, Complex64::new(0.35, 2.71));
        let expected = (0.65f64.powi(2) + 2.71f64.powi(2)) / (1.35f64.powi(2) + 2.71f64.powi(2));
        assert!((r_s.norm_sqr() - expected).abs() < 1e-12 && (r_p.norm_sqr() - expected).abs() < 1e-12);
        let brewster = 1.5f64.atan();
        let (_, r_p) = reflection_amplitudes(brewster.cos(), Complex64::new(1.5, 0.0));
        assert!(r_p.norm() < 1e-12);
        // Total internal reflection keeps all the power.
        let (r_s, r_p) = reflection_amplitudes(0.3, Complex64::new(1.0 / 1.5, 0.0));
        assert!((r_s.norm() - 1.0).abs() < 1e-12 && (r_p.norm() - 1.0).abs() < 1e-12);
    }

    /// Two crossed polarisers pass nothing; at 60°, a quarter of the half that the first passes.
    #[test]
    fn polarisers_follow_malus() {
        let normal = DVec3::Z;
        let through = |theta: f64| {
            let elements = [
                Element::Polarizer { normal, axis: DVec3::X },
                Element::Polarizer { normal, axis: DVec3::new(theta.cos(), theta.sin(), 0.0) },
            ];
            unpolarized_through(1.0, DVec3::Z, &elements, |_| DVec3::X)[0]
        };
        assert!(through(std::f64::consts::FRAC_PI_2) < 1e-24);
        assert!((through(60f64.to_radians()) - 0.125).abs() < 1e-12);
    }
}
