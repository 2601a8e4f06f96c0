//! `ftwire reproduce`.

use clap::Args;
use ftwire::args::{Count, ResultsArgs, SeedArgs, SimSetupArgs};
use ftwire_lab::reproduce::JOBS;
use serde::Serialize;

/// `ftwire reproduce`: every experiment of the paper's §IV, one report beside the paper.
#[derive(Debug, Clone, Args, Serialize)]
#[command(
    after_help = "Runs the calibration first, then the experiments that use it in \
    parallel, each as its own `ftwire experiment` process with its own results folder and \
    log; writes report.md with the paper's tables beside ours.\n\n\
    Exit codes: 0 every experiment ran, 1 one failed (the report says which), 2 bad input."
)]
pub struct ReproduceArgs {
    /// The seed of every random choice (each experiment gets it).
    #[command(flatten)]
    pub seed: SeedArgs,
    /// Reduced trial counts: a few minutes instead of the full run.
    #[arg(long)]
    pub quick: bool,
    /// Experiments run at once, 1 to 64 [default: the machine's cores]. The results do not
    /// depend on it: every experiment is seeded on its own.
    #[arg(long, value_name = "N", value_parser = Count(JOBS))]
    pub jobs: Option<usize>,
    /// The results folder (`--out`, `--force`) [default: results/reproduce].
    #[command(flatten)]
    #[serde(flatten)]
    pub results: ResultsArgs,
    /// Also write the documentation's results page, `DIR/results.md` with the tables, the
    /// commit, date and machine, and its figures in `DIR/results/` (`--docs docs` writes
    /// the project's `docs/results.md`). A page or folder there that ftwire did not write is
    /// replaced only with `--force`.
    #[arg(long, value_name = "DIR")]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub docs: Option<std::path::PathBuf>,
    /// The simulated sensor and rig, passed on to every experiment (checked before any runs).
    #[command(flatten)]
    pub setup: SimSetupArgs,
}
