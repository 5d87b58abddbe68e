//! The light tracer: caustics, by following light from the lights through mirrors and glass to
//! the diffuse surfaces the camera sees (particle tracing; Veach, *Robust Monte Carlo Methods
//! for Light Transport Simulation*, 1997, §3.7 and §5.2; Mitsuba 3's `ptracer`).
//!
//! # One image, two estimators, each path counted once
//! In Heckbert's notation (L light, S a mirror or glass interaction, D diffuse, X either, E the
//! eye), with polarising sheets crossed freely by both estimators and not counted as vertices,
//! the light tracer works beside one of two camera-side estimators:
//!
//! | path class | Whitted render | full transport (`integrator = "path"`) |
//! |---|---|---|
//! | L S\* E (no diffuse vertex) | [`super::Whitted`] | the path tracer |
//! | L D X\* E (diffuse next to the light) | [`super::Whitted`], L D S\* E only | the path tracer |
//! | **L S⁺ D E** | **the light tracer** | **the light tracer** |
//! | **L S⁺ D X\* D E** | nobody | **the light tracer, with interreflection** |
//! | L S⁺ D X\* S⁺ E, area lights | nobody | the path tracer |
//! | L S⁺ D X\* S⁺ E, point, spot and beam lights | nobody | nobody (still missing) |
//!
//! That is: Whitted counts **E S\* D L** and **E S\* L**, and the light tracer **L S⁺ D E**:
//! light that met at least one mirror or glass surface before its first diffuse surface, which
//! the camera sees directly; paths whose first interaction is diffuse (L D …) end there, as the
//! camera side has them. In full transport ([`LightTracer::with_interreflection`]) the light
//! tracer counts **L S⁺ D (X\* D)? E**: the same paths, connected to the camera at their first
//! diffuse vertex and then at **every** diffuse vertex they reach after it; the path tracer
//! counts every path whose vertex next to the light is diffuse, every path without a diffuse
//! vertex, and for area lights the caustics seen through mirrors and glass (L S⁺ D X\* S⁺ E).
//! The classes are disjoint, so the images add ([`crate::render`]); a scene without mirrors or
//! glass renders bit for bit as its camera side alone (tested for Whitted). Still missing: a
//! caustic of a point, spot or beam light seen in a mirror or through glass (**L S⁺ D X\* S⁺
//! E**: the connection to the camera cannot pass a specular surface).
//!
//! # Alone, for validation
//! [`LightTracer::counting_everything`] makes the light tracer an estimator of the whole image
//! on its own, never beside a camera side (the adjoint check: a render from the light side must
//! agree with one from the camera side, Veach 1997 ch. 3 and 4; polarised, as Mojzík et al.,
//! EGSR 2016): paths start over the whole emission of every light
//! ([`super::emission::Emission::everything`]: quads cosine-weighted over their hemisphere), are
//! connected to the camera at **every** diffuse vertex, the first included (L D E, L X\* D E),
//! and, on a quad light, at their start (L E: the light seen directly, L·cos θ_y over the density
//! of the point, times the camera's sensitivity). It counts every path but those that reach the
//! pinhole through a mirror or glass (L X\* S⁺ E), and wants a black background (no light to
//! it). So on the pixels whose camera ray first meets a diffuse surface or a light it must agree
//! with the path tracer alone (`caustics = false`), Stokes vectors included
//! (tests/adjoint_transport.rs). Off, the default, nothing it traces changes.
//!
//! # What a light path carries
//! Flux: a light path starts with the light's power per unit wavelength divided by the
//! densities that chose it ([`super::emission`]), at the wavelengths of a camera sample (the
//! same lanes and densities, [`SampledWavelengths::sample_visible`]). A mirror multiplies it by
//! its reflectance, a dielectric by the Fresnel reflectance or transmittance (Mueller matrices
//! when polarised, as on the camera side): flux crossing an interface keeps its value, so the
//! (n_t/n_i)² that radiance gains on the camera side does **not** appear here (the adjoint of a
//! refraction carries importance, Veach §5.2; Mitsuba's and pbrt's dielectrics switch it off in
//! importance mode). At a **dispersive refraction every live wavelength continues** on its own
//! direction, as a path carrying that lane alone; none is dropped.
//!
//! At the first diffuse surface (after a mirror or glass) the path is connected to the camera:
//! to the pinhole, or to a point of a thin lens drawn uniformly from the path's next two sample
//! values (drawn only for a lens: a pinhole's light paths keep their stream), landing on the film
//! where the line from that lens point through the surface point crosses the plane of focus
//! ([`crate::camera::ThinLens::project`]). If the camera sees the point (same side, unoccluded,
//! inside the image), the pixel it lands in gains
//!
//! ```text
//! Φ · f_r · cos θ_x · 1/(d² · A_pixel · cos³θ_c)
//! ```
//! (flux times the BRDF times the cosine at the receiver toward the camera: the radiant
//! intensity the point sends to the camera; then [`crate::camera::FilmPoint::sensitivity`]: the
//! pinhole's importance with its cosine, over d², from the pinhole or the lens point drawn, whose
//! density 1/(π·a²) cancels the lens average a camera ray takes). The diffuse receiver depolarises: the camera
//! gets unpolarised light (S0), changed only by sheets on the way. The film divides the sums by
//! the number of light paths traced ([`crate::film::WindowSums::film`]).
//!
//! # Where paths start
//! Emission aims paths at the mirrors and glass ([`super::emission`]); within that, the first
//! light paths of a render start uniformly, and the rest by the density [`super::guide`] learns
//! from them (their flux divided by it): fewer where light piles up in a bright focus, more
//! where it spreads thin. Where the guide predicts little gain (a beam through a prism) every
//! path starts uniformly.
//!
//! # Branches at glass
//! Where a path meets glass straight from its light (its first interaction), it **traces both
//! branches**, the reflected one with the Fresnel reflectance and the refracted one with the
//! transmittance. Everywhere after, it continues along **one** branch, reflected or refracted,
//! chosen with probability proportional to each branch's flux (summed over the lanes), and
//! divided by that probability: unbiased, and a path stays one path (until dispersion splits it
//! by lane); through lossless glass it keeps its flux exactly.
//!
//! Why the first interface differs: the light glass reflects straight from the light is spread
//! thin over the receiver (a ball reflects a spot over the whole floor around it), and chosen
//! with probability R ≈ 0.05–0.1 it reached each pixel as a rare photon of the full flux; at
//! relMSE 1e-3 on the caustic bench's ball half the error sat in those pixels. Splitting there
//! gives every path that meets glass a reflected child. Measured at equal spp (render time,
//! relMSE against long renders, 1–16 spp; validation/bench/RESULTS.md): the bench's ball lens
//! 1.1–1.25× the time for 0.66–0.73× the error, `glass_sphere_spot` 1.1–1.3× for 0.62–0.78×,
//! the Newton prism 1.0–1.07× for 0.74–0.88×; `tp6_mirror_glass_caustics`, whose error is
//! mostly its camera side's, 1.07–1.16× for 0.96× (a loss of 5–12 % at equal error, the price
//! of a rule without a setting). Splitting at the second interface too cost more than it gained
//! on the ball; splitting at every interface, as Whitted does, took 3× the rays for 2.3× less
//! variance over the ball's caustic, 1.25× worse at equal time (validation/README.md).
//!
//! Depth is capped at `max_depth` interactions with mirrors, glass and sheets, and paths whose
//! flux falls below `prune_below` of their starting value go through Russian roulette.
//!
//! # Interreflection
//! With [`LightTracer::with_interreflection`] (full transport), a path that reached its first
//! diffuse vertex after a mirror or glass is connected to the camera there, as above, and then
//! **goes on**: it leaves in a direction drawn by the cosine density
//! ([`Diffuse::sample`]) about the normal on the side the light arrived from, its flux
//! depolarised (S0 alone) and multiplied by f·cos θ/pdf = ρ(λ)·[`Diffuse::shape_factor`] (the
//! BRDF with its two directions swapped: Lambert and Oren–Nayar's qualitative model are
//! symmetric in them). From there it crosses mirrors, glass and sheets as before (one branch
//! chosen by flux at glass; at a dispersive refraction every live lane on its own direction),
//! and is connected to the camera at every diffuse vertex it reaches, scattering on from each.
//! Once it has left a diffuse surface, every continuation whose flux is below the path's
//! starting flux survives Russian roulette with probability (its flux)/(starting flux), the
//! larger over the lanes, and is divided by it (unbiased; a survivor carries the starting flux
//! again, so a path's splats stay of one size). `max_depth` then counts **every** interaction,
//! diffuse, specular and sheets: a path is counted when its vertices between the light and the
//! camera (the diffuse one the camera sees included) number at most `max_depth`.
//!
//! # Shading normals
//! Where a mesh's interpolated shading normal differs from its geometric one, the light side
//! carries Veach's adjoint BSDF (thesis §5.3; pbrt's `CorrectShadingNormal` in importance
//! mode): every vertex a light path leaves (mirror, glass, sheet, diffuse scattering) and every
//! connection to the camera multiplies the flux by |ω_i·N_s||ω_o·N_g|/(|ω_i·N_g||ω_o·N_s|)
//! (ω_i back toward the light, ω_o onward), so a diffuse connection weighs
//! f·(ω_i·N_s/ω_i·N_g)·(ω_o·N_g): the flux arriving per unit of geometric area, turned into the
//! shading irradiance, seen over the geometric area. Without it the light side and the camera
//! side disagree on smooth-shaded meshes (`tests/adjoint_transport.rs`,
//! `Fault::NoShadingNormalAdjoint`). Flat shapes are untouched, bit for bit.

use glam::Vec3;

use super::emission::{Cone, Emission};
use super::guide::EmissionGuide;
use super::{
    coated_matrices, element, film_matrices, fresnel, refraction, rotation, Beam, Fault,
    MonochromaticIndices, TraceStats,
};
use crate::camera::FilmPoint;
use crate::film::{FilmLayout, Splats};
use crate::geometry::{spawn_origin, Hit, Ray};
use crate::light::Light;
use crate::material::{Dielectric, Diffuse, Film, Material};
use crate::optics::{reflect, DielectricFresnel};
use crate::polarization::frame::{any_perpendicular, s_axis};
use crate::polarization::mueller::JonesDiagonal;
use crate::polarization::Mueller;
use crate::sampler::LightPathRng;
use crate::scene::{RenderSettings, Scene};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, N_LAMBDA};

/// The connection to the camera stops this fraction short of it (relative, as Whitted's
/// shadow rays).
const CONNECTION_SHORTENING: f32 = 1e-4;
/// Most polarising sheets a connection to the camera crosses before it counts as blocked.
const MAX_SHEETS_PER_CONNECTION: usize = 16;

/// A light path in flight: its ray, the Stokes frame of its flux, the flux, the interactions
/// so far, whether it has met a mirror or glass yet, and whether it has left a diffuse surface
/// (with interreflection).
#[derive(Debug, Clone, Copy)]
struct Photon<B> {
    ray: Ray,
    frame_x: Vec3,
    flux: B,
    depth: u32,
    through_specular: bool,
    after_diffuse: bool,
}

/// Where the branches of a path at a dielectric leave from: the hit, the path arriving, its
/// starting flux (for roulette), and the s axis both branches are framed in.
struct Branches<'a, B> {
    hit: &'a Hit,
    photon: &'a Photon<B>,
    reference: f32,
    frame_x: Vec3,
}

impl<B> Branches<'_, B> {
    /// The reflected direction, made only for a reflected branch that is traced (after the
    /// first interface most paths refract).
    fn reflected(&self) -> Vec3 {
        reflect(self.photon.ray.dir, self.hit.shading_normal).normalize()
    }
}

/// Scratch space of one worker, reused from path to path.
pub struct Scratch<B> {
    stack: Vec<Photon<B>>,
    cones: Vec<Cone>,
}

impl<B> Default for Scratch<B> {
    fn default() -> Self {
        Self { stack: Vec::new(), cones: Vec::new() }
    }
}

/// The light tracer over one scene.
#[derive(Clone)]
pub struct LightTracer<'a> {
    scene: &'a Scene,
    emission: Emission,
    max_depth: u32,
    prune_below: f32,
    wavelengths: usize,
    /// The one wavelength of a monochromatic render, made once (with its place on the grid).
    monochromatic: Option<SampledWavelengths>,
    fault: Option<Fault>,
    has_sheets: bool,
    guide: EmissionGuide,
    /// Each glass's index at a monochromatic render's wavelength.
    indices: MonochromaticIndices,
    /// Paths go on past their first diffuse vertex (module docs, "Interreflection").
    interreflection: bool,
    /// Validation: paths start over the whole emission and count every path they can make,
    /// alone (module docs, "Alone, for validation").
    everything: bool,
}

impl<'a> LightTracer<'a> {
    /// A light tracer for `scene` with the depth cap, roulette threshold and wavelengths per
    /// path of `settings`; `monochromatic_nm` traces every path at that one wavelength.
    pub fn new(scene: &'a Scene, settings: &RenderSettings, monochromatic_nm: Option<f32>) -> Self {
        Self {
            scene,
            emission: Emission::new(scene),
            max_depth: settings.max_depth,
            prune_below: settings.prune_below,
            wavelengths: settings.wavelengths,
            monochromatic: monochromatic_nm.map(SampledWavelengths::monochromatic),
            fault: None,
            has_sheets: scene.materials.iter().any(Material::is_filter),
            guide: EmissionGuide::uniform(),
            indices: MonochromaticIndices::new(&scene.materials, monochromatic_nm),
            interreflection: false,
            everything: false,
        }
    }

    /// The same tracer counting, alone, every path a light path can make (validation only;
    /// module docs, "Alone, for validation"): paths start over the whole emission of every
    /// light ([`Emission::everything`]), uniformly (no guide), and are connected to the camera
    /// at every diffuse vertex, the first included, and at their start on a quad light (the
    /// light seen directly). Its image is then the whole image on the pixels whose camera ray
    /// first meets a diffuse surface or a light; it cannot run beside a camera side, which would
    /// count the same paths again.
    pub fn counting_everything(self) -> Self {
        Self {
            emission: Emission::everything(self.scene),
            guide: EmissionGuide::uniform(),
            interreflection: true,
            everything: true,
            ..self
        }
    }

    /// The same tracer with its paths going on past their first diffuse vertex when `on` (the
    /// full-transport integrator's light side: **L S⁺ D (X\* D)? E**, module docs,
    /// "Interreflection"), or ending there when not (Whitted's light side, **L S⁺ D E**; the
    /// default, and bit for bit what it traced before the switch existed).
    pub fn with_interreflection(self, on: bool) -> Self {
        Self { interreflection: on, ..self }
    }

    /// The same tracer starting its paths as `guide` says ([`super::guide`]).
    pub fn with_guide(self, guide: EmissionGuide) -> Self {
        Self { guide, ..self }
    }

    /// The same tracer with a deliberate physics error (validation only).
    pub fn with_fault(self, fault: Option<Fault>) -> Self {
        Self { fault, ..self }
    }

    /// Why this scene can have no caustics, if it cannot: no light, no mirror or glass, or no
    /// light that can reach one.
    pub fn why_none(&self) -> Option<&'static str> {
        if self.scene.lights.is_empty() {
            Some("the scene has no light")
        } else if self.everything {
            self.emission.is_empty().then_some("no light emits")
        } else if !self
            .scene
            .materials
            .iter()
            .any(|m| matches!(m, Material::Mirror(_) | Material::Dielectric(_) | Material::Film(_)))
        {
            Some("the scene has no mirror or glass")
        } else if self.emission.is_empty() {
            Some("no light can reach a mirror or glass surface")
        } else {
            None
        }
    }

    /// Traces one light path drawing from `rng`, and adds what the camera sees of it to
    /// `splats`: the point of the unit square its first two sample dimensions drew, before the
    /// guide's warp (what [`super::guide::Record`] files a path of a uniform tracer under).
    pub fn trace_path<B: Beam>(
        &self,
        rng: &mut LightPathRng,
        layout: &FilmLayout,
        splats: &mut Splats,
        scratch: &mut Scratch<B>,
        stats: &mut TraceStats,
    ) -> (f32, f32) {
        // The direction (or a beam's position) first: the sampler stratifies dimensions 0 and 1
        // jointly over all the render's light paths; the guide warps them where paths are
        // worth most. Then only the choices this path has (the wavelengths unless
        // monochromatic, the light among several...), so that in a monochromatic render with
        // one light the first Fresnel choices (after the first interface, which traces both
        // branches) take dimensions 2 and 3, stratified with the direction.
        let u = (rng.uniform(), rng.uniform());
        let (u_dir, weight) = self.guide.warp(u);
        self.trace_path_from(u_dir, weight, rng, layout, splats, scratch, stats);
        u
    }

    /// What its splats hold per pixel in a render of `layout`: S0 alone unless polarising
    /// sheets can filter the light on its way to the camera (a diffuse receiver sends
    /// unpolarised light, [`Self::trace_path`]).
    pub fn splat_layout(&self, layout: &FilmLayout) -> FilmLayout {
        if self.has_sheets {
            *layout
        } else {
            layout.unpolarized()
        }
    }

    /// True when its paths start by a learned guide rather than uniformly.
    pub fn is_guided(&self) -> bool {
        !self.guide.is_uniform()
    }

    /// [`Self::trace_path`] from the point `u_dir` of its first two sample dimensions (already
    /// drawn from `rng`, already warped), its flux scaled by `weight`.
    #[allow(clippy::too_many_arguments)] // the path's state, passed flat
    fn trace_path_from<B: Beam>(
        &self,
        u_dir: (f32, f32),
        weight: f32,
        rng: &mut LightPathRng,
        layout: &FilmLayout,
        splats: &mut Splats,
        scratch: &mut Scratch<B>,
        stats: &mut TraceStats,
    ) {
        let sampled;
        let wavelengths = match &self.monochromatic {
            Some(wavelengths) => wavelengths,
            None => {
                sampled = SampledWavelengths::sample_visible(rng.uniform(), self.wavelengths);
                &sampled
            }
        };
        let Some(emitted) =
            self.emission.sample(self.scene, u_dir, &mut || rng.uniform(), &mut scratch.cones)
        else {
            return;
        };
        let flux = self.scene.lights[emitted.light].emitted().sample(wavelengths)
            * wavelengths.active_mask()
            * (emitted.weight * weight);
        let reference = flux.max_value();
        if reference.is_nan() || reference <= 0.0 {
            return;
        }
        if self.everything {
            if let Some(area_weight) = emitted.area_weight {
                let radiance = self.scene.lights[emitted.light].emitted().sample(wavelengths)
                    * wavelengths.active_mask()
                    * (area_weight * weight);
                self.connect_light::<B>(
                    emitted.light,
                    &emitted.ray,
                    radiance,
                    wavelengths,
                    layout,
                    splats,
                    stats,
                    rng,
                );
            }
        }
        scratch.stack.clear();
        scratch.stack.push(Photon {
            ray: emitted.ray,
            frame_x: any_perpendicular(emitted.ray.dir),
            flux: B::unpolarized(flux),
            depth: 0,
            through_specular: false,
            after_diffuse: false,
        });
        // The photon on top is traced where it lies and copied off the stack only after: its
        // push wrote it field by field a moment ago, and a copy right away read those narrow
        // stores back with wide loads, which the processor cannot forward (a stall of about a
        // dozen cycles per ray). For the same reason the hit is read where `intersect` left it.
        while let Some(last) = scratch.stack.len().checked_sub(1) {
            stats.rays += 1;
            let found = self.scene.geometry.intersect(&scratch.stack[last].ray, f32::INFINITY);
            let photon = scratch.stack[last];
            scratch.stack.truncate(last);
            let Some(hit) = found.as_ref() else { continue };
            let surface = self.scene.surfaces[hit.prim as usize];
            match &self.scene.materials[surface.material as usize] {
                Material::Black => {}
                // Paths whose first interaction is diffuse (L D) are the camera side's, unless
                // this tracer counts everything.
                Material::Diffuse(_) if !photon.through_specular && !self.everything => {}
                Material::Diffuse(diffuse) if !self.interreflection => {
                    self.connect(diffuse, hit, &photon, wavelengths, layout, splats, stats, rng);
                }
                // With interreflection this vertex is interaction depth + 1 (module docs).
                Material::Diffuse(_) if photon.depth >= self.max_depth => {}
                Material::Diffuse(diffuse) => {
                    self.connect(diffuse, hit, &photon, wavelengths, layout, splats, stats, rng);
                    if photon.depth + 1 < self.max_depth {
                        self.scatter(diffuse, hit, &photon, wavelengths, reference, scratch, rng);
                    }
                }
                _ if photon.depth >= self.max_depth => {}
                Material::Mirror(mirror) => {
                    let dir = photon.ray.dir;
                    let cos_theta_i = dir.dot(hit.shading_normal);
                    let mueller = super::mirror_mueller::<B>(self.fault, mirror, cos_theta_i, wavelengths);
                    let s = if B::POLARIZED {
                        s_axis(hit.shading_normal, dir, photon.frame_x)
                    } else {
                        photon.frame_x
                    };
                    let flux =
                        photon.flux.rotated(rotation(self.fault, dir, photon.frame_x, s)).through(&mueller);
                    let out = reflect(dir, hit.shading_normal).normalize();
                    self.push(scratch, hit, out, s, flux, &photon, true, reference, rng);
                }
                Material::Dielectric(dielectric) => {
                    let glass = (surface.material, dielectric);
                    self.dielectric(glass, hit, &photon, wavelengths, reference, scratch, rng);
                }
                Material::Film(film) => self.film(film, hit, &photon, wavelengths, reference, scratch, rng),
                Material::Polarizer(polarizer) => {
                    let dir = photon.ray.dir;
                    let axis = polarizer.transmission_axis(hit.normal, dir);
                    let mueller = Mueller::splat(JonesDiagonal::linear_polarizer(1.0))
                        .scaled(polarizer.transmittance.sample(wavelengths));
                    self.sheet(scratch, hit, &photon, axis, &mueller, reference, rng);
                }
                Material::Retarder(retarder) => {
                    let dir = photon.ray.dir;
                    let axis = retarder.fast_axis_across(hit.normal, dir);
                    let mueller = Mueller::splat(element(
                        self.fault,
                        JonesDiagonal::linear_retarder(retarder.retardance_rad),
                    ));
                    self.sheet(scratch, hit, &photon, axis, &mueller, reference, rng);
                }
            }
        }
    }

    /// A sheet: the path continues straight through, its flux filtered in the sheet's frame.
    #[allow(clippy::too_many_arguments)] // the path's state, passed flat
    fn sheet<B: Beam>(
        &self,
        scratch: &mut Scratch<B>,
        hit: &Hit,
        photon: &Photon<B>,
        axis: Vec3,
        mueller: &Mueller,
        reference: f32,
        rng: &mut LightPathRng,
    ) {
        let dir = photon.ray.dir;
        let axis = if B::POLARIZED { axis } else { photon.frame_x };
        let flux = photon.flux.rotated(rotation(self.fault, dir, photon.frame_x, axis)).through(mueller);
        self.push(scratch, hit, dir, axis, flux, photon, photon.through_specular, reference, rng);
    }

    /// Pushes the continuation of `parent` leaving `hit` along `dir` with `flux` in the frame
    /// `frame_x`, after Russian roulette: when its flux is below `prune_below` of the path's
    /// starting flux `reference`, or, once the path has left a diffuse surface, whenever its
    /// flux is below `reference` (module docs, "Interreflection").
    #[allow(clippy::too_many_arguments)] // the path's state, passed flat
    fn push<B: Beam>(
        &self,
        scratch: &mut Scratch<B>,
        hit: &Hit,
        dir: Vec3,
        frame_x: Vec3,
        flux: B,
        parent: &Photon<B>,
        through_specular: bool,
        reference: f32,
        rng: &mut LightPathRng,
    ) {
        let flux = match self.shading_adjoint(hit, -parent.ray.dir, dir) {
            None => flux,
            Some(factor) if factor.is_finite() => flux.scaled(SampledSpectrum::splat(factor)),
            Some(_) => return,
        };
        let strength = flux.components()[0].max_value() / reference;
        if strength.is_nan() || strength <= 0.0 {
            return;
        }
        let mut flux = flux;
        if parent.after_diffuse && strength < 1.0 {
            let survive = strength;
            if rng.uniform() >= survive {
                return;
            }
            flux = flux.scaled(SampledSpectrum::splat(1.0 / survive));
        } else if strength < self.prune_below {
            let survive = strength / self.prune_below;
            if rng.uniform() >= survive {
                return;
            }
            flux = flux.scaled(SampledSpectrum::splat(1.0 / survive));
        }
        scratch.stack.push(Photon {
            ray: Ray::new(spawn_origin(hit.point, hit.normal, dir), dir),
            frame_x,
            flux,
            depth: parent.depth + 1,
            through_specular,
            after_diffuse: parent.after_diffuse,
        });
    }

    /// Whether `hit`'s shading normal differs from its geometric one and the light side corrects
    /// for it ([`Self::shading_adjoint`]).
    fn corrects_shading(&self, hit: &Hit) -> bool {
        hit.shading_normal != hit.normal && self.fault != Some(Fault::NoShadingNormalAdjoint)
    }

    /// Veach's correction for the adjoint of a shading normal (thesis §5.3): a path leaving `hit`
    /// along `out` after arriving from `to_light` (the direction back along the arriving
    /// segment) carries flux, and a shading normal N_s tilted off the geometric normal N_g makes
    /// the adjoint of the camera side's BSDF f(ω_o → ω_i)·|ω_i·N_s| the light side's
    /// f·|ω_i·N_s|·|ω_o·N_g|/(|ω_i·N_g|·|ω_o·N_s|) with ω_i = `to_light`, ω_o = `out`: the factor
    /// returned. `None` where the two normals are one (every flat shape), so nothing changes
    /// there, nor under `Fault::NoShadingNormalAdjoint`. Straight through a sheet it is 1; a
    /// direction grazing N_g or N_s makes it infinite or NaN (the caller drops the path).
    fn shading_adjoint(&self, hit: &Hit, to_light: Vec3, out: Vec3) -> Option<f32> {
        if !self.corrects_shading(hit) {
            return None;
        }
        let (geometric, shading) = (hit.normal, hit.shading_normal);
        Some(
            (to_light.dot(shading) * out.dot(geometric) / (to_light.dot(geometric) * out.dot(shading))).abs(),
        )
    }

    /// A dielectric: Beer–Lambert over the segment just crossed inside, then both Fresnel
    /// branches at the path's first interaction, one chosen by flux after; a dispersive
    /// refraction continues every live lane on its own direction. `glass` is the material (its
    /// number and itself).
    #[allow(clippy::too_many_arguments)] // the path's state, passed flat
    fn dielectric<B: Beam>(
        &self,
        (material, dielectric): (u32, &Dielectric),
        hit: &Hit,
        photon: &Photon<B>,
        wavelengths: &SampledWavelengths,
        reference: f32,
        scratch: &mut Scratch<B>,
        rng: &mut LightPathRng,
    ) {
        let dir = photon.ray.dir;
        let from_inside = dir.dot(hit.normal) > 0.0;
        let flux = match (&dielectric.absorption, from_inside) {
            (Some(sigma), true) => photon.flux.scaled((sigma.sample(wavelengths) * -hit.t).exp()),
            _ => photon.flux,
        };
        let normal = hit.shading_normal;
        let cos_theta_i = -dir.dot(normal);
        // The lanes still carrying light, as bits (lane i: bit i).
        let live = flux.components()[0].positive_lanes();
        let live_count = live.count_ones();
        if live_count == 0 {
            return;
        }
        let fresnel_at = |lane: usize| {
            let ior = self.indices.ior(material, dielectric, wavelengths.lambda_nm(lane));
            fresnel(self.fault, cos_theta_i, ior)
        };
        // Both branches leave in the s frame of this incidence, where the Fresnel matrices are
        // diagonal.
        let s = if B::POLARIZED { s_axis(normal, dir, photon.frame_x) } else { photon.frame_x };
        let incident = flux.rotated(rotation(self.fault, dir, photon.frame_x, s));
        let branches = Branches { hit, photon, reference, frame_x: s };
        // A coating replaces both branches' matrices, lane by lane; the directions stay the
        // bare interface's, and refraction still carries flux (no 1/η²).
        let coated = dielectric.is_coated().then(|| {
            coated_matrices::<B>(self.fault, dielectric, cos_theta_i, wavelengths, live, |lane| {
                self.indices.ior(material, dielectric, wavelengths.lambda_nm(lane))
            })
        });
        let with_coating = |transmission: Mueller, f: &DielectricFresnel| match &coated {
            Some((_, flux)) if self.fault == Some(Fault::LightPathRadianceScaling) => {
                flux.scaled(SampledSpectrum::splat(1.0 / (f.eta_it * f.eta_it)))
            }
            Some((_, flux)) => *flux,
            None => transmission,
        };

        if !dielectric.ior.is_dispersive() || live_count == 1 {
            // One index for every live lane: one Fresnel evaluation and one refracted direction
            // (the common case, kept free of per-lane arrays).
            let first_live = live.trailing_zeros() as usize;
            let f = fresnel_at(first_live);
            let reflection = if let Some((coated_reflection, _)) = coated {
                coated_reflection
            } else if B::POLARIZED {
                Mueller::splat(element(self.fault, JonesDiagonal::dielectric_reflection(cos_theta_i, &f)))
            } else {
                Mueller::attenuation(SampledSpectrum::splat(f.reflectance))
            };
            let refracted = self
                .transmission::<B>(dir, normal, &f)
                .map(|(dir_t, transmission)| (dir_t, incident.through(&with_coating(transmission, &f))));
            self.choose_branch::<B>(
                &branches,
                incident.through(&reflection),
                std::slice::from_ref(&refracted),
                scratch,
                rng,
            );
            return;
        }

        let fresnels: [_; N_LAMBDA] = std::array::from_fn(fresnel_at);
        let reflection = if let Some((coated_reflection, _)) = coated {
            coated_reflection
        } else if B::POLARIZED {
            Mueller::from_lanes(
                &fresnels.map(|f| element(self.fault, JonesDiagonal::dielectric_reflection(cos_theta_i, &f))),
            )
        } else {
            Mueller::attenuation(SampledSpectrum { values: fresnels.map(|f| f.reflectance) })
        };
        let mut refracted: [Option<(Vec3, B)>; N_LAMBDA] = [None; N_LAMBDA];
        for lane in (0..N_LAMBDA).filter(|&i| live & (1 << i) != 0) {
            if let Some((dir_t, transmission)) = self.transmission::<B>(dir, normal, &fresnels[lane]) {
                let transmission = with_coating(transmission, &fresnels[lane]);
                refracted[lane] = Some((dir_t, incident.only_lane(lane).through(&transmission)));
            }
        }
        self.choose_branch::<B>(&branches, incident.through(&reflection), &refracted, scratch, rng);
    }

    /// A free-standing film: its reflection and its straight-through transmission, as flux (air
    /// on both sides: nothing to scale), continued as glass's branches are
    /// ([`Self::choose_branch`]: both at the path's first interaction, one chosen by flux after).
    #[allow(clippy::too_many_arguments)] // the path's state, passed flat
    fn film<B: Beam>(
        &self,
        film: &Film,
        hit: &Hit,
        photon: &Photon<B>,
        wavelengths: &SampledWavelengths,
        reference: f32,
        scratch: &mut Scratch<B>,
        rng: &mut LightPathRng,
    ) {
        let dir = photon.ray.dir;
        let live = photon.flux.components()[0].positive_lanes();
        if live == 0 {
            return;
        }
        let normal = hit.shading_normal;
        let cos_theta_i = -dir.dot(normal);
        let thickness_nm = film.thickness.at(hit.point);
        let (reflection, transmission) =
            film_matrices::<B>(self.fault, film, cos_theta_i, thickness_nm, wavelengths, live);
        let s = if B::POLARIZED { s_axis(normal, dir, photon.frame_x) } else { photon.frame_x };
        let incident = photon.flux.rotated(rotation(self.fault, dir, photon.frame_x, s));
        let branches = Branches { hit, photon, reference, frame_x: s };
        let straight = Some((dir, incident.through(&transmission)));
        self.choose_branch::<B>(
            &branches,
            incident.through(&reflection),
            std::slice::from_ref(&straight),
            scratch,
            rng,
        );
    }

    /// The refracted direction and the Mueller matrix of a refraction with Fresnel terms `f`, or
    /// `None` under total internal reflection. Refraction carries flux: (1 − R) without the
    /// camera side's 1/η² (unless the validation fault puts it back).
    fn transmission<B: Beam>(
        &self,
        dir: Vec3,
        normal: Vec3,
        f: &DielectricFresnel,
    ) -> Option<(Vec3, Mueller)> {
        let (refracted, flux) = refraction::<B>(dir, normal, f)?;
        if self.fault == Some(Fault::LightPathRadianceScaling) {
            return Some((refracted, flux.scaled(SampledSpectrum::splat(1.0 / (f.eta_it * f.eta_it)))));
        }
        Some((refracted, flux))
    }

    /// Continues a path at a dielectric: at its first interaction along both branches,
    /// `reflected` and all of `refracted` (one entry per lane that refracts on its own
    /// direction, or one for all), each with its own flux; after that along one of the two,
    /// chosen with probability proportional to its flux (summed over the lanes) and divided by
    /// that probability (module docs, "Branches at glass").
    fn choose_branch<B: Beam>(
        &self,
        at: &Branches<B>,
        reflected: B,
        refracted: &[Option<(Vec3, B)>],
        scratch: &mut Scratch<B>,
        rng: &mut LightPathRng,
    ) {
        let total = |beam: &B| beam.components()[0].values.iter().sum::<f32>();
        let reflected_flux = total(&reflected);
        let refracted_flux: f32 = refracted.iter().flatten().map(|(_, beam)| total(beam)).sum();
        let all = reflected_flux + refracted_flux;
        if all.is_nan() || all <= 0.0 {
            return;
        }
        if at.photon.depth == 0 {
            self.push(
                scratch,
                at.hit,
                at.reflected(),
                at.frame_x,
                reflected,
                at.photon,
                true,
                at.reference,
                rng,
            );
            for (dir_t, beam) in refracted.iter().flatten() {
                self.push(scratch, at.hit, *dir_t, at.frame_x, *beam, at.photon, true, at.reference, rng);
            }
            return;
        }
        let p_reflect = reflected_flux / all;
        if rng.uniform() < p_reflect {
            let flux = reflected.scaled(SampledSpectrum::splat(1.0 / p_reflect));
            self.push(scratch, at.hit, at.reflected(), at.frame_x, flux, at.photon, true, at.reference, rng);
        } else {
            let scale = SampledSpectrum::splat(1.0 / (1.0 - p_reflect));
            for (dir_t, beam) in refracted.iter().flatten() {
                self.push(
                    scratch,
                    at.hit,
                    *dir_t,
                    at.frame_x,
                    beam.scaled(scale),
                    at.photon,
                    true,
                    at.reference,
                    rng,
                );
            }
        }
    }

    /// Continues a path from a diffuse surface (interreflection): a direction drawn by the
    /// cosine density about the normal on the side the light arrived from, the flux depolarised
    /// and multiplied by f·cos θ/pdf = ρ(λ)·[`Diffuse::shape_factor`] (the BRDF with its
    /// directions swapped: Lambert and Oren–Nayar's qualitative model are symmetric in them).
    #[allow(clippy::too_many_arguments)] // the path's state, passed flat
    fn scatter<B: Beam>(
        &self,
        diffuse: &Diffuse,
        hit: &Hit,
        photon: &Photon<B>,
        wavelengths: &SampledWavelengths,
        reference: f32,
        scratch: &mut Scratch<B>,
        rng: &mut LightPathRng,
    ) {
        let to_light = -photon.ray.dir;
        let (normal, shading_normal) = lit_side(hit, to_light);
        // The camera side gathers light only from directions above the shading normal too.
        if self.corrects_shading(hit) && shading_normal.dot(to_light) <= 0.0 {
            return;
        }
        let u = (rng.uniform(), rng.uniform());
        let (dir, _pdf) = Diffuse::sample(shading_normal, u);
        // A shading normal tilted off the geometric one can aim a sample into the surface.
        if dir.dot(normal) <= 0.0 {
            return;
        }
        let weight = diffuse.albedo.sample(wavelengths) * diffuse.shape_factor(shading_normal, to_light, dir);
        let flux = B::unpolarized(photon.flux.components()[0] * weight);
        let scattered = Photon { after_diffuse: true, ..*photon };
        self.push(scratch, hit, dir, any_perpendicular(dir), flux, &scattered, true, reference, rng);
    }

    /// Connects a path arriving at a diffuse surface to the camera and adds what the camera
    /// sees to `splats`.
    #[allow(clippy::too_many_arguments)] // the path's state, passed flat
    fn connect<B: Beam>(
        &self,
        diffuse: &Diffuse,
        hit: &Hit,
        photon: &Photon<B>,
        wavelengths: &SampledWavelengths,
        layout: &FilmLayout,
        splats: &mut Splats,
        stats: &mut TraceStats,
        rng: &mut LightPathRng,
    ) {
        let camera = &self.scene.camera;
        let Some(seen) = camera.project(hit.point, || (rng.uniform(), rng.uniform())) else { return };
        // Shade the side the light arrives on; the camera must be on it too.
        let to_light = -photon.ray.dir;
        let (normal, shading_normal) = lit_side(hit, to_light);
        let to_camera = seen.to_camera;
        let cos_camera = if self.corrects_shading(hit) {
            // f·|ω_o·N_s| times the adjoint's factor (`shading_adjoint`): the light's cosine on
            // the shading normal over its cosine on the geometric one, times the camera's on
            // the geometric one; the camera side gathers only light from above the shading
            // normal.
            if shading_normal.dot(to_light) <= 0.0 {
                return;
            }
            normal.dot(to_camera) * (shading_normal.dot(to_light) / normal.dot(to_light))
        } else if shading_normal.dot(to_camera) <= 0.0 {
            return;
        } else {
            shading_normal.dot(to_camera)
        };
        if !(cos_camera > 0.0 && cos_camera.is_finite()) || normal.dot(to_camera) <= 0.0 {
            return;
        }
        let cosine = if self.fault == Some(Fault::NoReceiverCosine) { 1.0 } else { cos_camera };
        let brdf = diffuse.albedo.sample(wavelengths)
            * (std::f32::consts::FRAC_1_PI * diffuse.shape_factor(shading_normal, to_light, to_camera));
        let radiance = photon.flux.components()[0] * brdf * (cosine * seen.sensitivity);
        let origin = spawn_origin(hit.point, normal, to_camera);
        self.send_to_camera::<B>(origin, &seen, radiance, wavelengths, layout, splats, stats);
    }

    /// Connects the start of a light path on a quad light (its ray `leaving`, from just off the
    /// emitting side) to the camera (L E, [`Self::counting_everything`] only): the pixel it
    /// lands in gains L·cos θ_y/(p(y)·p(light)) times the camera's sensitivity, with
    /// `radiance_weight` = L/(p(y)·p(light)) (W·sr⁻¹·m⁻²·nm⁻¹ times m²). The emission is
    /// unpolarised.
    #[allow(clippy::too_many_arguments)] // the connection's state, passed flat
    fn connect_light<B: Beam>(
        &self,
        light: usize,
        leaving: &Ray,
        radiance_weight: SampledSpectrum,
        wavelengths: &SampledWavelengths,
        layout: &FilmLayout,
        splats: &mut Splats,
        stats: &mut TraceStats,
        rng: &mut LightPathRng,
    ) {
        let Light::Quad(quad) = &self.scene.lights[light] else { return };
        let Some(seen) = self.scene.camera.project(leaving.origin, || (rng.uniform(), rng.uniform())) else {
            return;
        };
        // One-sided: the camera must be on the emitting side.
        let cos_light = quad.emit_normal.dot(seen.to_camera);
        if cos_light <= 0.0 {
            return;
        }
        let radiance = radiance_weight * (cos_light * seen.sensitivity);
        self.send_to_camera::<B>(leaving.origin, &seen, radiance, wavelengths, layout, splats, stats);
    }

    /// Sends the unpolarised `radiance` (what the pixel `seen` gains, before occlusion) from
    /// `origin` to the camera: nothing when something blocks the way, filtered by the
    /// polarising sheets crossed, and added to `splats`.
    #[allow(clippy::too_many_arguments)] // the connection's state, passed flat
    fn send_to_camera<B: Beam>(
        &self,
        origin: Vec3,
        seen: &FilmPoint,
        radiance: SampledSpectrum,
        wavelengths: &SampledWavelengths,
        layout: &FilmLayout,
        splats: &mut Splats,
        stats: &mut TraceStats,
    ) {
        let camera = &self.scene.camera;
        let to_camera = seen.to_camera;
        let mut light = B::unpolarized(radiance);
        let remaining = seen.distance * (1.0 - CONNECTION_SHORTENING);
        if !self.has_sheets {
            stats.rays += 1;
            if self.scene.geometry.occluded(&Ray::new(origin, to_camera), remaining) {
                return;
            }
        } else {
            // Sheets between the receiver and the camera filter the (unpolarised) light.
            let (mut origin, mut remaining, mut frame_x) = (origin, remaining, any_perpendicular(to_camera));
            let mut crossed = 0;
            loop {
                stats.rays += 1;
                let Some(blocker) = self.scene.geometry.intersect(&Ray::new(origin, to_camera), remaining)
                else {
                    break;
                };
                let material =
                    &self.scene.materials[self.scene.surfaces[blocker.prim as usize].material as usize];
                let (axis, mueller) = match material {
                    Material::Polarizer(polarizer) => (
                        polarizer.transmission_axis(blocker.normal, to_camera),
                        Mueller::splat(JonesDiagonal::linear_polarizer(1.0))
                            .scaled(polarizer.transmittance.sample(wavelengths)),
                    ),
                    Material::Retarder(retarder) => (
                        retarder.fast_axis_across(blocker.normal, to_camera),
                        Mueller::splat(element(
                            self.fault,
                            JonesDiagonal::linear_retarder(retarder.retardance_rad),
                        )),
                    ),
                    _ => return,
                };
                crossed += 1;
                if crossed > MAX_SHEETS_PER_CONNECTION {
                    return;
                }
                let axis = if B::POLARIZED { axis } else { frame_x };
                light = light.rotated(rotation(self.fault, to_camera, frame_x, axis)).through(&mueller);
                frame_x = axis;
                remaining -= blocker.t;
                origin = spawn_origin(blocker.point, blocker.normal, to_camera);
            }
            if B::POLARIZED {
                let camera_x = camera.stokes_x(-to_camera);
                light = light.rotated(rotation(self.fault, to_camera, frame_x, camera_x));
            }
        }
        splats.add(seen.pixel, &light, wavelengths, layout);
    }
}

/// The geometric and shading normals of `hit` on the side `to_light` (the direction back along
/// the arriving path) lies on: the side a diffuse surface reflects the light to.
fn lit_side(hit: &Hit, to_light: Vec3) -> (Vec3, Vec3) {
    if hit.normal.dot(to_light) >= 0.0 {
        (hit.normal, hit.shading_normal)
    } else {
        (-hit.normal, -hit.shading_normal)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polarization::Stokes;
    use crate::sampler::LightPathSequence;

    /// A diffuse floor of albedo 0.6.
    const FLOOR: &str = r#"
[camera]
position = [0, 3, -5]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov_y_deg = 40
width = 8
height = 8

[materials.floor]
type = "diffuse"
albedo = { value = 0.6 }

[[shapes]]
type = "plane"
point = [0, 0, 0]
normal = [0, 1, 0]
material = "floor"
"#;

    /// A diffuse vertex depolarises: fully polarised light (S1 = 0.8·S0, S3 = 0.6·S0, so
    /// S1² + S3² = S0²) arriving at the floor leaves it with S1–S3 zero and S0 times the albedo 0.6 (Lambert: f·cos θ/pdf = ρ), on the side it came from,
    /// one interaction deeper. With the path's starting flux equal to what leaves, the
    /// roulette keeps it as it is.
    #[test]
    fn a_diffuse_bounce_depolarises_and_weighs_by_the_albedo() {
        let scene = crate::scene::parse(FLOOR, std::path::Path::new("floor.toml")).unwrap();
        let tracer = LightTracer::new(&scene, &scene.settings, Some(550.0)).with_interreflection(true);
        let wavelengths = SampledWavelengths::monochromatic(550.0);
        let Material::Diffuse(diffuse) = &scene.materials[0] else { panic!("the floor is diffuse") };
        let arriving = Vec3::new(0.6, -0.8, 0.0);
        let hit = Hit { t: 1.0, point: Vec3::ZERO, normal: Vec3::Y, shading_normal: Vec3::Y, prim: 0 };
        let s0 = SampledSpectrum::splat(2.0);
        let photon = Photon {
            ray: Ray::new(Vec3::new(-0.6, 0.8, 0.0), arriving),
            frame_x: Vec3::Z,
            flux: Stokes { s: [s0, s0 * 0.8, SampledSpectrum::zero(), s0 * 0.6] },
            depth: 2,
            through_specular: true,
            after_diffuse: false,
        };
        let sequence = LightPathSequence::new(0);
        for path in 0..64 {
            let mut rng = sequence.path(path);
            let mut scratch = Scratch::<Stokes>::default();
            tracer.scatter(diffuse, &hit, &photon, &wavelengths, 1.2, &mut scratch, &mut rng);
            let [left] = scratch.stack.as_slice() else {
                panic!("one continuation, got {}", scratch.stack.len())
            };
            assert!((left.flux.s[0][0] - 1.2).abs() < 1e-6, "{:?}", left.flux);
            assert!(left.flux.s[1..].iter().all(|s| s.is_zero()), "{:?}", left.flux);
            assert!(left.ray.dir.y > 0.0 && left.ray.origin.y > 0.0);
            assert!((left.frame_x.dot(left.ray.dir)).abs() < 1e-6);
            assert_eq!((left.depth, left.through_specular, left.after_diffuse), (3, true, true));
        }
    }
}
