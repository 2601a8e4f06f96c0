//! `ftwire solve`.

use std::process::ExitCode;

use crate::cli::solve::SolveArgs;

/// Runs `ftwire solve`.
pub fn run(_args: SolveArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("`ftwire solve` is not implemented yet")
}
