//! Scenes: the file format ([`desc`]), its validation into runtime types ([`build`]) and the
//! errors a user sees ([`error`]).

pub mod build;
pub mod desc;
pub mod error;
pub mod limits;
mod locate;
pub mod typed;

pub use build::{load, parse};
pub use error::SceneError;

use crate::camera::Camera;
use crate::geometry::Geometry;
use crate::light::Light;
use crate::material::Material;
use crate::spectrum::DenseSpectrum;
use limits::MAX_DEPTH_UNPRUNED_QUIET;

/// Sampling settings of a render.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    /// Camera samples per pixel (≥ 1).
    pub spp: u32,
    /// Maximum recursion depth: the number of specular bounces a camera ray may take.
    pub max_depth: u32,
    /// Wavelengths each camera sample carries (1..=`N_LAMBDA`).
    pub wavelengths: usize,
    /// Seed of the per-pixel random streams.
    pub seed: u64,
    /// Stratified samples per quad light at each diffuse shading point (≥ 1).
    pub area_light_samples: u32,
    /// Branch weight under which Russian roulette may end a branch (0: never).
    pub prune_below: f32,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self { spp: 16, max_depth: 16, wavelengths: 8, seed: 0, area_light_samples: 4, prune_below: 0.01 }
    }
}

impl RenderSettings {
    /// A one-line warning when these settings let the Whitted ray tree of `scene` grow
    /// exponentially: with `prune_below = 0` every dielectric hit keeps both branches, so a
    /// camera sample may cost up to 2^`max_depth` rays where glass faces glass (measured: 40 s
    /// at depth 24 where depth 16 took 1 s). `None` when pruning is on, the depth is at most
    /// [`MAX_DEPTH_UNPRUNED_QUIET`], or no shape is a dielectric.
    pub fn exponential_growth_warning(&self, scene: &Scene) -> Option<String> {
        let has_glass = scene
            .surfaces
            .iter()
            .any(|s| matches!(scene.materials.get(s.material as usize), Some(Material::Dielectric(_))));
        (self.prune_below == 0.0 && self.max_depth > MAX_DEPTH_UNPRUNED_QUIET && has_glass).then(|| {
            format!(
                "prune_below = 0 with max_depth = {} lets every glass hit double the ray tree \
                 (up to 2^{} rays per sample): the render may take exponentially long; \
                 keep max_depth ≤ {MAX_DEPTH_UNPRUNED_QUIET} or set prune_below > 0 (default 0.01)",
                self.max_depth, self.max_depth
            )
        })
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
}
