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

use std::fmt::Write as _;
use std::fs::File;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::paper::{TABLE_I, TABLE_II};
use ftwire_lab::results::OutGuard;
use ftwire_report::html::{code_span, escape_markdown};
use rayon::prelude::*;
use serde::Serialize;
use serde_json::Value;

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
    let markdown = report(&dir, &statuses, args.quick, &sensor);
    folder.write("report.md", &markdown)?;
    let ids: Vec<&str> = statuses.iter().map(|s| s.id).collect();
    page::write(&folder, &dir, &markdown, &ids)?;
    let failed: Vec<&str> = statuses
        .iter()
        .filter(|s| s.status != "ok")
        .map(|s| s.id)
        .collect();
    folder.write_json(
        "timings.json",
        &Timings {
            experiments: timings,
            total_s: total.elapsed().as_secs_f64(),
        },
    )?;
    let header = RunHeader::new("reproduce", Some(seed), &args)?;
    let summary = Summary {
        quick: args.quick,
        experiments: statuses,
    };
    let target = folder.finish(&header, &summary)?;
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

/// An experiment's `summary` object, if it ran.
fn summary_of(dir: &Path, id: &str) -> Option<Value> {
    let text = std::fs::read_to_string(dir.join(id).join("summary.json")).ok()?;
    let value: Value = serde_json::from_str(&text).ok()?;
    value.get("summary").cloned()
}

fn percent(v: &Value) -> String {
    v.as_f64()
        .map_or_else(|| "–".to_owned(), |x| format!("{:.2}", 100.0 * x))
}

fn number(v: &Value, digits: usize) -> String {
    v.as_f64()
        .map_or_else(|| "–".to_owned(), |x| format!("{x:.digits$}"))
}

/// `report.md`: the paper's tables beside ours. `sensor` is Markdown; every text read from the
/// experiments' summaries and statuses goes in as literal text.
fn report(dir: &Path, statuses: &[Status], quick: bool, sensor: &str) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# ftwire against Mishani & Sintov (RA-L 2022), §IV\n\nIn the simulator, gravity on, \
         {sensor} through the learnt calibration{}. Each experiment's own folder has its full \
         summary, figures and log.\n",
        if quick {
            "; **quick run** (reduced trial counts)"
        } else {
            ""
        }
    );
    let _ = writeln!(md, "| experiment | status |\n| --- | --- |");
    for s in statuses {
        let _ = writeln!(
            md,
            "| {} | {} |",
            code_span(s.id),
            escape_markdown(&s.status)
        );
    }
    md.push('\n');
    if let Some(s) = summary_of(dir, "identify") {
        identification_table(&mut md, &s);
    }
    if let Some(s) = summary_of(dir, "calibrate") {
        let _ = writeln!(
            md,
            "## §IV-A: the learnt F/T calibration\n\nOn the test split of the known wire \
             ({}): relative error of `ã` against the true wrench, and the shape error of \
             Φ(ã).\n\n| map | torque % | force % | shape mm |\n| --- | --- | --- | --- |\n\
             | raw (mounting only) | {} | {} | {} |\n| calibrated | {} | {} | {} |\n",
            escape_markdown(s["wire"]["name"].as_str().unwrap_or("?")),
            percent(&s["raw"]["torque_rel"]),
            percent(&s["raw"]["force_rel"]),
            number(&s["raw"]["shape_mm"], 2),
            percent(&s["calibrated"]["torque_rel"]),
            percent(&s["calibrated"]["force_rel"]),
            number(&s["calibrated"]["shape_mm"], 2),
        );
    }
    if let Some(s) = summary_of(dir, "shape") {
        let _ = writeln!(
            md,
            "## Table II: shape from F/T, mean distance to the true wire [mm]\n\n\
             | wire | ours, loaded model | ours, the paper's model (same ã) | paper |\n\
             | --- | --- | --- | --- |"
        );
        for wire in s["wires"].as_array().into_iter().flatten() {
            let name = wire["name"].as_str().unwrap_or("?");
            let paper = TABLE_II
                .iter()
                .find(|(n, _)| *n == name)
                .map_or_else(|| "–".to_owned(), |(_, mm)| format!("{mm:.2}"));
            let _ = writeln!(
                md,
                "| {} | {} | {} | {paper} |",
                escape_markdown(name),
                number(&wire["loaded_mean_mm"], 2),
                number(&wire["kirchhoff_mean_mm"], 2),
            );
        }
        md.push('\n');
    }
    if let Some(s) = summary_of(dir, "goal") {
        goal_table(&mut md, &s);
    }
    if let Some(s) = summary_of(dir, "track") {
        track_table(&mut md, &s);
    }
    let passages: Vec<Value> = ["passage", "passage_offset"]
        .iter()
        .filter_map(|id| summary_of(dir, id))
        .collect();
    if !passages.is_empty() {
        passage_table(&mut md, &passages);
    }
    md
}

/// Table IV: tracking planned paths, ours beside the paper's.
fn track_table(md: &mut String, s: &Value) {
    let _ = writeln!(
        md,
        "## Table IV: tracking a path planned with RRT* ({} pairs, noise model {}, gain {})\n\n\
         Distance [mm] between the true wire and Φ(γ_A) at each waypoint reached, over every \
         waypoint of every pair (the planning times are in the experiment's `timings.json`).\n\n\
         | | mean ± std | max | waypoints | paper, mean ± std |\n| --- | --- | --- | --- | --- |",
        number(&s["pairs"], 0),
        code_span(s["noise_model"].as_str().unwrap_or("?")),
        number(&s["gain"], 2),
    );
    let (open, closed, closed_std) = ftwire_lab::paper::TABLE_IV;
    for (key, label, paper) in [
        ("open_loop", "open loop", format!("{open:.2}")),
        (
            "closed_loop",
            "closed loop",
            format!("{closed:.2} ± {closed_std:.2}"),
        ),
    ] {
        let r = &s["results"][key];
        let _ = writeln!(
            md,
            "| {label} | {} ± {} | {} | {} | {paper} |",
            number(&r["mean_mm"], 2),
            number(&r["std_mm"], 2),
            number(&r["max_mm"], 2),
            number(&r["waypoints"], 0),
        );
    }
    md.push('\n');
}

/// §IV-E: the passage success rates, ours beside the paper's
/// (`ftwire_lab::paper::PASSAGE_SUCCESSES`, with the paper's noise).
fn passage_table(md: &mut String, runs: &[Value]) {
    use ftwire_lab::paper::{PASSAGE_ATTEMPTS, PASSAGE_SUCCESSES};
    let _ = writeln!(
        md,
        "## §IV-E: through the 50 mm passage\n\nSuccess: the whole path executed and the true \
         wire never touched a box; under `offset` it must also end within the success tolerance \
         of the goal, under `increment` (whose every move lands the wire the full noise away) \
         the paper's rule, no collision, decides. At goal: completed within the tolerance, under \
         every noise model. Collisions: the true wire touched a box; detected: of those, stopped \
         by the collision detector.\n\n\
         | noise model | mode | successes | at goal | collisions | detected | false alarms | paper |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    let rate = |successes: usize| format!("{successes}/{PASSAGE_ATTEMPTS} (increment)");
    let (open, closed) = (rate(PASSAGE_SUCCESSES.0), rate(PASSAGE_SUCCESSES.1));
    for s in runs {
        let noise = s["noise_model"].as_str().unwrap_or("?");
        for (key, label, paper) in [
            ("open_loop", "open loop", open.as_str()),
            ("closed_loop", "closed loop", closed.as_str()),
        ] {
            let r = &s["results"][key];
            let _ = writeln!(
                md,
                "| {} | {label} | {}/{} | {} | {} | {} | {} | {} |",
                code_span(noise),
                number(&r["successes"], 0),
                number(&r["attempts"], 0),
                number(&r["at_goal"], 0),
                number(&r["collisions"], 0),
                number(&r["detected"], 0),
                number(&r["false_alarms"], 0),
                if noise == "increment" { paper } else { "–" },
            );
        }
    }
    md.push('\n');
}

/// Table I: identification from 3 samples, ours (both models) beside the paper's.
fn identification_table(md: &mut String, s: &Value) {
    let _ = writeln!(
        md,
        "## Table I: identification from 3 samples\n\nOurs: mean ± std over the trials and the \
         error of the mean (as the paper's), then the mean of each trial's absolute error; the \
         loaded model (which also identifies the weight), and the paper's weightless model on \
         the same data.\n\n| wire | parameter | true | ours, loaded | error of mean % | mean \
         abs. error % | paper's model: mean abs. error % | paper | paper error % |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    let models = s["by_model"].as_array().cloned().unwrap_or_default();
    let model = |name: &str| {
        models
            .iter()
            .find(|m| m["model"] == name)
            .map(|m| m["wires"].clone())
    };
    let (Some(loaded), other) = (model("loaded"), model("kirchhoff")) else {
        return;
    };
    let names = ["c1", "c2", "c3", "L"];
    for (w, wire) in loaded.as_array().into_iter().flatten().enumerate() {
        let name = wire["wire"]["name"].as_str().unwrap_or("?");
        let row = &wire["by_samples"][0];
        let other_row = other.as_ref().map(|o| o[w]["by_samples"][0].clone());
        let paper = TABLE_I
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, rows)| rows);
        for (j, parameter) in names.iter().enumerate() {
            let truth = if j < 3 {
                &wire["wire"]["c"][j]
            } else {
                &wire["wire"]["length"]
            };
            let (paper_value, paper_error) = paper.map_or_else(
                || ("–".to_owned(), "–".to_owned()),
                |rows| {
                    let (_, mean, std, error) = rows[j];
                    (format!("{mean:.3} ± {std:.3}"), format!("{error:.1}"))
                },
            );
            let _ = writeln!(
                md,
                "| {} | {parameter} | {} | {} ± {} | {} | {} | {} | {paper_value} | \
                 {paper_error} |",
                escape_markdown(name),
                number(truth, 3),
                number(&row["mean"][j], 4),
                number(&row["std"][j], 4),
                percent(&row["relative_error"][j].as_f64().map(f64::abs).into()),
                percent(&row["mean_abs_relative_error"][j]),
                other_row.as_ref().map_or_else(
                    || "–".to_owned(),
                    |r| percent(&r["mean_abs_relative_error"][j])
                ),
            );
        }
    }
    md.push('\n');
}

/// Paper Table III: mean shape error \[mm\] at the end of a motion to a goal, `(open loop,
/// closed loop)`, without and with the paper's noise (`None` where the paper gives none).
const TABLE_III: [(&str, Option<f64>, Option<f64>); 2] = [
    ("no noise", None, Some(9.67)),
    ("noise", Some(17.35), Some(9.11)),
];

/// Table III: goal reaching, ours beside the paper's.
fn goal_table(md: &mut String, s: &Value) {
    let _ = writeln!(
        md,
        "## Table III: reaching a goal in A ({} pairs, noise model {})\n\nMean distance \
         [mm] between the true final shape and Φ(a_g) (± std), the trials counted (failed runs \
         and simulator failures are left out and listed in the experiment's summary), and the \
         mean over the trials in which the simulated wire did not snap to another shape.\n\n\
         | | ours, open loop | ours, closed loop | paper, open loop | paper, closed loop |\n\
         | --- | --- | --- | --- | --- |",
        number(&s["pairs"], 0),
        code_span(s["noise_model"].as_str().unwrap_or("?")),
    );
    let cell = |v: &Value| {
        format!(
            "{} ± {} ({} trials; {} without snaps)",
            number(&v["mean_mm"], 2),
            number(&v["std_mm"], 2),
            number(&v["trials"], 0),
            number(&v["mean_mm_without_snaps"], 2),
        )
    };
    let paper = |v: Option<f64>| v.map_or_else(|| "–".to_owned(), |x| format!("{x:.2}"));
    for (key, (label, open, closed)) in ["no_noise", "noise"].iter().zip(TABLE_III) {
        let _ = writeln!(
            md,
            "| {label} | {} | {} | {} | {} |",
            cell(&s["results"]["open_loop"][key]),
            cell(&s["results"]["closed_loop"][key]),
            paper(open),
            paper(closed),
        );
    }
    let c = &s["collision"];
    let _ = writeln!(
        md,
        "\nSteps (median, with noise): {}. Collision detection: {} false alarms in {} free \
         motions; {} of {} contacts detected, median delay {} steps.\n",
        number(&s["steps_median"], 1),
        number(&c["false_alarms"], 0),
        number(&c["free_motions"], 0),
        number(&c["detected"], 0),
        number(&c["trials"], 0),
        number(&c["detection_delay_steps_median"], 1),
    );
}
