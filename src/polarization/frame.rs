//! Reference frames of Stokes vectors: the x axis a beam's Stokes vector is written in, and the
//! [`Rotation`] that re-expresses it in another frame about the same direction.
//!
//! The Stokes frame of a camera ray of direction d has x = normalize(d × up) with `up` the
//! camera's up vector (image right for the central ray) and light travelling along −d, as in
//! Mitsuba 3's `stokes` integrator. At an interface the frame is the s axis
//! `normalize(n × f)` for light travelling along f (see [`crate::polarization`]).

use glam::Vec3;

/// Below this squared length a cross product is treated as zero (parallel vectors): the
/// plane of incidence is undefined within float rounding at normal incidence.
const PARALLEL_SQUARED: f32 = 1e-12;

/// A change of Stokes frame about a beam's direction: the new x axis is the old one turned by
/// θ counter-clockwise as seen by the receiver (right-handed about the direction of travel).
/// Holds cos 2θ and sin 2θ, all a Stokes vector needs ([`super::Stokes::rotated`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rotation {
    /// cos 2θ.
    pub cos_2theta: f32,
    /// sin 2θ.
    pub sin_2theta: f32,
}

impl Rotation {
    /// No change of frame.
    pub const IDENTITY: Self = Self { cos_2theta: 1.0, sin_2theta: 0.0 };

    /// The change of frame that turns the x axis by `theta` radians counter-clockwise about the
    /// direction of travel.
    pub fn by_angle(theta: f32) -> Self {
        let (sin_2theta, cos_2theta) = (2.0 * theta).sin_cos();
        Self { cos_2theta, sin_2theta }
    }

    /// The change of frame from x axis `from` to x axis `to` for light travelling along
    /// `forward` (unit vectors, `from` and `to` perpendicular to `forward`). θ is read from the
    /// vectors themselves: cos θ = from·to, sin θ = forward·(from × to).
    #[inline]
    pub fn between(forward: Vec3, from: Vec3, to: Vec3) -> Self {
        let cos_theta = from.dot(to);
        let sin_theta = forward.dot(from.cross(to));
        // Divided by cos² + sin² (1 for exact unit vectors), so that rounding in the vectors
        // cannot make the rotation scale the polarised part.
        let norm = cos_theta * cos_theta + sin_theta * sin_theta;
        if norm <= 0.0 {
            return Self::IDENTITY;
        }
        Self {
            cos_2theta: (cos_theta * cos_theta - sin_theta * sin_theta) / norm,
            sin_2theta: 2.0 * sin_theta * cos_theta / norm,
        }
    }

    /// The rotation by −θ: what a rotation matrix built transposed would do. Only for the
    /// validation fault that proves the frame tests can see it.
    pub fn transposed(self) -> Self {
        Self { sin_2theta: -self.sin_2theta, ..self }
    }
}

/// The s axis of an interface of normal `normal` for light travelling along `forward`:
/// normalize(normal × forward), perpendicular to the plane of incidence. At normal incidence,
/// where the plane is undefined, `fallback` (a unit vector perpendicular to `forward`) is used:
/// every frame is then an s frame.
#[inline]
pub fn s_axis(normal: Vec3, forward: Vec3, fallback: Vec3) -> Vec3 {
    let s = normal.cross(forward);
    let length_squared = s.length_squared();
    if length_squared > PARALLEL_SQUARED {
        s / length_squared.sqrt()
    } else {
        fallback
    }
}

/// A unit vector perpendicular to the unit vector `v` (Duff et al. 2017's branchless basis),
/// for beams that need some frame and have no preferred one.
#[inline]
pub fn any_perpendicular(v: Vec3) -> Vec3 {
    let sign = 1f32.copysign(v.z);
    let a = -1.0 / (sign + v.z);
    let b = v.x * v.y * a;
    Vec3::new(1.0 + sign * v.x * v.x * a, sign * b, -sign * v.x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polarization::Stokes;
    use crate::spectrum::SampledSpectrum;
    use num_complex::Complex64;

    /// Stokes parameters of the complex field components (E_x, E_y) of a wave `E·e^{+iωt}`
    /// (the module's time convention), from their definitions.
    fn stokes_of(ex: Complex64, ey: Complex64) -> [f64; 4] {
        let cross = ex * ey.conj();
        [ex.norm_sqr() + ey.norm_sqr(), ex.norm_sqr() - ey.norm_sqr(), 2.0 * cross.re, -2.0 * cross.im]
    }

    fn as_stokes(values: [f64; 4]) -> Stokes {
        Stokes { s: values.map(|v| SampledSpectrum::splat(v as f32)) }
    }

    /// The physical test of the rotation: a field given by its complex components in frame a is
    /// turned into a vector in space, projected onto frame b, and its Stokes vector computed
    /// there from the definitions; `Rotation::between` must give the same numbers. A rotation
    /// matrix built transposed (the glam row/column trap) fails on S2 for elliptical light.
    #[test]
    fn rotation_follows_the_electric_field() {
        let forward = Vec3::new(0.3, -0.5, 0.81).normalize();
        let x_a = any_perpendicular(forward);
        let y_a = forward.cross(x_a);
        let field_a = (Complex64::new(0.8, 0.1), Complex64::new(0.3, -0.45));
        for angle_deg in [10.0f32, 30.0, 45.0, 100.0, 200.0, -70.0] {
            let angle = angle_deg.to_radians();
            let x_b = x_a * angle.cos() + y_a * angle.sin();
            let y_b = forward.cross(x_b);
            let project = |axis: Vec3| {
                let (u, v) = (f64::from(x_a.dot(axis)), f64::from(y_a.dot(axis)));
                field_a.0 * u + field_a.1 * v
            };
            let expected = stokes_of(project(x_b), project(y_b));
            let turned =
                as_stokes(stokes_of(field_a.0, field_a.1)).rotated(Rotation::between(forward, x_a, x_b));
            for (k, want) in expected.iter().enumerate() {
                let got = f64::from(turned.s[k][0]);
                assert!((got - want).abs() < 1e-5, "S{k} at {angle_deg}°: {got} vs {want}");
            }
            let wrong = as_stokes(stokes_of(field_a.0, field_a.1))
                .rotated(Rotation::between(forward, x_a, x_b).transposed());
            assert!(
                (f64::from(wrong.s[2][0]) - expected[2]).abs() > 1e-2,
                "the transposed rotation must differ"
            );
        }
    }

    #[test]
    fn between_matches_by_angle() {
        let forward = Vec3::Z;
        let rotation = Rotation::between(forward, Vec3::X, Vec3::new(0.5, 0.75f32.sqrt(), 0.0));
        let expected = Rotation::by_angle(60f32.to_radians());
        assert!((rotation.cos_2theta - expected.cos_2theta).abs() < 1e-6);
        assert!((rotation.sin_2theta - expected.sin_2theta).abs() < 1e-6);
    }

    #[test]
    fn s_axis_is_perpendicular_to_the_plane_of_incidence() {
        let normal = Vec3::Y;
        let forward = Vec3::new(1.0, -1.0, 0.0).normalize();
        let s = s_axis(normal, forward, Vec3::X);
        assert!((s - Vec3::new(0.0, 0.0, 1.0)).length() < 1e-6 || (s + Vec3::Z).length() < 1e-6);
        // At normal incidence the fallback is used.
        assert_eq!(s_axis(normal, -Vec3::Y, Vec3::X), Vec3::X);
    }

    #[test]
    fn any_perpendicular_is_a_unit_normal() {
        for v in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::Z, Vec3::new(0.2, -0.9, 0.1).normalize()] {
            let p = any_perpendicular(v);
            assert!(p.dot(v).abs() < 1e-6 && (p.length() - 1.0).abs() < 1e-6, "{v} -> {p}");
        }
    }
}
