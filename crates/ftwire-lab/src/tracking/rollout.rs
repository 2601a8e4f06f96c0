//! The settings of the experiments that roll a plan out in the simulator (`track`,
//! `passage`): the execution noise, the learnt calibration, how the closed loop tracks, and
//! whether it corrects the sensor's bias drift.

use std::path::PathBuf;

use ftwire_control::{NoiseModel, TrackingPolicy};
use serde::Serialize;

use crate::error::LabError;

/// The roll-out settings of [`crate::track`] and [`crate::passage`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RolloutParams {
    /// The second gripper's execution noise (default `increment`, the paper's).
    pub noise: NoiseModel,
    /// Learnt calibration weights (`ftwire_estimate::calibration` JSON); `None`: a
    /// calibration is first run on the known wire and cached in the results folder.
    pub calibration: Option<PathBuf>,
    /// How the closed loop executes the path: the gain, the shape stops, each leg's move
    /// budget, the recoveries and the success rule (default `TrackingPolicy::for_noise` of
    /// `noise`).
    pub policy: TrackingPolicy,
    /// Whether the closed loop steers by `ã` corrected for the sensor's bias drift
    /// (`ftwire_control::BiasObserver`; see [`crate::experiment::rig::bias_observer`]).
    pub bias_observer: bool,
}

impl Default for RolloutParams {
    fn default() -> Self {
        Self::for_noise(NoiseModel::Increment)
    }
}

impl RolloutParams {
    /// The defaults under `noise`: no calibration file, the noise's tracking policy, the bias
    /// observer on.
    pub fn for_noise(noise: NoiseModel) -> Self {
        Self {
            noise,
            calibration: None,
            policy: TrackingPolicy::for_noise(noise),
            bias_observer: true,
        }
    }

    /// Checks the policy's settings a user may change: the gain in `(0, 1]`, the shape stops
    /// finite and `≥ 0` \[m\], at least one move per leg.
    ///
    /// # Errors
    /// Bad input naming the setting and what is allowed.
    pub fn check(&self) -> Result<(), LabError> {
        let policy = &self.policy;
        if !(policy.gain > 0.0 && policy.gain <= 1.0) {
            return Err(LabError::bad_input(format!(
                "gain {}: give a gain K in (0, 1]",
                policy.gain
            )));
        }
        for (name, stop) in [
            ("shape stop", policy.shape_stop),
            ("near shape stop", policy.near_shape_stop),
        ] {
            if !(stop.is_finite() && stop >= 0.0) {
                return Err(LabError::bad_input(format!(
                    "{name} {stop} m: give a distance ≥ 0 (0: off)"
                )));
            }
        }
        if policy.through.max_iterations == 0 {
            return Err(LabError::bad_input(
                "waypoint moves 0: give at least 1 move per leg",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gain_outside_the_unit_interval_or_a_negative_stop_is_refused() {
        assert!(RolloutParams::default().check().is_ok());
        let mut bad = RolloutParams::for_noise(NoiseModel::Offset);
        bad.policy.gain = 1.5;
        assert_eq!(bad.check().map_err(|e| e.exit_code()), Err(2));
        let mut bad = RolloutParams::default();
        bad.policy.near_shape_stop = -0.002;
        assert_eq!(bad.check().map_err(|e| e.exit_code()), Err(2));
        let mut bad = RolloutParams::default();
        bad.policy.through.max_iterations = 0;
        assert_eq!(bad.check().map_err(|e| e.exit_code()), Err(2));
    }
}
