//! [`PartHeader`]: what a render's EXR says about itself (provenance), as `prisma.*` text
//! attributes of its header. Every render writes one; `prisma info` prints it, and the merge
//! reads it to decide which parts belong together.
//!
//! | attribute | value |
//! |---|---|
//! | `prisma.version`, `prisma.commit` | the renderer's version and git commit (`-dirty` when built from changed sources, `unknown` outside git) |
//! | `prisma.scene`, `prisma.sceneSha256` | the scene file, and SHA-256 of it and its meshes ([`crate::scene::digest`]) |
//! | `prisma.seed` | seed of the sample sequences |
//! | `prisma.samples`, `prisma.spp` | sample indices held (`0..64,128..192`) and the render's total samples per pixel |
//! | `prisma.crop` | the pixel window `X0,Y0,X1,Y1` (also the EXR data window) |
//! | `prisma.settings` | the integrator settings as JSON: `max_depth`, `prune_below`, `wavelengths` (per sample), `area_light_samples`, `edge_samples` (camera samples per pass at edges, [`crate::edges`]; only when above 1), `polarized`, `caustics`, `light_paths` (per pass, 0 without caustics), `light_guide` (light paths started by a learned guide, [`crate::integrator::guide`]), `spectral_bands`, `monochromatic_nm` |
//! | `prisma.wallSeconds`, `prisma.threads`, `prisma.parts` | render time (summed over merged parts), threads (the most any part used), parts merged into this file |
//! | `prisma.sumsFormat`, `prisma.sumsBlake3` | present when the file holds per-pixel sums: their format and a BLAKE3 digest of them (corruption check) |

use crate::film::FilmLayout;
use crate::scene::{RenderSettings, Scene};

use super::{PixelWindow, SampleSet};

/// The format of the sums a part holds: 192-bit fixed point with 2⁻⁶⁴ quanta, as up to six
/// 32-bit words per value ([`crate::fixed::FixedSum`], [`crate::part::file`]), with a digest of
/// the stored channels (`-v2`: the first format's digest covered all six words of every value,
/// implied or not; `-v3`: a monochromatic render's pixel holds its radiance once per Stokes
/// component, where `-v2` held (L, L, L) as XYZ). A different format is a different renderer.
pub const SUMS_FORMAT: &str = "fixed192-q64-v3";

/// The renderer's version (Cargo).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
/// The git commit the renderer was built from (see `build.rs`).
pub const COMMIT: &str = env!("PRISMA_COMMIT");

/// What a render's EXR says about itself.
#[derive(Debug, Clone, PartialEq)]
pub struct PartHeader {
    /// prisma's version.
    pub version: String,
    /// prisma's git commit.
    pub commit: String,
    /// The scene file as named on the command line.
    pub scene: String,
    /// Hex SHA-256 of the scene and its meshes.
    pub scene_sha256: String,
    /// Seed.
    pub seed: u64,
    /// Sample indices held.
    pub samples: SampleSet,
    /// Samples per pixel of the whole render.
    pub spp: u32,
    /// Pixels held.
    pub window: PixelWindow,
    /// Size (width, height) of the whole image.
    pub display: (u32, u32),
    /// Integrator settings, canonical JSON ([`settings_json`]).
    pub settings: String,
    /// Light paths per pass (per sample), 0 without caustics.
    pub light_paths_per_pass: u64,
    /// Wall-clock seconds of the render (summed over merged parts).
    pub wall_seconds: f64,
    /// Render threads (the most any merged part used).
    pub threads: usize,
    /// Parts merged into this file (1 for a render).
    pub parts: u32,
}

/// The integrator settings and film layout a part was rendered with, as canonical JSON (keys
/// sorted): parts merge only when these are equal. `edge_samples` is written only when edge
/// refinement is on, so that parts without it still merge with those of earlier versions.
pub fn settings_json(settings: &RenderSettings, light_paths_per_pass: u64, layout: &FilmLayout) -> String {
    let mut json = serde_json::json!({
        "max_depth": settings.max_depth,
        // Through its shortest decimal form, so that 0.01 reads 0.01, not 0.009999999776482582.
        "prune_below": settings.prune_below.to_string().parse::<f64>().unwrap_or(f64::NAN),
        "wavelengths": settings.wavelengths,
        "area_light_samples": settings.area_light_samples,
        "polarized": layout.stokes,
        "caustics": light_paths_per_pass > 0,
        "light_paths": light_paths_per_pass,
        "light_guide": light_paths_per_pass > 0 && settings.light_guide,
        "spectral_bands": layout.bands.map(|b| serde_json::json!({
            "count": b.count, "min_nm": b.min_nm, "max_nm": b.max_nm
        })),
        "monochromatic_nm": layout.monochromatic_nm,
    });
    if settings.edge_samples > 1 {
        json["edge_samples"] = settings.edge_samples.into();
    }
    json.to_string()
}

/// The film layout a settings JSON of [`settings_json`] describes, if it parses.
pub fn layout_of(settings: &str) -> Option<FilmLayout> {
    let value: serde_json::Value = serde_json::from_str(settings).ok()?;
    let bands = match &value["spectral_bands"] {
        serde_json::Value::Null => None,
        b => Some(crate::film::SpectralBands {
            count: usize::try_from(b["count"].as_u64()?).ok().filter(|&c| c >= 1)?,
            min_nm: b["min_nm"].as_f64()? as f32,
            max_nm: b["max_nm"].as_f64()? as f32,
        }),
    };
    let monochromatic_nm = match &value["monochromatic_nm"] {
        serde_json::Value::Null => None,
        nm => Some(nm.as_f64()? as f32),
    };
    Some(FilmLayout { stokes: value["polarized"].as_bool()?, bands, monochromatic_nm })
}

impl PartHeader {
    /// The header of a render of `scene` (named `scene_name` in messages) with `settings`,
    /// `layout` and `light_paths_per_pass` over `window`, by this prisma: no samples yet, no
    /// time, one part.
    pub fn new(
        scene_name: &str,
        scene: &Scene,
        settings: &RenderSettings,
        layout: &FilmLayout,
        light_paths_per_pass: u64,
        window: PixelWindow,
    ) -> Self {
        Self {
            version: VERSION.to_owned(),
            commit: COMMIT.to_owned(),
            scene: scene_name.to_owned(),
            scene_sha256: scene.digest.clone(),
            seed: settings.seed,
            samples: SampleSet::default(),
            spp: settings.spp,
            window,
            display: (scene.camera.width(), scene.camera.height()),
            settings: settings_json(settings, light_paths_per_pass, layout),
            light_paths_per_pass,
            wall_seconds: 0.0,
            threads: 0,
            parts: 1,
        }
    }

    /// The header as (attribute name, text) pairs, in a fixed order.
    pub fn attributes(&self) -> Vec<(&'static str, String)> {
        vec![
            ("prisma.version", self.version.clone()),
            ("prisma.commit", self.commit.clone()),
            ("prisma.scene", self.scene.clone()),
            ("prisma.sceneSha256", self.scene_sha256.clone()),
            ("prisma.seed", self.seed.to_string()),
            ("prisma.samples", self.samples.to_string()),
            ("prisma.spp", self.spp.to_string()),
            ("prisma.crop", self.window.to_string()),
            ("prisma.settings", self.settings.clone()),
            ("prisma.lightPathsPerPass", self.light_paths_per_pass.to_string()),
            ("prisma.wallSeconds", format!("{:.3}", self.wall_seconds)),
            ("prisma.threads", self.threads.to_string()),
            ("prisma.parts", self.parts.to_string()),
        ]
    }

    /// The header from the attributes `get` returns (by name) of a `width`×`height` display
    /// window; the error names the missing or malformed attribute.
    pub fn from_attributes(
        get: impl Fn(&str) -> Option<String>,
        display: (u32, u32),
    ) -> Result<Self, String> {
        let text =
            |name: &str| get(name).ok_or_else(|| format!("no {name} attribute (not a prisma render?)"));
        fn number<T: std::str::FromStr>(name: &str, value: String) -> Result<T, String> {
            value.trim().parse().map_err(|_| format!("{name} = \"{value}\" is not a number"))
        }
        let samples = text("prisma.samples")?;
        let samples = SampleSet::parse(&samples).map_err(|e| format!("prisma.samples: {e}"))?;
        let crop = text("prisma.crop")?;
        let window =
            PixelWindow::parse(&crop, display.0, display.1).map_err(|e| format!("prisma.crop: {e}"))?;
        let settings = text("prisma.settings")?;
        if layout_of(&settings).is_none() {
            return Err(format!("prisma.settings = {settings} is not valid"));
        }
        Ok(Self {
            version: text("prisma.version")?,
            commit: text("prisma.commit")?,
            scene: text("prisma.scene")?,
            scene_sha256: text("prisma.sceneSha256")?,
            seed: number("prisma.seed", text("prisma.seed")?)?,
            samples,
            spp: number("prisma.spp", text("prisma.spp")?)?,
            window,
            display,
            settings,
            light_paths_per_pass: number("prisma.lightPathsPerPass", text("prisma.lightPathsPerPass")?)?,
            wall_seconds: number("prisma.wallSeconds", text("prisma.wallSeconds")?)?,
            threads: number("prisma.threads", text("prisma.threads")?)?,
            parts: number("prisma.parts", text("prisma.parts")?)?,
        })
    }

    /// The film layout of the settings (they were checked to parse when read).
    pub fn layout(&self) -> FilmLayout {
        layout_of(&self.settings).unwrap_or_default()
    }

    /// The first field in which `other` cannot be merged with this header: (what, this value,
    /// the other's value). Parts merge when they come from the same renderer, scene, seed,
    /// image size and settings.
    pub fn mismatch(&self, other: &Self) -> Option<(&'static str, String, String)> {
        let fields: [(&'static str, String, String); 6] = [
            ("prisma version", self.version.clone(), other.version.clone()),
            ("prisma commit", self.commit.clone(), other.commit.clone()),
            ("scene (SHA-256)", self.scene_sha256.clone(), other.scene_sha256.clone()),
            ("seed", self.seed.to_string(), other.seed.to_string()),
            (
                "image size",
                format!("{}×{}", self.display.0, self.display.1),
                format!("{}×{}", other.display.0, other.display.1),
            ),
            ("settings", self.settings.clone(), other.settings.clone()),
        ];
        fields.into_iter().find(|(_, a, b)| a != b)
    }
}
