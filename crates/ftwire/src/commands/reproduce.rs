//! `ftwire reproduce`: every experiment of the paper's §IV that ftwire has, in the simulator,
//! and one report that sets the paper's tables beside ours ([`ftwire_lab::reproduce`] runs
//! them and writes the report).
//!
//! Each experiment runs as an `ftwire experiment` process of its own (this binary), its output
//! in its log, so that printed tables do not interleave and one failure does not take the
//! others down. Results folder (`--out`, default `results/reproduce`, written whole or not at
//! all): one subfolder per experiment, `report.md`, `report.html`, `summary.json` (the run
//! header, then `quick`, `experiments`: each `{id, status}`) and `timings.json`.

use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::reproduce::{self, Job, ReproduceParams};
use ftwire_lab::results::OutGuard;

use crate::cli::reproduce::ReproduceArgs;

/// The lab's settings of `args`.
fn params(args: &ReproduceArgs) -> ReproduceParams {
    ReproduceParams {
        seed: args.seed.seed,
        quick: args.quick,
        jobs: args.jobs,
        sensor: args.setup.sensor.clone(),
        rig: args.setup.rig.clone(),
        docs: args.docs.clone(),
        force: args.results.force,
    }
}

/// Runs `job` as a child process of this binary ([`Job::run_as_child`]).
fn run_job(job: &Job) -> Result<(), String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot find ftwire itself: {e}"))?;
    job.run_as_child(&exe)
}

/// Runs every experiment and writes the report.
pub fn run(args: ReproduceArgs) -> Result<(), LabError> {
    let params = params(&args);
    // A bad sensor or rig file, or a docs page that is not ftwire's, is bad input before
    // anything runs or is written.
    params.check()?;
    let inputs = OutGuard::default()
        .input_opt("--sensor", args.setup.sensor.as_deref())
        .input_opt("--rig", args.setup.rig.as_deref());
    let folder = args.results.open("reproduce", inputs)?;
    let run = reproduce::run(&params, &folder, &run_job, &|line| errln!("{line}"))?;
    let header = RunHeader::new("reproduce", Some(params.seed), &args)?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    outln!(
        "reproduce: report in {}",
        target.join("report.md").display()
    );
    if let Some(dir) = &args.docs {
        let command = std::iter::once("ftwire".to_owned())
            .chain(std::env::args().skip(1))
            .collect::<Vec<_>>()
            .join(" ");
        let page = reproduce::docs::write(dir, &target, &run.report, &run.ids(), &command)?;
        outln!("reproduce: results page in {}", page.display());
    }
    run.require_all_ok(&target)
}
