//! [`Dielectric`]: a smooth interface between vacuum (outside, n = 1) and a dielectric of index
//! n(λ) (inside), with Fresnel-weighted reflection and refraction (Hecht, *Optics*, §4.6) and
//! optional Beer–Lambert absorption inside. An optional **coating**, a stack of coherent thin
//! layers on the interface, replaces the bare Fresnel amplitudes by the stack's
//! ([`crate::optics::thin_film`], the transfer-matrix method of Macleod, *Thin-Film Optical
//! Filters*, §2.2–2.4) for light from either side; the directions stay those of the bare
//! interface (the layers are thin and parallel, so n sin θ carries through them). The same
//! coatings go on metal mirrors ([`crate::material::Mirror`]); a layer may absorb (n + ik of a
//! metal, or a constant n + ik).
//!
//! ```toml
//! [materials.flint]
//! type = "dielectric"
//! ior = { glass = "N-SF11" }          # or 1.5, { cauchy = [A, B, C] }, { sellmeier = { ... } }
//! absorption = { rgb = [0.0, 0.05, 0.1] }   # optional, per scene unit
//! coating = [{ ior = 1.38, thickness_nm = 99.64 }]   # optional, outside (air) side first
//!
//! [materials.half_silvered]
//! type = "dielectric"
//! ior = { glass = "N-BK7" }
//! coating = [{ metal = "silver", thickness_nm = 20 }]   # absorbing layers: metal or complex_ior
//! ```

use num_complex::{Complex32, Complex64};
use wide::f64x8;

use crate::optics::metals::MetalEntry;
use crate::optics::thin_film::lanes::{lossless_stack_lanes, Lanes, LayerLanes, StackLanes};
use crate::optics::{thin_film_amplitudes, Ior, Layer, ThinFilmAmplitudes};
use crate::polarization::mueller::{JonesDiagonal, Mueller};
use crate::spectrum::{DenseSpectrum, SampledSpectrum, N_LAMBDA};

/// Most layers a coating may have (checked at load; see `scene::limits`).
pub const MAX_COATING_LAYERS: usize = 64;

/// A smooth dielectric.
#[derive(Debug, Clone)]
pub struct Dielectric {
    /// Index of refraction of the inside relative to the outside (vacuum), as a function of λ.
    pub ior: Ior,
    /// Absorption coefficient inside (per scene unit), if any.
    pub absorption: Option<DenseSpectrum>,
    /// The coating's layers from the outside (the side the normal points to) inwards; empty for
    /// a bare interface. At most [`MAX_COATING_LAYERS`].
    pub coating: Vec<CoatingLayer>,
}

/// Every lane's bit.
const ALL_LANES: u32 = (1 << N_LAMBDA) - 1;

/// Coatings of up to this many layers are evaluated in a short array.
const SHORT_COATING: usize = 8;

/// The index of a coating layer: a real n(λ) of any dielectric model, or a complex n + ik.
#[derive(Debug, Clone)]
pub enum LayerIndex {
    /// A non-absorbing layer of real index n(λ) (constant, Cauchy, Sellmeier, table, catalogue).
    Real(Ior),
    /// A metal of the catalogue (`data/metals/`), its measured n + ik(λ).
    Metal(&'static MetalEntry),
    /// A constant complex index n + ik (n > 0, k ≥ 0).
    Complex(Complex32),
}

impl LayerIndex {
    /// The index n + ik (k ≥ 0, the sign users and tables write) at `lambda_nm` (nm).
    #[inline]
    pub fn at(&self, lambda_nm: f32) -> Complex64 {
        match self {
            LayerIndex::Real(ior) => Complex64::new(f64::from(ior.eval(lambda_nm)), 0.0),
            LayerIndex::Metal(metal) => {
                let eta = metal.eta(lambda_nm);
                Complex64::new(f64::from(eta.re), f64::from(eta.im))
            }
            LayerIndex::Complex(eta) => Complex64::new(f64::from(eta.re), f64::from(eta.im)),
        }
    }
}

/// One coherent layer of a coating.
#[derive(Debug, Clone)]
pub struct CoatingLayer {
    /// The layer's index of refraction, real or complex.
    pub index: LayerIndex,
    /// Its physical thickness in nm, in (0, 10⁵].
    pub thickness_nm: f32,
}

impl CoatingLayer {
    /// A non-absorbing layer of index `ior` and thickness `thickness_nm` (nm).
    pub fn dielectric(ior: Ior, thickness_nm: f32) -> Self {
        Self { index: LayerIndex::Real(ior), thickness_nm }
    }
}

/// A deliberate error in a coating's evaluation, so that validation can prove it sees one
/// (`prisma validate --fault coating-phase` / `coating-sp-swapped`). Never in a normal render.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoatingFault {
    /// Every layer's phase thickness β taken as 0 (a layer of zero thickness): the film's
    /// interference is lost and the interface is the bare one.
    PhaseDropped,
    /// The s and p amplitudes of the stack exchanged.
    SpSwapped,
}

/// The amplitudes of `coating` for light of vacuum wavelength `lambda_nm` (nm) arriving at
/// `cos_theta_i` in [0, 1] from an ambient of real index `n_ambient` onto a substrate of index
/// `n_substrate` (n + ik, k ≥ 0), the layers crossed in the order given or, if `reversed`,
/// last first; with an optional injected `fault`. The one evaluation every coated material
/// uses ([`Dielectric`] from either side, [`crate::material::Mirror`] on its metal).
pub fn coating_amplitudes(
    coating: &[CoatingLayer],
    reversed: bool,
    n_ambient: f64,
    n_substrate: Complex64,
    lambda_nm: f32,
    cos_theta_i: f32,
    fault: Option<CoatingFault>,
) -> ThinFilmAmplitudes {
    // The layers at this wavelength, in the order the light crosses them, on the stack: a short
    // array for the common short coatings, the longest accepted otherwise.
    let mut short = [Layer::dielectric(1.0, 0.0); SHORT_COATING];
    let mut long;
    let layers: &mut [Layer] = if coating.len() <= SHORT_COATING {
        &mut short
    } else {
        long = [Layer::dielectric(1.0, 0.0); MAX_COATING_LAYERS];
        &mut long
    };
    let count = coating.len().min(layers.len());
    for (slot, layer) in coating[..count].iter().enumerate() {
        let at = if reversed { count - 1 - slot } else { slot };
        let thickness_nm =
            if fault == Some(CoatingFault::PhaseDropped) { 0.0 } else { f64::from(layer.thickness_nm) };
        layers[at] = Layer { index: layer.index.at(lambda_nm), thickness_nm };
    }
    let stack = thin_film_amplitudes(
        n_ambient,
        &layers[..count],
        n_substrate,
        f64::from(lambda_nm),
        f64::from(cos_theta_i.abs().min(1.0)),
    );
    if fault == Some(CoatingFault::SpSwapped) {
        ThinFilmAmplitudes {
            r_s: stack.r_p,
            r_p: stack.r_s,
            t_s: stack.t_p,
            t_p: stack.t_s,
            reflectance_s: stack.reflectance_p,
            reflectance_p: stack.reflectance_s,
            transmittance_s: stack.transmittance_p,
            transmittance_p: stack.transmittance_s,
        }
    } else {
        stack
    }
}

/// The Mueller matrices of Jones matrices diag(x, y) at every lane ([`JonesDiagonal::new`] lane
/// by lane), x and y given as real and imaginary parts: the elements formed in f64 (vector
/// arithmetic, fused multiply-adds) and narrowed to f32 once (`JonesDiagonal::new` narrows the
/// amplitudes first: the same to f32 rounding).
#[inline(always)]
fn elements(x: &[Lanes; 2], y: &[Lanes; 2]) -> Mueller {
    let (x_re, x_im, y_re, y_im) =
        (f64x8::from(x[0]), f64x8::from(x[1]), f64x8::from(y[0]), f64x8::from(y[1]));
    let power_x = x_re.mul_add(x_re, x_im * x_im);
    let power_y = y_re.mul_add(y_re, y_im * y_im);
    let half = f64x8::HALF;
    let narrow_lanes = |lanes: f64x8| SampledSpectrum { values: lanes.to_array().map(|value| value as f32) };
    Mueller {
        a: narrow_lanes(half * (power_x + power_y)),
        b: narrow_lanes(half * (power_x - power_y)),
        w_re: narrow_lanes(x_re.mul_add(y_re, x_im * y_im)),
        w_im: narrow_lanes(x_im.mul_sub(y_re, x_re * y_im)),
    }
}

/// A complex amplitude narrowed to f32.
#[inline]
pub(crate) fn narrow(z: Complex64) -> Complex32 {
    Complex32::new(z.re as f32, z.im as f32)
}

/// A coated interface at one wavelength and incidence, as Jones elements in the s/p frame of
/// the incidence (x = s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoatedInterface {
    /// Reflection: diag(r_s, r_p) of the stack; a = (R_s + R_p)/2.
    pub reflection: JonesDiagonal,
    /// Transmission as flux: diag(√T_s·e^{i arg t_s}, √T_p·e^{i arg t_p}), so that
    /// a = (T_s + T_p)/2, the power transmittance, as
    /// [`JonesDiagonal::dielectric_transmission`] for a bare interface (whose t_s, t_p are
    /// real and positive: there w = √(T_s·T_p) too). The radiance scaling 1/η_it² across the
    /// interface is not included.
    pub transmission: JonesDiagonal,
}

impl Dielectric {
    /// True when the interface carries a coating.
    #[inline]
    pub fn is_coated(&self) -> bool {
        !self.coating.is_empty()
    }

    /// The coated interface for light of vacuum wavelength `lambda_nm` arriving at
    /// `cos_theta_i` (against the outward normal, negative from the inside, −0 counting as the
    /// outside, as [`crate::optics::fresnel_dielectric`] takes it) when the glass has index
    /// `n_glass` there. From the outside the layers are crossed in the order given (ambient
    /// vacuum, substrate the glass); from the inside in reverse (ambient the glass, substrate
    /// vacuum). Under total internal reflection the transmission is zero. `fault` is `None`
    /// but in validation.
    pub fn coated_interface(
        &self,
        cos_theta_i: f32,
        n_glass: f32,
        lambda_nm: f32,
        fault: Option<CoatingFault>,
    ) -> CoatedInterface {
        let from_inside = cos_theta_i < 0.0;
        let (n_ambient, n_substrate) =
            if from_inside { (f64::from(n_glass), 1.0) } else { (1.0, f64::from(n_glass)) };
        let stack = coating_amplitudes(
            &self.coating,
            from_inside,
            n_ambient,
            n_substrate.into(),
            lambda_nm,
            cos_theta_i,
            fault,
        );
        // An amplitude of modulus √T with the phase of t: t·√(T/|t|²) (1 where t = 0: T is 0
        // there too).
        let flux_amplitude = |t: Complex64, transmittance: f64| {
            let norm_sqr = t.norm_sqr();
            if norm_sqr > 0.0 {
                narrow(t * (transmittance.max(0.0) / norm_sqr).sqrt())
            } else {
                Complex32::new(transmittance.max(0.0).sqrt() as f32, 0.0)
            }
        };
        CoatedInterface {
            reflection: JonesDiagonal::new(narrow(stack.r_s), narrow(stack.r_p)),
            transmission: JonesDiagonal::new(
                flux_amplitude(stack.t_s, stack.transmittance_s),
                flux_amplitude(stack.t_p, stack.transmittance_p),
            ),
        }
    }
}

impl Dielectric {
    /// [`Dielectric::coated_interface`] at every wavelength lane of a vertex at once, as the
    /// reflection and transmission [`Mueller`] matrices whose lane i is that lane's
    /// [`CoatedInterface`] elements: lane i has vacuum wavelength `lambda_nm[i]` and glass index
    /// `n_glass[i]`, all lanes arrive at `cos_theta_i` (signed as there). Lanes outside `live`
    /// (bit i: lane i) are zero (their inputs need only be finite and positive). A coating of
    /// real layers goes through [`lossless_stack_lanes`] (all lanes together, in vector
    /// arithmetic), each layer's index evaluated once per lane (none for a constant one), and
    /// the elements are formed in vector arithmetic too, component by component; a lane it
    /// cannot take, every lane of a coating with an absorbing layer, and every lane under the
    /// s/p-swap fault take [`Dielectric::coated_interface`]. The same values to f32 rounding
    /// (tested).
    pub fn coated_interfaces(
        &self,
        cos_theta_i: f32,
        n_glass: &[f32; N_LAMBDA],
        lambda_nm: &[f32; N_LAMBDA],
        live: u32,
        fault: Option<CoatingFault>,
    ) -> (Mueller, Mueller) {
        let lossless = self.coating.iter().all(|layer| matches!(layer.index, LayerIndex::Real(_)));
        if lossless && fault != Some(CoatingFault::SpSwapped) {
            let stack =
                self.stack_lanes(cos_theta_i, n_glass, lambda_nm, fault == Some(CoatingFault::PhaseDropped));
            // JonesDiagonal::new of the amplitudes narrowed to f32, every lane at once.
            let mut matrices = (elements(&stack.r_s, &stack.r_p), elements(&stack.flux_s, &stack.flux_p));
            if (live & !stack.refused) & ALL_LANES != ALL_LANES {
                // Out of line, so that the common case keeps its matrices in whole vectors.
                self.patch_lanes(&mut matrices, live, stack.refused, cos_theta_i, n_glass, lambda_nm, fault);
            }
            matrices
        } else {
            let zero = SampledSpectrum::splat(0.0);
            let mut matrices = (
                Mueller { a: zero, b: zero, w_re: zero, w_im: zero },
                Mueller { a: zero, b: zero, w_re: zero, w_im: zero },
            );
            self.patch_lanes(&mut matrices, live, ALL_LANES, cos_theta_i, n_glass, lambda_nm, fault);
            matrices
        }
    }

    /// In `matrices` (reflection, transmission): the lanes outside `live` set to zero, and the
    /// live lanes in `exact` evaluated one by one by [`Dielectric::coated_interface`].
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn patch_lanes(
        &self,
        matrices: &mut (Mueller, Mueller),
        live: u32,
        exact: u32,
        cos_theta_i: f32,
        n_glass: &[f32; N_LAMBDA],
        lambda_nm: &[f32; N_LAMBDA],
        fault: Option<CoatingFault>,
    ) {
        for lane in 0..N_LAMBDA {
            let element = if live & (1 << lane) == 0 {
                let zero = JonesDiagonal { a: 0.0, b: 0.0, w_re: 0.0, w_im: 0.0 };
                CoatedInterface { reflection: zero, transmission: zero }
            } else if exact & (1 << lane) != 0 {
                self.coated_interface(cos_theta_i, n_glass[lane], lambda_nm[lane], fault)
            } else {
                continue;
            };
            for (matrix, element) in
                [(&mut matrices.0, element.reflection), (&mut matrices.1, element.transmission)]
            {
                matrix.a.values[lane] = element.a;
                matrix.b.values[lane] = element.b;
                matrix.w_re.values[lane] = element.w_re;
                matrix.w_im.values[lane] = element.w_im;
            }
        }
    }

    /// The coating (all layers real) at every lane, from the side `cos_theta_i` says; with
    /// `phase_dropped` every layer of zero thickness ([`CoatingFault::PhaseDropped`]).
    fn stack_lanes(
        &self,
        cos_theta_i: f32,
        n_glass: &[f32; N_LAMBDA],
        lambda_nm: &[f32; N_LAMBDA],
        phase_dropped: bool,
    ) -> StackLanes {
        let glass: Lanes = n_glass.map(f64::from);
        let wavenumber: Lanes = lambda_nm.map(|nm| std::f64::consts::TAU / f64::from(nm));
        let from_inside = cos_theta_i < 0.0;
        // The layers at these wavelengths, in the order the light crosses them, on the stack: a
        // short array for the common short coatings, the longest accepted otherwise.
        let empty = LayerLanes { index: [1.0; N_LAMBDA], thickness_nm: 0.0 };
        let mut short = [empty; SHORT_COATING];
        let mut long;
        let layers: &mut [LayerLanes] = if self.coating.len() <= SHORT_COATING {
            &mut short
        } else {
            long = [empty; MAX_COATING_LAYERS];
            &mut long
        };
        let count = self.coating.len().min(layers.len());
        for (slot, layer) in self.coating[..count].iter().enumerate() {
            let at = if from_inside { count - 1 - slot } else { slot };
            layers[at] = LayerLanes {
                index: match &layer.index {
                    LayerIndex::Real(Ior::Constant(n)) => [f64::from(*n); N_LAMBDA],
                    index => lambda_nm.map(|nm| index.at(nm).re),
                },
                thickness_nm: if phase_dropped { 0.0 } else { f64::from(layer.thickness_nm) },
            };
        }
        let cos = f64::from(cos_theta_i.abs().min(1.0));
        let vacuum = [1.0; N_LAMBDA];
        let (ambient, substrate) = if from_inside { (&glass, &vacuum) } else { (&vacuum, &glass) };
        lossless_stack_lanes(ambient, &layers[..count], substrate, &wavenumber, cos)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::fresnel_dielectric;

    fn coated(layers: &[(f32, f32)]) -> Dielectric {
        Dielectric {
            ior: Ior::Constant(1.5),
            absorption: None,
            coating: layers.iter().map(|&(n, d)| CoatingLayer::dielectric(Ior::Constant(n), d)).collect(),
        }
    }

    /// A layer of the outside's index (n = 1) is no layer at all: the interface is the bare
    /// one, from both sides, total internal reflection included (Hecht §4.6, §4.7).
    #[test]
    fn a_vacuum_layer_is_the_bare_interface() {
        let glass = coated(&[(1.0, 250.0)]);
        for cos_theta_i in [1.0_f32, 0.8, 0.3, -1.0, -0.9, -0.5, -0.2] {
            let bare = fresnel_dielectric(cos_theta_i, 1.5);
            let interface = glass.coated_interface(cos_theta_i, 1.5, 550.0, None);
            let expected_t = 0.5 * ((1.0 - bare.reflectance_s) + (1.0 - bare.reflectance_p));
            assert!((interface.reflection.a - bare.reflectance).abs() < 1e-5, "cos {cos_theta_i}");
            assert!((interface.transmission.a - expected_t).abs() < 1e-5, "cos {cos_theta_i}");
            if bare.reflectance < 1.0 {
                let w = (1.0 - bare.reflectance_s) * (1.0 - bare.reflectance_p);
                assert!((interface.transmission.w_re - w.sqrt()).abs() < 1e-5, "cos {cos_theta_i}");
            }
        }
    }

    /// A quarter-wave MgF₂ layer (n = 1.38, d = 550/(4·1.38) nm) on n = 1.5 at normal
    /// incidence and 550 nm: R = ((n_g − n²)/(n_g + n²))² = 0.01306... (Hecht §9.7.1), against
    /// 4 % bare; R + T = 1 (no absorption), and the same R from the inside (a lossless stack
    /// reflects the same power from both sides).
    #[test]
    fn quarter_wave_layer_reflects_the_closed_form() {
        let glass = coated(&[(1.38, 550.0 / (4.0 * 1.38))]);
        let expected = ((1.5 - 1.38_f32 * 1.38) / (1.5 + 1.38 * 1.38)).powi(2);
        for cos_theta_i in [1.0_f32, -1.0] {
            let interface = glass.coated_interface(cos_theta_i, 1.5, 550.0, None);
            assert!((interface.reflection.a - expected).abs() < 1e-6, "{}", interface.reflection.a);
            assert!((interface.reflection.a + interface.transmission.a - 1.0).abs() < 1e-6);
        }
    }

    /// All lanes at once equal the lane-by-lane evaluation (the complex or the scalar real
    /// path) to f32 rounding of the elements (2e-6: the amplitudes are narrowed to f32 before
    /// the elements are formed, and R up to 1 carries a few ulps of f32), for a dispersive
    /// glass and a dispersive layer, from both sides (total internal reflection included), with
    /// and without the phase fault, and with dead lanes left zero.
    #[test]
    fn all_lanes_at_once_are_each_lane_alone() {
        let glass = Dielectric {
            ior: Ior::Constant(1.5),
            absorption: None,
            coating: vec![
                CoatingLayer::dielectric(Ior::Constant(1.38), 99.64),
                CoatingLayer::dielectric(Ior::Cauchy { a: 2.0, b_um2: 0.02, c_um4: 0.0 }, 134.0),
                CoatingLayer::dielectric(Ior::Constant(1.62), 84.9),
            ],
        };
        let lambda: [f32; N_LAMBDA] = std::array::from_fn(|i| 365.0 + 58.0 * i as f32);
        let n_glass: [f32; N_LAMBDA] = std::array::from_fn(|i| 1.53 - 0.004 * i as f32);
        let live = 0b1011_1101;
        for fault in [None, Some(CoatingFault::PhaseDropped), Some(CoatingFault::SpSwapped)] {
            for step in 0..=40 {
                let cos_theta_i = -1.0 + step as f32 / 20.0;
                let (reflection, transmission) =
                    glass.coated_interfaces(cos_theta_i, &n_glass, &lambda, live, fault);
                for lane in 0..N_LAMBDA {
                    let expected = if live & (1 << lane) != 0 {
                        glass.coated_interface(cos_theta_i, n_glass[lane], lambda[lane], fault)
                    } else {
                        let zero = JonesDiagonal { a: 0.0, b: 0.0, w_re: 0.0, w_im: 0.0 };
                        CoatedInterface { reflection: zero, transmission: zero }
                    };
                    for (matrix, element) in
                        [(&reflection, expected.reflection), (&transmission, expected.transmission)]
                    {
                        let got = [matrix.a, matrix.b, matrix.w_re, matrix.w_im].map(|c| c.values[lane]);
                        let worst = got
                            .iter()
                            .zip([element.a, element.b, element.w_re, element.w_im])
                            .fold(0.0_f32, |m, (x, y)| m.max((x - y).abs()));
                        assert!(
                            worst < 2e-6,
                            "{fault:?} cos {cos_theta_i} lane {lane}: {got:?} vs {element:?}"
                        );
                    }
                }
            }
        }
    }
}
