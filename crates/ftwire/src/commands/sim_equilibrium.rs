//! `ftwire sim-equilibrium`.

use std::process::ExitCode;

use crate::cli::sim_equilibrium::SimEquilibriumArgs;

/// Runs `ftwire sim-equilibrium`.
pub fn run(_args: SimEquilibriumArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("`ftwire sim-equilibrium` is not implemented yet")
}
