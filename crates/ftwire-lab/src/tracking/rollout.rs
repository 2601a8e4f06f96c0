//! The settings of the experiments that roll a plan out in the simulator (`track`,
//! `passage`): the execution noise, the learnt calibration, how the closed loop tracks, and
//! whether it corrects the sensor's bias drift; and the same as a user gives them
//! ([`RolloutOptions`]: distances in mm, the policy's overrides), checked.

use std::path::PathBuf;

use ftwire_app::error::FrontEnd;
use ftwire_control::tracking::{PolicyError, PolicySettings};
use ftwire_control::{NoiseModel, TrackingPolicy};
use serde::Serialize;

use crate::error::LabError;
use crate::experiment::limits::WAYPOINT_MOVES;

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

/// The roll-out settings as a user gives them (`--noise-model`, `--calibration`,
/// `--bias-observer`, `--gain`, `--shape-stop`, `--near-shape-stop`, `--waypoint-moves`):
/// distances in mm, each policy setting `None` for the tuned value of the noise's tracking
/// policy ([`TrackingPolicy::with_settings`]).
#[derive(Debug, Clone, PartialEq)]
pub struct RolloutOptions {
    /// The second gripper's execution noise.
    pub noise: NoiseModel,
    /// Learnt calibration weights; `None`: a calibration is run first and cached.
    pub calibration: Option<PathBuf>,
    /// Whether the closed loop corrects the sensor's bias drift.
    pub bias_observer: bool,
    /// The controller's gain `K`, in `(0, 1]`.
    pub gain: Option<f64>,
    /// The shape stop of every leg \[mm\], at least 0 (0: off).
    pub shape_stop_mm: Option<f64>,
    /// The shape stop of a leg from or to a waypoint near an obstacle \[mm\], at least 0.
    pub near_shape_stop_mm: Option<f64>,
    /// Most moves toward each waypoint before the last, in [`WAYPOINT_MOVES`].
    pub waypoint_moves: Option<usize>,
}

impl RolloutOptions {
    /// The roll-out settings, their policy checked; an error names the option as
    /// `front_end` spells it, with the value as the user gave it.
    ///
    /// # Errors
    /// Bad input for a gain outside `(0, 1]`, a negative or non-finite distance, or a move
    /// count outside [`WAYPOINT_MOVES`].
    ///
    /// # Example
    /// ```
    /// use ftwire_lab::error::FrontEnd;
    /// use ftwire_control::NoiseModel;
    /// use ftwire_lab::tracking::RolloutOptions;
    /// let mut options = RolloutOptions::new(NoiseModel::Offset);
    /// options.shape_stop_mm = Some(4.0);
    /// let params = options.params(FrontEnd::Cli).expect("valid");
    /// assert_eq!(params.policy.shape_stop, 4e-3);
    /// options.gain = Some(1.5);
    /// let error = options.params(FrontEnd::Cli).expect_err("gain above 1");
    /// assert_eq!(error.to_string(), "--gain 1.5: give a gain K in (0, 1]");
    /// ```
    pub fn params(&self, front_end: FrontEnd) -> Result<RolloutParams, LabError> {
        let name = |flag: &str| front_end.spell(flag);
        if let Some(moves) = self.waypoint_moves {
            WAYPOINT_MOVES
                .check_value(&name("--waypoint-moves"), moves)
                .map_err(LabError::bad_input)?;
        }
        let settings = PolicySettings {
            gain: self.gain,
            shape_stop: self.shape_stop_mm.map(|mm| 1e-3 * mm),
            near_shape_stop: self.near_shape_stop_mm.map(|mm| 1e-3 * mm),
            waypoint_moves: self.waypoint_moves,
        };
        let policy = TrackingPolicy::with_settings(self.noise, &settings).map_err(|error| {
            // The option as given: a distance in mm, as the user typed it.
            let given = |value: Option<f64>| value.map_or_else(String::new, |v| v.to_string());
            LabError::bad_input(match error {
                PolicyError::Gain(gain) => {
                    format!("{} {gain}: give a gain K in (0, 1]", name("--gain"))
                }
                PolicyError::ShapeStop(_) => format!(
                    "{} {}: give a distance ≥ 0 mm (0: off)",
                    name("--shape-stop"),
                    given(self.shape_stop_mm)
                ),
                PolicyError::NearShapeStop(_) => format!(
                    "{} {}: give a distance ≥ 0 mm (0: off)",
                    name("--near-shape-stop"),
                    given(self.near_shape_stop_mm)
                ),
                PolicyError::WaypointMoves(moves) => format!(
                    "{} {moves}: at least {} and at most {}",
                    name("--waypoint-moves"),
                    WAYPOINT_MOVES.min,
                    WAYPOINT_MOVES.max
                ),
            })
        })?;
        Ok(RolloutParams {
            noise: self.noise,
            calibration: self.calibration.clone(),
            policy,
            bias_observer: self.bias_observer,
        })
    }

    /// The options under `noise` with nothing else given: no calibration file, the bias
    /// observer on, the policy's tuned values.
    pub fn new(noise: NoiseModel) -> Self {
        Self {
            noise,
            calibration: None,
            bias_observer: true,
            gain: None,
            shape_stop_mm: None,
            near_shape_stop_mm: None,
            waypoint_moves: None,
        }
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

    #[test]
    fn the_options_are_named_as_the_front_end_spells_them() {
        let mut options = RolloutOptions::new(NoiseModel::Increment);
        options.near_shape_stop_mm = Some(-2.0);
        let cli = options.params(FrontEnd::Cli).expect_err("negative");
        assert_eq!(
            cli.to_string(),
            "--near-shape-stop -2: give a distance ≥ 0 mm (0: off)"
        );
        let python = options.params(FrontEnd::Python).expect_err("negative");
        assert!(
            python.to_string().starts_with("near_shape_stop -2: "),
            "{python}"
        );
        options.near_shape_stop_mm = None;
        options.waypoint_moves = Some(1001);
        let many = options.params(FrontEnd::Cli).expect_err("too many moves");
        assert_eq!(
            many.to_string(),
            "--waypoint-moves 1001: at least 1 and at most 1000"
        );
    }
}
