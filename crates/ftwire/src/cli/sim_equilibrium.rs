//! Arguments of `ftwire sim-equilibrium`.

use clap::Args;

/// Arguments of `ftwire sim-equilibrium`.
#[derive(Debug, Args)]
pub struct SimEquilibriumArgs {}
