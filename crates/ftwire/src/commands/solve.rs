//! `ftwire solve`: the Kirchhoff model for one configuration or a JSON Lines batch. The work is
//! [`ftwire_lab::solve`]'s; this command maps the options and prints.
//!
//! The batch answers each line as soon as it is read, on one flushed line, so that another
//! process can drive `ftwire solve --batch -` as a service (one line in, one line out). A bad
//! line gets an error object `{"error", "kind", "line"}` and the batch goes on. At the end of
//! the input the exit code sums the batch up: 0 if every line was answered, 2 if any line was
//! bad input, else 1 if any line had no answer (an integration that diverged).

use std::io;
use std::path::Path;

use ftwire_app::output::{self, JsonLines};
use ftwire_lab::error::LabError;
use ftwire_lab::solve::{self, SolveParams};

use crate::cli::solve::SolveArgs;

/// Runs `ftwire solve`.
pub fn run(args: SolveArgs) -> Result<(), LabError> {
    match &args.batch {
        Some(path) => run_batch(path),
        None => run_single(&args),
    }
}

fn run_single(args: &SolveArgs) -> Result<(), LabError> {
    let wire = args.wire.params()?;
    let a = args
        .a
        .ok_or_else(|| LabError::bad_input("solve needs --a A1,..,A6"))?;
    let params = SolveParams {
        wire,
        a: a.0,
        nodes: args.nodes,
        gravity: args.gravity.map(|g| g.to_vector()),
        density: args.density.density,
        natural_curvature: args.natural_curvature.map(|k| k.to_vector()),
    };
    params.check()?;
    output::print_display(&solve::single(&params)?, args.output.json)
}

/// A batch always prints JSON Lines, so `--json` changes nothing there ([`solve::serve`]).
fn run_batch(path: &Path) -> Result<(), LabError> {
    let input = solve::batch_input(path, "--batch")?;
    solve::serve(input, &mut JsonLines::new(io::stdout().lock()))
}
