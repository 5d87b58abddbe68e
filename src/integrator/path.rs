//! Full light transport from the camera: unidirectional path tracing (Kajiya 1986) with
//! next-event estimation at diffuse vertices, combined with BSDF sampling by multiple importance
//! sampling (Veach & Guibas 1995, the power heuristic), the background as a light, and Russian
//! roulette; spectral, dispersive and polarised as Whitted's recursion is. Mitsuba's `path` and
//! pbrt's `path` integrators are its peers.
//!
//! # Which paths it counts
//! In Heckbert's notation (L a light or the background, S a mirror or glass interaction, D a
//! diffuse one, E the eye; polarising sheets are crossed by every ray and are no vertex), the
//! render's estimators share path space as follows (the one table; [`crate::render`] adds the
//! images, [`super::light_tracer`] states its side):
//!
//! | path class                         | counted by                                            |
//! |------------------------------------|-------------------------------------------------------|
//! | L E, L S⁺ E (no diffuse vertex)     | camera paths: emitter or background hit, weight 1     |
//! | L D X\* E (light next to a D)       | camera paths: next-event estimation + BSDF hits, MIS   |
//! | L S⁺ D X\* D E, L a light           | the light tracer, when it runs (`caustics`)            |
//! | L S⁺ D X\* D E, L the background    | camera paths: BSDF hits, weight 1                     |
//! | L S⁺ D X\* S⁺ E, L an area light    | camera paths: BSDF hits, weight 1                     |
//! | L S⁺ D X\* S⁺ E, L a delta light    | **nobody**: no camera path reaches a point, spot or    |
//! |                                    | beam light through S, no light path reaches a pinhole |
//!
//! (X is S or D; a free-standing film is S.) The classes are disjoint and, but for the last, cover every path; without
//! the light tracer (`caustics = false`) the camera paths count the L S⁺ D X\* D E paths of
//! area lights too (by BSDF hits), and those of delta lights are missing.
//!
//! # What a path carries
//! The camera's [`Response`]: the product of the Mueller matrices met so far, from the camera
//! outward (`P ← P·R·M`), so that light arriving at the current vertex is recorded as `P·S`.
//! A diffuse vertex depolarises (the first column kept). Unpolarised renders carry `P₀₀` alone,
//! and so do polarised renders of scenes whose materials are all diffuse or black (their light
//! is S0 alone).
//! A refraction into a denser medium multiplies radiance by (n_t/n_i)² in the direction light
//! flows, so the camera side applies 1/η² as Whitted does.
//!
//! # Glass
//! At a mirror the path reflects. At glass it continues along one branch, reflected or
//! refracted, chosen with probability proportional to each branch's radiance response summed
//! over the live lanes (the Fresnel reflectance or transmittance, exact s/p or a coating's
//! stack) and divided by it. At a dispersive refraction of a path still carrying several
//! wavelengths, every live wavelength continues on its own direction, as a path of its own
//! carrying that lane alone; none is dropped. A split path cannot split again, so a camera
//! sample makes at most [`N_LAMBDA`] paths.
//!
//! # Diffuse vertices
//! Next-event estimation toward every light (points, spots and beams once; quad lights by
//! `area_light_samples` stratified points, as Whitted samples them), then one direction drawn
//! with the cosine density ([`Diffuse::sample`]) whose weight is f·cos θ/pdf = ρ·(Oren–Nayar's
//! factor). Where a drawn direction meets a quad light, the hit is weighted by the power
//! heuristic against the light sampling that could have made it, with the multi-sample rule
//! for quads (`n` light samples against one BSDF sample).
//!
//! **The background is gathered by the drawn direction alone** (weight 1): its radiance is the
//! same along every direction, so at a Lambertian vertex the cosine density is already
//! proportional to everything in the integrand but visibility (at an Oren–Nayar one, to all but
//! its bounded factor), and a next-event direction toward it (uniform over the sphere, as
//! Mitsuba's `constant` emitter samples) adds a shadow ray and no information. On
//! the glass-and-mirror room lit by a quad and the sky, dropping it left the error per sample
//! unchanged (relMSE × spp 0.266 against 0.267 at 1024 spp) at 5.0 rays per sample instead of
//! 6.0 and 1.28× less CPU (validation/bench/RESULTS.md). Until then a probe of the scene
//! dropped it only where the background was hidden from every diffuse surface.
//!
//! Each diffuse vertex takes one padded group of four sampler dimensions
//! ([`PixelRng::uniform_4d`]): the drawn direction on the first two, stratified jointly in 2D
//! over the pixel's samples, and the first quad light's point on the other two. (Taken one at a
//! time, the pairs straddled groups and were stratified per dimension only: relMSE × spp on TP6
//! with its quad light stayed at 0.052 from 16 to 1024 spp; validation/bench/RESULTS.md.)
//! Only the first [`SOBOL_GROUPS`] groups of a camera sample (the pixel's, the first two
//! diffuse vertices') come from the scrambled Sobol sequence; deeper vertices take hashed
//! independent numbers, cheaper to make and, that deep, about as good
//! ([`PixelRng::sobol_groups`]).
//!
//! # Depth and roulette
//! `max_depth` bounces of any kind (diffuse, mirror, glass; a sheet counts as one, as in
//! Whitted). From the third bounce on, a path whose strongest lane's response r is below 1/4
//! survives with probability 4r, and is divided by it: unbiased ([`ROULETTE_SCALE`]). After a
//! diffuse vertex the number drawn against it is that vertex's quad-point dimension, which
//! nothing later on the path depends on (`PathTracer::survives`).

use glam::Vec3;

use super::response::{PathBeam, Response};
use super::visibility::{self, Sheet};
use super::{
    coated_matrices, element, film_matrices, fresnel, refraction, rotation, Fault, MonochromaticIndices,
    TraceStats,
};
use crate::geometry::{spawn_origin, Hit, Ray};
use crate::light::{Light, LightSample};
use crate::material::{Dielectric, Diffuse, Film, Material};
use crate::optics::{reflect, DielectricFresnel};
use crate::polarization::frame::{any_perpendicular, s_axis};
use crate::polarization::mueller::JonesDiagonal;
use crate::polarization::Mueller;
use crate::sampler::PixelRng;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, N_LAMBDA};

/// Bounces after which Russian roulette may end a path.
const ROULETTE_AFTER_BOUNCES: u32 = 3;
/// A path past [`ROULETTE_AFTER_BOUNCES`] survives roulette with probability this times its
/// strongest lane's response (at most 1): only paths carrying less than a quarter of what the
/// camera gives them are thinned. Measured on TP6 with its quad light (150×100, 64 spp, relMSE ×
/// render time against the converged reference, validation/bench/RESULTS.md): 1 (survival equal to
/// the response, as pbrt's rule) 16.6, 2 14.0, 3 13.4, **4 13.0**, 8 13.5; starting after 5
/// bounces with 1 15.9 (Mitsuba's rule), with 2 15.4.
const ROULETTE_SCALE: f32 = 4.0;

/// Padded sampler groups per camera sample drawn from the pixel's scrambled Sobol sequence
/// (the position and wavelength's, then one per diffuse vertex: the first two vertices'); later
/// groups are hashed independent numbers ([`PixelRng::sobol_groups`]). Measured on TP6 with its
/// quad light (150×100, six seeds, `--unpolarized`): from the third diffuse vertex on, relMSE at
/// 32 spp +1.4 % and render CPU −6 % (about 5 % less time to equal error); from the second, +4 %
/// and −9 %; validation/bench/RESULTS.md.
const SOBOL_GROUPS: u32 = 3;

/// The path tracer over one scene.
pub struct PathTracer<'a> {
    scene: &'a Scene,
    max_depth: u32,
    area_light_samples: u32,
    fault: Option<Fault>,
    /// True when the light tracer counts the L S⁺ D X* D E paths of the scene's lights (see the
    /// module's table): camera paths then leave them out.
    light_tracer_counts_caustics: bool,
    /// True when the background radiance is non-zero somewhere: it is then a light.
    background_lights: bool,
    /// True when some material is a polariser or retarder (shadow rays look through them).
    has_sheets: bool,
    /// True when every material is diffuse or black: no vertex can polarise (the lights and the
    /// background are unpolarised, a diffuse vertex depolarises), so a polarised render's
    /// response keeps columns 1–3 zero and its light is S0 alone: traced as unpolarised.
    never_polarized: bool,
    /// Per light (same index as `scene.lights`), the shape it is when it is a quad light, else
    /// `u32::MAX`: its own shadow rays need not test it ([`crate::geometry::Geometry::occluded_except`]).
    light_shapes: Vec<u32>,
    /// Each glass's index at a monochromatic render's wavelength.
    indices: MonochromaticIndices,
    /// Validation only: count the quad lights' L S⁺ D X* S⁺ E paths and nothing else
    /// ([`Self::counting_only_specular_eye_caustics`]).
    only_specular_eye_caustics: bool,
}

/// What the previous vertex of a path was, for weighting what the path meets next.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Previous {
    /// The camera: the path is a camera ray.
    Camera,
    /// A mirror or glass interaction.
    Specular,
    /// A diffuse vertex at `from` whose drawn direction had this density (sr⁻¹).
    Diffuse { pdf: f32, from: Vec3 },
}

/// One path on its way: where it goes, what the camera makes of the light it finds, and the
/// classes of its vertices so far.
#[derive(Clone, Copy)]
struct PathState<R> {
    ray: Ray,
    /// The x axis of the Stokes frame the response's columns are written in.
    frame_x: Vec3,
    response: R,
    /// Lanes still carried (bit i: lane i).
    live: u32,
    /// Bounces so far.
    depth: u32,
    previous: Previous,
    /// True once the path has a diffuse vertex.
    diffuse_seen: bool,
    /// Whether the vertex next to the eye is diffuse, once the path has one.
    eye_vertex_diffuse: Option<bool>,
}

impl<'a> PathTracer<'a> {
    /// A path tracer for `scene` with at most `max_depth` bounces and `area_light_samples`
    /// samples per quad light at each diffuse vertex; `light_tracer_counts_caustics` says
    /// whether the light tracer runs beside it (and counts its classes).
    pub fn new(
        scene: &'a Scene,
        max_depth: u32,
        area_light_samples: u32,
        light_tracer_counts_caustics: bool,
    ) -> Self {
        let background_lights = scene.background.values().iter().any(|&v| v > 0.0);
        Self {
            scene,
            max_depth,
            area_light_samples: area_light_samples.max(1),
            fault: None,
            light_tracer_counts_caustics,
            background_lights,
            has_sheets: scene.materials.iter().any(Material::is_filter),
            never_polarized: scene
                .materials
                .iter()
                .all(|m| matches!(m, Material::Diffuse(_) | Material::Black)),
            light_shapes: (0..scene.lights.len())
                .map(|light| {
                    let is_quad = matches!(scene.lights[light], Light::Quad(_));
                    let shape = scene.surfaces.iter().position(|s| s.emitter == Some(light as u32));
                    shape.filter(|_| is_quad).map_or(u32::MAX, |shape| shape as u32)
                })
                .collect(),
            indices: MonochromaticIndices::default(),
            only_specular_eye_caustics: false,
        }
    }

    /// Validation only (tests/missing_class.rs): the same integrator counting nothing but the
    /// paths L S⁺ D X* S⁺ E of quad lights (BSDF hits after a specular vertex, on a path with a
    /// diffuse vertex and a specular eye end): the class that nobody counts for delta lights,
    /// measured on scenes whose delta lights are replaced by small area lights.
    pub fn counting_only_specular_eye_caustics(self) -> Self {
        Self { only_specular_eye_caustics: true, ..self }
    }

    /// The same integrator for a render at the one wavelength `nm` (nm), if monochromatic.
    pub fn with_monochromatic(self, nm: Option<f32>) -> Self {
        Self { indices: MonochromaticIndices::new(&self.scene.materials, nm), ..self }
    }

    /// The same integrator with a deliberate physics error (validation only).
    pub fn with_fault(self, fault: Option<Fault>) -> Self {
        Self { fault, ..self }
    }

    /// Light (W·m⁻²·sr⁻¹·nm⁻¹) arriving at the origin of `ray` along it, at `wavelengths`, in
    /// the Stokes frame of x axis `frame_x` when polarised (as [`super::Whitted::radiance`]).
    pub fn radiance<B: PathBeam>(
        &self,
        ray: &Ray,
        frame_x: Vec3,
        wavelengths: &SampledWavelengths,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
    ) -> B {
        rng.sobol_groups(SOBOL_GROUPS);
        if B::POLARIZED && self.never_polarized {
            // The Stokes response would carry (r, 0, 0, 0) in its column 0 throughout and give
            // (r·L, 0, 0, 0): the same S0, bit for bit, for a sixth less time per sample (TP6).
            let light = self.radiance::<SampledSpectrum>(ray, frame_x, wavelengths, rng, stats);
            return B::unpolarized(light);
        }
        let mask = wavelengths.active_mask();
        let live = (0..N_LAMBDA).filter(|&i| mask[i] > 0.0).fold(0_u32, |bits, i| bits | 1 << i);
        let first = PathState {
            ray: *ray,
            frame_x,
            response: B::Response::identity(mask),
            live,
            depth: 0,
            previous: Previous::Camera,
            diffuse_seen: false,
            eye_vertex_diffuse: None,
        };
        // Paths split off at a dispersive refraction wait here; one split per camera sample at
        // most (a split path carries one lane), so N_LAMBDA places suffice.
        let mut pending: [Option<PathState<B::Response>>; N_LAMBDA] = [None; N_LAMBDA];
        let mut light = B::zero();
        let mut next = Some(first);
        while let Some(state) = next.take().or_else(|| pending.iter_mut().find_map(Option::take)) {
            light += self.follow::<B>(state, wavelengths, rng, stats, &mut pending);
        }
        light
    }

    /// Follows one path to its end, returning the light it records; paths split off at a
    /// dispersive refraction go to `pending`.
    fn follow<B: PathBeam>(
        &self,
        mut state: PathState<B::Response>,
        wavelengths: &SampledWavelengths,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
        pending: &mut [Option<PathState<B::Response>>; N_LAMBDA],
    ) -> B {
        let mut light = B::zero();
        loop {
            stats.rays += 1;
            let found = self.scene.geometry.intersect(&state.ray, f32::INFINITY);
            let Some(hit) = found.as_ref() else {
                light += self.background::<B>(&state, wavelengths);
                return light;
            };
            let surface = self.scene.surfaces[hit.prim as usize];
            if let Some(emitter) = surface.emitter {
                if let Light::Quad(quad) = &self.scene.lights[emitter as usize] {
                    if quad.faces(state.ray.dir) {
                        let weight = self.emitter_hit_weight(&state, quad, hit);
                        if weight > 0.0 {
                            let radiance = quad.radiance.sample(wavelengths) * weight;
                            light += state.response.unpolarized(radiance);
                        }
                    }
                }
            }
            let material = &self.scene.materials[surface.material as usize];
            if matches!(material, Material::Black) || state.depth >= self.max_depth {
                return light;
            }
            // The roulette's number after a diffuse vertex (see `survives`); after any other
            // vertex, the sampler's next dimension.
            let mut roulette_u = None;
            let continues = match material {
                Material::Black => false,
                Material::Diffuse(diffuse) => {
                    // One padded group per diffuse vertex: the drawn direction on its first two
                    // dimensions (a (0, 2)-sequence), the first quad light's point on the other two.
                    let [bsdf_u1, bsdf_u2, quad_u1, quad_u2] = rng.uniform_4d();
                    let quad_u = Some((quad_u1, quad_u2));
                    roulette_u = Some(quad_u1);
                    // The bounce is drawn before the next-event estimate, which depends on none
                    // of it (nor it on the estimate: both took their numbers above): the chains
                    // of long latency of the two (divisions, square roots, the shadow ray's
                    // tests) then overlap in the processor, 3–4 % less CPU per sample on the
                    // glass-and-mirror room (validation/bench/PROFILE.md; tracing the bounce
                    // before the shadow ray too was slower). The same numbers in the same order:
                    // the same image, bit for bit.
                    let mut bounced = state;
                    let continues =
                        self.diffuse_bounce::<B>(&mut bounced, diffuse, hit, wavelengths, (bsdf_u1, bsdf_u2));
                    light += self.next_event::<B>(&state, (diffuse, hit), wavelengths, rng, stats, quad_u);
                    state = bounced;
                    continues
                }
                Material::Mirror(mirror) => {
                    let cos_theta_i = state.ray.dir.dot(hit.shading_normal);
                    let mueller = super::mirror_mueller::<B>(self.fault, mirror, cos_theta_i, wavelengths);
                    let dir = reflect(state.ray.dir, hit.shading_normal).normalize();
                    self.turn::<B>(&mut state, hit, hit.shading_normal, &mueller, dir);
                    state.previous = Previous::Specular;
                    state.eye_vertex_diffuse.get_or_insert(false);
                    true
                }
                Material::Dielectric(dielectric) => self.dielectric::<B>(
                    &mut state,
                    (surface.material, dielectric),
                    hit,
                    wavelengths,
                    rng,
                    pending,
                ),
                Material::Film(film) => self.film::<B>(&mut state, film, hit, wavelengths, rng),
                Material::Polarizer(_) | Material::Retarder(_) => {
                    let Some(sheet) = Sheet::of(material) else { return light };
                    let dir = state.ray.dir;
                    let (axis, element, spectrum) = sheet.element(self.fault, hit.normal, -dir, wavelengths);
                    let mueller = Mueller::splat(element).scaled(spectrum);
                    if B::POLARIZED {
                        state.response = state
                            .response
                            .rotated(rotation(self.fault, -dir, axis, state.frame_x))
                            .through(&mueller);
                        state.frame_x = axis;
                    } else {
                        state.response = state.response.through(&mueller);
                    }
                    // Straight through: not a vertex of the path's class, but a bounce of its depth.
                    state.ray = Ray::new(spawn_origin(hit.point, hit.normal, dir), dir);
                    true
                }
            };
            if !continues {
                return light;
            }
            state.depth += 1;
            if !self.survives::<B>(&mut state, roulette_u, rng) {
                return light;
            }
        }
    }

    /// Russian roulette from the third bounce on: a path whose strongest live lane's response r
    /// is below 1/[`ROULETTE_SCALE`] survives with probability [`ROULETTE_SCALE`]·r, divided by it.
    ///
    /// The number compared with the survival probability is `u` when given: after a diffuse
    /// vertex, the first dimension of the quad light's point of its next-event estimate. That
    /// number steers only this vertex's next-event estimate, which is counted whether or not the
    /// path survives, and nothing the path meets later (its direction came from the group's
    /// other dimensions, later vertices from later groups); within one sample it is uniform and
    /// independent of them, so E[1(u < p)/p · later light] is the later light's expectation:
    /// unbiased. Over a pixel's samples it is stratified, as the sampler's own dimension was,
    /// and it saves a fresh padded group per vertex.
    fn survives<B: PathBeam>(
        &self,
        state: &mut PathState<B::Response>,
        u: Option<f32>,
        rng: &mut PixelRng,
    ) -> bool {
        let strongest = state.response.strength().max_value();
        if strongest.is_nan() || strongest <= 0.0 {
            return false;
        }
        let survival = strongest * ROULETTE_SCALE;
        if state.depth < ROULETTE_AFTER_BOUNCES || survival >= 1.0 {
            return true;
        }
        if u.unwrap_or_else(|| rng.uniform()) >= survival {
            return false;
        }
        state.response = state.response.scaled(SampledSpectrum::splat(1.0 / survival));
        true
    }

    /// The weight of a quad light's radiance met along a path (see the module's table): 1 where
    /// only this hit makes the path, the power heuristic's where next-event estimation could
    /// have made it too, 0 where the light tracer counts it.
    fn emitter_hit_weight<R>(&self, state: &PathState<R>, quad: &crate::light::QuadLight, hit: &Hit) -> f32 {
        if self.only_specular_eye_caustics {
            let class = state.previous == Previous::Specular
                && state.diffuse_seen
                && state.eye_vertex_diffuse == Some(false);
            return if class { 1.0 } else { 0.0 };
        }
        match state.previous {
            Previous::Camera => 1.0,
            Previous::Specular => {
                let light_tracer_has_it = state.diffuse_seen
                    && state.eye_vertex_diffuse == Some(true)
                    && self.light_tracer_counts_caustics;
                if light_tracer_has_it && self.fault != Some(Fault::CausticsCountedTwice) {
                    0.0
                } else {
                    1.0
                }
            }
            Previous::Diffuse { pdf, from } => {
                if self.fault == Some(Fault::MisWeightsUnnormalized) {
                    return 1.0;
                }
                let cos_light = quad.emit_normal.dot(state.ray.dir).abs();
                if cos_light.is_nan() || cos_light <= 0.0 {
                    return 0.0;
                }
                // The density, per steradian, with which `area_light_samples` points on the quad
                // would have drawn this direction: over the whole distance from the diffuse
                // vertex (the last segment alone is shorter when the path crossed a sheet).
                let distance_squared = (hit.point - from).length_squared();
                let light_pdf =
                    self.area_light_samples as f32 * distance_squared / (quad.quad.area() * cos_light);
                power_heuristic(pdf, light_pdf)
            }
        }
    }

    /// The background's radiance met by a path escaping the scene, weighted as
    /// [`Self::emitter_hit_weight`] weights quads (the light tracer never starts at the
    /// background, so camera paths count all of its paths).
    fn background<B: PathBeam>(&self, state: &PathState<B::Response>, wavelengths: &SampledWavelengths) -> B {
        if !self.background_lights || self.only_specular_eye_caustics {
            return B::zero();
        }
        let weight = match state.previous {
            _ if self.fault == Some(Fault::DarkBackground) && state.diffuse_seen => 0.0,
            Previous::Camera | Previous::Specular => 1.0,
            // The cosine-sampled bounce alone gathers the background (module doc, "Diffuse
            // vertices"): weight 1.
            Previous::Diffuse { .. } => 1.0,
        };
        if weight <= 0.0 {
            return B::zero();
        }
        state.response.unpolarized(self.scene.background.sample(wavelengths) * weight)
    }

    /// Next-event estimation at a diffuse vertex: light from every light and the background
    /// reaching it directly (through sheets), as the camera records it.
    fn next_event<B: PathBeam>(
        &self,
        state: &PathState<B::Response>,
        (diffuse, hit): (&Diffuse, &Hit),
        wavelengths: &SampledWavelengths,
        rng: &mut PixelRng,
        stats: &mut TraceStats,
        mut quad_u: Option<(f32, f32)>,
    ) -> B {
        if self.only_specular_eye_caustics {
            return B::zero();
        }
        let to_viewer = -state.ray.dir;
        let (normal, shading_normal) = facing(hit, to_viewer);
        // Σ over samples of L_e·G·shape·MIS weight; ρ/π once at the end.
        let mut radiance = SampledSpectrum::zero();
        let arriving =
            |sample: &LightSample, shape: u32, stats: &mut TraceStats| -> Option<(f32, SampledSpectrum)> {
                let cos_theta = shading_normal.dot(sample.to_light);
                if cos_theta <= 0.0 || normal.dot(sample.to_light) <= 0.0 {
                    return None;
                }
                let (response, spectrum) =
                    self.visible::<B>(hit, normal, sample, shape, wavelengths, stats)?;
                let weight = response
                    * sample.weight
                    * cos_theta
                    * diffuse.shape_factor(shading_normal, sample.to_light, to_viewer);
                (weight > 0.0).then_some((weight, spectrum))
            };
        for (light, &shape) in self.scene.lights.iter().zip(&self.light_shapes) {
            let mut sum = SampledSpectrum::zero();
            match light {
                Light::Point(point) => {
                    if let Some((w, s)) =
                        point.sample(hit.point).and_then(|sample| arriving(&sample, u32::MAX, stats))
                    {
                        sum += s * w;
                    }
                }
                Light::Spot(spot) => {
                    if let Some((w, s)) =
                        spot.sample(hit.point).and_then(|sample| arriving(&sample, u32::MAX, stats))
                    {
                        sum += s * w;
                    }
                }
                Light::Beam(beam) => {
                    if let Some((w, s)) =
                        beam.sample(hit.point).and_then(|sample| arriving(&sample, u32::MAX, stats))
                    {
                        sum += s * w;
                    }
                }
                Light::Quad(quad) => {
                    let count = self.area_light_samples;
                    let shift = quad_u.take().unwrap_or_else(|| rng.uniform_2d());
                    for index in 0..count {
                        let Some(sample) = quad.sample(hit.point, index, count, shift) else { continue };
                        let Some((w, s)) = arriving(&sample, shape, stats) else { continue };
                        // `sample.weight` is 1/(n·p_light) per steradian.
                        let mis = if self.fault == Some(Fault::MisWeightsUnnormalized) {
                            1.0
                        } else {
                            power_heuristic(
                                1.0 / sample.weight,
                                Diffuse::pdf(shading_normal, sample.to_light),
                            )
                        };
                        sum += s * (w * mis);
                    }
                }
            }
            if !sum.is_zero() {
                radiance += light.emitted().sample(wavelengths) * sum;
            }
        }
        if radiance.is_zero() {
            return B::zero();
        }
        let reflected = radiance * (diffuse.albedo.sample(wavelengths) * std::f32::consts::FRAC_1_PI);
        state.response.unpolarized(reflected)
    }

    /// Whether a light sample is visible from `hit`: the sheets' response and spectrum, or
    /// `None` when blocked. `shape` is the light's own quad (`u32::MAX` for none), which the
    /// shadow ray, stopped short of it, need not test.
    fn visible<B: PathBeam>(
        &self,
        hit: &Hit,
        normal: Vec3,
        sample: &LightSample,
        shape: u32,
        wavelengths: &SampledWavelengths,
        stats: &mut TraceStats,
    ) -> Option<(f32, SampledSpectrum)> {
        let origin = spawn_origin(hit.point, normal, sample.to_light);
        if self.has_sheets {
            return visibility::through_sheets::<B>(
                self.scene,
                self.fault,
                origin,
                sample.to_light,
                sample.distance,
                wavelengths,
                stats,
            );
        }
        stats.rays += 1;
        let shadow = Ray::new(origin, sample.to_light);
        let reach = sample.distance * (1.0 - visibility::SHADOW_RAY_SHORTENING);
        (!self.scene.geometry.occluded_except(&shadow, reach, shape))
            .then_some((1.0, SampledSpectrum::splat(1.0)))
    }

    /// A diffuse bounce: a direction drawn with the cosine density on the side the path
    /// arrived from, the response depolarised and weighted by f·cos θ/pdf. False when the
    /// drawn direction leaves through the geometric surface (the path ends).
    fn diffuse_bounce<B: PathBeam>(
        &self,
        state: &mut PathState<B::Response>,
        diffuse: &Diffuse,
        hit: &Hit,
        wavelengths: &SampledWavelengths,
        u: (f32, f32),
    ) -> bool {
        let to_viewer = -state.ray.dir;
        let (normal, shading_normal) = facing(hit, to_viewer);
        let (dir, pdf) = Diffuse::sample_polynomial(shading_normal, u);
        let cos_theta = shading_normal.dot(dir);
        if pdf.is_nan() || pdf <= 0.0 || normal.dot(dir) <= 0.0 {
            return false;
        }
        // f·cos θ/pdf = (ρ/π)·shape·cos θ/(cos θ/π) = ρ·shape.
        let mut weight = diffuse.shape_factor(shading_normal, dir, to_viewer);
        if self.fault == Some(Fault::NoDiffuseCosine) {
            weight /= cos_theta;
        }
        state.response = state.response.depolarized(diffuse.albedo.sample(wavelengths) * weight);
        state.frame_x = any_perpendicular(dir);
        state.ray = Ray::new(spawn_origin(hit.point, normal, dir), dir);
        state.previous = Previous::Diffuse { pdf, from: hit.point };
        state.diffuse_seen = true;
        state.eye_vertex_diffuse.get_or_insert(true);
        true
    }

    /// A specular turn at `hit`: the response through `mueller`, written in the s frame of the
    /// incidence on `normal`, and the path on along `dir`.
    fn turn<B: PathBeam>(
        &self,
        state: &mut PathState<B::Response>,
        hit: &Hit,
        normal: Vec3,
        mueller: &Mueller,
        dir: Vec3,
    ) {
        let incoming = state.ray.dir;
        if B::POLARIZED {
            let s = s_axis(normal, -incoming, state.frame_x);
            state.response =
                state.response.rotated(rotation(self.fault, -incoming, s, state.frame_x)).through(mueller);
            state.frame_x = s;
        } else {
            state.response = state.response.through(mueller);
        }
        state.ray = Ray::new(spawn_origin(hit.point, hit.normal, dir), dir);
    }

    /// The branch choice at a specular interface: reflection with probability
    /// p = reflected / (reflected + transmitted) (`sums`: each branch's response summed over
    /// the live lanes), taken here with the response `reflection` divided by p; otherwise the
    /// transmission's probability 1 − p, for the caller to take. [`Branch::Ended`] when neither
    /// branch carries light.
    #[allow(clippy::too_many_arguments)] // the vertex and its two branches, passed flat
    fn choose_branch<B: PathBeam>(
        &self,
        state: &mut PathState<B::Response>,
        hit: &Hit,
        normal: Vec3,
        reflection: &Mueller,
        (reflected_sum, transmitted_sum): (f32, f32),
        rng: &mut PixelRng,
    ) -> Branch {
        let total = reflected_sum + transmitted_sum;
        if total.is_nan() || total <= 0.0 {
            return Branch::Ended;
        }
        let p_reflect = reflected_sum / total;
        state.previous = Previous::Specular;
        state.eye_vertex_diffuse.get_or_insert(false);
        if rng.uniform() < p_reflect {
            let reflection = reflection.scaled(SampledSpectrum::splat(1.0 / p_reflect));
            let reflected = reflect(state.ray.dir, normal).normalize();
            self.turn::<B>(state, hit, normal, &reflection, reflected);
            Branch::Reflected
        } else {
            Branch::Transmitted { probability: 1.0 - p_reflect }
        }
    }

    /// A free-standing film: one branch, the mirrored or the straight one, chosen with
    /// probability proportional to the film's R or T summed over the live lanes (weighted by
    /// the path's response) and divided by it. False when the path ends.
    fn film<B: PathBeam>(
        &self,
        state: &mut PathState<B::Response>,
        film: &Film,
        hit: &Hit,
        wavelengths: &SampledWavelengths,
        rng: &mut PixelRng,
    ) -> bool {
        let dir = state.ray.dir;
        let normal = hit.shading_normal;
        let cos_theta_i = -dir.dot(normal);
        let thickness_nm = film.thickness.at(hit.point);
        let (reflection, transmission) =
            film_matrices::<B>(self.fault, film, cos_theta_i, thickness_nm, wavelengths, state.live);
        let strength = state.response.strength();
        let (mut reflected_sum, mut transmitted_sum) = (0.0f32, 0.0f32);
        for lane in (0..N_LAMBDA).filter(|&i| state.live & (1 << i) != 0) {
            let w = strength[lane].abs();
            reflected_sum += w * reflection.a[lane];
            transmitted_sum += w * transmission.a[lane];
        }
        match self.choose_branch::<B>(state, hit, normal, &reflection, (reflected_sum, transmitted_sum), rng)
        {
            Branch::Ended => return false,
            Branch::Reflected => {}
            Branch::Transmitted { probability } => {
                let transmission = transmission.scaled(SampledSpectrum::splat(1.0 / probability));
                self.turn::<B>(state, hit, normal, &transmission, dir);
            }
        }
        true
    }

    /// Glass: Beer–Lambert over the segment inside, then one branch, reflected or refracted,
    /// chosen by the branches' responses; at a dispersive refraction of a path of several
    /// lanes, one path per lane (all but the first to `pending`). False when the path ends.
    fn dielectric<B: PathBeam>(
        &self,
        state: &mut PathState<B::Response>,
        (material, dielectric): (u32, &Dielectric),
        hit: &Hit,
        wavelengths: &SampledWavelengths,
        rng: &mut PixelRng,
        pending: &mut [Option<PathState<B::Response>>; N_LAMBDA],
    ) -> bool {
        let dir = state.ray.dir;
        if let (Some(sigma), true) = (&dielectric.absorption, dir.dot(hit.normal) > 0.0) {
            state.response = state.response.scaled((sigma.sample(wavelengths) * -hit.t).exp());
        }
        let normal = hit.shading_normal;
        let cos_theta_i = -dir.dot(normal);
        let live = state.live;
        let lanes = (0..N_LAMBDA).filter(move |&i| live & (1 << i) != 0);
        let first_live = lanes.clone().next().unwrap_or(0);
        let split = dielectric.ior.is_dispersive() && state.live.count_ones() > 1;
        let fresnel_at = |lane: usize| {
            fresnel(
                self.fault,
                cos_theta_i,
                self.indices.ior(material, dielectric, wavelengths.lambda_nm(lane)),
            )
        };
        let fresnel: [DielectricFresnel; N_LAMBDA] =
            if split { std::array::from_fn(fresnel_at) } else { [fresnel_at(first_live); N_LAMBDA] };
        let coated = dielectric.is_coated().then(|| {
            coated_matrices::<B>(self.fault, dielectric, cos_theta_i, wavelengths, state.live, |lane| {
                self.indices.ior(material, dielectric, wavelengths.lambda_nm(lane))
            })
        });
        let reflection = match &coated {
            Some((reflection, _)) => *reflection,
            None if B::POLARIZED => Mueller::from_lanes(
                &fresnel.map(|f| element(self.fault, JonesDiagonal::dielectric_reflection(cos_theta_i, &f))),
            ),
            None => Mueller::attenuation(SampledSpectrum { values: fresnel.map(|f| f.reflectance) }),
        };
        // The transmitted flux per lane (the camera side's 1/η² applied below), zero under
        // total internal reflection.
        let transmission_at = |lane: usize| {
            let f = &fresnel[lane];
            let (refracted, flux) = refraction::<B>(dir, normal, f)?;
            let flux = match &coated {
                Some((_, coated_flux)) => *coated_flux,
                None => flux,
            };
            Some((refracted, flux.scaled(SampledSpectrum::splat(1.0 / (f.eta_it * f.eta_it)))))
        };
        // One refraction for every lane unless the lanes split (then one per live lane).
        let transmissions: [Option<(Vec3, Mueller)>; N_LAMBDA] = if split {
            std::array::from_fn(|lane| if live & (1 << lane) != 0 { transmission_at(lane) } else { None })
        } else {
            [transmission_at(first_live); N_LAMBDA]
        };
        // Branch choice: each branch's flux response summed over the live lanes (the camera
        // side's 1/η² left out, so that lossless glass chooses by R and T).
        let strength = state.response.strength();
        let (mut reflected_sum, mut transmitted_sum) = (0.0f32, 0.0f32);
        for lane in lanes.clone() {
            let w = strength[lane].abs();
            reflected_sum += w * reflection.a[lane];
            if let Some((_, m)) = &transmissions[lane] {
                let eta = fresnel[lane].eta_it;
                transmitted_sum += w * m.a[lane] * eta * eta;
            }
        }
        let p_transmit = match self.choose_branch::<B>(
            state,
            hit,
            normal,
            &reflection,
            (reflected_sum, transmitted_sum),
            rng,
        ) {
            Branch::Ended => return false,
            Branch::Reflected => return true,
            Branch::Transmitted { probability } => probability,
        };
        if !split {
            let Some((refracted, transmission)) = transmissions[first_live] else { return false };
            let transmission = transmission.scaled(SampledSpectrum::splat(1.0 / p_transmit));
            self.turn::<B>(state, hit, normal, &transmission, refracted);
            return true;
        }
        // Every live lane on its own direction: this path continues with the first, the others
        // wait in `pending` (the same state, one lane each).
        let before = *state;
        let mut continued = false;
        let mut slot = 0;
        for lane in lanes {
            let Some((refracted, transmission)) = transmissions[lane] else { continue };
            let mut lane_state = before;
            lane_state.response = lane_state.response.only_lane(lane);
            lane_state.live = 1 << lane;
            let transmission = transmission.scaled(SampledSpectrum::splat(1.0 / p_transmit));
            self.turn::<B>(&mut lane_state, hit, normal, &transmission, refracted);
            if !continued {
                *state = lane_state;
                continued = true;
            } else {
                while slot < N_LAMBDA && pending[slot].is_some() {
                    slot += 1;
                }
                if let Some(place) = pending.get_mut(slot) {
                    // A split path's depth and roulette continue where the parent's stood.
                    lane_state.depth += 1;
                    *place = Some(lane_state);
                }
            }
        }
        continued
    }
}

/// What [`PathTracer::choose_branch`] did at a specular interface.
enum Branch {
    /// Neither branch carries light: the path ends.
    Ended,
    /// The reflection was taken.
    Reflected,
    /// The transmission is to be taken, with this probability to divide by.
    Transmitted {
        /// 1 − p_reflect.
        probability: f32,
    },
}

/// The geometric and shading normals on the side of `to_viewer`.
#[inline]
fn facing(hit: &Hit, to_viewer: Vec3) -> (Vec3, Vec3) {
    if hit.normal.dot(to_viewer) >= 0.0 {
        (hit.normal, hit.shading_normal)
    } else {
        (-hit.normal, -hit.shading_normal)
    }
}

/// Veach's power heuristic (β = 2) for a sample drawn with density `chosen` against another
/// technique's density `other` at the same direction.
#[inline]
fn power_heuristic(chosen: f32, other: f32) -> f32 {
    // As 1/(1 + (other/chosen)²): the squares of the densities themselves overflow f32 for a
    // light seen at a grazing angle from far away (a floor hit 6e7 m out at the horizon gives
    // p_light ≈ d²/(cos θ·A) ≈ 1e23 sr⁻¹), and ∞/∞ would be NaN.
    if chosen.is_nan() || chosen <= 0.0 || !other.is_finite() {
        return 0.0;
    }
    let ratio = other / chosen;
    1.0 / (1.0 + ratio * ratio)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_heuristic_weights_add_to_one() {
        for (a, b) in [(0.3f32, 0.7f32), (1.0, 1e-3), (5.0, 5.0), (1e23, 1.0), (1e-30, 1e30)] {
            let sum = power_heuristic(a, b) + power_heuristic(b, a);
            assert!((sum - 1.0).abs() < 1e-6, "{a} {b}: {sum}");
        }
        assert_eq!(power_heuristic(0.0, 1.0), 0.0);
        assert_eq!(power_heuristic(1.0, f32::INFINITY), 0.0);
    }
}
