//! The roll-out settings that `track` and `passage` share.

use ftwire_lab::error::{FrontEnd, LabError};
use ftwire_lab::tracking::{RolloutOptions, RolloutParams};

use crate::cli::experiment::RolloutArgs;

/// The lab's roll-out settings of `track` and `passage` ([`RolloutOptions::params`]: the
/// tracking policy of `--noise-model` with `--gain`, `--shape-stop`, `--waypoint-moves` and
/// `--near-shape-stop`).
///
/// # Errors
/// Bad input for a bad gain or a negative distance, naming the option.
pub(super) fn rollout_params(args: &RolloutArgs) -> Result<RolloutParams, LabError> {
    RolloutOptions {
        noise: args.closed_loop.noise_model().model(),
        calibration: args.closed_loop.calibration.file.clone(),
        bias_observer: args.closed_loop.bias_observer.on(),
        gain: args.gain,
        shape_stop_mm: args.closed_loop.shape_stop,
        near_shape_stop_mm: args.near_shape_stop,
        waypoint_moves: args.waypoint_moves,
    }
    .params(FrontEnd::Cli)
}
