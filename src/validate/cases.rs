//! `validation/cases.toml`: the list of Mitsuba-referenced cases and their thresholds.
//!
//! ```toml
//! [[case]]
//! name = "specular_spheres"
//! scene = "scenes/specular_spheres.toml"    # relative to validation/
//! references = ["references/specular_spheres_seed1.exr", "references/specular_spheres_seed2.exr"]
//! channels = ["R", "G", "B"]                 # Mitsuba channels, compared with prisma's of the same name
//! wavelength_nm = 550.0                      # monochromatic cases only
//! polarized = false                          # prisma's transport: as the references (default true)
//! why = "specular-only: Mitsuba's path tracer computes exactly Whitted here"
//! spp = 256                                  # prisma samples per pixel for each of its two renders
//! max_rel_mse = 1e-3
//! max_outlier_fraction = 0.005
//! max_mean_z = 5.0
//! max_sidak_failing_fraction = 0.0025        # Mitsuba's rule (99.75 % of its tests pass)
//! ```

use std::path::Path;

use serde::Deserialize;

use super::{Kind, ValidateError};

/// Default prisma samples per pixel of each of the two renders of a case.
pub const DEFAULT_SPP: u32 = 256;
/// Default largest relative MSE beyond what the measured noise explains.
pub const DEFAULT_MAX_REL_MSE: f64 = 5e-4;
/// Default largest fraction of pixels whose |z| exceeds [`super::metrics::Z_OUTLIER`], beyond the
/// fraction seen between two renders of the same renderer.
pub const DEFAULT_MAX_OUTLIER_FRACTION: f64 = 0.005;
/// Default largest |z| of the image-wide mean difference of any channel.
pub const DEFAULT_MAX_MEAN_Z: f64 = 5.0;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CasesFile {
    /// The cases, in order.
    #[serde(rename = "case")]
    pub cases: Vec<Case>,
}

/// One Mitsuba-referenced case.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Case {
    /// Short unique name.
    pub name: String,
    /// prisma scene file, relative to the validation directory.
    pub scene: String,
    /// Two Mitsuba renders with independent seeds, relative to the validation directory.
    pub references: Vec<String>,
    /// Mitsuba channels to compare with prisma's channels of the same name: `R`, `G`, `B`; `Y`
    /// (monochromatic: the spectral radiance); `S0.R` … `S3.B` (Stokes components, as Mitsuba's
    /// `stokes` integrator writes them).
    pub channels: Vec<String>,
    /// Whether prisma renders polarised, as the references were (a polarised or a plain
    /// Mitsuba variant); true when absent.
    #[serde(default = "polarized_by_default")]
    pub polarized: bool,
    /// The wavelength (nm) of a monochromatic case.
    #[serde(default)]
    pub wavelength_nm: Option<f32>,
    /// Why prisma and Mitsuba compute the same quantity here.
    pub why: String,
    /// prisma samples per pixel of each of its two renders.
    #[serde(default)]
    pub spp: Option<u32>,
    /// Largest relative MSE.
    #[serde(default)]
    pub max_rel_mse: Option<f64>,
    /// Largest fraction of outlier pixels.
    #[serde(default)]
    pub max_outlier_fraction: Option<f64>,
    /// Largest |z| of the mean difference.
    #[serde(default)]
    pub max_mean_z: Option<f64>,
    /// Largest fraction of Mitsuba's Šidák-corrected pixel tests that may fail (1 − 0.9975 when
    /// absent, Mitsuba's own rule); a case that needs more states the cause in `why`.
    #[serde(default)]
    pub max_sidak_failing_fraction: Option<f64>,
    /// A systematic difference, relative to the image mean, that the mean test must not call a
    /// bias because its cause is known and written in `why` (0 when absent: the usual case).
    #[serde(default)]
    pub mean_tolerance: Option<f64>,
    /// Compare only some pixels: `"diffuse_seen_directly"` keeps the pixels whose whole
    /// footprint, and their neighbours', shows a diffuse surface directly (the light tracer's
    /// references: Mitsuba's `ptracer` renders mirrors and glass black).
    #[serde(default)]
    pub mask: Option<String>,
    /// What the case is compared with, from the file that lists it (not a key of the file).
    #[serde(skip)]
    pub kind: Kind,
}

fn polarized_by_default() -> bool {
    true
}

/// The files of Mitsuba-referenced cases in a validation directory: the unpolarised Whitted and
/// colour cases, the caustic cases (light tracer against Mitsuba's `ptracer`), the polarised
/// cases (Mitsuba's polarised variants: S0 of every glass case, and Stokes cases), and the
/// unpolarised cases whose references go through prisma's colour pipeline.
pub const CASE_FILES: [&str; 4] =
    ["cases.toml", "caustic_cases.toml", "polarised_cases.toml", "colour_cases.toml"];

/// The kind of the cases of each of [`CASE_FILES`], in the same order.
const CASE_FILE_KINDS: [Kind; 4] =
    [Kind::Mitsuba, Kind::MitsubaPtracer, Kind::MitsubaPolarised, Kind::MitsubaPrismaCmf];

/// Reads every case of [`CASE_FILES`] in `validation_dir` (only `cases.toml` must exist).
pub fn load(validation_dir: &Path) -> Result<Vec<Case>, ValidateError> {
    let mut all = Vec::new();
    for (index, (file, kind)) in CASE_FILES.iter().zip(CASE_FILE_KINDS).enumerate() {
        let path = validation_dir.join(file);
        if index > 0 && !path.exists() {
            continue;
        }
        all.extend(load_file(&path)?.into_iter().map(|case| Case { kind, ..case }));
    }
    Ok(all)
}

/// Reads one file of cases.
fn load_file(path: &Path) -> Result<Vec<Case>, ValidateError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| ValidateError::Input(format!("{}: cannot read: {e}", path.display())))?;
    let file: CasesFile = toml::from_str(&text).map_err(|e| {
        ValidateError::Input(format!("{}: {}", path.display(), crate::scene::error::one_line(e.message())))
    })?;
    for case in &file.cases {
        if case.references.len() != 2 {
            return Err(ValidateError::Input(format!(
                "{}: case {}: `references` must list two renders with independent seeds",
                path.display(),
                case.name
            )));
        }
        if case.mask.as_ref().is_some_and(|m| m != "diffuse_seen_directly") {
            return Err(ValidateError::Input(format!(
                "{}: case {}: the only `mask` is \"diffuse_seen_directly\"",
                path.display(),
                case.name
            )));
        }
        if case.channels.is_empty() {
            return Err(ValidateError::Input(format!(
                "{}: case {}: `channels` must name at least one channel",
                path.display(),
                case.name
            )));
        }
    }
    Ok(file.cases)
}
