//! Subcommands of the `prisma` binary, one file each, and the error type that maps failures to
//! exit codes.

mod bench;
mod destinations;
mod export;
mod fresnel;
mod glass;
mod info;
mod lens;
mod merge;
mod plot;
mod polviz;
mod render;
mod validate;

use clap::{Parser, Subcommand};

/// prisma: a spectral Whitted ray tracer for glass and dispersion.
#[derive(Debug, Parser)]
#[command(name = "prisma", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Render a scene file to an OpenEXR image and a PNG preview.
    Render(render::RenderArgs),
    /// Add parts of a split render (sample ranges, crops, interrupted runs) into one image, exactly.
    Merge(merge::MergeArgs),
    /// Print what an EXR prisma wrote says about itself: provenance, samples, window, settings.
    Info(info::InfoArgs),
    /// Export a scene as prisma resolved it: spectra.json (spectra and IORs per nm) and meshes as OBJ.
    Export(export::ExportArgs),
    /// Fresnel reflectance curves of an interface (CSV, plots), or a Mitsuba fixture against prisma.
    Fresnel(fresnel::FresnelArgs),
    /// The glass catalogue: n_d, V_d and sources, n(λ) tables and plots.
    Glass(glass::GlassArgs),
    /// A lens prescription's first-order optics, aberrations and illumination, printed and plotted.
    Lens(lens::LensArgs),
    /// False-colour maps of a polarised render (DoLP, AoLP, S3/S0) with legends, as one PNG.
    Polviz(polviz::PolvizArgs),
    /// Compare prisma with Mitsuba 3 references and analytic answers (validation/cases.toml).
    Validate(validate::ValidateArgs),
    /// Raw ray throughput of the BVH on an OBJ mesh for a stored ray set (benchmarks).
    BenchRays(bench::BenchArgs),
}

/// A failed command: bad input (exit code 2), a failure while running (exit code 1), or an
/// interrupted render that wrote what it had (exit code 130).
#[derive(Debug)]
pub enum CliError {
    /// The user's input is wrong (scene file, arguments).
    Input(anyhow::Error),
    /// Something failed while running (I/O, ...).
    Failed(anyhow::Error),
    /// Interrupted (Ctrl-C, SIGTERM): the message says what was written.
    Interrupted(anyhow::Error),
}

impl CliError {
    /// The process exit code.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) => 2,
            CliError::Failed(_) => 1,
            CliError::Interrupted(_) => 130,
        }
    }
    /// The whole error chain on one line.
    pub fn message(&self) -> String {
        let (CliError::Input(e) | CliError::Failed(e) | CliError::Interrupted(e)) = self;
        // One line, and no control sequence from a file's text reaches the terminal.
        prisma::printable::one_line(&format!("{e:#}"))
    }
}

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Some(Command::Render(args)) => render::run(&args),
        Some(Command::Merge(args)) => merge::run(&args),
        Some(Command::Info(args)) => info::run(&args),
        Some(Command::Export(args)) => export::run(&args),
        Some(Command::Fresnel(args)) => fresnel::run(&args),
        Some(Command::Glass(args)) => glass::run(&args),
        Some(Command::Lens(args)) => lens::run(&args),
        Some(Command::Polviz(args)) => polviz::run(&args),
        Some(Command::Validate(args)) => validate::run(&args),
        Some(Command::BenchRays(args)) => bench::run(&args),
        None => render::run(&render::RenderArgs::default_scene()),
    }
}

/// Prints `text` and a newline to standard output, ignoring errors: a closed pipe (`prisma … |
/// head`) must not turn a finished command into a panic.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}
pub(crate) use say;

/// An output error as a command failure: a destination that cannot be used is bad input (exit
/// code 2, found before any work); a failed write is a failure while running (exit code 1).
pub fn output_error(error: prisma::output::OutputError, context: &str) -> CliError {
    match error {
        prisma::output::OutputError::Destination { .. } => CliError::Input(error.into()),
        error => CliError::Failed(anyhow::Error::from(error).context(context.to_owned())),
    }
}
