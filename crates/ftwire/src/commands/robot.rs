//! `ftwire robot`.

use std::process::ExitCode;

use crate::cli::robot::RobotArgs;

/// Runs `ftwire robot`.
pub fn run(_args: RobotArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("`ftwire robot` is not implemented yet")
}
