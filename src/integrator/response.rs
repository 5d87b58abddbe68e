//! [`Response`]: what a camera path carries forward from the camera, the linear map from the
//! light arriving at its current vertex to what the camera records. Whitted's recursion applies
//! each interaction's Mueller matrix on the way back (`S_camera = R₁·M₁·R₂·M₂·…·S_light`); a
//! path tracer walks the same chain forward and multiplies the matrices from the left end:
//! `P ← P·R·M` at each vertex, then `S_camera = P·S_light` when it reaches light. A polarised
//! path keeps the whole 4×4 product per wavelength lane ([`StokesResponse`]); an unpolarised one
//! keeps its first entry alone (a [`SampledSpectrum`]), as [`super::Beam`] does for beams.
//!
//! A diffuse vertex depolarises: the light it sends on is unpolarised, of radiance read from the
//! S0 of the light it receives, so `P ← P·w·e₀e₀ᵀ` keeps the first column of `P` (times the
//! vertex's weight `w`) and zeroes the rest.

use super::Beam;
use crate::polarization::{Mueller, Rotation, Stokes};
use crate::spectrum::SampledSpectrum;

/// A beam type a path tracer can carry: its [`Response`] says how the camera reads light.
pub trait PathBeam: Beam {
    /// The camera's response carried along a path, for this kind of beam.
    type Response: Response<Self>;
}

impl PathBeam for SampledSpectrum {
    type Response = SampledSpectrum;
}

impl PathBeam for Stokes {
    type Response = StokesResponse;
}

/// The linear map from light arriving at a path's current vertex (in the path's current Stokes
/// frame) to what the camera records, at every wavelength lane.
pub trait Response<B>: Copy {
    /// The identity at the lanes where `mask` is 1 (0 elsewhere): the camera's own response.
    fn identity(mask: SampledSpectrum) -> Self;
    /// `P·R`: the light is now described in a frame turned by `rotation` (which takes Stokes
    /// vectors from the new frame to the current one, as [`Stokes::rotated`] applies it).
    fn rotated(self, rotation: Rotation) -> Self;
    /// `P·M`: the light reaches the current vertex through the element `mueller`.
    fn through(self, mueller: &Mueller) -> Self;
    /// `P·w`: a non-polarising factor per lane.
    fn scaled(self, weight: SampledSpectrum) -> Self;
    /// `P·w·e₀e₀ᵀ`: a depolarising vertex of weight `weight` (the first column kept).
    fn depolarized(self, weight: SampledSpectrum) -> Self;
    /// Only lane `lane` kept.
    fn only_lane(self, lane: usize) -> Self;
    /// The camera's radiance response to unpolarised light, per lane (`P₀₀`): what Russian
    /// roulette and branch choices weigh. Bounds every other entry of a physical response.
    fn strength(&self) -> SampledSpectrum;
    /// What the camera records of unpolarised light of radiance `radiance` arriving at the
    /// current vertex: `P·(L, 0, 0, 0)`.
    fn unpolarized(&self, radiance: SampledSpectrum) -> B;
}

impl Response<SampledSpectrum> for SampledSpectrum {
    #[inline]
    fn identity(mask: SampledSpectrum) -> Self {
        mask
    }
    #[inline]
    fn rotated(self, _rotation: Rotation) -> Self {
        self
    }
    #[inline]
    fn through(self, mueller: &Mueller) -> Self {
        self * mueller.a
    }
    #[inline]
    fn scaled(self, weight: SampledSpectrum) -> Self {
        self * weight
    }
    #[inline]
    fn depolarized(self, weight: SampledSpectrum) -> Self {
        self * weight
    }
    #[inline]
    fn only_lane(self, lane: usize) -> Self {
        SampledSpectrum::only_lane(self, lane)
    }
    #[inline]
    fn strength(&self) -> SampledSpectrum {
        *self
    }
    #[inline]
    fn unpolarized(&self, radiance: SampledSpectrum) -> SampledSpectrum {
        *self * radiance
    }
}

/// A 4×4 Mueller response per lane: `rows[i][j]` is entry (i, j) at every lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StokesResponse {
    rows: [[SampledSpectrum; 4]; 4],
    /// True once a diffuse vertex zeroed columns 1–3: rotations and diattenuation then leave
    /// them zero, and only column 0 needs updating.
    depolarized: bool,
}

impl StokesResponse {
    /// Entry (`row`, `column`) at every lane (for tests).
    pub fn entry(&self, row: usize, column: usize) -> SampledSpectrum {
        self.rows[row][column]
    }
}

impl Response<Stokes> for StokesResponse {
    #[inline]
    fn identity(mask: SampledSpectrum) -> Self {
        let zero = SampledSpectrum::zero();
        let mut rows = [[zero; 4]; 4];
        for (i, row) in rows.iter_mut().enumerate() {
            row[i] = mask;
        }
        Self { rows, depolarized: false }
    }

    #[inline]
    fn rotated(self, rotation: Rotation) -> Self {
        if self.depolarized {
            return self;
        }
        let (c, s) = (rotation.cos_2theta, rotation.sin_2theta);
        Self {
            rows: self.rows.map(|[r0, r1, r2, r3]| [r0, r1 * c - r2 * s, r1 * s + r2 * c, r3]),
            depolarized: false,
        }
    }

    #[inline]
    fn through(self, m: &Mueller) -> Self {
        if self.depolarized {
            // Columns 1–3 are zero: r·M keeps r₀·(a, b, 0, 0), and column 1 must stay zero for
            // the shortcut to hold, so the whole row is recomputed from r₀.
            return Self {
                rows: self.rows.map(|[r0, _, _, _]| {
                    let zero = SampledSpectrum::zero();
                    [r0 * m.a, r0 * m.b, zero, zero]
                }),
                depolarized: false,
            };
        }
        Self {
            rows: self.rows.map(|[r0, r1, r2, r3]| {
                [
                    r0 * m.a + r1 * m.b,
                    r0 * m.b + r1 * m.a,
                    r2 * m.w_re - r3 * m.w_im,
                    r2 * m.w_im + r3 * m.w_re,
                ]
            }),
            depolarized: false,
        }
    }

    #[inline]
    fn scaled(self, weight: SampledSpectrum) -> Self {
        Self { rows: self.rows.map(|row| row.map(|entry| entry * weight)), ..self }
    }

    #[inline]
    fn depolarized(self, weight: SampledSpectrum) -> Self {
        let zero = SampledSpectrum::zero();
        Self { rows: self.rows.map(|[r0, _, _, _]| [r0 * weight, zero, zero, zero]), depolarized: true }
    }

    #[inline]
    fn only_lane(self, lane: usize) -> Self {
        Self { rows: self.rows.map(|row| row.map(|entry| entry.only_lane(lane))), ..self }
    }

    #[inline]
    fn strength(&self) -> SampledSpectrum {
        self.rows[0][0]
    }

    #[inline]
    fn unpolarized(&self, radiance: SampledSpectrum) -> Stokes {
        Stokes { s: [0, 1, 2, 3].map(|i| self.rows[i][0] * radiance) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polarization::mueller::JonesDiagonal;

    fn stokes(values: [f32; 4]) -> Stokes {
        Stokes { s: values.map(SampledSpectrum::splat) }
    }

    /// The forward product P·R·M applied to a light vector equals the backward chain
    /// R·M·S that Whitted's recursion applies, for two rotations and two elements with phase.
    #[test]
    fn forward_product_equals_the_backward_chain() {
        let m1 = Mueller::from_jones_diagonal(
            num_complex::Complex32::new(0.3, 0.4),
            num_complex::Complex32::new(-0.7, 0.1),
        );
        let m2 = Mueller::splat(JonesDiagonal::linear_retarder(0.9));
        let r1 = Rotation::by_angle(0.4);
        let r2 = Rotation::by_angle(-1.1);
        let light = stokes([1.0, 0.3, -0.2, 0.5]);
        let backward = m2.apply(&light).rotated(r2);
        let backward = m1.apply(&backward).rotated(r1);
        let forward = StokesResponse::identity(SampledSpectrum::splat(1.0))
            .rotated(r1)
            .through(&m1)
            .rotated(r2)
            .through(&m2);
        // P·S by columns: column j of P times S_j.
        let applied: [f32; 4] =
            std::array::from_fn(|i| (0..4).map(|j| forward.entry(i, j)[0] * light.s[j][0]).sum::<f32>());
        for i in 0..4 {
            assert!(
                (applied[i] - backward.s[i][0]).abs() < 1e-6,
                "S{i}: {} vs {}",
                applied[i],
                backward.s[i][0]
            );
        }
    }

    /// After a depolarising vertex, the response to any light is its S0 times the first column.
    #[test]
    fn depolarizing_keeps_the_first_column() {
        let m = Mueller::splat(JonesDiagonal::linear_polarizer(1.0));
        let p = StokesResponse::identity(SampledSpectrum::splat(1.0))
            .through(&m)
            .depolarized(SampledSpectrum::splat(0.5))
            .through(&m);
        // A polariser, then a diffuse receiver of weight ½ read through a polariser: the camera
        // sees ½·½·S0 of unpolarised light, polarised along x (S1 = S0).
        let seen = p.unpolarized(SampledSpectrum::splat(1.0));
        assert!((seen.s[0][0] - 0.125).abs() < 1e-7 && (seen.s[1][0] - 0.125).abs() < 1e-7, "{seen:?}");
        assert_eq!(p.strength()[0], 0.125);
    }
}
