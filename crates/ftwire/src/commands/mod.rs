//! One module per subcommand; each exposes `run(args) -> anyhow::Result<ExitCode>`.

pub mod robot;
pub mod sim_equilibrium;
pub mod solve;

use std::process::ExitCode;

use crate::cli::{Cli, Command};

/// Runs the chosen subcommand.
pub fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Command::Solve(args) => solve::run(args),
        Command::SimEquilibrium(args) => sim_equilibrium::run(args),
        Command::Robot(args) => robot::run(args),
    }
}
