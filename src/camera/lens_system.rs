//! [`LensCamera`]: a camera made of real glass, a lens prescription ([`crate::lens`]) in front
//! of a sensor, traced per wavelength from the sensor out into the scene.
//!
//! ```toml
//! [camera]
//! position = [0, 1, -4]       # the lens's first vertex (scene units, metres)
//! look_at = [0, 1, 0]
//! up = [0, 1, 0]
//! lens = "../data/lenses/dgauss50.dat"  # pbrt-v4 lens file or Zemax .zmx, relative to the scene
//! sensor_height_mm = 24       # the image's height on the sensor (mm); width from the aspect
//! focus_distance = 4          # metres from the first vertex; absent: infinity
//! f_number = 2.8              # optional: stop down (never wider than the stop's semi-diameter)
//! lens_ghosts = 0             # optional: the most ghost reflections a camera ray may take
//! lens_lanes = "per_lane"     # optional: or "shared" (one scene path per camera sample)
//! width = 320
//! height = 240
//! ```
//!
//! **Geometry.** The lens's axis +z (object toward image, [`crate::lens`]) is the view's
//! reverse: lens −z is the view direction (`look_at − position`), lens +y the camera's up and
//! lens +x the image's right (a rotation, no mirror: x × y = z maps to right × up =
//! −forward). The first vertex sits at `position`; lens millimetres are scene metres / 1000.
//! The sensor is behind the lens (toward +z), at the image plane of the prescription after
//! focusing.
//!
//! **Upright image.** A real lens forms an inverted image: the sensor point at (+x, +y) sees
//! the scene toward (−x, −y). As a camera's processing does, the image is turned by 180°: the
//! pixel at film position (u right, v up) from the image centre, in mm on the sensor, reads
//! the sensor point (−u, −v). So the image shows the scene as the pinhole does: upright, not
//! mirrored.
//!
//! **Focus.** By moving the sensor: the prescription's last thickness becomes
//! [`LensSystem::focus_thickness_mm`] of an object `focus_distance` (m → mm) in front of the
//! first vertex, at the d line ([`LAMBDA_D_NM`], 587.5618 nm). Other wavelengths focus where
//! the glass puts them (the chromatic focal shift shows in the render).
//!
//! **Radiometry.** Each camera ray's weight is [`crate::lens::CameraRay::weight`]: the sensor
//! weight normalised so that a constant radiance L through the ideal lossless twin of the lens
//! reads L at the image centre, times the lens's transmission along the ray (Fresnel losses at
//! every surface; vignetting and cos⁴ falloff elsewhere). A ray that misses the lens
//! contributes 0.
//!
//! **One scene path per camera sample** (`lens_lanes = "shared"`, [`LanePaths`]; issue 40,
//! "Speed"; without ghosts). Each wavelength leaves the lens on its own direction, so by
//! default every lane traces its own ray and its own scene path. With `"shared"` the lanes
//! share the hero lane's ray instead, an exact (unbiased) estimate by spectral multiple
//! importance sampling through the lens's inverse map (hero wavelength sampling, Wilkie et al.
//! 2014, with the lens map as the wavelength-dependent part):
//! - *Measure.* Rays carry étendue dμ = cos θ dA dω, which refraction conserves exactly
//!   (n² dμ is invariant; sensor and scene are both in air, n = 1), so the lens map T_λ from
//!   sensor rays to scene rays preserves μ at every λ. A camera ray from sensor point p to
//!   rear-vertex-plane point t ([`crate::lens::pupil`]: Δ the sensor's distance behind that
//!   plane, θ the ray's angle to the axis) has dA_p dA_t = Δ²/cos⁴θ dμ.
//! - *Pixel value for lane j* (box pixel of area A on the sensor, K the normalisation):
//!   I_j = (1/(K A)) ∫ 1[p_j(r) ∈ pixel] τ_j(r) L_j(r) dμ(r) over scene rays r, (p_j, t_j)
//!   the preimage T_λj⁻¹(r), τ_j the lens's transmission along it (the Mueller matrix when
//!   polarised; 0 when blocked).
//! - *Sampling.* The hero h is uniform among the N lanes (its own number, dimension 5 of the
//!   pixel's sequence: the lanes' wavelengths do not depend on h, and a fixed hero would miss
//!   light whose hero preimage falls outside the pixel or the pupil bounds), p uniform in the
//!   pixel, t from the pupil sampler (pdf_t), traced forward at λ_h to r (hero blocked: the
//!   sample adds 0). With lane k as hero, r has density per μ
//!   q_k(r) = (1/A) 1[p_k ∈ pixel] pdf_t(t_k | p_k) Δ²/cos⁴θ_k.
//! - *Estimate* for lane j: f_j(r)/((1/N) Σ_k q_k(r)) with f_j = 1[p_j ∈ pixel] τ_j L_j/(K A):
//!   the one-sample balance heuristic over the N strategies, unbiased wherever some q_k > 0
//!   covers f_j > 0 (q_j does, up to the pupil bounds' own approximation). A cancels; with
//!   all preimages equal (a lens without dispersion) it is the per-lane weight
//!   cos⁴θ/(Δ² pdf_t K) τ_j (tested).
//! - *Preimages.* The other lanes' (p_k, t_k) come from tracing r backward through the lens
//!   ([`crate::lens::reverse`]), one lens trace per lane, which gives τ_k (or the Mueller
//!   matrix) of the same path; the hero's are its forward trace's. Then one integrator call
//!   with all the lanes live, each lane's light times its weight.
//!
//! The images differ from the per-lane estimator's by noise only (tests/lens_hero.rs compares
//! the two region by region through the N-BK7 singlet and the double Gauss, and the fault
//! `LensHeroPdfOnly` fails there); with one lane, or a lens of more than
//! [`MAX_REVERSE_SURFACES`] surfaces, each lane keeps its own ray and path.
//!
//! *Why it is not the default* (validation/bench/RESULTS.md, "Lens-system camera against the
//! pinhole"): it saves the scene paths, not the lens: a camera sample still traces the lens
//! once per lane (the hero out, one scalar trace; the others back, in SIMD with their Mueller
//! matrices, [`crate::lens::LensTracer::trace_lanes_back_to_sensor`]), while the per-lane
//! default traces its 8 lanes out in one SIMD trace
//! ([`crate::lens::LensTracer::trace_lanes_from_sensor`]), so the two cost about the same per
//! sample on `scenes/lens_dgauss50.toml` (8.0× and 8.3× the pinhole, 16 spp). What the shared
//! path saves is paid for in noise: the lanes' preimages of one scene ray fall up to a few
//! pixels apart (the double Gauss's colour: at 360×240, 59 % of its camera samples have a lane
//! whose preimage leaves the pixel or is blocked), each such lane adds 0 while the others
//! carry more, and one scene path instead of eight leaves the scene's own noise undivided
//! (relMSE 2.5× the per-lane's at equal spp). So on `scenes/lens_dgauss50.toml` it is 2.1–2.6×
//! slower to equal error; on a scene whose paths cost more than the lens (the glass-and-mirror
//! room, max_depth 64) it is 1.6× faster per sample.
//!
//! **Polarisation.** In a polarised render the Stokes vector arriving along the ray goes
//! through the lens's Mueller matrix (every surface's exact s/p Fresnel transmission, the
//! frames turned between surfaces) into the sensor's frame.
//!
//! **Refused with it** (one-line errors): `fov_y_deg` (the lens and sensor set the field),
//! `aperture_radius` (a thin lens), caustics (light paths cannot be connected to the camera
//! through glass), and `lens_lanes = "shared"` with ghosts (a ghost path's branch choices are
//! its own lane's).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DVec3, Vec3};

use super::{CameraError, Pinhole};
use crate::geometry::Ray;
use crate::lens::trace::MAX_LANES;
use crate::lens::{
    read_lens_file, CameraRay, LensSample, LensSystem, PupilSample, SensorSampler, TraceOptions, LAMBDA_D_NM,
    MAX_REVERSE_SURFACES,
};

// A camera sample's wavelength lanes are traced together.
const _: () = assert!(MAX_LANES >= crate::spectrum::N_LAMBDA);

/// Millimetres per scene unit (metre).
const MM_PER_METRE: f64 = 1000.0;

/// What the `[camera]` table says about the lens, besides the pinhole's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct LensSettings {
    /// The lens file (pbrt-v4 `.dat` or Zemax `.zmx`), as resolved against the scene's folder.
    pub lens: PathBuf,
    /// The image's height on the sensor (mm).
    pub sensor_height_mm: f64,
    /// Distance of the plane in focus from the first vertex (scene units, metres);
    /// `f64::INFINITY` for infinity.
    pub focus_distance_m: f64,
    /// Stop down to this f-number (for an object at infinity, at the d line); `None`: as the
    /// prescription is.
    pub f_number: Option<f64>,
    /// The most ghost reflections a camera ray may take (0: the transmitted path only).
    pub max_ghost_reflections: u32,
}

/// A lens-system camera: the pinhole's frame and resolution, a lens focused and stopped down as
/// [`LensSettings`] say, and its sampler (exit-pupil bounds and normalisation, measured once).
#[derive(Clone, Debug)]
pub struct LensCamera {
    /// Frame and resolution; its field of view is the paraxial one of the sensor at the d
    /// line (for the chief-ray approximation [`super::Camera::ray`]).
    pinhole: Pinhole,
    settings: LensSettings,
    sampler: Arc<SensorSampler>,
    /// The image's width on the sensor (mm): the height times the aspect ratio.
    sensor_width_mm: f64,
    /// How the lanes of a camera sample find their scene paths.
    lane_paths: LanePaths,
}

/// How the wavelength lanes of a lens camera's sample find their scene paths (see the module
/// header, "One scene path per camera sample").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LanePaths {
    /// Each lane its own ray through the lens and its own scene path
    /// ([`LensCamera::sample_rays_for_lanes`]): the default (`lens_lanes = "per_lane"`).
    PerLane,
    /// One scene path for all the lanes, along the hero lane's ray, weighted by spectral MIS
    /// ([`LensCamera::sample_shared_path`]; `lens_lanes = "shared"`), used when the lens has no
    /// ghosts and at most [`MAX_REVERSE_SURFACES`] surfaces (otherwise as `PerLane`).
    Shared,
}

/// One camera sample of [`LensCamera::sample_shared_path`]: the scene ray all the lanes share
/// and, per lane, the weights of what comes back along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeroSample {
    /// The scene ray (the hero lane's, out of the lens).
    pub ray: Ray,
    /// The lane's weights (`None`: it adds 0): [`CameraRay::weight`] multiplies the radiance
    /// of unpolarised light, `sensor_weight` × `sample.mueller` the Stokes vector arriving
    /// along the ray (frames as [`LensCamera::sample_ray`]'s).
    pub lanes: [Option<CameraRay>; MAX_LANES],
}

impl PartialEq for LensCamera {
    fn eq(&self, other: &Self) -> bool {
        // The sampler is a function of the settings and the file.
        self.pinhole == other.pinhole
            && self.settings == other.settings
            && self.lane_paths == other.lane_paths
    }
}

impl LensCamera {
    /// Reads `settings.lens`, focuses it, stops it down and measures its sampler, for a camera
    /// at `position` looking at `look_at` with `up`, of `width`×`height` pixels.
    ///
    /// # Errors
    /// The lens reader's error (naming the file and line), a focus the lens cannot reach, an
    /// f-number wider than the stop allows, or a degenerate frame.
    pub fn new(
        position: Vec3,
        look_at: Vec3,
        up: Vec3,
        width: u32,
        height: u32,
        settings: LensSettings,
    ) -> Result<Self, CameraError> {
        let lens_error = |message: String| CameraError::Lens(message);
        if !(settings.sensor_height_mm > 0.0 && settings.sensor_height_mm.is_finite()) {
            return Err(lens_error(format!(
                "sensor_height_mm must be positive and finite, got {}",
                settings.sensor_height_mm
            )));
        }
        if settings.focus_distance_m.is_nan() || settings.focus_distance_m <= 0.0 {
            return Err(CameraError::FocusDistance(settings.focus_distance_m as f32));
        }
        let mut system = read_lens_file(&settings.lens).map_err(|err| lens_error(err.to_string()))?;
        let file = settings.lens.display().to_string();
        let paraxial = system.paraxial(LAMBDA_D_NM).map_err(|err| lens_error(err.to_string()))?;
        if let Some(f_number) = settings.f_number {
            let stop = system.stop_index().ok_or_else(|| lens_error(format!("{file}: no aperture stop")))?;
            let current = system.surfaces[stop].semi_diameter_mm;
            let wanted = paraxial.stop_semi_diameter_for_f_number(f_number, current);
            if !(f_number > 0.0 && wanted.is_finite()) {
                return Err(lens_error(format!("f_number must be positive and finite, got {f_number}")));
            }
            if wanted > current * (1.0 + 1e-9) {
                return Err(lens_error(format!(
                    "f_number {f_number} opens the stop of {file} beyond its semi-diameter {current} mm \
                     (the widest is f/{:.3})",
                    paraxial.f_number
                )));
            }
            system.surfaces[stop].semi_diameter_mm = wanted;
        }
        let object_mm = settings.focus_distance_m * MM_PER_METRE;
        let thickness =
            system.focus_thickness_mm(object_mm, LAMBDA_D_NM).map_err(|err| lens_error(err.to_string()))?;
        if !(thickness > 0.0 && thickness.is_finite()) {
            return Err(lens_error(format!(
                "{file}: focused at {} m the image lies {thickness:.3} mm from the last vertex: the sensor \
                 would be inside or in front of the lens",
                settings.focus_distance_m
            )));
        }
        let last = system.surfaces.len() - 1;
        system.surfaces[last].thickness_mm = thickness;
        let fov_y_deg = (2.0 * (0.5 * settings.sensor_height_mm / paraxial.efl_mm.abs()).atan()).to_degrees();
        let pinhole = Pinhole::look_at(position, look_at, up, fov_y_deg as f32, width, height)?;
        Ok(Self::with_system(pinhole, settings, system))
    }

    /// The camera of `system` (focused and stopped down), measuring its sampler for the
    /// pinhole's resolution.
    fn with_system(pinhole: Pinhole, settings: LensSettings, system: LensSystem) -> Self {
        let sensor_width_mm = settings.sensor_height_mm * pinhole.width() as f64 / pinhole.height() as f64;
        let half_diagonal = 0.5 * sensor_width_mm.hypot(settings.sensor_height_mm);
        let sampler = Arc::new(SensorSampler::new(system, half_diagonal, LAMBDA_D_NM));
        Self { pinhole, settings, sampler, sensor_width_mm, lane_paths: LanePaths::PerLane }
    }

    /// The same camera with another resolution: the sensor height stays, the width follows the
    /// aspect ratio (the sampler is measured again when the aspect changes).
    pub fn with_resolution(&self, width: u32, height: u32) -> Result<Self, CameraError> {
        let pinhole = self.pinhole.with_resolution(width, height)?;
        if u64::from(width) * u64::from(self.pinhole.height())
            == u64::from(height) * u64::from(self.pinhole.width())
        {
            return Ok(Self { pinhole, ..self.clone() });
        }
        let resized = Self::with_system(pinhole, self.settings.clone(), self.sampler.tracer.system.clone());
        Ok(resized.with_lane_paths(self.lane_paths))
    }

    /// The same camera with its sensor moved `offset_mm` (mm) along the axis from where
    /// focusing put it (+: away from the lens), its sampler measured again: a through-focus
    /// series of one scene (tests/lens_sharpest_plane.rs). The settings stay as they were, so
    /// the scene's digest does not see the offset.
    ///
    /// # Errors
    /// When the sensor would meet or pass the last vertex.
    pub fn with_sensor_offset_mm(&self, offset_mm: f64) -> Result<Self, CameraError> {
        let mut system = self.sampler.tracer.system.clone();
        let last = system.surfaces.len() - 1;
        let thickness = system.surfaces[last].thickness_mm + offset_mm;
        if !(thickness > 0.0 && thickness.is_finite()) {
            return Err(CameraError::Lens(format!(
                "a sensor offset of {offset_mm} mm puts the sensor {thickness} mm behind the last vertex"
            )));
        }
        system.surfaces[last].thickness_mm = thickness;
        Ok(Self::with_system(self.pinhole.clone(), self.settings.clone(), system)
            .with_lane_paths(self.lane_paths))
    }

    /// The same camera with its lanes finding their scene paths as `lane_paths` says.
    pub fn with_lane_paths(&self, lane_paths: LanePaths) -> Self {
        Self { lane_paths, ..self.clone() }
    }

    /// Whether a render gives a camera sample's lanes one scene path
    /// ([`Self::sample_shared_path`]): [`LanePaths::Shared`], no ghosts, and a lens of at most
    /// [`MAX_REVERSE_SURFACES`] surfaces.
    pub fn shares_scene_path(&self) -> bool {
        self.lane_paths == LanePaths::Shared
            && self.settings.max_ghost_reflections == 0
            && self.sampler.tracer.system.surfaces.len() <= MAX_REVERSE_SURFACES
    }

    /// The frame, resolution and paraxial field, as a pinhole.
    pub fn pinhole(&self) -> &Pinhole {
        &self.pinhole
    }

    /// The settings it was made from.
    pub fn settings(&self) -> &LensSettings {
        &self.settings
    }

    /// The lens as traced (focused and stopped down) with its sampler.
    pub fn sampler(&self) -> &SensorSampler {
        &self.sampler
    }

    /// The lens file.
    pub fn lens_file(&self) -> &Path {
        &self.settings.lens
    }

    /// The sensor point (mm, lens coordinates) that film position (`x`, `y`) in pixels reads:
    /// the film position about the image centre, turned by 180° (the upright image).
    pub fn sensor_point_mm(&self, x: f32, y: f32) -> [f64; 2] {
        let u = (f64::from(x) / f64::from(self.pinhole.width()) - 0.5) * self.sensor_width_mm;
        let v = (0.5 - f64::from(y) / f64::from(self.pinhole.height())) * self.settings.sensor_height_mm;
        [-u, -v]
    }

    /// A camera ray from film position (`x`, `y`) in pixels through the lens at `lambda_nm`,
    /// aimed by the uniform pair `u_pupil`, with `next_uniform` for ghost branches; `None` when
    /// it does not pass the lens (the sample contributes 0). The ray is in scene space; the
    /// [`CameraRay`] gives its weights: [`CameraRay::weight`] multiplies the radiance of
    /// unpolarised light, `sensor_weight` × `sample.mueller` the Stokes vector arriving along
    /// the ray in the frame x = normalize(dir × up) ([`super::Camera::stokes_x`]; the lens's
    /// scene-side frame, lens +y being the camera's up), giving it in the sensor's frame
    /// (x = the image's right for the central ray, as the pinhole's; the 180° turn of the image
    /// leaves Stokes vectors as they are).
    pub fn sample_ray(
        &self,
        x: f32,
        y: f32,
        u_pupil: (f32, f32),
        lambda_nm: f32,
        next_uniform: &mut dyn FnMut() -> f64,
    ) -> Option<(Ray, CameraRay)> {
        self.sample_ray_for(x, y, u_pupil, lambda_nm, true, next_uniform)
    }

    /// [`Self::sample_ray`] for a polarised render (`polarized`: the whole Mueller matrix) or an
    /// unpolarised one (only its row 0 is traced: `sample.mueller`'s rows 1–3 are 0, and
    /// [`CameraRay::weight`] is the same number).
    pub fn sample_ray_for(
        &self,
        x: f32,
        y: f32,
        u_pupil: (f32, f32),
        lambda_nm: f32,
        polarized: bool,
        next_uniform: &mut dyn FnMut() -> f64,
    ) -> Option<(Ray, CameraRay)> {
        let options = TraceOptions {
            max_ghost_reflections: self.settings.max_ghost_reflections,
            full_mueller: polarized,
            ..TraceOptions::new(f64::from(lambda_nm))
        };
        let u = [f64::from(u_pupil.0), f64::from(u_pupil.1)];
        let camera_ray = self.sampler.sample(self.sensor_point_mm(x, y), u, &options, next_uniform)?;
        self.scene_ray(camera_ray)
    }

    /// [`Self::sample_ray_for`] for each wavelength of `lambdas_nm` (nm, at most [`MAX_LANES`])
    /// at once, into the same places of the array: the same rays and weights, to the bit, as a
    /// call per wavelength (one pupil target for all, as those calls draw; the lens traced for
    /// all the wavelengths together, [`crate::lens::LensTracer::trace_lanes_from_sensor`]).
    /// `None` when the camera takes ghost reflections: their branch choices draw numbers, in the
    /// order of a call per wavelength, which the caller then makes.
    pub fn sample_rays_for_lanes(
        &self,
        x: f32,
        y: f32,
        u_pupil: (f32, f32),
        lambdas_nm: &[f32],
        polarized: bool,
    ) -> Option<[Option<(Ray, CameraRay)>; MAX_LANES]> {
        if self.settings.max_ghost_reflections > 0 {
            return None;
        }
        let mut out = [None; MAX_LANES];
        let lanes = lambdas_nm.len().min(MAX_LANES);
        // SensorSampler::sample for every lane: the pupil target, the trace, the weight.
        let sensor = self.sensor_point_mm(x, y);
        let u = [f64::from(u_pupil.0), f64::from(u_pupil.1)];
        let Some(pupil) = self.sampler.bounds.sample(sensor, u) else { return Some(out) };
        let options = TraceOptions { full_mueller: polarized, ..TraceOptions::new(LAMBDA_D_NM) };
        let mut lambdas = [0.0; MAX_LANES];
        for (to, from) in lambdas.iter_mut().zip(&lambdas_nm[..lanes]) {
            *to = f64::from(*from);
        }
        let mut samples = [None; MAX_LANES];
        self.sampler.tracer.trace_lanes_from_sensor(
            sensor,
            pupil.target_mm,
            &lambdas[..lanes],
            &options,
            &mut samples,
        );
        let sensor_weight = self.sampler.normalisation.sensor_weight(sensor, &pupil);
        for (slot, sample) in out.iter_mut().zip(samples) {
            *slot = sample.and_then(|sample| {
                self.scene_ray(CameraRay { sample, sensor_weight, weight: sensor_weight * sample.throughput })
            });
        }
        Some(out)
    }

    /// One camera sample whose `lambdas_nm.len()` lanes (1 to [`MAX_LANES`]) share one scene
    /// path, at film position `film` (pixels) of pixel `pixel`, aimed by the uniform pair
    /// `u_pupil`, its hero lane chosen by the uniform `u_hero` (see the module header, "One
    /// scene path per camera sample"). `None` when the hero's ray does not pass the lens (the
    /// sample adds 0 for every lane). `hero_pdf_only` is the fault
    /// [`crate::integrator::Fault::LensHeroPdfOnly`]: the hero's density alone in each lane's
    /// weight. Only for a camera that [`Self::shares_scene_path`].
    #[allow(clippy::too_many_arguments)] // the sample's numbers, passed flat as sample_ray's
    pub fn sample_shared_path(
        &self,
        pixel: (u32, u32),
        film: (f32, f32),
        u_pupil: (f32, f32),
        u_hero: f32,
        lambdas_nm: &[f32],
        polarized: bool,
        hero_pdf_only: bool,
    ) -> Option<HeroSample> {
        let count = lambdas_nm.len().min(MAX_LANES);
        debug_assert!(count >= 1 && self.shares_scene_path());
        let hero = ((u_hero * count as f32) as usize).min(count - 1);
        let sampler = &*self.sampler;
        let sensor = self.sensor_point_mm(film.0, film.1);
        let u = [f64::from(u_pupil.0), f64::from(u_pupil.1)];
        let pupil = sampler.bounds.sample(sensor, u)?;
        let options =
            TraceOptions { full_mueller: polarized, ..TraceOptions::new(f64::from(lambdas_nm[hero])) };
        let exit = sampler.tracer.trace_from_sensor(sensor, pupil.target_mm, &options, &mut || 0.0)?;
        let scene_ray = crate::lens::Ray { origin: exit.origin_mm, dir: exit.dir };
        // Per lane: its sample of the lens (None: blocked, or its preimage outside the pixel)
        // and the sum over the lanes of their densities (times K).
        let mut samples: [Option<LensSample>; MAX_LANES] = [None; MAX_LANES];
        samples[hero] = Some(exit);
        let hero_density = sampler.normalisation.inverse_sensor_weight(sensor, &pupil);
        let mut density_sum = hero_density;
        // The other lanes' preimages, traced back together.
        let others: [usize; MAX_LANES] = std::array::from_fn(|k| if k < hero { k } else { k + 1 });
        let others = &others[..count - 1];
        let lambdas: [f64; MAX_LANES] =
            std::array::from_fn(|k| others.get(k).map_or(0.0, |&lane| f64::from(lambdas_nm[lane])));
        let mut back = [None; MAX_LANES];
        sampler.tracer.trace_lanes_back_to_sensor(scene_ray, &lambdas[..count - 1], &options, &mut back);
        for (&lane, reverse) in others.iter().zip(&back) {
            let Some(reverse) = reverse else { continue };
            if !self.in_pixel(pixel, reverse.sensor_mm) {
                continue;
            }
            let preimage = PupilSample {
                target_mm: reverse.target_mm,
                pdf_per_mm2: sampler.bounds.pdf_per_mm2(reverse.sensor_mm, reverse.target_mm),
            };
            density_sum += sampler.normalisation.inverse_sensor_weight(reverse.sensor_mm, &preimage);
            samples[lane] = Some(reverse.sample);
        }
        // The mixture's density is the mean over the lanes; the fault takes the hero's alone.
        let sensor_weight = if hero_pdf_only { 1.0 / hero_density } else { count as f64 / density_sum };
        let ray = self.world_ray(&exit)?;
        let lanes = samples.map(|sample| {
            let sample = sample?;
            let weight = sensor_weight * sample.throughput;
            (weight > 0.0 && (weight as f32).is_finite()).then_some(CameraRay {
                sample,
                sensor_weight,
                weight,
            })
        });
        Some(HeroSample { ray, lanes })
    }

    /// Whether the sensor point `sensor_mm` (mm, lens coordinates) is read by pixel `pixel`:
    /// the inverse of [`Self::sensor_point_mm`], the pixel a box of one pixel's side.
    fn in_pixel(&self, pixel: (u32, u32), sensor_mm: [f64; 2]) -> bool {
        let x = (0.5 - sensor_mm[0] / self.sensor_width_mm) * f64::from(self.pinhole.width());
        let y = (0.5 + sensor_mm[1] / self.settings.sensor_height_mm) * f64::from(self.pinhole.height());
        x.floor() == f64::from(pixel.0) && y.floor() == f64::from(pixel.1)
    }

    /// The scene ray of a lens sample, `None` when not finite.
    fn world_ray(&self, sample: &LensSample) -> Option<Ray> {
        let origin = self.to_world(sample.origin_mm / MM_PER_METRE);
        let dir = self.to_world(sample.dir).normalize();
        (origin.is_finite() && dir.is_finite()).then(|| Ray::new(self.pinhole.position() + origin, dir))
    }

    /// The scene ray of a camera ray that passed the lens, `None` for one of weight 0 or not
    /// finite.
    fn scene_ray(&self, camera_ray: CameraRay) -> Option<(Ray, CameraRay)> {
        if !(camera_ray.weight > 0.0 && (camera_ray.weight as f32).is_finite()) {
            return None;
        }
        let origin = self.to_world(camera_ray.sample.origin_mm / MM_PER_METRE);
        let dir = self.to_world(camera_ray.sample.dir);
        let ray = Ray::new(self.pinhole.position() + origin, dir.normalize());
        Some((ray, camera_ray))
    }

    /// A vector in lens coordinates, in scene space: x → right, y → up, z → −forward.
    fn to_world(&self, v: DVec3) -> Vec3 {
        let (right, up) = self.pinhole.right_and_up();
        let forward = up.cross(right);
        v.x as f32 * right + v.y as f32 * up - v.z as f32 * forward
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_at_once_are_the_lanes_one_by_one() {
        // sample_rays_for_lanes (what a render without ghosts uses) must give every lane the
        // ray and weights of its own sample_ray_for call, to the bit: it composes the same
        // pupil target, trace and weight as SensorSampler::sample, and this test guards that
        // they stay the same.
        let settings = LensSettings {
            lens: PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/data/lenses/dgauss50.dat")),
            sensor_height_mm: 24.0,
            focus_distance_m: 6.0,
            f_number: Some(2.8),
            max_ghost_reflections: 0,
        };
        let camera =
            LensCamera::new(Vec3::new(0.0, 1.2, -5.0), Vec3::new(0.0, 0.8, 10.0), Vec3::Y, 36, 24, settings)
                .expect("the shipped lens");
        let lambdas = [365.0, 410.0, 460.0, 510.0, 560.0, 610.0, 680.0, 800.0];
        let (mut passed, mut blocked) = (0, 0);
        for polarized in [false, true] {
            for i in 0..400 {
                let a = i as f32 * 0.618_034;
                let (x, y) = (36.0 * (a * 0.37).fract(), 24.0 * (a * 0.71).fract());
                let u = ((a * 0.53).fract(), (a * 0.29).fract());
                let lanes = 1 + i % MAX_LANES;
                let together =
                    camera.sample_rays_for_lanes(x, y, u, &lambdas[..lanes], polarized).expect("no ghosts");
                for (lane, lambda_nm) in lambdas[..lanes].iter().enumerate() {
                    let alone = camera.sample_ray_for(x, y, u, *lambda_nm, polarized, &mut || 0.0);
                    assert_eq!(together[lane], alone, "sample {i}, lane {lane}");
                    if alone.is_some() {
                        passed += 1;
                    } else {
                        blocked += 1;
                    }
                }
            }
        }
        assert!(passed > 100 && blocked > 10, "{passed} passed, {blocked} blocked");
    }

    #[test]
    fn without_dispersion_the_shared_path_is_the_per_lane_estimate() {
        // pbrt-v4's own double Gauss file gives each glass one index for every wavelength:
        // every lane's preimage of the hero's scene ray is the hero's own (p, t), so the
        // mixture's density is the hero's and every lane's weights must be those of its own
        // per-lane ray (the same ray, to rounding), whichever lane is the hero. Tolerance
        // 1e-12 relative: the reverse trace's rounding (tested in lens::reverse, ~1e-14) and
        // the sum of eight equal densities divided by eight (~1e-16).
        let settings = LensSettings {
            lens: PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/data/lenses/dgauss50_pbrt.dat")),
            sensor_height_mm: 24.0,
            focus_distance_m: 6.0,
            f_number: None,
            max_ghost_reflections: 0,
        };
        let camera =
            LensCamera::new(Vec3::new(0.0, 1.2, -5.0), Vec3::new(0.0, 0.8, 10.0), Vec3::Y, 36, 24, settings)
                .expect("the shipped lens");
        let camera = camera.with_lane_paths(LanePaths::Shared);
        assert!(camera.shares_scene_path());
        let lambdas = [365.0, 410.0, 460.0, 510.0, 560.0, 610.0, 680.0, 800.0];
        let mut compared = 0;
        for polarized in [false, true] {
            for i in 0..300 {
                let a = i as f32 * 0.618_034;
                let pixel = ((36.0 * (a * 0.37).fract()) as u32, (24.0 * (a * 0.71).fract()) as u32);
                let film = (pixel.0 as f32 + (a * 0.13).fract(), pixel.1 as f32 + (a * 0.41).fract());
                let u = ((a * 0.53).fract(), (a * 0.29).fract());
                let u_hero = (a * 0.87).fract();
                let per_lane =
                    camera.sample_rays_for_lanes(film.0, film.1, u, &lambdas, polarized).expect("no ghosts");
                let shared = camera.sample_shared_path(pixel, film, u, u_hero, &lambdas, polarized, false);
                let Some(shared) = shared else {
                    assert!(per_lane.iter().all(Option::is_none), "sample {i}");
                    continue;
                };
                for (lane, (alone, together)) in per_lane.iter().zip(&shared.lanes).enumerate() {
                    let (Some((ray, alone)), Some(together)) = (alone, together) else {
                        panic!("sample {i}, lane {lane}: {alone:?} against {together:?}");
                    };
                    assert!((ray.dir - shared.ray.dir).abs().max_element() < 1e-6, "sample {i}");
                    let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * x.abs().max(y.abs()).max(1e-300);
                    assert!(close(alone.weight, together.weight), "{} vs {}", alone.weight, together.weight);
                    assert!(close(alone.sensor_weight, together.sensor_weight), "sample {i}, lane {lane}");
                    for (x, y) in
                        alone.sample.mueller.iter().flatten().zip(together.sample.mueller.iter().flatten())
                    {
                        assert!((x - y).abs() <= 1e-12 * alone.sample.throughput, "sample {i}, lane {lane}");
                    }
                    compared += 1;
                }
            }
        }
        assert!(compared > 2000, "{compared}");
    }
}
