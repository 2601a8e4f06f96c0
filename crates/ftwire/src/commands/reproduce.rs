//! `ftwire reproduce`: every experiment of the paper's §IV that ftwire has, in the simulator,
//! and one report that sets the paper's tables beside ours.
//!
//! The calibration runs first (gravity on, labels from the loaded model); the experiments that
//! use it then run in parallel, `--jobs` at a time on a rayon pool, each as its own
//! `ftwire experiment` process (this binary) with its own results folder and log, so their
//! printed tables do not interleave and one failure does not take the others down. Every
//! experiment is seeded by `--seed` alone, so the results do not depend on `--jobs`.
//!
//! Results folder (`--out`, default `results/reproduce`, written whole or not at all): one
//! subfolder per experiment (its own `summary.json`, figures and `log.txt`), `report.md` (the
//! tables), `report.html` (the tables and every experiment's figures in one self-contained
//! page; [`page`]), `summary.json` (the run header, then `quick`, `experiments`: each
//! `{id, status}`), `timings.json` (each experiment's wall time).

use std::fs::File;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::results::OutGuard;
use ftwire_report::html::code_span;
use rayon::prelude::*;
use serde::Serialize;

use crate::cli::reproduce::ReproduceArgs;

mod docs;
mod page;

/// One experiment run as a child process.
struct Job {
    /// Its subfolder and name in the report.
    id: &'static str,
    /// `ftwire` arguments before `--out` and `--seed`.
    args: Vec<String>,
    /// Expected wall time \[s\] on a 2-core machine, quick and full, announced before the run
    /// (an estimate, not a bound).
    expected_s: (f64, f64),
}

/// One experiment's result in `summary.json`.
#[derive(Debug, Serialize)]
struct Status {
    id: &'static str,
    /// `ok`, or the failure (exit code and the log's last line).
    status: String,
}

/// `summary.json`'s body.
#[derive(Debug, Serialize)]
struct Summary {
    quick: bool,
    experiments: Vec<Status>,
}

/// `timings.json`.
#[derive(Debug, Serialize)]
struct Timings {
    experiments: Vec<(&'static str, f64)>,
    total_s: f64,
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| (*s).to_owned()).collect()
}

/// The calibration job (it runs alone, before the others).
fn calibration_job(quick: bool) -> Job {
    let trials = if quick { "300" } else { "600" };
    Job {
        id: "calibrate",
        args: strings(&["experiment", "calibrate", "--trials", trials]),
        expected_s: (25.0, 50.0),
    }
}

/// The jobs that use the calibration, in report order. Quick: the paper's trial counts at
/// three samples only; full: every sample count of Figs. 3–4.
fn experiment_jobs(quick: bool, calibration: &Path) -> Vec<Job> {
    let calibration = calibration.to_string_lossy().into_owned();
    let mut identify = strings(&["experiment", "identify"]);
    if quick {
        identify.extend(strings(&["--samples", "3"]));
    }
    let mut shape = strings(&["experiment", "shape"]);
    let mut goal = strings(&["experiment", "goal"]);
    if quick {
        goal.extend(strings(&["--pairs", "10"]));
    }
    let mut track = strings(&["experiment", "track"]);
    let mut passage = strings(&["experiment", "passage"]);
    let mut passage_offset = strings(&["experiment", "passage", "--noise-model", "offset"]);
    if quick {
        track.extend(strings(&["--pairs", "2"]));
        // One plan: the choice among candidates costs a plan each (`experiment passage
        // --plan-candidates`).
        passage.extend(strings(&["--attempts", "4", "--plan-candidates", "1"]));
        passage_offset.extend(strings(&["--attempts", "4"]));
    }
    for args in [
        &mut identify,
        &mut shape,
        &mut goal,
        &mut track,
        &mut passage,
        &mut passage_offset,
    ] {
        args.extend(["--calibration".to_owned(), calibration.clone()]);
    }
    vec![
        Job {
            id: "identify",
            args: identify,
            expected_s: (5.0, 120.0),
        },
        Job {
            id: "shape",
            args: shape,
            expected_s: (10.0, 10.0),
        },
        Job {
            id: "goal",
            args: goal,
            expected_s: (25.0, 70.0),
        },
        Job {
            id: "track",
            args: track,
            expected_s: (50.0, 220.0),
        },
        Job {
            id: "passage",
            args: passage,
            expected_s: (20.0, 230.0),
        },
        Job {
            id: "passage_offset",
            args: passage_offset,
            expected_s: (20.0, 170.0),
        },
    ]
}

/// Runs one job into `dir/<id>`; returns its status and wall time.
fn run_job(job: &Job, dir: &Path, seed: u64) -> (Status, f64) {
    let start = Instant::now();
    let out = dir.join(job.id);
    let log = dir.join(format!("{}.log", job.id));
    let status = (|| -> Result<(), String> {
        let exe = std::env::current_exe().map_err(|e| format!("cannot find ftwire itself: {e}"))?;
        let file =
            File::create(&log).map_err(|e| format!("cannot write {}: {e}", log.display()))?;
        let err = file
            .try_clone()
            .map_err(|e| format!("cannot write {}: {e}", log.display()))?;
        let exit = ftwire_lab::results::run_child(
            Command::new(exe)
                .args(&job.args)
                .arg("--seed")
                .arg(seed.to_string())
                .arg("--out")
                .arg(&out)
                .env(crate::PARENT_PID_VAR, std::process::id().to_string())
                .stdin(Stdio::null())
                .stdout(file)
                .stderr(err),
        )
        .map_err(|e| format!("cannot start: {e}"))?;
        if exit.success() {
            Ok(())
        } else {
            let text = std::fs::read_to_string(&log).unwrap_or_default();
            let last = text.lines().last().unwrap_or("").to_owned();
            Err(format!("exit {}: {last}", exit.code().unwrap_or(-1)))
        }
    })();
    // The log goes into the experiment's folder when it has one.
    if out.is_dir() {
        let _ = std::fs::rename(&log, out.join("log.txt"));
    }
    let seconds = start.elapsed().as_secs_f64();
    eprintln!(
        "reproduce: {} {} ({seconds:.0} s)",
        job.id,
        status
            .as_ref()
            .map_or_else(|e| format!("failed: {e}"), |()| "done".to_owned())
    );
    (
        Status {
            id: job.id,
            status: status.map_or_else(|e| e, |()| "ok".to_owned()),
        },
        seconds,
    )
}

/// Runs every experiment and writes the report.
pub fn run(args: ReproduceArgs) -> Result<(), LabError> {
    let total = Instant::now();
    let seed = args.seed.seed;
    let jobs = args.jobs.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    // A bad sensor or rig file, or a docs page that is not ftwire's, is bad input before
    // anything runs or is written.
    args.setup.load()?;
    if let Some(dir) = &args.docs {
        docs::check(dir, args.results.force)?;
    }
    let mut passed_on = Vec::new();
    if let Some(sensor) = &args.setup.sensor {
        passed_on.extend(["--sensor".to_owned(), sensor.clone()]);
    }
    if let Some(rig) = &args.setup.rig {
        passed_on.extend(["--rig".to_owned(), rig.to_string_lossy().into_owned()]);
    }
    let inputs = OutGuard::default()
        .input_opt("--sensor", args.setup.sensor.as_deref())
        .input_opt("--rig", args.setup.rig.as_deref());
    let folder = args.results.open("reproduce", inputs)?;
    let dir = folder.dir().to_path_buf();
    let mut calibration = calibration_job(args.quick);
    let calibration_file = dir.join(calibration.id).join("calibration.json");
    let mut rest = experiment_jobs(args.quick, &calibration_file);
    for job in std::iter::once(&mut calibration).chain(rest.iter_mut()) {
        job.args.extend(passed_on.iter().cloned());
    }
    let pick = |(quick, full): (f64, f64)| if args.quick { quick } else { full };
    let parallel: f64 = rest.iter().map(|j| pick(j.expected_s)).sum::<f64>() / jobs as f64;
    let longest = rest.iter().map(|j| pick(j.expected_s)).fold(0.0, f64::max);
    eprintln!(
        "reproduce: {} experiments{}, {jobs} at a time; expected time about {:.0} min on a \
         2-core machine",
        rest.len() + 1,
        if args.quick { " (quick)" } else { "" },
        ((pick(calibration.expected_s) + parallel.max(longest)) / 60.0).ceil()
    );
    let (first, first_s) = run_job(&calibration, &dir, seed);
    let mut statuses = vec![first];
    let mut timings = vec![(calibration.id, first_s)];
    if statuses[0].status == "ok" {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(jobs)
            .build()
            .map_err(|e| LabError::bad_input(format!("--jobs {jobs}: {e}")))?;
        let results: Vec<(Status, f64)> = pool.install(|| {
            rest.par_iter()
                .map(|job| run_job(job, &dir, seed))
                .collect()
        });
        for (job, (status, seconds)) in rest.iter().zip(results) {
            statuses.push(status);
            timings.push((job.id, seconds));
        }
    } else {
        for job in &rest {
            statuses.push(Status {
                id: job.id,
                status: "not run: the calibration failed".to_owned(),
            });
        }
    }
    let sensor = match (&args.setup.sensor, &args.setup.rig) {
        (None, None) => "the default F/T sensor".to_owned(),
        (sensor, rig) => format!(
            "the F/T sensor {} and the rig {}",
            code_span(sensor.as_deref().unwrap_or("distorted")),
            code_span(
                &rig.as_ref()
                    .map_or_else(|| "default".to_owned(), |r| r.display().to_string())
            ),
        ),
    };
    let pairs: Vec<(&str, &str)> = statuses.iter().map(|s| (s.id, s.status.as_str())).collect();
    let markdown = ftwire_lab::beside::report(&dir, &pairs, args.quick, &sensor);
    folder.write("report.md", &markdown)?;
    let ids: Vec<&str> = statuses.iter().map(|s| s.id).collect();
    page::write(&folder, &dir, &markdown, &ids)?;
    let failed: Vec<&str> = statuses
        .iter()
        .filter(|s| s.status != "ok")
        .map(|s| s.id)
        .collect();
    let header = RunHeader::new("reproduce", Some(seed), &args)?;
    let summary = Summary {
        quick: args.quick,
        experiments: statuses,
    };
    let timings = &Timings {
        experiments: timings,
        total_s: total.elapsed().as_secs_f64(),
    };
    let target = folder.finish_run(&header, &summary, &timings)?;
    println!(
        "reproduce: report in {}",
        target.join("report.md").display()
    );
    if let Some(dir) = &args.docs {
        let command = std::iter::once("ftwire".to_owned())
            .chain(std::env::args().skip(1))
            .collect::<Vec<_>>()
            .join(" ");
        let page = docs::write(dir, &target, &markdown, &ids, &command)?;
        println!("reproduce: results page in {}", page.display());
    }
    if failed.is_empty() {
        Ok(())
    } else {
        Err(LabError::no_answer(format!(
            "experiments that failed: {} (their logs are in {})",
            failed.join(", "),
            target.display()
        )))
    }
}
