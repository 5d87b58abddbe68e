//! The `prisma` command line. Without a subcommand it renders the bundled dispersive showcase.
//!
//! Exit codes: 0 success, 1 a failure while running (I/O, ...), 2 bad input (arguments or scene).

mod cli;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    match cli::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {}", err.message());
            ExitCode::from(err.exit_code())
        }
    }
}
