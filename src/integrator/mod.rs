//! Integrators: estimators of the light reaching the camera. Whitted's recursion (`whitted`)
//! follows camera rays; the light tracer (`light_tracer`) follows light from the lights through
//! mirrors and glass to the diffuse surfaces the camera sees: the caustics Whitted cannot find.
//! Each counts its own path classes, so their images add up (see `light_tracer`).

pub mod beam;
pub mod emission;
pub mod guide;
pub mod light_tracer;
pub mod path;
pub mod response;
mod visibility;
pub mod whitted;

use glam::Vec3;

pub use beam::Beam;
pub use light_tracer::LightTracer;
pub use path::PathTracer;
pub use response::PathBeam;
pub use whitted::Whitted;

use crate::material::{Dielectric, Film, Material};
use crate::optics::{fresnel_dielectric, refract, DielectricFresnel};
use crate::polarization::mueller::JonesDiagonal;
use crate::polarization::{Mueller, Rotation};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, N_LAMBDA};

/// The camera's estimator of a render ([`crate::scene::IntegratorKind`]).
pub enum CameraIntegrator<'a> {
    /// Whitted's recursion.
    Whitted(Whitted<'a>),
    /// The path tracer.
    Path(PathTracer<'a>),
}

impl CameraIntegrator<'_> {
    /// Light arriving at the origin of `ray` along it, in the Stokes frame of x axis `frame_x`
    /// ([`Whitted::radiance`], [`PathTracer::radiance`]).
    #[inline]
    pub fn radiance<B: PathBeam>(
        &self,
        ray: &crate::geometry::Ray,
        frame_x: Vec3,
        wavelengths: &SampledWavelengths,
        rng: &mut crate::sampler::PixelRng,
        stats: &mut TraceStats,
    ) -> B {
        match self {
            CameraIntegrator::Whitted(whitted) => whitted.radiance(ray, frame_x, wavelengths, rng, stats),
            CameraIntegrator::Path(path) => path.radiance(ray, frame_x, wavelengths, rng, stats),
        }
    }
}

/// Counters an integrator accumulates while tracing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TraceStats {
    /// Rays cast: camera, specular branches and shadow rays (light paths and their connections
    /// to the camera in the light tracer).
    pub rays: u64,
}

/// A deliberate error injected into the physics, so that validation can prove it would catch a
/// wrong renderer (`prisma validate --fault ...`). Never used by a normal render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fault {
    /// Schlick's approximation R ≈ R₀ + (1 − R₀)(1 − cos θ)⁵ instead of the exact Fresnel
    /// equations (and no total internal reflection beyond what Snell's law forces).
    SchlickFresnel,
    /// Every dielectric's index of refraction multiplied by this factor (e.g. 1.01).
    IorScale(f32),
    /// Every change of Stokes frame turned the wrong way: a rotation matrix built transposed
    /// (glam's column-major constructors fed a row-major literal).
    TransposedRotation,
    /// The sign of every phase term flipped (the wrong time convention, or `atan2(x, y)` for
    /// `atan2(y, x)`): circular polarisation of the wrong handedness.
    FlippedPhase,
    /// Polarisation dropped: an unpolarised render where a polarised one was asked for, each
    /// interface's reflectance averaged over s and p.
    Unpolarized,
    /// The light tracer scales light paths at a refraction as camera paths are scaled, by
    /// (n_i/n_t)²: radiance transport where flux (importance) transport is right. Entering and
    /// leaving the same glass cancels it; a light inside glass shows it.
    LightPathRadianceScaling,
    /// The light tracer drops the cosine at the diffuse receiver (the cosine between its normal
    /// and the direction to the camera) when it connects a light path to the camera.
    NoReceiverCosine,
    /// The path tracer's multiple-importance weights do not add up to one: next-event
    /// estimation and a BSDF-sampled hit of the same light both count in full (weight 1 each),
    /// so direct light from area lights and the background is counted twice.
    MisWeightsUnnormalized,
    /// The path tracer's diffuse bounces drop the cosine: each sampled direction's weight is
    /// ρ/cos θ where f·cos θ/pdf = ρ is right.
    NoDiffuseCosine,
    /// The background does not light in the path tracer: it is seen by camera rays (as
    /// Whitted sees it) but neither next-event estimation nor a bounce gathers it.
    DarkBackground,
    /// The path tracer also counts the paths the light tracer counts (L S⁺ D … D E, from the
    /// lights the light tracer emits from): those paths are counted twice.
    CausticsCountedTwice,
    /// In full transport the light tracer stops at its first diffuse vertex, as beside Whitted,
    /// while the path tracer still leaves the light tracer's paths to it: the paths L S⁺ D X⁺ D E
    /// (light through glass, then on from a diffuse surface) are counted by nobody.
    CausticsCountedNever,
    /// Every coating layer's phase thickness dropped (β = 0): a film without interference.
    CoatingPhaseDropped,
    /// The s and p amplitudes of every coating's stack exchanged.
    CoatingSpSwapped,
    /// The light tracer shades smooth-shaded meshes as the camera side does, without Veach's
    /// correction for the adjoint of a shading normal (the light side's flux off by
    /// |ω_i·N_s||ω_o·N_g|/(|ω_i·N_g||ω_o·N_s|) at every vertex where the normals differ).
    NoShadingNormalAdjoint,
    /// A lens-system camera's lanes share the hero wavelength's scene path, each weighted by
    /// the hero's density alone instead of the mixture over the lanes
    /// (`crate::camera::LensCamera::sample_shared_path`): light whose preimage at a lane's
    /// wavelength falls in the pixel but at the hero's outside it is never counted, so the
    /// image darkens where the lens disperses (lateral and longitudinal colour).
    LensHeroPdfOnly,
}

/// The coatings' share of `fault` (`material::dielectric::CoatingFault`).
#[inline]
pub(crate) fn coating_fault(fault: Option<Fault>) -> Option<crate::material::dielectric::CoatingFault> {
    use crate::material::dielectric::CoatingFault;
    match fault {
        Some(Fault::CoatingPhaseDropped) => Some(CoatingFault::PhaseDropped),
        Some(Fault::CoatingSpSwapped) => Some(CoatingFault::SpSwapped),
        _ => None,
    }
}

/// Each dielectric's index of refraction at the one wavelength of a monochromatic render, by
/// material index: evaluated once, where a glass hit would evaluate its dispersion law again
/// (a Sellmeier law costs three divisions and a square root). Empty for spectral renders.
#[derive(Debug, Clone, Default)]
pub(crate) struct MonochromaticIndices(Vec<f32>);

impl MonochromaticIndices {
    /// The indices of `materials` at `monochromatic_nm` (nm), if the render is monochromatic.
    pub(crate) fn new(materials: &[Material], monochromatic_nm: Option<f32>) -> Self {
        let Some(nm) = monochromatic_nm else { return Self::default() };
        let index = |material: &Material| match material {
            Material::Dielectric(dielectric) => dielectric.ior.eval(nm),
            _ => 0.0,
        };
        Self(materials.iter().map(index).collect())
    }

    /// The index of `dielectric`, material number `material`, at the wavelength `lambda_nm` of a
    /// live lane: the stored value in a monochromatic render (whose one wavelength that is).
    #[inline]
    pub(crate) fn ior(&self, material: u32, dielectric: &Dielectric, lambda_nm: f32) -> f32 {
        match self.0.get(material as usize) {
            Some(&n) => n,
            None => dielectric.ior.eval(lambda_nm),
        }
    }
}

/// Fresnel at one lane, exact unless `fault` replaces it (Schlick, a scaled index).
#[inline]
pub(crate) fn fresnel(fault: Option<Fault>, cos_theta_i: f32, eta: f32) -> DielectricFresnel {
    match fault {
        Some(Fault::IorScale(scale)) => fresnel_dielectric(cos_theta_i, eta * scale),
        Some(Fault::SchlickFresnel) => {
            let exact = fresnel_dielectric(cos_theta_i, eta);
            if exact.reflectance >= 1.0 {
                return exact;
            }
            let r0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
            // Schlick uses the angle on the denser side.
            let cos = if exact.eta_it > 1.0 { cos_theta_i.abs() } else { exact.cos_theta_t.abs() };
            let schlick = r0 + (1.0 - r0) * (1.0 - cos).powi(5);
            // The polarised render sees the same approximation: Schlick's reflectance for
            // both polarisations, the amplitudes keeping their signs.
            let amplitude = schlick.sqrt();
            DielectricFresnel {
                reflectance: schlick,
                reflectance_s: schlick,
                reflectance_p: schlick,
                r_s: amplitude.copysign(exact.r_s),
                r_p: amplitude.copysign(exact.r_p),
                ..exact
            }
        }
        _ => fresnel_dielectric(cos_theta_i, eta),
    }
}

/// The change of Stokes frame from x axis `from` to `to` for light travelling along `forward`;
/// transposed under [`Fault::TransposedRotation`].
#[inline]
pub(crate) fn rotation(fault: Option<Fault>, forward: Vec3, from: Vec3, to: Vec3) -> Rotation {
    let rotation = Rotation::between(forward, from, to);
    if fault == Some(Fault::TransposedRotation) {
        rotation.transposed()
    } else {
        rotation
    }
}

/// A mirror's Mueller matrices at every lane for an incidence at `cos_theta_i` (signed, as
/// [`crate::material::Mirror::mueller`] takes it): the polarised ones, their phase flipped under
/// [`Fault::FlippedPhase`], when `B` carries Stokes vectors; its s/p-averaged reflectance as an
/// attenuation when not. The same for Whitted, the light tracer and the path tracer.
#[inline]
pub(crate) fn mirror_mueller<B: Beam>(
    fault: Option<Fault>,
    mirror: &crate::material::Mirror,
    cos_theta_i: f32,
    wavelengths: &SampledWavelengths,
) -> Mueller {
    if B::POLARIZED {
        let mueller = mirror.mueller(cos_theta_i, wavelengths, coating_fault(fault));
        if fault == Some(Fault::FlippedPhase) {
            mueller.phase_flipped()
        } else {
            mueller
        }
    } else {
        Mueller::attenuation(mirror.reflectance(cos_theta_i, wavelengths, coating_fault(fault)))
    }
}

/// An element's matrix as the render uses it: its phase sign flipped under
/// [`Fault::FlippedPhase`].
#[inline]
pub(crate) fn element(fault: Option<Fault>, element: JonesDiagonal) -> JonesDiagonal {
    if fault == Some(Fault::FlippedPhase) {
        element.phase_flipped()
    } else {
        element
    }
}

/// A coated dielectric's reflection and transmitted-flux matrices at every lane, in the s/p
/// frame of an incidence at `cos_theta_i` (signed as Fresnel's): polarised when `B` carries
/// Stokes vectors, the s/p averages (R_s + R_p)/2 and (T_s + T_p)/2 when not. Lanes outside
/// `live` (bit i: lane i) are left zero. The glass's index at lane i is `glass_ior(i)`; the
/// stack replaces the bare Fresnel amplitudes (`material::dielectric`). The faults that change
/// an index or flip a phase apply to the stack too; Schlick's approximation has no stack form.
/// The transmission excludes the camera side's 1/η², as [`refraction`] does.
pub(crate) fn coated_matrices<B: Beam>(
    fault: Option<Fault>,
    dielectric: &Dielectric,
    cos_theta_i: f32,
    wavelengths: &SampledWavelengths,
    live: u32,
    glass_ior: impl Fn(usize) -> f32,
) -> (Mueller, Mueller) {
    // All lanes at once (`Dielectric::coated_interfaces`); dead lanes get a placeholder index.
    let n_glass: [f32; N_LAMBDA] = std::array::from_fn(|lane| {
        if live & (1 << lane) == 0 {
            return 1.5;
        }
        match fault {
            Some(Fault::IorScale(scale)) => glass_ior(lane) * scale,
            _ => glass_ior(lane),
        }
    });
    let lambda_nm: [f32; N_LAMBDA] = std::array::from_fn(|lane| wavelengths.lambda_nm(lane));
    let (reflection, transmission) =
        dielectric.coated_interfaces(cos_theta_i, &n_glass, &lambda_nm, live, coating_fault(fault));
    let element =
        |matrix: Mueller| if fault == Some(Fault::FlippedPhase) { matrix.phase_flipped() } else { matrix };
    if B::POLARIZED {
        (element(reflection), element(transmission))
    } else {
        (Mueller::attenuation(reflection.a), Mueller::attenuation(transmission.a))
    }
}

/// The reflection and transmission matrices of per-lane Jones elements: Mueller matrices when
/// `B` carries Stokes vectors, the s/p-averaged attenuations (each element's `a`) when not.
fn lane_matrices<B: Beam>(
    reflection: &[JonesDiagonal; N_LAMBDA],
    transmission: &[JonesDiagonal; N_LAMBDA],
) -> (Mueller, Mueller) {
    if B::POLARIZED {
        (Mueller::from_lanes(reflection), Mueller::from_lanes(transmission))
    } else {
        let average = |elements: &[JonesDiagonal; N_LAMBDA]| {
            Mueller::attenuation(SampledSpectrum { values: elements.map(|e| e.a) })
        };
        (average(reflection), average(transmission))
    }
}

/// A free-standing film's reflection and transmission matrices at every lane, in the s/p frame
/// of an incidence at `cos_theta_i` (either sign) on its point of thickness `thickness_nm`:
/// polarised when `B` carries Stokes vectors, the s/p averages (R_s + R_p)/2 and
/// (T_s + T_p)/2 when not. Lanes outside `live` (bit i: lane i) are left zero. Air on both
/// sides: no radiance scaling, camera and light paths alike. The faults that scale an index or
/// flip a phase apply to the film too.
pub(crate) fn film_matrices<B: Beam>(
    fault: Option<Fault>,
    film: &Film,
    cos_theta_i: f32,
    thickness_nm: f32,
    wavelengths: &SampledWavelengths,
    live: u32,
) -> (Mueller, Mueller) {
    let zero = JonesDiagonal { a: 0.0, b: 0.0, w_re: 0.0, w_im: 0.0 };
    let mut reflection = [zero; N_LAMBDA];
    let mut transmission = [zero; N_LAMBDA];
    for lane in (0..N_LAMBDA).filter(|&i| live & (1 << i) != 0) {
        let lambda_nm = wavelengths.lambda_nm(lane);
        let n_film = match fault {
            Some(Fault::IorScale(scale)) => film.ior.eval(lambda_nm) * scale,
            _ => film.ior.eval(lambda_nm),
        };
        let interface = Film::interface(cos_theta_i, n_film, thickness_nm, lambda_nm);
        reflection[lane] = element(fault, interface.reflection);
        transmission[lane] = element(fault, interface.transmission);
    }
    lane_matrices::<B>(&reflection, &transmission)
}

/// A refraction with Fresnel terms `f` of light travelling along `dir` onto a surface with
/// unit normal `normal`: the refracted direction and the matrix of the flux it carries (the
/// transmittance: polarised when `B` carries Stokes vectors, averaged over s and p when not),
/// or `None` under total internal reflection. Radiance seen through the interface is that flux
/// times 1/η² (Whitted's side); light paths carry the flux as it is.
#[inline(always)]
pub(crate) fn refraction<B: Beam>(dir: Vec3, normal: Vec3, f: &DielectricFresnel) -> Option<(Vec3, Mueller)> {
    if f.reflectance >= 1.0 {
        return None;
    }
    let refracted = refract(dir, normal, 1.0 / f.eta_it)?;
    let element = if B::POLARIZED {
        JonesDiagonal::dielectric_transmission(f)
    } else {
        JonesDiagonal { a: 1.0 - f.reflectance, b: 0.0, w_re: 0.0, w_im: 0.0 }
    };
    Some((refracted.normalize(), Mueller::splat(element)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::catalogue::glass_ior;

    /// Schott's N-BK7 at the helium d line (587.56 nm) and the hydrogen F line (486.13 nm):
    /// n_d = 1.51680, n_F = 1.52238 (Schott data sheet).
    #[test]
    fn monochromatic_indices_hold_each_glass_at_the_render_wavelength() {
        let bk7 = Dielectric {
            ior: glass_ior("N-BK7").expect("N-BK7 is catalogued"),
            absorption: None,
            coating: Vec::new(),
        };
        let materials = [Material::Black, Material::Dielectric(bk7.clone())];
        let at_d = MonochromaticIndices::new(&materials, Some(587.56));
        // The stored index answers whatever lane wavelength is asked: a monochromatic render
        // has only its own.
        assert!((at_d.ior(1, &bk7, 587.56) - 1.51680).abs() < 2e-5);
        assert_eq!(at_d.ior(1, &bk7, 486.13), at_d.ior(1, &bk7, 587.56));
        // A spectral render evaluates the law at each lane.
        let spectral = MonochromaticIndices::new(&materials, None);
        assert!((spectral.ior(1, &bk7, 486.13) - 1.52238).abs() < 2e-5);
        assert!((spectral.ior(1, &bk7, 587.56) - 1.51680).abs() < 2e-5);
    }
}
