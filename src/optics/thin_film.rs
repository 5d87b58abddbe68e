//! Thin-film stacks: the complex s and p amplitudes (reflection and transmission) of a smooth
//! interface coated with coherent layers, by the transfer-matrix (characteristic-matrix) method
//! of Macleod, *Thin-Film Optical Filters*, 4th ed., §2.2–2.4 (Born & Wolf, *Principles of
//! Optics*, 7th ed., §1.6, in the other time convention). A stack returns what a bare interface
//! returns ([`crate::optics::fresnel_dielectric_amplitudes`]), in the same conventions, so a
//! stack of zero layers *is* the bare interface, and every caller can take a coating where it
//! takes Fresnel.
//!
//! # Geometry and units
//! Light arrives from a semi-infinite, non-absorbing ambient of real index n₀ at θ₀, crosses the
//! layers in the order given (layer 0 touches the ambient) and enters a semi-infinite substrate
//! of complex index. Thicknesses and wavelengths are in nm (vacuum wavelength). Layers are
//! coherent (thin compared with the coherence length). Light from the substrate side (when it
//! does not absorb) is the same call with the layers reversed and the substrate as the ambient.
//!
//! # Conventions (those of [`crate::polarization`], stated once there)
//! - Fields are `E·e^{i(ωt − k·r)}`; an absorbing medium has the index n − ik. Indices are
//!   *given* as n + ik with k ≥ 0 (as users and the metal tables write them,
//!   [`crate::optics::fresnel_conductor_amplitudes`] takes them alike) and conjugated here.
//! - In every medium j, n_j cos θ_j = √(n_j² − n₀² sin² θ₀) with the root of Im ≤ 0 (and Re ≥ 0
//!   when it is real): the forward wave decays, or is the evanescent cos θ = −i·q of total
//!   internal reflection, as in the bare Fresnel functions.
//! - Hecht's signs: r_s = r⊥, r_p = r∥ = (n_t cos θi − n_i cos θt)/(n_t cos θi + n_i cos θt) for
//!   one interface, so r_p = −r_s at normal incidence; t_s, t_p are ratios of the electric
//!   fields just inside the substrate and just outside the stack.
//! - Ellipsometry: tan ψ·e^{iΔ} = r_p / r_s, Δ in (−π, π]; a bare dielectric below Brewster's
//!   angle has Δ = π. (`tmm`'s `ellips` returns angle(−r_p/r_s) in e^{−iωt}: Δ_tmm = π − Δ.)
//!
//! # Method
//! For each polarisation take a primary tangential field U and its partner V = y·U for the
//! forward wave: s: U = E, y = n cos θ (the tilted admittance, in units of free space's);
//! p: U = H, y = cos θ / n (so that V is the tangential E). Across a layer of phase thickness
//! β = 2π n d cos θ / λ,
//! ```text
//! [U; V]_front = [[cos β, i sin β / y], [i y sin β, cos β]] · [U; V]_back
//! [B; C] = M_1 · M_2 ⋯ M_N · [1; y_sub]
//! r = (y₀ B − C) / (y₀ B + C),   t_U = 2 y₀ / (y₀ B + C)
//! ```
//! (Macleod's matrices; with y_p = cos θ / n rather than n / cos θ the p reflection comes out
//! with Hecht's sign). t_s = t_U; t_p = t_U · n₀ / n_sub (E = H / n). Power: the normal
//! Poynting flux is Re(y)·|U|² in both polarisations, so R = |r|² and
//! T = Re(y_sub) / y₀ · |t_U|², the power entering the substrate (absorbed there if it is a
//! metal; `tmm`'s T, Byrnes' Re(n conj(cos θ)) factors, oblique incidence into an absorbing
//! substrate included); A = 1 − R − T is what the layers absorb. Byrnes, arXiv:1603.02720,
//! writes the same method as interface and propagation matrices, and its `tmm` package provides
//! the fixtures of `tests/thin_film_fixtures.rs`.
//!
//! Limits: cos β and sin β grow like e^{|Im β|}; an absorbing layer overflows f64 only past
//! |Im β| ≈ 700 (some 20 µm of gold, k = 3.43 at 650 nm), long after it is opaque.
//!
//! # In a scene
//! A dielectric's `coating` (`crate::material::dielectric`; issue 41) is a stack whose ambient
//! is the vacuum outside and whose substrate is the glass (reversed from inside):
//! ```toml
//! [materials.coated_lens]
//! type = "dielectric"
//! ior = { glass = "N-BK7" }
//! coating = [{ ior = 1.38, thickness_nm = 99.64 }]   # quarter-wave MgF₂ at 550 nm, air side first
//! ```
//! A mirror's coating (`crate::material::mirror`) has the vacuum as its ambient and the metal
//! (complex n + ik) as its substrate; a layer may absorb (`metal = "gold"`, `complex_ior`).
//!
//! # Speed
//! Stacks whose layers are lossless and not past their critical angle, on a lossless substrate
//! (the usual coatings on glass, from either side), take a real-arithmetic path
//! (`lossless_amplitudes`: real matrices of the form [[a, i·b], [i·c, d]], one reduced sin/cos
//! per layer) that agrees with the complex one to rounding (tested); the rest take the complex
//! path. The renderer evaluates a coated dielectric at every wavelength lane of a vertex at once
//! ([`lanes`]: the same real method in eight-lane vectors, each layer's matrix scaled by its
//! admittance so that no layer needs a division, layers past their critical angle kept in the
//! real form through cosh and sinh; tested against this module's evaluation in
//! `tests/thin_film_lanes.rs`).

use num_complex::Complex64;

pub mod lanes;

/// One coherent layer of a stack.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layer {
    /// Complex index n + ik, k ≥ 0 for an absorbing layer (the sign users and data tables use;
    /// see the module documentation).
    pub index: Complex64,
    /// Physical thickness in nm, ≥ 0.
    pub thickness_nm: f64,
}

impl Layer {
    /// A non-absorbing layer of real index `index` and thickness `thickness_nm` (nm).
    pub fn dielectric(index: f64, thickness_nm: f64) -> Self {
        Self { index: Complex64::new(index, 0.0), thickness_nm }
    }

    /// A quarter-wave layer at `design_nm`: optical thickness n·d = λ/4, so that at normal
    /// incidence its two faces reflect in antiphase (the classic single-layer AR coating).
    pub fn quarter_wave(index: f64, design_nm: f64) -> Self {
        Self::dielectric(index, design_nm / (4.0 * index))
    }
}

/// The amplitudes and powers of a stack for one wavelength and angle; see the module
/// documentation for the conventions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinFilmAmplitudes {
    /// Amplitude reflection coefficient for s (TE) polarisation.
    pub r_s: Complex64,
    /// Amplitude reflection coefficient for p (TM) polarisation (Hecht's sign).
    pub r_p: Complex64,
    /// Amplitude transmission coefficient for s: E just inside the substrate over the
    /// incident E at the first interface.
    pub t_s: Complex64,
    /// Amplitude transmission coefficient for p, of the electric fields likewise.
    pub t_p: Complex64,
    /// Reflectance for s, |r_s|².
    pub reflectance_s: f64,
    /// Reflectance for p, |r_p|².
    pub reflectance_p: f64,
    /// Transmittance for s: the fraction of the incident power entering the substrate.
    pub transmittance_s: f64,
    /// Transmittance for p.
    pub transmittance_p: f64,
}

impl ThinFilmAmplitudes {
    /// Fraction of the s power absorbed in the layers, 1 − R_s − T_s (0 to rounding for
    /// non-absorbing layers).
    pub fn absorptance_s(&self) -> f64 {
        1.0 - self.reflectance_s - self.transmittance_s
    }

    /// Fraction of the p power absorbed in the layers, 1 − R_p − T_p.
    pub fn absorptance_p(&self) -> f64 {
        1.0 - self.reflectance_p - self.transmittance_p
    }

    /// Ellipsometric ψ in radians, in [0, π/2]: tan ψ = |r_p| / |r_s|.
    pub fn psi(&self) -> f64 {
        self.r_p.norm().atan2(self.r_s.norm())
    }

    /// Ellipsometric Δ in radians, in (−π, π]: the phase of r_p / r_s (see the module
    /// documentation for its convention). Ill-conditioned where r_s or r_p nearly vanishes.
    pub fn delta(&self) -> f64 {
        (self.r_p * self.r_s.conj()).arg()
    }
}

/// Reflection and transmission amplitudes of `layers` (from the ambient side) on a substrate,
/// for light of vacuum wavelength `lambda_nm` (nm, > 0) arriving from an ambient of real index
/// `n_ambient` (> 0) at `cos_theta_i` in [0, 1] (measured in the ambient). `n_substrate` is
/// n + ik, k ≥ 0 (a metal too). Zero layers give the bare interface's Fresnel amplitudes.
///
/// Never NaN for finite inputs, layers at their critical angle and grazing incidence included
/// (where R = 1 and T = 0, unless every medium has the ambient's index: then r = 0, t = 1,
/// as for a bare index-matched interface). Debug builds
/// panic on a negative thickness, a non-positive wavelength or ambient index, or cos θ_i
/// outside [0, 1] (beyond rounding).
pub fn thin_film_amplitudes(
    n_ambient: f64,
    layers: &[Layer],
    n_substrate: Complex64,
    lambda_nm: f64,
    cos_theta_i: f64,
) -> ThinFilmAmplitudes {
    debug_assert!(n_ambient.is_finite() && n_ambient > 0.0, "ambient index {n_ambient}");
    debug_assert!(lambda_nm.is_finite() && lambda_nm > 0.0, "wavelength {lambda_nm} nm");
    debug_assert!((-1e-12..=1.0 + 1e-12).contains(&cos_theta_i), "cos θi = {cos_theta_i}");
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    // n₀ sin θ₀, conserved across every interface (Snell).
    let sin_i_sqr = (1.0 - cos_i * cos_i).max(0.0);
    let invariant_sqr = n_ambient * n_ambient * sin_i_sqr;
    if let Some(amplitudes) =
        lossless_amplitudes(n_ambient, layers, n_substrate, lambda_nm, cos_i, invariant_sqr)
    {
        return amplitudes;
    }
    complex_amplitudes(n_ambient, layers, n_substrate, lambda_nm, cos_i, invariant_sqr)
}

/// [`thin_film_amplitudes`] in complex arithmetic, valid for every stack (absorbing media, total
/// internal reflection, critical angles); `cos_i` in [0, 1], `invariant_sqr` = n₀² sin² θ₀.
fn complex_amplitudes(
    n_ambient: f64,
    layers: &[Layer],
    n_substrate: Complex64,
    lambda_nm: f64,
    cos_i: f64,
    invariant_sqr: f64,
) -> ThinFilmAmplitudes {
    let ambient = Medium::new(Complex64::new(n_ambient, 0.0), invariant_sqr);
    let substrate = Medium::new(n_substrate, invariant_sqr);
    // For the ambient, n cos θ = n₀ cos θ₀ exactly, not its round trip through sin².
    let ambient = Medium { n_cos: Complex64::new(n_ambient * cos_i, 0.0), ..ambient };

    let mut s = Characteristic::identity();
    let mut p = Characteristic::identity();
    for layer in layers {
        debug_assert!(layer.thickness_nm >= 0.0, "thickness {} nm", layer.thickness_nm);
        let medium = Medium::new(layer.index, invariant_sqr);
        // β = k d · n cos θ with k = 2π/λ; the matrices need β/y = k d (s) and k d n² (p).
        let wavenumber_thickness = std::f64::consts::TAU * layer.thickness_nm / lambda_nm;
        let beta = medium.n_cos * wavenumber_thickness;
        let index_sqr = medium.index * medium.index;
        // β is the same for s and p: its (complex, f64) cos, sin and sinc once for both.
        let phase = Phase::new(beta);
        s = s.then(&phase, medium.admittance_s(), Complex64::new(wavenumber_thickness, 0.0));
        p = p.then(&phase, medium.admittance_p(), index_sqr * wavenumber_thickness);
    }
    let (r_s, t_s, transmittance_s) = s.solve(ambient.admittance_s(), substrate.admittance_s());
    let (r_p, t_p_h, transmittance_p) = p.solve(ambient.admittance_p(), substrate.admittance_p());
    // The p primary field is H; E = H / n in each medium (units of free space's impedance).
    let t_p = t_p_h * (ambient.index / substrate.index);
    ThinFilmAmplitudes {
        r_s,
        r_p,
        t_s,
        t_p,
        reflectance_s: r_s.norm_sqr(),
        reflectance_p: r_p.norm_sqr(),
        transmittance_s,
        transmittance_p,
    }
}

/// The same amplitudes in real arithmetic, when every layer of non-zero thickness and the
/// substrate are lossless (k = 0), the wave propagates in each layer (n² > n₀² sin² θ₀, so
/// that n cos θ is real and positive) and propagates in the substrate or is evanescent there
/// (total internal reflection behind the stack); `None` otherwise (absorbing media, a layer
/// past or at its critical angle, the substrate at its), for [`thin_film_amplitudes`]'s
/// complex path.
/// The speed of the common coating (issue 41: a coated interface within a small factor of a bare
/// one): no complex square roots or divisions, one real sin and cos per layer shared by s and
/// p, one reciprocal per polarisation.
///
/// Every characteristic matrix of a lossless propagating layer is [[c, i·S/y], [i·y·S, c]] with
/// c = cos β, S = sin β, y real, and products of matrices [[a, i·b], [i·c, d]] (a, b, c, d
/// real) keep that form: [[a₁a₂ − b₁c₂, i(a₁b₂ + b₁d₂)], [i(c₁a₂ + d₁c₂), d₁d₂ − c₁b₂]]. With
/// B = a + i·b·y_sub and C = d·y_sub + i·c, r = (y₀B − C)/(y₀B + C), t = 2y₀/(y₀B + C) and
/// T = 4y₀·y_sub/|y₀B + C|², as in the complex path. A layer of zero thickness is the identity
/// and is skipped by both paths alike.
fn lossless_amplitudes(
    n_ambient: f64,
    layers: &[Layer],
    n_substrate: Complex64,
    lambda_nm: f64,
    cos_i: f64,
    invariant_sqr: f64,
) -> Option<ThinFilmAmplitudes> {
    // n cos θ of a lossless medium where the wave propagates, else None.
    let propagating = |index: Complex64| {
        let n_cos_sqr = index.re * index.re - invariant_sqr;
        (index.im == 0.0 && n_cos_sqr > 0.0).then(|| n_cos_sqr.sqrt())
    };
    if layers.iter().any(|layer| layer.thickness_nm > 0.0 && propagating(layer.index).is_none()) {
        return None;
    }
    // The substrate may also take the wave evanescent (total internal reflection behind the
    // stack): n cos θ = −i·q, the decaying root (Im ≤ 0), held as (re, im).
    if n_substrate.im != 0.0 {
        return None;
    }
    let n_substrate = n_substrate.re;
    let substrate_n_cos_sqr = n_substrate * n_substrate - invariant_sqr;
    let substrate_n_cos = match substrate_n_cos_sqr {
        x if x > 0.0 => (x.sqrt(), 0.0),
        x if x < 0.0 => (0.0, -(-x).sqrt()),
        _ => return None,
    };
    // [a, b, c, d] for s and p.
    let mut s = [1.0, 0.0, 0.0, 1.0];
    let mut p = [1.0, 0.0, 0.0, 1.0];
    let wavenumber = std::f64::consts::TAU / lambda_nm;
    for layer in layers.iter().filter(|layer| layer.thickness_nm > 0.0) {
        let n = layer.index.re;
        let n_cos = (n * n - invariant_sqr).sqrt();
        let (sin, cos) = sin_cos(wavenumber * layer.thickness_nm * n_cos);
        // y_s = n cos θ, y_p = n cos θ / n².
        let y_s = n_cos;
        let y_p = n_cos / (n * n);
        let then = |[a, b, c, d]: [f64; 4], y: f64| {
            let (sin_over_y, sin_times_y) = (sin / y, sin * y);
            [
                a * cos - b * sin_times_y,
                a * sin_over_y + b * cos,
                c * cos + d * sin_times_y,
                d * cos - c * sin_over_y,
            ]
        };
        s = then(s, y_s);
        p = then(p, y_p);
    }
    // y_sub = u + i·v is real (v = 0) or imaginary (u = 0): B = (a − b·v) + i·b·u,
    // C = d·u + i(c + d·v).
    let solve = |[a, b, c, d]: [f64; 4], y_ambient: f64, (u, v): (f64, f64)| {
        let (front_re, front_im) = (y_ambient * (a - b * v), y_ambient * b * u);
        let (back_re, back_im) = (d * u, c + d * v);
        let denominator = Complex64::new(front_re + back_re, front_im + back_im);
        let inverse_norm_sqr = 1.0 / denominator.norm_sqr();
        let conjugate = denominator.conj() * inverse_norm_sqr;
        let r = Complex64::new(front_re - back_re, front_im - back_im) * conjugate;
        let t = 2.0 * y_ambient * conjugate;
        // T = 4·y₀·Re(y_sub)/|y₀B + C|²: 0 behind total internal reflection.
        let transmittance = 4.0 * y_ambient * u * inverse_norm_sqr;
        (r, t, transmittance)
    };
    let index_sqr = n_substrate * n_substrate;
    let (r_s, t_s, transmittance_s) = solve(s, n_ambient * cos_i, substrate_n_cos);
    let (r_p, t_p_h, transmittance_p) =
        solve(p, cos_i / n_ambient, (substrate_n_cos.0 / index_sqr, substrate_n_cos.1 / index_sqr));
    Some(ThinFilmAmplitudes {
        r_s,
        r_p,
        t_s,
        t_p: t_p_h * (n_ambient / n_substrate),
        reflectance_s: r_s.norm_sqr(),
        reflectance_p: r_p.norm_sqr(),
        transmittance_s,
        transmittance_p,
    })
}

/// sin x and cos x of a phase thickness x ≥ 0 (radians), within a few units in the last place
/// ([`sin_cos_reduced`]); beyond its exact range (never for the scenes' limits) the library's.
#[inline]
fn sin_cos(x: f64) -> (f64, f64) {
    match sin_cos_reduced(x) {
        (sin, cos, true) => (sin, cos),
        _ => x.sin_cos(),
    }
}

/// sin x and cos x of a phase thickness x (radians), and whether they are exact (within a few
/// units in the last place): x reduced by the nearest multiple q of π/2 (Cody and Waite's
/// two-part π/2, exact for |q| < 2²⁰, i.e. every phase of a layer of at most 100 µm and index
/// ≤ 100), then the Taylor series of sin and cos on |r| ≤ π/4 to r¹⁷ and r¹⁸ (the next terms
/// are below 1e-19). About a quarter of the cost of the library's separate `sin` and `cos`,
/// which is most of a one-layer stack's. No branch (the quadrant is chosen by selects), so that
/// a loop over wavelength lanes ([`lanes`]) vectorises; `false` (x too large, or NaN) leaves
/// the caller to the library.
#[inline(always)]
fn sin_cos_reduced(x: f64) -> (f64, f64, bool) {
    // π/2 = PI_2_HIGH + PI_2_LOW: the high part's 33 significant bits make q·PI_2_HIGH exact.
    const PI_2_HIGH: f64 = 1.570_796_326_734_125_6;
    const PI_2_LOW: f64 = 6.077_100_506_506_192e-11;
    // Ties to even: one vector instruction (ties away from zero is not); either nearest
    // multiple keeps |r| ≤ π/4.
    let quadrant = (x * std::f64::consts::FRAC_2_PI).round_ties_even();
    // Also false for NaN.
    let exact = quadrant.abs() < f64::from(1u32 << 20);
    let r = (x - quadrant * PI_2_HIGH) - quadrant * PI_2_LOW;
    let z = r * r;
    // 1/3!, 1/5!, … and 1/2!, 1/4!, … with alternating signs, Horner in z.
    let sin = r
        * (1.0
            + z * (-1.0 / 6.0
                + z * (1.0 / 120.0
                    + z * (-1.0 / 5040.0
                        + z * (1.0 / 362_880.0
                            + z * (-1.0 / 39_916_800.0
                                + z * (1.0 / 6_227_020_800.0
                                    + z * (-1.0 / 1_307_674_368_000.0
                                        + z * (1.0 / 355_687_428_096_000.0)))))))));
    let cos = 1.0
        + z * (-0.5
            + z * (1.0 / 24.0
                + z * (-1.0 / 720.0
                    + z * (1.0 / 40_320.0
                        + z * (-1.0 / 3_628_800.0
                            + z * (1.0 / 479_001_600.0
                                + z * (-1.0 / 87_178_291_200.0
                                    + z * (1.0 / 20_922_789_888_000.0
                                        + z * (-1.0 / 6_402_373_705_728_000.0)))))))));
    // Quadrant q: (sin, cos) of x are (s, c), (c, −s), (−s, −c), (−c, s) for q mod 4 = 0…3.
    // q mod 4 in floating point (exact for |q| < 2²⁰), not through an integer: a float to
    // integer conversion does not vectorise here (it saturates, element by element).
    let quarter = quadrant - 4.0 * (0.25 * quadrant).floor();
    let odd = quarter == 1.0 || quarter == 3.0;
    let (sin, cos) = if odd { (cos, -sin) } else { (sin, cos) };
    let (sin, cos) = if quarter >= 2.0 { (-sin, -cos) } else { (sin, cos) };
    (sin, cos, exact)
}

/// A medium seen by the wave: its index in the e^{+iωt} convention and n cos θ.
#[derive(Clone, Copy)]
struct Medium {
    /// n − ik.
    index: Complex64,
    /// n cos θ = √(n² − n₀² sin² θ₀), the root with Im ≤ 0 (Re ≥ 0 when real).
    n_cos: Complex64,
}

impl Medium {
    /// `index` as given, n + ik (k ≥ 0); `invariant_sqr` = n₀² sin² θ₀.
    fn new(index: Complex64, invariant_sqr: f64) -> Self {
        debug_assert!(index.re.is_finite() && index.im.is_finite() && index.norm_sqr() > 0.0);
        let index = Complex64::new(index.re, -index.im.abs());
        // The principal root has Re ≥ 0; for a lossless medium beyond its critical angle
        // it is +i·q, the growing wave, and the decaying one is its negative.
        let mut n_cos = (index * index - invariant_sqr).sqrt();
        if n_cos.im > 0.0 {
            n_cos = -n_cos;
        }
        Self { index, n_cos }
    }

    /// Tilted admittance for s: y = n cos θ.
    fn admittance_s(&self) -> Complex64 {
        self.n_cos
    }

    /// For p: y = cos θ / n = (n cos θ) / n², the ratio of tangential E to H.
    fn admittance_p(&self) -> Complex64 {
        self.n_cos / (self.index * self.index)
    }
}

/// A layer's phase thickness β through its cos β, sin β and sinc β (shared by s and p).
struct Phase {
    cos: Complex64,
    sin: Complex64,
    sinc: Complex64,
}

impl Phase {
    fn new(beta: Complex64) -> Self {
        // num-complex's sin and cos (sin(a + ib) = sin a cosh b + i cos a sinh b, cos(a + ib) =
        // cos a cosh b − i sin a sinh b), with each real function evaluated once, and cosh, sinh
        // of a zero b (every lossless layer short of its critical angle) taken as the 1 and ±0
        // they are exactly: the same bits.
        let (sin_re, cos_re) = (beta.re.sin(), beta.re.cos());
        let (cosh_im, sinh_im) =
            if beta.im == 0.0 { (1.0, beta.im) } else { (beta.im.cosh(), beta.im.sinh()) };
        let sin = Complex64::new(sin_re * cosh_im, cos_re * sinh_im);
        let cos = Complex64::new(cos_re * cosh_im, -sin_re * sinh_im);
        Self { cos, sin, sinc: sinc(beta, sin) }
    }
}

/// The product of the layers' characteristic matrices, [[m11, m12], [m21, m22]].
#[derive(Clone, Copy)]
struct Characteristic {
    m11: Complex64,
    m12: Complex64,
    m21: Complex64,
    m22: Complex64,
}

impl Characteristic {
    fn identity() -> Self {
        let (zero, one) = (Complex64::new(0.0, 0.0), Complex64::new(1.0, 0.0));
        Self { m11: one, m12: zero, m21: zero, m22: one }
    }

    /// This product times the next layer's matrix [[cos β, i sin β / y], [i y sin β, cos β]],
    /// given β, y and β / y (finite where y = 0: a layer at its critical angle, or of the
    /// ambient's index at grazing incidence, where sin β / y → β / y).
    fn then(self, phase: &Phase, admittance: Complex64, beta_over_admittance: Complex64) -> Self {
        let i = Complex64::i();
        // sin β / y = sinc β · β / y; i sin β / y and i y sin β are even in y (and so in the
        // choice of root), as is cos β.
        let (cos, sin, sinc) = (phase.cos, phase.sin, phase.sinc);
        let (l11, l12, l21, l22) = (cos, i * sinc * beta_over_admittance, i * sin * admittance, cos);
        Self {
            m11: self.m11 * l11 + self.m12 * l21,
            m12: self.m11 * l12 + self.m12 * l22,
            m21: self.m21 * l11 + self.m22 * l21,
            m22: self.m21 * l12 + self.m22 * l22,
        }
    }

    /// r, t of the primary field, and the power transmittance, between an ambient of real
    /// admittance `y_ambient` (≥ 0) and the substrate's `y_substrate`.
    fn solve(&self, y_ambient: Complex64, y_substrate: Complex64) -> (Complex64, Complex64, f64) {
        let b = self.m11 + self.m12 * y_substrate;
        let c = self.m21 + self.m22 * y_substrate;
        let denominator = y_ambient * b + c;
        if denominator.norm_sqr() == 0.0 {
            // Only at grazing incidence (y₀ = 0; for y₀ > 0 a passive stack's input
            // admittance C/B has Re ≥ 0, and B, C never vanish together since det M = 1) on a
            // stack whose input admittance vanishes too, as when every medium has the ambient's
            // index: no interface, as `fresnel_dielectric_amplitudes` answers for eta = 1.
            return (Complex64::new(0.0, 0.0), Complex64::new(1.0, 0.0), 1.0);
        }
        let r = (y_ambient * b - c) / denominator;
        let t = 2.0 * y_ambient / denominator;
        // T = Re(y_sub) |t|² / y₀ = 4 y₀ Re(y_sub) / |y₀ B + C|²: no division by y₀, so
        // grazing incidence (y₀ = 0) gives T = 0.
        let transmittance = 4.0 * y_ambient.re * y_substrate.re / denominator.norm_sqr();
        (r, t, transmittance)
    }
}

/// sin z / z, 1 at z = 0, given `sin` = sin z.
fn sinc(z: Complex64, sin: Complex64) -> Complex64 {
    // Below |z| = 1e-3 the series' next term z⁶/5040 is < 2e-22, far under f64 rounding of 1.
    if z.norm_sqr() < 1e-6 {
        let z_sqr = z * z;
        1.0 - z_sqr / 6.0 + z_sqr * z_sqr / 120.0
    } else {
        sin / z
    }
}

/// A seeded xorshift64 stream of uniform numbers in [0, 1) on a 2⁻⁵³ grid, for the stack tests
/// of this module and of [`lanes`] (reproducible: the same seed, the same numbers).
#[cfg(test)]
fn seeded_uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::{fresnel_conductor_amplitudes, fresnel_dielectric_amplitudes};
    use num_complex::Complex32;

    fn real(n: f64) -> Complex64 {
        Complex64::new(n, 0.0)
    }

    #[test]
    fn quarter_wave_mgf2_on_bk7_meets_the_closed_form() {
        // Macleod §3.2: a quarter wave of index n1 on a substrate ns at normal incidence and its
        // design wavelength reflects R = ((n0 ns − n1²)/(n0 ns + n1²))². MgF₂ (1.38) on N-BK7
        // (1.5168): (1.5168 − 1.9044)²/(1.5168 + 1.9044)² = 0.0128354…, 1.28 % against the
        // bare ((1.5168 − 1)/(1.5168 + 1))² = 4.22 %.
        let (n1, ns) = (1.38_f64, 1.5168_f64);
        let closed_form = ((ns - n1 * n1) / (ns + n1 * n1)).powi(2);
        let coated = thin_film_amplitudes(1.0, &[Layer::quarter_wave(n1, 550.0)], real(ns), 550.0, 1.0);
        assert!((coated.reflectance_s - closed_form).abs() < 1e-15, "{coated:?} vs {closed_form}");
        assert!((coated.reflectance_p - closed_form).abs() < 1e-15);
        assert!((closed_form - 0.012_835_4).abs() < 1e-7, "{closed_form}");
        let bare = thin_film_amplitudes(1.0, &[], real(ns), 550.0, 1.0);
        assert!((bare.reflectance_s - 0.042_164_6).abs() < 1e-7, "{bare:?}");
        // At normal incidence the quarter wave delays the transmitted field by π/2: e^{−iπ/2}.
        assert!((coated.t_s.arg() + std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{coated:?}");
    }

    #[test]
    fn zero_layers_are_the_bare_dielectric_interface() {
        // The same numbers as fresnel_dielectric_amplitudes (f32, so within its rounding), and
        // in f64 exactly Hecht's formulas.
        for eta in [1.0001_f64, 1.333, 1.5168, 2.4, 0.75] {
            for i in 0..=40 {
                let cos_i = i as f64 / 40.0;
                let stack = thin_film_amplitudes(1.0, &[], real(eta), 550.0, cos_i);
                let bare = fresnel_dielectric_amplitudes(cos_i as f32, eta as f32);
                let context = format!("eta {eta}, cos θi {cos_i}: {stack:?} {bare:?}");
                let close =
                    |a: Complex64, b: Complex32| (a - Complex64::new(b.re as f64, b.im as f64)).norm();
                // Near cos θt = 0 (eta 0.75 at its critical angle, 1.0001 grazing) f32 rounding
                // of cos θt is magnified, as the bare function's documentation says.
                let tolerance = if bare.cos_theta_t.abs() > 0.05 { 1e-5 } else { 2e-3 };
                assert!(close(stack.r_s, bare.r_s) < tolerance, "{context}");
                assert!(close(stack.r_p, bare.r_p) < tolerance, "{context}");
                assert!(close(stack.t_s, bare.t_s) < tolerance, "{context}");
                assert!(close(stack.t_p, bare.t_p) < tolerance, "{context}");
                assert!((stack.transmittance_s - bare.transmittance_s as f64).abs() < tolerance);
                assert!((stack.transmittance_p - bare.transmittance_p as f64).abs() < tolerance);
                // Hecht §4.6 in f64, with the decaying root under total internal reflection.
                let cos_t = Medium::new(real(eta), 1.0 - cos_i * cos_i).n_cos / eta;
                let hecht_r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
                let hecht_r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
                let hecht_t_p = 2.0 * cos_i / (eta * cos_i + cos_t);
                assert!((stack.r_s - hecht_r_s).norm() < 1e-15, "{context}");
                assert!((stack.r_p - hecht_r_p).norm() < 1e-14, "{context}");
                assert!((stack.t_p - hecht_t_p).norm() < 1e-14, "{context}");
            }
        }
    }

    #[test]
    fn zero_layers_on_gold_are_the_bare_conductor() {
        let gold = Complex64::new(0.18, 3.43);
        for i in 0..=20 {
            let cos_i = i as f64 / 20.0;
            let stack = thin_film_amplitudes(1.0, &[], gold, 650.0, cos_i);
            let (r_s, r_p) = fresnel_conductor_amplitudes(cos_i as f32, Complex32::new(0.18, 3.43));
            let close = |a: Complex64, b: Complex32| (a - Complex64::new(b.re as f64, b.im as f64)).norm();
            assert!(close(stack.r_s, r_s) < 2e-6 && close(stack.r_p, r_p) < 2e-6, "{cos_i}: {stack:?}");
            // Nothing absorbed before the substrate: what is not reflected enters the gold.
            assert!(stack.absorptance_s().abs() < 1e-14 && stack.absorptance_p().abs() < 1e-14);
        }
    }

    #[test]
    fn invisible_layers_change_nothing() {
        // A layer of zero thickness is no layer at all; a layer of the ambient's own index only
        // moves the reference plane back by d: r gains the round-trip phase e^{−2iβ} and t the
        // single pass e^{−iβ}, β = 2π n₀ d cos θ₀ / λ, and no power changes.
        let substrate = Complex64::new(1.5168, 0.0);
        for cos_i in [1.0, 0.8, 0.3, 0.05] {
            let bare = thin_film_amplitudes(1.0, &[], substrate, 500.0, cos_i);
            let thin =
                [Layer::dielectric(2.4, 0.0), Layer { index: Complex64::new(0.18, 3.43), thickness_nm: 0.0 }];
            for layer in thin {
                let coated = thin_film_amplitudes(1.0, &[layer], substrate, 500.0, cos_i);
                assert_eq!(coated, bare, "{layer:?}, cos θi {cos_i}");
            }
            let coated = thin_film_amplitudes(1.0, &[Layer::dielectric(1.0, 123.4)], substrate, 500.0, cos_i);
            let beta = std::f64::consts::TAU * 123.4 * cos_i / 500.0;
            let (single, round_trip) =
                (Complex64::from_polar(1.0, beta), Complex64::from_polar(1.0, 2.0 * beta));
            let context = format!("cos θi {cos_i}: {coated:?} {bare:?}");
            assert!((coated.r_s * round_trip - bare.r_s).norm() < 1e-14, "{context}");
            assert!((coated.r_p * round_trip - bare.r_p).norm() < 1e-14, "{context}");
            assert!((coated.t_s * single - bare.t_s).norm() < 1e-14, "{context}");
            assert!((coated.t_p * single - bare.t_p).norm() < 1e-14, "{context}");
            assert!((coated.transmittance_s - bare.transmittance_s).abs() < 1e-14, "{context}");
            assert!((coated.transmittance_p - bare.transmittance_p).abs() < 1e-14, "{context}");
        }
    }

    #[test]
    fn a_half_wave_layer_is_absent_at_its_design_wavelength() {
        // Macleod §3.1: at normal incidence a half-wave layer (n·d = λ/2) is an "absentee":
        // r of the coated surface equals the bare one's; t changes by the round phase −1.
        let layer = Layer::dielectric(2.05, 550.0 / (2.0 * 2.05));
        let coated = thin_film_amplitudes(1.0, &[layer], real(1.5168), 550.0, 1.0);
        let bare = thin_film_amplitudes(1.0, &[], real(1.5168), 550.0, 1.0);
        assert!((coated.r_s - bare.r_s).norm() < 1e-14, "{coated:?} {bare:?}");
        assert!((coated.t_s + bare.t_s).norm() < 1e-14, "{coated:?} {bare:?}");
    }

    #[test]
    fn a_lossless_stack_conserves_energy_at_every_angle() {
        // R + T = 1 to rounding, also beyond the substrate's critical angle (T = 0 there).
        let layers = [
            Layer::quarter_wave(2.4, 550.0),
            Layer::quarter_wave(1.46, 550.0),
            Layer::dielectric(1.38, 77.0),
        ];
        for (n0, ns) in [(1.0, 1.5168), (1.5168, 1.0), (1.333, 1.0)] {
            for i in 0..=50 {
                let cos_i = i as f64 / 50.0;
                for lambda in [380.0, 550.0, 700.0] {
                    let a = thin_film_amplitudes(n0, &layers, real(ns), lambda, cos_i);
                    let context = format!("{n0} → {ns}, cos θi {cos_i}, {lambda} nm: {a:?}");
                    assert!(a.absorptance_s().abs() < 1e-13, "{context}");
                    assert!(a.absorptance_p().abs() < 1e-13, "{context}");
                }
            }
        }
    }

    #[test]
    fn an_absorbing_layer_absorbs() {
        // 10 nm of gold on glass: 0 < A < 1, and R, T in [0, 1].
        let layers = [Layer { index: Complex64::new(0.18, 3.43), thickness_nm: 10.0 }];
        for cos_i in [1.0, 0.7, 0.2] {
            let a = thin_film_amplitudes(1.0, &layers, real(1.5168), 650.0, cos_i);
            for value in [a.reflectance_s, a.reflectance_p, a.transmittance_s, a.transmittance_p] {
                assert!((0.0..=1.0).contains(&value), "{a:?}");
            }
            assert!(a.absorptance_s() > 0.01 && a.absorptance_p() > 0.01, "{a:?}");
        }
    }

    #[test]
    fn ellipsometry_of_a_bare_surface() {
        // Below Brewster's angle r_p/r_s < 0 (Δ = π), above it > 0 (Δ = 0); tan ψ = |r_p/r_s|.
        let below = thin_film_amplitudes(1.0, &[], real(1.5), 500.0, 40.0_f64.to_radians().cos());
        let above = thin_film_amplitudes(1.0, &[], real(1.5), 500.0, 70.0_f64.to_radians().cos());
        assert!((below.delta().abs() - std::f64::consts::PI).abs() < 1e-12, "{below:?}");
        assert!(above.delta().abs() < 1e-12, "{above:?}");
        assert!((below.psi().tan() - (below.r_p / below.r_s).norm()).abs() < 1e-12);
    }

    #[test]
    fn a_layer_at_its_critical_angle_is_finite_and_continuous() {
        // From glass (1.5) into MgF₂ (1.38) at sin θ = 1.38/1.5: the layer's n cos θ = 0, its
        // admittance vanishes and sin β / y → β / y. The result must be finite and the limit
        // of its neighbours (a first-order change of 1e-9 in cos θi moves r by ~1e-9 · |dr|).
        let layers = [Layer::dielectric(1.38, 80.0), Layer::dielectric(2.05, 60.0)];
        let sin_critical = 1.38_f64 / 1.5;
        let cos_critical = (1.0 - sin_critical * sin_critical).sqrt();
        // Exactly: this cos θi rounds so that the layer's n cos θ is 0, not merely small.
        let invariant_sqr = 1.5 * 1.5 * (1.0 - cos_critical * cos_critical);
        assert_eq!(Medium::new(real(1.38), invariant_sqr).n_cos, real(0.0));
        let at = thin_film_amplitudes(1.5, &layers, real(1.0), 550.0, cos_critical);
        let near = thin_film_amplitudes(1.5, &layers, real(1.0), 550.0, cos_critical + 1e-9);
        for (a, b) in [(at.r_s, near.r_s), (at.r_p, near.r_p)] {
            assert!(a.re.is_finite() && a.im.is_finite(), "{at:?}");
            assert!((a - b).norm() < 1e-6, "{at:?} {near:?}");
        }
        assert!(at.absorptance_s().abs() < 1e-13 && at.absorptance_p().abs() < 1e-13, "{at:?}");
    }

    #[test]
    fn grazing_incidence_on_matched_media_is_no_interface() {
        // Ambient, layer and substrate of one index at cos θi = 0: y₀ = y = y_sub = 0.
        let a = thin_film_amplitudes(1.333, &[Layer::dielectric(1.333, 50.0)], real(1.333), 550.0, 0.0);
        assert_eq!((a.r_s, a.t_s, a.transmittance_s), (real(0.0), real(1.0), 1.0), "{a:?}");
        assert_eq!((a.r_p, a.t_p, a.transmittance_p), (real(0.0), real(1.0), 1.0), "{a:?}");
    }

    #[test]
    fn the_real_path_agrees_with_the_complex_one() {
        // Lossless stacks of 0–6 layers (index 1.2–2.5, 0–400 nm) on substrates of 1.0–1.9 from
        // ambients of 1.0 and 1.5 at every angle, both paths in f64: they evaluate the same
        // products in another order, so they agree to rounding (1e-12 leaves room for the
        // growth of cos β, sin β products over six layers).
        let mut uniform = seeded_uniform(0x2545_f491_4f6c_dd1d);
        let mut compared = 0;
        let mut evanescent = 0;
        for _ in 0..400 {
            let count = (uniform() * 7.0) as usize;
            let layers: Vec<Layer> =
                (0..count).map(|_| Layer::dielectric(1.2 + 1.3 * uniform(), 400.0 * uniform())).collect();
            let n_ambient = if uniform() < 0.5 { 1.0 } else { 1.5 };
            let substrate = real(1.0 + 0.9 * uniform());
            let lambda = 360.0 + 470.0 * uniform();
            let cos_i = uniform();
            let invariant_sqr = n_ambient * n_ambient * (1.0 - cos_i * cos_i);
            let Some(fast) = lossless_amplitudes(n_ambient, &layers, substrate, lambda, cos_i, invariant_sqr)
            else {
                continue;
            };
            let general = complex_amplitudes(n_ambient, &layers, substrate, lambda, cos_i, invariant_sqr);
            let context = format!("{layers:?} on {substrate} from {n_ambient}, {lambda} nm, cos {cos_i}");
            for (a, b) in [
                (fast.r_s, general.r_s),
                (fast.r_p, general.r_p),
                (fast.t_s, general.t_s),
                (fast.t_p, general.t_p),
            ] {
                assert!((a - b).norm() < 1e-12, "{context}: {fast:?} {general:?}");
            }
            assert!((fast.transmittance_s - general.transmittance_s).abs() < 1e-12, "{context}");
            assert!((fast.transmittance_p - general.transmittance_p).abs() < 1e-12, "{context}");
            compared += 1;
            evanescent +=
                usize::from(n_ambient * n_ambient * (1.0 - cos_i * cos_i) > substrate.re * substrate.re);
        }
        // Most draws take the real path, some of them with total internal reflection behind the
        // stack; the rest (a layer past its critical angle) go the complex way.
        assert!(compared > 200 && evanescent > 20, "{compared}, {evanescent}");
    }

    #[test]
    fn the_phase_sin_cos_is_the_librarys() {
        // Against the library's sin and cos (within an ulp): the reduction and the series add
        // a few rounding errors of the result's size (≤ 1), so 1e-15 absolute (measured: see
        // the message); up to beyond the largest phase of a 100 µm layer of n = 10 at 360 nm
        // (1.75e4 rad).
        let mut worst = 0.0_f64;
        for i in 0..200_000 {
            let x = i as f64 * 0.173_205_080_756_887_7;
            let (sin, cos) = sin_cos(x);
            worst = worst.max((sin - x.sin()).abs()).max((cos - x.cos()).abs());
        }
        assert!(worst < 1e-15, "worst difference {worst:e}");
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert_eq!(sin_cos(1e300), 1e300_f64.sin_cos());
    }

    #[test]
    fn grazing_incidence_is_finite() {
        let layers = [Layer::quarter_wave(1.38, 550.0)];
        for substrate in [real(1.5168), Complex64::new(0.18, 3.43), real(1.0)] {
            let a = thin_film_amplitudes(1.0, &layers, substrate, 550.0, 0.0);
            assert!((a.reflectance_s - 1.0).abs() < 1e-12 && (a.reflectance_p - 1.0).abs() < 1e-12, "{a:?}");
            assert_eq!((a.transmittance_s, a.transmittance_p), (0.0, 0.0));
        }
    }
}
