//! Validation: comparing prisma's images with references made offline by Mitsuba 3 (listed in
//! `validation/cases.toml`) and with analytic answers, with metrics that a wrong renderer fails.
//!
//! See `validation/README.md` for the method, the metrics and how to regenerate references.

pub mod analytic;
pub mod cases;
pub mod caustics;
pub mod field;
pub mod metrics;
pub mod mitsuba;
pub mod polarization;

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
