//! Planning in a scene and tracking the plan in the simulator (paper §III-D, §IV-E): the
//! demo's phases 4 and 5, and the tracking experiments' building blocks.
//!
//! - [`plan_in_scene`]: RRT* in `A_free` of the scene (fixed base) with a fixed iteration
//!   budget and seeded restarts, so the same seed gives the same path on any machine, resampled into waypoints
//!   `γ_A(i/N)`.
//! - [`place_in_scene`]: the simulated rig with the base clamp at the scene's base pose, the
//!   scene's obstacles (the same file the planner read) and the true wire at a configuration.
//! - [`Tracking::closed_loop`]: the controller (eq. 13–14) toward each waypoint in turn, with
//!   the collision detector armed; [`Tracking::open_loop`]: the planned gripper poses with no
//!   feedback. Both under the execution noise of [`NoiseModel`], both scored on the simulator's
//!   truth: whether the true wire touched an obstacle at any rest, and its shape against
//!   `Φ(γ_A)` at each waypoint.

use std::time::Instant;

use ftwire_control::{
    AnyPose, BiasObserver, BiasObserverSettings, CollisionDetector, ControlError, ControlSettings,
    Controller, FtFeedback, NoiseModel, NoiseSettings, NoisyRig, Outcome, Reach, ReachCheck,
    RobotReach, Run, configuration_at,
};
use ftwire_core::{Command, GripperPoses, Pose, Rig};
use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::WireModel;
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::ft::FtPipeline;
use ftwire_estimate::shape::{DEFAULT_METRIC_SAMPLES, centreline_distance};
use ftwire_plan::{
    Checker, Config, FixedBase, Plan, PlannerParams, PolishParams, Sample, Scene, ValidityParams,
    plan, scene_endpoint,
};
use ftwire_robot::{DualArmParams, DualArmTarget, Robot};
use ftwire_rod::{Rod, to_normalised};
use ftwire_sim::{RigConfig, SimRig, World};
use nalgebra::{Point3, Translation3, Vector3, Vector6};
use rayon::prelude::*;
use serde::Serialize;

use ftwire_lab::csv_table::{CsvTable, fixed, text, value};
use ftwire_lab::error::{LabError, from_plan, from_rod, from_sim};
use ftwire_lab::experiment::Gravity;
use ftwire_lab::experiment::rig::{
    SAMPLES_PER_REST, bias_observer, pipeline, place_in_world, tare, true_rod,
};
use ftwire_lab::scene::with_scene;
use ftwire_lab::setup::SimSetup;
use ftwire_lab::wire::WireSpec;

/// RRT* iterations of [`plan_in_scene`]'s first attempt (an iteration budget, not a time
/// budget, so that the path does not depend on the machine's speed).
pub const PLAN_ITERATIONS: usize = 1000;

/// Planner restarts of [`plan_in_scene`], each with its own seed drawn from the caller's (a
/// tree grown from an unlucky first samples can stall) and twice the budget of the one before
/// (1000, 2000, 4000, 8000 iterations): a narrowed `Z_free`, as under
/// [`MAX_SPAN_NOISY`], needed 2000–2700 iterations to the passage's first path.
pub const PLAN_RESTARTS: u64 = 4;

/// Waypoints the plan is resampled into (`N` of `γ_A(i/N)`).
pub const WAYPOINTS: usize = 12;

/// Success tolerance on the true configuration at the end, `‖a_true − a_g‖` \[normalised\],
/// without noise or with `offset` noise: twice the controller's default stop `ε` (0.05).
pub const SUCCESS_EPSILON: f64 = 0.1;

/// The controller's stop `ε` on the last leg without noise and under `offset` \[normalised\],
/// well inside [`SUCCESS_EPSILON`]: the stop is on the measured `ã`, and after a passage's
/// hundred moves the sensor's bias has drifted a few hundredths from its tare
/// (`docs/design/tracking.md`).
pub const EPSILON_GOAL: f64 = 0.02;

/// The controller's stop `ε` on the last leg under `increment` or `absolute` noise
/// \[normalised\]: each noisy move lands the wire about 0.2–0.5 away from where it was sent,
/// so the stop rule waits for a move that lands within ε (as `ftwire experiment goal`'s
/// headline ε with that noise).
pub const EPSILON_NOISY: f64 = 0.5;

/// The controller's iteration limit on the last leg under `increment` or `absolute` noise.
pub const MAX_ITERATIONS_NOISY: usize = 400;

/// The controller's settings on the last leg (to the goal) under `noise`: the library's
/// defaults with [`EPSILON_GOAL`], or with [`EPSILON_NOISY`] and [`MAX_ITERATIONS_NOISY`] for
/// the noise models whose every move is off by the full noise.
pub fn goal_settings(noise: NoiseModel) -> ControlSettings {
    match noise {
        NoiseModel::Increment | NoiseModel::Absolute => ControlSettings {
            epsilon: EPSILON_NOISY,
            max_iterations: MAX_ITERATIONS_NOISY,
            divergence: DIVERGENCE_NOISY,
            ..ControlSettings::default()
        },
        NoiseModel::None | NoiseModel::Offset => ControlSettings {
            epsilon: EPSILON_GOAL,
            ..ControlSettings::default()
        },
    }
}

/// The controller's stop `ε` at the waypoints before the last without noise and under
/// `offset` \[normalised\]: the wire passes each waypoint near its planned shape (Table IV
/// scores every waypoint), a few steps of gain 0.5 from the last waypoint's stop.
pub const EPSILON_THROUGH: f64 = 0.05;

/// The controller's stop `ε` at the waypoints before the last under `increment` or
/// `absolute` noise \[normalised\]: looser than each move's own scatter, so that the wire
/// moves on rather than waiting for a lucky move at every waypoint.
pub const EPSILON_THROUGH_NOISY: f64 = 0.3;

/// Most moves toward one waypoint before the last under `increment` or `absolute` noise: with
/// the shape stop ([`SHAPE_STOP_NOISY`]) `experiment track` took 74.5 moves median over a
/// path's 12 legs (about 6 a waypoint, seed 0), so 20 leave a waypoint unmet now and then
/// without stalling the path.
pub const MAX_ITERATIONS_THROUGH_NOISY: usize = 20;

/// The shape stop \[m\] of the closed loop under `increment` or `absolute` noise
/// (`ControlSettings::shape_tolerance`; `--shape-stop`), of every leg of a tracked path and of
/// `experiment goal`'s noise runs. Every move lands the wire about 12 mm (mean along it) from
/// where it was sent (DESIGN.md), so the stop waits for a move that landed the model's shape at
/// `ã` within half of that of the goal's. It must stay well above the error of that shape
/// estimate (about 1 mm, `experiment shape`) for the measured shape to pick the true one.
pub const SHAPE_STOP_NOISY: f64 = 0.006;

/// The clearance \[m\] below which a waypoint's planned wire is near an obstacle: its
/// surface closer than this to a box or the floor ([`near_obstacles`]). The shipped passage's
/// gap is 50 mm, so a 3 mm wire through its middle is 23.5 mm from each box; the plans for the
/// paper's noise keep 15 mm ([`MARGIN_NOISY`]).
pub const NEAR_CLEARANCE: f64 = 0.025;

/// The shape stop \[m\] of a leg near an obstacle under `increment` or `absolute` noise
/// ([`near_shape_stop`]): a leg from or to a waypoint within [`NEAR_CLEARANCE`] of a box.
/// Every landing there, one the stop rejects too, is a chance to touch the box, so a
/// looser stop there means fewer landings beside it; the other legs keep
/// [`SHAPE_STOP_NOISY`], so the wire enters the gap, and ends at the goal, as before.
/// Measured on `experiment passage` under the paper's noise, seeds 0 / 1 / 2 / 3: 46 / 46 /
/// 38 / 43 of 50 at 6 mm everywhere, 47 / 45 / 46 / 43 with 10 mm near the boxes (moves 104.5
/// → 68 median on seed 0; 24 attempts at the goal, against 23). 10 mm everywhere gave 48 /
/// 46 / 45 / 39, and fewer attempts at the goal (seed 0: 15).
pub const SHAPE_STOP_NEAR_NOISY: f64 = 0.010;

/// The shape stop \[m\] of a leg near an obstacle, given the closed loop's `shape_stop` under
/// `noise`: the larger of it and [`SHAPE_STOP_NEAR_NOISY`] under `increment` and `absolute`
/// with the shape stop on; `shape_stop` itself otherwise (without noise and under `offset`
/// the loop converges, and nearness to a box asks for no looser stop).
pub fn near_shape_stop(noise: NoiseModel, shape_stop: f64) -> f64 {
    no_tighter_under_noise(noise, shape_stop, SHAPE_STOP_NEAR_NOISY)
}

/// `shape_stop`, but no tighter than `floor` under `increment` and `absolute` with the shape
/// stop on (0, the `ε` stop alone, stays 0).
fn no_tighter_under_noise(noise: NoiseModel, shape_stop: f64, floor: f64) -> f64 {
    match noise {
        NoiseModel::Increment | NoiseModel::Absolute if shape_stop > 0.0 => shape_stop.max(floor),
        _ => shape_stop,
    }
}

/// The move after which a leg with a budget of `moves` loosens its shape stop
/// ([`LATE_FRACTION`]).
pub fn late_after(moves: usize) -> usize {
    (LATE_FRACTION * moves as f64).ceil() as usize
}

/// The shape stop \[m\] of a leg run again after an undo, given the closed loop's `shape_stop`
/// under `noise`: no tighter than [`default_shape_stop`] (under `increment` and `absolute`
/// with the shape stop on); `shape_stop` itself otherwise.
///
/// A leg is undone when its landings threw the wire far from the waypoint twice in a row
/// ([`MAX_UNDOS`]): near a fold, or a wire close to straight, where a move's noise can snap
/// it. A stop tighter than the default waits there for a lucky landing over many moves, and
/// every move is another chance of a throw, so the rerun takes the default's few landings.
/// Measured on `experiment track --shape-stop 3.5 --waypoint-moves 500`, seed 0, pair 5: its
/// legs 5–8 diverged after 24–77 moves each, five times in all, and the fifth ended the
/// attempt 37 mm from waypoint 8.
pub fn rerun_shape_stop(noise: NoiseModel, shape_stop: f64) -> f64 {
    no_tighter_under_noise(noise, shape_stop, default_shape_stop(noise))
}

/// For each waypoint, whether its planned wire (`Waypoint::centreline`, world frame, the
/// surface at `rod`'s radius) comes within [`NEAR_CLEARANCE`] of a box or the floor of
/// `scene`.
///
/// # Errors
/// Bad input when the robot's description cannot be loaded.
pub fn near_obstacles(
    scene: &Scene,
    rod: &Rod,
    waypoints: &[Waypoint],
) -> Result<Vec<bool>, LabError> {
    let robot = Robot::sda10f().map_err(|e| LabError::bad_input(e.to_string()))?;
    let checker = Checker::new(*rod, robot, scene, ValidityParams::default())
        .map_err(|e| from_plan(e, "the scene"))?;
    Ok(waypoints
        .iter()
        .map(|w| checker.wire_clearance(&w.centreline).0 < NEAR_CLEARANCE)
        .collect())
}

/// The shape stop \[m\] by default under `noise`: [`SHAPE_STOP_NOISY`] under `increment` and
/// `absolute`; off (0, the `ε` stop) without noise and under `offset`, where the loop converges
/// and `ε` is tighter than any shape stop worth waiting for.
pub fn default_shape_stop(noise: NoiseModel) -> f64 {
    match noise {
        NoiseModel::Increment | NoiseModel::Absolute => SHAPE_STOP_NOISY,
        NoiseModel::None | NoiseModel::Offset => 0.0,
    }
}

/// The controller's gain `K` by default for tracking under `noise`: 1 under `increment` and
/// `absolute`, where each move's error is independent and the wire's stationary spread about
/// the path, `1/√(K(2 − K))` times one move's, is least at `K = 1` (1.67 times at the paper's
/// 0.2); 0.5 without noise and under `offset` (`docs/design/tracking.md`).
pub fn default_gain(noise: NoiseModel) -> f64 {
    match noise {
        NoiseModel::Increment | NoiseModel::Absolute => 1.0,
        NoiseModel::None | NoiseModel::Offset => 0.5,
    }
}

/// The controller's settings between waypoints under `noise`: [`EPSILON_THROUGH`] with up to
/// 20 steps where the error is systematic (none, `offset`), so that closed loop follows the
/// planned shapes, not only ends at the goal; [`EPSILON_THROUGH_NOISY`] and
/// [`MAX_ITERATIONS_THROUGH_NOISY`] steps where every move scatters the wire (`increment`,
/// `absolute`; the experiments replace that `ε` by the shape stop, [`default_shape_stop`]).
pub fn through_settings(noise: NoiseModel) -> ControlSettings {
    match noise {
        NoiseModel::Increment | NoiseModel::Absolute => ControlSettings {
            epsilon: EPSILON_THROUGH_NOISY,
            max_iterations: MAX_ITERATIONS_THROUGH_NOISY,
            divergence: DIVERGENCE_NOISY,
            ..ControlSettings::default()
        },
        NoiseModel::None | NoiseModel::Offset => ControlSettings {
            epsilon: EPSILON_THROUGH,
            max_iterations: 20,
            ..ControlSettings::default()
        },
    }
}

/// The success tolerance on the true final configuration under `noise`: [`SUCCESS_EPSILON`]
/// without noise and with `offset`, twice the stop `ε` of [`goal_settings`] under
/// `increment` and `absolute`.
pub fn success_epsilon(noise: NoiseModel) -> f64 {
    match noise {
        NoiseModel::None | NoiseModel::Offset => SUCCESS_EPSILON,
        NoiseModel::Increment | NoiseModel::Absolute => 2.0 * goal_settings(noise).epsilon,
    }
}

/// Whether success under `noise` also asks the wire to end at the goal (within
/// [`success_epsilon`]): without noise and under `offset`, yes; under `increment` and
/// `absolute`, no. Under those two every move lands the wire the full noise away from where it
/// was sent (about 12 mm along it, DESIGN.md), far beyond any goal tolerance, so success is
/// the paper's (§IV-E: "failure is declared when the wire collides with an obstacle"): the
/// whole path executed without touching an obstacle. [`Attempt::at_goal`] still reports the
/// stricter count.
pub fn success_needs_goal(noise: NoiseModel) -> bool {
    matches!(noise, NoiseModel::None | NoiseModel::Offset)
}

/// The success rule under `noise`, in words (the summaries' `success_rule`).
pub fn success_rule(noise: NoiseModel) -> &'static str {
    if success_needs_goal(noise) {
        "the whole path executed, no contact with an obstacle, and the true configuration within success_epsilon of the goal"
    } else {
        "the whole path executed and no contact with an obstacle (the paper's rule; the noise moves the wire beyond any goal tolerance)"
    }
}

/// `(at_goal, success)` of an attempt under `noise` that `completed` the path or not, `touched`
/// an obstacle or not, and ended `error` from the goal (normalised, the true wrench); see
/// [`success_rule`].
pub fn judge(noise: NoiseModel, completed: bool, touched: bool, error: f64) -> (bool, bool) {
    let at_goal = completed && error <= success_epsilon(noise);
    let success = completed && !touched && (at_goal || !success_needs_goal(noise));
    (at_goal, success)
}

/// F/T samples averaged at each rest of the last leg (at the simulated sensor's 1 kHz, a
/// 0.4 s rest; the other legs rest [`SAMPLES_PER_REST`]): the goal's stop rule and the
/// success are judged on it, and the white noise of `ã` falls as `1/√N` (the rest length
/// `experiment identify` measured best).
pub const GOAL_REST_SAMPLES: usize = 400;

/// Most rehearsals [`Tracking::detector`] runs.
pub const REHEARSALS: u64 = 5;

/// Most retreats of one closed-loop attempt (beyond the paper, issue 15 §4: "a detected
/// contact ends the attempt as a failure, unless the retreat recovers it"). After a detection
/// the second gripper moves back one move and the leg runs again; a contact that persists is
/// detected again, and the next detection after the last retreat ends the attempt. A false
/// alarm (the detector's threshold is set on noisy free motion, so the noise's own tail
/// crosses it now and then) costs one move back instead of the attempt. The success is still
/// judged on the true wire: a touch before the retreat is a failure, so more retreats can
/// only turn false alarms into completed paths. Under the paper's noise, passage seed 0, two
/// retreats left 2 of 4 false alarms unrecovered (flagged a third time); four recover all
/// four (seeds 0, 1, 2: 45, 46, 37 → 46, 46, 38 of 50). Under `increment` and `absolute` a
/// second detection on a leg undoes it instead ([`escalates`]).
pub const MAX_RETREATS: usize = 4;

/// The controller's divergence stop under `increment` and `absolute` noise \[normalised\]
/// (`ControlSettings::divergence`): a leg whose measured `‖a_g − ã‖` stays more than this
/// above its start's for two rests in a row is stopped and undone ([`MAX_UNDOS`]). The one
/// leg of `experiment track --seed 1` that ran away went from 1.4 to 10, 18 and 24 at its
/// second to fourth rests (a 38 mm throw toward a taut wire) and to 62 after twenty, 200 mm
/// from its waypoint. Near a taut wire one move's throw alone sets `ã` 5–15 away and the
/// next move brings it back: on `experiment passage --seed 1`, a stop at 5 undid 37 legs and
/// at 10 six (and each undo is one more noisy move near the boxes), at 20 none; 5, 10 and 20
/// all rescue the run away.
pub const DIVERGENCE_NOISY: f64 = 20.0;

/// Most undone legs of one closed-loop attempt. A leg the controller stopped as diverged
/// (`Outcome::Diverged`), or one that ended on a rest without a usable measurement
/// (`Outcome::SensorFault`: a wire pulled taut saturates the sensor), or, under fresh noise per
/// move, one whose waypoint the arms could not reach ([`reruns_unreachable`]), is undone: the
/// second gripper goes back to the pose the leg started from (the robot knows it: under
/// `increment` noise the encoders report where it went), and the leg runs again. The next such
/// end after the last undo ends the attempt. A limit per leg instead was tried on the cable
/// (`experiment track --wire cable-3mm-920 --shape-stop 3.5 --waypoint-moves 500`, seed 0):
/// its pair 1 diverged on legs 3, 4, 4 and 5, each rerun reaching its waypoint, then on leg 6
/// five times in a row, so it ended at leg 6 either way. (Those divergences were steered by
/// rests the bias observer could not fuse; since it tries them again on the last estimate's
/// branch, `BiasObserver::recovered`, that pair reaches its goal with three legs undone.)
pub const MAX_UNDOS: usize = 4;

/// The fraction of a leg's move budget (`--waypoint-moves`) after which its shape stop
/// loosens to [`rerun_shape_stop`] (`ControlSettings::late_shape_tolerance`). With the tight
/// stop of `--shape-stop 3.5 --waypoint-moves 500`, two of seed 0's 120 cable legs spent all
/// 500 moves without a landing within 3.5 mm and ended on the last one, 16–17 mm off; the
/// other legs took 83 moves on average. At the default stop nothing changes (the rerun stop
/// is the default's).
pub const LATE_FRACTION: f64 = 0.75;

/// A base gripper pose from which the arms reach the goal again, when the controller has
/// found the goal out of their reach (under `offset` noise the run's grasp offset moves the
/// pose the robot must command by up to a few centimetres), or the leg's start (under
/// `increment` the accumulated noise can carry the gripper there): the current base `poses.base`
/// moved by one translation of 1–4 cm along a world axis ([`RELOCATION_STEPS`], shortest
/// first), which leaves the wire's configuration and the sensor's gravity direction unchanged.
/// A candidate must keep the goal `a_goal` valid in `scene` with the margins of a plan tracked
/// under `noise` ([`validity`]: `model`'s wire clear of the boxes there and halfway, the
/// planned goal pose reachable with the planner's coarse torso sweep, the arms clear), and
/// two relative poses must be reachable from it with that sweep: the robot's current one and
/// the one it will command at the goal, `Γ(a_goal) · Γ(a_now)⁻¹ · b`, the current command
/// `b` carried by the model's step from the measured `a_now` (which holds the grasp offset
/// the robot cannot see). `None` when no candidate does.
///
/// # Errors
/// Bad input when the scene or the robot cannot be built; no answer when the model cannot
/// solve `a_now` or `a_goal`.
pub fn relocation(
    scene: &Scene,
    noise: NoiseModel,
    model: &KirchhoffModel,
    poses: &GripperPoses,
    a_now: &Vector6<f64>,
    a_goal: &Vector6<f64>,
) -> Result<Option<Pose>, LabError> {
    let robot = Robot::sda10f().map_err(|e| LabError::bad_input(e.to_string()))?;
    let checker = Checker::new(
        *model.rod(),
        robot.clone(),
        scene,
        validity(noise, model.wire().length()),
    )
    .map_err(|e| from_plan(e, "the scene"))?;
    let tip = |a: &Vector6<f64>| {
        model
            .tip(a)
            .map_err(|e| LabError::no_answer(format!("relocating the base: {e}")))
    };
    let now = poses.relative();
    let at_goal = tip(a_goal)? * tip(a_now)?.inverse() * now;
    let moved = |t: Vector3<f64>| {
        Pose::from_parts(
            Translation3::from(poses.base.translation.vector + t),
            poses.base.rotation,
        )
    };
    let clear = |base: Pose| checker.endpoint(&Config { a: *a_goal, base }).is_ok();
    let coarse = DualArmParams::default();
    for step in RELOCATION_STEPS {
        for axis in 0..6 {
            let mut t = Vector3::zeros();
            t[axis % 3] = if axis < 3 { step } else { -step };
            let base = moved(t);
            if !(clear(base) && clear(moved(0.5 * t))) {
                continue;
            }
            let reaches = |relative: Pose| {
                let target = DualArmTarget {
                    world_from_base: Pose::identity(),
                    base_gripper: base,
                    relative,
                };
                robot.dual_arm_ik(&target, None, &coarse).is_ok()
            };
            if reaches(now) && reaches(at_goal) {
                return Ok(Some(base));
            }
        }
    }
    Ok(None)
}

/// Lengths \[m\] of the translations [`relocation`] tries along each world axis.
pub const RELOCATION_STEPS: [f64; 4] = [0.01, 0.02, 0.03, 0.04];

/// Whether a leg that ended on a waypoint out of the arms' reach is undone and run again
/// ([`MAX_UNDOS`]): under `increment` and `absolute`, where every move lands with fresh noise,
/// so the accumulated noise that carried the gripper to the edge of the arms' workspace is
/// not there on the rerun. The undo comes before a relocation of the goal: the relocating move
/// lands with the noise too, and can leave the next start out of reach. Under the paper's
/// noise, passage seeds 2 and 3 had ended 3 and 1 of their 50 attempts so: the goal out of
/// reach 51–57 mm off it after a throw, where no translation of both grippers brought it
/// back, or a waypoint passed over and the next leg's start out of reach. Undone, every one of
/// them completed the path: 46 → 49 and 47 → 48 of 50 (`experiment passage --seed 2|3`).
/// Seed 6, with the undo only after a relocation, lost 2 attempts whose relocating move left
/// the goal leg's start out of reach (48 of 50); with the undo first, 50. Under `offset` and
/// without noise a rerun would meet the same pose again: those runs pass the waypoint over,
/// or relocate for the goal, as before.
pub fn reruns_unreachable(noise: NoiseModel) -> bool {
    matches!(noise, NoiseModel::Increment | NoiseModel::Absolute)
}

/// Whether, under `noise`, a leg to waypoint `waypoint` whose *start* is out of the arms'
/// reach goes back to the pose where the last leg run (`ran`: the leg in progress, see
/// [`undo_leg`]) first started, and runs that leg again, instead of ending the attempt. That
/// leg is the one before, whose last landing carried the second gripper there, or this one,
/// when it ran already and its undo landed there. Where [`reruns_unreachable`] and
/// [`MAX_UNDOS`] allows (`undone` so far), after the relocation an attempt may make once:
/// where that finds no translation, or was spent. On the 910 mm wire's passage attempt 35
/// ended so at waypoint 12, and on seed 3 of the 820 mm one attempt 48, each after an undo of
/// leg 12 whose move landed out of reach.
pub fn undoes_to_last_start(
    noise: NoiseModel,
    ran: Option<usize>,
    waypoint: usize,
    undone: usize,
) -> bool {
    reruns_unreachable(noise)
        && ran.is_some_and(|leg| leg + 1 == waypoint || leg == waypoint)
        && undone < MAX_UNDOS
}

/// Whether a leg that ended with `outcome` under `noise` is undone and run again
/// ([`MAX_UNDOS`] an attempt): diverged, or on a sensor fault, under any noise; at a waypoint
/// out of the arms' reach where [`reruns_unreachable`] (before any relocation, which would
/// land with the noise too).
pub fn undoes(outcome: &Outcome, noise: NoiseModel) -> bool {
    match outcome {
        Outcome::Diverged { .. } | Outcome::SensorFault { .. } => true,
        Outcome::Unreachable { .. } => reruns_unreachable(noise),
        _ => false,
    }
}

/// Whether a detection on a leg is answered by undoing the leg (back to the pose its first run
/// started from) instead of a retreat of one move: under fresh noise per move
/// ([`reruns_unreachable`]), when the loop has already retreated on this leg
/// (`retreated_before`). After a throw the wire lands 20–40 mm off, where the model's
/// linearisation is off and the detector flags every move; retreating one move at a time
/// spent all [`MAX_RETREATS`] there: 2 of passage seed 5's 50 attempts ended so without a
/// contact, and a third touched a box during its retreats. The leg's start was clear, for a
/// contact as for a false alarm. With the undo seed 5 went from 46 to 49 of 50; seeds 1, 4
/// and 6, the others with two retreats in an attempt, stayed at 45, 50 and 50.
pub fn escalates(noise: NoiseModel, retreated_before: bool) -> bool {
    retreated_before && reruns_unreachable(noise)
}

/// Whether the closed loop may pass over waypoint `i` (1-based leg), out of the arms' reach:
/// not the goal, and not right after passing over the one before.
fn may_pass_over(i: usize, final_leg: bool, skipped_last: Option<usize>) -> bool {
    !final_leg && (skipped_last.is_none() || skipped_last != i.checked_sub(1))
}

/// Contact force \[N\] on a node of the simulated wire above which it touches an obstacle.
pub const CONTACT_FORCE: f64 = 1e-6;

/// A plan and its waypoints.
#[derive(Debug, Clone)]
pub struct ScenePlan {
    /// The planner's result.
    pub plan: Plan,
    /// `γ_A(i/N)`, `i = 0..=N` ([`waypoints_along`]).
    pub waypoints: Vec<Waypoint>,
    /// Wall time of the planning \[s\].
    pub seconds: f64,
}

/// A waypoint of a planned path: the configuration and what the planning model makes of it.
#[derive(Debug, Clone, PartialEq)]
pub struct Waypoint {
    /// `a` \[N·m, N\], base clamp frame.
    pub a: Vector6<f64>,
    /// `Γ(a)`: the second gripper relative to the base clamp.
    pub tip: Pose,
    /// `Φ(a)`, world frame.
    pub centreline: Vec<Point3<f64>>,
}

/// `N + 1` waypoints `γ_A(i/N)` at equal steps of normalised arc length along the planned
/// path (piecewise straight in `A`, every edge checked by the planner), with `Γ` and `Φ` of
/// `rod`. The robot's reach is the controller's to check as it moves (its IK seeded by the
/// last pose), not re-solved here.
///
/// # Errors
/// No answer when the model cannot solve a waypoint.
pub fn waypoints_along(
    rod: &Rod,
    base: &Pose,
    path: &[Sample],
    n: usize,
) -> Result<Vec<Waypoint>, LabError> {
    let wire = rod.wire();
    let a: Vec<Vector6<f64>> = path.iter().map(|s| s.config.a).collect();
    let mut cumulative = vec![0.0];
    for w in a.windows(2) {
        let d = (to_normalised(wire, &w[1]) - to_normalised(wire, &w[0])).norm();
        cumulative.push(cumulative.last().copied().unwrap_or(0.0) + d);
    }
    let total = cumulative.last().copied().unwrap_or(0.0);
    let n = n.max(1);
    let along = (0..=n)
        .map(|i| {
            let target = total * i as f64 / n as f64;
            let k = cumulative
                .windows(2)
                .position(|w| target <= w[1])
                .unwrap_or(cumulative.len().saturating_sub(2));
            let (Some(from), Some(to)) = (a.get(k), a.get(k + 1).or_else(|| a.get(k))) else {
                return Err(LabError::no_answer("an empty path"));
            };
            let span = cumulative.get(k + 1).copied().unwrap_or(total) - cumulative[k];
            let t = if span > 0.0 {
                ((target - cumulative[k]) / span).clamp(0.0, 1.0)
            } else {
                0.0
            };
            Ok(from + (to - from) * t)
        })
        .collect::<Result<Vec<_>, LabError>>()?;
    waypoints_at(rod, base, &along)
}

/// The waypoints at the configurations `a` (in order), with `Γ` and `Φ` of `rod` (world
/// frame, base clamp at `base`).
///
/// # Errors
/// No answer when the model cannot solve one of them.
pub fn waypoints_at(rod: &Rod, base: &Pose, a: &[Vector6<f64>]) -> Result<Vec<Waypoint>, LabError> {
    a.iter()
        .map(|a| {
            let tip = rod
                .tip(a)
                .map_err(|e| from_rod(e, "a waypoint of the path"))?;
            let shape = rod
                .shape(a, ValidityParams::default().nodes)
                .map_err(|e| from_rod(e, "a waypoint of the path"))?;
            let centreline = shape
                .positions
                .iter()
                .map(|p| base * Point3::from(*p))
                .collect();
            Ok(Waypoint {
                a: *a,
                tip,
                centreline,
            })
        })
        .collect()
}

/// Whether a plan tracked under `noise` has its waypoints polished for clearance
/// ([`polish_waypoints`]): under `increment` and `absolute`, where every move lands the wire
/// about 12 mm from where it was sent, and the landings' tail beside the closest waypoint is
/// what touches a box. Without noise and under `offset` the loop converges onto the plan
/// (0.56 mm along the passage), which keeps its 5 mm margin; those runs track the plan as
/// resampled, as before.
pub fn polishes(noise: NoiseModel) -> bool {
    matches!(noise, NoiseModel::Increment | NoiseModel::Absolute)
}

/// The clearance polish of a plan tracked under the paper's noise: it raises each interior
/// waypoint's *landing clearance* ([`ftwire_plan::landing_clearance`]: the wire's clearance
/// where a move toward the waypoint lands when the second gripper lands [`LANDING_SIGMAS`]
/// standard deviations of that noise off on one axis) toward [`LANDING_TARGET`].
///
/// Why the landings, not the planned wire: the touches of a run are at the rests beside the
/// waypoints whose landings scatter most toward a box, and those are not the ones whose
/// planned wire is closest to it. On `experiment passage --seed 8` the touches cluster on the
/// legs to waypoints 6 and 7 (12 of 16 touching legs); after the polish of the planned
/// clearance, those waypoints' planned wires kept 22.3 and 21.8 mm, no less than the others,
/// but their landing clearances, 5.7 and 2.6 mm, were the path's two smallest (the others'
/// 7.1–40.3; seed 4, 50 of 50, kept 9.5 or more).
pub fn polish_params() -> PolishParams {
    let noise = NoiseSettings::default();
    PolishParams {
        target: LANDING_TARGET,
        landing: Some(ftwire_plan::Landing {
            position: LANDING_SIGMAS * noise.position_std,
            rotation: LANDING_SIGMAS * noise.orientation_std,
        }),
        ..PolishParams::default()
    }
}

/// Standard deviations of the paper's noise (`NoiseSettings`) by which [`polish_params`]'
/// probes land off: 2, so that a probe is a landing that one move in about twenty reaches on
/// its axis.
pub const LANDING_SIGMAS: f64 = 2.0;

/// The landing clearance \[m\] that [`polish_params`] aims at: 15 mm, the plans' own margin
/// under the paper's noise ([`MARGIN_NOISY`]), which a waypoint's planned wire already keeps.
pub const LANDING_TARGET: f64 = MARGIN_NOISY;

/// What [`polish_waypoints`] did.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PolishOut {
    /// Interior waypoints moved.
    pub moved: usize,
    /// The smallest waypoint clearance before the polish \[mm\] (`null` when nothing was
    /// polished).
    pub min_clearance_before_mm: f64,
    /// As `min_clearance_before_mm`, after.
    pub min_clearance_after_mm: f64,
    /// The smallest landing clearance of an interior waypoint before the polish \[mm\]
    /// ([`polish_params`]; `null` when nothing was polished).
    pub min_landing_clearance_before_mm: f64,
    /// As `min_landing_clearance_before_mm`, after.
    pub min_landing_clearance_after_mm: f64,
    /// Whether every waypoint was valid under the tracking model's checker (else nothing was
    /// polished).
    pub valid: bool,
}

/// The waypoints of a path tracked with `rod` in `scene` under `noise`, polished for clearance
/// ([`ftwire_plan::polish_clearance`] with [`polish_params`] and a checker of `rod` and
/// [`validity`]): each interior waypoint whose landings come closer than the target to a box
/// is moved away from it, its legs kept in `Z_free`. Each waypoint's joints continue the previous one's along their edge, or
/// are solved afresh where that edge is refused (a waypoint next to such an edge moves only
/// where both its new edges pass); when a waypoint is not valid at all under that checker,
/// the waypoints are returned as they are.
///
/// # Errors
/// Bad input when the robot or the checker cannot be built; no answer when the model cannot
/// solve a polished waypoint.
pub fn polish_waypoints(
    scene: &Scene,
    rod: &Rod,
    noise: NoiseModel,
    waypoints: &[Waypoint],
) -> Result<(Vec<Waypoint>, PolishOut), LabError> {
    let unpolished = PolishOut {
        moved: 0,
        min_clearance_before_mm: f64::NAN,
        min_clearance_after_mm: f64::NAN,
        min_landing_clearance_before_mm: f64::NAN,
        min_landing_clearance_after_mm: f64::NAN,
        valid: false,
    };
    let robot = Robot::sda10f().map_err(|e| LabError::bad_input(e.to_string()))?;
    // The checker's own model is the tracking one: `validity` keeps the margin on its folds
    // (`validity_tracked` would test the same model's stability twice).
    let checker = Checker::new(*rod, robot, scene, validity(noise, rod.wire().length()))
        .map_err(|e| from_plan(e, "the scene"))?;
    let configs = waypoints.iter().map(|w| Config {
        a: w.a,
        base: scene.base,
    });
    let mut chain: Vec<Sample> = Vec::with_capacity(waypoints.len());
    for config in configs {
        let next = match chain.last() {
            None => checker.endpoint(&config),
            Some(prev) => checker
                .edge(prev, &config)
                .map(|e| e.end)
                .or_else(|_| checker.endpoint(&config)),
        };
        match next {
            Ok(sample) => chain.push(sample),
            Err(_) => return Ok((waypoints.to_vec(), unpolished)),
        }
    }
    let polished = ftwire_plan::polish_clearance(&checker, &chain, &polish_params())
        .map_err(|e| from_plan(e, "the clearance polish"))?;
    let a: Vec<Vector6<f64>> = polished.waypoints.iter().map(|s| s.config.a).collect();
    let out = PolishOut {
        moved: polished.moved,
        min_clearance_before_mm: 1e3 * polished.min_clearance.0,
        min_clearance_after_mm: 1e3 * polished.min_clearance.1,
        min_landing_clearance_before_mm: 1e3 * polished.min_score.0,
        min_landing_clearance_after_mm: 1e3 * polished.min_score.1,
        valid: true,
    };
    Ok((waypoints_at(rod, &scene.base, &a)?, out))
}

/// The expected number of touching landings of one pass along `waypoints` tracked with `rod`
/// in `scene` under the paper's noise: the sum over the waypoints after the first of
/// [`ftwire_plan::touch_rate`] (each reached by one move whose landing scatters by
/// `NoiseSettings::default()`; [`TOUCH_SAMPLES`] landings each, the same landings at every
/// waypoint).
///
/// # Errors
/// Bad input when the robot or the checker cannot be built; no answer when the model refuses
/// a waypoint.
pub fn expected_touches(
    scene: &Scene,
    rod: &Rod,
    noise: NoiseModel,
    waypoints: &[Waypoint],
) -> Result<f64, LabError> {
    let robot = Robot::sda10f().map_err(|e| LabError::bad_input(e.to_string()))?;
    let checker = Checker::new(*rod, robot, scene, validity(noise, rod.wire().length()))
        .map_err(|e| from_plan(e, "the scene"))?;
    let settings = NoiseSettings::default();
    let scatter = ftwire_plan::Scatter {
        position_std: settings.position_std,
        orientation_std: settings.orientation_std,
        samples: TOUCH_SAMPLES,
        seed: 0,
    };
    waypoints.iter().skip(1).try_fold(0.0, |sum, w| {
        let config = Config {
            a: w.a,
            base: scene.base,
        };
        ftwire_plan::touch_rate(&checker, &config, &scatter)
            .map(|rate| sum + rate)
            .map_err(|e| from_plan(e, "the expected touches"))
    })
}

/// Landings per waypoint of [`expected_touches`]: 1024, so that one touching landing at one
/// waypoint counts 0.001 in a sum whose plans on the shipped passage span 0–0.05.
pub const TOUCH_SAMPLES: usize = 1024;

/// Plans [`choose_plan`] makes by default (`experiment passage --plan-candidates`, the demo).
pub const PLAN_CANDIDATES: usize = 4;

/// The seed of [`choose_plan`]'s candidate `k` from the run's `seed`: `seed` itself for the
/// first, so that one candidate plans as [`plan_in_scene`] does.
pub fn candidate_seed(seed: u64, k: usize) -> u64 {
    seed.wrapping_add((k as u64).wrapping_mul(0xd1b5_4a32_d192_ed03))
}

/// How [`choose_plan`] chose, in the summaries (`plan.choice`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChoiceOut {
    /// Plans made, each from its own seed ([`candidate_seed`]).
    pub candidates: usize,
    /// Each candidate's expected touching landings ([`expected_touches`] of its tracked,
    /// polished waypoints); `null` for a candidate that found no path, or whose waypoints the
    /// tracking model refused.
    pub expected_touches: Vec<Option<f64>>,
    /// The candidate tracked (0-based): the fewest expected touches, the first among equals.
    pub chosen: usize,
}

/// A plan chosen by [`choose_plan`], with its tracked waypoints.
#[derive(Debug)]
pub struct Chosen {
    /// The plan.
    pub planned: ScenePlan,
    /// Its waypoints as tracked (`prepare`d, then polished when asked).
    pub waypoints: Vec<Waypoint>,
    /// What the polish did (`None` when not asked).
    pub polish: Option<PolishOut>,
    /// How it was chosen (`None` when one plan was made without a choice: see
    /// [`choose_plan`]).
    pub choice: Option<ChoiceOut>,
    /// Wall time of all the candidates' planning, preparing, polishing and scoring \[s\].
    pub seconds: f64,
    /// Each candidate's planning wall time \[ms\] (`None` when it found no path), for the
    /// timings (not [`ChoiceOut`], so that the summaries are the same for the same seed).
    pub candidate_plan_ms: Vec<Option<f64>>,
}

/// Plans `candidates` times from the scene's `start` to its `goal` ([`plan_in_scene`] with
/// `planner` and `validity`, from the seeds [`candidate_seed`]), turns each plan into the
/// waypoints tracked with `tracker` (`prepare`, then [`polish_waypoints`] when `polish`), and
/// keeps the one with the fewest [`expected_touches`] under `noise`.
///
/// Why: the passage's touches under the paper's noise are a property of the plan far more
/// than of the run. Over `experiment passage` seeds 0–8 (one plan each, 50 attempts), the
/// touching attempts were 4 / 5 / 1 / 0 / 0 / 4 / 2 / 6 / 9, and the plans' expected touches
/// ranked them with Spearman's ρ = 0.83 (0.0049 / 0.0088 / 0.0010 / 0.0068 / 0 / 0.0107 /
/// 0.0088 / 0.0254 / 0.0537): the worst plans are the ones to avoid, and one noisy move's
/// landings tell them apart before any roll-out.
///
/// The choice runs only where the polish does ([`polishes`]: `increment` and `absolute`);
/// otherwise one plan is made, as before, and `choice` is `None`. The candidates are made in
/// parallel and compared in order: the same seed chooses the same plan on any machine
/// (passage seed 8: 29 s for four alone, against 52 s for their sum).
///
/// # Errors
/// The first error (planning, `prepare` or the polish) when no candidate gave waypoints to
/// track; bad input for no candidates.
#[allow(clippy::too_many_arguments)]
pub fn choose_plan(
    scene: &Scene,
    planner: &Rod,
    tracker: &Rod,
    validity: ValidityParams,
    noise: NoiseModel,
    seed: u64,
    candidates: usize,
    polish: bool,
    prepare: impl Fn(&ScenePlan) -> Result<Vec<Waypoint>, LabError> + Sync,
) -> Result<Chosen, LabError> {
    if candidates == 0 {
        return Err(LabError::bad_input(
            "--plan-candidates 0: make at least 1 plan",
        ));
    }
    let began = Instant::now();
    let chooses = polishes(noise);
    let candidates = if chooses { candidates } else { 1 };
    // Each candidate: its planning time (`None`: no path), and its expected touches with its
    // plan and waypoints, or why it was passed over. The candidates are independent, so they
    // run in parallel; the choice below takes them in order, so it is the same on any machine.
    type Outcome = (Option<f64>, Result<(Option<f64>, Chosen), LabError>);
    let outcomes: Vec<Outcome> = (0..candidates)
        .into_par_iter()
        .map(|k| {
            let planned = match plan_in_scene(scene, planner, validity, candidate_seed(seed, k)) {
                Ok((planned, _)) => planned,
                Err(e) => return (None, Err(e)),
            };
            let ms = Some(1e3 * planned.seconds);
            // A plan whose waypoints cannot be prepared or polished (the tracking model has no
            // configuration at one of them) is passed over like one not found.
            let prepared = prepare(&planned).and_then(|waypoints| {
                if polish {
                    polish_waypoints(scene, tracker, noise, &waypoints)
                        .map(|(waypoints, out)| (waypoints, Some(out)))
                } else {
                    Ok((waypoints, None))
                }
            });
            let scored = prepared.map(|(waypoints, polished)| {
                let expected = if chooses {
                    expected_touches(scene, tracker, noise, &waypoints).ok()
                } else {
                    None
                };
                let candidate = Chosen {
                    planned,
                    waypoints,
                    polish: polished,
                    choice: None,
                    seconds: 0.0,
                    candidate_plan_ms: Vec::new(),
                };
                (expected, candidate)
            });
            (ms, scored)
        })
        .collect();
    // The fewest expected touches, its candidate and the candidate's plan.
    let mut best: Option<(f64, usize, Chosen)> = None;
    let mut first_error = None;
    let mut touches = Vec::with_capacity(candidates);
    let mut plan_ms = Vec::with_capacity(candidates);
    for (k, (ms, scored)) in outcomes.into_iter().enumerate() {
        plan_ms.push(ms);
        match scored {
            Ok((expected, candidate)) => {
                touches.push(expected);
                let score = expected.unwrap_or(f64::INFINITY);
                if best.as_ref().is_none_or(|(least, ..)| score < *least) {
                    best = Some((score, k, candidate));
                }
            }
            Err(e) => {
                first_error.get_or_insert(e);
                touches.push(None);
            }
        }
    }
    let Some((_, chosen, candidate)) = best else {
        return Err(
            first_error.unwrap_or_else(|| LabError::no_answer("planning in the scene: no attempt"))
        );
    };
    Ok(Chosen {
        choice: chooses.then_some(ChoiceOut {
            candidates,
            expected_touches: touches,
            chosen,
        }),
        seconds: began.elapsed().as_secs_f64(),
        candidate_plan_ms: plan_ms,
        ..candidate
    })
}

/// The waypoints of a plan made with one model, re-expressed for `model` (another load, e.g.
/// the identified wire's weight): each keeps its gripper pose and takes the `a` whose `Γ` under
/// `model` is that pose, with `model`'s shape (world frame, base clamp at `base`). Each is
/// found by Newton's method from the previous answer moved by the plan's own step, so that the
/// path stays on one branch. A plan made with the weightless model and tracked with the loaded
/// one would otherwise steer to the planned *wrenches*, whose loaded shapes sag away from the
/// planned ones.
///
/// # Errors
/// No answer when `model` has no stable configuration near a waypoint's pose.
pub fn reexpress(
    waypoints: &[Waypoint],
    model: &KirchhoffModel,
    base: &Pose,
) -> Result<Vec<Waypoint>, LabError> {
    let mut out: Vec<Waypoint> = Vec::with_capacity(waypoints.len());
    for (i, waypoint) in waypoints.iter().enumerate() {
        let guess = match (out.last(), i.checked_sub(1).and_then(|j| waypoints.get(j))) {
            (Some(previous), Some(planned)) => previous.a + (waypoint.a - planned.a),
            _ => waypoint.a,
        };
        let fail = |why: &str| {
            LabError::no_answer(format!(
                "waypoint {i}: the tracking model has no configuration at the planned pose ({why})"
            ))
        };
        let a = configuration_at(model, &guess, &waypoint.tip)
            .ok_or_else(|| fail("Newton's method did not converge"))?;
        if !model.is_stable(&a).unwrap_or(false) {
            return Err(fail("it is not stable there"));
        }
        let shape = model
            .shape(&a, ValidityParams::default().nodes)
            .map_err(|e| fail(&e.to_string()))?;
        out.push(Waypoint {
            a,
            tip: waypoint.tip,
            centreline: shape
                .positions
                .iter()
                .map(|p| base * Point3::from(*p))
                .collect(),
        });
    }
    Ok(out)
}

/// The largest distance between the grippers of a plan under `noise` for a wire of `length`
/// \[m\], as a fraction of that length: under `increment` and `absolute`, whose every move
/// lands the gripper the full noise (17 mm RMS) away, the wire keeps [`MAX_SPAN_NOISY`] of its
/// length, or [`MAX_SLACK_NOISY`] of slack where that is less (a longer wire); no limit but
/// the model's otherwise.
pub fn max_span(noise: NoiseModel, length: f64) -> f64 {
    match noise {
        NoiseModel::Increment | NoiseModel::Absolute => {
            MAX_SPAN_NOISY.max(1.0 - MAX_SLACK_NOISY / length)
        }
        NoiseModel::None | NoiseModel::Offset => 1.0,
    }
}

/// [`max_span`] under `increment` and `absolute` noise: 93 % of the wire's length (57 mm of
/// slack for the 3 mm / 820 mm nitinol wire). Measured on the shipped passage under the
/// paper's noise (seed 0, 50 attempts): unlimited, the plan's grippers came 0.78 m apart and
/// 12 open-loop roll-outs tore the wire (3 more found no equilibrium); at 93 %, 4 tore it. At
/// 92 %, four restarts of 1000 iterations each found no path through the passage.
pub const MAX_SPAN_NOISY: f64 = 0.93;

/// The most slack \[m\] [`max_span`] keeps under `increment` and `absolute` noise: the
/// 57.4 mm that [`MAX_SPAN_NOISY`] leaves the 820 mm nitinol wire. The tear it guards against
/// is a gripper landing the noise's few centimetres beyond a taut wire, whatever the wire's
/// length. At 93 % of its length the 910 mm wire (64 mm of slack) had no path through the
/// shipped passage with the 15 mm margin (`ftwire plan --wire nitinol-3mm-910 --margin 0.015
/// --max-span 0.93`, 8000 iterations), so neither `experiment passage --wire
/// nitinol-3mm-910` nor `demo --noise-model increment` (whose default wire is that one) could
/// plan; at 93.5 % it has.
pub const MAX_SLACK_NOISY: f64 = (1.0 - MAX_SPAN_NOISY) * 0.82;

/// The clearance \[m\] a plan tracked under `noise` keeps from every box and the floor:
/// [`MARGIN_NOISY`] under `increment` and `absolute`, whose every move scatters the wire by
/// about the gripper's noise, and the planner's default (`ValidityParams::default().margin`)
/// otherwise.
pub fn margin(noise: NoiseModel) -> f64 {
    match noise {
        NoiseModel::Increment | NoiseModel::Absolute => MARGIN_NOISY,
        NoiseModel::None | NoiseModel::Offset => ValidityParams::default().margin,
    }
}

/// [`margin`] under `increment` and `absolute` noise: 15 mm, a little more than the ~12 mm
/// by which a noisy move scatters the wire, so that the tracked wire keeps clear of a box the
/// plan passes (the shipped passage's gap is 50 mm); the planner's 5 mm default is less than
/// that scatter.
pub const MARGIN_NOISY: f64 = 0.015;

/// The distance in normalised `a` a plan tracked under `noise` keeps from the boundary of
/// `A_stable` (`ValidityParams::stability_margin`): [`STABILITY_MARGIN_NOISY`] under
/// `increment` and `absolute`, none otherwise.
pub fn stability_margin(noise: NoiseModel) -> f64 {
    match noise {
        NoiseModel::Increment | NoiseModel::Absolute => STABILITY_MARGIN_NOISY,
        NoiseModel::None | NoiseModel::Offset => 0.0,
    }
}

/// [`stability_margin`] under `increment` and `absolute` noise: 1 normalised unit. Each noisy
/// move scatters `a` by units, and a wire pushed over the boundary of `A_stable` snaps onto
/// another equilibrium that the controller cannot steer back from. On `experiment track`'s
/// seed 3 the two pairs that snapped (40.9 and 33.5 mm against 4.4–5.4 mm for the other
/// eight) were the only ones with a waypoint where a step of 1 along some normalised axis was
/// unstable (0.25 and 0.5 at their closest); seed 0's ten pairs kept 1.5 or more.
pub const STABILITY_MARGIN_NOISY: f64 = 1.0;

/// The validity settings of a plan tracked under `noise` for a wire of `length` \[m\]: the
/// defaults with [`max_span`], [`margin`] and [`stability_margin`].
pub fn validity(noise: NoiseModel, length: f64) -> ValidityParams {
    ValidityParams {
        max_span: max_span(noise, length),
        margin: margin(noise),
        stability_margin: stability_margin(noise),
        ..ValidityParams::default()
    }
}

/// [`validity`] for a plan tracked with the model `tracker`: where the plan keeps a
/// [`stability_margin`], it keeps it on `tracker`'s folds (`ValidityParams::stability_model`),
/// and every configuration is stable under `tracker` too. The planner's weightless model and
/// the loaded one the wire is tracked with differ most for a heavy wire, such as the cable.
pub fn validity_tracked(noise: NoiseModel, tracker: &Rod) -> ValidityParams {
    let params = validity(noise, tracker.wire().length());
    ValidityParams {
        stability_model: (params.stability_margin > 0.0).then_some(*tracker),
        ..params
    }
}

/// Plans from the scene's `start` to its `goal` for the wire model `rod` (fixed base; with a
/// [`Load`], the loaded model's shapes and stability) under the validity settings `validity`
/// ([`validity`] for a plan that is to be tracked under a noise model).
///
/// # Errors
/// Bad input for an invalid start or goal; no answer when no path is found.
pub fn plan_in_scene(
    scene: &Scene,
    rod: &Rod,
    validity: ValidityParams,
    seed: u64,
) -> Result<(ScenePlan, Checker), LabError> {
    let robot = Robot::sda10f().map_err(|e| LabError::bad_input(e.to_string()))?;
    let checker =
        Checker::new(*rod, robot, scene, validity).map_err(|e| from_plan(e, "the scene"))?;
    let endpoint = |name: &str, role| {
        scene_endpoint(scene, &checker, name, role).map_err(|e| from_plan(e, "the scene"))
    };
    let start = endpoint("start", "start")?;
    let goal = endpoint("goal", "goal")?;
    let began = Instant::now();
    let space = FixedBase::around(*rod.wire(), scene.base, &[start.config, goal.config], 2.0);
    let mut last = None;
    let mut found = None;
    for restart in 0..PLAN_RESTARTS {
        let params = PlannerParams {
            seed: seed.wrapping_add(restart.wrapping_mul(0x9e37_79b9_7f4a_7c15)),
            time_budget: None,
            max_iterations: PLAN_ITERATIONS << restart,
            ..PlannerParams::default()
        };
        match plan(&space, &checker, &start, &goal.config, &params) {
            Ok(plan) => {
                found = Some(plan);
                break;
            }
            Err(e) => last = Some(e),
        }
    }
    let found = match (found, last) {
        (Some(found), _) => found,
        (None, Some(e)) => return Err(from_plan(e, "planning in the scene")),
        (None, None) => return Err(LabError::no_answer("planning in the scene: no attempt")),
    };
    let waypoints = waypoints_along(rod, &scene.base, &found.path.waypoints, WAYPOINTS)?;
    let seconds = began.elapsed().as_secs_f64();
    Ok((
        ScenePlan {
            plan: found,
            waypoints,
            seconds,
        },
        checker,
    ))
}

/// A simulated rig holding the true `wire` at `a0` (of its loaded model: weight and rest
/// curvature under `gravity`) with its base clamp at the scene's base pose, with the scene's
/// obstacles when `obstacles` (gravity along the world's −z).
///
/// # Errors
/// No answer when the simulator cannot place the wire there.
pub fn place_in_scene(
    wire: &WireSpec,
    gravity: Gravity,
    scene: &Scene,
    obstacles: bool,
    a0: &Vector6<f64>,
    config: RigConfig,
) -> Result<SimRig, LabError> {
    let params = wire.rod_params(gravity.vector(), ftwire_lab::experiment::SIM_EDGES);
    let mut world = World::new(params).map_err(|e| from_sim(e, "building the simulated wire"))?;
    if obstacles {
        world = with_scene(world, scene).map_err(|e| from_sim(e, "the scene's obstacles"))?;
    }
    // The true wire's loaded model places it: its weight in the base clamp frame.
    let model = true_rod(wire, scene.base.rotation.inverse() * gravity.vector())?;
    place_in_world(world, &model, &scene.base, a0, config)
}

/// The model of a known wire held in `scene`: as [`super::known_model`], with the wire's
/// weight under `gravity` expressed in the scene's base clamp frame.
///
/// # Errors
/// Bad input for a wire whose parameters are not valid.
pub fn scene_model(
    wire: &WireSpec,
    gravity: Gravity,
    kind: ftwire_lab::experiment::ModelKind,
    scene: &Scene,
) -> Result<KirchhoffModel, LabError> {
    ftwire_lab::experiment::known_model_under(
        wire,
        scene.base.rotation.inverse() * gravity.vector(),
        kind,
    )
}

/// What one tracking attempt did, scored on the simulator's truth.
#[derive(Debug, Clone, Serialize)]
pub struct Attempt {
    /// `closed_loop` or `open_loop`.
    pub mode: &'static str,
    /// How it ended: a controller outcome's name, or `done` for a finished roll-out.
    pub outcome: String,
    /// Moves commanded.
    pub steps: usize,
    /// The true wire touched an obstacle at a rest.
    pub touched: bool,
    /// The collision detector flagged a move (it stopped the motion, or the retreat took the
    /// wire back and the leg went on).
    pub detected: bool,
    /// Retreats after a detection ([`MAX_RETREATS`] at most): each moved the second gripper
    /// back one move and ran the leg again.
    pub retreats: usize,
    /// Legs undone after the controller stopped them as diverged, on a sensor fault, or (under
    /// `increment` and `absolute` noise, [`reruns_unreachable`]) at a waypoint out of the arms'
    /// reach or on a second detection after a retreat ([`escalates`]) ([`MAX_UNDOS`] at most):
    /// each moved the second gripper back to the leg's start and ran the leg again.
    pub undone: usize,
    /// Intermediate waypoints passed over because the arms could not reach them (the closed
    /// loop moves on to the next; two in a row end the attempt).
    pub skipped: usize,
    /// Whether the closed loop moved both grippers by one translation to reach the goal
    /// ([`relocation`]; at most once an attempt).
    pub relocated: bool,
    /// `‖a_true − a_g‖` at the end \[normalised\] (the simulator's wrench).
    pub final_error: f64,
    /// The whole path was executed: every leg ended by reaching its waypoint or, between
    /// waypoints and on the last leg, by the iteration limit, or passed over an intermediate
    /// waypoint out of the arms' reach ([`Attempt::skipped`]) (closed loop); every move made
    /// (open loop).
    pub completed: bool,
    /// Ended within [`success_epsilon`] of the goal (true wrench).
    pub at_goal: bool,
    /// Success by [`success_rule`]: completed and never touched, and at the goal when
    /// [`success_needs_goal`].
    pub success: bool,
    /// The true shape against `Φ(γ_A(i/N))` at each waypoint reached \[mm\].
    pub shape_mm: Vec<f64>,
    /// The true centreline (world frame) at each rest, for figures.
    #[serde(skip)]
    pub centrelines: Vec<Vec<[f64; 3]>>,
    /// The true configuration (the simulator's base wrench) at the start and at each rest
    /// \[N·m, N\], for figures.
    #[serde(skip)]
    pub a_true: Vec<[f64; 6]>,
    /// Every leg the closed loop ran, in order, reruns included (empty for the open loop).
    #[serde(skip)]
    pub legs: Vec<Leg>,
}

/// One leg of the closed loop as it ran: what `waypoints.csv` lists.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Leg {
    /// The waypoint it steered to (1: the first after the start).
    pub waypoint: usize,
    /// Moves it made.
    pub moves: usize,
    /// How it ended: the controller outcome's name.
    pub outcome: String,
    /// The true shape against the waypoint's when it ended \[mm\].
    pub shape_mm: f64,
    /// Whether [`Attempt::shape_mm`] (Table IV) scores it: not when the leg was run again
    /// (after a retreat, an undo or a relocation) or its waypoint was passed over.
    pub scored: bool,
    /// The true wire touched an obstacle at one of its rests.
    pub touched: bool,
}

impl Attempt {
    /// `success` or `failure` in words, saying when a success by the paper's rule (under
    /// `increment`/`absolute` noise) did not end at the goal.
    pub fn verdict(&self) -> &'static str {
        match (self.success, self.at_goal) {
            (true, true) => "success",
            (true, false) => "success by the paper's rule (no contact), not at the goal",
            (false, _) => "failure",
        }
    }
}

/// One scenario of tracking: the true wire, the scene, the sensor's calibration, the noise.
#[derive(Debug, Clone, Copy)]
pub struct Tracking<'a> {
    /// The true wire (the simulator's).
    pub wire: &'a WireSpec,
    /// Gravity in the simulated world.
    pub gravity: Gravity,
    /// The scene (obstacles in the simulator, base pose).
    pub scene: &'a Scene,
    /// The learnt F/T calibration.
    pub calibration: &'a Calibration,
    /// The simulated sensor and rig (`--sensor`, `--rig`).
    pub setup: &'a SimSetup,
    /// Execution noise of the second gripper.
    pub noise: NoiseModel,
    /// The seed of the rig and of the noise.
    pub seed: u64,
    /// The controller's gain `K` (eq. 13; the paper's is 0.2,
    /// `ControlSettings::default().gain`).
    pub gain: f64,
    /// The closed loop's shape stop \[m\] on every leg (`ControlSettings::shape_tolerance`;
    /// 0: the `ε` stops of [`through_settings`] and [`goal_settings`]).
    pub shape_stop: f64,
    /// Most moves toward each waypoint before the last (`ControlSettings::max_iterations` of
    /// the legs between waypoints; [`through_settings`]'s by default, 20). Under `increment`
    /// a tighter shape stop needs more: every move lands the wire about 12 mm from where it
    /// was sent, and the stop waits for a landing within it.
    pub waypoint_moves: usize,
    /// The shape stop \[m\] of the legs from or to a waypoint near a box
    /// ([`near_obstacles`]); [`near_shape_stop`] of `shape_stop` by default.
    pub near_shape_stop: f64,
    /// Whether the closed loop checks each commanded pose against the SDA10F's arms (IK
    /// within joint limits, no arm collision) and stops at one they cannot reach; `false`
    /// ignores the arms' kinematics, as the paper's noise experiments do (eq. 13–14 do not
    /// see them).
    pub arms: bool,
    /// Whether the closed loop steers by `ã` corrected for the sensor's bias drift (one
    /// [`BiasObserver`] over the whole path; not under `absolute`, and each rest fused with
    /// the pose without noise and under `increment`, see [`bias_observer`]).
    pub bias_observer: bool,
}

/// The reach check of a closed-loop run: the robot's arms, or none.
enum TrackReach {
    Robot(Box<RobotReach>),
    Any(AnyPose),
}

impl ReachCheck for TrackReach {
    fn check(&mut self, relative: &Pose) -> Reach {
        match self {
            Self::Robot(robot) => robot.check(relative),
            Self::Any(any) => any.check(relative),
        }
    }
}

/// Truth of the rig at a rest: contact, centreline, base wrench in normalised units.
struct Truth {
    touched: bool,
    centreline: Vec<Point3<f64>>,
    a: Vector6<f64>,
}

fn truth_of(rig: &SimRig) -> Truth {
    let equilibrium = rig.equilibrium();
    Truth {
        touched: equilibrium
            .contact_forces
            .iter()
            .any(|f| f.norm() > CONTACT_FORCE),
        centreline: equilibrium.wire_centreline(),
        a: equilibrium.base_wrench.to_vector(),
    }
}

impl Tracking<'_> {
    /// The rig at the path's start, tared before the pick-up, wrapped in the execution noise,
    /// and its F/T feedback.
    fn rig(
        &self,
        start: &Vector6<f64>,
        obstacles: bool,
        stream: u64,
    ) -> Result<(NoisyRig<SimRig>, FtFeedback<Calibration>), LabError> {
        let config = self
            .setup
            .rig_config(self.seed ^ stream.wrapping_mul(0x9e37_79b9));
        let mut rig = place_in_scene(
            self.wire,
            self.gravity,
            self.scene,
            obstacles,
            start,
            config,
        )?;
        let tared: FtPipeline<Calibration> = pipeline(tare(&mut rig)?, self.calibration.clone())?;
        let noisy = NoisyRig::new(
            rig,
            self.noise,
            NoiseSettings::default(),
            self.seed.wrapping_add(stream),
        )
        .map_err(|e| LabError::bad_input(e.to_string()))?;
        Ok((noisy, FtFeedback::new(tared, SAMPLES_PER_REST)))
    }

    /// The bias observer's settings of the closed loop; `None` where it steers by the tared
    /// `ã` alone (switched off, or under `absolute`).
    pub fn observer_settings(&self) -> Option<BiasObserverSettings> {
        bias_observer(self.setup, self.noise, self.bias_observer)
    }

    /// Calibrates the collision detector on [`REHEARSALS`] rehearsals of the path with the
    /// obstacles away (free motion in the same conditions, each under its own noise draw), as a
    /// robot would before entering the passage: the threshold is the detector's default margin
    /// over the largest residual of those free moves (the miss against the model's Newton
    /// prediction over the default floor, `CollisionDetector::uncalibrated`).
    ///
    /// # Errors
    /// No answer when the rehearsal gives too few residuals.
    pub fn detector(
        &self,
        model: &KirchhoffModel,
        waypoints: &[Waypoint],
    ) -> Result<CollisionDetector, LabError> {
        let mut residuals = Vec::new();
        for stream in 1..=REHEARSALS {
            let (_, more) = self.closed_loop_with(model, waypoints, None, false, stream)?;
            residuals.extend(more);
        }
        CollisionDetector::calibrate(
            &residuals,
            CollisionDetector::DEFAULT_MARGIN,
            CollisionDetector::DEFAULT_FLOOR,
        )
        .map_err(|e| LabError::no_answer(format!("calibrating the collision detector: {e}")))
    }

    /// Tracks the waypoints closed loop with `detector` armed. A waypoint the controller
    /// refuses (outside its model's `A_stable`, an unreachable pose) ends the attempt, with
    /// the reason as its outcome.
    ///
    /// # Errors
    /// No answer when the rig cannot be placed at the start.
    pub fn closed_loop(
        &self,
        model: &KirchhoffModel,
        waypoints: &[Waypoint],
        detector: CollisionDetector,
        stream: u64,
    ) -> Result<Attempt, LabError> {
        self.closed_loop_with(model, waypoints, Some(detector), true, stream)
            .map(|(attempt, _)| attempt)
    }

    /// Tracks the waypoints closed loop with no collision detector (a scene with nothing to
    /// collide with, where it could only raise false alarms).
    ///
    /// # Errors
    /// As [`Tracking::closed_loop`].
    pub fn closed_loop_unarmed(
        &self,
        model: &KirchhoffModel,
        waypoints: &[Waypoint],
        stream: u64,
    ) -> Result<Attempt, LabError> {
        self.closed_loop_with(model, waypoints, None, true, stream)
            .map(|(attempt, _)| attempt)
    }

    /// Closed-loop tracking; returns the attempt and every move's detector residual.
    fn closed_loop_with(
        &self,
        model: &KirchhoffModel,
        waypoints: &[Waypoint],
        detector: Option<CollisionDetector>,
        obstacles: bool,
        stream: u64,
    ) -> Result<(Attempt, Vec<f64>), LabError> {
        let (Some(first), Some(last)) = (waypoints.first(), waypoints.last()) else {
            return Err(LabError::no_answer("an empty path"));
        };
        let (mut rig, feedback) = self.rig(&first.a, obstacles, stream)?;
        let mut reach = if self.arms {
            let robot = Robot::sda10f().map_err(|e| LabError::bad_input(e.to_string()))?;
            TrackReach::Robot(Box::new(RobotReach::new(
                robot,
                Pose::identity(),
                self.scene.base,
            )))
        } else {
            TrackReach::Any(AnyPose)
        };
        // Between waypoints the stop of `through_settings`; the goal to the controller's ε.
        // A leg run again after an undo, and the last quarter of a leg's budget: no tighter
        // than the default stop.
        let rerun_stop = rerun_shape_stop(self.noise, self.shape_stop);
        let through = ControlSettings {
            gain: self.gain,
            shape_tolerance: self.shape_stop,
            max_iterations: self.waypoint_moves,
            late_shape_tolerance: rerun_stop,
            late_after: late_after(self.waypoint_moves),
            ..through_settings(self.noise)
        };
        let end = ControlSettings {
            gain: self.gain,
            shape_tolerance: self.shape_stop,
            ..goal_settings(self.noise)
        };
        let build = |settings| {
            let controller = Controller::new(*model, settings)
                .map_err(|e| LabError::bad_input(e.to_string()))?;
            Ok::<_, LabError>(match detector {
                Some(d) => controller.with_detector(d),
                None => controller,
            })
        };
        // Legs from or to a waypoint near an obstacle: the looser shape stop there.
        let near_stop = self.near_shape_stop;
        let near = if near_stop == self.shape_stop {
            vec![false; waypoints.len()]
        } else {
            near_obstacles(self.scene, model.rod(), waypoints)?
        };
        let close = build(ControlSettings {
            shape_tolerance: near_stop,
            ..through
        })?;
        let rerun = |settings: ControlSettings| {
            build(ControlSettings {
                shape_tolerance: settings.shape_tolerance.max(rerun_stop),
                ..settings
            })
        };
        let (through_again, close_again, end_again) = (
            rerun(through)?,
            rerun(ControlSettings {
                shape_tolerance: near_stop,
                ..through
            })?,
            rerun(end)?,
        );
        let (through, end) = (build(through)?, build(end)?);
        // One observer follows the sensor from its tare over every leg.
        let mut observer = self
            .observer_settings()
            .map(|settings| BiasObserver::new(*model, settings))
            .transpose()
            .map_err(|e| LabError::bad_input(e.to_string()))?;
        // The last leg rests longer: its stop rule and the success are judged there.
        let end_feedback = FtFeedback::new(feedback.pipeline().clone(), GOAL_REST_SAMPLES);
        let mut attempt = Attempt {
            mode: "closed_loop",
            outcome: String::new(),
            steps: 0,
            touched: false,
            detected: false,
            retreats: 0,
            undone: 0,
            skipped: 0,
            relocated: false,
            final_error: f64::NAN,
            completed: false,
            at_goal: false,
            success: false,
            shape_mm: Vec::new(),
            centrelines: Vec::new(),
            a_true: Vec::new(),
            legs: Vec::new(),
        };
        let mut residuals = Vec::new();
        // The measured configuration where the last leg ended (the relocation's `a_now`).
        let mut estimate = first.a;
        let start = truth_of(rig.inner());
        let mut touched = start.touched;
        attempt.a_true.push(start.a.into());
        let mut i = 1;
        let mut skipped_last = None;
        // The waypoint whose leg was last undone: its reruns take the rerun stop.
        let mut undone_at = None;
        // The leg in progress and the pose its first run started from; the leg of the last
        // retreat ([`escalates`]).
        let mut leg_start: Option<(usize, Pose)> = None;
        let mut retreated_on = None;
        while let Some(waypoint) = waypoints.get(i) {
            let final_leg = i + 1 == waypoints.len();
            let again = undone_at == Some(i);
            let (controller, feedback) = match (final_leg, near[i] || near[i - 1], again) {
                (true, _, false) => (&end, &end_feedback),
                (true, _, true) => (&end_again, &end_feedback),
                (false, true, false) => (&close, &feedback),
                (false, true, true) => (&close_again, &feedback),
                (false, false, false) => (&through, &feedback),
                (false, false, true) => (&through_again, &feedback),
            };
            let mut centrelines = Vec::new();
            let mut leg_touched = false;
            let run = controller.run_estimated(
                &mut rig,
                feedback,
                &mut reach,
                &waypoint.a,
                observer.as_mut(),
                |r, _| {
                    let truth = truth_of(r.inner());
                    leg_touched |= truth.touched;
                    centrelines.push((truth.centreline, truth.a));
                },
            );
            touched |= leg_touched;
            // The controller refuses a waypoint it cannot steer to (outside its model's
            // A_stable, or from a pose the robot cannot hold): the attempt ends there, unless
            // the start is out of the arms' reach (the accumulated noise carried the gripper
            // there) and one translation of both grippers brings it, and the waypoint, back.
            // Else, under fresh noise, back to where the last leg run first started
            // ([`undoes_to_last_start`]).
            let previous = leg_start
                .filter(|(leg, _)| undoes_to_last_start(self.noise, Some(*leg), i, attempt.undone));
            let run = match run {
                Ok(run) => run,
                Err(e @ ControlError::UnreachableStart { .. }) => {
                    if self.arms && !attempt.relocated {
                        match self.relocate(&mut rig, model, &estimate, &waypoint.a)? {
                            Relocated::Moved(base) => {
                                reach = robot_reach(base)?;
                                attempt.relocated = true;
                                // The leg never ran: the last score is the waypoint before's.
                                touched |= extra_move(&mut attempt, rig.inner());
                                continue;
                            }
                            Relocated::NoneFound if previous.is_none() => {
                                attempt.outcome = format!(
                                    "refused at waypoint {i}: its start is out of the arms' \
                                     reach, and no translation of both grippers brings it back"
                                );
                                break;
                            }
                            Relocated::NoneFound => {}
                            Relocated::Refused(why) => {
                                attempt.outcome = why;
                                break;
                            }
                        }
                    }
                    let Some((leg, pose)) = previous else {
                        attempt.outcome = format!("refused at waypoint {i}: {e}");
                        break;
                    };
                    if let Err(e) = undo_leg(&mut attempt, &mut rig, pose, &mut touched) {
                        attempt.outcome = e;
                        break;
                    }
                    i = leg;
                    undone_at = Some(leg);
                    continue;
                }
                Err(e) => {
                    attempt.outcome = format!("refused at waypoint {i}: {e}");
                    break;
                }
            };
            let first_start = match leg_start {
                Some((leg, pose)) if leg == i => pose,
                _ => run.start_tip,
            };
            leg_start = Some((i, first_start));
            estimate = run.steps.last().map_or(run.start_estimate, |s| s.estimate);
            attempt.steps += run.steps.len();
            residuals.extend(run.steps.iter().map(|s| s.residual));
            for (centreline, a) in &centrelines {
                attempt.centrelines.push(to_points(centreline));
                attempt.a_true.push((*a).into());
            }
            let truth = truth_of(rig.inner());
            let error_mm = shape_mm(&truth.centreline, &waypoint.centreline)?;
            attempt.shape_mm.push(error_mm);
            attempt.outcome = run.outcome.name().to_owned();
            attempt.legs.push(Leg {
                waypoint: i,
                moves: run.steps.len(),
                outcome: attempt.outcome.clone(),
                shape_mm: error_mm,
                scored: true,
                touched: leg_touched,
            });
            match run.outcome {
                Outcome::Reached { .. } | Outcome::IterationLimit { .. } => {
                    attempt.completed = final_leg;
                }
                Outcome::CollisionDetected { .. } => {
                    attempt.detected = true;
                    // A second detection on a leg already retreated on: back to where the leg
                    // first started instead (see `escalates`).
                    if escalates(self.noise, retreated_on == Some(i)) && attempt.undone < MAX_UNDOS
                    {
                        if let Err(e) = undo_leg(&mut attempt, &mut rig, first_start, &mut touched)
                        {
                            attempt.outcome = e;
                            break;
                        }
                        undone_at = Some(i);
                        retreated_on = None;
                        continue;
                    }
                    if attempt.retreats >= MAX_RETREATS {
                        break;
                    }
                    // Retreat: back to the pose before the flagged move, then the same leg
                    // again with a fresh detector window.
                    if let Err(e) = step_back(&mut rig, &run) {
                        attempt.outcome = format!("retreat failed: {e}");
                        break;
                    }
                    attempt.retreats += 1;
                    retreated_on = Some(i);
                    unscore_last_leg(&mut attempt);
                    touched |= extra_move(&mut attempt, rig.inner());
                    continue;
                }
                // A leg thrown far from its waypoint, a rest with no usable measurement (the
                // sensor saturated by a wire pulled taut, or dropped out), or, under fresh noise
                // per move, a waypoint the noise carried out of the arms' reach: back to where
                // the leg started (a pose the arms held), then again.
                ref outcome if undoes(outcome, self.noise) && attempt.undone < MAX_UNDOS => {
                    if let Err(e) = undo_leg(&mut attempt, &mut rig, run.start_tip, &mut touched) {
                        attempt.outcome = e;
                        break;
                    }
                    undone_at = Some(i);
                    continue;
                }
                // The goal out of the arms' reach: one translation of both grippers (the
                // wire's configuration unchanged) that brings it back, then the leg again.
                Outcome::Unreachable { .. } if final_leg && self.arms && !attempt.relocated => {
                    match self.relocate(&mut rig, model, &estimate, &last.a)? {
                        Relocated::Moved(base) => {
                            reach = robot_reach(base)?;
                            attempt.relocated = true;
                            unscore_last_leg(&mut attempt);
                            touched |= extra_move(&mut attempt, rig.inner());
                            continue;
                        }
                        // No translation found: the outcome stays the controller's.
                        Relocated::NoneFound => break,
                        Relocated::Refused(why) => {
                            attempt.outcome = why;
                            break;
                        }
                    }
                }
                // An intermediate waypoint the arms cannot reach (the run's grasp offset or
                // the accumulated noise moved its pose beyond them) is passed over once: the
                // leg to the next waypoint starts from where the wire is. The waypoint is not
                // scored; a second unreachable waypoint in a row ends the attempt.
                Outcome::Unreachable { .. } if may_pass_over(i, final_leg, skipped_last) => {
                    unscore_last_leg(&mut attempt);
                    attempt.skipped += 1;
                    skipped_last = Some(i);
                }
                _ => break,
            }
            i += 1;
        }
        attempt.touched = touched;
        self.finish(&mut attempt, rig.inner(), &last.a, model);
        Ok((attempt, residuals))
    }

    /// Moves both grippers by the [`relocation`] from the wire measured at `a_now` toward
    /// `a_goal`.
    ///
    /// # Errors
    /// As [`relocation`]; no answer when the rig cannot report its poses.
    fn relocate(
        &self,
        rig: &mut NoisyRig<SimRig>,
        model: &KirchhoffModel,
        a_now: &Vector6<f64>,
        a_goal: &Vector6<f64>,
    ) -> Result<Relocated, LabError> {
        let poses = rig
            .gripper_poses()
            .map_err(|e| LabError::no_answer(e.to_string()))?;
        let Some(base) = relocation(self.scene, self.noise, model, &poses, a_now, a_goal)? else {
            return Ok(Relocated::NoneFound);
        };
        let command = Command {
            base,
            tip: base * poses.relative(),
        };
        Ok(match rig.command(&command) {
            Ok(()) => Relocated::Moved(base),
            Err(e) => Relocated::Refused(format!("relocation failed: {e}")),
        })
    }

    /// Rolls the planned gripper poses out with no feedback.
    ///
    /// # Errors
    /// No answer when the rig cannot be placed at the start.
    pub fn open_loop(
        &self,
        model: &KirchhoffModel,
        waypoints: &[Waypoint],
        stream: u64,
    ) -> Result<Attempt, LabError> {
        let (Some(first), Some(last)) = (waypoints.first(), waypoints.last()) else {
            return Err(LabError::no_answer("an empty path"));
        };
        let (mut rig, _) = self.rig(&first.a, true, stream)?;
        let poses: Vec<Pose> = waypoints.iter().map(|w| w.tip).collect();
        let start = truth_of(rig.inner());
        let mut attempt = Attempt {
            mode: "open_loop",
            outcome: "done".to_owned(),
            steps: 0,
            touched: start.touched,
            detected: false,
            retreats: 0,
            undone: 0,
            skipped: 0,
            relocated: false,
            final_error: f64::NAN,
            completed: false,
            at_goal: false,
            success: false,
            shape_mm: Vec::new(),
            centrelines: Vec::new(),
            a_true: vec![start.a.into()],
            legs: Vec::new(),
        };
        let mut truths = Vec::new();
        let rolled = ftwire_control::open_loop::roll_out::<_, Calibration>(
            &mut rig,
            &poses,
            None,
            |r, k| truths.push((k, truth_of(r.inner()))),
        )
        .map_err(|e| LabError::no_answer(e.to_string()))?;
        attempt.steps = rolled.moves;
        match rolled.failed {
            Some((k, message)) => attempt.outcome = format!("move {k} failed: {message}"),
            None => attempt.completed = true,
        }
        for (k, truth) in &truths {
            attempt.touched |= truth.touched;
            attempt.centrelines.push(to_points(&truth.centreline));
            attempt.a_true.push(truth.a.into());
            // `roll_out` numbers its moves from 0: move k ends at waypoint k + 1.
            if let Some(waypoint) = waypoints.get(k + 1) {
                attempt
                    .shape_mm
                    .push(shape_mm(&truth.centreline, &waypoint.centreline)?);
            }
        }
        self.finish(&mut attempt, rig.inner(), &last.a, model);
        Ok(attempt)
    }

    /// The final error on the true wrench, and success.
    fn finish(
        &self,
        attempt: &mut Attempt,
        rig: &SimRig,
        goal: &Vector6<f64>,
        model: &KirchhoffModel,
    ) {
        let truth = truth_of(rig);
        let wire = model.wire();
        let error = (to_normalised(wire, &truth.a) - to_normalised(wire, goal)).norm();
        attempt.final_error = error;
        (attempt.at_goal, attempt.success) =
            judge(self.noise, attempt.completed, attempt.touched, error);
    }
}

/// What [`Tracking::relocate`] did.
enum Relocated {
    /// Both grippers moved; the new base pose (world frame).
    Moved(Pose),
    /// No translation brings the poses back into the arms' reach; nothing moved.
    NoneFound,
    /// The rig refused the move: the attempt's outcome.
    Refused(String),
}

/// The arms' reach with the base gripper at `base` (world frame).
///
/// # Errors
/// Bad input when the robot's description cannot be loaded.
fn robot_reach(base: Pose) -> Result<TrackReach, LabError> {
    Ok(TrackReach::Robot(Box::new(RobotReach::new(
        Robot::sda10f().map_err(|e| LabError::bad_input(e.to_string()))?,
        Pose::identity(),
        base,
    ))))
}

/// Moves the second gripper back to where it was before the last move of `run` (the one the
/// collision detector flagged): the pose the robot reported after the move before it, or the
/// run's start.
fn step_back<R: Rig>(rig: &mut R, run: &Run) -> Result<(), LabError> {
    let Some((_, before)) = run.steps.split_last() else {
        return Ok(());
    };
    let back = before.last().map_or(run.start_tip, |s| s.tip);
    rig.move_tip(rig_base(rig)? * back)
        .map_err(|e| LabError::no_answer(e.to_string()))
}

/// The base gripper's pose as the robot reports it.
fn rig_base<R: Rig>(rig: &R) -> Result<Pose, LabError> {
    rig.gripper_poses()
        .map(|poses| poses.base)
        .map_err(|e| LabError::no_answer(e.to_string()))
}

/// `waypoints.csv`: every closed-loop leg of every run, numbered by `label` (`pair`,
/// `attempt`): its waypoint, the moves it made, how it ended, the true shape error then, whether
/// Table IV scores it (not when it was run again or its waypoint passed over), and whether the
/// true wire touched an obstacle during it.
///
/// # Errors
/// As [`CsvTable::row`].
pub fn waypoints_csv(label: &str, closed: &[Attempt]) -> Result<Vec<u8>, LabError> {
    let mut csv = CsvTable::new(
        "waypoints.csv",
        &[
            label, "waypoint", "moves", "outcome", "shape_mm", "scored", "touched",
        ],
    )?;
    for (k, attempt) in closed.iter().enumerate() {
        for leg in &attempt.legs {
            csv.row([
                value(k),
                value(leg.waypoint),
                value(leg.moves),
                text(&leg.outcome),
                fixed(leg.shape_mm, 3),
                value(leg.scored),
                value(leg.touched),
            ])?;
        }
    }
    csv.into_bytes()
}

/// Drops the score of the leg that just ran: its waypoint was not reached (Table IV scores the
/// rerun) or is passed over.
fn unscore_last_leg(attempt: &mut Attempt) {
    attempt.shape_mm.pop();
    if let Some(leg) = attempt.legs.last_mut() {
        leg.scored = false;
    }
}

/// Undoes a leg: the second gripper back to `start`, a pose a run of it started from (one the
/// arms held; relative to the base gripper), the leg unscored and counted in
/// [`Attempt::undone`]; `touched` records the move's rest. The message says why the undo
/// failed.
fn undo_leg(
    attempt: &mut Attempt,
    rig: &mut NoisyRig<SimRig>,
    start: Pose,
    touched: &mut bool,
) -> Result<(), String> {
    let base = rig_base(rig).map_err(|e| format!("undo failed: {e}"))?;
    rig.move_tip(base * start)
        .map_err(|e| format!("undo failed: {e}"))?;
    attempt.undone += 1;
    unscore_last_leg(attempt);
    *touched |= extra_move(attempt, rig.inner());
    Ok(())
}

/// Records a move the closed loop made outside a controller run (a retreat, an undo, a
/// relocation) before it runs a leg again; the rest's truth is kept. Returns whether the wire
/// touched.
fn extra_move(attempt: &mut Attempt, rig: &SimRig) -> bool {
    attempt.steps += 1;
    let truth = truth_of(rig);
    attempt.centrelines.push(to_points(&truth.centreline));
    attempt.a_true.push(truth.a.into());
    truth.touched
}

fn to_points(centreline: &[Point3<f64>]) -> Vec<[f64; 3]> {
    centreline.iter().map(|p| [p.x, p.y, p.z]).collect()
}

/// Mean distance \[mm\] between two centrelines (world frame).
fn shape_mm(truth: &[Point3<f64>], planned: &[Point3<f64>]) -> Result<f64, LabError> {
    let a: Vec<Vector3<f64>> = truth.iter().map(|p| p.coords).collect();
    let b: Vec<Vector3<f64>> = planned.iter().map(|p| p.coords).collect();
    centreline_distance(&a, &b, DEFAULT_METRIC_SAMPLES)
        .map(|d| 1e3 * d)
        .map_err(|e| LabError::no_answer(format!("the shape error: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_success_tolerance_holds_the_stop_rule_of_the_noise() {
        assert_eq!(success_epsilon(NoiseModel::None), SUCCESS_EPSILON);
        assert_eq!(success_epsilon(NoiseModel::Offset), SUCCESS_EPSILON);
        // Without noise and under `offset` the stop aims well inside the tolerance, leaving
        // room for the sensor's drift between the stop's reading and the truth.
        for noise in [NoiseModel::None, NoiseModel::Offset] {
            assert!(goal_settings(noise).epsilon <= 0.25 * SUCCESS_EPSILON);
        }
        assert_eq!(success_epsilon(NoiseModel::Increment), 2.0 * EPSILON_NOISY);
        assert_eq!(
            goal_settings(NoiseModel::Absolute).max_iterations,
            MAX_ITERATIONS_NOISY
        );
    }

    #[test]
    fn reexpressed_waypoints_keep_the_poses_and_take_the_loaded_configurations() {
        let wire =
            ftwire_core::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire");
        let weightless = KirchhoffModel::new(wire);
        let load = ftwire_rod::Load::from_gravity(6450.0, 0.0015, Vector3::new(0.0, 0.0, -9.81))
            .expect("valid load");
        let loaded = weightless.with_load(load);
        let base = Pose::translation(0.1, 0.0, 0.3);
        let waypoints: Vec<Waypoint> = [
            Vector6::new(0.5, 2.0, 1.0, -2.0, 3.0, 0.5),
            Vector6::new(0.35, 2.5, 0.75, -1.5, 2.5, 0.75),
            Vector6::new(0.2, 3.0, 0.5, -1.0, 2.0, 1.0),
        ]
        .iter()
        .map(|n| {
            let a = ftwire_rod::from_normalised(&wire, n);
            Waypoint {
                a,
                tip: weightless.tip(&a).expect("solves"),
                centreline: Vec::new(),
            }
        })
        .collect();
        // The same model gives the same configurations back.
        let same = reexpress(&waypoints, &weightless, &base).expect("re-expressed");
        for (w, r) in waypoints.iter().zip(&same) {
            assert!((w.a - r.a).norm() < 1e-8, "{:?} against {:?}", r.a, w.a);
        }
        // The loaded model: the same poses, other wrenches, its own shapes.
        let heavy = reexpress(&waypoints, &loaded, &base).expect("re-expressed");
        for (w, r) in waypoints.iter().zip(&heavy) {
            let miss = ftwire_rod::se3::log(&(w.tip.inverse() * loaded.tip(&r.a).expect("solves")));
            assert!(miss.norm() < 1e-9, "{miss:?}");
            assert!((w.a - r.a).norm() > 1e-3, "the weight changes the wrench");
            let shape = loaded.shape(&r.a, r.centreline.len()).expect("solves");
            let first = base * Point3::from(shape.positions[1]);
            assert!((r.centreline[1] - first).norm() < 1e-12);
        }
    }

    #[test]
    fn the_verdict_says_when_a_success_is_not_at_the_goal() {
        let attempt = |success, at_goal| Attempt {
            mode: "open_loop",
            outcome: "done".to_owned(),
            steps: 12,
            touched: false,
            detected: false,
            retreats: 0,
            undone: 0,
            skipped: 0,
            relocated: false,
            final_error: 14.0,
            completed: true,
            at_goal,
            success,
            shape_mm: Vec::new(),
            centrelines: Vec::new(),
            a_true: Vec::new(),
            legs: Vec::new(),
        };
        assert_eq!(attempt(true, true).verdict(), "success");
        assert!(attempt(true, false).verdict().contains("not at the goal"));
        assert_eq!(attempt(false, true).verdict(), "failure");
    }

    #[test]
    fn a_relocation_is_one_clear_axis_translation_from_which_the_arms_reach() {
        let scene = Scene::from_toml(ftwire_lab::scene::PASSAGE, "passage.toml").expect("scene");
        let wire =
            ftwire_core::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire");
        let rod = Rod::new(wire);
        let goal = ftwire_plan::scene_configuration(&scene, &rod, "goal").expect("goal");
        let tip = scene.base * KirchhoffModel::new(wire).tip(&goal.a).expect("solves");
        let poses = GripperPoses {
            base: scene.base,
            tip,
        };
        let model = KirchhoffModel::new(wire);
        let base = relocation(&scene, NoiseModel::Offset, &model, &poses, &goal.a, &goal.a)
            .expect("runs")
            .expect("the passage's goal has room around it");
        assert_eq!(base.rotation, scene.base.rotation, "a pure translation");
        let t = base.translation.vector - scene.base.translation.vector;
        let along = t.iter().filter(|c| c.abs() > 1e-12).count();
        assert_eq!(along, 1, "along one axis: {t:?}");
        assert!(
            RELOCATION_STEPS
                .iter()
                .any(|s| (t.norm() - s).abs() < 1e-12)
        );
        let robot = Robot::sda10f().expect("robot");
        let checker =
            Checker::new(rod, robot, &scene, validity(NoiseModel::Offset, 0.82)).expect("ok");
        assert!(checker.endpoint(&Config { a: goal.a, base }).is_ok());
        // A relative pose no base near here reaches (the grippers 3 m apart): none.
        let far = GripperPoses {
            base: scene.base,
            tip: scene.base * Pose::translation(3.0, 0.0, 0.0),
        };
        assert_eq!(
            relocation(&scene, NoiseModel::Offset, &model, &far, &goal.a, &goal.a).expect("runs"),
            None
        );
    }

    #[test]
    fn legs_near_a_box_stop_looser_only_under_the_paper_noise_with_the_shape_stop_on() {
        let default = |noise| near_shape_stop(noise, default_shape_stop(noise));
        assert_eq!(default(NoiseModel::Increment), SHAPE_STOP_NEAR_NOISY);
        assert_eq!(default(NoiseModel::Absolute), SHAPE_STOP_NEAR_NOISY);
        const { assert!(SHAPE_STOP_NEAR_NOISY > SHAPE_STOP_NOISY) };
        // Off stays off, and a user's looser stop is kept.
        assert_eq!(default(NoiseModel::Offset), 0.0);
        assert_eq!(default(NoiseModel::None), 0.0);
        assert_eq!(near_shape_stop(NoiseModel::Increment, 0.0), 0.0);
        assert_eq!(near_shape_stop(NoiseModel::Increment, 0.02), 0.02);
        assert_eq!(near_shape_stop(NoiseModel::Offset, 0.004), 0.004);
    }

    #[test]
    fn a_leg_run_again_after_an_undo_stops_no_tighter_than_the_default() {
        for noise in [NoiseModel::Increment, NoiseModel::Absolute] {
            let default = default_shape_stop(noise);
            assert_eq!(rerun_shape_stop(noise, 0.0035), default);
            assert_eq!(rerun_shape_stop(noise, default), default);
            assert_eq!(rerun_shape_stop(noise, 0.008), 0.008);
            // The ε stop alone stays the ε stop.
            assert_eq!(rerun_shape_stop(noise, 0.0), 0.0);
        }
        for noise in [NoiseModel::None, NoiseModel::Offset] {
            assert_eq!(rerun_shape_stop(noise, 0.0), 0.0);
            assert_eq!(rerun_shape_stop(noise, 0.002), 0.002);
        }
    }

    #[test]
    fn the_last_quarter_of_a_legs_budget_stops_no_tighter_than_the_default() {
        assert_eq!(late_after(500), 375);
        assert_eq!(late_after(20), 15);
        assert_eq!(late_after(1), 1);
        let noise = NoiseModel::Increment;
        let settings = |stop: f64| ControlSettings {
            shape_tolerance: stop,
            late_shape_tolerance: rerun_shape_stop(noise, stop),
            late_after: late_after(500),
            ..through_settings(noise)
        };
        let tight = settings(0.0035);
        assert_eq!(tight.shape_stop_at(374), 0.0035);
        assert_eq!(tight.shape_stop_at(375), default_shape_stop(noise));
        // At the default stop nothing changes.
        let default = settings(default_shape_stop(noise));
        assert_eq!(default.shape_stop_at(499), default_shape_stop(noise));
    }

    #[test]
    fn a_wire_through_the_passage_gap_is_near_its_boxes_and_one_above_the_wall_is_not() {
        let scene = Scene::from_toml(ftwire_lab::scene::PASSAGE, "passage.toml").expect("scene");
        let wire =
            ftwire_core::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire");
        // A straight wire across the wall's plane (y = 0.05) at `x`, `z`.
        let across = |x: f64, z: f64| Waypoint {
            a: Vector6::zeros(),
            tip: Pose::identity(),
            centreline: (0..=40)
                .map(|k| Point3::new(x, 0.25 - 0.01 * f64::from(k), z))
                .collect(),
        };
        let near = near_obstacles(
            &scene,
            &Rod::new(wire),
            &[
                // The gap's middle: 25 mm to each box, 23.5 mm from the wire's surface.
                across(0.6, 0.35),
                // 30 mm above the wall: 28.5 mm.
                across(0.6, 0.43),
                // Through the back block.
                across(0.45, 0.35),
                // Far above.
                across(0.6, 0.7),
            ],
        )
        .expect("runs");
        assert_eq!(near, [true, false, true, false]);
    }

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
    fn a_noisy_plan_is_polished_for_landings_two_standard_deviations_off() {
        let noise = NoiseSettings::default();
        let params = polish_params();
        let landing = params.landing.expect("the landings are polished");
        assert_eq!(landing.position, 2.0 * noise.position_std);
        assert_eq!(landing.rotation, 2.0 * noise.orientation_std);
        assert_eq!(params.target, MARGIN_NOISY);
        // The rest as the plain polish.
        assert_eq!(
            PolishParams {
                target: PolishParams::default().target,
                landing: None,
                ..params
            },
            PolishParams::default()
        );
    }

    #[test]
    fn a_noisy_plan_keeps_seven_percent_of_its_length_as_slack_up_to_that_of_the_820_mm_wire() {
        for noise in [NoiseModel::Increment, NoiseModel::Absolute] {
            // Up to 820 mm: 93 % of the length.
            assert_eq!(max_span(noise, 0.63), MAX_SPAN_NOISY);
            assert_eq!(max_span(noise, 0.82), MAX_SPAN_NOISY);
            // Longer: the same 57.4 mm of slack.
            for length in [0.91, 0.92, 1.5] {
                let slack = (1.0 - max_span(noise, length)) * length;
                assert!((slack - 0.0574).abs() < 1e-12, "{length}: {slack}");
                assert!(max_span(noise, length) > MAX_SPAN_NOISY);
            }
        }
    }

    #[test]
    fn one_plan_is_made_without_a_choice_where_the_loop_converges() {
        let wire = WireSpec::preset("nitinol-3mm-820").expect("a preset");
        let scene = Scene::from_toml(ftwire_lab::scene::PASSAGE, "passage.toml").expect("scene");
        let loaded = scene_model(
            &wire,
            Gravity::On,
            ftwire_lab::experiment::ModelKind::Loaded,
            &scene,
        )
        .expect("the loaded model");
        let planner = Rod::new(*loaded.wire());
        let noise = NoiseModel::Offset;
        let validity = validity_tracked(noise, loaded.rod());
        let prepare = |planned: &ScenePlan| {
            waypoints_along(
                loaded.rod(),
                &scene.base,
                &planned.plan.path.waypoints,
                WAYPOINTS,
            )
        };
        let choose = |candidates| {
            choose_plan(
                &scene,
                &planner,
                loaded.rod(),
                validity,
                noise,
                3,
                candidates,
                false,
                prepare,
            )
        };
        let err = choose(0).expect_err("no plan to make");
        assert!(err.to_string().contains("--plan-candidates 0"), "{err}");
        // Under `offset`, four candidates asked for: the one plan `plan_in_scene` makes.
        let chosen = choose(4).expect("a path");
        assert!(chosen.choice.is_none());
        assert!(chosen.polish.is_none());
        let (alone, _) = plan_in_scene(&scene, &planner, validity, 3).expect("a path");
        let a = |path: &ftwire_plan::Path| -> Vec<Vector6<f64>> {
            path.waypoints.iter().map(|w| w.config.a).collect()
        };
        assert_eq!(a(&chosen.planned.plan.path), a(&alone.plan.path));
        assert_eq!(chosen.waypoints, prepare(&alone).expect("waypoints"));
        // The first candidate plans from the run's seed; the others from seeds of their own.
        assert_eq!(candidate_seed(3, 0), 3);
        let seeds: std::collections::BTreeSet<u64> = (0..8).map(|k| candidate_seed(3, k)).collect();
        assert_eq!(seeds.len(), 8);
    }

    #[test]
    fn the_910_mm_wire_plans_through_the_shipped_passage_under_the_paper_noise() {
        // The demo's default wire: at 93 % of its length it had no path there.
        let wire = WireSpec::preset("nitinol-3mm-910").expect("a preset");
        let scene = Scene::from_toml(ftwire_lab::scene::PASSAGE, "passage.toml").expect("scene");
        let loaded = scene_model(
            &wire,
            Gravity::On,
            ftwire_lab::experiment::ModelKind::Loaded,
            &scene,
        )
        .expect("the loaded model");
        let noise = NoiseModel::Increment;
        let params = validity_tracked(noise, loaded.rod());
        assert!(params.max_span > MAX_SPAN_NOISY);
        let planner = Rod::new(*loaded.wire());
        let (planned, checker) = plan_in_scene(&scene, &planner, params, 0).expect("a path");
        let waypoints = &planned.plan.path.waypoints;
        assert!(waypoints.len() >= 2);
        // Every waypoint keeps the noisy margins: clear of the boxes by 15 mm, slack.
        for w in waypoints {
            assert!(checker.clearance(&w.config).expect("solves") >= MARGIN_NOISY - 1e-9);
        }
    }

    #[test]
    fn a_start_out_of_reach_goes_back_to_the_last_legs_start_only_under_fresh_noise() {
        for noise in [
            NoiseModel::None,
            NoiseModel::Offset,
            NoiseModel::Increment,
            NoiseModel::Absolute,
        ] {
            let fresh = reruns_unreachable(noise);
            // The leg before the refused waypoint 5 ran: undone where the rerun lands afresh.
            assert_eq!(
                undoes_to_last_start(noise, Some(4), 5, 0),
                fresh,
                "{noise:?}"
            );
            assert_eq!(
                undoes_to_last_start(noise, Some(4), 5, MAX_UNDOS - 1),
                fresh
            );
            // Leg 5 ran, and its undo landed out of reach: back to where it first started.
            assert_eq!(undoes_to_last_start(noise, Some(5), 5, 1), fresh);
            // No undo left, no leg run yet, or the leg before was passed over.
            assert!(!undoes_to_last_start(noise, Some(4), 5, MAX_UNDOS));
            assert!(!undoes_to_last_start(noise, None, 1, 0));
            assert!(!undoes_to_last_start(noise, Some(3), 5, 0));
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
        for noise in [
            NoiseModel::None,
            NoiseModel::Offset,
            NoiseModel::Increment,
            NoiseModel::Absolute,
        ] {
            // Fresh noise per move: the rerun does not meet the same pose again. One offset
            // per run, or none: it would, so the waypoint is passed over (or the goal
            // relocated) as before.
            assert_eq!(undoes(&unreachable, noise), reruns_unreachable(noise));
            assert!(undoes(&diverged, noise) && undoes(&fault, noise));
            // A retreat, not an undo, answers a detection; the rest end or finish the leg.
            assert!(others.iter().all(|o| !undoes(o, noise)), "{noise:?}");
        }
        assert!(reruns_unreachable(NoiseModel::Increment));
        assert!(reruns_unreachable(NoiseModel::Absolute));
        assert!(!reruns_unreachable(NoiseModel::Offset));
        assert!(!reruns_unreachable(NoiseModel::None));
    }

    #[test]
    fn a_second_detection_on_a_leg_undoes_it_only_under_fresh_noise() {
        for noise in [NoiseModel::Increment, NoiseModel::Absolute] {
            assert!(
                !escalates(noise, false),
                "the first detection retreats one move"
            );
            assert!(escalates(noise, true));
        }
        // One offset per run, or none: a detection keeps retreating one move at a time.
        for noise in [NoiseModel::Offset, NoiseModel::None] {
            assert!(!escalates(noise, false) && !escalates(noise, true));
        }
    }

    #[test]
    fn success_needs_the_goal_only_where_the_noise_allows_reaching_it() {
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
        for noise in [NoiseModel::None, NoiseModel::Offset, NoiseModel::Increment] {
            assert_eq!(
                success_rule(noise).contains("paper"),
                !success_needs_goal(noise)
            );
            for length in [0.63, 0.82, 0.92, 2.0] {
                let span = max_span(noise, length);
                assert!(span <= 1.0 && span > 0.5);
            }
        }
        assert_eq!(
            validity(NoiseModel::Increment, 0.82).max_span,
            MAX_SPAN_NOISY
        );
        assert_eq!(validity(NoiseModel::Absolute, 0.82).margin, MARGIN_NOISY);
        assert_eq!(
            validity(NoiseModel::Offset, 0.82),
            ValidityParams::default()
        );
        assert_eq!(max_span(NoiseModel::Offset, 0.91), 1.0);
        // The stability margin, on the tracking model's folds, only under the paper's noise.
        let tracker = Rod::new(
            ftwire_core::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("wire"),
        )
        .with_load(
            ftwire_rod::Load::from_gravity(6450.0, 0.0015, Vector3::new(0.0, 0.0, -9.81))
                .expect("load"),
        );
        let noisy = validity_tracked(NoiseModel::Increment, &tracker);
        assert_eq!(noisy.stability_margin, STABILITY_MARGIN_NOISY);
        assert_eq!(noisy.stability_model, Some(tracker));
        assert_eq!(
            validity_tracked(NoiseModel::Offset, &tracker),
            ValidityParams::default()
        );
    }
}
