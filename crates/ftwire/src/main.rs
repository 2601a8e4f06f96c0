//! `ftwire`: sense and steer an elastic wire with a dual-arm robot from one wrist F/T sensor.
//!
//! The binary is thin: clap types live in [`cli`], each subcommand's logic in its own module
//! under [`commands`], and the libraries do the work.

mod cli;
mod commands;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    match commands::run(cli) {
        Ok(code) => code,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::from(1)
        }
    }
}
