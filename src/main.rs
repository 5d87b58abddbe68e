//! The `prisma` command line. Without a subcommand it renders the bundled dispersive showcase.
//!
//! Exit codes: 0 success, 1 a failure while running (I/O, ...), 2 bad input (arguments or scene),
//! 130 interrupted (Ctrl-C, SIGTERM or SIGHUP: temporary output files are removed first; an
//! interrupted render first writes what it has as a part).

mod cli;

use std::process::ExitCode;

use clap::Parser as _;

fn main() -> ExitCode {
    // An interrupted command leaves no partial output: the handler removes the temporary files
    // being written (the finished outputs are renamed into place atomically) and exits; a render
    // is first asked to stop (abandoning a light pass in progress) and write what it has as a part
    // (`prisma::interrupt`). If the handler cannot be installed, the default action (terminate)
    // still applies.
    let _ = ctrlc::set_handler(prisma::interrupt::on_signal);
    let args = match cli::Cli::try_parse() {
        Ok(args) => args,
        // --help and --version: clap prints them to standard output.
        Err(error) if !error.use_stderr() => {
            let _ = error.print();
            return ExitCode::SUCCESS;
        }
        // Bad arguments: clap's first line (its message), then one hint, as every other input
        // error is one line.
        Err(error) => {
            let rendered = error.render().to_string();
            let message = rendered.lines().next().unwrap_or("error: invalid arguments");
            eprintln!("{message} (try --help)");
            return ExitCode::from(2);
        }
    };
    match cli::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {}", err.message());
            ExitCode::from(err.exit_code())
        }
    }
}
