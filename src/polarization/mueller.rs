//! [`Mueller`]: the Mueller matrices of the elements prisma models, all of them diagonal in
//! some frame of their own (a Jones matrix diag(A_x, A_y)): dielectric reflection and
//! refraction in the s/p frame of the interface, conductors and the ideal mirror, the linear
//! polariser along its transmission axis and the linear retarder along its fast axis. The
//! matrix form and its sign conventions are in [`crate::polarization`].

use num_complex::Complex32;

use super::Stokes;
use crate::optics::DielectricFresnel;
use crate::spectrum::{SampledSpectrum, N_LAMBDA};

/// The Mueller matrix of a Jones matrix diag(A_x, A_y) at one wavelength:
/// a = (|A_x|² + |A_y|²)/2, b = (|A_x|² − |A_y|²)/2, w = A_x·conj(A_y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JonesDiagonal {
    /// (|A_x|² + |A_y|²)/2: the transmittance of unpolarised light.
    pub a: f32,
    /// (|A_x|² − |A_y|²)/2: the diattenuation times `a`.
    pub b: f32,
    /// Re(A_x·conj(A_y)).
    pub w_re: f32,
    /// Im(A_x·conj(A_y)): non-zero only for elements with a phase difference between x and y.
    pub w_im: f32,
}

impl JonesDiagonal {
    /// The element of Jones matrix diag(`a_x`, `a_y`) (complex amplitudes, `e^{+iωt}` convention).
    pub fn new(a_x: Complex32, a_y: Complex32) -> Self {
        let (power_x, power_y) = (a_x.norm_sqr(), a_y.norm_sqr());
        let w = a_x * a_y.conj();
        Self { a: 0.5 * (power_x + power_y), b: 0.5 * (power_x - power_y), w_re: w.re, w_im: w.im }
    }

    /// The element of real amplitudes `a_x`, `a_y` (no phase difference beyond a sign).
    pub fn real(a_x: f32, a_y: f32) -> Self {
        Self {
            a: 0.5 * (a_x * a_x + a_y * a_y),
            b: 0.5 * (a_x * a_x - a_y * a_y),
            w_re: a_x * a_y,
            w_im: 0.0,
        }
    }

    /// A non-polarising attenuation by `factor`: `factor` times the identity.
    pub fn attenuator(factor: f32) -> Self {
        Self { a: factor, b: 0.0, w_re: factor, w_im: 0.0 }
    }

    /// An ideal mirror, a perfect electric conductor: (r_s, r_p) = (−1, +1) in the s/p frame,
    /// the limit of every conductor's Fresnel amplitudes as |n + ik| → ∞. Mueller
    /// diag(1, 1, −1, −1).
    pub const PERFECT_CONDUCTOR: Self = Self { a: 1.0, b: 0.0, w_re: -1.0, w_im: 0.0 };

    /// An ideal linear polariser with its transmission axis along x, transmitting the fraction
    /// `transmittance` of the light polarised along it: (A_x, A_y) = (√T, 0).
    pub fn linear_polarizer(transmittance: f32) -> Self {
        let half = 0.5 * transmittance;
        Self { a: half, b: half, w_re: 0.0, w_im: 0.0 }
    }

    /// An ideal linear retarder with its fast axis along x: the field along the fast axis leads
    /// the other by `retardance_rad`, (A_x, A_y) = (1, e^{−iφ}) in the `e^{+iωt}` convention.
    /// A quarter-wave plate turns light at +45° into light turning counter-clockwise for the
    /// receiver (S3 = −S0).
    pub fn linear_retarder(retardance_rad: f32) -> Self {
        let (sin, cos) = retardance_rad.sin_cos();
        Self { a: 1.0, b: 0.0, w_re: cos, w_im: sin }
    }

    /// Reflection at a dielectric interface in its s/p frame (x = s), from the Fresnel
    /// coefficients `fresnel` of [`crate::optics::fresnel_dielectric`] at `cos_theta_i`:
    /// real amplitudes outside total internal reflection, the phases of r_s = e^{iφs},
    /// r_p = e^{iφp} under it (cos θt = −i·q, q = √(sin²θi/η_it² − 1): the decaying root in the
    /// `e^{+iωt}` convention, as Mitsuba's `fresnel_polarized`).
    pub fn dielectric_reflection(cos_theta_i: f32, fresnel: &DielectricFresnel) -> Self {
        if fresnel.reflectance < 1.0 {
            return Self::real(fresnel.r_s, fresnel.r_p);
        }
        let cos_i = cos_theta_i.abs();
        let eta_it = fresnel.eta_it;
        let sin_sqr = (-cos_i).mul_add(cos_i, 1.0);
        let q = (sin_sqr / (eta_it * eta_it) - 1.0).max(0.0).sqrt();
        // r = (x + iy)/(x − iy) = (x + iy)²/(x² + y²), of modulus 1.
        let unit_ratio = |x: f32, y: f32| {
            let norm = x * x + y * y;
            if norm > 0.0 {
                Complex32::new((x * x - y * y) / norm, 2.0 * x * y / norm)
            } else {
                Complex32::new(1.0, 0.0)
            }
        };
        let r_s = unit_ratio(cos_i, eta_it * q);
        let r_p = unit_ratio(eta_it * cos_i, q);
        Self::new(r_s, r_p)
    }

    /// Refraction at a dielectric interface in its s/p frame (x = s), as flux: T_s = 1 − R_s,
    /// T_p = 1 − R_p and w = √(T_s·T_p) (t_s, t_p > 0 and real outside total internal
    /// reflection, where the flux factor η_it·cos θt/cos θi times t_s·t_p is that root). The
    /// radiance scaling 1/η_it² across the interface is not included. Zero under total internal
    /// reflection.
    pub fn dielectric_transmission(fresnel: &DielectricFresnel) -> Self {
        if fresnel.reflectance >= 1.0 {
            return Self { a: 0.0, b: 0.0, w_re: 0.0, w_im: 0.0 };
        }
        let transmittance_s = 1.0 - fresnel.reflectance_s;
        let transmittance_p = 1.0 - fresnel.reflectance_p;
        Self {
            a: 0.5 * (transmittance_s + transmittance_p),
            b: 0.5 * (transmittance_s - transmittance_p),
            w_re: (transmittance_s * transmittance_p).max(0.0).sqrt(),
            w_im: 0.0,
        }
    }

    /// The same element with the sign of its phase term flipped: what a wrong time convention
    /// (or `atan2(x, y)` for `atan2(y, x)`) does. Only for the validation fault.
    pub fn phase_flipped(self) -> Self {
        Self { w_im: -self.w_im, ..self }
    }
}

/// The Mueller matrices of one interaction at every wavelength lane, each diagonal-Jones in the
/// same frame ([`JonesDiagonal`] lane by lane, stored component by component).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mueller {
    /// a at every lane.
    pub a: SampledSpectrum,
    /// b at every lane.
    pub b: SampledSpectrum,
    /// Re w at every lane.
    pub w_re: SampledSpectrum,
    /// Im w at every lane.
    pub w_im: SampledSpectrum,
}

impl Mueller {
    /// The same element at every lane.
    #[inline]
    pub fn splat(element: JonesDiagonal) -> Self {
        Self {
            a: SampledSpectrum::splat(element.a),
            b: SampledSpectrum::splat(element.b),
            w_re: SampledSpectrum::splat(element.w_re),
            w_im: SampledSpectrum::splat(element.w_im),
        }
    }

    /// Lane `i` takes `elements[i]`.
    #[inline]
    pub fn from_lanes(elements: &[JonesDiagonal; N_LAMBDA]) -> Self {
        Self {
            a: SampledSpectrum { values: elements.map(|e| e.a) },
            b: SampledSpectrum { values: elements.map(|e| e.b) },
            w_re: SampledSpectrum { values: elements.map(|e| e.w_re) },
            w_im: SampledSpectrum { values: elements.map(|e| e.w_im) },
        }
    }

    /// The Mueller matrix of Jones matrix diag(`a_x`, `a_y`) at one wavelength (see
    /// [`JonesDiagonal::new`]), for every lane.
    pub fn from_jones_diagonal(a_x: Complex32, a_y: Complex32) -> Self {
        Self::splat(JonesDiagonal::new(a_x, a_y))
    }

    /// A non-polarising attenuation by `weight`, lane by lane: `weight` times the identity.
    #[inline]
    pub fn attenuation(weight: SampledSpectrum) -> Self {
        Self { a: weight, b: SampledSpectrum::zero(), w_re: weight, w_im: SampledSpectrum::zero() }
    }

    /// The same matrices with the sign of their phase terms flipped (see
    /// [`JonesDiagonal::phase_flipped`]); only for the validation fault.
    pub fn phase_flipped(self) -> Self {
        Self { w_im: self.w_im * -1.0, ..self }
    }

    /// Every entry multiplied lane-wise by `weight` (a non-polarising attenuation).
    #[inline]
    pub fn scaled(self, weight: SampledSpectrum) -> Self {
        Self { a: self.a * weight, b: self.b * weight, w_re: self.w_re * weight, w_im: self.w_im * weight }
    }

    /// M·S for `stokes` in this element's frame (its x axis on both sides).
    #[inline]
    pub fn apply(&self, stokes: &Stokes) -> Stokes {
        let [s0, s1, s2, s3] = stokes.s;
        Stokes {
            s: [
                self.a * s0 + self.b * s1,
                self.b * s0 + self.a * s1,
                self.w_re * s2 + self.w_im * s3,
                self.w_re * s3 - self.w_im * s2,
            ],
        }
    }

    /// The first row of the matrix applied to `stokes`: the radiance S0 after the element,
    /// a·S0 + b·S1, without the rest.
    #[inline]
    pub fn apply_intensity(&self, stokes: &Stokes) -> SampledSpectrum {
        self.a * stokes.s[0] + self.b * stokes.s[1]
    }

    /// The 4×4 matrix at lane `lane`, row-major, for tests and plots.
    pub fn matrix(&self, lane: usize) -> [[f32; 4]; 4] {
        let (a, b, wr, wi) = (self.a[lane], self.b[lane], self.w_re[lane], self.w_im[lane]);
        [[a, b, 0.0, 0.0], [b, a, 0.0, 0.0], [0.0, 0.0, wr, wi], [0.0, 0.0, -wi, wr]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::{fresnel_dielectric, fresnel_dielectric_amplitudes};
    use num_complex::Complex64;

    fn stokes(values: [f32; 4]) -> Stokes {
        Stokes { s: values.map(SampledSpectrum::splat) }
    }

    fn stokes_of(ex: Complex64, ey: Complex64) -> [f64; 4] {
        let cross = ex * ey.conj();
        [ex.norm_sqr() + ey.norm_sqr(), ex.norm_sqr() - ey.norm_sqr(), 2.0 * cross.re, -2.0 * cross.im]
    }

    /// +1 if the real field E(t) = Re[(E_x, E_y)·e^{+iωt}] turns clockwise in the (x right,
    /// y up) view of the receiver, −1 counter-clockwise: the sign of −(E(0) × E(dt))·z.
    fn turns_clockwise(ex: Complex64, ey: Complex64) -> f64 {
        let at = |t: f64| {
            let phase = Complex64::new(t.cos(), t.sin());
            ((ex * phase).re, (ey * phase).re)
        };
        let (e0, e1) = (at(0.0), at(0.01));
        let cross_z = e0.0 * e1.1 - e0.1 * e1.0;
        -cross_z.signum()
    }

    /// Applying the Mueller matrix of diag(A_x, A_y) to the Stokes vector of a field gives the
    /// Stokes vector of the transformed field, for fields and elements with arbitrary phases.
    #[test]
    fn mueller_matrix_acts_as_its_jones_matrix() {
        let fields = [
            (Complex64::new(1.0, 0.0), Complex64::new(0.0, 1.0)),
            (Complex64::new(0.6, -0.2), Complex64::new(0.3, 0.7)),
            (Complex64::new(0.0, 0.0), Complex64::new(1.0, -1.0)),
        ];
        let elements = [
            (Complex32::new(0.9, 0.2), Complex32::new(-0.3, 0.5)),
            (Complex32::new(-1.0, 0.0), Complex32::new(1.0, 0.0)),
            (Complex32::new(0.0, 1.0), Complex32::new(0.7, 0.0)),
        ];
        for (ex, ey) in fields {
            for (ax, ay) in elements {
                let input = stokes_of(ex, ey).map(|v| v as f32);
                let output = Mueller::from_jones_diagonal(ax, ay).apply(&stokes(input));
                let (ax64, ay64) =
                    (Complex64::new(ax.re.into(), ax.im.into()), Complex64::new(ay.re.into(), ay.im.into()));
                let expected = stokes_of(ax64 * ex, ay64 * ey);
                for (k, want) in expected.iter().enumerate() {
                    assert!((f64::from(output.s[k][0]) - want).abs() < 1e-5, "S{k}");
                }
            }
        }
    }

    /// The sign of S3 is the sense in which the field turns, read off E(t) itself.
    #[test]
    fn s3_is_positive_for_a_field_turning_clockwise_for_the_receiver() {
        for (ex, ey) in [
            (Complex64::new(1.0, 0.0), Complex64::new(0.0, 1.0)),
            (Complex64::new(1.0, 0.0), Complex64::new(0.0, -1.0)),
            (Complex64::new(0.4, 0.3), Complex64::new(-0.2, 0.5)),
            (Complex64::new(0.4, 0.3), Complex64::new(0.5, -0.2)),
        ] {
            let s3 = stokes_of(ex, ey)[3];
            assert_eq!(s3.signum(), turns_clockwise(ex, ey), "field ({ex}, {ey}), S3 = {s3}");
        }
    }

    /// A quarter-wave plate with its fast axis along x delays y by a quarter period: light at
    /// +45° leaves with E = (cos ωt, sin ωt), turning counter-clockwise for the receiver.
    #[test]
    fn quarter_wave_plate_makes_counter_clockwise_light_from_plus_45_degrees() {
        let out = Mueller::splat(JonesDiagonal::linear_retarder(std::f32::consts::FRAC_PI_2))
            .apply(&stokes([1.0, 0.0, 1.0, 0.0]));
        assert!((out.s[3][0] + 1.0).abs() < 1e-6 && out.s[2][0].abs() < 1e-6, "{out:?}");
        let field_after = (Complex64::new(1.0, 0.0), Complex64::new(0.0, -1.0)); // (1, e^{−iπ/2})
        assert_eq!(turns_clockwise(field_after.0, field_after.1), -1.0);
        // A half-wave plate mirrors +45° to −45°.
        let half = Mueller::splat(JonesDiagonal::linear_retarder(std::f32::consts::PI))
            .apply(&stokes([1.0, 0.0, 1.0, 0.0]));
        assert!((half.s[2][0] + 1.0).abs() < 1e-6 && half.s[3][0].abs() < 1e-6);
    }

    /// Malus: unpolarised light through a polariser keeps half its power, all of it along the
    /// axis; light polarised along the axis passes whole, across it not at all.
    #[test]
    fn ideal_polariser_follows_malus() {
        let polariser = Mueller::splat(JonesDiagonal::linear_polarizer(1.0));
        let out = polariser.apply(&stokes([1.0, 0.0, 0.0, 0.0]));
        assert_eq!([out.s[0][0], out.s[1][0], out.s[2][0], out.s[3][0]], [0.5, 0.5, 0.0, 0.0]);
        assert_eq!(polariser.apply(&stokes([1.0, 1.0, 0.0, 0.0])).s[0][0], 1.0);
        assert_eq!(polariser.apply(&stokes([1.0, -1.0, 0.0, 0.0])).s[0][0], 0.0);
    }

    /// Outside total internal reflection the reflection matrix has a = R, b = (R_s − R_p)/2 and
    /// c = r_s·r_p; Mitsuba's `specular_reflection` at 45°, n = 1.5, has (2,2) = −0.0279.
    #[test]
    fn dielectric_reflection_matches_its_amplitudes() {
        let cos = std::f32::consts::FRAC_1_SQRT_2;
        let m = JonesDiagonal::dielectric_reflection(cos, &fresnel_dielectric(cos, 1.5));
        assert!((m.w_re + 0.0279).abs() < 5e-5, "{m:?}");
        for (cos, eta) in
            [(0.9f32, 1.5f32), (0.3, 1.5), (0.95, 1.0 / 1.5), (-0.5, 1.33), (-0.2, 1.5), (-0.05, 1.9)]
        {
            let element = JonesDiagonal::dielectric_reflection(cos, &fresnel_dielectric(cos, eta));
            let amplitudes = fresnel_dielectric_amplitudes(cos, eta);
            let expected = JonesDiagonal::new(amplitudes.r_s, amplitudes.r_p);
            for (got, want) in [
                (element.a, expected.a),
                (element.b, expected.b),
                (element.w_re, expected.w_re),
                (element.w_im, expected.w_im),
            ] {
                assert!((got - want).abs() < 2e-5, "cos {cos}, eta {eta}: {element:?} vs {expected:?}");
            }
        }
    }

    /// Transmission: a = 1 − R; per polarisation, flux is conserved (R + T = 1 for s and p).
    #[test]
    fn dielectric_transmission_conserves_flux_per_polarisation() {
        for (cos, eta) in [(0.9f32, 1.5f32), (0.2, 1.5), (-0.9, 1.5), (0.01, 1.9)] {
            let fresnel = fresnel_dielectric(cos, eta);
            let reflect = JonesDiagonal::dielectric_reflection(cos, &fresnel);
            let transmit = JonesDiagonal::dielectric_transmission(&fresnel);
            assert!((reflect.a + transmit.a - 1.0).abs() < 1e-6);
            assert!((reflect.b + transmit.b).abs() < 1e-6);
            let amplitudes = fresnel_dielectric_amplitudes(cos, eta);
            let flux = amplitudes.eta_it * amplitudes.cos_theta_t.abs() / cos.abs();
            let expected = flux * (amplitudes.t_s * amplitudes.t_p.conj()).re;
            assert!((transmit.w_re - expected).abs() < 1e-4, "{} vs {expected}", transmit.w_re);
        }
    }

    /// Past the critical angle both amplitudes have modulus 1 (a = 1, b = 0) and only the
    /// phase difference remains; it vanishes at the critical angle and at grazing incidence.
    #[test]
    fn total_internal_reflection_is_a_pure_retarder() {
        let eta = 1.0 / 1.5;
        let critical = (1.0f32 - eta * eta).sqrt();
        for cos in [0.05f32, 0.3, 0.6, critical * 0.999] {
            let m = JonesDiagonal::dielectric_reflection(cos, &fresnel_dielectric(cos, eta));
            assert!((m.a - 1.0).abs() < 1e-6 && m.b.abs() < 1e-6, "{m:?}");
            assert!((m.w_re.hypot(m.w_im) - 1.0).abs() < 1e-5);
        }
        let near_critical = JonesDiagonal::dielectric_reflection(
            critical * 0.99999,
            &fresnel_dielectric(critical * 0.99999, eta),
        );
        assert!(near_critical.w_im.abs() < 0.02, "{near_critical:?}");
    }
}
