//! A lossless stack at every wavelength lane of a vertex at once: the same transfer-matrix
//! method as [`super::thin_film_amplitudes`]'s real path (module documentation there), each
//! quantity one [`wide::f64x8`] over the [`LANES`] lanes (two AVX2 halves, with fused multiply-adds:
//! `.cargo/config.toml` builds for the host, without AVX-512, which measured slower). Issue 41's speed target (a coated interface at most 2× a bare one per lane) is what
//! it is for.
//!
//! The lanes share the angle of incidence (every lane of a vertex arrives along one direction);
//! each has its own wavelength, ambient, substrate and layer indices (a dispersive glass or
//! layer). A lane the real method cannot take (a layer or the substrate exactly at its critical
//! angle, a phase beyond the range of the sin/cos kernel or of cosh, a product out of f64's
//! comfortable range) is flagged in [`StackLanes::refused`]; the caller evaluates it with
//! [`super::thin_film_amplitudes`], which takes every case. Layers of zero thickness are skipped,
//! as both scalar paths skip them.
//!
//! # Scaled matrices: no division per layer
//! A propagating layer's matrix [[cos β, i·sin β/y], [i·y·sin β, cos β]] needs 1/y; a layer past
//! its critical angle (n cos θ = −i·q, β = −i·t) is [[cosh t, i·sinh t/q], [−i·q·sinh t, cosh t]]
//! and needs sinh t/q. Each layer's matrix is taken **multiplied by a real scale g** instead:
//! with x = (n cos θ)² = n² − n₀² sin² θ₀ and root = √|x|, g_s = root gives
//! [[root·C, i·S], [i·x·S, root·C]] for s and g_p = root·n² gives [[n²·root·C, i·n⁴·S],
//! [i·x·S, n²·root·C]] for p, (C, S) = (cos β, sin β) or (cosh t, sinh t): one form for both
//! kinds of layer, and no division. The product of the scaled matrices is G times the true one
//! (G the product of the scales): r = (y₀B − C)/(y₀B + C) does not see G, and the flux amplitude
//! below takes it as a factor (conj(D)/|D|² = G·conj(D′)/|D′|² for D′ = G·D). A layer exactly at
//! its critical angle (root = 0) makes D′ = 0, and the lane is refused (|D′|² is held within
//! [1e-150, 1e150], so that the few orders of magnitude G spans cannot lose precision).
//!
//! # Amplitudes
//! What it returns is what the renderer needs: r_s and r_p, and the transmitted **flux
//! amplitudes** τ = √T·e^{i arg t} for s and p (the amplitude whose modulus squared is the
//! power transmittance, with the phase of t: what a coated dielectric's transmission element
//! carries). With the module's notation, t = 2y₀·conj(D)/|D|² and T = 4y₀·Re(y_sub)/|D|² for
//! D = y₀B + C, so τ = t·√(T/|t|²) = 2√(y₀·Re(y_sub))·conj(D)/|D|²: one square root shared by
//! s and p (y₀,p·Re(y_sub,p) = y₀,s·Re(y_sub,s)/(n₀·n_sub)²). The p equations are multiplied
//! through by n₀·n_sub² (no division by the indices), and 1/|D_s|² and 1/|D_p|² come from one
//! division. With air on both sides (a free-standing film) τ = t.
//!
//! # Cost
//! Per layer and vertex: one square root, one sin/cos (`sin_cos_lanes`, an Estrin evaluation
//! on the known range), and where a lane is past the layer's critical angle one e^t (`wide`'s
//! `exp`, `sinh`); eight multiply-adds per polarisation for the product. Per vertex: two square
//! roots and one division (the substrate), the division 2π/λ of the caller, and one division
//! for both 1/|D|². Measured in `benches/optics.rs` (`lanes` group) and
//! `validation/bench/RESULTS.md`.

use wide::f64x8;

use crate::spectrum::N_LAMBDA;

/// Lanes evaluated together: the renderer's wavelength lanes.
pub const LANES: usize = N_LAMBDA;

// One `f64x8` holds the lanes.
const _: () = assert!(LANES == 8);

/// One f64 per lane.
pub type Lanes = [f64; LANES];

/// Phases (radians) up to which the vector sin and cos are taken as exact: `wide`'s reduction
/// (Cody and Waite with a three-part π/2) and its polynomials agree with the library within
/// 1e-15 well beyond this (tested up to 1.2·10⁵; 1e5 rad is a 100 µm layer of n ≈ 57 at
/// 360 nm). A lane beyond it is refused.
const SIN_COS_LIMIT: f64 = 1e5;

/// Past-critical phases (t = k·d·q) up to which cosh t and sinh t are finite and exact (cosh
/// overflows f64 past t ≈ 710); a lane beyond it is refused.
const HYPERBOLIC_LIMIT: f64 = 700.0;

/// Below this |D|² (of the scaled product, module documentation), and above its inverse, a lane
/// is refused: the scaled entries could have lost terms to underflow (|D| ≥ 1e-75 leaves more
/// than 200 orders of magnitude above f64's smallest normal), and the product of the s and p
/// values, whose inverse is taken once for both, stays within f64's range.
const SMALLEST_NORM_SQR: f64 = 1e-150;

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
    /// Bit l set where lane l is refused: the real method does not hold there and the values
    /// above are meaningless.
    pub refused: u32,
}

/// A real 2 × 2 product [[a, i·b], [i·c, d]] per lane (module documentation of `thin_film`),
/// scaled (module documentation).
#[derive(Clone, Copy)]
struct Characteristic {
    a: f64x8,
    b: f64x8,
    c: f64x8,
    d: f64x8,
}

impl Characteristic {
    const IDENTITY: Self = Self { a: f64x8::ONE, b: f64x8::ZERO, c: f64x8::ZERO, d: f64x8::ONE };

    /// This product times a layer's [[diagonal, i·b], [i·c, diagonal]] (real a, b, c, d:
    /// products of such matrices keep the form, `thin_film`'s real path), in fused
    /// multiply-adds where the CPU has them.
    #[inline(always)]
    fn then(&mut self, diagonal: f64x8, b: f64x8, c: f64x8) {
        let Self { a: a0, b: b0, c: c0, d: d0 } = *self;
        self.a = a0.mul_sub(diagonal, b0 * c);
        self.b = a0.mul_add(b, b0 * diagonal);
        self.c = c0.mul_add(diagonal, d0 * c);
        self.d = d0.mul_sub(diagonal, c0 * b);
    }
}

/// The stack of `layers` (in the order the light crosses them) between an ambient of index
/// `n_ambient` and a lossless substrate of index `n_substrate` (real, > 0), for light of
/// wavenumber `wavenumber_per_nm` = 2π/λ (per nm, λ the vacuum wavelength) arriving at
/// `cos_theta_i` in [0, 1] (in the ambient, the same at every lane).
#[inline]
pub fn lossless_stack_lanes(
    n_ambient: &Lanes,
    layers: &[LayerLanes],
    n_substrate: &Lanes,
    wavenumber_per_nm: &Lanes,
    cos_theta_i: f64,
) -> StackLanes {
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    let sin_i_sqr = (1.0 - cos_i * cos_i).max(0.0);
    // Bit l set: lane l refused.
    let mut refused = 0u32;
    let n0 = f64x8::from(*n_ambient);
    let wavenumber = f64x8::from(*wavenumber_per_nm);
    // n₀² sin² θ₀ per lane, conserved across every interface.
    let invariant_sqr = n0 * n0 * f64x8::splat(sin_i_sqr);
    // The ambient's and the substrate's part first (it does not depend on the layers, and so
    // overlaps with them). The substrate's n cos θ = u + i·v: real (u > 0) where the wave
    // propagates, −i·q (evanescent, total internal reflection behind the stack) where it does
    // not; exactly at the critical angle the lane is refused.
    let ns = f64x8::from(*n_substrate);
    let x = ns * ns - invariant_sqr;
    let root = x.abs().sqrt();
    let propagates = x.simd_gt(f64x8::ZERO);
    let (u, v) = (propagates.select(root, f64x8::ZERO), propagates.select(f64x8::ZERO, -root));
    refused |= x.simd_eq(f64x8::ZERO).to_bitmask();
    let cos_i = f64x8::splat(cos_i);
    let y0_s = n0 * cos_i;
    // 2√(y₀·Re(y_sub)) of s (for p see below; times the gains after the layers).
    let flux_root = f64x8::splat(2.0) * (y0_s * u).sqrt();
    let (mut s, mut p) = (Characteristic::IDENTITY, Characteristic::IDENTITY);
    // The products of the layers' scale factors g (module documentation), for s and p.
    let (mut gain_s, mut gain_p) = (f64x8::ONE, f64x8::ONE);
    // The largest phase of any layer (lanes beyond the sin/cos range are refused at the end).
    let mut largest_phase = f64x8::ZERO;
    let mut first = true;
    for layer in layers.iter().filter(|layer| layer.thickness_nm > 0.0) {
        let index = f64x8::from(layer.index);
        let index_sqr = index * index;
        // x = (n cos θ)², root = √|x|: n cos θ = root where the wave propagates (x > 0), −i·root
        // past the layer's critical angle.
        let x = index_sqr - invariant_sqr;
        let root = x.abs().sqrt();
        let phase = wavenumber * f64x8::splat(layer.thickness_nm) * root;
        largest_phase = largest_phase.max(phase);
        let (mut sin, mut cos) = sin_cos_lanes(phase);
        let evanescent = x.simd_le(f64x8::ZERO);
        if evanescent.any() {
            // β = −i·t, t = k·d·q: cos β = cosh t, sin β = −i·sinh t; the scaled matrix below is
            // then the same expression with (cosh t, sinh t) for (cos β, sin β). cosh t from an
            // e^t written as `sinh` writes it (the compiler shares the polynomial, not the
            // division: a kernel sharing both measured no faster).
            let e = phase.abs().exp();
            sin = evanescent.select(phase.sinh(), sin);
            cos = evanescent.select((e + f64x8::ONE / e) * f64x8::HALF, cos);
            refused |= (evanescent & phase.simd_gt(f64x8::splat(HYPERBOLIC_LIMIT))).to_bitmask();
        }
        // s: root·[[cos β, i sin β/y], [i y sin β, cos β]] = [[root·cos, i·sin], [i·x·sin,
        // root·cos]]; p (y_p = y_s/n²) scaled by root·n²: [[n²·root·cos, i·n⁴·sin], [i·x·sin,
        // n²·root·cos]].
        let diagonal = root * cos;
        let lower = x * sin;
        let (diagonal_p, upper_p) = (index_sqr * diagonal, index_sqr * index_sqr * sin);
        if first {
            // The product of one matrix is that matrix.
            s = Characteristic { a: diagonal, b: sin, c: lower, d: diagonal };
            p = Characteristic { a: diagonal_p, b: upper_p, c: lower, d: diagonal_p };
            first = false;
        } else {
            s.then(diagonal, sin, lower);
            p.then(diagonal_p, upper_p, lower);
        }
        gain_s *= root;
        gain_p *= root * index_sqr;
    }
    refused |= largest_phase.simd_gt(f64x8::splat(SIN_COS_LIMIT)).to_bitmask();
    // s: D = y₀B + C with y₀ = n₀ cos θ₀ and y_sub = u + i·v. p (y₀ = cos θ₀/n₀, y_sub/n_sub²)
    // multiplied through by n₀·n_sub², which r does not see and which leaves no division:
    // n₀n_sub²·D_p = cos θ₀·(n_sub²a + i·b·y_sub) + n₀·(i·n_sub²c + d·y_sub), and the p flux
    // amplitude 2√(y₀,p·Re(y_sub,p))·conj(D_p)/|D_p|² = 2√(y₀·u)·n_sub·conj(D̃)/|D̃|² for
    // D̃ = n₀n_sub²·D_p (y₀,p·Re(y_sub,p) = y₀,s·u/(n₀·n_sub)²).
    let ns_sqr = ns * ns;
    let p = Characteristic { a: p.a * ns_sqr, c: p.c * ns_sqr, ..p };
    let (front_s, back_s) = halves(&s, y0_s, f64x8::ONE, u, v);
    let (front_p, back_p) = halves(&p, cos_i, n0, u, v);
    let (den_s, den_p) = (add(front_s, back_s), add(front_p, back_p));
    let norm_s = den_s[0].mul_add(den_s[0], den_s[1] * den_s[1]);
    let norm_p = den_p[0].mul_add(den_p[0], den_p[1] * den_p[1]);
    // 1/|D_s|² and 1/|D̃|² from one division: both in [1e-150, 1e150] (else refused), so that
    // their product neither overflows nor underflows.
    let inverse = f64x8::ONE / (norm_s * norm_p);
    let (inverse_s, inverse_p) = (norm_p * inverse, norm_s * inverse);
    let (r_s, flux_s) = amplitudes(front_s, back_s, den_s, inverse_s, flux_root * gain_s);
    let (r_p, flux_p) = amplitudes(front_p, back_p, den_p, inverse_p, flux_root * gain_p * ns);
    let (low, high) = (f64x8::splat(SMALLEST_NORM_SQR), f64x8::splat(1.0 / SMALLEST_NORM_SQR));
    // NaN fails the comparisons; a flux that is not finite (a gain that overflowed) is refused.
    let accepted = norm_s.simd_ge(low)
        & norm_s.simd_le(high)
        & norm_p.simd_ge(low)
        & norm_p.simd_le(high)
        & flux_s[0].is_finite()
        & flux_s[1].is_finite()
        & flux_p[0].is_finite()
        & flux_p[1].is_finite();
    refused |= !accepted.to_bitmask() & ((1 << LANES) - 1);
    let parts = |[re, im]: [f64x8; 2]| [re.to_array(), im.to_array()];
    StackLanes { r_s: parts(r_s), r_p: parts(r_p), flux_s: parts(flux_s), flux_p: parts(flux_p), refused }
}

/// The two halves of D = front + back (each as Re, Im) of the scaled product `m`:
/// front = w_front·B = w_front·((a − b·v) + i·b·u), back = w_back·C = w_back·(d·u + i(c + d·v))
/// for a substrate admittance u + i·v (v = 0 or u = 0).
#[inline(always)]
fn halves(m: &Characteristic, w_front: f64x8, w_back: f64x8, u: f64x8, v: f64x8) -> ([f64x8; 2], [f64x8; 2]) {
    let front = [w_front * m.b.mul_neg_add(v, m.a), w_front * m.b * u];
    let back = [w_back * m.d * u, w_back * m.d.mul_add(v, m.c)];
    (front, back)
}

/// The complex sum of two (Re, Im) pairs.
#[inline(always)]
fn add(x: [f64x8; 2], y: [f64x8; 2]) -> [f64x8; 2] {
    [x[0] + y[0], x[1] + y[1]]
}

/// r = (front − back)·conj(D)/|D|² and the flux amplitude factor·conj(D)/|D|², each as
/// (Re, Im), given D = front + back and `inverse` = 1/|D|².
#[inline(always)]
fn amplitudes(
    front: [f64x8; 2],
    back: [f64x8; 2],
    den: [f64x8; 2],
    inverse: f64x8,
    flux_factor: f64x8,
) -> ([f64x8; 2], [f64x8; 2]) {
    let (conj_re, conj_im) = (den[0] * inverse, -den[1] * inverse);
    let (num_re, num_im) = (front[0] - back[0], front[1] - back[1]);
    let r = [num_re.mul_sub(conj_re, num_im * conj_im), num_re.mul_add(conj_im, num_im * conj_re)];
    (r, [flux_factor * conj_re, flux_factor * conj_im])
}

/// sin x and cos x at every lane for phases 0 ≤ x ≤ [`SIN_COS_LIMIT`] (radians), within a few
/// units in the last place (tested against the library's). x is reduced by the nearest
/// multiple q of π/2 (Cody and Waite's two-part π/2 of `thin_film::sin_cos_reduced`, exact for
/// q < 2²⁰), then the Taylor series of sin and cos on |r| ≤ π/4 to r¹⁷ and r¹⁸ (the next terms
/// are below 1e-19), each evaluated by Estrin's scheme (powers z, z², z⁴ of z = r² and pairs
/// of fused multiply-adds), and the quadrant chosen by selects on q mod 4 in floating point.
/// Why not `wide`'s `sin_cos`, which the lanes took first: it is a Horner evaluation for any
/// finite x (integer quadrant, range and NaN selects), and a vertex's stack is one chain of
/// dependent operations, so the shorter chain of Estrin's scheme on the known range is what
/// sets the speed (issue 41's 2×); no crate offers that kernel.
#[inline(always)]
fn sin_cos_lanes(x: f64x8) -> (f64x8, f64x8) {
    // π/2 = PI_2_HIGH + PI_2_LOW: the high part's 33 significant bits make q·PI_2_HIGH exact.
    const PI_2_HIGH: f64 = 1.570_796_326_734_125_6;
    const PI_2_LOW: f64 = 6.077_100_506_506_192e-11;
    // (−1)^(k+1)/(2k+1)! for k = 1…8 (sin) and (−1)^k/(2k)! for k = 2…9 (cos).
    const SIN: [f64; 8] = [
        -1.0 / 6.0,
        1.0 / 120.0,
        -1.0 / 5040.0,
        1.0 / 362_880.0,
        -1.0 / 39_916_800.0,
        1.0 / 6_227_020_800.0,
        -1.0 / 1_307_674_368_000.0,
        1.0 / 355_687_428_096_000.0,
    ];
    const COS: [f64; 8] = [
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40_320.0,
        -1.0 / 3_628_800.0,
        1.0 / 479_001_600.0,
        -1.0 / 87_178_291_200.0,
        1.0 / 20_922_789_888_000.0,
        -1.0 / 6_402_373_705_728_000.0,
    ];
    let quadrant = (x * f64x8::splat(std::f64::consts::FRAC_2_PI)).round_ties_even();
    let r = quadrant.mul_neg_add(f64x8::splat(PI_2_LOW), quadrant.mul_neg_add(f64x8::splat(PI_2_HIGH), x));
    let z = r * r;
    let z2 = z * z;
    let z4 = z2 * z2;
    // c₀ + c₁z + … + c₇z⁷ = ((c₀ + c₁z) + z²(c₂ + c₃z)) + z⁴((c₄ + c₅z) + z²(c₆ + c₇z)).
    let estrin = |c: [f64; 8]| {
        let pair = |i: usize| z.mul_add(f64x8::splat(c[i + 1]), f64x8::splat(c[i]));
        let low = z2.mul_add(pair(2), pair(0));
        let high = z2.mul_add(pair(6), pair(4));
        z4.mul_add(high, low)
    };
    // sin r = r + r·z·S(z), cos r = 1 − z/2 + z²·C(z).
    let sin = (r * z).mul_add(estrin(SIN), r);
    let cos = z2.mul_add(estrin(COS), z.mul_neg_add(f64x8::HALF, f64x8::ONE));
    // Quadrant q mod 4: (sin, cos) of x are (s, c), (c, −s), (−s, −c), (−c, s).
    let quarter = (quadrant * f64x8::splat(0.25)).floor().mul_neg_add(f64x8::splat(4.0), quadrant);
    let odd = quarter.simd_eq(f64x8::ONE) | quarter.simd_eq(f64x8::splat(3.0));
    let (sin, cos) = (odd.select(cos, sin), odd.select(sin, cos));
    let sign = f64x8::splat(-0.0);
    let negate_sin = quarter.simd_ge(f64x8::splat(2.0)) & sign;
    let negate_cos = (quarter - f64x8::splat(1.5)).abs().simd_lt(f64x8::ONE) & sign;
    (sin ^ negate_sin, cos ^ negate_cos)
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
        let mut uniform = super::super::seeded_uniform(0x9e37_79b9_7f4a_7c15);
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
            let lanes = lossless_stack_lanes(&n_ambient, &layers, &n_substrate, &wavenumber, cos_i);
            for l in 0..LANES {
                let scalar_layers: Vec<Layer> = layers
                    .iter()
                    .map(|layer| Layer::dielectric(layer.index[l], layer.thickness_nm))
                    .collect();
                let invariant = n_ambient[l] * n_ambient[l] * (1.0 - cos_i * cos_i);
                assert!(lanes.refused & (1 << l) == 0, "lane {l} refused: {scalar_layers:?}, cos {cos_i}");
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

    /// The vector functions the lanes rely on (`wide`'s, after Agner Fog's vector class
    /// library) against the library's scalar ones over the ranges the lanes accept: sin and cos
    /// within 1e-15 absolute (values ≤ 1; the reduction and the polynomial add a few roundings)
    /// from 0 to beyond [`SIN_COS_LIMIT`]; cosh and sinh within 2e-15 relative (a few ulps:
    /// the reduction, the series and e^t ± e^{−t}) from 1e-9 to [`HYPERBOLIC_LIMIT`]; at 0
    /// exactly (1, 0) and (0, 1). The worst measured is printed.
    #[test]
    fn vector_functions_are_the_librarys() {
        let (mut worst_trig, mut worst_hyperbolic) = (0.0_f64, 0.0_f64);
        for i in 0..40_000 {
            let phases: Lanes = std::array::from_fn(|l| (i * LANES + l) as f64 * 0.377_964_473);
            let (sin, cos) = sin_cos_lanes(f64x8::from(phases));
            for (l, &x) in phases.iter().enumerate() {
                worst_trig = worst_trig
                    .max((sin.to_array()[l] - x.sin()).abs())
                    .max((cos.to_array()[l] - x.cos()).abs());
            }
            let t: Lanes = std::array::from_fn(|l| {
                1e-9 * (HYPERBOLIC_LIMIT / 1e-9).powf((i * LANES + l) as f64 / (40_000 * LANES - 1) as f64)
            });
            let (sinh, cosh) = (f64x8::from(t).sinh(), f64x8::from(t).cosh());
            for (l, &t) in t.iter().enumerate() {
                let relative = |a: f64, b: f64| ((a - b) / b).abs();
                worst_hyperbolic = worst_hyperbolic
                    .max(relative(sinh.to_array()[l], t.sinh()))
                    .max(relative(cosh.to_array()[l], t.cosh()));
            }
        }
        assert!(40_000.0 * LANES as f64 * 0.377_964_473 > SIN_COS_LIMIT);
        eprintln!("worst sin/cos difference {worst_trig:e}, worst sinh/cosh relative {worst_hyperbolic:e}");
        assert!(worst_trig < 1e-15, "{worst_trig:e}");
        assert!(worst_hyperbolic < 2e-15, "{worst_hyperbolic:e}");
        let zero = f64x8::ZERO;
        let (sin, cos) = sin_cos_lanes(zero);
        assert_eq!((sin.to_array(), cos.to_array()), ([0.0; LANES], [1.0; LANES]));
        assert_eq!((zero.sinh().to_array(), zero.cosh().to_array()), ([0.0; LANES], [1.0; LANES]));
    }
}
