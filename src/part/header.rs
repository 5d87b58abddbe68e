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
//! | `prisma.settings` | the integrator settings as JSON: `max_depth`, `prune_below`, `wavelengths` (per sample), `area_light_samples`, `edge_samples` (camera samples per pass at edges, [`crate::edges`]; only when above 1), `polarized`, `caustics`, `light_paths` (per pass, 0 without caustics), `light_guide` (light paths started by a learned guide, [`crate::integrator::guide`]), `spectral_bands`, `monochromatic_nm`, `integrator` (only when not Whitted) |
//! | `prisma.wallSeconds`, `prisma.threads`, `prisma.parts` | render time (summed over merged parts), threads (the most any part used), parts merged into this file |
//! | `prisma.sumsFormat`, `prisma.sumsBlake3` | present when the file holds per-pixel sums: their format and a BLAKE3 digest of them (corruption check) |
//! | `prisma.headerBlake3` | BLAKE3 of every other `prisma.*` attribute and the display and data windows ([`header_digest`]): with `prisma.sumsBlake3` among them, it ties the header to the sums |
//!
//! **Read back, a header is input** ([`PartHeader::from_attributes`]): every field is checked
//! against the limits a scene file has (image size, samples per pixel, light paths, bands,
//! settings in their canonical form) and against the others (samples inside `0..spp`, light
//! paths per pass equal to the settings'), before any buffer is sized from it. The digests
//! catch accidents (a flipped bit, a truncated copy, an edited attribute), not a forger, who can
//! recompute them: prisma does not sign parts.

use serde::Deserialize;

use crate::film::{FilmLayout, SpectralBands};
use crate::printable::quote;
use crate::scene::build::MAX_LIGHT_PATHS;
use crate::scene::limits::{MAX_DEPTH, MAX_HEADER_TEXT, MAX_RESOLUTION, MAX_SPECTRAL_BANDS, MAX_SPP};
use crate::scene::{RenderSettings, Scene};
use crate::spectrum::{LAMBDA_MAX_NM, LAMBDA_MIN_NM, N_LAMBDA};

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
    // Written only for the path tracer, so that Whitted's parts still merge with those of
    // earlier versions.
    if settings.integrator != crate::scene::IntegratorKind::Whitted {
        json["integrator"] = settings.integrator.name().into();
    }
    json.to_string()
}

/// The attribute holding [`header_digest`].
pub const HEADER_DIGEST: &str = "prisma.headerBlake3";

/// BLAKE3 (hex) of a header: every `prisma.*` attribute but [`HEADER_DIGEST`] itself, sorted by
/// name (an EXR keeps its attributes unordered), each as name, zero byte, text, zero byte; then
/// the display size and the data window. Includes `prisma.sumsBlake3` where the file has sums,
/// so that a header cannot be moved onto other sums either.
pub fn header_digest<'a>(
    attributes: impl IntoIterator<Item = (&'a str, &'a str)>,
    display: (u32, u32),
    window: PixelWindow,
) -> String {
    let mut attributes: Vec<(&str, &str)> = attributes
        .into_iter()
        .filter(|(name, _)| name.starts_with("prisma.") && *name != HEADER_DIGEST)
        .collect();
    attributes.sort_unstable();
    let mut hasher = blake3::Hasher::new();
    for (name, text) in attributes {
        for piece in [name, text] {
            hasher.update(piece.as_bytes());
            hasher.update(&[0]);
        }
    }
    hasher.update(format!("display {}x{} window {window}", display.0, display.1).as_bytes());
    crate::scene::digest::hex(hasher.finalize().as_bytes())
}

/// The settings JSON as [`settings_json`] writes it, read back strictly.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SettingsRecord {
    max_depth: u32,
    prune_below: f64,
    wavelengths: usize,
    area_light_samples: u32,
    polarized: bool,
    caustics: bool,
    light_paths: u64,
    light_guide: bool,
    spectral_bands: Option<BandsRecord>,
    monochromatic_nm: Option<f64>,
    #[serde(default)]
    edge_samples: Option<u32>,
    #[serde(default)]
    integrator: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BandsRecord {
    count: u64,
    min_nm: f64,
    max_nm: f64,
}

/// The settings and film layout a settings JSON describes, checked field by field against the
/// limits of a scene file and the command line, and required to be the very text
/// [`settings_json`] writes for them (so that two parts whose texts differ are two renders).
/// The error names the field.
fn parse_settings(text: &str) -> Result<(RenderSettings, FilmLayout, u64), String> {
    let record: SettingsRecord =
        serde_json::from_str(text).map_err(|e| format!("is not prisma's settings JSON ({e})"))?;
    let within = |field: &str, value: u64, low: u64, high: u64| {
        if (low..=high).contains(&value) {
            Ok(())
        } else {
            Err(format!("{field} = {value} is outside {low}..={high}"))
        }
    };
    within("max_depth", record.max_depth.into(), 1, MAX_DEPTH.into())?;
    within("wavelengths", record.wavelengths as u64, 1, N_LAMBDA as u64)?;
    within("area_light_samples", record.area_light_samples.into(), 1, 65_536)?;
    if let Some(edge_samples) = record.edge_samples {
        within("edge_samples", edge_samples.into(), 2, crate::edges::MAX_EDGE_SAMPLES.into())?;
    }
    if !(0.0..1.0).contains(&record.prune_below) {
        return Err(format!("prune_below = {} is outside [0, 1)", record.prune_below));
    }
    if record.caustics != (record.light_paths > 0) {
        return Err(format!("caustics = {} with light_paths = {}", record.caustics, record.light_paths));
    }
    within("light_paths", record.light_paths, 0, MAX_LIGHT_PATHS)?;
    let visible = |nm: f64| (f64::from(LAMBDA_MIN_NM)..=f64::from(LAMBDA_MAX_NM)).contains(&nm);
    let bands = match record.spectral_bands {
        None => None,
        Some(b) => {
            within("spectral_bands.count", b.count, 1, MAX_SPECTRAL_BANDS.into())?;
            if !(visible(b.min_nm) && visible(b.max_nm) && b.min_nm < b.max_nm) {
                return Err(format!(
                    "spectral_bands {}–{} nm is not a range inside {LAMBDA_MIN_NM}–{LAMBDA_MAX_NM} nm",
                    b.min_nm, b.max_nm
                ));
            }
            let bands =
                SpectralBands { count: b.count as usize, min_nm: b.min_nm as f32, max_nm: b.max_nm as f32 };
            if let Some((first, second, name)) = crate::output::exr::shared_band_name(&bands) {
                return Err(format!("spectral_bands {first} and {second} would both be channel {name}"));
            }
            Some(bands)
        }
    };
    if let Some(nm) = record.monochromatic_nm.filter(|&nm| !visible(nm)) {
        return Err(format!("monochromatic_nm = {nm} is outside {LAMBDA_MIN_NM}–{LAMBDA_MAX_NM} nm"));
    }
    let layout = FilmLayout {
        stokes: record.polarized,
        bands,
        monochromatic_nm: record.monochromatic_nm.map(|nm| nm as f32),
    };
    let integrator = match record.integrator.as_deref() {
        None => crate::scene::IntegratorKind::Whitted,
        Some(name) => crate::scene::IntegratorKind::from_name(name)?,
    };
    let settings = RenderSettings {
        integrator,
        max_depth: record.max_depth,
        wavelengths: record.wavelengths,
        area_light_samples: record.area_light_samples,
        prune_below: record.prune_below as f32,
        polarized: record.polarized,
        caustics: record.caustics,
        light_paths: (record.light_paths > 0).then_some(record.light_paths),
        light_guide: record.light_guide,
        edge_samples: record.edge_samples.unwrap_or(1),
        ..RenderSettings::default()
    };
    if settings_json(&settings, record.light_paths, &layout) != text {
        return Err("is not in the canonical form prisma writes (edited?)".into());
    }
    Ok((settings, layout, record.light_paths))
}

/// The film layout a settings JSON of [`settings_json`] describes, if it is valid.
pub fn layout_of(settings: &str) -> Option<FilmLayout> {
    parse_settings(settings).ok().map(|(_, layout, _)| layout)
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
            // A file name may hold control characters; the header holds them escaped, so that
            // it reads back (a header's names may not hold any) and prints safely.
            scene: crate::printable::one_line(scene_name),
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
    /// window, every field checked (see the module doc); the error names the attribute. The
    /// digest ([`HEADER_DIGEST`]) is checked by the part reader, which knows the data window.
    pub fn from_attributes(
        get: impl Fn(&str) -> Option<String>,
        display: (u32, u32),
    ) -> Result<Self, String> {
        let text =
            |name: &str| get(name).ok_or_else(|| format!("no {name} attribute (not a prisma render?)"));
        fn number<T: std::str::FromStr>(name: &str, value: String) -> Result<T, String> {
            value.trim().parse().map_err(|_| format!("{name} = \"{}\" is not a number", quote(&value)))
        }
        let name = |attribute: &str| -> Result<String, String> {
            let value = text(attribute)?;
            if value.len() > MAX_HEADER_TEXT || value.chars().any(char::is_control) {
                return Err(format!(
                    "{attribute} = \"{}\" is not a name (control characters, or over {MAX_HEADER_TEXT} bytes)",
                    quote(&value)
                ));
            }
            Ok(value)
        };
        let (width, height) = display;
        if !(1..=MAX_RESOLUTION).contains(&width) || !(1..=MAX_RESOLUTION).contains(&height) {
            return Err(format!("the image is {width}×{height}: each side must be in 1..={MAX_RESOLUTION}"));
        }
        let spp: u32 = number("prisma.spp", text("prisma.spp")?)?;
        if !(1..=MAX_SPP).contains(&spp) {
            return Err(format!("prisma.spp = {spp} is outside 1..={MAX_SPP}"));
        }
        let samples = text("prisma.samples")?;
        let samples = SampleSet::parse(&samples).map_err(|e| format!("prisma.samples: {e}"))?;
        if samples.end() > spp {
            return Err(format!("prisma.samples {samples} go past prisma.spp = {spp}"));
        }
        let crop = text("prisma.crop")?;
        let window = PixelWindow::parse(&crop, width, height).map_err(|e| format!("prisma.crop: {e}"))?;
        let settings = text("prisma.settings")?;
        let (_, _, light_paths) =
            parse_settings(&settings).map_err(|e| format!("prisma.settings {e}: {}", quote(&settings)))?;
        let light_paths_per_pass: u64 =
            number("prisma.lightPathsPerPass", text("prisma.lightPathsPerPass")?)?;
        if light_paths_per_pass != light_paths {
            return Err(format!(
                "prisma.lightPathsPerPass = {light_paths_per_pass} is not the settings' light_paths = {light_paths}"
            ));
        }
        let scene_sha256 = text("prisma.sceneSha256")?;
        if scene_sha256.len() != 64
            || !scene_sha256.bytes().all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
        {
            return Err(format!("prisma.sceneSha256 = \"{}\" is not a SHA-256 in hex", quote(&scene_sha256)));
        }
        let wall_seconds: f64 = number("prisma.wallSeconds", text("prisma.wallSeconds")?)?;
        if !(wall_seconds.is_finite() && wall_seconds >= 0.0) {
            return Err(format!("prisma.wallSeconds = {wall_seconds} is not a time"));
        }
        let parts: u32 = number("prisma.parts", text("prisma.parts")?)?;
        if parts == 0 {
            return Err("prisma.parts = 0: a file holds at least one part".into());
        }
        Ok(Self {
            version: name("prisma.version")?,
            commit: name("prisma.commit")?,
            scene: name("prisma.scene")?,
            scene_sha256,
            seed: number("prisma.seed", text("prisma.seed")?)?,
            samples,
            spp,
            window,
            display,
            settings,
            light_paths_per_pass,
            wall_seconds,
            threads: number("prisma.threads", text("prisma.threads")?)?,
            parts,
        })
    }

    /// The film layout of the settings (checked when read: [`Self::from_attributes`]).
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
