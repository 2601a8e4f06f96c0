//! The closed loop along a planned path on any [`Rig`]: the controller (eq. 13–14) toward each
//! waypoint in turn, with the retreat, undo, relocation and pass-over of
//! [`TrackingPolicy`].
//!
//! Ground truth never reaches the tracker: a caller that has some (a simulator, motion capture)
//! reads it in the observer, which is called at every rest with what the tracker was doing
//! there ([`Rest`]).

use ftwire_core::{Command, GripperPoses, Pose, Rig};
use ftwire_estimate::WireModel;
use ftwire_estimate::ft::FtCalibration;
use nalgebra::Vector6;
use serde::Serialize;

use crate::{
    BiasObserver, BiasObserverParams, CollisionDetector, ControlError, ControlParams, Controller,
    FtFeedback, Outcome, ReachCheck, Run, StepRecord, TrackingPolicy,
};

/// Executes a list of waypoints closed loop (see the module docs).
///
/// # Example
/// ```
/// use ftwire_control::{NoiseModel, PathTracker, TrackingPolicy};
/// use ftwire_estimate::KirchhoffModel;
/// let wire = ftwire_core::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015)?;
/// let tracker = PathTracker::new(
///     KirchhoffModel::new(wire),
///     TrackingPolicy::for_noise(NoiseModel::None),
/// )
/// .with_near(vec![false, true, false]);
/// assert!(tracker.is_near(1) && !tracker.is_near(7));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct PathTracker<M> {
    model: M,
    policy: TrackingPolicy,
    detector: Option<CollisionDetector>,
    bias: Option<BiasObserverParams>,
    near: Vec<bool>,
}

/// What the tracker was doing at a rest it reports to the observer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RestKind {
    /// The path's start, before any move.
    Start,
    /// After a controller move of a leg.
    Step,
    /// A leg has ended and is recorded (the rig has not moved since the leg's last rest).
    LegEnd,
    /// After the move back of a retreat.
    Retreat,
    /// After the move back of an undo.
    Undo,
    /// After a relocation of both grippers.
    Relocation,
}

/// A rest the tracker reports to the observer.
#[derive(Debug, Clone, Copy)]
pub struct Rest<'a> {
    /// What the tracker was doing.
    pub kind: RestKind,
    /// The index in [`Tracked::legs`] of the leg the rest belongs to: the leg running (a
    /// step), the leg just recorded (its end), or the next leg to be recorded (the start, a
    /// retreat, an undo, a relocation).
    pub leg: usize,
    /// The waypoint steered to (0 at the start).
    pub waypoint: usize,
    /// The step's record, at a [`RestKind::Step`].
    pub step: Option<&'a StepRecord>,
}

/// One leg as it ran: toward one waypoint, reruns counted apart.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackedLeg {
    /// The waypoint it steered to (1: the first after the start).
    pub waypoint: usize,
    /// Moves it made.
    pub moves: usize,
    /// How the controller ended it.
    pub outcome: Outcome,
    /// Whether it counts as the visit of its waypoint: not when it was run again (after a
    /// retreat, an undo or a relocation) or its waypoint was passed over.
    pub scored: bool,
}

/// How a tracked path ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "end", rename_all = "snake_case")]
pub enum TrackEnd {
    /// The last leg's controller outcome.
    Leg(Outcome),
    /// The controller refused a waypoint before moving (outside its model's `A_stable`, a
    /// start the arms cannot hold).
    Refused {
        /// The waypoint.
        waypoint: usize,
        /// The controller's reason.
        reason: String,
    },
    /// A leg's start was out of the arms' reach and no relocation brought it back.
    StartOutOfReach {
        /// The waypoint.
        waypoint: usize,
    },
    /// The rig failed the move back of a retreat.
    RetreatFailed {
        /// The rig's message.
        message: String,
    },
    /// The rig failed the move back of an undo.
    UndoFailed {
        /// The rig's message.
        message: String,
    },
    /// The rig refused the relocating move.
    RelocationFailed {
        /// The rig's message.
        message: String,
    },
}

impl std::fmt::Display for TrackEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Leg(outcome) => f.write_str(outcome.name()),
            Self::Refused { waypoint, reason } => {
                write!(f, "refused at waypoint {waypoint}: {reason}")
            }
            Self::StartOutOfReach { waypoint } => write!(
                f,
                "refused at waypoint {waypoint}: its start is out of the arms' reach, and no \
                 translation of both grippers brings it back"
            ),
            Self::RetreatFailed { message } => write!(f, "retreat failed: {message}"),
            Self::UndoFailed { message } => write!(f, "undo failed: {message}"),
            Self::RelocationFailed { message } => write!(f, "relocation failed: {message}"),
        }
    }
}

/// What [`PathTracker::track`] did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Tracked {
    /// How it ended (`None` for a path of its start alone).
    pub end: Option<TrackEnd>,
    /// Moves commanded: the legs' and the retreats', undos' and relocation's.
    pub moves: usize,
    /// The whole path was executed: every leg ended by reaching its waypoint or by its
    /// iteration limit, or passed over an intermediate waypoint out of the arms' reach.
    pub completed: bool,
    /// The collision detector flagged a move.
    pub detected: bool,
    /// Retreats after a detection ([`TrackingPolicy::max_retreats`] at most).
    pub retreats: usize,
    /// Legs undone ([`TrackingPolicy::max_undos`] at most).
    pub undone: usize,
    /// Intermediate waypoints passed over, out of the arms' reach.
    pub skipped: usize,
    /// Whether both grippers were relocated (at most once).
    pub relocated: bool,
    /// Every leg as it ran, in order, reruns included.
    pub legs: Vec<TrackedLeg>,
    /// The legs that count as their waypoint's visit, in order (indices into
    /// [`Tracked::legs`]).
    pub scored: Vec<usize>,
    /// Every move's detector residual (what calibrates a detector on free motion).
    pub residuals: Vec<f64>,
    /// The configuration the controller last steered by (the last leg's last estimate).
    pub last_estimate: Vector6<f64>,
}

/// A way to move both grippers by one translation when a pose is out of the arms' reach
/// (`Z = A × Q` at execution), and the reach check from the new base pose.
pub trait Relocate<Q: ReachCheck> {
    /// A base gripper pose (world frame) from which the arms reach the goal `a_goal` again,
    /// given the robot's `poses` and the measured `a_now`; `None` when there is none.
    ///
    /// # Errors
    /// Whatever stops the search (a model that cannot be solved).
    fn relocation(
        &mut self,
        poses: &GripperPoses,
        a_now: &Vector6<f64>,
        a_goal: &Vector6<f64>,
    ) -> Result<Option<Pose>, ControlError>;

    /// The reach check with the base gripper at `base` (world frame).
    ///
    /// # Errors
    /// Whatever stops building it.
    fn reach_from(&mut self, base: &Pose) -> Result<Q, ControlError>;
}

/// The controllers of a path: between waypoints, near an obstacle, to the goal; each for a
/// first run and for a rerun.
struct Controllers<M> {
    through: Controller<M>,
    close: Controller<M>,
    end: Controller<M>,
    through_again: Controller<M>,
    close_again: Controller<M>,
    end_again: Controller<M>,
}

impl<M: WireModel> PathTracker<M> {
    /// A tracker steering by `model` under `policy`, with no collision detector, no bias
    /// observer and no waypoint near an obstacle.
    pub fn new(model: M, policy: TrackingPolicy) -> Self {
        Self {
            model,
            policy,
            detector: None,
            bias: None,
            near: Vec::new(),
        }
    }

    /// With `detector` watching every move.
    #[must_use]
    pub fn with_detector(mut self, detector: CollisionDetector) -> Self {
        self.detector = Some(detector);
        self
    }

    /// Steering by `ã` corrected for the sensor's bias drift by one [`BiasObserver`] with
    /// `settings` over the whole path.
    #[must_use]
    pub fn with_bias_observer(mut self, settings: BiasObserverParams) -> Self {
        self.bias = Some(settings);
        self
    }

    /// With the waypoints whose planned wire is near an obstacle flagged (`near[i]`): the legs
    /// from and to them stop at [`TrackingPolicy::near_shape_stop`].
    #[must_use]
    pub fn with_near(mut self, near: Vec<bool>) -> Self {
        self.near = near;
        self
    }

    /// The policy.
    pub fn policy(&self) -> &TrackingPolicy {
        &self.policy
    }

    /// Whether waypoint `i` is flagged near an obstacle (`false` past the flags).
    pub fn is_near(&self, i: usize) -> bool {
        self.near.get(i).copied().unwrap_or(false)
    }

    /// Tracks `waypoints` (the first is where the wire is) on `rig` with `feedback`, checking
    /// every pose with `reach`, and calls `observe` at every rest. No relocation: a pose out of
    /// reach is passed over, undone or ends the attempt. See
    /// [`PathTracker::track_relocating`].
    ///
    /// # Errors
    /// As [`PathTracker::track_relocating`].
    pub fn track<R: Rig, C: FtCalibration + Clone, Q: ReachCheck>(
        &self,
        rig: &mut R,
        feedback: &FtFeedback<C>,
        reach: &mut Q,
        waypoints: &[Vector6<f64>],
        observe: impl FnMut(&R, &Rest<'_>),
    ) -> Result<Tracked, ControlError> {
        self.track_relocating(rig, feedback, reach, None, waypoints, observe)
    }

    /// As [`PathTracker::track`], with `relocate` (at most once an attempt) bringing a goal,
    /// or a leg's start, that is out of the arms' reach back into it. The last leg rests
    /// [`TrackingPolicy::goal_rest_samples`] samples, the others `feedback`'s.
    ///
    /// # Errors
    /// [`ControlError::EmptyPath`] for no waypoints; bad settings in the policy; a rig that
    /// cannot report its poses for a relocation; the errors of `relocate`. Everything else is
    /// in [`Tracked::end`].
    pub fn track_relocating<R: Rig, C: FtCalibration + Clone, Q: ReachCheck>(
        &self,
        rig: &mut R,
        feedback: &FtFeedback<C>,
        reach: &mut Q,
        relocate: Option<&mut dyn Relocate<Q>>,
        waypoints: &[Vector6<f64>],
        mut observe: impl FnMut(&R, &Rest<'_>),
    ) -> Result<Tracked, ControlError> {
        let Some(first) = waypoints.first() else {
            return Err(ControlError::EmptyPath);
        };
        let controllers = self.controllers()?;
        // One observer follows the sensor from its tare over every leg.
        let bias = self
            .bias
            .map(|settings| BiasObserver::new(self.model.clone(), settings))
            .transpose()?;
        let end_feedback =
            FtFeedback::new(feedback.pipeline().clone(), self.policy.goal_rest_samples);
        let mut pass = Pass {
            tracker: self,
            controllers: &controllers,
            rig,
            reach,
            relocate,
            bias,
            waypoints,
            observe: &mut observe,
            tracked: Tracked {
                end: None,
                moves: 0,
                completed: false,
                detected: false,
                retreats: 0,
                undone: 0,
                skipped: 0,
                relocated: false,
                legs: Vec::new(),
                scored: Vec::new(),
                residuals: Vec::new(),
                last_estimate: *first,
            },
            i: 1,
            skipped_last: None,
            undone_at: None,
            leg_start: None,
            retreated_on: None,
        };
        (pass.observe)(
            pass.rig,
            &Rest {
                kind: RestKind::Start,
                leg: 0,
                waypoint: 0,
                step: None,
            },
        );
        while pass.i < waypoints.len() {
            let flow = pass.leg(feedback, &end_feedback)?;
            match flow {
                Flow::Next => pass.i += 1,
                Flow::Again => {}
                Flow::Stop => break,
            }
        }
        Ok(pass.tracked)
    }

    /// The controllers of the legs. Between waypoints the stop of
    /// [`TrackingPolicy::through`]; the goal's of [`TrackingPolicy::goal`]. A leg run again
    /// after an undo, and the late part of a leg's budget: no tighter than
    /// [`TrackingPolicy::rerun_shape_stop`].
    fn controllers(&self) -> Result<Controllers<M>, ControlError> {
        let p = &self.policy;
        let rerun_stop = p.rerun_shape_stop(p.shape_stop);
        let through = ControlParams {
            gain: p.gain,
            shape_tolerance: p.shape_stop,
            late_shape_tolerance: rerun_stop,
            late_after: p.late_after(p.through.max_iterations),
            ..p.through
        };
        let end = ControlParams {
            gain: p.gain,
            shape_tolerance: p.shape_stop,
            ..p.goal
        };
        let build = |settings| {
            let controller = Controller::new(self.model.clone(), settings)?;
            Ok::<_, ControlError>(match self.detector {
                Some(d) => controller.with_detector(d),
                None => controller,
            })
        };
        let near = ControlParams {
            shape_tolerance: p.near_shape_stop,
            ..through
        };
        let close = build(near)?;
        let rerun = |settings: ControlParams| {
            build(ControlParams {
                shape_tolerance: settings.shape_tolerance.max(rerun_stop),
                ..settings
            })
        };
        let (through_again, close_again, end_again) = (rerun(through)?, rerun(near)?, rerun(end)?);
        Ok(Controllers {
            through: build(through)?,
            close,
            end: build(end)?,
            through_again,
            close_again,
            end_again,
        })
    }
}

/// What the loop does after a leg.
enum Flow {
    /// On to the next waypoint.
    Next,
    /// Run the leg to waypoint `Pass::i` (set by the leg) again.
    Again,
    /// The attempt ends.
    Stop,
}

/// What a relocation did.
enum Relocated {
    /// Both grippers moved; the new base pose (world frame).
    Moved(Pose),
    /// No translation brings the poses back into the arms' reach; nothing moved.
    NoneFound,
    /// The rig refused the move: its message.
    Refused(String),
}

/// One attempt along the path: its state between legs.
struct Pass<'a, 'r, M, R, Q: ReachCheck, O> {
    tracker: &'a PathTracker<M>,
    controllers: &'a Controllers<M>,
    rig: &'a mut R,
    reach: &'a mut Q,
    relocate: Option<&'a mut (dyn Relocate<Q> + 'r)>,
    bias: Option<BiasObserver<M>>,
    waypoints: &'a [Vector6<f64>],
    observe: &'a mut O,
    tracked: Tracked,
    /// The waypoint of the leg to run.
    i: usize,
    /// The last waypoint passed over.
    skipped_last: Option<usize>,
    /// The waypoint whose leg was last undone: its reruns take the rerun stop.
    undone_at: Option<usize>,
    /// The leg in progress and the pose its first run started from.
    leg_start: Option<(usize, Pose)>,
    /// The leg of the last retreat ([`TrackingPolicy::escalates`]).
    retreated_on: Option<usize>,
}

impl<M: WireModel, R: Rig, Q: ReachCheck, O: FnMut(&R, &Rest<'_>)> Pass<'_, '_, M, R, Q, O> {
    /// Runs the leg to waypoint `i` and decides what comes next.
    fn leg<C: FtCalibration>(
        &mut self,
        feedback: &FtFeedback<C>,
        end_feedback: &FtFeedback<C>,
    ) -> Result<Flow, ControlError> {
        let i = self.i;
        let waypoints = self.waypoints;
        let Some(waypoint) = waypoints.get(i) else {
            return Ok(Flow::Stop);
        };
        let final_leg = i + 1 == waypoints.len();
        let again = self.undone_at == Some(i);
        let near = self.tracker.is_near(i) || self.tracker.is_near(i - 1);
        let c = self.controllers;
        let (controller, feedback) = match (final_leg, near, again) {
            (true, _, false) => (&c.end, end_feedback),
            (true, _, true) => (&c.end_again, end_feedback),
            (false, true, false) => (&c.close, feedback),
            (false, true, true) => (&c.close_again, feedback),
            (false, false, false) => (&c.through, feedback),
            (false, false, true) => (&c.through_again, feedback),
        };
        let leg = self.tracked.legs.len();
        let observe = &mut *self.observe;
        let run = controller.run_with_bias_observer(
            &mut *self.rig,
            feedback,
            &mut *self.reach,
            waypoint,
            self.bias.as_mut(),
            |rig, step| {
                observe(
                    rig,
                    &Rest {
                        kind: RestKind::Step,
                        leg,
                        waypoint: i,
                        step: Some(step),
                    },
                );
            },
        );
        let run = match run {
            Ok(run) => run,
            Err(e @ ControlError::UnreachableStart { .. }) => {
                return self.unreachable_start(e, waypoint);
            }
            Err(e) => {
                return Ok(self.stop(TrackEnd::Refused {
                    waypoint: i,
                    reason: e.to_string(),
                }));
            }
        };
        let first_start = match self.leg_start {
            Some((leg, pose)) if leg == i => pose,
            _ => run.start_tip,
        };
        self.leg_start = Some((i, first_start));
        self.record(&run, leg);
        self.after(&run, first_start, final_leg)
    }

    /// Records the leg that ran and tells the observer.
    fn record(&mut self, run: &Run, leg: usize) {
        let t = &mut self.tracked;
        t.last_estimate = run.steps.last().map_or(run.start_estimate, |s| s.estimate);
        t.moves += run.steps.len();
        t.residuals.extend(run.steps.iter().map(|s| s.residual));
        t.legs.push(TrackedLeg {
            waypoint: self.i,
            moves: run.steps.len(),
            outcome: run.outcome.clone(),
            scored: true,
        });
        t.scored.push(leg);
        t.end = Some(TrackEnd::Leg(run.outcome.clone()));
        (self.observe)(
            self.rig,
            &Rest {
                kind: RestKind::LegEnd,
                leg,
                waypoint: self.i,
                step: None,
            },
        );
    }

    /// What follows a leg that ran to its end `run.outcome`.
    fn after(
        &mut self,
        run: &Run,
        first_start: Pose,
        final_leg: bool,
    ) -> Result<Flow, ControlError> {
        let tracker = self.tracker;
        let policy = &tracker.policy;
        let i = self.i;
        match &run.outcome {
            Outcome::Reached { .. } | Outcome::IterationLimit { .. } => {
                self.tracked.completed = final_leg;
            }
            Outcome::CollisionDetected { .. } => {
                self.tracked.detected = true;
                // A second detection on a leg already retreated on: back to where the leg
                // first started instead.
                if policy.escalates(self.retreated_on == Some(i))
                    && self.tracked.undone < policy.max_undos
                {
                    return Ok(match self.undo(first_start, i) {
                        Ok(()) => {
                            self.retreated_on = None;
                            Flow::Again
                        }
                        Err(e) => self.stop(e),
                    });
                }
                if self.tracked.retreats >= policy.max_retreats {
                    return Ok(Flow::Stop);
                }
                // Retreat: back to the pose before the flagged move, then the same leg again
                // with a fresh detector window.
                if let Err(message) = step_back(&mut *self.rig, run) {
                    return Ok(self.stop(TrackEnd::RetreatFailed { message }));
                }
                self.tracked.retreats += 1;
                self.retreated_on = Some(i);
                self.unscore_last_leg();
                self.extra_move(RestKind::Retreat);
                return Ok(Flow::Again);
            }
            // A leg thrown far from its waypoint, a rest with no usable measurement, or (under
            // fresh noise) a waypoint out of reach: back to where the leg started, then again.
            outcome if policy.undoes(outcome) && self.tracked.undone < policy.max_undos => {
                return Ok(match self.undo(run.start_tip, i) {
                    Ok(()) => Flow::Again,
                    Err(e) => self.stop(e),
                });
            }
            // The goal out of the arms' reach: one translation of both grippers (the wire's
            // configuration unchanged) that brings it back, then the leg again.
            Outcome::Unreachable { .. }
                if final_leg && self.relocate.is_some() && !self.tracked.relocated =>
            {
                let goal = self.waypoints.get(i).copied().unwrap_or_default();
                return Ok(match self.relocate_toward(&goal)? {
                    Relocated::Moved(base) => {
                        self.moved_to(&base)?;
                        self.unscore_last_leg();
                        self.extra_move(RestKind::Relocation);
                        Flow::Again
                    }
                    // No translation found: the end stays the controller's.
                    Relocated::NoneFound => Flow::Stop,
                    Relocated::Refused(message) => {
                        self.stop(TrackEnd::RelocationFailed { message })
                    }
                });
            }
            // An intermediate waypoint out of reach is passed over once: the leg to the next
            // one starts from where the wire is; a second in a row ends the attempt.
            Outcome::Unreachable { .. } if may_pass_over(i, final_leg, self.skipped_last) => {
                self.unscore_last_leg();
                self.tracked.skipped += 1;
                self.skipped_last = Some(i);
            }
            _ => return Ok(Flow::Stop),
        }
        Ok(Flow::Next)
    }

    /// The leg to `waypoint` was refused because its start is out of the arms' reach (the
    /// accumulated noise carried the gripper there): one relocation that brings it and the
    /// waypoint back, or, under fresh noise, back to where the last leg run first started
    /// ([`TrackingPolicy::undoes_to_last_start`]); else the attempt ends.
    fn unreachable_start(
        &mut self,
        error: ControlError,
        waypoint: &Vector6<f64>,
    ) -> Result<Flow, ControlError> {
        let i = self.i;
        let tracker = self.tracker;
        let policy = &tracker.policy;
        let undone = self.tracked.undone;
        let previous = self
            .leg_start
            .filter(|(leg, _)| policy.undoes_to_last_start(Some(*leg), i, undone));
        if self.relocate.is_some() && !self.tracked.relocated {
            match self.relocate_toward(waypoint)? {
                Relocated::Moved(base) => {
                    self.moved_to(&base)?;
                    // The leg never ran: the last score is the waypoint before's.
                    self.extra_move(RestKind::Relocation);
                    return Ok(Flow::Again);
                }
                Relocated::NoneFound if previous.is_none() => {
                    return Ok(self.stop(TrackEnd::StartOutOfReach { waypoint: i }));
                }
                Relocated::NoneFound => {}
                Relocated::Refused(message) => {
                    return Ok(self.stop(TrackEnd::RelocationFailed { message }));
                }
            }
        }
        let Some((leg, pose)) = previous else {
            return Ok(self.stop(TrackEnd::Refused {
                waypoint: i,
                reason: error.to_string(),
            }));
        };
        self.i = leg;
        Ok(match self.undo(pose, leg) {
            Ok(()) => Flow::Again,
            Err(e) => self.stop(e),
        })
    }

    /// Ends the attempt with `end`.
    fn stop(&mut self, end: TrackEnd) -> Flow {
        self.tracked.end = Some(end);
        Flow::Stop
    }

    /// Moves both grippers by the relocation from the wire measured at the last estimate
    /// toward `a_goal`.
    fn relocate_toward(&mut self, a_goal: &Vector6<f64>) -> Result<Relocated, ControlError> {
        let Some(hook) = self.relocate.as_deref_mut() else {
            return Ok(Relocated::NoneFound);
        };
        let poses = self.rig.gripper_poses().map_err(|e| ControlError::Rig {
            message: e.to_string(),
        })?;
        let Some(base) = hook.relocation(&poses, &self.tracked.last_estimate, a_goal)? else {
            return Ok(Relocated::NoneFound);
        };
        let command = Command {
            base,
            tip: base * poses.relative(),
        };
        Ok(match self.rig.command(&command) {
            Ok(()) => Relocated::Moved(base),
            Err(e) => Relocated::Refused(e.to_string()),
        })
    }

    /// After a relocation to `base`: the reach check from there, the relocation spent.
    fn moved_to(&mut self, base: &Pose) -> Result<(), ControlError> {
        if let Some(hook) = self.relocate.as_deref_mut() {
            *self.reach = hook.reach_from(base)?;
        }
        self.tracked.relocated = true;
        Ok(())
    }

    /// Undoes a leg: the second gripper back to `start`, a pose a run of it started from (one
    /// the arms held; relative to the base gripper), the last leg unscored, and the leg to
    /// waypoint `leg` marked for its rerun stop.
    fn undo(&mut self, start: Pose, leg: usize) -> Result<(), TrackEnd> {
        let failed = |e: &dyn std::fmt::Display| TrackEnd::UndoFailed {
            message: e.to_string(),
        };
        let base = self.rig.gripper_poses().map_err(|e| failed(&e))?.base;
        self.rig.move_tip(base * start).map_err(|e| failed(&e))?;
        self.tracked.undone += 1;
        self.unscore_last_leg();
        self.extra_move(RestKind::Undo);
        self.undone_at = Some(leg);
        Ok(())
    }

    /// Drops the score of the last leg recorded: its waypoint was not reached (the rerun is
    /// scored) or is passed over.
    fn unscore_last_leg(&mut self) {
        self.tracked.scored.pop();
        if let Some(leg) = self.tracked.legs.last_mut() {
            leg.scored = false;
        }
    }

    /// Counts a move made outside a controller run (a retreat, an undo, a relocation) and
    /// tells the observer.
    fn extra_move(&mut self, kind: RestKind) {
        self.tracked.moves += 1;
        (self.observe)(
            self.rig,
            &Rest {
                kind,
                leg: self.tracked.legs.len(),
                waypoint: self.i,
                step: None,
            },
        );
    }
}

/// Moves the second gripper back to where it was before the last move of `run` (the one the
/// collision detector flagged): the pose the robot reported after the move before it, or the
/// run's start. The message says why the move failed.
fn step_back<R: Rig>(rig: &mut R, run: &Run) -> Result<(), String> {
    let Some((_, before)) = run.steps.split_last() else {
        return Ok(());
    };
    let back = before.last().map_or(run.start_tip, |s| s.tip);
    let base = rig.gripper_poses().map_err(|e| e.to_string())?.base;
    rig.move_tip(base * back).map_err(|e| e.to_string())
}

/// Whether the closed loop may pass over waypoint `i` (1-based leg), out of the arms' reach:
/// not the goal, and not right after passing over the one before.
fn may_pass_over(i: usize, final_leg: bool, skipped_last: Option<usize>) -> bool {
    !final_leg && (skipped_last.is_none() || skipped_last != i.checked_sub(1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unreachable_waypoint_is_passed_over_once_in_a_row_and_never_the_goal() {
        assert!(may_pass_over(3, false, None));
        assert!(
            !may_pass_over(4, false, Some(3)),
            "two in a row end the attempt"
        );
        assert!(may_pass_over(5, false, Some(3)));
        assert!(
            !may_pass_over(12, true, None),
            "the goal is never passed over"
        );
        assert!(may_pass_over(1, false, None));
    }

    #[test]
    fn the_ends_read_as_the_summaries_name_them() {
        assert_eq!(
            TrackEnd::Leg(Outcome::Reached { error: 0.01 }).to_string(),
            "reached"
        );
        assert_eq!(
            TrackEnd::Refused {
                waypoint: 3,
                reason: "x".into()
            }
            .to_string(),
            "refused at waypoint 3: x"
        );
        assert!(
            TrackEnd::StartOutOfReach { waypoint: 2 }
                .to_string()
                .contains("no translation of both grippers")
        );
    }
}
