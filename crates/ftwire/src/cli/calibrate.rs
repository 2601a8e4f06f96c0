//! Arguments of `ftwire calibrate --log`: the F/T calibration learnt from a rig's recording.

use std::path::PathBuf;

use clap::Args;
use ftwire::args::{CountRange, ResultsArgs, SeedArgs, parse_finite};
use serde::Serialize;

use crate::cli::groups::MountingArgs;

/// `ftwire calibrate --log FILE.jsonl --wire W [--mounting FILE.toml] [--out DIR]`.
#[derive(Debug, Clone, Args, Serialize)]
#[command(
    after_help = "Example (a simulated recording, then its calibration):\n  \
    ftwire experiment calibrate --gravity off --trials 600 --save-log --out rec\n  \
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
          value_parser = CountRange::new(0, 256))]
    pub hidden: Vec<usize>,
    /// Most passes over the training block.
    #[arg(long, value_name = "N", default_value_t = 2000, value_parser = CountRange::new(1, 1_000_000))]
    pub epochs: usize,
    /// Stop after this many epochs without a better validation loss.
    #[arg(long, value_name = "N", default_value_t = 200, value_parser = CountRange::new(1, 1_000_000))]
    pub patience: usize,
    /// Do not offer the map a drift term. By default an offset linear in time (a sensor's
    /// creep), fitted on the training block, is kept when it predicts the validation block
    /// better than none; the log commands then apply it at each record's time.
    #[arg(long)]
    pub no_drift: bool,
    /// Seed of the fits and of the network's initial weights.
    #[command(flatten)]
    pub seed: SeedArgs,
    /// Results folder (`--out`, `--force`) [default: results/calibrate-log].
    #[command(flatten)]
    pub results: ResultsArgs,
}
