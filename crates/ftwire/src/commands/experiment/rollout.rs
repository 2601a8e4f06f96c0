//! The roll-out settings that `track` and `passage` share.

use ftwire_lab::error::LabError;
use ftwire_lab::tracking::RolloutParams;

use crate::cli::experiment::RolloutArgs;

/// The lab's roll-out settings of `track` and `passage` (the tracking policy of
/// `--noise-model` with `--gain`, `--shape-stop`, `--waypoint-moves` and `--near-shape-stop`).
///
/// # Errors
/// Bad input for a bad gain or a negative distance, naming the option.
pub(super) fn rollout_params(args: &RolloutArgs) -> Result<RolloutParams, LabError> {
    Ok(RolloutParams {
        noise: args.closed_loop.noise_model().model(),
        calibration: args.closed_loop.calibration.file.clone(),
        policy: args.policy()?,
        bias_observer: args.closed_loop.bias_observer.on(),
    })
}
