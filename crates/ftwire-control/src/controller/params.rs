//! The controller's settings ([`ControlParams`]).

use serde::Serialize;

use crate::ControlError;

/// Settings of the controller (public fields + `Default`; checked by [`Controller::new`](crate::Controller::new)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ControlParams {
    /// The gain `K` of eq. 13 (default `0.2`, the paper's), in `(0, 1]`.
    pub gain: f64,
    /// Stop threshold `ε` on `‖a_g − ã‖` in normalised units (torque in `c2/L`, force in
    /// `c2/L²`) of the measured `ã` (default `0.05`).
    pub epsilon: f64,
    /// Largest translation of one step, `|δx|` \[m\] (default `0.05`).
    pub max_translation: f64,
    /// Largest rotation of one step, `|δθ|` \[rad\] (default `0.3`).
    pub max_rotation: f64,
    /// Most steps of one run (default `100`).
    pub max_iterations: usize,
    /// Most halvings of a step whose predicted configuration leaves `A_stable` or whose pose
    /// the robot cannot reach (default `6`).
    pub max_shrinks: usize,
    /// Settling radius \[normalised\]: once the measured `ã` is within it of the goal, each
    /// rest averages at least [`ControlParams::settle_samples`] F/T samples (default `0`:
    /// off). Near the goal the steps `K (a_g − ã)` shrink below the noise of a rest's mean, so
    /// the loop steers by noise and the stop rule fires on a lucky reading; a longer average
    /// there halves the noise for each fourfold of samples, at the cost of only the last few
    /// rests, and lets the loop stop at an ε below that noise (`tests/controller.rs`,
    /// `longer_rests_near_the_goal_let_the_loop_stop_at_a_small_epsilon`).
    pub settle_radius: f64,
    /// F/T samples averaged per rest inside [`ControlParams::settle_radius`] (default `0`;
    /// the feedback's own count when that is larger).
    pub settle_samples: usize,
    /// Shape stop \[m\] (default `0`: off, the stop is `ε`'s). When positive, it replaces `ε`:
    /// the run stops once the model's shape at the `a` it steers by, `Φ(ã)`, is within this
    /// mean distance of the goal's, `Φ(a_g)` (at [`SHAPE_STOP_SAMPLES`](crate::SHAPE_STOP_SAMPLES) matched arc lengths:
    /// the distance Tables III–IV score). Where every move scatters the wire by the full
    /// execution noise, the stop picks a move that landed the *wire* near its goal, which `ε`
    /// on the six wrench components does only loosely (`docs/control-noise.md`).
    pub shape_tolerance: f64,
    /// The shape stop \[m\] once [`ControlParams::late_after`] steps are spent (default
    /// `0`: the same as [`ControlParams::shape_tolerance`]; never tighter than it). A tight
    /// shape stop waits for a lucky landing of the noisy moves; where landings near the goal
    /// are rare, the run would end at [`ControlParams::max_iterations`] on whatever landing
    /// came last. A looser stop for the last moves of the budget ends it on a landing near the
    /// goal instead (optimal stopping with a finite budget: the threshold rises as the moves
    /// left run out).
    pub late_shape_tolerance: f64,
    /// Steps after which [`ControlParams::late_shape_tolerance`] applies (default
    /// `usize::MAX`: never).
    pub late_after: usize,
    /// Divergence stop \[normalised\] (default `0`: off). When positive, the run stops with
    /// [`Outcome::Diverged`](crate::Outcome::Diverged) once the measured `‖a_g − ã‖` has exceeded its value at the
    /// run's start by more than this at [`DIVERGED_RESTS`](crate::DIVERGED_RESTS) rests in a row. Under the paper's
    /// `increment` noise one move can throw the gripper 40 mm; near a taut wire the next
    /// measurement is then far from the goal. One such throw is noise the next step corrects;
    /// a second in a row is a run away from the region where eq. 13's linear step helps,
    /// where every further move only adds its own noise. Stopping there lets the caller undo
    /// the run from a pose it knows.
    pub divergence: f64,
}

impl Default for ControlParams {
    fn default() -> Self {
        Self {
            gain: 0.2,
            epsilon: 0.05,
            max_translation: 0.05,
            max_rotation: 0.3,
            max_iterations: 100,
            max_shrinks: 6,
            settle_radius: 0.0,
            settle_samples: 0,
            shape_tolerance: 0.0,
            late_shape_tolerance: 0.0,
            late_after: usize::MAX,
            divergence: 0.0,
        }
    }
}

impl ControlParams {
    /// Checks every setting ([`Controller::new`](crate::Controller::new)).
    pub(super) fn validate(&self) -> Result<(), ControlError> {
        let bad = |name, value, allowed| ControlError::BadSetting {
            name,
            value,
            allowed,
        };
        if !(self.gain.is_finite() && self.gain > 0.0 && self.gain <= 1.0) {
            return Err(bad("gain", self.gain, "a gain K in (0, 1]"));
        }
        for (name, value) in [
            ("epsilon", self.epsilon),
            ("max_translation", self.max_translation),
            ("max_rotation", self.max_rotation),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(bad(name, value, "a finite number > 0"));
            }
        }
        if self.max_iterations == 0 {
            return Err(bad("max_iterations", 0.0, "at least 1 step"));
        }
        if !(self.settle_radius.is_finite() && self.settle_radius >= 0.0) {
            return Err(bad(
                "settle_radius",
                self.settle_radius,
                "a finite number ≥ 0 (0: off)",
            ));
        }
        if !(self.divergence.is_finite() && self.divergence >= 0.0) {
            return Err(bad(
                "divergence",
                self.divergence,
                "a finite number ≥ 0 (0: off)",
            ));
        }
        if !(self.shape_tolerance.is_finite() && self.shape_tolerance >= 0.0) {
            return Err(bad(
                "shape_tolerance",
                self.shape_tolerance,
                "a finite distance ≥ 0 m (0: off)",
            ));
        }
        if !(self.late_shape_tolerance.is_finite() && self.late_shape_tolerance >= 0.0) {
            return Err(bad(
                "late_shape_tolerance",
                self.late_shape_tolerance,
                "a finite distance ≥ 0 m (0: the shape stop's)",
            ));
        }
        Ok(())
    }

    /// The shape stop \[m\] at step `step` of a run: [`ControlParams::shape_tolerance`], or
    /// the looser [`ControlParams::late_shape_tolerance`] from step
    /// [`ControlParams::late_after`] on.
    pub fn shape_stop_at(&self, step: usize) -> f64 {
        if step >= self.late_after {
            self.shape_tolerance.max(self.late_shape_tolerance)
        } else {
            self.shape_tolerance
        }
    }
}
