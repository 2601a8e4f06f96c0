//! Arguments of `ftwire shape --log`: shape estimation from a recorded rig log.

use std::path::PathBuf;

use clap::Args;
use ftwire::args::{Count, CountRange, JsonArgs, ResultsArgs, Vec6, parse_numbers};
use ftwire_lab::log::shape::{DEFAULT_POINTS, MAX_POINTS, MIN_POINTS};
use serde::Serialize;

use crate::cli::groups::{CalibrationArgs, GravityInClampArgs, MountingArgs};

/// `ftwire shape --log FILE.jsonl --wire W [--calibration FILE] [--mounting FILE.toml]
/// [--gravity-in-clamp X,Y,Z] [--a-std T1,T2,T3,F1,F2,F3] [--points N] [--out DIR] [--json]`.
#[derive(Debug, Clone, Args, Serialize)]
#[command(
    after_help = "Examples (a simulated recording as a rig writes it, its calibration, its \
    shapes):\n  \
    ftwire experiment calibrate --gravity off --trials 150 --save-log --out rec\n  \
    ftwire calibrate --log rec/logs/recording.jsonl --wire nitinol-3mm-820 --out cal\n  \
    ftwire shape --log rec/logs/recording.jsonl --wire nitinol-3mm-820 \\\n    \
    --calibration cal/calibration.json --out shapes --points 50\n\n\
    Each record is one shape record: line, time, a, points [m], stable, confident, \
    confidence, with error bars sigma [m], with inner markers marker_mean_mm. Without --out \
    each is printed (text, or JSON Lines with --json); with --out DIR they go to \
    DIR/shapes.jsonl with summary.json and the report.\n\n\
    Error bars: with --a-std, --sensor, or a --calibration whose file has its test error (for \
    the raw records read through it), each shape also gets sigma, the RMS radius of each \
    point's first-order error [m], and summary.json sigma_mean_mm.\n\n\
    Exit codes: 0 every record shaped, 1 the model has no shape for some record (its `error` \
    says why; the others are written), 2 bad input (a bad log line, a raw record with neither \
    --calibration nor --mounting, a tool without the record's gravity)."
)]
pub struct ShapeArgs {
    /// The JSON Lines log (format: `ftwire_estimate::log`); each record has `a` (calibrated)
    /// or `raw` (force first, sensor frame; needs --calibration or --mounting). `b` is not
    /// needed.
    #[arg(long, value_name = "FILE.jsonl")]
    pub log: PathBuf,
    /// The wire the shapes are solved for: a preset or a wire file (TOML), e.g. with the
    /// identified c and L.
    #[arg(long, value_name = "PRESET|FILE.toml")]
    pub wire: String,
    /// The learnt calibration (`--calibration`).
    #[command(flatten)]
    #[serde(flatten)]
    pub calibration: CalibrationArgs,
    /// The sensor's mounting (`--mounting`).
    #[command(flatten)]
    #[serde(flatten)]
    pub mounting: MountingArgs,
    /// The loaded model (`--gravity-in-clamp`).
    #[command(flatten)]
    #[serde(flatten)]
    pub gravity: GravityInClampArgs,
    /// Standard deviations of every record's ã, torque first [N·m ×3, N ×3], each >= 0: the
    /// whole error of ã (sensor noise and calibration error). Each shape then carries σ(s) at
    /// each point, sqrt(trace D Σ D^T) with D = ∂p(s)/∂a and Σ = diag(std²): the RMS radius of
    /// the point's first-order error [mm] (`sigma_mm`; 12 more shape solves per record)
    /// [default: from --sensor; otherwise the calibration file's per-channel test RMSE for the
    /// raw records read through it; otherwise no error bars].
    #[arg(long, value_name = "T1,T2,T3,F1,F2,F3", value_parser = parse_numbers::<6>, allow_hyphen_values = true)]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub a_std: Option<Vec6>,
    /// The model's own error e per metre of arc length [m/m], 0 to 1: each σ(s) adds
    /// σ_model(s) = e·s in quadrature, zero at the base clamp (e: the model's RMS distance from
    /// the wire per metre, e.g. measured with markers where ã is known) [default: not counted].
    #[arg(long, value_name = "E", value_parser = ftwire::args::parse_finite)]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_error: Option<f64>,
    /// The F/T sensor's data sheet, for every record's error bars in place of the
    /// calibration's test error (which carries its labels' own error): the record's white
    /// noise (`noise_std` over --rest-samples readings), the tare's (over --tare-samples) and
    /// the drift since the tare at the record's time (`bias_random_walk`,
    /// `bias_time_constant`), force first in the sensor frame, mapped to ã by --mounting (or
    /// the file's clamp keys). A preset (`distorted`, `undistorted`, `real-like`) or a sensor
    /// file (TOML, `docs/config.md`). --a-std, when given, is used instead.
    #[arg(long, value_name = "PRESET|FILE.toml")]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensor: Option<String>,
    /// F/T readings averaged into each record (with --sensor), 1 to 1000000.
    #[arg(long, value_name = "N", default_value_t = ftwire_lab::identify::REST_SAMPLES, value_parser = Count(ftwire_lab::log::identify::LOG_SAMPLES), requires = "sensor")]
    pub rest_samples: usize,
    /// F/T readings averaged by the tare (with --sensor), 1 to 1000000.
    #[arg(long, value_name = "N", default_value_t = ftwire_lab::experiment::rig::TARE_SAMPLES, value_parser = Count(ftwire_lab::log::identify::LOG_SAMPLES), requires = "sensor")]
    pub tare_samples: usize,
    /// When the sensor was tared, on the log's clock [s] (with --sensor) [default: the first
    /// record's time].
    #[arg(long, value_name = "T", value_parser = ftwire::args::parse_finite, allow_hyphen_values = true, requires = "sensor")]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tare_time: Option<f64>,
    /// The calibration's accuracy (with --sensor): a relative error of each channel of ã that
    /// every record shares [% of the value, standard deviation] [default: 0].
    #[arg(long, value_name = "PCT", value_parser = ftwire::args::parse_finite, allow_hyphen_values = true, requires = "sensor")]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gain_error: Option<f64>,
    /// Points of each shape, evenly spaced in arc length from the base clamp to the tip, 2 to
    /// 10000, printed or written alike.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_POINTS, value_parser = Count(CountRange::new(MIN_POINTS, MAX_POINTS)))]
    pub points: usize,
    /// Results folder (`--out`, `--force`): write shapes.jsonl, summary.json and the report
    /// there instead of printing each record [no default: without --out nothing is written].
    #[command(flatten)]
    pub results: ResultsArgs,
    /// Output: one JSON object per record (JSON Lines) with --json; with --out, the summary
    /// as one JSON object.
    #[command(flatten)]
    pub output: JsonArgs,
}
