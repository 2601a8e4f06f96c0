//! `ftwire sim-equilibrium`: one equilibrium of the ground-truth discrete elastic rod, with the
//! base clamp at the identity and the tip clamp at `--tip-position`, `--tip-rotation` (a
//! rotation vector). The work, the checks and the answer's fields are
//! [`ftwire_lab::equilibrium`]'s; this command maps the options and prints. Exit codes: 1 when
//! Newton finds no equilibrium, 2 on bad input.

use ftwire_app::output;
use ftwire_lab::equilibrium::{self, EquilibriumParams};
use ftwire_lab::error::LabError;

use crate::cli::sim_equilibrium::SimEquilibriumArgs;

/// Runs `ftwire sim-equilibrium`.
pub fn run(args: SimEquilibriumArgs) -> Result<(), LabError> {
    let params = EquilibriumParams {
        wire: args.wire.params()?,
        density: args.density.density,
        gravity: args.gravity.to_vector(),
        edges: args.edges,
        tip: args.tip.pose(),
        initial_a: args.initial_a.map(|a| a.to_vector()),
    };
    output::print_display(&equilibrium::solve(&params)?, args.output.json)
}
