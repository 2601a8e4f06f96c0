//! Arguments of `ftwire identify --log FILE.jsonl`, and the identification settings that it
//! shares with `ftwire experiment identify`.
#![allow(rustdoc::broken_intra_doc_links)]

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use ftwire::args::{Count, JsonArgs, SeedArgs, parse_finite};
use ftwire_lab::identify::{Form, ResidualParams};
use ftwire_lab::log::identify::LOG_SAMPLES;
use serde::Serialize;

/// The residual identification minimises (`--form`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FormArg {
    /// The exact absolute form `log(Γ_η(ã_i)⁻¹ b̃_i)`: reaches the noise floor.
    Absolute,
    /// The paper's eq. 12, `J_η(ã_i) δã_i − δb̃_i`: its linearisation limits its accuracy
    /// even without noise.
    Eq12,
    /// Eq. 12 with `J` at the midpoint of each step.
    Midpoint,
    /// Exact relative poses of consecutive samples.
    Relative,
}

impl FormArg {
    /// The lab's residual form.
    pub fn form(self) -> Form {
        match self {
            Self::Absolute => Form::Absolute,
            Self::Eq12 => Form::Eq12,
            Self::Midpoint => Form::Midpoint,
            Self::Relative => Form::Relative,
        }
    }
}

/// How to identify: the residual form and the known relations between the parameters. Shared
/// by `ftwire identify` and `ftwire experiment identify`, so both read the same flags the same
/// way.
#[derive(Debug, Clone, Copy, Args, Serialize)]
pub struct IdentifySettingsArgs {
    /// The residual minimised.
    #[arg(long, value_enum, default_value_t = FormArg::Absolute)]
    pub form: FormArg,
    /// Isotropic bending, c3 = c2 (a wire of round cross-section).
    #[arg(long)]
    pub isotropic: bool,
    /// A known torsion ratio NU = c1/c2 (a round rod: 1/(1 + Poisson's ratio)).
    #[arg(
        long,
        value_name = "NU",
        allow_hyphen_values = true,
        value_parser = parse_finite
    )]
    pub torsion_ratio: Option<f64>,
    /// The robot's repeatability at the rests: the standard deviation of the gripper pose
    /// b̃'s rotation about each axis [degrees], as the fit weights the pose equation and as
    /// the covariance and 95 % intervals count it [default: 0.05].
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_finite)]
    pub pose_noise_deg: Option<f64>,
    /// The same for b̃'s position along each axis [mm] [default: 0.1].
    #[arg(long, value_name = "MM", allow_hyphen_values = true, value_parser = parse_finite)]
    pub pose_noise_mm: Option<f64>,
    /// The relative error of each channel of ã that every sample shares, the F/T calibration's
    /// accuracy [% of the value, standard deviation]: unlike the noise it does not average
    /// away over samples, so it bounds how narrow the intervals get; the fit estimates it with
    /// the wire [default: 0; `experiment identify`: its map's, see its --no-bias-model].
    #[arg(long, value_name = "PCT", allow_hyphen_values = true, value_parser = parse_finite)]
    pub gain_error: Option<f64>,
    /// The wire model's own error against the wire [% of each of c1, c2, c3, L (and the
    /// density), standard deviation]: what the model leaves out biases the estimate whatever
    /// the number of samples, so it is added in quadrature to each parameter's standard
    /// deviation and interval; it moves no estimate [default: 0; `experiment identify`: 0.01,
    /// the model's error against the simulated rod].
    #[arg(long, value_name = "PCT", allow_hyphen_values = true, value_parser = parse_finite)]
    pub model_floor: Option<f64>,
}

impl IdentifySettingsArgs {
    /// The lab's settings of these flags.
    pub fn settings(&self) -> ResidualParams {
        let pose_noise = ResidualParams::pose_noise_of(
            self.pose_noise_deg.map(f64::to_radians),
            self.pose_noise_mm.map(|mm| 1e-3 * mm),
        );
        ResidualParams {
            form: self.form.form(),
            isotropic: self.isotropic,
            torsion_ratio: self.torsion_ratio,
            pose_noise,
            gain_error: self.gain_error.map(|pct| 1e-2 * pct),
            model_floor: self.model_floor.map(|pct| 1e-2 * pct),
        }
    }
}

/// `ftwire identify --log FILE.jsonl`: identify `η = (c1, c2, c3, L)` from a recorded log.
#[derive(Debug, Args)]
#[command(after_help = "Examples:\n  \
    ftwire experiment identify --wire nitinol-2mm-630 --gravity off --trials 1 --save-log --out run\n  \
    ftwire identify --log run/logs/nitinol-2mm-630-trial0.jsonl --samples 3 --json\n\n\
    (With gravity on, give identify --log the gravity in the clamp frame: --gravity-in-clamp.)\n\n\
    Exit codes: 0 identified, 1 the data do not identify the wire (the estimate is printed \
    with the reason), 2 bad input (a bad log line, an empty log, too few samples or too \
    little motion).")]
pub struct IdentifyArgs {
    /// The JSON Lines log (format: `ftwire_estimate::log`): time, `a` (tared, calibrated,
    /// torque first, base clamp frame) or `raw` (force first, sensor frame; needs
    /// --calibration or --mounting), and `b` the second gripper's pose relative to the base
    /// clamp, on every record.
    #[arg(long, value_name = "FILE.jsonl")]
    pub log: PathBuf,
    /// The learnt calibration (`--calibration`).
    #[command(flatten)]
    pub calibration: crate::cli::groups::CalibrationArgs,
    /// The sensor's mounting (`--mounting`).
    #[command(flatten)]
    pub mounting: crate::cli::groups::MountingArgs,
    /// Use only the first N records, 1 to 1000000 (default: all). With independent record
    /// errors the identification's time grows in proportion to the records it uses; with
    /// `--sensor` (a bias or gain every record shares) every pair of records is correlated,
    /// memory grows as N² and time as N³, and more than 500 records are refused before any
    /// work; a window of the first few hundred of a long log gives an estimate in seconds (on
    /// a terminal, progress is shown on stderr).
    #[arg(long, value_name = "N", value_parser = Count(LOG_SAMPLES))]
    pub samples: Option<usize>,
    /// Gravity in the base clamp frame [m/s²]: identify with the loaded model, the wire's
    /// linear density (its weight) as well as `c` and `L` (default: the paper's weightless
    /// model).
    #[arg(
        long = "gravity-in-clamp",
        visible_alias = "gravity",
        value_name = "GX,GY,GZ",
        allow_hyphen_values = true,
        value_parser = ftwire::args::parse_numbers::<3>
    )]
    pub gravity: Option<ftwire::args::Vec3>,
    /// The residual form and the known relations between the parameters.
    #[command(flatten)]
    pub settings: IdentifySettingsArgs,
    /// The sensor's shared bias (`--sensor`, `--rest-samples`, `--tare-samples`,
    /// `--tare-time`).
    #[command(flatten)]
    pub drift: LogDriftArgs,
    /// The seed of the particle swarm.
    #[command(flatten)]
    pub seed: SeedArgs,
    /// Output format.
    #[command(flatten)]
    pub output: JsonArgs,
}

/// The sensor's data sheet for the bias every record shares.
#[derive(Debug, Clone, Args, Serialize)]
pub struct LogDriftArgs {
    /// The F/T sensor's data sheet, to model the bias all records share and estimate it with
    /// the wire: the tare's offset (its white noise `noise_std` over --tare-samples readings)
    /// and the drift since (`bias_random_walk` [N/√s, N·m/√s], `bias_time_constant` [s]), force
    /// first in the sensor frame, mapped to ã by --mounting (or the file's clamp keys). A preset
    /// (`distorted`, `undistorted`, `real-like`: the simulated sensors) or a sensor file (TOML,
    /// `docs/config.md`) [default: none; the records' errors are treated as independent].
    /// Record times are read from each record's `time`.
    #[arg(long, value_name = "PRESET|FILE.toml")]
    pub sensor: Option<String>,
    /// F/T readings averaged into each record, for its own noise (with --sensor), 1 to 1000000.
    #[arg(long, value_name = "N", default_value_t = ftwire_lab::identify::REST_SAMPLES, value_parser = Count(LOG_SAMPLES), requires = "sensor")]
    pub rest_samples: usize,
    /// F/T readings averaged by the tare (with --sensor), 1 to 1000000.
    #[arg(long, value_name = "N", default_value_t = ftwire_lab::experiment::rig::TARE_SAMPLES, value_parser = Count(LOG_SAMPLES), requires = "sensor")]
    pub tare_samples: usize,
    /// When the sensor was tared, on the log's clock [s] (with --sensor): the drift is counted
    /// from it [default: the first record's time].
    #[arg(long, value_name = "T", value_parser = parse_finite, allow_hyphen_values = true, requires = "sensor")]
    pub tare_time: Option<f64>,
}
