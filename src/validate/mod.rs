//! Validation: comparing prisma's images with references made offline by Mitsuba 3 (listed in
//! `validation/cases.toml`) and with analytic answers, with metrics that a wrong renderer fails.
//!
//! See `validation/README.md` for the method, the metrics and how to regenerate references.

pub mod analytic;
pub mod cases;
pub mod caustics;
pub mod field;
pub mod film;
pub mod furnace;
pub mod metrics;
pub mod mitsuba;
pub mod polarization;
pub mod summary;
pub mod textbook;
pub mod tmm_fixture;

/// The outcome of one validation case.
#[derive(Debug, Clone)]
pub struct CaseResult {
    /// Case name.
    pub name: String,
    /// One row per metric checked.
    pub checks: Vec<Check>,
    /// Why the compared quantities are the same (or what the analytic answer is).
    pub why: String,
}

/// One metric of a case against its threshold.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    /// What is measured, e.g. `relMSE` or `outliers |z|>5`.
    pub metric: String,
    /// Measured value.
    pub value: f64,
    /// Largest value that passes.
    pub threshold: f64,
}

impl Check {
    /// True when the value is within the threshold (NaN fails).
    pub fn passed(&self) -> bool {
        self.value <= self.threshold
    }
}

impl CaseResult {
    /// True when every check passes.
    pub fn passed(&self) -> bool {
        !self.checks.is_empty() && self.checks.iter().all(Check::passed)
    }
}

/// What a case is compared with: the `kind` column of `prisma validate`'s table and report, and
/// the classes by which it estimates the time left.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kind {
    /// An answer computed in closed form (furnaces, Snell's window, the slab's transmittance).
    Analytic,
    /// A Stokes vector from the independent electric-field tracer of [`field`].
    FieldTracer,
    /// Mitsuba 3 references, monochromatic or through Mitsuba's colour pipeline (`cases.toml`).
    #[default]
    Mitsuba,
    /// Mitsuba 3's particle tracer `ptracer` against prisma's light tracer (`caustic_cases.toml`).
    MitsubaPtracer,
    /// Mitsuba 3's polarised variants (`polarised_cases.toml`).
    MitsubaPolarised,
    /// Mitsuba 3's spectra through prisma's colour pipeline, its CIE table and matrix
    /// (`colour_cases.toml`).
    MitsubaPrismaCmf,
}

impl Kind {
    /// The short label printed in the `kind` column.
    pub fn label(self) -> &'static str {
        match self {
            Kind::Analytic => "analytic",
            Kind::FieldTracer => "field tracer",
            Kind::Mitsuba => "Mitsuba",
            Kind::MitsubaPtracer => "Mitsuba ptracer",
            Kind::MitsubaPolarised => "Mitsuba polarised",
            Kind::MitsubaPrismaCmf => "Mitsuba, prisma CMF",
        }
    }

    /// True for cases that render two full images and compare them with reference images: they
    /// take seconds to minutes, where an analytic case takes milliseconds to seconds.
    pub fn compares_images(self) -> bool {
        !matches!(self, Kind::Analytic | Kind::FieldTracer)
    }
}

/// Why a validation case could not run.
#[derive(Debug, thiserror::Error)]
pub enum ValidateError {
    /// A file of the validation set is missing or malformed.
    #[error("{0}")]
    Input(String),
    /// Rendering failed.
    #[error(transparent)]
    Render(#[from] crate::render::RenderError),
}
