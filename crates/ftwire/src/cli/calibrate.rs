//! Arguments of `ftwire calibrate --log`: the F/T calibration learnt from a rig's recording.

use std::path::PathBuf;

use clap::Args;
use ftwire::args::{Count, CountRange, ResultsArgs, SeedArgs, parse_finite};
use ftwire_lab::log::calibrate::MapLoss;
use serde::Serialize;

use crate::cli::groups::MountingArgs;

/// `ftwire calibrate --log FILE.jsonl --wire W [--mounting FILE.toml] [--out DIR]`.
#[derive(Debug, Clone, Args, Serialize)]
#[command(
    after_help = "Example (a simulated recording, then its calibration):\n  \
    ftwire experiment calibrate --gravity off --trials 150 --save-log --out rec\n  \
    ftwire calibrate --log rec/logs/recording.jsonl --wire nitinol-3mm-820 --out cal"
)]
pub struct CalibrateArgs {
    /// The recording (JSON Lines, `ftwire_estimate::log`): records with `raw` (the reading
    /// averaged at rest, force first, sensor frame, not tared) and `markers` (base clamp
    /// frame); `b` optional. Records in time order.
    #[arg(long, value_name = "FILE.jsonl")]
    pub log: PathBuf,
    /// The known wire of the recording: a preset or a wire file (TOML).
    #[arg(long, value_name = "PRESET|FILE.toml")]
    pub wire: String,
    /// The sensor's mounting (`--mounting`).
    #[command(flatten)]
    #[serde(flatten)]
    pub mounting: MountingArgs,
    /// The markers' arc lengths as fractions of the wire's length, in the log's order
    /// (e.g. `0,0.1,...,1`); without it each marker is matched to its closest point of the
    /// wire (the paper's eq. 15).
    #[arg(long, value_name = "F,F,...", value_delimiter = ',', value_parser = parse_finite)]
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub marker_fractions: Vec<f64>,
    /// The loaded model of the labels (`--gravity-in-clamp`).
    #[command(flatten)]
    #[serde(flatten)]
    pub gravity: crate::cli::groups::GravityInClampArgs,
    /// Largest RMS marker residual of a label's fit [mm]; a record fitted worse is rejected
    /// and counted.
    #[arg(long, value_name = "MM", default_value_t = 3.0, value_parser = parse_finite)]
    pub max_label_rms_mm: f64,
    /// Hidden layer widths of the network on what the affine map leaves (comma-separated;
    /// `0` for the affine map alone).
    #[arg(long, value_name = "W,W", value_delimiter = ',', default_value = "16,16",
          value_parser = Count(CountRange::new(0, 256)))]
    pub hidden: Vec<usize>,
    /// Most passes over the training block.
    #[arg(long, value_name = "N", default_value_t = 2000, value_parser = Count(CountRange::new(1, 1_000_000)))]
    pub epochs: usize,
    /// Stop after this many epochs without a better validation loss.
    #[arg(long, value_name = "N", default_value_t = 200, value_parser = Count(CountRange::new(1, 1_000_000)))]
    pub patience: usize,
    /// Do not offer the map a drift term. By default an offset linear in time (a sensor's
    /// creep), fitted on the training block, is kept when it predicts the validation block
    /// better than none; the log commands then apply it at each record's time.
    #[arg(long)]
    pub no_drift: bool,
    /// What the map is fitted on: `shape`, the markers' distance to the model's shape of the
    /// map's `a` (Huber's loss, Gauss–Newton through the model's Jacobian; the labels only
    /// start it; the affine map and polynomial parts of degree 2 and 3 are the candidates,
    /// the one closest on the validation block kept), or `labels`, least squares in `a` (the
    /// affine map and the network, the paper's §IV-A).
    #[arg(long, value_name = "LOSS", default_value = "shape",
          value_parser = ftwire::args::named::<MapLoss>(&MapLoss::NAMES))]
    pub loss: MapLoss,
    /// With `--loss shape`, the labels' weight beside the shape, relative to the shape's
    /// curvature in the affine weights (0: the shape alone). It keeps the wrench directions
    /// a wire's shape barely shows (a taut wire's tension) near the labels.
    #[arg(long, value_name = "W", value_parser = parse_finite,
          default_value_t = ftwire_estimate::calibration::shape_loss::DEFAULT_LABEL_WEIGHT)]
    pub label_weight: f64,
    /// Fit gravity's direction in the clamp frame with the map (the loaded model, |g| from
    /// `--gravity-norm`); `--gravity-in-clamp`, when given, is where it starts. The fitted
    /// gravity is written into calibration.json's model, which `shape --log`, `identify
    /// --log` and ROS 2 then use.
    #[arg(long)]
    pub fit_gravity: bool,
    /// |g| of `--fit-gravity` [m/s²].
    #[arg(long, value_name = "M/S2", value_parser = parse_finite,
          default_value_t = ftwire_lab::log::calibrate::STANDARD_GRAVITY,
          requires = "fit_gravity")]
    pub gravity_norm: f64,
    /// Consecutive records whose markers moved less than this on average [mm] are one rest:
    /// their labels are fitted to the rest's mean markers (0: every record alone).
    #[arg(long, value_name = "MM", value_parser = parse_finite,
          default_value_t = 1e3 * ftwire_lab::log::calibrate::DEFAULT_REST_TOLERANCE)]
    pub rest_tolerance_mm: f64,
    /// Seed of the fits and of the network's initial weights.
    #[command(flatten)]
    pub seed: SeedArgs,
    /// Results folder (`--out`, `--force`) [default: results/calibrate-log].
    #[command(flatten)]
    pub results: ResultsArgs,
}
