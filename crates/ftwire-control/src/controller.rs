//! The Jacobian controller (paper §III-C, eq. 13–14).
//!
//! From the measured configuration `ã_i` and the goal `a_g`, each step commands
//!
//! ```text
//! δb_i = K J(L; ã_i) (a_g − ã_i)          (eq. 13)
//! b_{i+1} = b_i M(δb_i)                    (eq. 14, M of eq. 8)
//! ```
//!
//! with three guards the paper leaves out: `δb` is scaled down to the step limits; the
//! configuration the model predicts after the step, `ã_i + s K (a_g − ã_i)` for the step's
//! scale `s` (exactly `J⁻¹ δb`), must be in `A_stable`; and the robot must be able to reach
//! `b_{i+1}` ([`ReachCheck`]). A step that fails either of the last two is halved until it
//! passes both (at most [`ControlParams::max_shrinks`] times): near a joint limit a shorter
//! step along the same direction often stays inside. The loop stops when the *measured* `ã` is
//! within `ε` of the goal in normalised units (or, with [`ControlParams::shape_tolerance`],
//! when the model's shape at `ã` is within that distance of the goal's), and every other end
//! is an [`Outcome`]; with [`ControlParams::divergence`] one of them is
//! [`Outcome::Diverged`], a measured `ã` that ran away from the goal. With a
//! [`BiasObserver`] ([`Controller::run_with_bias_observer`]) the step, the guard and the stop use `ã`
//! corrected for the sensor's bias drift. A [`CollisionDetector`] can watch
//! the residual of every move (see [`crate::collision`]).

use std::ops::ControlFlow;
use std::time::Instant;

use ftwire_core::{Pose, Rig};
use ftwire_estimate::WireModel;
use ftwire_estimate::ft::{FtCalibration, Measurement};
use ftwire_estimate::shape::centreline_distance;
use ftwire_rod::to_normalised;
use nalgebra::{Vector3, Vector6};
use serde::Serialize;

use crate::collision::MoveCheck;
use crate::{
    AnyPose, BiasObserver, CollisionDetector, ControlError, FtFeedback, Reach, ReachCheck,
};

mod params;
pub use params::ControlParams;

/// Rests in a row beyond [`ControlParams::divergence`] that stop a run as diverged.
pub const DIVERGED_RESTS: usize = 2;

/// Nodes of the model shapes the shape stop compares, and their matched arc lengths
/// ([`ControlParams::shape_tolerance`]).
pub const SHAPE_STOP_SAMPLES: usize = 50;

/// One planned step: what the controller will command, and what the model expects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepPlan {
    /// `δb` after the step limits and shrinking (rotation first, base clamp frame of `b_i`).
    pub delta_b: Vector6<f64>,
    /// `b_{i+1} = b_i M(δb)`: the second gripper's next pose relative to the base clamp.
    pub next_tip: Pose,
    /// `δa` the model predicts for `δb` (`J⁻¹ δb = s K (a_g − ã)`).
    pub predicted_da: Vector6<f64>,
    /// The scale `s ∈ (0, 1]` applied to eq. 13's `δb`.
    pub scale: f64,
}

/// What the step search of [`Controller::plan_reachable_step`] found.
enum Planned {
    /// A step that passes the stability guard and the reach check.
    Step(StepPlan),
    /// No step passes the stability guard.
    Unstable,
    /// Some step passes the stability guard but the robot reaches none (the last reason).
    Unreachable(String),
}

/// How a controlled motion ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
pub enum Outcome {
    /// The measured `ã` is within `ε` of the goal (or its shape within the shape stop).
    Reached {
        /// `‖a_g − ã‖` at the stop \[normalised\].
        error: f64,
    },
    /// [`ControlParams::max_iterations`] steps were taken without reaching the goal.
    IterationLimit {
        /// `‖a_g − ã‖` at the end \[normalised\].
        error: f64,
    },
    /// The robot cannot reach the next pose of the second gripper.
    Unreachable {
        /// The step that would have moved there (0-based).
        step: usize,
        /// Why.
        reason: String,
    },
    /// From a measured `ã` in the model's `A_stable`, even the smallest allowed step leaves it
    /// by the model's prediction.
    PredictedInstability {
        /// The step (0-based).
        step: usize,
    },
    /// The residual of a move jumped: a contact (the robot stopped there).
    CollisionDetected {
        /// The step whose move was detected (0-based).
        step: usize,
        /// Its residual.
        residual: f64,
    },
    /// The F/T pipeline gave no usable `ã` (too many dropouts, saturation, non-finite).
    SensorFault {
        /// The step after which the measurement failed (0 = the start measurement).
        step: usize,
        /// The pipeline's message.
        message: String,
    },
    /// The measured `ã` stayed away from the goal by more than [`ControlParams::divergence`]
    /// beyond the start's distance for [`DIVERGED_RESTS`] rests in a row.
    Diverged {
        /// The step whose move ended there (0-based).
        step: usize,
        /// `‖a_g − ã‖` there \[normalised\].
        error: f64,
    },
    /// The rig refused or failed a commanded move (nothing moved).
    CommandFailed {
        /// The step (0-based).
        step: usize,
        /// The rig's message.
        message: String,
    },
    /// The model could not be solved at the measured `ã` (outside `A`, or diverged).
    ModelFailed {
        /// The step (0-based).
        step: usize,
        /// The model's message.
        message: String,
    },
}

impl Outcome {
    /// The outcome's name (`reached`, `iteration_limit`, …).
    pub fn name(&self) -> &'static str {
        match self {
            Self::Reached { .. } => "reached",
            Self::IterationLimit { .. } => "iteration_limit",
            Self::Unreachable { .. } => "unreachable",
            Self::PredictedInstability { .. } => "predicted_instability",
            Self::CollisionDetected { .. } => "collision_detected",
            Self::SensorFault { .. } => "sensor_fault",
            Self::Diverged { .. } => "diverged",
            Self::CommandFailed { .. } => "command_failed",
            Self::ModelFailed { .. } => "model_failed",
        }
    }
}

/// One executed step of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRecord {
    /// `a_i` the step was computed from: the measured `ã_i`, corrected by the bias observer
    /// when the run has one (the `estimate` of the step before).
    pub a: Vector6<f64>,
    /// The planned step.
    pub plan: StepPlan,
    /// `ã_{i+1}` measured after the move.
    pub measured: Vector6<f64>,
    /// What the controller took as `a_{i+1}`: `measured`, corrected by the bias observer
    /// when the run has one ([`Controller::run_with_bias_observer`]).
    pub estimate: Vector6<f64>,
    /// The move's miss against the model's prediction \[normalised\] (see [`MoveCheck::miss`]).
    pub miss: f64,
    /// The move as the collision detector sees it: its deviation from the model's (Newton)
    /// prediction for the executed motion, and the predicted step.
    pub check: MoveCheck,
    /// The move's detector residual (see [`CollisionDetector`]; without a detector, that of
    /// [`CollisionDetector::uncalibrated`]).
    pub residual: f64,
    /// Compute time of the control law and its stability guard \[s\].
    pub plan_s: f64,
    /// Compute time of the reach checks, one per halving the step needed \[s\].
    pub reach_s: f64,
    /// `b_{i+1}`: the second gripper's pose relative to the base clamp after the move, as the
    /// robot reports it. It is `plan.next_tip` unless the rig reports that it landed elsewhere
    /// (a robot whose encoders see an error injected into its commands).
    pub tip: Pose,
}

/// A finished run: the outcome and every executed step.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// How it ended.
    pub outcome: Outcome,
    /// `ã_0`, measured at the start.
    pub start: Vector6<f64>,
    /// What the controller took as `a_0`: `start`, corrected by the bias observer when the
    /// run has one.
    pub start_estimate: Vector6<f64>,
    /// `b_0`, the second gripper's pose relative to the base clamp at the start (believed).
    pub start_tip: Pose,
    /// The executed steps, in order.
    pub steps: Vec<StepRecord>,
}

impl Run {
    /// The last measured `ã`.
    pub fn last_a(&self) -> Vector6<f64> {
        self.steps.last().map_or(self.start, |s| s.measured)
    }

    /// The last configuration the controller steered by (the last `ã`, corrected by the bias
    /// observer when the run has one).
    pub fn last_estimate(&self) -> Vector6<f64> {
        self.steps
            .last()
            .map_or(self.start_estimate, |s| s.estimate)
    }
}

/// The controller of eq. 13–14 for a wire model (see the module docs).
///
/// # Example
/// ```
/// use ftwire_control::{ControlParams, Controller};
/// use ftwire_estimate::KirchhoffModel;
/// use ftwire_core::{Pose, WireParams};
/// use nalgebra::Vector6;
///
/// let model = KirchhoffModel::new(WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015)?);
/// let controller = Controller::new(model, ControlParams::default())?;
/// let a = Vector6::new(0.0, 0.2, 0.1, -0.5, 0.3, 0.0);
/// let goal = Vector6::new(0.0, 0.25, 0.1, -0.4, 0.3, 0.0);
/// let plan = controller.plan_step(&a, &goal, &Pose::identity())?.expect("a stable step");
/// // The model expects the step to close K = 0.2 of the gap.
/// assert!((plan.predicted_da - 0.2 * (goal - a)).norm() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct Controller<M> {
    model: M,
    settings: ControlParams,
    detector: Option<CollisionDetector>,
}

impl<M: WireModel> Controller<M> {
    /// A controller for `model` with `settings`, without collision detection.
    ///
    /// # Errors
    /// [`ControlError::BadSetting`] for a setting outside its range.
    pub fn new(model: M, settings: ControlParams) -> Result<Self, ControlError> {
        settings.validate()?;
        Ok(Self {
            model,
            settings,
            detector: None,
        })
    }

    /// The same controller, stopping on a contact that `detector` sees.
    #[must_use]
    pub fn with_detector(mut self, detector: CollisionDetector) -> Self {
        self.detector = Some(detector);
        self
    }

    /// The model.
    pub fn model(&self) -> &M {
        &self.model
    }

    /// The settings.
    pub fn settings(&self) -> &ControlParams {
        &self.settings
    }

    /// The collision detector, if any.
    pub fn detector(&self) -> Option<&CollisionDetector> {
        self.detector.as_ref()
    }

    /// F/T samples to average at the rest after a step taken `error` (normalised) from the
    /// goal: `samples` (the feedback's own), or at least [`ControlParams::settle_samples`]
    /// within [`ControlParams::settle_radius`].
    ///
    /// # Example
    /// ```
    /// use ftwire_control::{ControlParams, Controller};
    /// use ftwire_estimate::KirchhoffModel;
    /// let wire = ftwire_core::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015)?;
    /// let settings = ControlParams {
    ///     settle_radius: 0.2,
    ///     settle_samples: 400,
    ///     ..Default::default()
    /// };
    /// let controller = Controller::new(KirchhoffModel::new(wire), settings)?;
    /// assert_eq!(controller.rest_samples(100, 0.5), 100);
    /// assert_eq!(controller.rest_samples(100, 0.1), 400);
    /// assert_eq!(controller.rest_samples(1000, 0.1), 1000);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn rest_samples(&self, samples: usize, error: f64) -> usize {
        if error < self.settings.settle_radius {
            samples.max(self.settings.settle_samples)
        } else {
            samples
        }
    }

    /// `‖a_g − a‖` in normalised units.
    pub fn distance(&self, a: &Vector6<f64>, goal: &Vector6<f64>) -> f64 {
        to_normalised(self.model.wire(), &(goal - a)).norm()
    }

    /// The goal's model shape `Φ(a_g)` for the shape stop, `None` when it is off
    /// ([`ControlParams::shape_tolerance`]).
    ///
    /// # Errors
    /// [`ControlError::Model`] when the model cannot be solved at `goal`.
    fn stop_shape(&self, goal: &Vector6<f64>) -> Result<Option<Vec<Vector3<f64>>>, ControlError> {
        if self.settings.shape_tolerance > 0.0 {
            Ok(Some(self.model.shape(goal, SHAPE_STOP_SAMPLES)?.positions))
        } else {
            Ok(None)
        }
    }

    /// Mean distance \[m\] between the model's shape at `a` and `shape` (the goal's, from the
    /// same model) at [`SHAPE_STOP_SAMPLES`] matched arc lengths: the shape stop's measure.
    ///
    /// # Errors
    /// [`ControlError::Model`] when the model cannot be solved at `a`.
    pub fn shape_distance(
        &self,
        a: &Vector6<f64>,
        shape: &[Vector3<f64>],
    ) -> Result<f64, ControlError> {
        let positions = self.model.shape(a, SHAPE_STOP_SAMPLES)?.positions;
        Ok(centreline_distance(&positions, shape, SHAPE_STOP_SAMPLES)?)
    }

    /// Plans one step from `a` toward `goal` with the second gripper at `tip` (eq. 13–14, the
    /// step limits and the stability guard). `None` when `a` is in the model's `A_stable` and
    /// even the smallest allowed step leaves it by the model's prediction. From an `a` outside
    /// `A_stable` (a noisy measurement, or a true wire the model calls unstable near the
    /// boundary) the step toward the stable goal is taken unguarded: it is the way back, and
    /// refusing it would strand the wire there.
    ///
    /// # Errors
    /// [`ControlError::Model`] when the model cannot be solved at `a`.
    pub fn plan_step(
        &self,
        a: &Vector6<f64>,
        goal: &Vector6<f64>,
        tip: &Pose,
    ) -> Result<Option<StepPlan>, ControlError> {
        let (planned, _) = self.plan_reachable_step(a, goal, tip, &mut AnyPose)?;
        Ok(match planned {
            Planned::Step(plan) => Some(plan),
            Planned::Unstable | Planned::Unreachable(_) => None,
        })
    }

    /// [`Controller::plan_step`] with the reach guard: the step's scale is halved (at most
    /// [`ControlParams::max_shrinks`] times) until its prediction passes the stability guard
    /// and `reach` can reach its `next_tip`. Also returns the time spent in `reach` \[s\].
    fn plan_reachable_step<Q: ReachCheck>(
        &self,
        a: &Vector6<f64>,
        goal: &Vector6<f64>,
        tip: &Pose,
        reach: &mut Q,
    ) -> Result<(Planned, f64), ControlError> {
        let s = &self.settings;
        let jacobian = self.model.jacobian(a)?.jacobian;
        let da = s.gain * (goal - a);
        let db = jacobian * da;
        let rotation = db.fixed_rows::<3>(0).norm();
        let translation = db.fixed_rows::<3>(3).norm();
        let mut scale = 1.0_f64
            .min(s.max_rotation / rotation.max(f64::MIN_POSITIVE))
            .min(s.max_translation / translation.max(f64::MIN_POSITIVE));
        // Measured outside the model's A_stable (noise, or where the model and the true
        // wire disagree near the boundary), every step toward the (stable) goal is the way
        // back: the guard only keeps a stable configuration from leaving A_stable.
        let inside = self.model.is_stable(a).unwrap_or(false);
        let mut reach_s = 0.0;
        let mut unreachable = None;
        for _ in 0..=s.max_shrinks {
            let predicted_da = scale * da;
            // A prediction outside A (or one the model cannot solve) is not a stable step.
            if !inside || self.model.is_stable(&(a + predicted_da)).unwrap_or(false) {
                let delta_b = scale * db;
                let next_tip = tip * ftwire_rod::se3::exp(&delta_b);
                let clock = Instant::now();
                let reachable = reach.check(&next_tip);
                reach_s += clock.elapsed().as_secs_f64();
                match reachable {
                    Reach::Reachable => {
                        let plan = StepPlan {
                            delta_b,
                            next_tip,
                            predicted_da,
                            scale,
                        };
                        return Ok((Planned::Step(plan), reach_s));
                    }
                    Reach::Unreachable(reason) => unreachable = Some(reason),
                }
            }
            scale *= 0.5;
        }
        // Unreachable when some stable step was found but none the robot could reach.
        let planned = unreachable.map_or(Planned::Unstable, Planned::Unreachable);
        Ok((planned, reach_s))
    }

    /// Checks the goal: finite and in `A_stable` of the model.
    ///
    /// # Errors
    /// [`ControlError::NonFiniteGoal`], [`ControlError::GoalUnstable`], or
    /// [`ControlError::Model`] for a goal outside `A`.
    pub fn check_goal(&self, goal: &Vector6<f64>) -> Result<(), ControlError> {
        if let Some(index) = goal.iter().position(|v| !v.is_finite()) {
            return Err(ControlError::NonFiniteGoal {
                index,
                value: goal[index],
            });
        }
        if !self.model.is_stable(goal)? {
            return Err(ControlError::GoalUnstable {
                goal: (*goal).into(),
            });
        }
        Ok(())
    }

    /// Steers the wire on `rig` to `goal`, measuring `ã` through `feedback` and checking every
    /// pose with `reach`. See [`Controller::run_observed`].
    ///
    /// # Errors
    /// As [`Controller::run_observed`].
    pub fn run<R: Rig, C: FtCalibration, Q: ReachCheck>(
        &self,
        rig: &mut R,
        feedback: &FtFeedback<C>,
        reach: &mut Q,
        goal: &Vector6<f64>,
    ) -> Result<Run, ControlError> {
        self.run_observed(rig, feedback, reach, goal, |_, _| {})
    }

    /// As [`Controller::run`], calling `observe(rig, step)` after every executed step (the
    /// experiments read their ground truth there).
    ///
    /// Bad input is refused before anything moves: a goal that is not finite or not in
    /// `A_stable` ([`Controller::check_goal`]), or a start pose the robot cannot reach.
    ///
    /// # Errors
    /// Bad input as above; [`ControlError::Rig`] when the rig cannot report its poses.
    /// Everything after the start is an [`Outcome`].
    pub fn run_observed<R: Rig, C: FtCalibration, Q: ReachCheck>(
        &self,
        rig: &mut R,
        feedback: &FtFeedback<C>,
        reach: &mut Q,
        goal: &Vector6<f64>,
        observe: impl FnMut(&R, &StepRecord),
    ) -> Result<Run, ControlError> {
        self.run_with_bias_observer(rig, feedback, reach, goal, None, observe)
    }

    /// As [`Controller::run_observed`], steering by `ã` corrected by a [`BiasObserver`] of
    /// the sensor's drift when one is given: every rest, the measured `ã`, its standard errors
    /// and the reported pose update it, and the step, the stop rule and the stability guard
    /// use `ã − β̂`. The collision detector keeps watching the raw `ã`. Pass the same observer
    /// to every run after one tare (the legs of a tracked path).
    ///
    /// # Errors
    /// As [`Controller::run_observed`].
    pub fn run_with_bias_observer<R: Rig, C: FtCalibration, Q: ReachCheck>(
        &self,
        rig: &mut R,
        feedback: &FtFeedback<C>,
        reach: &mut Q,
        goal: &Vector6<f64>,
        mut observer: Option<&mut BiasObserver<M>>,
        observe: impl FnMut(&R, &StepRecord),
    ) -> Result<Run, ControlError> {
        self.check_goal(goal)?;
        let poses = rig.gripper_poses().map_err(|e| ControlError::Rig {
            message: e.to_string(),
        })?;
        let base = poses.base;
        let start_tip = poses.relative();
        if let Reach::Unreachable(reason) = reach.check(&start_tip) {
            return Err(ControlError::UnreachableStart { reason });
        }
        let mut run = Run {
            outcome: Outcome::IterationLimit { error: f64::NAN },
            start: Vector6::zeros(),
            start_estimate: Vector6::zeros(),
            start_tip,
            steps: Vec::new(),
        };
        match feedback.measure(rig) {
            Ok(m) => {
                run.start = m.a;
                run.start_estimate = corrected(&mut observer, &m, &start_tip, rig.time());
            }
            Err(e) => {
                run.outcome = Outcome::SensorFault {
                    step: 0,
                    message: e.to_string(),
                };
                return Ok(run);
            }
        }
        let steering = Steering {
            rig,
            feedback,
            reach,
            base,
            observer,
        };
        run.outcome = self.steer(steering, goal, &mut run, observe)?;
        Ok(run)
    }

    /// The control loop from the start measured in `run`: each step checks the stop rules
    /// ([`Controller::is_reached`], divergence), plans ([`Controller::timed_step`]), moves and
    /// measures ([`Controller::execute`]), and records the move with its collision residual in
    /// `run.steps` (after `observe`). Returns how the motion ended.
    ///
    /// # Errors
    /// [`ControlError::Model`] when the model cannot be solved at the goal for the shape stop.
    fn steer<R: Rig, C: FtCalibration, Q: ReachCheck>(
        &self,
        mut steering: Steering<'_, '_, R, C, Q, M>,
        goal: &Vector6<f64>,
        run: &mut Run,
        mut observe: impl FnMut(&R, &StepRecord),
    ) -> Result<Outcome, ControlError> {
        let (mut raw, mut a, mut tip) = (run.start, run.start_estimate, run.start_tip);
        let mut checks = Vec::new();
        let goal_shape = self.stop_shape(goal)?;
        let start_error = self.distance(&a, goal);
        let mut beyond = 0;
        for step in 0..self.settings.max_iterations {
            let error = self.distance(&a, goal);
            if self.is_reached(&a, error, goal_shape.as_deref(), step) {
                return Ok(Outcome::Reached { error });
            }
            let diverging =
                self.settings.divergence > 0.0 && error > start_error + self.settings.divergence;
            beyond = if diverging { beyond + 1 } else { 0 };
            if beyond >= DIVERGED_RESTS {
                return Ok(Outcome::Diverged {
                    step: step - 1,
                    error,
                });
            }
            let (plan, plan_s, reach_s) =
                match self.timed_step(&a, goal, &tip, steering.reach, step) {
                    ControlFlow::Continue(planned) => planned,
                    ControlFlow::Break(outcome) => return Ok(outcome),
                };
            let (reported, m) = match self.execute(&mut steering, &plan, error, step) {
                ControlFlow::Continue(moved) => moved,
                ControlFlow::Break(outcome) => return Ok(outcome),
            };
            let next = corrected(&mut steering.observer, &m, &reported, steering.rig.time());
            let measured = m.a;
            let check = MoveCheck::of_move(
                &self.model,
                &raw,
                &measured,
                &(tip.inverse() * reported),
                &plan.predicted_da,
            );
            checks.push(check);
            let residual = self
                .detector
                .unwrap_or_else(CollisionDetector::uncalibrated)
                .residual(&checks);
            let record = StepRecord {
                a,
                plan,
                measured,
                estimate: next,
                miss: check.miss(),
                check,
                residual,
                plan_s,
                reach_s,
                tip: reported,
            };
            observe(steering.rig, &record);
            run.steps.push(record);
            if let Some(detector) = &self.detector
                && detector.is_contact(residual)
            {
                return Ok(Outcome::CollisionDetected { step, residual });
            }
            raw = measured;
            a = next;
            tip = reported;
        }
        Ok(Outcome::IterationLimit {
            error: self.distance(&a, goal),
        })
    }

    /// The stop rule at `a`, `error` from the goal: within the shape stop of step `step` of
    /// the goal's shape when there is one, else within `ε`.
    fn is_reached(
        &self,
        a: &Vector6<f64>,
        error: f64,
        goal_shape: Option<&[Vector3<f64>]>,
        step: usize,
    ) -> bool {
        match goal_shape {
            Some(g) => self
                .shape_distance(a, g)
                .is_ok_and(|d| d < self.settings.shape_stop_at(step)),
            None => error < self.settings.epsilon,
        }
    }

    /// Plans step `step` with the reach guard ([`Controller::plan_reachable_step`]); returns
    /// the plan with its compute time and its reach-check time \[s\], or breaks with the
    /// outcome when no step passes the guards or the model fails.
    fn timed_step<Q: ReachCheck>(
        &self,
        a: &Vector6<f64>,
        goal: &Vector6<f64>,
        tip: &Pose,
        reach: &mut Q,
        step: usize,
    ) -> ControlFlow<Outcome, (StepPlan, f64, f64)> {
        let clock = Instant::now();
        let (plan, reach_s) = match self.plan_reachable_step(a, goal, tip, reach) {
            Ok((Planned::Step(plan), reach_s)) => (plan, reach_s),
            Ok((Planned::Unstable, _)) => {
                return ControlFlow::Break(Outcome::PredictedInstability { step });
            }
            Ok((Planned::Unreachable(reason), _)) => {
                return ControlFlow::Break(Outcome::Unreachable { step, reason });
            }
            Err(e) => {
                return ControlFlow::Break(Outcome::ModelFailed {
                    step,
                    message: e.to_string(),
                });
            }
        };
        let plan_s = (clock.elapsed().as_secs_f64() - reach_s).max(0.0);
        ControlFlow::Continue((plan, plan_s, reach_s))
    }

    /// Moves the second gripper to the plan's pose and rests: returns the pose the robot
    /// reports after the move (eq. 14's next `b_i`) and the measurement there, over
    /// [`Controller::rest_samples`] samples for a step `error` from the goal; or breaks with
    /// the outcome when the rig refuses the move, cannot report its pose, or the sensor fails.
    fn execute<R: Rig, C: FtCalibration, Q: ReachCheck>(
        &self,
        steering: &mut Steering<'_, '_, R, C, Q, M>,
        plan: &StepPlan,
        error: f64,
        step: usize,
    ) -> ControlFlow<Outcome, (Pose, Measurement)> {
        let rig = &mut *steering.rig;
        if let Err(e) = rig.move_tip(steering.base * plan.next_tip) {
            return ControlFlow::Break(Outcome::CommandFailed {
                step,
                message: e.to_string(),
            });
        }
        let reported = match rig.gripper_poses() {
            Ok(poses) => poses.relative(),
            Err(e) => {
                return ControlFlow::Break(Outcome::CommandFailed {
                    step,
                    message: format!("the robot cannot report its pose after the move: {e}"),
                });
            }
        };
        let samples = self.rest_samples(steering.feedback.samples(), error);
        match steering.feedback.measure_samples(rig, samples) {
            Ok(m) => ControlFlow::Continue((reported, m)),
            Err(e) => ControlFlow::Break(Outcome::SensorFault {
                step: step + 1,
                message: e.to_string(),
            }),
        }
    }
}

/// What a run steers with: the rig, its F/T pipeline and reach check, the base gripper's pose
/// (the robot frame of the commands), and the bias observer when the run has one.
struct Steering<'r, 'o, R, C, Q, M> {
    rig: &'r mut R,
    feedback: &'r FtFeedback<C>,
    reach: &'r mut Q,
    base: Pose,
    observer: Option<&'o mut BiasObserver<M>>,
}

/// The `a` the controller steers by: the measured `ã`, corrected by the bias observer (which
/// this rest at `tip` and `time` \[s\] updates) when there is one.
fn corrected<M: WireModel>(
    observer: &mut Option<&mut BiasObserver<M>>,
    m: &Measurement,
    tip: &Pose,
    time: f64,
) -> Vector6<f64> {
    match observer.as_deref_mut() {
        Some(o) => o.update(&m.a, &m.a_std_error, tip, time),
        None => m.a,
    }
}
