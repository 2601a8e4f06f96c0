//! `ftwire ros2 control`: steers the held wire to a goal configuration by the closed loop of
//! the paper's Jacobian controller (`ftwire_control::Controller`, eq. 13–14), on a robot that
//! speaks ROS 2.
//!
//! After the tare ([`super::robot`]), at each rest:
//!
//! 1. **measure**: the wrench averaged over the rest, mapped to `ã` ([`super::robot`]);
//! 2. **shape and contact**: the model's centreline at `ã` is published as `nav_msgs/Path` on
//!    [`SHAPE_TOPIC`]; with `contact_miss`, the model's tip `Γ(ã)` is compared with the
//!    reported tip pose, as `ftwire ros2 estimate` does: a free wire's shape ends at the
//!    gripper, so a miss above `contact_miss` is a force the model does not have, a contact,
//!    and the run stops there (`contact`);
//! 3. **stop rule**: `‖a_g − ã‖` in normalised units (torque in `c2/L`, force in `c2/L²`);
//!    within `epsilon` of the goal the run ends (`reached`). With waypoints (a planned path),
//!    each intermediate goal is passed once within `waypoint_epsilon`, and the next is steered
//!    to from the same rest;
//! 4. **step**: `δb = K J(L; ã)(a_g − ã)`, limited and guarded for stability
//!    ([`ftwire_control::Controller::plan_step`]), and `b_{i+1} = b_i M(δb)` from the reported
//!    pose `b_i`; `b_{i+1}` is sent on `/wire/tip_target` and waited for. A step the guard
//!    refuses ends the run (`unstable_step`), a target not reached within the timeout too
//!    (`unreached`), and so does the step budget (`max_steps`).
//!
//! With `truth_topic` (a simulator's `/wire/truth`), the last true centreline is compared with
//! the goal's model shape `Φ(a_g)`: the mean and largest distance of its nodes to it.

use std::sync::atomic::AtomicBool;

use ftwire_app::config::wire::WireSpec;
use ftwire_control::{ControlParams, Controller};
use ftwire_estimate::shape::marker_distances;
use ftwire_estimate::{KirchhoffModel, WireModel};
use nalgebra::{Vector3, Vector6};
use ros2_client::Publisher;
use serde::Serialize;

use super::robot::{Halt, Robot, RobotCounts, RobotParams};
use super::{BASE_FRAME, Log, NodeError, NodeSettings, SHAPE_TOPIC, header, publish, reliable};
use crate::msg::Path;
use crate::node::pose::ros_point;
use crate::node::{check_contact_miss, path_message};

/// Nodes of the published shapes.
const SHAPE_NODES: usize = 64;

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
    /// `no_model` (the model has no answer at the measured `ã`) or `stopped`.
    pub outcome: &'static str,
    /// Steps sent.
    pub steps: usize,
    /// Goals passed (waypoints, and the goal when reached).
    pub passed: usize,
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
        if !(self.waypoint_epsilon.is_finite() && self.waypoint_epsilon > 0.0) {
            return Err(NodeError::BadSetting {
                setting: "--waypoint-epsilon",
                value: self.waypoint_epsilon.to_string(),
                allowed: "a positive normalised distance",
            });
        }
        if !(1..=100_000).contains(&self.max_steps) {
            return Err(NodeError::BadSetting {
                setting: "--max-steps",
                value: self.max_steps.to_string(),
                allowed: "1 to 100000 steps",
            });
        }
        check_contact_miss(self.contact_miss)?;
        Ok(())
    }

    /// The controller, with every goal checked.
    fn controller(&self) -> Result<Controller<KirchhoffModel>, NodeError> {
        self.validate()?;
        let gravity = ftwire_logs::model_gravity(&self.robot.map, self.gravity_in_clamp)?;
        let model = ftwire_logs::shape::wire_model(&self.wire, gravity).map_err(|e| {
            NodeError::BadSetting {
                setting: "--wire or --gravity-in-clamp",
                value: format!("{} ({e})", self.wire.name),
                allowed: "a wire with valid parameters, gravity of norm in (0, 100] m/s²",
            }
        })?;
        let controller =
            Controller::new(model, self.control).map_err(|e| NodeError::BadSetting {
                setting: "--gain, --epsilon, --max-step-mm or --max-step-deg",
                value: e.to_string(),
                allowed: "a gain in (0, 1], positive ε and step limits",
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
        Ok(controller)
    }
}

/// The model's shape at `a`, published; returns its nodes.
fn publish_shape(
    model: &KirchhoffModel,
    a: &Vector6<f64>,
    stamp: f64,
    shape_pub: &Publisher<Path>,
    counts: &mut RobotCounts,
) -> Option<Vec<Vector3<f64>>> {
    let nodes = model.shape(a, SHAPE_NODES).ok()?.positions;
    let path = path_message(header(stamp, BASE_FRAME), nodes.iter().map(ros_point));
    publish(
        shape_pub,
        path,
        "shape",
        &mut counts.published,
        &mut counts.publish_failed,
    );
    Some(nodes)
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

/// Runs the closed loop (module docs) until it ends, `settings.duration` ends or `stop` is set.
///
/// # Errors
/// [`NodeError`] for bad settings (a goal outside `A_stable` among them) or ROS 2 entities
/// that cannot be created. How the loop ended is the summary's `outcome`, not an error.
pub fn run(
    params: &ControlNodeParams,
    settings: NodeSettings,
    stop: &AtomicBool,
    log: Log<'_>,
) -> Result<ControlSummary, NodeError> {
    settings.validate()?;
    let controller = params.controller()?;
    let model = *controller.model();
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
        goal: goal.into(),
        final_a: None,
        errors: Vec::new(),
        final_error: None,
        tip_miss_mm: None,
        truth: None,
    };
    if robot.wait_ready(stop)?.is_ok() {
        summary.outcome = steer(
            params,
            &controller,
            &mut robot,
            &shape_pub,
            stop,
            log,
            &mut summary,
        )?;
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

/// The loop of rests and steps; returns the outcome.
fn steer(
    params: &ControlNodeParams,
    controller: &Controller<KirchhoffModel>,
    robot: &mut Robot,
    shape_pub: &Publisher<Path>,
    stop: &AtomicBool,
    log: Log<'_>,
    summary: &mut ControlSummary,
) -> Result<&'static str, NodeError> {
    let model = controller.model();
    let last = params.goals.len() - 1;
    let mut index = 0;
    let mut since = f64::NEG_INFINITY;
    loop {
        let rest = match robot.rest(since, stop)? {
            Ok(rest) => rest,
            Err(_) => return Ok("stopped"),
        };
        let a = rest.a;
        summary.final_a = Some(a.into());
        summary.final_error = Some(controller.distance(&a, &params.goals[last]));
        publish_shape(model, &a, since.max(0.0), shape_pub, &mut robot.counts);
        let Ok(model_tip) = model.tip(&a) else {
            log(&format!(
                "control: the model has no shape at ã = {:?}",
                a.as_slice()
            ));
            return Ok("no_model");
        };
        let miss = (model_tip.translation.vector - rest.tip.translation.vector).norm();
        summary.tip_miss_mm = Some(1e3 * miss);
        if params.contact_miss.is_some_and(|limit| miss > limit) {
            log(&format!(
                "control: contact: the model's tip misses the gripper by {:.1} mm",
                1e3 * miss
            ));
            return Ok("contact");
        }
        while index < last
            && controller.distance(&a, &params.goals[index]) < params.waypoint_epsilon
        {
            index += 1;
            summary.passed += 1;
            log(&format!("control: waypoint {index} passed"));
        }
        let error = controller.distance(&a, &params.goals[index]);
        summary.errors.push(error);
        log(&format!(
            "control: rest {}: error {error:.4} to goal {index}",
            summary.steps
        ));
        if index == last && error < params.control.epsilon {
            summary.passed += 1;
            return Ok("reached");
        }
        if summary.steps >= params.max_steps {
            return Ok("max_steps");
        }
        let plan = match controller.plan_step(&a, &params.goals[index], &rest.tip) {
            Ok(Some(plan)) => plan,
            Ok(None) => return Ok("unstable_step"),
            Err(e) => {
                log(&format!(
                    "control: no step from ã = {:?}: {e}",
                    a.as_slice()
                ));
                return Ok("no_model");
            }
        };
        match robot.move_to(&plan.next_tip, stop)? {
            Ok(t) => since = t,
            Err(Halt::Stopped) => return Ok("stopped"),
            Err(Halt::Timeout) => {
                log(&format!(
                    "control: step {} not reached within {} s",
                    summary.steps + 1,
                    params.robot.move_timeout
                ));
                return Ok("unreached");
            }
        }
        summary.steps += 1;
    }
}
