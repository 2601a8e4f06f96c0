//! What the identification experiment reports: the summary's rows over trials (Table I), the
//! timings, `identify.csv` and Figs. 3–4.

use ftwire_report::{LineChart, Series};
use serde::Serialize;

use super::method::Pipeline;
use crate::csv_table::{Cell, CsvTable, text, value};
use crate::error::LabError;
use crate::experiment::stats::median;
use crate::experiment::{Gravity, ModelKind};
use crate::results::ResultsFolder;
use crate::wire::{WireSpec, file_stem};
use ftwire_logs::identification::Form;

/// Names of the four parameters, in the order of every `[4]` array.
pub const PARAMETERS: [&str; 4] = ["c1", "c2", "c3", "L"];

/// The wire's true linear density `ρ π r²` \[kg/m\].
pub fn linear_density(wire: &WireSpec) -> f64 {
    wire.density * std::f64::consts::PI * wire.radius * wire.radius
}

/// The true `(c1, c2, c3, L)` \[N·m², N·m², N·m², m\].
pub fn truth(wire: &WireSpec) -> [f64; 4] {
    [wire.c[0], wire.c[1], wire.c[2], wire.length]
}

/// One identification: a model, a wire, a trial, a sample count.
#[derive(Debug, Clone)]
pub(super) struct Row {
    /// The estimator's model.
    pub(super) model: ModelKind,
    /// The wire's index.
    pub(super) wire: usize,
    pub(super) trial: usize,
    pub(super) samples: usize,
    /// `(c1, c2, c3, L)`, or `None` when identification returned an error.
    pub(super) eta: Option<[f64; 4]>,
    /// The identified linear density \[kg/m\] (the loaded model only).
    pub(super) linear_density: Option<f64>,
    pub(super) chi2_per_dof: f64,
    /// The 95 % interval of each of `(c1, c2, c3, L)`, when the fit has a covariance.
    pub(super) interval95: Option<[[f64; 2]; 4]>,
    /// Flag name, `"error"`, or `None` when identified.
    pub(super) flag: Option<&'static str>,
    pub(super) evaluations: usize,
    pub(super) compute_ms: f64,
}

/// A wire in the summary: its true parameters.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WireOut {
    /// The wire's name.
    pub name: String,
    /// The true stiffnesses `(c1, c2, c3)` \[N·m²\].
    pub c: [f64; 3],
    /// The true length \[m\].
    pub length: f64,
    /// The true linear density `ρ π r²` \[kg/m\] (what the loaded model identifies).
    pub linear_density: f64,
}

impl WireOut {
    /// The summary's record of `wire`.
    pub fn of(wire: &WireSpec) -> Self {
        Self {
            name: wire.name.clone(),
            c: wire.c,
            length: wire.length,
            linear_density: linear_density(wire),
        }
    }
}

/// One sample count's statistics over the trials, each `[4]` over `(c1, c2, c3, L)`; relative
/// errors are fractions (0.005 is 0.5 %).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BySamples {
    /// The sample count identified from.
    pub samples: usize,
    /// Trials that returned an estimate, flagged ones included.
    pub estimated: usize,
    /// Trials whose estimate was not flagged.
    pub identified: usize,
    /// Mean of the estimates.
    pub mean: [f64; 4],
    /// Sample standard deviation of the estimates.
    pub std: [f64; 4],
    /// Relative error of the mean (Table I).
    pub relative_error: [f64; 4],
    /// Mean of each trial's absolute relative error.
    pub mean_abs_relative_error: [f64; 4],
    /// As `mean_abs_relative_error`, over the trials not flagged only (NaN, `null` in JSON,
    /// if none): what a user who heeds the flags gets.
    pub mean_abs_relative_error_identified: [f64; 4],
    /// Median cost-function evaluations over the trials.
    pub evaluations_median: f64,
    /// The share of the trials whose 95 % interval
    /// ([`ftwire_estimate::identify::Estimate::interval95`]) holds the true value; a trial
    /// without an estimate or a covariance counts as a miss (NaN, `null` in JSON, if no trial
    /// ran).
    pub coverage95: [f64; 4],
    /// The identified linear density over the trials (the loaded model only).
    pub linear_density: Option<DensityStats>,
}

/// The identified linear density over trials \[kg/m\].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DensityStats {
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation.
    pub std: f64,
    /// Mean of each trial's absolute relative error (a fraction).
    pub mean_abs_relative_error: f64,
}

/// One model's results over the wires.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelResults {
    /// The estimator's model.
    pub model: ModelKind,
    /// One entry per wire.
    pub wires: Vec<WireResults>,
}

/// A wire's results: its truth and one row per sample count.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WireResults {
    /// The wire's true parameters.
    pub wire: WireOut,
    /// One row per sample count, ascending.
    pub by_samples: Vec<BySamples>,
    /// The trials sampled until the `--until` target (absent without it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub until: Option<super::until::UntilSummary>,
}

/// `summary.json`'s body (after the run header). Every value is the same for the same seed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IdentifySummary {
    /// The estimators' model; `wire`, `by_samples` and `wires` are its results.
    pub model: ModelKind,
    /// The residual form.
    pub form: Form,
    /// Gravity in the simulated world.
    pub gravity: Gravity,
    /// The sensor: a preset's name or the sensor file as given.
    pub sensor: String,
    /// How `ã` was computed from the tared reading.
    pub pipeline: Pipeline,
    /// The calibration file's path, `"cached"` when one was run, `None` for the mounting
    /// pipeline.
    pub calibration: Option<String>,
    /// Trials per wire.
    pub trials: usize,
    /// The noise model the fits weight the samples by and their intervals count.
    pub noise: NoiseOut,
    /// The sample counts identified from, ascending.
    pub sample_counts: Vec<usize>,
    /// The first wire (its entry of `wires`).
    pub wire: WireOut,
    /// The first wire's rows (its entry of `wires`).
    pub by_samples: Vec<BySamples>,
    /// The first wire's `--until` results (its entry of `wires`; absent without `--until`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub until: Option<super::until::UntilSummary>,
    /// Every wire's results with the estimators' model.
    pub wires: Vec<WireResults>,
    /// Every model run on the same data (with gravity on, both), `model` first.
    pub by_model: Vec<ModelResults>,
}

/// The noise model of a run's fits, as `summary.json` reports it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NoiseOut {
    /// The pose noise of `b̃` per axis: rotation \[degrees\].
    pub pose_noise_deg: f64,
    /// The pose noise of `b̃` per axis: position \[mm\].
    pub pose_noise_mm: f64,
    /// The relative error of each force channel of `ã` every sample shares \[%\] (0: none),
    /// and of each torque channel unless [`Self::torque_gain_error_percent`] differs.
    pub gain_error_percent: f64,
    /// The relative error of each torque channel of `ã` every sample shares \[%\].
    pub torque_gain_error_percent: f64,
    /// Whether the tare's offset and the drift since are modelled and estimated.
    pub bias_model: bool,
    /// The wire model's own relative error in each parameter, added to every interval \[%\]
    /// ([`ftwire_estimate::identify::IdentifierParams::model_error`]).
    pub model_floor_percent: f64,
}

impl NoiseOut {
    /// The report of `config`'s noise model and model error.
    pub fn new(config: &ftwire_estimate::identify::IdentifierParams) -> Self {
        let noise = &config.noise;
        Self {
            pose_noise_deg: noise.rotation.to_degrees(),
            pose_noise_mm: 1e3 * noise.translation,
            gain_error_percent: 1e2 * noise.gain,
            torque_gain_error_percent: 1e2 * noise.gains()[0],
            bias_model: noise.bias.is_some(),
            model_floor_percent: 1e2 * config.model_error,
        }
    }
}

/// `timings.json`: the wall-clock times, kept out of the summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IdentifyTimings {
    /// The calibration run \[s\] (0 when loaded or not needed).
    pub calibration_s: f64,
    /// Every identification.
    pub identifications: Vec<Timing>,
    /// The median over the trials of each model, wire and sample count (Fig. 4).
    pub compute_ms_median: Vec<MedianTiming>,
}

impl IdentifyTimings {
    /// The median identification time \[ms\] of `model` on `wire` from `samples` samples
    /// (NaN when there is none).
    pub fn median_ms(&self, model: ModelKind, wire: &str, samples: usize) -> f64 {
        self.compute_ms_median
            .iter()
            .find(|m| m.model == model && m.wire == wire && m.samples == samples)
            .map_or(f64::NAN, |m| m.compute_ms_median)
    }
}

/// The median identification time of a model, wire and sample count.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MedianTiming {
    /// The estimator's model.
    pub model: ModelKind,
    /// The wire's name.
    pub wire: String,
    /// The sample count.
    pub samples: usize,
    /// The median over the trials \[ms\].
    pub compute_ms_median: f64,
}

/// One identification's time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Timing {
    /// The estimator's model.
    pub model: ModelKind,
    /// The wire's name.
    pub wire: String,
    /// The trial.
    pub trial: usize,
    /// The sample count.
    pub samples: usize,
    /// Wall time \[ms\].
    pub compute_ms: f64,
}

/// The mean of `|e[j] − truth| / truth` over `estimates` (NaN for none).
fn mean_abs_relative(estimates: &[[f64; 4]], j: usize, truth: f64) -> f64 {
    estimates
        .iter()
        .map(|e| (e[j] - truth).abs() / truth)
        .sum::<f64>()
        / estimates.len() as f64
}

/// One `by_samples` row from the rows of a wire and a sample count.
pub(super) fn aggregate<'a>(
    wire: &WireSpec,
    rows: impl Iterator<Item = &'a Row>,
    n: usize,
) -> BySamples {
    let rows: Vec<&Row> = rows.collect();
    let truth = truth(wire);
    let estimates: Vec<[f64; 4]> = rows.iter().filter_map(|r| r.eta).collect();
    let count = estimates.len() as f64;
    let mut mean = [f64::NAN; 4];
    let mut std = [f64::NAN; 4];
    let mut relative_error = [f64::NAN; 4];
    let mut mean_abs_relative_error = [f64::NAN; 4];
    let trusted: Vec<[f64; 4]> = rows
        .iter()
        .filter(|r| r.flag.is_none())
        .filter_map(|r| r.eta)
        .collect();
    let mean_abs_relative_error_identified =
        std::array::from_fn(|j| mean_abs_relative(&trusted, j, truth[j]));
    if !estimates.is_empty() {
        for j in 0..4 {
            let m = estimates.iter().map(|e| e[j]).sum::<f64>() / count;
            let var = if estimates.len() > 1 {
                estimates.iter().map(|e| (e[j] - m).powi(2)).sum::<f64>() / (count - 1.0)
            } else {
                0.0
            };
            mean[j] = m;
            std[j] = var.sqrt();
            relative_error[j] = (m - truth[j]).abs() / truth[j];
            mean_abs_relative_error[j] = mean_abs_relative(&estimates, j, truth[j]);
        }
    }
    let densities: Vec<f64> = rows.iter().filter_map(|r| r.linear_density).collect();
    let linear_density = (!densities.is_empty()).then(|| {
        let count = densities.len() as f64;
        let mean = densities.iter().sum::<f64>() / count;
        let truth = self::linear_density(wire);
        let var =
            densities.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (count - 1.0).max(1.0);
        DensityStats {
            mean,
            std: var.sqrt(),
            mean_abs_relative_error: densities
                .iter()
                .map(|d| (d - truth).abs() / truth)
                .sum::<f64>()
                / count,
        }
    });
    let coverage95 = std::array::from_fn(|j| {
        let inside = rows
            .iter()
            .filter(|r| {
                r.interval95
                    .is_some_and(|i| i[j][0] <= truth[j] && truth[j] <= i[j][1])
            })
            .count();
        inside as f64 / rows.len() as f64
    });
    BySamples {
        linear_density,
        coverage95,
        samples: n,
        estimated: estimates.len(),
        identified: rows.iter().filter(|r| r.flag.is_none()).count(),
        mean,
        std,
        relative_error,
        mean_abs_relative_error,
        mean_abs_relative_error_identified,
        evaluations_median: median(
            &rows
                .iter()
                .map(|r| r.evaluations as f64)
                .collect::<Vec<_>>(),
        ),
    }
}

/// `model`'s results over `wires` from the rows, one `by_samples` row per count.
pub(super) fn model_results(
    model: ModelKind,
    wires: &[WireSpec],
    counts: &[usize],
    rows: &[Row],
) -> ModelResults {
    ModelResults {
        model,
        wires: wires
            .iter()
            .enumerate()
            .map(|(w, wire)| WireResults {
                wire: WireOut::of(wire),
                by_samples: counts
                    .iter()
                    .map(|&n| {
                        aggregate(
                            wire,
                            rows.iter()
                                .filter(|r| r.model == model && r.wire == w && r.samples == n),
                            n,
                        )
                    })
                    .collect(),
                until: None,
            })
            .collect(),
    }
}

/// The median wall time \[ms\] of `model`'s identifications of wire `wire` (its index) from
/// `samples` samples, over the trials (NaN for none).
pub(super) fn compute_ms_median(
    rows: &[Row],
    model: ModelKind,
    wire: usize,
    samples: usize,
) -> f64 {
    let times: Vec<f64> = rows
        .iter()
        .filter(|r| r.model == model && r.wire == wire && r.samples == samples)
        .map(|r| r.compute_ms)
        .collect();
    median(&times)
}

/// The timings of the rows: every identification, and the medians of each model (in `models`'
/// order), wire and count.
pub(super) fn timings(
    calibration_s: f64,
    models: &[ModelKind],
    (wires, counts): (&[WireSpec], &[usize]),
    rows: &[Row],
) -> IdentifyTimings {
    let mut medians = Vec::new();
    for &model in models {
        for (w, wire) in wires.iter().enumerate() {
            for &samples in counts {
                medians.push(MedianTiming {
                    model,
                    wire: wire.name.clone(),
                    samples,
                    compute_ms_median: compute_ms_median(rows, model, w, samples),
                });
            }
        }
    }
    IdentifyTimings {
        calibration_s,
        compute_ms_median: medians,
        identifications: rows
            .iter()
            .map(|r| Timing {
                model: r.model,
                wire: wires
                    .get(r.wire)
                    .map_or_else(String::new, |w| w.name.clone()),
                trial: r.trial,
                samples: r.samples,
                compute_ms: r.compute_ms,
            })
            .collect(),
    }
}

/// `identify.csv`: one row per model, wire, trial and sample count, with the 95 % interval of
/// each of `(c1, c2, c3, L)` (empty without a covariance).
pub(super) fn csv(wires: &[WireSpec], rows: &[Row]) -> Result<Vec<u8>, LabError> {
    let mut table = CsvTable::new(
        "identify.csv",
        &[
            "wire",
            "trial",
            "samples",
            "c1",
            "c2",
            "c3",
            "L",
            "rel_err_c1",
            "rel_err_c2",
            "rel_err_c3",
            "rel_err_L",
            "chi2_per_dof",
            "evaluations",
            "identified",
            "flag",
            "model",
            "linear_density",
            "low95_c1",
            "high95_c1",
            "low95_c2",
            "high95_c2",
            "low95_c3",
            "high95_c3",
            "low95_L",
            "high95_L",
        ],
    )?;
    for row in rows {
        let Some(wire) = wires.get(row.wire) else {
            continue;
        };
        let truth = truth(wire);
        let eta = row.eta.unwrap_or([f64::NAN; 4]);
        let mut cells = vec![text(&wire.name), value(row.trial), value(row.samples)];
        cells.extend(eta.iter().map(|&v| value(v)));
        cells.extend(
            eta.iter()
                .zip(truth)
                .map(|(v, true_value)| value((v - true_value) / true_value)),
        );
        cells.extend([
            value(row.chi2_per_dof),
            value(row.evaluations),
            value(row.flag.is_none()),
            text(row.flag.unwrap_or("")),
            text(row.model.name()),
            row.linear_density.map_or_else(Cell::empty, value),
        ]);
        match row.interval95 {
            Some(intervals) => cells.extend(intervals.iter().flatten().map(|&v| value(v))),
            None => cells.extend((0..8).map(|_| Cell::empty())),
        }
        table.row(cells)?;
    }
    table.into_bytes()
}

/// Figs. 3 and 4 into the results folder: the errors of `results`, and the time of each wire
/// (its index) and sample count from `median_ms`.
pub(super) fn write_figures(
    folder: &ResultsFolder,
    results: &[WireResults],
    median_ms: &dyn Fn(usize, usize) -> f64,
) -> Result<(), LabError> {
    let mut charts = Vec::new();
    let mut time = LineChart::new(
        "identification time against samples (Fig. 4)",
        "samples",
        "compute time, median over trials [ms]",
    );
    for (w, result) in results.iter().enumerate() {
        let mut error = LineChart::new(
            format!(
                "{}: identification error against samples (Fig. 3)",
                result.wire.name
            ),
            "samples",
            "mean |relative error| [%]",
        )
        .with_log_y();
        for (j, parameter) in PARAMETERS.iter().enumerate() {
            let points = result
                .by_samples
                .iter()
                .map(|r| (r.samples as f64, 100.0 * r.mean_abs_relative_error[j]))
                .collect();
            error = error.with_series(Series::line_points(*parameter, points));
        }
        charts.push((
            error,
            format!("error_vs_samples_{}", file_stem(&result.wire.name)),
        ));
        let points = result
            .by_samples
            .iter()
            .map(|r| (r.samples as f64, median_ms(w, r.samples)))
            .collect();
        time = time.with_series(Series::line_points(result.wire.name.clone(), points));
    }
    charts.push((time, crate::report::TIMING_FIGURES[0].to_owned()));
    for (chart, stem) in &charts {
        match chart.write(folder.dir(), stem) {
            // A figure without a drawable point (every estimate failed) is left out.
            Ok(_) | Err(ftwire_report::ReportError::Empty { .. }) => {}
            Err(e) => return Err(LabError::no_answer(format!("drawing {stem}: {e}"))),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_are_of_the_mean_and_of_each_trial() {
        let wire = WireSpec::preset("nitinol-2mm-630").expect("a preset");
        let t = truth(&wire);
        let row = |trial, scale: f64| Row {
            model: ModelKind::Weightless,
            linear_density: None,
            wire: 0,
            trial,
            samples: 3,
            eta: Some(t.map(|v| v * scale)),
            chi2_per_dof: 1.0,
            interval95: None,
            flag: None,
            evaluations: 10,
            compute_ms: trial as f64,
        };
        // +1 % and −1 %: the mean is exact, each trial is 1 % off.
        let rows = [row(0, 1.01), row(1, 0.99), row(2, 1.0)];
        let out = aggregate(&wire, rows.iter(), 3);
        for (j, true_value) in t.iter().enumerate() {
            assert!(out.relative_error[j] < 1e-12);
            assert!((out.mean_abs_relative_error[j] - 0.02 / 3.0).abs() < 1e-12);
            assert!((out.std[j] - 0.01 * true_value).abs() < 1e-12);
        }
        assert_eq!(out.identified, 3);
        let mut flagged = rows.to_vec();
        flagged[0].flag = Some("residual_above_noise");
        let out = aggregate(&wire, flagged.iter(), 3);
        assert_eq!(out.identified, 2);
        assert!((out.mean_abs_relative_error_identified[3] - 0.005).abs() < 1e-12);
        assert!((out.mean_abs_relative_error[3] - 0.02 / 3.0).abs() < 1e-12);
        assert!((compute_ms_median(&rows, ModelKind::Weightless, 0, 3) - 1.0).abs() < 1e-12);
        assert!(compute_ms_median(&rows, ModelKind::Loaded, 0, 3).is_nan());
        let timings = timings(0.0, &[ModelKind::Weightless], (&[wire], &[3]), &rows);
        assert!(
            (timings.median_ms(ModelKind::Weightless, "nitinol-2mm-630", 3) - 1.0).abs() < 1e-12
        );
        assert!(
            timings
                .median_ms(ModelKind::Loaded, "nitinol-2mm-630", 3)
                .is_nan()
        );
    }
}
