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
//! - a free-standing film (soap film) spawns its reflection and the straight-through branch,
//!   weighted by the film's R and T (`material::film`);
//! - escaping rays take the background radiance.
//!
//! The wavelengths of a camera sample travel together until a dispersive refraction, where every
//! live wavelength continues on its own refracted direction (a branch that carries only that lane),
//! so colour fringes are exact rather than noise. Reflection is not dispersive: the reflected
//! branch stays shared, with a per-lane Fresnel weight.
//!
//! Polarisation (on by default, [`crate::polarization`] has the conventions): every branch
//! returns the Stokes vectors of the light it brings back, in a frame its caller chose. A mirror
//! or a dielectric asks its children for their light in the s frame of its own incidence, applies
//! its Mueller matrices there (reflection and refraction, with the phases of total internal
//! reflection and of metals), and turns the sum into the frame its own caller asked for. Diffuse
//! surfaces depolarise (direct light is unpolarised, or read as radiance through polarising
//! sheets on the shadow ray); lights and the background are unpolarised. Unpolarised renders run
//! the same code on radiance alone ([`super::Beam`]).
//!
//! Polarisers and retarders are sheets light passes straight through: a camera branch continues
//! behind them, and shadow rays cross them, reading the radiance a depolarising receiver gets
//! through the chain ([`crate::polarization::Detector`]).
//!
//! Recursion stops after `max_depth` bounces (a sheet counts as one). Branches whose throughput falls below
//! `prune_below` go through Russian roulette (kept with probability throughput/prune_below and
//! reweighted), which leaves the estimate unbiased.

use glam::Vec3;

use super::visibility::{self, Sheet, SHADOW_RAY_SHORTENING};
use super::{coated_matrices, film_matrices, refraction, Beam, Fault, MonochromaticIndices, TraceStats};
use crate::geometry::{spawn_origin, Hit, Ray};
use crate::light::Light;
use crate::material::{Dielectric, Diffuse, Film, Material};
use crate::optics::{reflect, DielectricFresnel};
use crate::polarization::frame::s_axis;
use crate::polarization::mueller::JonesDiagonal;
use crate::polarization::{Mueller, Rotation};
use crate::sampler::PixelRng;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, N_LAMBDA};

/// The Whitted integrator over one scene.
pub struct Whitted<'a> {
    scene: &'a Scene,
    max_depth: u32,
    prune_below: f32,
    area_light_samples: u32,
    fault: Option<Fault>,
    /// True when some material is a polariser or retarder (shadow rays must look through them).
    has_sheets: bool,
    /// Each glass's index at a monochromatic render's wavelength.
    indices: MonochromaticIndices,
}

impl<'a> Whitted<'a> {
    /// An integrator for `scene` with at most `max_depth` specular bounces, Russian roulette under
    /// branch weight `prune_below` (0: off) and `area_light_samples` samples per quad light.
    pub fn new(scene: &'a Scene, max_depth: u32, prune_below: f32, area_light_samples: u32) -> Self {
        Self {
            scene,
            max_depth,
            prune_below,
            area_light_samples: area_light_samples.max(1),
            fault: None,
            has_sheets: scene.materials.iter().any(Material::is_filter),
            indices: MonochromaticIndices::default(),
        }
    }

    /// The same integrator for a render at the one wavelength `nm` (nm), if monochromatic: its
    /// glass takes the index at that wavelength, evaluated once.
    pub fn with_monochromatic(self, nm: Option<f32>) -> Self {
        Self { indices: MonochromaticIndices::new(&self.scene.materials, nm), ..self }
    }

    /// The same integrator with a deliberate physics error (validation only).
    pub fn with_fault(self, fault: Option<Fault>) -> Self {
        Self { fault, ..self }
    }

    /// Fresnel at one lane: exact, unless a fault is injected.
    #[inline]
    fn fresnel(&self, cos_theta_i: f32, eta: f32) -> DielectricFresnel {
        super::fresnel(self.fault, cos_theta_i, eta)
    }

    /// The change of Stokes frame from x axis `from` to `to` for light travelling along
    /// `forward`; transposed under [`Fault::TransposedRotation`].
    #[inline]
    fn rotation(&self, forward: Vec3, from: Vec3, to: Vec3) -> Rotation {
        super::rotation(self.fault, forward, from, to)
    }

    /// An element's matrix as the render uses it: its phase sign flipped under
    /// [`Fault::FlippedPhase`].
    #[inline]
    fn element(&self, element: JonesDiagonal) -> JonesDiagonal {
        super::element(self.fault, element)
    }

    /// Light (W·m⁻²·sr⁻¹·nm⁻¹) arriving at the origin of `ray` along it, at `wavelengths`. A
    /// polarised beam is expressed in the Stokes frame of x axis `frame_x` (a unit vector
    /// perpendicular to `ray.dir`; see [`crate::camera::Camera::stokes_x`]).
    pub fn radiance<B: Beam>(
        &self,
        ray: &Ray,
        frame_x: Vec3,
        wavelengths: &SampledWavelengths,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> B {
        let throughput = wavelengths.active_mask();
        self.trace::<B>(ray, frame_x, wavelengths, throughput, 0, rng, stats).scaled(throughput)
    }

    /// Light along `ray`, in the frame of x axis `frame_x`, for a branch of weight `throughput`
    /// (only lanes with non-zero throughput are meaningful) at recursion depth `depth`.
    #[allow(clippy::too_many_arguments)] // the recursion state is passed flat to stay allocation-free
    fn trace<B: Beam>(
        &self,
        ray: &Ray,
        frame_x: Vec3,
        wavelengths: &SampledWavelengths,
        throughput: SampledSpectrum,
        depth: u32,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> B {
        stats.rays += 1;
        // The hit is read where `intersect` left it, field by field: moved into a local, it was
        // copied by wide loads over the narrow stores that wrote it, which the processor cannot
        // forward (a stall of about a dozen cycles per ray).
        let found = self.scene.geometry.intersect(ray, f32::INFINITY);
        let Some(hit) = found.as_ref() else {
            return B::unpolarized(self.scene.background.sample(wavelengths));
        };
        let surface = self.scene.surfaces[hit.prim as usize];
        let mut radiance = B::zero();
        if let Some(emitter) = surface.emitter {
            if let Light::Quad(light) = &self.scene.lights[emitter as usize] {
                if light.faces(ray.dir) {
                    radiance += B::unpolarized(light.radiance.sample(wavelengths));
                }
            }
        }
        match &self.scene.materials[surface.material as usize] {
            Material::Black => {}
            Material::Diffuse(diffuse) => {
                radiance +=
                    B::unpolarized(self.direct_light::<B>(diffuse, hit, ray.dir, wavelengths, rng, stats))
            }
            Material::Mirror(_) | Material::Polarizer(_) | Material::Retarder(_)
                if depth >= self.max_depth => {}
            Material::Mirror(mirror) => {
                let cos_theta_i = ray.dir.dot(hit.shading_normal);
                let mueller = super::mirror_mueller::<B>(self.fault, mirror, cos_theta_i, wavelengths);
                let dir = reflect(ray.dir, hit.shading_normal).normalize();
                let s = if B::POLARIZED { s_axis(hit.shading_normal, -ray.dir, frame_x) } else { frame_x };
                let reflected =
                    self.branch::<B>(hit, dir, s, mueller.a, throughput, wavelengths, depth, rng, stats);
                radiance += reflected.through(&mueller).rotated(self.rotation(-ray.dir, s, frame_x));
            }
            Material::Dielectric(dielectric) => {
                radiance += self.dielectric::<B>(
                    (surface.material, dielectric),
                    hit,
                    ray.dir,
                    frame_x,
                    throughput,
                    wavelengths,
                    depth,
                    rng,
                    stats,
                );
            }
            Material::Film(film) => {
                radiance +=
                    self.film::<B>(film, hit, ray.dir, frame_x, throughput, wavelengths, depth, rng, stats)
            }
            Material::Polarizer(polarizer) => {
                radiance += self.sheet::<B>(
                    Sheet::Polarizer(polarizer),
                    hit,
                    ray.dir,
                    frame_x,
                    throughput,
                    wavelengths,
                    depth,
                    rng,
                    stats,
                )
            }
            Material::Retarder(retarder) => {
                radiance += self.sheet::<B>(
                    Sheet::Retarder(retarder),
                    hit,
                    ray.dir,
                    frame_x,
                    throughput,
                    wavelengths,
                    depth,
                    rng,
                    stats,
                )
            }
        }
        radiance
    }

    /// Traces a child branch leaving `hit` along `dir`, asking for its light in the frame of
    /// x axis `frame_x`; `weight` is the unpolarised weight the caller will apply (it decides
    /// Russian roulette). Returns the child's light, divided by its survival probability when
    /// roulette kept it.
    #[allow(clippy::too_many_arguments)] // the recursion state is passed flat to stay allocation-free
    fn branch<B: Beam>(
        &self,
        hit: &Hit,
        dir: Vec3,
        frame_x: Vec3,
        weight: SampledSpectrum,
        throughput: SampledSpectrum,
        wavelengths: &SampledWavelengths,
        depth: u32,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> B {
        let mut child_throughput = throughput * weight;
        if child_throughput.is_zero() {
            return B::zero();
        }
        let mut survival = None;
        if self.prune_below > 0.0 {
            let strongest = child_throughput.max_value();
            if strongest < self.prune_below {
                let survive = strongest / self.prune_below;
                if rng.uniform() >= survive {
                    return B::zero();
                }
                child_throughput = child_throughput / survive;
                survival = Some(survive);
            }
        }
        let child = Ray::new(spawn_origin(hit.point, hit.normal, dir), dir);
        let light = self.trace::<B>(&child, frame_x, wavelengths, child_throughput, depth + 1, rng, stats);
        match survival {
            Some(survive) => light.scaled(SampledSpectrum::splat(1.0 / survive)),
            None => light,
        }
    }

    // Out of line: inlined into `trace`, its two ways of branching (one index for all lanes, or
    // one per lane) made every `trace` call dearer (callgrind: 1.3 M more instructions on the
    // caustic bench's 4-spp render, 1.1 M on `tp6_point`, 2.0 M on `specular_spheres`).
    #[inline(never)]
    #[allow(clippy::too_many_arguments)] // the recursion state is passed flat to stay allocation-free
    fn dielectric<B: Beam>(
        &self,
        (material, dielectric): (u32, &Dielectric),
        hit: &Hit,
        dir: Vec3,
        frame_x: Vec3,
        throughput: SampledSpectrum,
        wavelengths: &SampledWavelengths,
        depth: u32,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> B {
        // The ray arrives from the inside when it travels along the outward normal: the segment it
        // just crossed was inside the medium and is attenuated by Beer–Lambert.
        let from_inside = dir.dot(hit.normal) > 0.0;
        let transmittance = match (&dielectric.absorption, from_inside) {
            (Some(sigma), true) => (sigma.sample(wavelengths) * -hit.t).exp(),
            _ => SampledSpectrum::splat(1.0),
        };
        if depth >= self.max_depth {
            return B::zero();
        }
        let throughput = throughput * transmittance;
        let normal = hit.shading_normal;
        let cos_theta_i = -dir.dot(normal);
        let live: [bool; N_LAMBDA] = std::array::from_fn(|i| throughput[i] > 0.0);
        let live_count = live.iter().filter(|&&l| l).count();
        if live_count == 0 {
            return B::zero();
        }

        // Both branches report in the s frame of this incidence, where the Fresnel matrices are
        // diagonal; the sum is turned into the caller's frame at the end.
        let s = if B::POLARIZED { s_axis(normal, -dir, frame_x) } else { frame_x };
        let reflected_dir = reflect(dir, normal).normalize();
        let fresnel_at = |lane: usize| {
            self.fresnel(cos_theta_i, self.indices.ior(material, dielectric, wavelengths.lambda_nm(lane)))
        };
        let reflection_of =
            |f: &DielectricFresnel| self.element(JonesDiagonal::dielectric_reflection(cos_theta_i, f));
        // A coating replaces both branches' matrices, lane by lane (its phases depend on λ even
        // where the glass's index does not); the directions stay the bare interface's.
        let coated = dielectric.is_coated().then(|| {
            let live_bits = (0..N_LAMBDA).filter(|&i| live[i]).fold(0_u32, |bits, i| bits | 1 << i);
            coated_matrices::<B>(self.fault, dielectric, cos_theta_i, wavelengths, live_bits, |lane| {
                self.indices.ior(material, dielectric, wavelengths.lambda_nm(lane))
            })
        });
        let camera_side = |transmission: Mueller, f: &DielectricFresnel| match &coated {
            Some((_, flux)) => flux.scaled(SampledSpectrum::splat(1.0 / (f.eta_it * f.eta_it))),
            None => transmission,
        };

        // A non-dispersive glass (or a branch that already carries one lane) refracts every lane
        // the same way: one Fresnel evaluation, one refracted branch.
        if !dielectric.ior.is_dispersive() || live_count == 1 {
            let first_live = live.iter().position(|&l| l).unwrap_or(0);
            let f = fresnel_at(first_live);
            let reflection = if let Some((coated_reflection, _)) = coated {
                coated_reflection
            } else if B::POLARIZED {
                Mueller::splat(reflection_of(&f))
            } else {
                Mueller::attenuation(SampledSpectrum::splat(f.reflectance))
            };
            let mut radiance = self
                .branch::<B>(hit, reflected_dir, s, reflection.a, throughput, wavelengths, depth, rng, stats)
                .through(&reflection);
            if let Some((refracted, transmission)) = self.transmission::<B>(dir, normal, &f) {
                let transmission = camera_side(transmission, &f);
                radiance += self
                    .branch::<B>(
                        hit,
                        refracted,
                        s,
                        transmission.a,
                        throughput,
                        wavelengths,
                        depth,
                        rng,
                        stats,
                    )
                    .through(&transmission);
            }
            return radiance.scaled(transmittance).rotated(self.rotation(-dir, s, frame_x));
        }

        let fresnel: [_; N_LAMBDA] = std::array::from_fn(fresnel_at);
        let reflection = if let Some((coated_reflection, _)) = coated {
            coated_reflection
        } else if B::POLARIZED {
            Mueller::from_lanes(&fresnel.map(|f| reflection_of(&f)))
        } else {
            Mueller::attenuation(SampledSpectrum { values: fresnel.map(|f| f.reflectance) })
        };
        let mut radiance = self
            .branch::<B>(hit, reflected_dir, s, reflection.a, throughput, wavelengths, depth, rng, stats)
            .through(&reflection);
        for lane in (0..N_LAMBDA).filter(|&i| live[i]) {
            if let Some((refracted, transmission)) = self.transmission::<B>(dir, normal, &fresnel[lane]) {
                let transmission = camera_side(transmission, &fresnel[lane]);
                let lane_throughput = throughput.only_lane(lane);
                let lane_light = self.branch::<B>(
                    hit,
                    refracted,
                    s,
                    transmission.a.only_lane(lane),
                    lane_throughput,
                    wavelengths,
                    depth,
                    rng,
                    stats,
                );
                radiance += lane_light.only_lane(lane).through(&transmission);
            }
        }
        radiance.scaled(transmittance).rotated(self.rotation(-dir, s, frame_x))
    }

    /// A free-standing film: both branches, the mirrored one through the film's reflection and
    /// the straight one through its transmission (`material::film`), all lanes together.
    #[allow(clippy::too_many_arguments)] // the recursion state is passed flat to stay allocation-free
    fn film<B: Beam>(
        &self,
        film: &Film,
        hit: &Hit,
        dir: Vec3,
        frame_x: Vec3,
        throughput: SampledSpectrum,
        wavelengths: &SampledWavelengths,
        depth: u32,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> B {
        if depth >= self.max_depth {
            return B::zero();
        }
        let live = (0..N_LAMBDA).filter(|&i| throughput[i] > 0.0).fold(0_u32, |bits, i| bits | 1 << i);
        if live == 0 {
            return B::zero();
        }
        let normal = hit.shading_normal;
        let cos_theta_i = -dir.dot(normal);
        let thickness_nm = film.thickness.at(hit.point);
        let (reflection, transmission) =
            film_matrices::<B>(self.fault, film, cos_theta_i, thickness_nm, wavelengths, live);
        let s = if B::POLARIZED { s_axis(normal, -dir, frame_x) } else { frame_x };
        let reflected_dir = reflect(dir, normal).normalize();
        let mut radiance = self
            .branch::<B>(hit, reflected_dir, s, reflection.a, throughput, wavelengths, depth, rng, stats)
            .through(&reflection);
        radiance += self
            .branch::<B>(hit, dir, s, transmission.a, throughput, wavelengths, depth, rng, stats)
            .through(&transmission);
        radiance.rotated(self.rotation(-dir, s, frame_x))
    }

    /// The refracted direction and the Mueller matrix of a refraction with Fresnel terms `f` as
    /// the camera sees it, or `None` under total internal reflection: the flux matrix times 1/η²
    /// (radiance crossing into a denser medium is multiplied by η² in the direction light flows,
    /// so the camera sees 1/η² of it).
    fn transmission<B: Beam>(
        &self,
        dir: Vec3,
        normal: Vec3,
        f: &DielectricFresnel,
    ) -> Option<(Vec3, Mueller)> {
        let (refracted, flux) = refraction::<B>(dir, normal, f)?;
        Some((refracted, flux.scaled(SampledSpectrum::splat(1.0 / (f.eta_it * f.eta_it)))))
    }

    /// A polariser or retarder met by a camera branch: the branch continues straight through,
    /// and the light behind is filtered in the element's own frame.
    #[allow(clippy::too_many_arguments)] // the recursion state is passed flat to stay allocation-free
    fn sheet<B: Beam>(
        &self,
        sheet: Sheet,
        hit: &Hit,
        dir: Vec3,
        frame_x: Vec3,
        throughput: SampledSpectrum,
        wavelengths: &SampledWavelengths,
        depth: u32,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> B {
        let (axis, element, spectrum) = sheet.element(self.fault, hit.normal, -dir, wavelengths);
        let mueller = Mueller::splat(element).scaled(spectrum);
        let axis = if B::POLARIZED { axis } else { frame_x };
        self.branch::<B>(hit, dir, axis, mueller.a, throughput, wavelengths, depth, rng, stats)
            .through(&mueller)
            .rotated(self.rotation(-dir, axis, frame_x))
    }

    /// Direct light at a diffuse hit seen along `dir`.
    fn direct_light<B: Beam>(
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
            if self.has_sheets {
                // Each sample's sheets filter it by their own spectra.
                let mut filtered = SampledSpectrum::zero();
                let mut add = |sample: crate::light::LightSample| {
                    if let Some((weight, spectrum)) = self.through_sheets::<B>(
                        diffuse,
                        hit,
                        normal,
                        shading_normal,
                        to_viewer,
                        sample,
                        wavelengths,
                        stats,
                    ) {
                        filtered += spectrum * weight;
                    }
                };
                match light {
                    Light::Point(point) => point.sample(hit.point).into_iter().for_each(&mut add),
                    Light::Spot(spot) => spot.sample(hit.point).into_iter().for_each(&mut add),
                    Light::Beam(beam) => beam.sample(hit.point).into_iter().for_each(&mut add),
                    Light::Quad(quad) => {
                        let count = self.area_light_samples;
                        let shift = (rng.uniform(), rng.uniform());
                        (0..count)
                            .filter_map(|index| quad.sample(hit.point, index, count, shift))
                            .for_each(&mut add);
                    }
                }
                if !filtered.is_zero() {
                    radiance += light.emitted().sample(wavelengths) * filtered;
                }
                continue;
            }
            // The unoccluded samples' weights first; the light's spectrum once, if any is lit.
            let shadowed = |sample: crate::light::LightSample| {
                self.shadowed(diffuse, hit, normal, shading_normal, to_viewer, sample, stats)
            };
            let weight = match light {
                Light::Point(point) => point.sample(hit.point).map_or(0.0, shadowed),
                Light::Spot(spot) => spot.sample(hit.point).map_or(0.0, shadowed),
                Light::Beam(beam) => beam.sample(hit.point).map_or(0.0, shadowed),
                Light::Quad(quad) => {
                    let count = self.area_light_samples;
                    let shift = (rng.uniform(), rng.uniform());
                    (0..count)
                        .filter_map(|index| quad.sample(hit.point, index, count, shift))
                        .map(shadowed)
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

    /// As [`Self::shadowed`] in a scene with polarising sheets: the shadow ray crosses sheets,
    /// and the diffuse receiver reads the radiance of the unpolarised light after them. Returns
    /// the geometric weight (with the sheets' polarisation) and the product of their
    /// transmittance spectra, or `None` when blocked.
    #[allow(clippy::too_many_arguments)] // small helper; a struct would only rename the same values
    fn through_sheets<B: Beam>(
        &self,
        diffuse: &Diffuse,
        hit: &Hit,
        normal: Vec3,
        shading_normal: Vec3,
        to_viewer: Vec3,
        sample: crate::light::LightSample,
        wavelengths: &SampledWavelengths,
        stats: &mut TraceStats,
    ) -> Option<(f32, SampledSpectrum)> {
        let cos_theta = shading_normal.dot(sample.to_light);
        if cos_theta <= 0.0 || normal.dot(sample.to_light) <= 0.0 {
            return None;
        }
        let origin = spawn_origin(hit.point, normal, sample.to_light);
        let (response, spectrum) = visibility::through_sheets::<B>(
            self.scene,
            self.fault,
            origin,
            sample.to_light,
            sample.distance,
            wavelengths,
            stats,
        )?;
        let weight = response
            * sample.weight
            * cos_theta
            * diffuse.shape_factor(shading_normal, sample.to_light, to_viewer);
        (weight > 0.0).then_some((weight, spectrum))
    }
}
