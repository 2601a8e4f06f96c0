//! `ftwire identify --log FILE.jsonl`: identify a wire's `η = (c1, c2, c3, L)` from a recorded
//! log, through the one identification the live experiment makes, so that both give the same
//! answer on the same data and seed. The work is [`ftwire_lab::log::identify`]'s; this
//! command maps the options, shows the search's progress on a terminal and prints the
//! estimate.

use std::io::{self, IsTerminal};
use std::time::Duration;

use ftwire_app::output;
use ftwire_lab::error::LabError;
use ftwire_lab::experiment::Progress;
use ftwire_lab::log::identify::{self, IdentifyLogParams};
use indicatif::{ProgressBar, ProgressStyle};
use nalgebra::Vector3;

use crate::cli::identify::IdentifyArgs;

/// The lab's settings of `args`.
///
/// # Errors
/// Bad input for a mounting file that cannot be read.
fn params(args: &IdentifyArgs) -> Result<IdentifyLogParams, LabError> {
    Ok(IdentifyLogParams {
        log: args.log.clone(),
        calibration: args.calibration.file.clone(),
        mounting: args.mounting.given()?,
        samples: args.samples,
        residual: args.settings.settings(),
        gravity: args.gravity.map(|g| Vector3::from(g.0)),
        seed: args.seed.seed,
        drift: args
            .drift
            .sensor
            .as_deref()
            .map(|given| {
                ftwire_lab::log::identify::LogDrift::load(
                    given,
                    args.drift.rest_samples,
                    args.drift.tare_samples,
                    args.drift.tare_time,
                )
            })
            .transpose()?,
        front_end: ftwire_lab::error::FrontEnd::Cli,
    })
}

/// Runs `ftwire identify`.
pub fn run(args: IdentifyArgs) -> Result<(), LabError> {
    let params = params(&args)?;
    params.check()?;
    let samples = identify::samples(&params)?;
    let report = with_progress_line(samples.len(), |progress| {
        identify::estimate(&params, &samples, progress)
    })?;
    output::print_display(&report, args.output.json)?;
    report.verdict(&args.log)
}

/// Runs `work` with a progress line on stderr while it runs, when stderr is a terminal: where
/// the search is, and the time so far. The time grows in proportion to the samples, so the
/// line also says how to take fewer (`--samples`).
fn with_progress_line<T>(samples: usize, work: impl FnOnce(Progress) -> T) -> T {
    let bar = io::stderr().is_terminal().then(|| {
        let bar = ProgressBar::new_spinner();
        let style = ProgressStyle::with_template("{spinner} {prefix}: {msg} ({elapsed})")
            .unwrap_or_else(|_| ProgressStyle::default_spinner());
        bar.set_style(style);
        bar.set_prefix(format!(
            "identifying from {samples} samples (--samples N takes the first N)"
        ));
        bar.enable_steady_tick(Duration::from_millis(200));
        bar
    });
    let result = work(&mut |line| {
        if let Some(bar) = &bar {
            bar.set_message(line.to_owned());
        }
    });
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    result
}
