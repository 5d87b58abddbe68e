//! `validation/cases.toml` and its siblings ([`CASE_FILES`]): the Mitsuba-referenced cases and
//! their thresholds.
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
//!
//! The full-transport cases of `transport_cases.toml` add:
//!
//! ```toml
//! mitsuba_integrator = "path"                # or "ptracer": which Mitsuba integrator made the references
//! integrator = "path"                        # prisma's integrator the references are for (the scene's must agree)
//! caustics = true                            # prisma's light tracer on or off, whatever the scene says
//! ```

use std::path::Path;

use serde::Deserialize;

use super::{Kind, ValidateError};
use crate::scene::{IntegratorKind, RenderSettings};

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
    /// The Mitsuba integrator of the references of a full-transport case: `"path"` (its path
    /// tracer, for area lights and the background) or `"ptracer"` (its particle tracer, for point
    /// and spot lights, compared under `mask`). Required in `transport_cases.toml`.
    #[serde(default)]
    pub mitsuba_integrator: Option<String>,
    /// prisma's integrator the references stand for (`"whitted"` or `"path"`): the scene's own
    /// `[render] integrator` must be this one, since the references depend on it (the
    /// validation scripts translate the scene's `max_depth` by it). `None`: the scene's.
    #[serde(default)]
    pub integrator: Option<String>,
    /// Turns prisma's light tracer on or off for this case, whatever the scene says: how prisma
    /// estimates the image, not what the image is (`None`: the scene's setting).
    #[serde(default)]
    pub caustics: Option<bool>,
    /// What the case is compared with, from the file that lists it (not a key of the file).
    #[serde(skip)]
    pub kind: Kind,
}

fn polarized_by_default() -> bool {
    true
}

impl Case {
    /// prisma's integrator the references stand for, if the case names one.
    pub fn prisma_integrator(&self) -> Result<Option<IntegratorKind>, String> {
        self.integrator.as_deref().map(IntegratorKind::from_name).transpose()
    }

    /// Applies the case's prisma-side fields to the settings of its scene: checks that the
    /// scene's integrator is the case's `integrator`, and sets `caustics` when the case gives it.
    /// The error says what disagrees.
    pub fn apply_to(&self, settings: &mut RenderSettings) -> Result<(), String> {
        if let Some(kind) = self.prisma_integrator()? {
            if kind != settings.integrator {
                return Err(format!(
                    "the references are for prisma's integrator \"{}\" but the scene's is \"{}\" \
                     (set [render] integrator in the scene)",
                    kind.name(),
                    settings.integrator.name()
                ));
            }
        }
        if let Some(caustics) = self.caustics {
            settings.caustics = caustics;
        }
        Ok(())
    }
}

/// The files of Mitsuba-referenced cases in a validation directory: the unpolarised Whitted and
/// colour cases, the caustic cases (light tracer against Mitsuba's `ptracer`), the polarised
/// cases (Mitsuba's polarised variants: S0 of every glass case, and Stokes cases), the
/// unpolarised cases whose references go through prisma's colour pipeline, and the
/// full-transport cases (prisma's path integrator against Mitsuba's `path` and `ptracer`).
pub const CASE_FILES: [&str; 5] =
    ["cases.toml", "caustic_cases.toml", "polarised_cases.toml", "colour_cases.toml", TRANSPORT_CASES];

/// The file of full-transport cases, whose cases must name their `mitsuba_integrator`.
const TRANSPORT_CASES: &str = "transport_cases.toml";

/// The kind of the cases of each of [`CASE_FILES`], in the same order (`None`: by case, see
/// [`transport_kind`]).
const CASE_FILE_KINDS: [Option<Kind>; 5] = [
    Some(Kind::Mitsuba),
    Some(Kind::MitsubaPtracer),
    Some(Kind::MitsubaPolarised),
    Some(Kind::MitsubaPrismaCmf),
    None,
];

/// The kind of a full-transport case: by the Mitsuba integrator of its references, and for
/// `path`, whether prisma renders it polarised.
fn transport_kind(case: &Case) -> Kind {
    match (case.mitsuba_integrator.as_deref(), case.polarized) {
        (Some("ptracer"), _) => Kind::MitsubaPtracer,
        (_, true) => Kind::MitsubaPolarised,
        (_, false) => Kind::Mitsuba,
    }
}

/// Reads every case of [`CASE_FILES`] in `validation_dir` (only `cases.toml` must exist).
pub fn load(validation_dir: &Path) -> Result<Vec<Case>, ValidateError> {
    let mut all = Vec::new();
    for (index, (file, kind)) in CASE_FILES.iter().zip(CASE_FILE_KINDS).enumerate() {
        let path = validation_dir.join(file);
        if index > 0 && !path.exists() {
            continue;
        }
        let cases = load_file(&path)?;
        if *file == TRANSPORT_CASES {
            if let Some(case) = cases.iter().find(|case| case.mitsuba_integrator.is_none()) {
                return Err(ValidateError::Input(format!(
                    "{}: case {}: `mitsuba_integrator` (\"path\" or \"ptracer\") is required here",
                    path.display(),
                    case.name
                )));
            }
        }
        all.extend(
            cases
                .into_iter()
                .map(|case| Case { kind: kind.unwrap_or_else(|| transport_kind(&case)), ..case }),
        );
    }
    Ok(all)
}

/// Reads one file of cases.
fn load_file(path: &Path) -> Result<Vec<Case>, ValidateError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| ValidateError::Input(format!("{}: cannot read: {e}", path.display())))?;
    parse_file(&text, path)
}

/// Parses and checks the cases of one file (`path` names it in errors).
fn parse_file(text: &str, path: &Path) -> Result<Vec<Case>, ValidateError> {
    let file: CasesFile = toml::from_str(text).map_err(|e| {
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
        let bad = |message: &str| {
            Err(ValidateError::Input(format!("{}: case {}: {message}", path.display(), case.name)))
        };
        match case.mitsuba_integrator.as_deref() {
            None | Some("path") => {}
            Some("ptracer") if case.mask.is_none() => {
                return bad("a `ptracer` reference renders glass and mirrors black: compare under \
                     mask = \"diffuse_seen_directly\"")
            }
            Some("ptracer") => {}
            Some(other) => {
                return bad(&format!("unknown mitsuba_integrator {other:?}; valid: \"path\", \"ptracer\""))
            }
        }
        if let Err(message) = case.prisma_integrator() {
            return bad(&format!("integrator: {message}"));
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

#[cfg(test)]
mod tests {
    use super::*;

    const TRANSPORT_CASE: &str = r#"
[[case]]
name = "room"
scene = "scenes/room.toml"
references = ["references/room_seed1.exr", "references/room_seed2.exr"]
channels = ["R", "G", "B"]
polarized = false
mask = "diffuse_seen_directly"
mitsuba_integrator = "ptracer"
integrator = "path"
caustics = true
why = "test"
"#;

    fn parse(text: &str) -> Result<Vec<Case>, String> {
        parse_file(text, Path::new("transport_cases.toml")).map_err(|e| e.to_string())
    }

    #[test]
    fn a_transport_case_names_its_integrators() {
        let cases = parse(TRANSPORT_CASE).unwrap();
        assert_eq!(cases[0].mitsuba_integrator.as_deref(), Some("ptracer"));
        assert_eq!(cases[0].prisma_integrator(), Ok(Some(IntegratorKind::Path)));
        assert_eq!(cases[0].caustics, Some(true));
        assert_eq!(transport_kind(&cases[0]), Kind::MitsubaPtracer);
    }

    #[test]
    fn bad_integrator_fields_are_refused() {
        let unknown =
            TRANSPORT_CASE.replace("mitsuba_integrator = \"ptracer\"", "mitsuba_integrator = \"bdpt\"");
        assert!(parse(&unknown).unwrap_err().contains("unknown mitsuba_integrator"));
        let unmasked = TRANSPORT_CASE.replace("mask = \"diffuse_seen_directly\"\n", "");
        assert!(parse(&unmasked).unwrap_err().contains("mask"));
        let prisma = TRANSPORT_CASE.replace("integrator = \"path\"", "integrator = \"bdpt\"");
        assert!(parse(&prisma).unwrap_err().contains("integrator"));
    }

    #[test]
    fn the_scene_must_use_the_integrator_of_the_references() {
        let case = parse(TRANSPORT_CASE).unwrap().remove(0);
        let mut whitted = RenderSettings { caustics: false, ..RenderSettings::default() };
        let message = case.apply_to(&mut whitted).unwrap_err();
        assert!(message.contains("\"path\"") && message.contains("\"whitted\""), "{message}");
        let mut path =
            RenderSettings { integrator: IntegratorKind::Path, caustics: false, ..RenderSettings::default() };
        case.apply_to(&mut path).unwrap();
        assert!(path.caustics, "the case's caustics = true must turn the light tracer on");
    }

    #[test]
    fn every_shipped_transport_case_loads() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("validation");
        let all = load(&dir).unwrap();
        let transport: Vec<_> = all.iter().filter(|case| case.mitsuba_integrator.is_some()).collect();
        assert!(transport.len() >= 7, "only {} full-transport cases", transport.len());
        for case in transport {
            assert_eq!(case.prisma_integrator(), Ok(Some(IntegratorKind::Path)), "{}", case.name);
            let scene = crate::scene::load(&dir.join(&case.scene)).unwrap();
            let mut settings = scene.settings.clone();
            case.apply_to(&mut settings).unwrap_or_else(|e| panic!("{}: {e}", case.name));
        }
    }
}
