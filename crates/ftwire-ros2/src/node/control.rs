//! `ftwire ros2 control`: steers the held wire to a goal configuration, or along a planned
//! path, by the library's closed loop ([`ftwire_control::PathTracker`], the tracker of
//! `ftwire experiment track`, and its Jacobian controller of eq. 13–14) on a robot that speaks
//! ROS 2, through [`super::ros_rig`].
//!
//! After the tare ([`super::robot`]), the goals are the tracker's legs, each run by the
//! controller:
//!
//! 1. **measure**: each rest's window of raw samples through the library's pipeline (the
//!    tare, then the node's raw map) to `ã`; the rig publishes the model's shape at it on
//!    [`SHAPE_TOPIC`] and, with `contact_miss`, compares the model's tip `Γ(ã)` with the
//!    reported tip pose, as `ftwire ros2 estimate` does: a free wire's shape ends at the
//!    gripper, so a miss above `contact_miss` is a contact, and the run stops there
//!    (`contact`);
//! 2. **stop rule**: `‖a_g − ã‖` in normalised units (torque in `c2/L`, force in `c2/L²`);
//!    within `epsilon` of the goal the run ends (`reached`). With waypoints (a planned path),
//!    the leg to each waypoint before the goal ends within `waypoint_epsilon`, and the next
//!    leg starts with a rest of its own at the same pose;
//! 3. **step**: `δb = K J(L; ã)(a_g − ã)`, limited and guarded for stability
//!    ([`ftwire_control::Controller`]), `b_{i+1} = b_i M(δb)` from the reported pose `b_i`,
//!    sent on `/wire/tip_target` and waited for. A step the guard refuses ends the run
//!    (`unstable_step`), a target not reached within the timeout too (`unreached`), and so
//!    does the step budget over the whole path (`max_steps`: the move after `max_steps` is
//!    refused, so that the rest after the last step is still checked against the goal).
//!
//! With `truth_topic` (a simulator's `/wire/truth`), the last true centreline is compared with
//! the goal's model shape `Φ(a_g)`: the mean and largest distance of its nodes to it.

use std::sync::atomic::AtomicBool;

use ftwire_app::config::wire::WireSpec;
use ftwire_control::tracking::{PolicyError, PolicySettings};
use ftwire_control::{
    AnyPose, ControlParams, Controller, FtFeedback, NoiseModel, Outcome, PathTracker, Rest,
    RestKind, TrackEnd, Tracked, TrackedLeg, TrackingPolicy,
};
use ftwire_estimate::shape::marker_distances;
use ftwire_estimate::{KirchhoffModel, WireModel};
use nalgebra::Vector6;
use serde::Serialize;

use super::robot::{Robot, RobotCounts, RobotParams};
use super::ros_rig::{RigSettings, RosRig, SHAPE_NODES};
use super::{Log, NodeError, NodeSettings, SHAPE_TOPIC, reliable};
use crate::msg::Path;
use crate::node::check_contact_miss;

/// What the control node does.
#[derive(Debug, Clone)]
pub struct ControlNodeParams {
    /// The sensor, the moves and the topics.
    pub robot: RobotParams,
    /// The wire the controller's model is of.
    pub wire: WireSpec,
    /// Gravity in the base clamp frame \[m/s²\]: the controller's model is the loaded rod,
    /// with the wire's weight; `None`: the weight-free model.
    pub gravity_in_clamp: Option<[f64; 3]>,
    /// The goals in order, the last the goal (the ones before it waypoints of a path); each
    /// `a` \[N·m, N\], torque first, base clamp frame.
    pub goals: Vec<Vector6<f64>>,
    /// The controller's settings: gain, `epsilon` (the goal's stop), step limits.
    pub control: ControlParams,
    /// A waypoint is passed within this normalised distance (default 0.2).
    pub waypoint_epsilon: f64,
    /// Most steps (default 100).
    pub max_steps: usize,
    /// A tip miss above this is a contact \[m\]; `None`: no contact check.
    pub contact_miss: Option<f64>,
}

/// The last true centreline against the goal's model shape.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TruthToGoal {
    /// Mean distance of the true nodes to `Φ(a_g)` \[mm\].
    pub mean_mm: f64,
    /// Largest \[mm\].
    pub max_mm: f64,
}

/// The end of a run: one JSON line.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ControlSummary {
    /// `"control"`.
    pub node: &'static str,
    /// What the robot side counted.
    #[serde(flatten)]
    pub counts: RobotCounts,
    /// How the run ended: `reached`, `contact`, `max_steps`, `unstable_step`, `unreached`,
    /// `no_model` (the model has no answer at the measured `ã`) or `stopped`; rarely, an end
    /// of the tracker's own: `sensor_fault` (a rest without a finite `ã`), `refused` (a goal
    /// the controller refused before moving), `command_failed`.
    pub outcome: &'static str,
    /// Steps sent (and reached).
    pub steps: usize,
    /// Goals passed (waypoints, and the goal when reached).
    pub passed: usize,
    /// The tracker's legs as they ran: each leg's waypoint (1: the first goal), moves and
    /// controller outcome.
    pub legs: Vec<TrackedLeg>,
    /// The goal \[N·m, N\].
    pub goal: [f64; 6],
    /// The last measured `ã` \[N·m, N\].
    pub final_a: Option<[f64; 6]>,
    /// `‖a_g − ã‖` \[normalised\] at each rest, to the goal then steered to.
    pub errors: Vec<f64>,
    /// The last rest's `‖a_g − ã‖` to the final goal \[normalised\].
    pub final_error: Option<f64>,
    /// The last rest's miss of the model's tip from the reported one \[mm\].
    pub tip_miss_mm: Option<f64>,
    /// With `truth_topic`: the last true centreline against `Φ(a_g)`.
    pub truth: Option<TruthToGoal>,
}

impl ControlNodeParams {
    fn validate(&self) -> Result<(), NodeError> {
        if self.goals.is_empty() {
            return Err(NodeError::BadSetting {
                setting: "--goal",
                value: "none".to_owned(),
                allowed: "a goal configuration (--goal or --scene)",
            });
        }
        if !(1..=100_000).contains(&self.max_steps) {
            return Err(NodeError::BadSetting {
                setting: "--max-steps",
                value: self.max_steps.to_string(),
                allowed: "1 to 100000 steps",
            });
        }
        check_contact_miss(self.contact_miss)
    }

    /// The model, and the tracking policy: the tuned policy of a robot without execution
    /// noise (`TrackingPolicy::with_settings`, which checks the gain) with the goal's and the
    /// waypoints' stops, the step limits, each leg's budget of `max_steps + 1` (the node's
    /// rig refuses the move after `max_steps` over the whole path) and `rest_samples` at every
    /// rest. Each leg's controller is built once here, so that a bad setting or a goal outside
    /// `A_stable` is refused before anything moves.
    fn tracking(&self) -> Result<(KirchhoffModel, TrackingPolicy), NodeError> {
        self.validate()?;
        let gravity = ftwire_logs::model_gravity(&self.robot.map, self.gravity_in_clamp)?;
        let model = ftwire_logs::shape::wire_model(&self.wire, gravity).map_err(|e| {
            NodeError::BadSetting {
                setting: "--wire or --gravity-in-clamp",
                value: format!("{} ({e})", self.wire.name),
                allowed: "a wire with valid parameters, gravity of norm in (0, 100] m/s²",
            }
        })?;
        let settings = PolicySettings {
            gain: Some(self.control.gain),
            waypoint_moves: Some(self.max_steps + 1),
            ..PolicySettings::default()
        };
        let mut policy =
            TrackingPolicy::with_settings(NoiseModel::None, &settings).map_err(|e| match e {
                PolicyError::Gain(gain) => NodeError::BadSetting {
                    setting: "--gain",
                    value: gain.to_string(),
                    allowed: "a gain K in (0, 1]",
                },
                e => NodeError::Incomplete(format!("the tracking policy: {e}")),
            })?;
        policy.goal = ControlParams {
            max_iterations: self.max_steps + 1,
            ..self.control
        };
        policy.through = ControlParams {
            epsilon: self.waypoint_epsilon,
            ..policy.goal
        };
        policy.goal_rest_samples = self.robot.rest_samples;
        let legs = [
            (policy.goal, "--epsilon, --max-step-mm or --max-step-deg"),
            (policy.through, "--waypoint-epsilon"),
        ];
        for (leg, setting) in legs {
            let controller = Controller::new(
                model,
                ControlParams {
                    gain: policy.gain,
                    ..leg
                },
            )
            .map_err(|e| NodeError::BadSetting {
                setting,
                value: e.to_string(),
                allowed: "positive stops and step limits",
            })?;
            for goal in &self.goals {
                controller
                    .check_goal(goal)
                    .map_err(|e| NodeError::BadSetting {
                        setting: "--goal",
                        value: format!("{:?} ({e})", goal.as_slice()),
                        allowed: "a configuration in the model's A_stable",
                    })?;
            }
        }
        Ok((model, policy))
    }
}

/// The last true centreline against the goal's model shape.
fn truth_to_goal(
    robot: &Robot,
    model: &KirchhoffModel,
    goal: &Vector6<f64>,
) -> Option<TruthToGoal> {
    let truth = robot.truth()?;
    let shape = model.shape(goal, SHAPE_NODES).ok()?.positions;
    let d = marker_distances(truth, &shape).ok()?;
    if d.is_empty() {
        return None;
    }
    #[allow(clippy::cast_precision_loss)] // a few hundred nodes
    let mean_mm = 1e3 * d.iter().sum::<f64>() / d.len() as f64;
    let max_mm = 1e3 * d.iter().fold(0.0_f64, |m, v| m.max(*v));
    Some(TruthToGoal { mean_mm, max_mm })
}

/// `‖a_g − a‖` in normalised units.
fn distance(model: &KirchhoffModel, a: &Vector6<f64>, goal: &Vector6<f64>) -> f64 {
    ftwire_rod::to_normalised(model.wire(), &(goal - a)).norm()
}

/// Runs the closed loop (module docs) until it ends, `settings.duration` ends or `stop` is set.
///
/// # Errors
/// [`NodeError`] for bad settings (a goal outside `A_stable` among them), ROS 2 entities
/// that cannot be created or a middleware that fails. How the loop ended is the summary's
/// `outcome`, not an error.
pub fn run(
    params: &ControlNodeParams,
    settings: NodeSettings,
    stop: &AtomicBool,
    log: Log<'_>,
) -> Result<ControlSummary, NodeError> {
    settings.validate()?;
    let (model, policy) = params.tracking()?;
    let last = params.goals.len() - 1;
    let goal = params.goals[last];
    let mut robot = Robot::new(
        "ftwire_control",
        &params.robot,
        settings.domain_id,
        settings.duration,
    )?;
    let shape_pub = robot.node().publisher::<Path>(SHAPE_TOPIC, &reliable(10))?;
    log(&format!(
        "control: domain {}; subscribed to {} and {}; publishing {} and {SHAPE_TOPIC}; goal {:?} \
         after {last} waypoints; gain {}, ε {}, at most {} steps",
        settings.domain_id,
        params.robot.wrench_topic,
        params.robot.tip_pose_topic,
        params.robot.target_topic,
        goal.as_slice(),
        params.control.gain,
        params.control.epsilon,
        params.max_steps
    ));
    let mut summary = ControlSummary {
        node: "control",
        counts: RobotCounts::default(),
        outcome: "stopped",
        steps: 0,
        passed: 0,
        legs: Vec::new(),
        goal: goal.into(),
        final_a: None,
        errors: Vec::new(),
        final_error: None,
        tip_miss_mm: None,
        truth: None,
    };
    if robot.wait_ready(stop)?.is_ok() {
        let rig_settings = RigSettings {
            model,
            contact_miss: params.contact_miss,
            budget: params.max_steps,
            move_timeout: params.robot.move_timeout,
            shape_pub,
            stop,
        };
        let mut rig = RosRig::new(robot, params.robot.rest_samples, rig_settings)?;
        let tracker = PathTracker::new(model, policy);
        let tracked = track(&tracker, &model, &mut rig, &params.goals, log, &mut summary);
        if let Some(e) = rig.take_fatal() {
            return Err(e);
        }
        let tracked = tracked.map_err(|e| NodeError::Incomplete(format!("tracking: {e}")))?;
        if let Some(end) = rig.end() {
            log(&format!("control: {end}"));
        }
        summary.outcome = outcome(rig.end(), &tracked);
        summary.steps = tracked.moves;
        summary.passed = tracked
            .legs
            .iter()
            .filter(|l| l.scored && matches!(l.outcome, Outcome::Reached { .. }))
            .count();
        summary.legs = tracked.legs;
        if let Some(rest) = rig.rests().last() {
            summary.final_a = Some(rest.a.into());
            summary.final_error = Some(distance(&model, &rest.a, &goal));
            summary.tip_miss_mm = rest.tip_miss.map(|m| 1e3 * m);
        }
        robot = rig.into_robot();
    }
    summary.truth = truth_to_goal(&robot, &model, &goal);
    summary.counts = robot.finish_counts();
    log(&format!(
        "control: {} after {} steps; final error {:.4} (normalised)",
        summary.outcome,
        summary.steps,
        summary.final_error.unwrap_or(f64::NAN)
    ));
    Ok(summary)
}

/// The goals tracked on `rig`; each rest's error, to the goal then steered to, into
/// `summary.errors`.
fn track(
    tracker: &PathTracker<KirchhoffModel>,
    model: &KirchhoffModel,
    rig: &mut RosRig<'_>,
    goals: &[Vector6<f64>],
    log: Log<'_>,
    summary: &mut ControlSummary,
) -> Result<Tracked, ftwire_control::ControlError> {
    let feedback = FtFeedback::new(rig.pipeline().clone(), tracker.policy().goal_rest_samples);
    // Waypoint 0 is where the wire is: the tracker reads it only as its estimate before the
    // first leg, whose first rest measures the wire.
    let waypoints: Vec<Vector6<f64>> = std::iter::once(goals[0])
        .chain(goals.iter().copied())
        .collect();
    let errors = &mut summary.errors;
    // Each rest the rig measured belongs to the leg whose step or end is reported next.
    let mut tag = |rig: &RosRig<'_>, goal: usize| {
        for rest in &rig.rests()[errors.len()..] {
            let error = distance(model, &rest.a, &goals[goal]);
            log(&format!(
                "control: rest {}: error {error:.4} to goal {goal}",
                errors.len()
            ));
            errors.push(error);
        }
    };
    let tracked = tracker.track(
        rig,
        &feedback,
        &mut AnyPose,
        &waypoints,
        |rig: &RosRig<'_>, rest: &Rest<'_>| {
            if matches!(rest.kind, RestKind::Step | RestKind::LegEnd) {
                tag(rig, rest.waypoint.saturating_sub(1).min(goals.len() - 1));
            }
        },
    );
    let steered = tracked
        .as_ref()
        .ok()
        .and_then(|t| t.legs.last())
        .map_or(0, |leg| leg.waypoint.saturating_sub(1).min(goals.len() - 1));
    tag(rig, steered);
    tracked
}

/// The summary's outcome: the rig's end, else the tracker's.
fn outcome(rig_end: Option<&super::ros_rig::RosRigError>, tracked: &Tracked) -> &'static str {
    if let Some(end) = rig_end {
        return end.outcome();
    }
    match &tracked.end {
        Some(TrackEnd::Leg(leg)) => match leg {
            Outcome::IterationLimit { .. } => "max_steps",
            Outcome::PredictedInstability { .. } => "unstable_step",
            Outcome::ModelFailed { .. } => "no_model",
            other => other.name(),
        },
        Some(TrackEnd::Refused { .. } | TrackEnd::StartOutOfReach { .. }) => "refused",
        Some(_) => "command_failed",
        None => "reached",
    }
}
