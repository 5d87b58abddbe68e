//! A lossless stack at every wavelength lane of a vertex at once: the same transfer-matrix
//! method as [`super::thin_film_amplitudes`]'s real path (module documentation there), written
//! structure-of-arrays over [`LANES`] lanes, each step a loop over the lanes with no branch, so
//! that it compiles to vector instructions (eight f64 lanes in one AVX-512 register where the
//! CPU has it, two AVX2 halves otherwise; `.cargo/config.toml` builds for the host). Issue 41's
//! speed target (a coated interface at most 2× a bare one per lane) is what it is for.
//!
//! The lanes share the angle of incidence (every lane of a vertex arrives along one direction);
//! each has its own wavelength, ambient, substrate and layer indices (a dispersive glass or
//! layer). A lane the real method cannot take (a layer at or past its critical angle, the
//! substrate at its, a phase beyond the exact reduction of the shared sin/cos, a vanishing
//! denominator) is flagged in [`StackLanes::valid`]; the caller evaluates it with
//! [`super::thin_film_amplitudes`], which takes every case. Layers of zero thickness are skipped,
//! as both scalar paths skip them.
//!
//! What it returns is what the renderer needs: r_s and r_p, and the transmitted **flux
//! amplitudes** τ = √T·e^{i arg t} for s and p (the amplitude whose modulus squared is the
//! power transmittance, with the phase of t: what a coated dielectric's transmission element
//! carries). With the module's notation, t = 2y₀·conj(D)/|D|² and T = 4y₀·Re(y_sub)/|D|² for
//! D = y₀B + C, so τ = t·√(T/|t|²) = 2√(y₀·Re(y_sub))·conj(D)/|D|²: one square root shared by
//! s and p (y₀,p·Re(y_sub,p) = y₀,s·Re(y_sub,s)/(n₀·n_sub)²) and no division but 1/|D|². With air
//! on both sides (a free-standing film) τ = t.

use crate::spectrum::N_LAMBDA;

use super::sin_cos_reduced;

/// Lanes evaluated together: the renderer's wavelength lanes.
pub const LANES: usize = N_LAMBDA;

/// One f64 per lane.
pub type Lanes = [f64; LANES];

/// One layer of a lossless stack at every lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerLanes {
    /// The layer's real index n at each lane's wavelength.
    pub index: Lanes,
    /// Physical thickness in nm, ≥ 0 (the same at every lane).
    pub thickness_nm: f64,
}

/// The amplitudes of a stack at every lane, as real and imaginary parts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StackLanes {
    /// Re and Im of r_s (Hecht's sign, as [`super::ThinFilmAmplitudes::r_s`]).
    pub r_s: [Lanes; 2],
    /// Re and Im of r_p.
    pub r_p: [Lanes; 2],
    /// Re and Im of the s flux amplitude √T_s·e^{i arg t_s} (module documentation).
    pub flux_s: [Lanes; 2],
    /// Re and Im of the p flux amplitude √T_p·e^{i arg t_p}.
    pub flux_p: [Lanes; 2],
    /// False where the real method does not hold and the values above are meaningless.
    pub valid: [bool; LANES],
}

/// A real 2 × 2 product [[a, i·b], [i·c, d]] per lane (module documentation of `thin_film`).
#[derive(Clone, Copy)]
struct Characteristic {
    a: Lanes,
    b: Lanes,
    c: Lanes,
    d: Lanes,
}

impl Characteristic {
    const IDENTITY: Self = Self { a: [1.0; LANES], b: [0.0; LANES], c: [0.0; LANES], d: [1.0; LANES] };
}

/// The stack of `layers` (in the order the light crosses them) between an ambient of index
/// `n_ambient` and a lossless substrate of index `n_substrate` (real, > 0), for light of
/// wavenumber `wavenumber_per_nm` = 2π/λ (per nm, λ the vacuum wavelength) arriving at
/// `cos_theta_i` in [0, 1] (in the ambient, the same at every lane).
#[inline]
pub fn lossless_stack_lanes(
    n_ambient: &Lanes,
    layers: impl IntoIterator<Item = LayerLanes>,
    n_substrate: &Lanes,
    wavenumber_per_nm: &Lanes,
    cos_theta_i: f64,
) -> StackLanes {
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    let sin_i_sqr = (1.0 - cos_i * cos_i).max(0.0);
    let mut valid = [true; LANES];
    // n₀² sin² θ₀ per lane, conserved across every interface.
    let invariant_sqr: Lanes = std::array::from_fn(|l| n_ambient[l] * n_ambient[l] * sin_i_sqr);
    let (mut s, mut p) = (Characteristic::IDENTITY, Characteristic::IDENTITY);
    for layer in layers.into_iter().filter(|layer| layer.thickness_nm > 0.0) {
        let thickness_nm = layer.thickness_nm;
        // Per lane: the layer's matrix [[cos, i·b], [i·c, cos]] for s and p (see `step`).
        let mut cos = [0.0; LANES];
        let (mut b_s, mut c_s, mut b_p, mut c_p) = ([0.0; LANES], [0.0; LANES], [0.0; LANES], [0.0; LANES]);
        let mut propagating = [false; LANES];
        let mut root = [0.0; LANES];
        for l in 0..LANES {
            let n_cos_sqr = layer.index[l] * layer.index[l] - invariant_sqr[l];
            propagating[l] = n_cos_sqr > 0.0;
            root[l] = n_cos_sqr.abs().sqrt();
        }
        if propagating.iter().any(|&p| p) {
            // n cos θ = root real: β = k·d·root, the matrix [[cos β, i·sin β/y], [i·y·sin β, cos β]]
            // with y_s = root, y_p = root/n².
            for l in 0..LANES {
                let (n_cos, index_sqr) = (root[l], layer.index[l] * layer.index[l]);
                let (sin, cos_beta, exact) = sin_cos_reduced(wavenumber_per_nm[l] * thickness_nm * n_cos);
                valid[l] &= exact || !propagating[l];
                // Clamped so that a lane of the other kind stays finite (it is overwritten).
                let y_s = n_cos.max(f64::MIN_POSITIVE);
                let sin_over_y_s = sin / y_s;
                cos[l] = cos_beta;
                (b_s[l], c_s[l]) = (sin_over_y_s, sin * y_s);
                // y_p = y_s / n².
                (b_p[l], c_p[l]) = (sin_over_y_s * index_sqr, sin * y_s / index_sqr);
            }
        }
        if propagating.iter().any(|&p| !p) {
            // Past (or at) the layer's critical angle: n cos θ = −i·q with q = root, β = −i·t,
            // t = k·d·q; cos β = cosh t, sin β = −i·sinh t, so that i·sin β/y_s = i·sinh t/q and
            // i·y_s·sin β = −i·q·sinh t (y_p = −i·q/n² likewise): the same real form. sinh t/q
            // = k·d·(sinh t/t), finite at q = 0 (exactly at the critical angle: β/y = k·d).
            for l in 0..LANES {
                let (q, index_sqr) = (root[l], layer.index[l] * layer.index[l]);
                let kd = wavenumber_per_nm[l] * thickness_nm;
                let (cosh, sinh, sinh_over_t, exact) = cosh_sinh(kd * q);
                if !propagating[l] {
                    valid[l] &= exact;
                    cos[l] = cosh;
                    (b_s[l], c_s[l]) = (kd * sinh_over_t, -q * sinh);
                    (b_p[l], c_p[l]) = (kd * sinh_over_t * index_sqr, -q / index_sqr * sinh);
                }
            }
        }
        step(&mut s, &cos, &b_s, &c_s);
        step(&mut p, &cos, &b_p, &c_p);
    }
    let mut out = StackLanes {
        r_s: [[0.0; LANES]; 2],
        r_p: [[0.0; LANES]; 2],
        flux_s: [[0.0; LANES]; 2],
        flux_p: [[0.0; LANES]; 2],
        valid,
    };
    for l in 0..LANES {
        let (n0, ns) = (n_ambient[l], n_substrate[l]);
        // The substrate's n cos θ = u + i·v: real (u > 0) where the wave propagates, −i·q
        // (evanescent, total internal reflection behind the stack) where it does not; exactly
        // at the critical angle the lane is left to the complex path.
        let x = ns * ns - invariant_sqr[l];
        let root = x.abs().sqrt();
        let (u, v) = if x > 0.0 { (root, 0.0) } else { (0.0, -root) };
        out.valid[l] &= x != 0.0;
        let (inverse_n0, inverse_ns) = (1.0 / n0, 1.0 / ns);
        let inverse_index_sqr = inverse_ns * inverse_ns;
        let y0_s = n0 * cos_i;
        let y0_p = cos_i * inverse_n0;
        // 2√(y₀·Re(y_sub)) for s, and for p the same over n₀·n_sub.
        let flux_factor_s = 2.0 * (y0_s * u).sqrt();
        let flux_factor_p = flux_factor_s * inverse_n0 * inverse_ns;
        let polarisations = [
            (&s, y0_s, u, v, flux_factor_s, 0),
            (&p, y0_p, u * inverse_index_sqr, v * inverse_index_sqr, flux_factor_p, 1),
        ];
        for (m, y0, u, v, flux_factor, which) in polarisations {
            let (a, b, c, d) = (m.a[l], m.b[l], m.c[l], m.d[l]);
            // y₀B = y₀(a − b·v) + i·y₀·b·u, C = d·u + i(c + d·v), D = y₀B + C.
            let (front_re, front_im) = (y0 * (a - b * v), y0 * b * u);
            let (back_re, back_im) = (d * u, c + d * v);
            let (den_re, den_im) = (front_re + back_re, front_im + back_im);
            let norm_sqr = den_re * den_re + den_im * den_im;
            out.valid[l] &= norm_sqr > 0.0 && norm_sqr.is_finite();
            let inverse = 1.0 / norm_sqr.max(f64::MIN_POSITIVE);
            // conj(D)/|D|².
            let (conj_re, conj_im) = (den_re * inverse, -den_im * inverse);
            let (num_re, num_im) = (front_re - back_re, front_im - back_im);
            let r = [num_re * conj_re - num_im * conj_im, num_re * conj_im + num_im * conj_re];
            let flux = [flux_factor * conj_re, flux_factor * conj_im];
            let (r_out, flux_out) =
                if which == 0 { (&mut out.r_s, &mut out.flux_s) } else { (&mut out.r_p, &mut out.flux_p) };
            r_out[0][l] = r[0];
            r_out[1][l] = r[1];
            flux_out[0][l] = flux[0];
            flux_out[1][l] = flux[1];
        }
    }
    out
}

/// `product` times a layer's [[cos, i·b], [i·c, cos]] at every lane (real a, b, c, d: products
/// of such matrices keep the form, `thin_film`'s real path).
#[inline(always)]
fn step(product: &mut Characteristic, cos: &Lanes, b: &Lanes, c: &Lanes) {
    for l in 0..LANES {
        let (a0, b0, c0, d0) = (product.a[l], product.b[l], product.c[l], product.d[l]);
        product.a[l] = a0 * cos[l] - b0 * c[l];
        product.b[l] = a0 * b[l] + b0 * cos[l];
        product.c[l] = c0 * cos[l] + d0 * c[l];
        product.d[l] = d0 * cos[l] - c0 * b[l];
    }
}

/// cosh t, sinh t and sinh t / t for t ≥ 0, and whether they are exact (within a few units in
/// the last place; false past t = 700, where cosh t nears f64's range, and for NaN). e^t by
/// t = m·ln 2 + r, |r| ≤ ln 2/2 (Cody and Waite's two-part ln 2), the Taylor series of e^r to
/// r¹³ (the next term < 1e-17 of it) and 2^m built in the exponent bits; below t = 1/2 sinh by
/// its own series to t¹³ (the next term < 1e-18 of it; e^t − e^{−t} would cancel there).
#[inline(always)]
fn cosh_sinh(t: f64) -> (f64, f64, f64, bool) {
    const LN_2_HIGH: f64 = 0.693_147_180_369_123_8;
    const LN_2_LOW: f64 = 1.908_214_929_270_587_7e-10;
    let exact = t <= 700.0;
    let t_in_range = if exact { t } else { 0.0 };
    let m = (t_in_range * std::f64::consts::LOG2_E).round_ties_even();
    let r = (t_in_range - m * LN_2_HIGH) - m * LN_2_LOW;
    // e^r = 1 + r(1 + r/2(1 + r/3(… (1 + r/13)))), Horner with the reciprocals folded.
    const INVERSE: [f64; 13] = [
        1.0,
        1.0 / 2.0,
        1.0 / 3.0,
        1.0 / 4.0,
        1.0 / 5.0,
        1.0 / 6.0,
        1.0 / 7.0,
        1.0 / 8.0,
        1.0 / 9.0,
        1.0 / 10.0,
        1.0 / 11.0,
        1.0 / 12.0,
        1.0 / 13.0,
    ];
    let e_r = INVERSE.iter().rev().fold(1.0, |acc, inverse| 1.0 + r * inverse * acc);
    // 2^m for 0 ≤ m ≤ 1010: m + 1023 in the low bits of 2⁵² + m + 1023, shifted into the
    // exponent (a bit cast and a shift: no float-to-integer conversion, which would not vectorise).
    let two_to_m = f64::from_bits(((m + 1023.0 + 4_503_599_627_370_496.0).to_bits()) << 52);
    let e = e_r * two_to_m;
    let inverse = 1.0 / e;
    let cosh = 0.5 * (e + inverse);
    let z = t_in_range * t_in_range;
    // sinh t / t = 1 + z/3!(1 + z/(4·5)(1 + z/(6·7)(…))), z = t².
    let series_over_t = 1.0
        + z * (1.0 / 6.0)
            * (1.0
                + z * (1.0 / 20.0)
                    * (1.0
                        + z * (1.0 / 42.0)
                            * (1.0
                                + z * (1.0 / 72.0) * (1.0 + z * (1.0 / 110.0) * (1.0 + z * (1.0 / 156.0))))));
    let small = t_in_range < 0.5;
    let sinh = if small { t_in_range * series_over_t } else { 0.5 * (e - inverse) };
    let sinh_over_t = if small { series_over_t } else { sinh / t_in_range.max(0.5) };
    (cosh, sinh, sinh_over_t, exact)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::{thin_film_amplitudes, Layer};
    use num_complex::Complex64;

    /// Every lane against the general (complex) evaluation of the same stack, for random
    /// lossless stacks of 0–6 layers on substrates 1.0–1.9 from ambients 1.0 and 1.5 (also the
    /// glass side: layers past their critical angle and total internal reflection behind the
    /// stack included), each lane at its own wavelength and with its own (dispersive) indices:
    /// the same products in another order (cosh and sinh from another exponential), so rounding
    /// only (1e-12 leaves room for the growth of the matrices' entries over six layers, as for
    /// the scalar real path; the worst measured is printed). No lane is refused.
    #[test]
    fn every_lane_is_the_general_stack() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut compared, mut evanescent, mut past_critical) = (0, 0, 0);
        let mut worst = 0.0_f64;
        for _ in 0..300 {
            let count = (uniform() * 7.0) as usize;
            let layers: Vec<LayerLanes> = (0..count)
                .map(|_| {
                    let base = 1.2 + 1.3 * uniform();
                    LayerLanes {
                        index: std::array::from_fn(|_| base + 0.02 * uniform()),
                        thickness_nm: if uniform() < 0.1 { 0.0 } else { 400.0 * uniform() },
                    }
                })
                .collect();
            let from_glass = uniform() < 0.5;
            let glass: Lanes = std::array::from_fn(|_| 1.0 + 0.9 * uniform());
            let (n_ambient, n_substrate) =
                if from_glass { (glass, [1.0; LANES]) } else { ([1.0; LANES], glass) };
            let lambda: Lanes = std::array::from_fn(|_| 360.0 + 470.0 * uniform());
            let wavenumber = lambda.map(|nm| std::f64::consts::TAU / nm);
            let cos_i = uniform();
            let lanes =
                lossless_stack_lanes(&n_ambient, layers.iter().copied(), &n_substrate, &wavenumber, cos_i);
            for l in 0..LANES {
                let scalar_layers: Vec<Layer> = layers
                    .iter()
                    .map(|layer| Layer::dielectric(layer.index[l], layer.thickness_nm))
                    .collect();
                let invariant = n_ambient[l] * n_ambient[l] * (1.0 - cos_i * cos_i);
                assert!(lanes.valid[l], "lane {l} refused: {scalar_layers:?}, cos {cos_i}");
                past_critical +=
                    usize::from(scalar_layers.iter().any(|layer| {
                        layer.thickness_nm > 0.0 && layer.index.re * layer.index.re < invariant
                    }));
                let general = thin_film_amplitudes(
                    n_ambient[l],
                    &scalar_layers,
                    Complex64::new(n_substrate[l], 0.0),
                    lambda[l],
                    cos_i,
                );
                let flux = |t: Complex64, transmittance: f64| {
                    if t.norm_sqr() > 0.0 {
                        t * (transmittance / t.norm_sqr()).sqrt()
                    } else {
                        Complex64::new(0.0, 0.0)
                    }
                };
                let lane = |parts: &[Lanes; 2]| Complex64::new(parts[0][l], parts[1][l]);
                let context =
                    format!("lane {l}: {scalar_layers:?}, {n_ambient:?} → {n_substrate:?}, cos {cos_i}");
                for (a, b) in [
                    (lane(&lanes.r_s), general.r_s),
                    (lane(&lanes.r_p), general.r_p),
                    (lane(&lanes.flux_s), flux(general.t_s, general.transmittance_s)),
                    (lane(&lanes.flux_p), flux(general.t_p, general.transmittance_p)),
                ] {
                    worst = worst.max((a - b).norm());
                    assert!((a - b).norm() < 1e-12, "{context}: {a} vs {b}");
                }
                compared += 1;
                evanescent += usize::from(invariant > n_substrate[l] * n_substrate[l]);
            }
        }
        eprintln!("worst difference {worst:e} over {compared} lanes ({past_critical} past a critical angle)");
        assert!(
            compared > 2000 && evanescent > 100 && past_critical > 100,
            "{compared}, {evanescent}, {past_critical}"
        );
    }

    /// cosh, sinh and sinh t/t against the library's within 4e-16 relative (a few ulps: the
    /// reduction and the series add a few roundings), from 0 (exactly 1, 0, 1) to 700.
    #[test]
    fn hyperbolic_functions_are_the_librarys() {
        assert_eq!(cosh_sinh(0.0), (1.0, 0.0, 1.0, true));
        let mut worst = 0.0_f64;
        for i in 1..200_000 {
            let t = (i as f64 * 1.3e-5).powi(3) * 0.3;
            let (cosh, sinh, sinh_over_t, exact) = cosh_sinh(t);
            assert!(exact == (t <= 700.0), "{t}");
            if !exact {
                continue;
            }
            let relative = |a: f64, b: f64| ((a - b) / b).abs();
            worst = worst
                .max(relative(cosh, t.cosh()))
                .max(relative(sinh, t.sinh()))
                .max(relative(sinh_over_t, t.sinh() / t));
        }
        eprintln!("worst relative difference {worst:e}");
        assert!(worst < 4e-16 * 4.0, "{worst:e}");
        assert!(!cosh_sinh(800.0).3 && !cosh_sinh(f64::NAN).3);
    }
}
