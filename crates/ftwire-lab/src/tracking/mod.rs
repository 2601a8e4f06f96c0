//! Tracking a plan in the simulator (paper §III-D, §IV-E): the demo's phase 5 and the
//! tracking experiments' building blocks, around the libraries that do the work
//! (`ftwire_plan::choose_plan` and its policy, `ftwire_control::PathTracker` and its
//! `TrackingPolicy`).
//!
//! - [`place_in_scene`]: the simulated rig with the base clamp at the scene's base pose, the
//!   scene's obstacles (the same file the planner read) and the true wire at a configuration.
//! - [`Tracking::closed_loop`]: the `PathTracker` along the waypoints with the collision
//!   detector armed, the simulator's truth read at every rest through the tracker's observer;
//!   [`Tracking::open_loop`]: the planned gripper poses with no feedback. Both under the
//!   execution noise of [`NoiseModel`], both scored on the simulator's truth: whether the true
//!   wire touched an obstacle at any rest ([`touches`]), and its shape against `Φ(γ_A)` at
//!   each waypoint.
//! - [`RolloutParams`]: the settings of the experiments that roll a plan out.

use ftwire_control::{
    AnyPose, BiasObserverParams, CollisionDetector, ControlError, FtFeedback, NoiseModel,
    NoiseParams, NoisyRig, PathTracker, Reach, ReachCheck, Relocate, Rest, RobotReach,
    TrackingPolicy, configuration_at,
};
use ftwire_core::{GripperPoses, Pose};
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::ft::FtPipeline;
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_plan::{PlanError, PlanPolicy, Scene, ValidityParams, Waypoint, near_obstacles};
use ftwire_robot::Robot;
use ftwire_rod::{Rod, to_normalised};
use ftwire_sim::{RigParams, SimRig, World};
use nalgebra::{Point3, Vector6};

mod attempt;
mod rollout;
mod truth;

pub use attempt::{Attempt, Leg};
pub use rollout::{RolloutOptions, RolloutParams};
pub use truth::{CONTACT_FORCE, touches};
use truth::{TruthLog, shape_mm, to_points, truth_of};

use crate::csv_table::{CsvTable, fixed, text, value};
use crate::error::{LabError, from_plan, from_sim};
use crate::experiment::rig::{
    SAMPLES_PER_REST, bias_observer, pipeline, place_in_world, tare, true_rod,
};
use crate::experiment::{Gravity, ModelKind, SIM_EDGES, known_model_under};
use crate::scene::with_scene;
use crate::setup::SimSetup;
use crate::wire::WireSpec;

/// Most rehearsals [`Tracking::detector`] runs.
pub const REHEARSALS: u64 = 5;

/// The planning side's policy for a plan tracked under `noise`: where every move lands the
/// gripper with fresh noise (`increment`, `absolute`), the wider margins, the polish and the
/// choice for the scatter of [`NoiseParams`]' default (the paper's noise); the planner's
/// defaults otherwise, where the loop converges onto the plan.
pub fn plan_policy(noise: NoiseModel) -> PlanPolicy {
    match noise {
        NoiseModel::Increment | NoiseModel::Absolute => {
            let settings = NoiseParams::default();
            PlanPolicy::scattered(settings.position_std, settings.orientation_std)
        }
        NoiseModel::None | NoiseModel::Offset => PlanPolicy::converging(),
    }
}

/// A planning error in a command's words, for `ftwire_plan::choose_plan`, whose `prepare`
/// step may fail with a [`LabError`] of its own.
#[derive(Debug)]
pub struct PlanFailure(pub LabError);

impl From<PlanError> for PlanFailure {
    fn from(error: PlanError) -> Self {
        Self(from_plan(error, "planning in the scene"))
    }
}

impl From<PlanFailure> for LabError {
    fn from(failure: PlanFailure) -> Self {
        failure.0
    }
}

/// A library error of the tracker in a command's words: a rig or a relocation that failed is
/// no answer; everything else (a setting) is bad input.
fn from_control(error: ControlError) -> LabError {
    match error {
        ControlError::Rig { .. } | ControlError::Relocation { .. } | ControlError::EmptyPath => {
            LabError::no_answer(error.to_string())
        }
        _ => LabError::bad_input(error.to_string()),
    }
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
    config: RigParams,
) -> Result<SimRig, LabError> {
    let params = crate::wire::rod_params(wire, gravity.vector(), SIM_EDGES);
    let mut world = World::new(params).map_err(|e| from_sim(e, "building the simulated wire"))?;
    if obstacles {
        world = with_scene(world, scene).map_err(|e| from_sim(e, "the scene's obstacles"))?;
    }
    // The true wire's loaded model places it: its weight in the base clamp frame.
    let model = true_rod(wire, scene.base.rotation.inverse() * gravity.vector())?;
    place_in_world(world, &model, &scene.base, a0, config)
}

/// The model of a known wire held in `scene`: as [`crate::experiment::known_model`], with the
/// wire's weight under `gravity` expressed in the scene's base clamp frame.
///
/// # Errors
/// Bad input for a wire whose parameters are not valid.
pub fn scene_model(
    wire: &WireSpec,
    gravity: Gravity,
    kind: ModelKind,
    scene: &Scene,
) -> Result<KirchhoffModel, LabError> {
    known_model_under(wire, scene.base.rotation.inverse() * gravity.vector(), kind)
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
    /// How the closed loop executes the path: the gain, the shape stops (`--shape-stop`,
    /// `--near-shape-stop`), each leg's move budget (`--waypoint-moves`), the recoveries and
    /// the success rule (`TrackingPolicy::for_noise` of [`Tracking::noise`] by default).
    pub policy: TrackingPolicy,
    /// Whether the closed loop checks each commanded pose against the SDA10F's arms (IK
    /// within joint limits, no arm collision) and stops at one they cannot reach (relocating
    /// the grippers once, `ftwire_plan::relocation`); `false` ignores the arms' kinematics,
    /// as the paper's noise experiments do (eq. 13–14 do not see them).
    pub arms: bool,
    /// Whether the closed loop steers by `ã` corrected for the sensor's bias drift (one
    /// `BiasObserver` over the whole path; not under `absolute`, and each rest fused with
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

/// The arms' reach with the base gripper at `base` (world frame).
fn robot_reach(base: Pose) -> Result<TrackReach, ControlError> {
    Ok(TrackReach::Robot(Box::new(RobotReach::new(
        Robot::sda10f()?,
        Pose::identity(),
        base,
    ))))
}

/// The relocation of both grippers in the scene ([`ftwire_plan::relocation`]), with the
/// margins of a plan tracked under the run's noise.
struct SceneRelocation<'a> {
    scene: &'a Scene,
    policy: PlanPolicy,
    rod: &'a Rod,
    steps: [f64; 4],
}

impl Relocate<TrackReach> for SceneRelocation<'_> {
    fn relocation(
        &mut self,
        poses: &GripperPoses,
        a_now: &Vector6<f64>,
        a_goal: &Vector6<f64>,
    ) -> Result<Option<Pose>, ControlError> {
        ftwire_plan::relocation(
            self.scene,
            &self.policy,
            self.rod,
            poses,
            a_now,
            a_goal,
            &self.steps,
        )
        .map_err(|e| ControlError::Relocation {
            message: e.to_string(),
        })
    }

    fn reach_from(&mut self, base: &Pose) -> Result<TrackReach, ControlError> {
        robot_reach(*base)
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
            NoiseParams::default(),
            self.seed.wrapping_add(stream),
        )
        .map_err(|e| LabError::bad_input(e.to_string()))?;
        Ok((noisy, FtFeedback::new(tared, SAMPLES_PER_REST)))
    }

    /// The bias observer's settings of the closed loop; `None` where it steers by the tared
    /// `ã` alone (switched off, or under `absolute`).
    pub fn observer_settings(&self) -> Option<BiasObserverParams> {
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

    /// Closed-loop tracking by the `PathTracker`, the truth read at every rest; returns the
    /// attempt and every move's detector residual.
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
            robot_reach(self.scene.base).map_err(from_control)?
        } else {
            TrackReach::Any(AnyPose)
        };
        // Legs from or to a waypoint near an obstacle: the looser shape stop there.
        let policy = self.policy;
        let near = if policy.near_shape_stop == policy.shape_stop {
            vec![false; waypoints.len()]
        } else {
            near_obstacles(self.scene, model.rod(), waypoints)
                .map_err(|e| from_plan(e, "the scene"))?
        };
        let mut tracker = PathTracker::new(*model, policy).with_near(near);
        if let Some(detector) = detector {
            tracker = tracker.with_detector(detector);
        }
        if let Some(settings) = self.observer_settings() {
            tracker = tracker.with_bias_observer(settings);
        }
        let targets: Vec<Vector6<f64>> = waypoints.iter().map(|w| w.a).collect();
        let mut log = TruthLog::new(waypoints);
        let observe = |rig: &NoisyRig<SimRig>, rest: &Rest<'_>| log.record(rig.inner(), rest);
        let tracked = if self.arms {
            let mut relocation = SceneRelocation {
                scene: self.scene,
                policy: plan_policy(self.noise),
                rod: model.rod(),
                steps: policy.relocation_steps,
            };
            tracker.track_relocating(
                &mut rig,
                &feedback,
                &mut reach,
                Some(&mut relocation),
                &targets,
                observe,
            )
        } else {
            tracker.track(&mut rig, &feedback, &mut reach, &targets, observe)
        }
        .map_err(from_control)?;
        let mut attempt = log.attempt(&tracked)?;
        self.finish(&mut attempt, rig.inner(), &last.a, model);
        Ok((attempt, tracked.residuals))
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
            outcome: "done".to_owned(),
            touched: start.touched,
            a_true: vec![start.a.into()],
            ..Attempt::new("open_loop")
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

    /// The final error on the true wrench, and the verdict of the policy.
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
        let verdict = self.policy.judge(attempt.completed, attempt.touched, error);
        (attempt.at_goal, attempt.success) = (verdict.at_goal, verdict.success);
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reexpressed_waypoints_keep_the_poses_and_take_the_loaded_configurations() {
        let wire =
            ftwire_core::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire");
        let weightless = KirchhoffModel::new(wire);
        let load =
            ftwire_rod::Load::from_gravity(6450.0, 0.0015, nalgebra::Vector3::new(0.0, 0.0, -9.81))
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
            outcome: "done".to_owned(),
            steps: 12,
            final_error: 14.0,
            completed: true,
            at_goal,
            success,
            ..Attempt::new("open_loop")
        };
        assert_eq!(attempt(true, true).verdict(), "success");
        assert!(attempt(true, false).verdict().contains("not at the goal"));
        assert_eq!(attempt(false, true).verdict(), "failure");
    }

    #[test]
    fn the_plan_policy_widens_the_margins_only_where_each_move_draws_fresh_noise() {
        for noise in [NoiseModel::Increment, NoiseModel::Absolute] {
            let policy = plan_policy(noise);
            assert!(policy.polishes());
            assert_eq!(policy.validity(0.82).margin, ftwire_plan::MARGIN_NOISY);
            let scatter = policy.scatter.expect("a scatter");
            assert_eq!(scatter.position_std, NoiseParams::default().position_std);
        }
        for noise in [NoiseModel::None, NoiseModel::Offset] {
            assert_eq!(plan_policy(noise).validity(0.91), ValidityParams::default());
        }
    }
}
