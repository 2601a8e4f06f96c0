//! `ftwire`: sense and steer an elastic wire with a dual-arm robot from one wrist F/T sensor.
//!
//! The binary is thin: clap types live in [`cli`], each subcommand's logic in its own module
//! under [`commands`], the shared argument groups, error type and output writer in the `ftwire`
//! library, and the libraries do the work. Exit codes are mapped here, in one place
//! ([`ftwire::error::CliError::exit_code`]): 0 success, 1 valid input but no answer, 2 bad input.

mod cli;
mod commands;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    match commands::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::from(error.exit_code())
        }
    }
}
