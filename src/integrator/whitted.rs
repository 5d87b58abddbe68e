//! Whitted-style recursive ray tracing (Whitted, "An improved illumination model for shaded
//! display", CACM 1980), spectral and with exact Fresnel weights.
//!
//! At each hit:
//! - an emitter seen from its emitting side adds its radiance;
//! - a diffuse surface adds direct light from every light through shadow rays (point lights
//!   `I·cos θ/d²`, quad lights by stratified area sampling); glass and mirrors block shadow rays
//!   (no caustics) and the background does not light anything;
//! - a mirror spawns its reflection, weighted by its reflectance;
//! - a dielectric spawns both the reflected branch (weight R) and the refracted branch (weight
//!   (1 − R)/η², η = n_t/n_i: radiance crossing into a medium of index n_t is multiplied by
//!   (n_t/n_i)² in the direction light flows, so the camera sees (n_i/n_t)² of it), with total
//!   internal reflection giving R = 1. Inside or outside is read from the ray direction and the
//!   outward normal at each hit, never carried along;
//! - escaping rays take the background radiance.
//!
//! The wavelengths of a camera sample travel together until a dispersive refraction, where every
//! live wavelength continues on its own refracted direction (a branch that carries only that lane),
//! so colour fringes are exact rather than noise. Reflection is not dispersive: the reflected
//! branch stays shared, with a per-lane Fresnel weight.
//!
//! Recursion stops after `max_depth` bounces. Branches whose throughput falls below
//! `prune_below` go through Russian roulette (kept with probability throughput/prune_below and
//! reweighted), which leaves the estimate unbiased.

use glam::Vec3;

use super::{Fault, TraceStats};
use crate::geometry::{spawn_origin, Hit, Ray};
use crate::light::Light;
use crate::material::{Dielectric, Diffuse, Material};
use crate::optics::{fresnel_dielectric, reflect, refract, DielectricFresnel};
use crate::sampler::PixelRng;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, N_LAMBDA};

/// Shadow rays stop this fraction short of the light so that an emitter's own quad never
/// occludes it (relative, so it holds at every scene scale).
const SHADOW_RAY_SHORTENING: f32 = 1e-4;

/// The Whitted integrator over one scene.
pub struct Whitted<'a> {
    scene: &'a Scene,
    max_depth: u32,
    prune_below: f32,
    area_light_samples: u32,
    fault: Option<Fault>,
}

impl<'a> Whitted<'a> {
    /// An integrator for `scene` with at most `max_depth` specular bounces, Russian roulette under
    /// branch weight `prune_below` (0: off) and `area_light_samples` samples per quad light.
    pub fn new(scene: &'a Scene, max_depth: u32, prune_below: f32, area_light_samples: u32) -> Self {
        Self { scene, max_depth, prune_below, area_light_samples: area_light_samples.max(1), fault: None }
    }

    /// The same integrator with a deliberate physics error (validation only).
    pub fn with_fault(self, fault: Option<Fault>) -> Self {
        Self { fault, ..self }
    }

    /// Fresnel at one lane: exact, unless a fault is injected.
    #[inline]
    fn fresnel(&self, cos_theta_i: f32, eta: f32) -> DielectricFresnel {
        match self.fault {
            None => fresnel_dielectric(cos_theta_i, eta),
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
                DielectricFresnel { reflectance: schlick, ..exact }
            }
        }
    }

    /// Radiance (W·m⁻²·sr⁻¹·nm⁻¹) arriving at the origin of `ray` along it, at `wavelengths`.
    pub fn radiance(
        &self,
        ray: &Ray,
        wavelengths: &SampledWavelengths,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> SampledSpectrum {
        let throughput = wavelengths.active_mask();
        self.trace(ray, wavelengths, throughput, 0, rng, stats) * throughput
    }

    /// Radiance along `ray` for a branch of weight `throughput` (only lanes with non-zero
    /// throughput are meaningful) at recursion depth `depth`.
    fn trace(
        &self,
        ray: &Ray,
        wavelengths: &SampledWavelengths,
        throughput: SampledSpectrum,
        depth: u32,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> SampledSpectrum {
        stats.rays += 1;
        let Some(hit) = self.scene.geometry.intersect(ray, f32::INFINITY) else {
            return self.scene.background.sample(wavelengths);
        };
        let surface = self.scene.surfaces[hit.prim as usize];
        let mut radiance = SampledSpectrum::zero();
        if let Some(emitter) = surface.emitter {
            if let Light::Quad(light) = &self.scene.lights[emitter as usize] {
                if light.faces(ray.dir) {
                    radiance += light.radiance.sample(wavelengths);
                }
            }
        }
        match &self.scene.materials[surface.material as usize] {
            Material::Black => {}
            Material::Diffuse(diffuse) => {
                radiance += self.direct_light(diffuse, &hit, ray.dir, wavelengths, rng, stats)
            }
            Material::Mirror(mirror) => {
                if depth < self.max_depth {
                    let weight = mirror.reflectance(ray.dir.dot(hit.shading_normal), wavelengths);
                    let dir = reflect(ray.dir, hit.shading_normal).normalize();
                    radiance += self.branch(&hit, dir, weight, throughput, wavelengths, depth, rng, stats);
                }
            }
            Material::Dielectric(dielectric) => {
                radiance +=
                    self.dielectric(dielectric, &hit, ray.dir, throughput, wavelengths, depth, rng, stats);
            }
        }
        radiance
    }

    /// Traces a child branch leaving `hit` along `dir` with local weight `weight`, and returns its
    /// weighted radiance. Applies Russian roulette to low-throughput branches.
    #[allow(clippy::too_many_arguments)] // the recursion state is passed flat to stay allocation-free
    fn branch(
        &self,
        hit: &Hit,
        dir: Vec3,
        weight: SampledSpectrum,
        throughput: SampledSpectrum,
        wavelengths: &SampledWavelengths,
        depth: u32,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> SampledSpectrum {
        let mut child_throughput = throughput * weight;
        if child_throughput.is_zero() {
            return SampledSpectrum::zero();
        }
        let mut weight = weight;
        if self.prune_below > 0.0 {
            let strongest = child_throughput.max_value();
            if strongest < self.prune_below {
                let survive = strongest / self.prune_below;
                if rng.uniform() >= survive {
                    return SampledSpectrum::zero();
                }
                weight = weight / survive;
                child_throughput = child_throughput / survive;
            }
        }
        let child = Ray::new(spawn_origin(hit.point, hit.normal, dir), dir);
        weight * self.trace(&child, wavelengths, child_throughput, depth + 1, rng, stats)
    }

    #[allow(clippy::too_many_arguments)] // the recursion state is passed flat to stay allocation-free
    fn dielectric(
        &self,
        dielectric: &Dielectric,
        hit: &Hit,
        dir: Vec3,
        throughput: SampledSpectrum,
        wavelengths: &SampledWavelengths,
        depth: u32,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> SampledSpectrum {
        // The ray arrives from the inside when it travels along the outward normal: the segment it
        // just crossed was inside the medium and is attenuated by Beer–Lambert.
        let from_inside = dir.dot(hit.normal) > 0.0;
        let transmittance = match (&dielectric.absorption, from_inside) {
            (Some(sigma), true) => (sigma.sample(wavelengths) * -hit.t).exp(),
            _ => SampledSpectrum::splat(1.0),
        };
        if depth >= self.max_depth {
            return SampledSpectrum::zero();
        }
        let throughput = throughput * transmittance;
        let normal = hit.shading_normal;
        let cos_theta_i = -dir.dot(normal);
        let live: [bool; N_LAMBDA] = std::array::from_fn(|i| throughput[i] > 0.0);
        let live_count = live.iter().filter(|&&l| l).count();
        if live_count == 0 {
            return SampledSpectrum::zero();
        }

        // Per-lane Fresnel. A non-dispersive glass (or a branch that already carries one lane)
        // refracts every lane the same way.
        let shared = !dielectric.ior.is_dispersive() || live_count == 1;
        let first_live = live.iter().position(|&l| l).unwrap_or(0);
        let fresnel: [_; N_LAMBDA] = if shared {
            [self.fresnel(cos_theta_i, dielectric.ior.eval(wavelengths.lambda_nm(first_live))); N_LAMBDA]
        } else {
            std::array::from_fn(|i| self.fresnel(cos_theta_i, dielectric.ior.eval(wavelengths.lambda_nm(i))))
        };

        let reflected_dir = reflect(dir, normal).normalize();
        let reflectance = SampledSpectrum { values: fresnel.map(|f| f.reflectance) };
        let mut radiance =
            self.branch(hit, reflected_dir, reflectance, throughput, wavelengths, depth, rng, stats);

        let refract_lane = |lane: usize| {
            let f = &fresnel[lane];
            if f.reflectance >= 1.0 {
                return None;
            }
            let refracted = refract(dir, normal, 1.0 / f.eta_it)?;
            Some((refracted.normalize(), (1.0 - f.reflectance) / (f.eta_it * f.eta_it)))
        };
        if shared {
            if let Some((refracted, weight)) = refract_lane(first_live) {
                let weight = SampledSpectrum::splat(weight);
                radiance += self.branch(hit, refracted, weight, throughput, wavelengths, depth, rng, stats);
            }
        } else {
            for lane in (0..N_LAMBDA).filter(|&i| live[i]) {
                if let Some((refracted, weight)) = refract_lane(lane) {
                    let weight = SampledSpectrum::splat(weight).only_lane(lane);
                    let lane_throughput = throughput.only_lane(lane);
                    let lane_radiance =
                        self.branch(hit, refracted, weight, lane_throughput, wavelengths, depth, rng, stats);
                    radiance += lane_radiance.only_lane(lane);
                }
            }
        }
        radiance * transmittance
    }

    /// Direct light at a diffuse hit seen along `dir`.
    fn direct_light(
        &self,
        diffuse: &Diffuse,
        hit: &Hit,
        dir: Vec3,
        wavelengths: &SampledWavelengths,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> SampledSpectrum {
        // Shade the side the ray arrives on.
        let to_viewer = -dir;
        let (normal, shading_normal) = if hit.normal.dot(to_viewer) >= 0.0 {
            (hit.normal, hit.shading_normal)
        } else {
            (-hit.normal, -hit.shading_normal)
        };
        let mut radiance = SampledSpectrum::zero();
        for light in &self.scene.lights {
            // The unoccluded samples' weights first; the light's spectrum once, if any is lit.
            let weight = match light {
                Light::Point(point) => point.sample(hit.point).map_or(0.0, |sample| {
                    self.shadowed(diffuse, hit, normal, shading_normal, to_viewer, sample, stats)
                }),
                Light::Quad(quad) => {
                    let count = self.area_light_samples;
                    let shift = (rng.uniform(), rng.uniform());
                    (0..count)
                        .filter_map(|index| quad.sample(hit.point, index, count, shift))
                        .map(|sample| {
                            self.shadowed(diffuse, hit, normal, shading_normal, to_viewer, sample, stats)
                        })
                        .sum()
                }
            };
            if weight > 0.0 {
                radiance += light.emitted().sample(wavelengths) * weight;
            }
        }
        if radiance.is_zero() {
            return radiance;
        }
        radiance * (diffuse.albedo.sample(wavelengths) * std::f32::consts::FRAC_1_PI)
    }

    /// One light sample's weight for the light's emitted spectrum (before the albedo/π factor):
    /// its [`crate::light::LightSample::weight`] times cos θ and the diffuse shape factor, zero when
    /// occluded or below the horizon.
    #[allow(clippy::too_many_arguments)] // small hot-path helper; a struct would only rename the same values
    fn shadowed(
        &self,
        diffuse: &Diffuse,
        hit: &Hit,
        normal: Vec3,
        shading_normal: Vec3,
        to_viewer: Vec3,
        sample: crate::light::LightSample,
        stats: &mut TraceStats,
    ) -> f32 {
        let cos_theta = shading_normal.dot(sample.to_light);
        if cos_theta <= 0.0 || normal.dot(sample.to_light) <= 0.0 {
            return 0.0;
        }
        stats.rays += 1;
        let shadow = Ray::new(spawn_origin(hit.point, normal, sample.to_light), sample.to_light);
        if self.scene.geometry.occluded(&shadow, sample.distance * (1.0 - SHADOW_RAY_SHORTENING)) {
            return 0.0;
        }
        sample.weight * cos_theta * diffuse.shape_factor(shading_normal, sample.to_light, to_viewer)
    }
}
