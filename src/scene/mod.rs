//! Scenes: the file format ([`desc`]), its validation into runtime types ([`build`]) and the
//! errors a user sees ([`error`]).

pub mod build;
pub mod desc;
pub mod digest;
pub mod error;
pub mod limits;
mod locate;
pub mod typed;

pub use build::{load, parse};
pub use error::SceneError;

use std::path::PathBuf;

use crate::camera::Camera;
use crate::geometry::Geometry;
use crate::light::Light;
use crate::material::Material;
use crate::spectrum::DenseSpectrum;
use limits::{MAX_DEPTH_UNPRUNED, MIN_PRUNE_BELOW_DEEP};

/// The estimator of the camera's image ([`crate::integrator`]), chosen per scene
/// (`[render] integrator`) or on the command line (`--integrator`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IntegratorKind {
    /// Whitted's recursion: direct light at diffuse surfaces, both branches at glass, no
    /// interreflection and no light from the background (the seed's model, and the fast preview).
    #[default]
    Whitted,
    /// Full transport ([`crate::integrator::PathTracer`]): unidirectional path tracing with
    /// next-event estimation and multiple importance sampling, the background as a light, and,
    /// with `caustics`, the light tracer for the paths camera paths cannot make.
    Path,
}

impl IntegratorKind {
    /// Every integrator, in the order users are told about them.
    pub const ALL: [IntegratorKind; 2] = [IntegratorKind::Whitted, IntegratorKind::Path];

    /// The name a scene file and the command line use (as Mitsuba and pbrt name theirs).
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Whitted => "whitted",
            IntegratorKind::Path => "path",
        }
    }

    /// The integrator named `name`, or an error listing the valid names.
    pub fn from_name(name: &str) -> Result<Self, String> {
        Self::ALL.into_iter().find(|kind| kind.name() == name).ok_or_else(|| {
            let names: Vec<_> = Self::ALL.iter().map(|kind| format!("\"{}\"", kind.name())).collect();
            format!("unknown integrator {name:?}; valid: {}", names.join(", "))
        })
    }

    /// The default `area_light_samples`: Whitted's stratified samples per quad light at each
    /// diffuse point; the path tracer's one sample per quad light per diffuse vertex (its only
    /// value).
    pub fn default_area_light_samples(self) -> u32 {
        match self {
            IntegratorKind::Whitted => 4,
            IntegratorKind::Path => 1,
        }
    }

    /// The default `max_depth` of this integrator: specular bounces for Whitted; every bounce
    /// (diffuse or specular) for the path tracer, where Russian roulette ends most paths long
    /// before it.
    pub fn default_max_depth(self) -> u32 {
        match self {
            IntegratorKind::Whitted => 16,
            IntegratorKind::Path => 256,
        }
    }
}

/// Sampling settings of a render.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    /// The camera's estimator.
    pub integrator: IntegratorKind,
    /// Camera samples per pixel (≥ 1).
    pub spp: u32,
    /// Maximum depth: the number of specular bounces a camera ray may take (Whitted), or of
    /// bounces of any kind along a path (the path tracer).
    pub max_depth: u32,
    /// Wavelengths each camera sample carries (1..=`N_LAMBDA`).
    pub wavelengths: usize,
    /// Seed of the per-pixel random streams.
    pub seed: u64,
    /// Stratified samples per quad light at each diffuse shading point (≥ 1).
    pub area_light_samples: u32,
    /// Branch weight under which Russian roulette may end a branch (0: never).
    pub prune_below: f32,
    /// Carry Stokes vectors (true) or radiance with s/p-averaged Fresnel weights (false).
    pub polarized: bool,
    /// Add caustics by light tracing ([`crate::integrator::LightTracer`]).
    pub caustics: bool,
    /// Light paths per pass when caustics are on (a render makes `spp` passes); `None`: one per
    /// pixel.
    pub light_paths: Option<u64>,
    /// Start light paths where they are worth most, as the render's first light paths teach
    /// ([`crate::integrator::guide`]); false: uniformly over each light's emission.
    pub light_guide: bool,
    /// Camera samples per pass of the pixels an edge crosses, chosen after the first pass (1:
    /// every pixel one sample per pass; [`crate::edges`]).
    pub edge_samples: u32,
}

impl RenderSettings {
    /// Light paths a render of `pixels` pixels traces in all: `spp` passes of
    /// [`Self::light_paths`] (one per pixel by default). Zero when caustics are off.
    pub fn total_light_paths(&self, pixels: u64) -> u64 {
        if !self.caustics {
            return 0;
        }
        self.light_paths.unwrap_or(pixels).saturating_mul(u64::from(self.spp))
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            integrator: IntegratorKind::Whitted,
            spp: 16,
            max_depth: IntegratorKind::Whitted.default_max_depth(),
            wavelengths: 8,
            seed: 0,
            area_light_samples: IntegratorKind::Whitted.default_area_light_samples(),
            prune_below: 0.01,
            polarized: true,
            caustics: false,
            light_paths: None,
            light_guide: true,
            edge_samples: 1,
        }
    }
}

impl RenderSettings {
    /// Checks the rule that bounds the Whitted ray tree: with `prune_below` below
    /// [`MIN_PRUNE_BELOW_DEEP`] (0: pruning off), `max_depth` may be at most
    /// [`MAX_DEPTH_UNPRUNED`], as every glass hit may keep both branches (2^max_depth rays per
    /// sample); with stronger pruning, Russian roulette bounds the tree at any depth. The error
    /// says what to change.
    pub fn check_ray_tree_bound(&self) -> Result<(), String> {
        // A path tracer's paths are no tree: at most one branch per wavelength lane.
        if self.integrator == IntegratorKind::Whitted
            && self.prune_below < MIN_PRUNE_BELOW_DEEP
            && self.max_depth > MAX_DEPTH_UNPRUNED
        {
            return Err(format!(
                "max_depth = {} with prune_below = {} could cost up to 2^{} rays per sample; with \
                 prune_below below {MIN_PRUNE_BELOW_DEEP:e}, max_depth must be at most \
                 {MAX_DEPTH_UNPRUNED} (or set prune_below ≥ {MIN_PRUNE_BELOW_DEEP:e}; the default is 0.01)",
                self.max_depth, self.prune_below, self.max_depth
            ));
        }
        Ok(())
    }
}

/// What a shape is made of: its material, and the light it emits (for quad lights).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Surface {
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Index into [`Scene::lights`] when the shape is an emitter.
    pub emitter: Option<u32>,
}

/// A scene ready to render.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Name (the file stem), used for default output names.
    pub name: String,
    /// The camera.
    pub camera: Camera,
    /// Render settings from the file (the CLI may override them).
    pub settings: RenderSettings,
    /// Every shape, intersectable.
    pub geometry: Geometry,
    /// Per shape (same index as `geometry.shapes()`): material and emitter.
    pub surfaces: Vec<Surface>,
    /// Materials.
    pub materials: Vec<Material>,
    /// The file's name of each material (same index as `materials`; `"(light)"` for the black
    /// surface of quad lights).
    pub material_names: Vec<String>,
    /// Lights.
    pub lights: Vec<Light>,
    /// Radiance of escaping rays, W·m⁻²·sr⁻¹·nm⁻¹.
    pub background: DenseSpectrum,
    /// Hex SHA-256 of the scene file and the meshes it loads ([`digest::scene_digest`]).
    pub digest: String,
    /// The files besides the scene file that the scene read (meshes, a lens file, textures),
    /// as opened (relative to the scene file's directory), each with what it is: inputs that no
    /// output may replace.
    pub input_files: Vec<(PathBuf, &'static str)>,
}
