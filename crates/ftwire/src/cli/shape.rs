//! Arguments of `ftwire shape --log`: shape estimation from a recorded rig log.

use std::path::PathBuf;

use clap::Args;
use ftwire::args::JsonArgs;
use serde::Serialize;

/// `ftwire shape --log FILE.jsonl --wire W [--calibration FILE] [--json]`.
#[derive(Debug, Clone, Args, Serialize)]
#[command(after_help = "Example:\n  \
    ftwire shape --log results/shape/logs/nitinol-2mm-630.jsonl --wire nitinol-2mm-630 \\\n    \
    --calibration results/shape/calibration.json --json")]
pub struct ShapeArgs {
    /// The JSON Lines log (format: `ftwire_estimate::log`); each record has `a` (calibrated)
    /// or `raw` (tared, force first, sensor frame; needs --calibration).
    #[arg(long, value_name = "FILE.jsonl")]
    pub log: PathBuf,
    /// The wire the shapes are solved for: a preset or a wire file (TOML), e.g. with the
    /// identified c and L.
    #[arg(long, value_name = "PRESET|FILE.toml")]
    pub wire: String,
    /// The learnt calibration (`--calibration`).
    #[command(flatten)]
    #[serde(flatten)]
    pub calibration: crate::cli::groups::CalibrationArgs,
    /// Output: one JSON object per record (JSON Lines) with --json.
    #[command(flatten)]
    pub output: JsonArgs,
}
