//! `ftwire identify --log FILE.jsonl`: identify a wire's `η = (c1, c2, c3, L)` from a recorded
//! log (paper §III-B, eq. 12; the library's `ftwire_estimate::identify`), through the one
//! identification the live experiment (`ftwire experiment identify`) makes
//! ([`ftwire_lab::identify::run_identification`]: the model template, the swarm's random
//! generator), so that both give the same answer on the same data and seed.
//!
//! Records with `a` (tared and calibrated) are used as they are; records with `raw` need
//! `--calibration W` (the learnt weights of `ftwire_estimate::calibration`), which maps the
//! tared raw reading to `a`.

use std::fs::File;
use std::io::{self, BufReader, IsTerminal, Write};
use std::path::Path;
use std::time::Duration;

use ftwire::output::{self, Report};
use ftwire_core::Pose;
use ftwire_estimate::Calibration;
use ftwire_estimate::identify::{Estimate, IdentifierParams, Unidentified};
use ftwire_estimate::log::{LogRecord, read_log};
use ftwire_lab::error::{LabError, from_estimate};
use ftwire_lab::identify::{flag_name, identifier};
use indicatif::{ProgressBar, ProgressStyle};
use nalgebra::{Vector3, Vector6};
use serde::Serialize;

use crate::cli::identify::{FormArg, IdentifyArgs};

/// Runs `ftwire identify`.
pub fn run(args: IdentifyArgs) -> Result<(), LabError> {
    let mut config = args.settings.config()?;
    if let Some(g) = args.gravity {
        config.constraints.weight = Some(Vector3::from(g.0));
        config
            .validate()
            .map_err(|e| LabError::bad_input(format!("--gravity: {e}")))?;
    }
    let records = read(&args.log)?;
    let calibration = args
        .calibration
        .path()
        .map(|path| {
            Calibration::load(path)
                .map_err(|e| LabError::bad_input(format!("--calibration {}: {e}", path.display())))
        })
        .transpose()?;
    let mut samples = samples_of(&records, calibration.as_ref(), &args.log)?;
    if let Some(n) = args.samples {
        if n > samples.len() {
            return Err(LabError::bad_input(format!(
                "--samples {n}: the log {} holds only {} records",
                args.log.display(),
                samples.len()
            )));
        }
        samples.truncate(n);
    }
    let estimate = identify_with_progress(&samples, &config, args.seed.seed)
        .map_err(|e| e.context(format!("identifying from {}", args.log.display())))?;
    let report = EstimateReport::new(&estimate, args.settings.form);
    output::print(&report, args.output.json)?;
    match estimate.unidentified {
        None => Ok(()),
        Some(reason) => Err(LabError::no_answer(format!(
            "the data of {} do not identify the wire: {reason}",
            args.log.display()
        ))),
    }
}

/// Reads the log; a bad line or an empty log is bad input naming the file (the library's error
/// names the line and the value).
fn read(path: &Path) -> Result<Vec<LogRecord>, LabError> {
    let file = File::open(path)
        .map_err(|e| LabError::bad_input(format!("cannot open log {}: {e}", path.display())))?;
    read_log(BufReader::new(file))
        .map_err(|e| LabError::bad_input(format!("log {}: {e}", path.display())))
}

/// The `(ã, b̃)` pairs of the records, in order.
fn samples_of(
    records: &[LogRecord],
    calibration: Option<&Calibration>,
    path: &Path,
) -> Result<Vec<(Vector6<f64>, Pose)>, LabError> {
    records
        .iter()
        .enumerate()
        .map(|(index, record)| {
            let a = match (record.a(), record.raw(), calibration) {
                (Some(a), _, _) => a,
                (None, Some(raw), Some(calibration)) => {
                    let a = calibration.apply(&raw);
                    if let Some(i) = a.iter().position(|v| !v.is_finite()) {
                        return Err(LabError::bad_input(format!(
                            "log {}: record {} (time {}): the calibration maps raw = {:?} to \
                             a[{i}] = {}, not a finite number",
                            path.display(),
                            index + 1,
                            record.time,
                            record.raw,
                            a[i]
                        )));
                    }
                    a
                }
                (None, _, None) => {
                    return Err(LabError::bad_input(format!(
                        "log {}: record {} (time {}) holds `raw`, not `a`: give the learnt \
                         calibration with --calibration W to turn raw readings into \
                         configurations",
                        path.display(),
                        index + 1,
                        record.time
                    )));
                }
                (None, None, Some(_)) => {
                    return Err(LabError::bad_input(format!(
                        "log {}: record {} has neither `raw` nor `a`",
                        path.display(),
                        index + 1
                    )));
                }
            };
            let b = record.b.ok_or_else(|| {
                LabError::bad_input(format!(
                    "log {}: record {} (time {}) has no `b`: identification needs the second \
                     gripper's pose on every record",
                    path.display(),
                    index + 1,
                    record.time
                ))
            })?;
            Ok((a, b.to_pose()))
        })
        .collect()
}

/// How long the search runs between two updates of the progress line.
const PROGRESS_TICK: Duration = Duration::from_millis(200);

/// As [`ftwire_lab::identify::run_identification`], the same estimate for the same samples
/// and seed (the search is cut into steps by [`ftwire_lab::identify::identifier`], which the
/// library's streaming identifier makes independent of the cut), with a progress line on
/// stderr while it runs, when stderr is a terminal: the search round, the swarm iteration,
/// the refinement, and the time so far. The time grows in proportion to the samples, so the
/// line also says how to take fewer (`--samples`).
///
/// # Errors
/// As [`ftwire_lab::identify::run_identification`].
pub fn identify_with_progress(
    samples: &[(Vector6<f64>, Pose)],
    config: &IdentifierParams,
    seed: u64,
) -> Result<Estimate, LabError> {
    let mut identifier = identifier(samples, config, seed)?;
    let bar = io::stderr().is_terminal().then(|| {
        let bar = ProgressBar::new_spinner();
        let style = ProgressStyle::with_template("{spinner} {prefix}: {msg} ({elapsed})")
            .unwrap_or_else(|_| ProgressStyle::default_spinner());
        bar.set_style(style);
        bar.set_prefix(format!(
            "identifying from {} samples (--samples N takes the first N)",
            samples.len()
        ));
        bar.enable_steady_tick(Duration::from_millis(200));
        bar
    });
    let estimate = loop {
        let estimate = identifier.step(PROGRESS_TICK);
        match &estimate {
            Ok(Estimate {
                unidentified:
                    Some(Unidentified::Unfinished {
                        iterations,
                        required,
                    }),
                ..
            }) => {
                if let Some(bar) = &bar {
                    let round = required / config.swarm_iterations.max(1);
                    bar.set_message(if iterations < required {
                        format!("search round {round}, swarm iteration {iterations}/{required}")
                    } else {
                        format!("search round {round}, refining the best fits")
                    });
                }
            }
            _ => break estimate,
        }
    };
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    estimate.map_err(|e| from_estimate(e, "identifying the wire"))
}

/// The estimate as printed (`--json`: one object).
#[derive(Debug, Serialize)]
pub struct EstimateReport {
    /// Samples used.
    pub samples: usize,
    /// The residual form.
    pub form: FormArg,
    /// Stiffnesses `(c1, c2, c3)` \[N·m²\].
    pub c: [f64; 3],
    /// Length \[m\].
    pub length: f64,
    /// Standard deviations of `c` \[N·m²\] (first order).
    pub c_std: [f64; 3],
    /// Standard deviation of `L` \[m\].
    pub length_std: f64,
    /// The linear density `λ` \[kg/m\] (with `--gravity`; absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linear_density: Option<f64>,
    /// Standard deviation of `λ` \[kg/m\] (with `--gravity`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linear_density_std: Option<f64>,
    /// `χ²` per degree of freedom under the assumed noise.
    pub chi2_per_dof: f64,
    /// `σ_min/σ_max` of the residual's Jacobian.
    pub condition: f64,
    /// Whether the data identify the wire.
    pub identified: bool,
    /// Why not ([`flag_name`]), or `null`.
    pub flag: Option<&'static str>,
    /// The reason in words, or `null`.
    pub reason: Option<String>,
}

impl EstimateReport {
    /// The report of `estimate`.
    pub fn new(estimate: &Estimate, form: FormArg) -> Self {
        Self {
            samples: estimate.samples,
            form,
            c: estimate.c,
            length: estimate.length,
            c_std: estimate.c_std,
            length_std: estimate.length_std,
            linear_density: estimate.linear_density,
            linear_density_std: estimate.linear_density_std,
            chi2_per_dof: estimate.chi2_per_dof,
            condition: estimate.condition,
            identified: estimate.is_identified(),
            flag: flag_name(estimate.unidentified.as_ref()),
            reason: estimate.unidentified.map(|r| r.to_string()),
        }
    }
}

impl Report for EstimateReport {
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        writeln!(
            out,
            "identified from {} samples ({:?} residual):",
            self.samples, self.form
        )?;
        let names = ["c1 [N·m²]", "c2 [N·m²]", "c3 [N·m²]"];
        for ((name, value), std) in names.iter().zip(self.c).zip(self.c_std) {
            writeln!(out, "  {name:<10} {value:.6} ± {std:.2e}")?;
        }
        writeln!(
            out,
            "  {:<10} {:.6} ± {:.2e}",
            "L [m]", self.length, self.length_std
        )?;
        if let (Some(lambda), Some(std)) = (self.linear_density, self.linear_density_std) {
            writeln!(out, "  {:<10} {lambda:.6} ± {std:.2e}", "λ [kg/m]")?;
        }
        writeln!(
            out,
            "  χ²/dof {:.3}, condition {:.2e}",
            self.chi2_per_dof, self.condition
        )?;
        match &self.reason {
            None => writeln!(out, "  identified: yes"),
            Some(reason) => writeln!(out, "  identified: NO: {reason}"),
        }
    }
}
