//! The `prisma` command line. Without a subcommand it renders the bundled dispersive showcase.
//!
//! Exit codes: 0 success, 1 a failure while running (I/O, ...), 2 bad input (arguments or scene),
//! 130 interrupted (Ctrl-C, SIGTERM or SIGHUP: temporary output files are removed first; an
//! interrupted render first writes what it has as a part).

mod cli;

use std::process::ExitCode;

use clap::{CommandFactory as _, FromArgMatches as _};

fn main() -> ExitCode {
    // An interrupted command leaves no partial output: the handler removes the temporary files
    // being written (the finished outputs are renamed into place atomically) and exits; a render
    // is first asked to stop (abandoning a light pass in progress) and write what it has as a part
    // (`prisma::interrupt`). If the handler cannot be installed, the default action (terminate)
    // still applies.
    let _ = ctrlc::set_handler(prisma::interrupt::on_signal);
    // Negative numbers are values, so that `--spp -4` is refused by the option's own range
    // ("-4 is not in 1..=1048576") rather than as an unknown flag.
    let command = cli::Cli::command()
        .allow_negative_numbers(true)
        .mut_subcommands(|subcommand| subcommand.allow_negative_numbers(true));
    let parsed = command.try_get_matches().and_then(|matches| cli::Cli::from_arg_matches(&matches));
    let args = match parsed {
        Ok(args) => args,
        // --help and --version: clap prints them to standard output.
        Err(error) if !error.use_stderr() => {
            let _ = error.print();
            return ExitCode::SUCCESS;
        }
        // Bad arguments: clap's message on one line (with the names of missing arguments, which
        // it lists on the lines below), then one hint, as every other input error is one line.
        Err(error) => {
            eprintln!("{} (try --help)", one_line_clap_error(&error.render().to_string()));
            return ExitCode::from(2);
        }
    };
    match cli::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            // An interrupted render says what it wrote: not an error of the user's.
            match err.exit_code() {
                130 => eprintln!("{}", err.message()),
                _ => eprintln!("error: {}", err.message()),
            }
            ExitCode::from(err.exit_code())
        }
    }
}

/// Clap's rendered error as one line: its message and the lines that continue it (the missing
/// arguments' names), without the usage and tips that follow.
fn one_line_clap_error(rendered: &str) -> String {
    let message: Vec<&str> = rendered
        .lines()
        .take_while(|line| !line.trim().is_empty() && !line.starts_with("Usage:"))
        .map(str::trim)
        .filter(|line| !line.starts_with("tip:"))
        .collect();
    match message.join(" ") {
        joined if joined.is_empty() => "error: invalid arguments".to_owned(),
        joined => joined,
    }
}

#[cfg(test)]
mod tests {
    use super::one_line_clap_error;

    #[test]
    fn missing_arguments_are_named_on_the_one_line() {
        let rendered = "error: the following required arguments were not provided:\n  --output <OUT.exr>\n  <PART.exr>...\n\nUsage: prisma merge --output <OUT.exr> <PART.exr>...\n\nFor more information, try '--help'.\n";
        assert_eq!(
            one_line_clap_error(rendered),
            "error: the following required arguments were not provided: --output <OUT.exr> <PART.exr>..."
        );
        let tip = "error: unexpected argument '-x' found\n\n  tip: to pass '-x' as a value, use '-- -x'\n\nUsage: prisma\n";
        assert_eq!(one_line_clap_error(tip), "error: unexpected argument '-x' found");
    }
}
