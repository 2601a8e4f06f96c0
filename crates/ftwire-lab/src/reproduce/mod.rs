//! A reproduction of the paper's §IV (`ftwire reproduce`): every experiment ftwire has, in the
//! simulator, and one report that sets the paper's tables beside ours.
//!
//! The calibrations run first ([`ReproduceParams::calibration_jobs`]: the simulated sensor's and
//! the real-like recording's); the experiments that use them
//! ([`ReproduceParams::experiment_jobs`]) then run in parallel, [`ReproduceParams::jobs`]
//! at a time on a rayon pool, each through the caller's [`Runner`] (the `ftwire` binary runs
//! each as an `ftwire experiment` process of its own, [`Job::run_as_child`], so their printed
//! tables do not interleave and one failure does not take the others down) with its own results folder and
//! log. Every experiment is seeded by [`ReproduceParams::seed`] alone, so the results do not
//! depend on the number of jobs.
//!
//! [`run`] writes into the reproduction's results folder one subfolder per experiment (its
//! own `summary.json`, figures and `log.txt`), `report.md` (the tables, [`crate::beside`]) and
//! `report.html` (the tables and every experiment's figures in one self-contained page); the
//! caller writes `summary.json` ([`ReproduceRun::summary`]: `quick`, then each experiment's
//! `{id, status}`) and `timings.json` ([`ReproduceRun::timings`]), and with `--docs` the
//! documentation's page ([`docs`]). Guarded by the `ftwire` binary's `tests/reproduce_cli.rs`.

mod child;
pub mod docs;
mod jobs;
mod page;
mod params;

use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

pub use child::PARENT_PID_VAR;
#[cfg(unix)]
pub use child::end_with_parent;
pub use jobs::{Job, REAL_LIKE_ARGS, REAL_LIKE_SUFFIX};
pub use params::ReproduceParams;

use crate::error::LabError;
use crate::results::ResultsFolder;
use ftwire_app::input::CountRange;

/// `--jobs`: each job is an experiment process of its own, and there are fewer experiments
/// than the cap, so more jobs would only add idle threads.
pub const JOBS: CountRange = CountRange::new(1, 64);

/// The status of an experiment that ran to its end.
pub const OK: &str = "ok";

/// Runs one job to its end: `Ok` when the experiment succeeded, otherwise why not (e.g. its
/// exit code and its log's last line). Called from the pool's threads.
pub type Runner<'a> = &'a (dyn Fn(&Job) -> Result<(), String> + Sync);

/// Where a reproduction reports its progress (one line per call: the plan, each experiment's
/// end). Called from the pool's threads.
pub type SharedProgress<'a> = &'a (dyn Fn(&str) + Sync);

/// One experiment's result in `summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Status {
    /// The experiment's id.
    pub id: &'static str,
    /// [`OK`], or the failure (e.g. the exit code and the log's last line).
    pub status: String,
}

/// `summary.json`'s body of a reproduction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReproduceSummary {
    /// Whether the trial counts were reduced.
    pub quick: bool,
    /// Each experiment's status, in report order (the calibration first).
    pub experiments: Vec<Status>,
}

/// `timings.json` of a reproduction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReproduceTimings {
    /// Each experiment's wall time \[s\] (those that ran).
    pub experiments: Vec<(&'static str, f64)>,
    /// The reproduction's wall time \[s\].
    pub total_s: f64,
}

/// A finished reproduction.
#[derive(Debug, Clone)]
pub struct ReproduceRun {
    /// `summary.json`'s body (after the run header).
    pub summary: ReproduceSummary,
    /// `timings.json`.
    pub timings: ReproduceTimings,
    /// `report.md`: the statuses and the paper's tables beside ours.
    pub report: String,
}

impl ReproduceRun {
    /// The experiments' ids, in report order.
    pub fn ids(&self) -> Vec<&'static str> {
        self.summary.experiments.iter().map(|s| s.id).collect()
    }

    /// Whether every experiment ran to its end.
    ///
    /// # Errors
    /// No answer naming the experiments that failed and where their logs are (`results`, the
    /// reproduction's folder).
    pub fn require_all_ok(&self, results: &Path) -> Result<(), LabError> {
        let failed: Vec<&str> = self
            .summary
            .experiments
            .iter()
            .filter(|s| s.status != OK)
            .map(|s| s.id)
            .collect();
        if failed.is_empty() {
            Ok(())
        } else {
            Err(LabError::no_answer(format!(
                "experiments that failed: {} (their logs are in {})",
                failed.join(", "),
                results.display()
            )))
        }
    }
}

/// Runs one job through `runner`, moves its log into its folder when it has one, and reports
/// its end; returns its status and wall time \[s\].
fn run_job(job: &Job, runner: Runner, progress: SharedProgress) -> (Status, f64) {
    let start = Instant::now();
    let status = runner(job);
    if job.out.is_dir() {
        let _ = std::fs::rename(&job.log, job.out.join("log.txt"));
    }
    let seconds = start.elapsed().as_secs_f64();
    progress(&format!(
        "reproduce: {} {} ({seconds:.0} s)",
        job.id,
        status
            .as_ref()
            .map_or_else(|e| format!("failed: {e}"), |()| "done".to_owned())
    ));
    let status = status.map_or_else(|e| e, |()| OK.to_owned());
    (Status { id: job.id, status }, seconds)
}

/// Runs the calibrations, then every other experiment on a pool of [`ReproduceParams::jobs`]
/// threads (an experiment whose calibration failed is "not run"), each into its subfolder
/// of `folder` through `runner`; writes `report.md` and `report.html`, and returns the summary,
/// timings and report for the caller to write (it does not finish the folder).
///
/// # Errors
/// Bad input when the pool cannot be built; I/O errors writing the folder. A failed
/// experiment is a status, not an error ([`ReproduceRun::require_all_ok`]).
pub fn run(
    params: &ReproduceParams,
    folder: &ResultsFolder,
    runner: Runner,
    progress: SharedProgress,
) -> Result<ReproduceRun, LabError> {
    let total = Instant::now();
    let jobs = params.jobs();
    let dir = folder.dir().to_path_buf();
    let calibrations = params.calibration_jobs(&dir);
    let rest = params.experiment_jobs(&dir);
    let quick = params.quick;
    let expected = |jobs_of: &[Job]| {
        let parallel: f64 = jobs_of.iter().map(|j| j.expected(quick)).sum::<f64>() / jobs as f64;
        let longest = jobs_of
            .iter()
            .map(|j| j.expected(quick))
            .fold(0.0, f64::max);
        parallel.max(longest)
    };
    progress(&format!(
        "reproduce: {} experiments{}, {jobs} at a time; expected time about {:.0} min on a \
         2-core machine",
        calibrations.len() + rest.len(),
        if quick { " (quick)" } else { "" },
        ((expected(&calibrations) + expected(&rest)) / 60.0).ceil()
    ));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| LabError::bad_input(format!("--jobs {jobs}: {e}")))?;
    let run_all = |list: &[&Job]| -> Vec<(Status, f64)> {
        pool.install(|| {
            list.par_iter()
                .map(|job| run_job(job, runner, progress))
                .collect()
        })
    };
    let mut statuses = Vec::new();
    let mut timings = Vec::new();
    let first: Vec<&Job> = calibrations.iter().collect();
    for (job, (status, seconds)) in calibrations.iter().zip(run_all(&first)) {
        statuses.push(status);
        timings.push((job.id, seconds));
    }
    let calibrated = |job: &Job| {
        statuses
            .iter()
            .any(|s| Some(s.id) == job.calibration && s.status == OK)
    };
    let (runnable, blocked): (Vec<&Job>, Vec<&Job>) = rest.iter().partition(|j| calibrated(j));
    let done = run_all(&runnable);
    // In report order: every experiment job, run or not.
    for job in &rest {
        if let Some(i) = runnable.iter().position(|r| r.id == job.id) {
            let (status, seconds) = done[i].clone();
            statuses.push(status);
            timings.push((job.id, seconds));
        } else if blocked.iter().any(|b| b.id == job.id) {
            statuses.push(Status {
                id: job.id,
                status: format!(
                    "not run: the calibration {} failed",
                    job.calibration.unwrap_or("?")
                ),
            });
        }
    }
    let pairs: Vec<(&str, &str)> = statuses.iter().map(|s| (s.id, s.status.as_str())).collect();
    let report = crate::beside::report(&dir, &pairs, quick, &params.sensor_words());
    folder.write("report.md", &report)?;
    let ids: Vec<&str> = statuses.iter().map(|s| s.id).collect();
    page::write(folder, &dir, &report, &ids)?;
    Ok(ReproduceRun {
        summary: ReproduceSummary {
            quick,
            experiments: statuses,
        },
        timings: ReproduceTimings {
            experiments: timings,
            total_s: total.elapsed().as_secs_f64(),
        },
        report,
    })
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;
    use crate::results::OutGuard;

    /// The report (report.md and report.html) and the statuses do not depend on the number of jobs, nor on the order in
    /// which the experiments end: each job here ends later the earlier it is listed, one
    /// experiment fails, and the experiments of the failed calibration are not run.
    #[test]
    fn the_report_is_the_same_for_any_number_of_jobs_and_any_order_of_ending() {
        let parent = std::env::temp_dir().join(format!("ftwire-jobs-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&parent);
        std::fs::create_dir_all(&parent).expect("creates a temporary folder");
        let run_with = |jobs: usize| {
            let params = ReproduceParams {
                quick: true,
                jobs: Some(jobs),
                ..ReproduceParams::default()
            };
            // The experiments listed first end last.
            let order: Vec<&'static str> = params
                .experiment_jobs(Path::new("/x"))
                .iter()
                .map(|j| j.id)
                .collect();
            let runner = move |job: &Job| {
                let later = order.len() - order.iter().position(|id| *id == job.id).unwrap_or(0);
                std::thread::sleep(Duration::from_millis(5) * u32::try_from(later).unwrap_or(0));
                match job.id {
                    "goal" => Err("exit 1: no goal".to_owned()),
                    "calibrate_real_like" => Err("exit 1: no labels".to_owned()),
                    _ => Ok(()),
                }
            };
            let folder =
                ResultsFolder::create(&parent.join(format!("jobs{jobs}")), &OutGuard::default())
                    .expect("a results folder");
            let run = super::run(&params, &folder, &runner, &|_| {}).expect("runs");
            let page =
                std::fs::read_to_string(folder.dir().join("report.html")).expect("report.html");
            (run.summary, run.report, page)
        };
        let (one, one_report, one_page) = run_with(1);
        let (three, three_report, three_page) = run_with(3);
        assert_eq!(one, three);
        assert_eq!(one_report, three_report);
        assert_eq!(one_page, three_page);
        let status = |id: &str| {
            one.experiments
                .iter()
                .find(|s| s.id == id)
                .map(|s| s.status.clone())
        };
        assert_eq!(status("calibrate").as_deref(), Some(OK));
        assert_eq!(status("goal").as_deref(), Some("exit 1: no goal"));
        assert_eq!(
            status("shape_real_like").as_deref(),
            Some("not run: the calibration calibrate_real_like failed")
        );
        let ids: Vec<&str> = one.experiments.iter().map(|s| s.id).collect();
        assert_eq!(ids[..2], ["calibrate", "calibrate_real_like"]);
        let _ = std::fs::remove_dir_all(&parent);
    }
}
