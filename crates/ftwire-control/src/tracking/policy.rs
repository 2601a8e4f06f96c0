//! How a planned path is executed: the controller's settings of each kind of leg, the stops,
//! the recoveries and the success rule, for each execution noise ([`NoiseModel`]).
//!
//! Under `increment` and `absolute` every move lands the gripper the full noise away from where
//! it was sent (about 12 mm along the wire), so most of the policy is about what a noisy landing
//! can do; without noise and under `offset` the loop converges onto the plan. The measurements
//! behind each value are in `docs/design/tracking.md`.

use serde::Serialize;

use crate::{ControlParams, NoiseModel, Outcome};

/// Success tolerance on the true final configuration, `‖a_true − a_g‖` \[normalised\], without
/// noise and under `offset`: twice the controller's default stop `ε` (0.05).
pub const SUCCESS_EPSILON: f64 = 0.1;

/// The controller's stop `ε` on the last leg without noise and under `offset` \[normalised\],
/// well inside [`SUCCESS_EPSILON`]: the stop is on the measured `ã`, and over a path's many
/// moves the sensor's bias drifts a few hundredths from its tare.
pub const EPSILON_GOAL: f64 = 0.02;

/// The controller's stop `ε` on the last leg under `increment` and `absolute` \[normalised\]:
/// each noisy move lands the wire a few tenths away from where it was sent, so the stop waits
/// for a move that lands within it.
pub const EPSILON_NOISY: f64 = 0.5;

/// The controller's iteration limit on the last leg under `increment` and `absolute`.
pub const MAX_ITERATIONS_NOISY: usize = 400;

/// The controller's stop `ε` at the waypoints before the last without noise and under
/// `offset` \[normalised\]: the wire passes each waypoint near its planned shape (Table IV
/// scores every waypoint).
pub const EPSILON_THROUGH: f64 = 0.05;

/// Most moves toward a waypoint before the last without noise and under `offset`.
pub const MAX_ITERATIONS_THROUGH: usize = 20;

/// The controller's stop `ε` at the waypoints before the last under `increment` and
/// `absolute` \[normalised\]: looser than a move's own scatter, so that the wire moves on
/// rather than waiting for a lucky landing at every waypoint (the shape stop usually replaces
/// it, [`SHAPE_STOP_NOISY`]).
pub const EPSILON_THROUGH_NOISY: f64 = 0.3;

/// Most moves toward a waypoint before the last under `increment` and `absolute`: enough for
/// the shape stop to find a landing at most waypoints, few enough that a waypoint left unmet
/// now and then does not stall the path.
pub const MAX_ITERATIONS_THROUGH_NOISY: usize = 20;

/// The shape stop \[m\] under `increment` and `absolute` (`ControlParams::shape_tolerance`):
/// a leg ends on a move that landed the model's shape at `ã` within this mean distance of the
/// waypoint's, half the scatter of one landing. It must stay well above the error of that
/// shape estimate (about 1 mm) for the measured shape to pick the true one.
pub const SHAPE_STOP_NOISY: f64 = 0.006;

/// The least shape stop \[m\] of a leg from or to a waypoint near an obstacle under
/// `increment` and `absolute`: every landing beside a box, one the stop rejects too, is a
/// chance to touch it, so a looser stop there means fewer landings beside it.
pub const SHAPE_STOP_NEAR_NOISY: f64 = 0.010;

/// The controller's divergence stop under `increment` and `absolute` \[normalised\]
/// (`ControlParams::divergence`): a leg whose measured `‖a_g − ã‖` stays this far above its
/// start's for two rests in a row is stopped and undone. One throw near a taut wire alone sets
/// `ã` several units away and the next move brings it back; a run away keeps growing.
pub const DIVERGENCE_NOISY: f64 = 20.0;

/// F/T samples averaged at each rest of the last leg (a 0.4 s rest at 1 kHz): the goal's stop
/// and the success are judged there, and the white noise of `ã` falls as `1/√N`.
pub const GOAL_REST_SAMPLES: usize = 400;

/// Most retreats of one attempt: after a detection the second gripper moves back one move and
/// the leg runs again, so a false alarm (the detector's threshold is set on noisy free motion,
/// whose tail crosses it now and then) costs one move instead of the attempt.
pub const MAX_RETREATS: usize = 4;

/// Most undone legs of one attempt: a leg stopped as diverged, on a sensor fault, or (where
/// [`TrackingPolicy::reruns_unreachable`]) at a waypoint out of the arms' reach, goes back to
/// the pose it started from (one the arms held) and runs again.
pub const MAX_UNDOS: usize = 4;

/// The fraction of a leg's move budget after which its shape stop loosens to
/// [`TrackingPolicy::rerun_shape_stop`] (`ControlParams::late_shape_tolerance`): with a
/// finite budget the best threshold rises as the moves left run out, instead of ending the
/// leg on whatever landing came last.
pub const LATE_FRACTION: f64 = 0.75;

/// Lengths \[m\] of the translations of both grippers along each world axis that a
/// relocation tries, shortest first: they leave the wire's configuration and the sensor's
/// gravity direction unchanged.
pub const RELOCATION_STEPS: [f64; 4] = [0.01, 0.02, 0.03, 0.04];

/// How a planned path is executed (plain data; [`TrackingPolicy::for_noise`] gives the
/// tuned policy of each execution noise). The [`crate::PathTracker`] reads every choice here.
///
/// # Example
/// ```
/// use ftwire_control::{NoiseModel, TrackingPolicy};
/// let policy = TrackingPolicy::for_noise(NoiseModel::Increment);
/// assert_eq!(policy.gain, 1.0);
/// // A user's tight shape stop is loosened near a box and on a rerun, never tightened.
/// assert_eq!(policy.near_shape_stop_for(0.004), 0.010);
/// assert_eq!(policy.rerun_shape_stop(0.004), 0.006);
/// assert_eq!(policy.rerun_shape_stop(0.008), 0.008);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrackingPolicy {
    /// The controller's settings on the last leg, to the goal, but for its gain and shape stop
    /// ([`TrackingPolicy::gain`], [`TrackingPolicy::shape_stop`]).
    pub goal: ControlParams,
    /// The controller's settings on the legs before the last, but for the gain and the shape
    /// stops; `max_iterations` is each leg's move budget (`--waypoint-moves`).
    pub through: ControlParams,
    /// The controller's gain `K` on every leg (eq. 13): 1 under `increment` and `absolute`,
    /// where each move's error is independent and the wire's stationary spread about the path,
    /// `1/√(K(2 − K))` times one move's, is least at `K = 1`; 0.5 otherwise.
    pub gain: f64,
    /// The shape stop \[m\] of every leg (`ControlParams::shape_tolerance`; 0: the `ε`
    /// stops): [`SHAPE_STOP_NOISY`] under `increment` and `absolute`, 0 otherwise, where the
    /// loop converges and `ε` is tighter than any shape stop worth waiting for.
    pub shape_stop: f64,
    /// The shape stop \[m\] of a leg from or to a waypoint near an obstacle (the tracker's
    /// `near` flags): [`TrackingPolicy::near_shape_stop_for`] of the default shape stop.
    pub near_shape_stop: f64,
    /// The least shape stop \[m\] near an obstacle when the shape stop is on
    /// ([`SHAPE_STOP_NEAR_NOISY`] under `increment` and `absolute`; 0: no floor).
    pub near_stop_floor: f64,
    /// The least shape stop \[m\] of a leg run again after an undo and of the late part of a
    /// leg's budget, when the shape stop is on (the default stop under `increment` and
    /// `absolute`; 0: no floor). Where a leg was thrown once, every landing is another chance
    /// of a throw, so the rerun takes the default's few landings.
    pub rerun_stop_floor: f64,
    /// [`LATE_FRACTION`]: the part of a leg's budget after which its stop loosens.
    pub late_fraction: f64,
    /// F/T samples averaged per rest on the last leg ([`GOAL_REST_SAMPLES`]).
    pub goal_rest_samples: usize,
    /// Most retreats of one attempt ([`MAX_RETREATS`]).
    pub max_retreats: usize,
    /// Most undone legs of one attempt ([`MAX_UNDOS`]).
    pub max_undos: usize,
    /// Whether a leg that ended at a waypoint out of the arms' reach is undone and run again:
    /// under `increment` and `absolute`, where every move lands with fresh noise, so the
    /// accumulated noise that carried the gripper to the edge of the workspace is not there on
    /// the rerun. Without noise and under `offset` a rerun would meet the same pose again: the
    /// waypoint is passed over, or the goal relocated. Also decides
    /// [`TrackingPolicy::escalates`] and [`TrackingPolicy::undoes_to_last_start`].
    pub reruns_unreachable: bool,
    /// Lengths \[m\] of the relocations tried ([`RELOCATION_STEPS`]).
    pub relocation_steps: [f64; 4],
    /// The success tolerance on the true final configuration \[normalised\]:
    /// [`SUCCESS_EPSILON`] without noise and under `offset`, twice the goal's stop `ε` under
    /// `increment` and `absolute`.
    pub success_epsilon: f64,
    /// Whether success also asks the wire to end within
    /// [`TrackingPolicy::success_epsilon`] of the goal: not under `increment` and `absolute`,
    /// where every move lands the wire beyond any goal tolerance, so success is the paper's
    /// (§IV-E: "failure is declared when the wire collides with an obstacle").
    pub success_needs_goal: bool,
}

/// A user's settings of the tracking policy, over the tuned policy of the execution noise
/// ([`TrackingPolicy::with_settings`]): each `None` keeps the tuned value. Every front end
/// (the binary's `--gain`, `--shape-stop`, `--near-shape-stop`, `--waypoint-moves`) gives
/// its numbers here, so that each is checked against the same range.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PolicySettings {
    /// The controller's gain `K` of every leg ([`TrackingPolicy::gain`]), in `(0, 1]`.
    pub gain: Option<f64>,
    /// The shape stop \[m\] of every leg ([`TrackingPolicy::shape_stop`]), at least 0 (0: the
    /// `ε` stops alone).
    pub shape_stop: Option<f64>,
    /// The shape stop \[m\] of a leg from or to a waypoint near an obstacle
    /// ([`TrackingPolicy::near_shape_stop`]), at least 0 (0: off) [default:
    /// [`TrackingPolicy::near_shape_stop_for`] of the shape stop].
    pub near_shape_stop: Option<f64>,
    /// Most moves toward each waypoint before the last (`through.max_iterations`), at least 1.
    pub waypoint_moves: Option<usize>,
}

/// A setting of [`PolicySettings`] outside its allowed range, with the value given (in the
/// settings' units), so that a front end can name it as it spells it.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum PolicyError {
    /// [`PolicySettings::gain`] is not in `(0, 1]` (or not a number).
    #[error("gain {0}: give a gain K in (0, 1]")]
    Gain(f64),
    /// [`PolicySettings::shape_stop`] is negative (or not a number).
    #[error("shape stop {0} m: give a distance ≥ 0 m (0: off)")]
    ShapeStop(f64),
    /// [`PolicySettings::near_shape_stop`] is negative (or not a number).
    #[error("shape stop near an obstacle {0} m: give a distance ≥ 0 m (0: off)")]
    NearShapeStop(f64),
    /// [`PolicySettings::waypoint_moves`] is 0.
    #[error("waypoint moves {0}: give at least 1")]
    WaypointMoves(usize),
}

/// Whether an attempt succeeded, and whether it ended at the goal ([`TrackingPolicy::judge`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Verdict {
    /// Success by [`TrackingPolicy::success_rule`].
    pub success: bool,
    /// The whole path executed and the true final configuration within
    /// [`TrackingPolicy::success_epsilon`] of the goal.
    pub at_goal: bool,
}

impl TrackingPolicy {
    /// The tuned policy of execution under `noise` (`docs/design/tracking.md`).
    pub fn for_noise(noise: NoiseModel) -> Self {
        let scatters = matches!(noise, NoiseModel::Increment | NoiseModel::Absolute);
        let (goal, through, gain, shape_stop, near_stop_floor) = if scatters {
            let goal = ControlParams {
                epsilon: EPSILON_NOISY,
                max_iterations: MAX_ITERATIONS_NOISY,
                divergence: DIVERGENCE_NOISY,
                ..ControlParams::default()
            };
            let through = ControlParams {
                epsilon: EPSILON_THROUGH_NOISY,
                max_iterations: MAX_ITERATIONS_THROUGH_NOISY,
                divergence: DIVERGENCE_NOISY,
                ..ControlParams::default()
            };
            (goal, through, 1.0, SHAPE_STOP_NOISY, SHAPE_STOP_NEAR_NOISY)
        } else {
            let goal = ControlParams {
                epsilon: EPSILON_GOAL,
                ..ControlParams::default()
            };
            let through = ControlParams {
                epsilon: EPSILON_THROUGH,
                max_iterations: MAX_ITERATIONS_THROUGH,
                ..ControlParams::default()
            };
            (goal, through, 0.5, 0.0, 0.0)
        };
        let mut policy = Self {
            goal,
            through,
            gain,
            shape_stop,
            near_shape_stop: shape_stop,
            near_stop_floor,
            rerun_stop_floor: shape_stop,
            late_fraction: LATE_FRACTION,
            goal_rest_samples: GOAL_REST_SAMPLES,
            max_retreats: MAX_RETREATS,
            max_undos: MAX_UNDOS,
            reruns_unreachable: scatters,
            relocation_steps: RELOCATION_STEPS,
            success_epsilon: if scatters {
                2.0 * goal.epsilon
            } else {
                SUCCESS_EPSILON
            },
            success_needs_goal: !scatters,
        };
        policy.near_shape_stop = policy.near_shape_stop_for(shape_stop);
        policy
    }

    /// The tuned policy of `noise` ([`TrackingPolicy::for_noise`]) with a user's `settings`,
    /// each checked: the shape stop first, then the gain, the near shape stop (by default
    /// [`TrackingPolicy::near_shape_stop_for`] of the shape stop) and the waypoint moves.
    ///
    /// # Errors
    /// [`PolicyError`] naming the first setting outside its range, with its value.
    ///
    /// # Example
    /// ```
    /// use ftwire_control::tracking::{PolicyError, PolicySettings};
    /// use ftwire_control::{NoiseModel, TrackingPolicy};
    /// let settings = PolicySettings {
    ///     shape_stop: Some(0.004),
    ///     ..PolicySettings::default()
    /// };
    /// let policy = TrackingPolicy::with_settings(NoiseModel::Increment, &settings)?;
    /// assert_eq!((policy.shape_stop, policy.near_shape_stop), (0.004, 0.010));
    /// let bad = PolicySettings {
    ///     gain: Some(1.5),
    ///     ..PolicySettings::default()
    /// };
    /// let error = TrackingPolicy::with_settings(NoiseModel::Offset, &bad);
    /// assert_eq!(error, Err(PolicyError::Gain(1.5)));
    /// # Ok::<(), PolicyError>(())
    /// ```
    pub fn with_settings(
        noise: NoiseModel,
        settings: &PolicySettings,
    ) -> Result<Self, PolicyError> {
        let tuned = Self::for_noise(noise);
        let shape_stop = match settings.shape_stop {
            None => tuned.shape_stop,
            Some(stop) if stop >= 0.0 => stop,
            Some(stop) => return Err(PolicyError::ShapeStop(stop)),
        };
        let gain = match settings.gain {
            None => tuned.gain,
            Some(gain) if gain > 0.0 && gain <= 1.0 => gain,
            Some(gain) => return Err(PolicyError::Gain(gain)),
        };
        let near_shape_stop = match settings.near_shape_stop {
            None => tuned.near_shape_stop_for(shape_stop),
            Some(stop) if stop >= 0.0 => stop,
            Some(stop) => return Err(PolicyError::NearShapeStop(stop)),
        };
        let mut policy = Self {
            gain,
            shape_stop,
            near_shape_stop,
            ..tuned
        };
        match settings.waypoint_moves {
            None => {}
            Some(0) => return Err(PolicyError::WaypointMoves(0)),
            Some(moves) => policy.through.max_iterations = moves,
        }
        Ok(policy)
    }

    /// The shape stop \[m\] near an obstacle for a leg shape stop `shape_stop`: no tighter
    /// than [`TrackingPolicy::near_stop_floor`] when the shape stop is on (0, the `ε` stop
    /// alone, stays 0).
    pub fn near_shape_stop_for(&self, shape_stop: f64) -> f64 {
        no_tighter(shape_stop, self.near_stop_floor)
    }

    /// The shape stop \[m\] of a leg run again after an undo, and of the late part of a leg's
    /// budget, for a leg shape stop `shape_stop`: no tighter than
    /// [`TrackingPolicy::rerun_stop_floor`] when the shape stop is on.
    pub fn rerun_shape_stop(&self, shape_stop: f64) -> f64 {
        no_tighter(shape_stop, self.rerun_stop_floor)
    }

    /// The move after which a leg with a budget of `moves` loosens its shape stop
    /// ([`TrackingPolicy::late_fraction`]).
    pub fn late_after(&self, moves: usize) -> usize {
        (self.late_fraction * moves as f64).ceil() as usize
    }

    /// Whether a leg that ended with `outcome` is undone and run again (while undos are
    /// left): diverged or on a sensor fault always; at a waypoint out of the arms' reach where
    /// [`TrackingPolicy::reruns_unreachable`] (before any relocation, which would land with
    /// the noise too).
    pub fn undoes(&self, outcome: &Outcome) -> bool {
        match outcome {
            Outcome::Diverged { .. } | Outcome::SensorFault { .. } => true,
            Outcome::Unreachable { .. } => self.reruns_unreachable,
            _ => false,
        }
    }

    /// Whether a detection on a leg is answered by undoing the leg (back to the pose its first
    /// run started from) instead of a retreat of one move: where each move lands with fresh
    /// noise, when the loop has already retreated on this leg (`retreated_before`). After a
    /// throw the wire lands far off, where the model's linearisation is off and the detector
    /// flags every move; the leg's start was clear.
    pub fn escalates(&self, retreated_before: bool) -> bool {
        retreated_before && self.reruns_unreachable
    }

    /// Whether a leg to `waypoint` whose *start* is out of the arms' reach goes back to the
    /// pose where the last leg run (`ran`) first started and runs that leg again, instead of
    /// ending the attempt: where [`TrackingPolicy::reruns_unreachable`], that leg is the one
    /// before or this one, and `undone` legs leave an undo.
    pub fn undoes_to_last_start(&self, ran: Option<usize>, waypoint: usize, undone: usize) -> bool {
        self.reruns_unreachable
            && ran.is_some_and(|leg| leg + 1 == waypoint || leg == waypoint)
            && undone < self.max_undos
    }

    /// The verdict on an attempt that `completed` the path or not, `touched` an obstacle or
    /// not, and ended `error` \[normalised\] from the goal on the true configuration (see
    /// [`TrackingPolicy::success_rule`]).
    pub fn judge(&self, completed: bool, touched: bool, error: f64) -> Verdict {
        let at_goal = completed && error <= self.success_epsilon;
        let success = completed && !touched && (at_goal || !self.success_needs_goal);
        Verdict { success, at_goal }
    }

    /// The success rule in words (the summaries' `success_rule`).
    pub fn success_rule(&self) -> &'static str {
        if self.success_needs_goal {
            "the whole path executed, no contact with an obstacle, and the true configuration within success_epsilon of the goal"
        } else {
            "the whole path executed and no contact with an obstacle (the paper's rule; the noise moves the wire beyond any goal tolerance)"
        }
    }
}

/// `shape_stop`, but no tighter than `floor` when the shape stop is on (0 stays 0).
fn no_tighter(shape_stop: f64, floor: f64) -> f64 {
    if shape_stop > 0.0 {
        shape_stop.max(floor)
    } else {
        shape_stop
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [NoiseModel; 4] = [
        NoiseModel::None,
        NoiseModel::Offset,
        NoiseModel::Increment,
        NoiseModel::Absolute,
    ];

    fn scatters(noise: NoiseModel) -> bool {
        matches!(noise, NoiseModel::Increment | NoiseModel::Absolute)
    }

    #[test]
    fn the_success_tolerance_holds_the_stop_rule_of_the_noise() {
        let policy = TrackingPolicy::for_noise;
        assert_eq!(policy(NoiseModel::None).success_epsilon, SUCCESS_EPSILON);
        assert_eq!(policy(NoiseModel::Offset).success_epsilon, SUCCESS_EPSILON);
        // Without noise and under `offset` the stop aims well inside the tolerance, leaving
        // room for the sensor's drift between the stop's reading and the truth.
        for noise in [NoiseModel::None, NoiseModel::Offset] {
            assert!(policy(noise).goal.epsilon <= 0.25 * SUCCESS_EPSILON);
        }
        assert_eq!(
            policy(NoiseModel::Increment).success_epsilon,
            2.0 * EPSILON_NOISY
        );
        assert_eq!(
            policy(NoiseModel::Absolute).goal.max_iterations,
            MAX_ITERATIONS_NOISY
        );
    }

    #[test]
    fn legs_near_a_box_stop_looser_only_under_the_paper_noise_with_the_shape_stop_on() {
        let default = |noise| TrackingPolicy::for_noise(noise).near_shape_stop;
        assert_eq!(default(NoiseModel::Increment), SHAPE_STOP_NEAR_NOISY);
        assert_eq!(default(NoiseModel::Absolute), SHAPE_STOP_NEAR_NOISY);
        const { assert!(SHAPE_STOP_NEAR_NOISY > SHAPE_STOP_NOISY) };
        // Off stays off, and a user's looser stop is kept.
        assert_eq!(default(NoiseModel::Offset), 0.0);
        assert_eq!(default(NoiseModel::None), 0.0);
        let increment = TrackingPolicy::for_noise(NoiseModel::Increment);
        assert_eq!(increment.near_shape_stop_for(0.0), 0.0);
        assert_eq!(increment.near_shape_stop_for(0.02), 0.02);
        let offset = TrackingPolicy::for_noise(NoiseModel::Offset);
        assert_eq!(offset.near_shape_stop_for(0.004), 0.004);
    }

    #[test]
    fn a_leg_run_again_after_an_undo_stops_no_tighter_than_the_default() {
        for noise in [NoiseModel::Increment, NoiseModel::Absolute] {
            let policy = TrackingPolicy::for_noise(noise);
            let default = policy.shape_stop;
            assert_eq!(policy.rerun_shape_stop(0.0035), default);
            assert_eq!(policy.rerun_shape_stop(default), default);
            assert_eq!(policy.rerun_shape_stop(0.008), 0.008);
            // The ε stop alone stays the ε stop.
            assert_eq!(policy.rerun_shape_stop(0.0), 0.0);
        }
        for noise in [NoiseModel::None, NoiseModel::Offset] {
            let policy = TrackingPolicy::for_noise(noise);
            assert_eq!(policy.rerun_shape_stop(0.0), 0.0);
            assert_eq!(policy.rerun_shape_stop(0.002), 0.002);
        }
    }

    #[test]
    fn the_last_quarter_of_a_legs_budget_stops_no_tighter_than_the_default() {
        let policy = TrackingPolicy::for_noise(NoiseModel::Increment);
        assert_eq!(policy.late_after(500), 375);
        assert_eq!(policy.late_after(20), 15);
        assert_eq!(policy.late_after(1), 1);
        let settings = |stop: f64| ControlParams {
            shape_tolerance: stop,
            late_shape_tolerance: policy.rerun_shape_stop(stop),
            late_after: policy.late_after(500),
            ..policy.through
        };
        let tight = settings(0.0035);
        assert_eq!(tight.shape_stop_at(374), 0.0035);
        assert_eq!(tight.shape_stop_at(375), policy.shape_stop);
        // At the default stop nothing changes.
        let default = settings(policy.shape_stop);
        assert_eq!(default.shape_stop_at(499), policy.shape_stop);
    }

    #[test]
    fn a_start_out_of_reach_goes_back_to_the_last_legs_start_only_under_fresh_noise() {
        for noise in ALL {
            let policy = TrackingPolicy::for_noise(noise);
            let fresh = scatters(noise);
            assert_eq!(policy.reruns_unreachable, fresh);
            // The leg before the refused waypoint 5 ran: undone where the rerun lands afresh.
            assert_eq!(policy.undoes_to_last_start(Some(4), 5, 0), fresh);
            assert_eq!(
                policy.undoes_to_last_start(Some(4), 5, MAX_UNDOS - 1),
                fresh
            );
            // Leg 5 ran, and its undo landed out of reach: back to where it first started.
            assert_eq!(policy.undoes_to_last_start(Some(5), 5, 1), fresh);
            // No undo left, no leg run yet, or the leg before was passed over.
            assert!(!policy.undoes_to_last_start(Some(4), 5, MAX_UNDOS));
            assert!(!policy.undoes_to_last_start(None, 1, 0));
            assert!(!policy.undoes_to_last_start(Some(3), 5, 0));
        }
    }

    #[test]
    fn an_unreachable_waypoint_is_run_again_only_where_each_move_draws_fresh_noise() {
        let unreachable = Outcome::Unreachable {
            step: 3,
            reason: "no dual-arm solution".to_owned(),
        };
        let diverged = Outcome::Diverged {
            step: 4,
            error: 30.0,
        };
        let fault = Outcome::SensorFault {
            step: 2,
            message: "saturated".to_owned(),
        };
        let others = [
            Outcome::Reached { error: 0.01 },
            Outcome::IterationLimit { error: 0.5 },
            Outcome::CollisionDetected {
                step: 1,
                residual: 100.0,
            },
            Outcome::PredictedInstability { step: 0 },
        ];
        for noise in ALL {
            let policy = TrackingPolicy::for_noise(noise);
            assert_eq!(policy.undoes(&unreachable), scatters(noise));
            assert!(policy.undoes(&diverged) && policy.undoes(&fault));
            // A retreat, not an undo, answers a detection; the rest end or finish the leg.
            assert!(others.iter().all(|o| !policy.undoes(o)), "{noise:?}");
        }
    }

    #[test]
    fn a_second_detection_on_a_leg_undoes_it_only_under_fresh_noise() {
        for noise in ALL {
            let policy = TrackingPolicy::for_noise(noise);
            assert!(!policy.escalates(false), "the first detection retreats");
            assert_eq!(policy.escalates(true), scatters(noise));
        }
    }

    #[test]
    fn success_needs_the_goal_only_where_the_noise_allows_reaching_it() {
        let judge = |noise, completed, touched, error| {
            let v = TrackingPolicy::for_noise(noise).judge(completed, touched, error);
            (v.at_goal, v.success)
        };
        // Completed, untouched, far from the goal: a success only by the paper's rule.
        assert_eq!(judge(NoiseModel::Offset, true, false, 0.5), (false, false));
        assert_eq!(judge(NoiseModel::None, true, false, 0.5), (false, false));
        assert_eq!(
            judge(NoiseModel::Increment, true, false, 5.0),
            (false, true)
        );
        assert_eq!(judge(NoiseModel::Absolute, true, false, 5.0), (false, true));
        // At the goal under every model.
        assert_eq!(judge(NoiseModel::Offset, true, false, 0.05), (true, true));
        assert_eq!(judge(NoiseModel::Increment, true, false, 0.5), (true, true));
        // A touch or an unfinished path fails whatever the error.
        for noise in [NoiseModel::Offset, NoiseModel::Increment] {
            assert_eq!(judge(noise, true, true, 0.0), (true, false));
            assert_eq!(judge(noise, false, false, 0.0), (false, false));
        }
        for noise in ALL {
            let policy = TrackingPolicy::for_noise(noise);
            assert_eq!(
                policy.success_rule().contains("paper"),
                !policy.success_needs_goal
            );
        }
    }

    #[test]
    fn a_users_settings_replace_the_tuned_ones_each_checked() {
        for noise in ALL {
            let tuned = TrackingPolicy::for_noise(noise);
            let none = TrackingPolicy::with_settings(noise, &PolicySettings::default());
            assert_eq!(none, Ok(tuned));
            let given = PolicySettings {
                gain: Some(0.3),
                shape_stop: Some(0.004),
                near_shape_stop: None,
                waypoint_moves: Some(7),
            };
            let policy = TrackingPolicy::with_settings(noise, &given).expect("valid settings");
            assert_eq!((policy.gain, policy.shape_stop), (0.3, 0.004));
            // The near stop follows the given stop, loosened to the floor under fresh noise.
            assert_eq!(policy.near_shape_stop, tuned.near_shape_stop_for(0.004));
            assert_eq!(policy.through.max_iterations, 7);
            assert_eq!(policy.goal, tuned.goal);
            let near = PolicySettings {
                near_shape_stop: Some(0.0),
                ..given
            };
            let policy = TrackingPolicy::with_settings(noise, &near).expect("valid settings");
            assert_eq!(policy.near_shape_stop, 0.0);
        }
        let bad = |settings: PolicySettings| {
            TrackingPolicy::with_settings(NoiseModel::Increment, &settings).err()
        };
        let none = PolicySettings::default();
        for gain in [0.0, -0.5, 1.5, f64::NAN] {
            let error = bad(PolicySettings {
                gain: Some(gain),
                ..none
            });
            assert!(
                matches!(error, Some(PolicyError::Gain(_))),
                "{gain}: {error:?}"
            );
        }
        assert_eq!(
            bad(PolicySettings {
                shape_stop: Some(-0.001),
                ..none
            }),
            Some(PolicyError::ShapeStop(-0.001))
        );
        assert_eq!(
            bad(PolicySettings {
                near_shape_stop: Some(-0.002),
                ..none
            }),
            Some(PolicyError::NearShapeStop(-0.002))
        );
        assert_eq!(
            bad(PolicySettings {
                waypoint_moves: Some(0),
                ..none
            }),
            Some(PolicyError::WaypointMoves(0))
        );
        // The shape stop is checked before the gain.
        let both = PolicySettings {
            gain: Some(2.0),
            shape_stop: Some(-1.0),
            ..none
        };
        assert_eq!(bad(both), Some(PolicyError::ShapeStop(-1.0)));
        assert_eq!(
            PolicyError::Gain(2.0).to_string(),
            "gain 2: give a gain K in (0, 1]"
        );
    }

    #[test]
    fn every_policy_builds_valid_controllers() {
        let wire = ftwire_core::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015)
            .expect("a valid wire");
        for noise in ALL {
            let policy = TrackingPolicy::for_noise(noise);
            for settings in [policy.goal, policy.through] {
                let settings = ControlParams {
                    gain: policy.gain,
                    shape_tolerance: policy.shape_stop,
                    ..settings
                };
                assert!(
                    crate::Controller::new(ftwire_estimate::KirchhoffModel::new(wire), settings)
                        .is_ok()
                );
            }
        }
    }
}
