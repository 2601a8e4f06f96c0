//! Bring your own robot: implement [`Rig`] for it, then tare → identify → shape → controller →
//! track a short plan.
//!
//! `MyRobot` below stands in for a real dual-arm robot with one wrist F/T sensor. It holds a
//! wire that the algorithms do not know and answers every move by solving the Kirchhoff model
//! for the configuration whose second-gripper pose is the commanded one; its sensor reads the
//! wire's wrench plus a constant offset and seeded white noise. Every place where a real
//! robot's driver would be called is marked `REAL ROBOT:`. Replace those bodies, keep the rest:
//! this file is the template for a real robot.
//!
//! The workflow, one function per step, called in order from `main`:
//! 1. **tare** the sensor before the second gripper closes on the wire;
//! 2. **identify** the wire's stiffnesses `c` and length `L` from a few small random moves;
//! 3. **shape**: estimate the wire's centreline from the F/T reading alone;
//! 4. **controller**: steer the wire to a goal configuration by the Jacobian rule (eq. 13–14);
//! 5. **track a plan**: waypoints on the straight line in `A` from the start to a second goal,
//!    each checked stable, executed by the library's `PathTracker` under a `TrackingPolicy`.
//!
//! Each step prints what it found, and the example exits non-zero when identification, shape
//! or tracking miss their tolerances, so running it in CI checks the whole workflow:
//!
//! ```text
//! cargo run --release -p ftwire-control --example custom_rig
//! ```

use std::error::Error;

use ftwire_control::open_loop::{a_connected, line_in_a};
use ftwire_control::{
    AnyPose, ControlParams, Controller, FtFeedback, NoiseModel, Outcome, PathTracker, Rest,
    RestKind, TrackingPolicy, configuration_at,
};
use ftwire_core::{Command, FtSample, GripperPoses, Pose, Rig, WireParams};
use ftwire_estimate::ft::{FtPipeline, Mounting, RestAverage, Tare};
use ftwire_estimate::identify::{IdentifierParams, MotionPlan, identify};
use ftwire_estimate::shape::{DEFAULT_METRIC_SAMPLES, ShapeEstimator, centreline_distance};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_rod::{Rod, from_normalised, to_normalised};
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// The sensor's sample period \[s\] (1 kHz).
const SAMPLE_PERIOD: f64 = 1e-3;
/// How long one quasi-static move takes \[s\].
const MOVE_TIME: f64 = 1.0;
/// F/T samples averaged for the tare (more than each measurement: its noise stays as an offset).
const TARE_SAMPLES: usize = 1000;
/// F/T samples averaged per rest.
const REST_SAMPLES: usize = 100;
/// Shape nodes compared.
const NODES: usize = 64;

/// Why `MyRobot` could not do what it was asked.
#[derive(Debug, thiserror::Error)]
enum RobotError {
    /// The wire has no equilibrium near its current one at the commanded pose.
    #[error("no wire equilibrium near the current one at the commanded pose")]
    NoEquilibrium,
}

/// A stand-in for a real robot: a wire of known parameters, held by two grippers, and a wrist
/// F/T sensor with an offset and noise.
struct MyRobot {
    /// The true wire (unknown to the algorithms).
    truth: KirchhoffModel,
    /// The wire's true configuration `a` (torque first, base clamp frame) while gripped.
    a: Vector6<f64>,
    /// The second gripper's pose in the base clamp frame.
    tip: Pose,
    /// Whether the second gripper holds the wire (before it does, the wire loads nothing).
    gripped: bool,
    /// The sensor's constant offset (raw, force first, \[N\], \[N·m\]).
    bias: Vector6<f64>,
    /// The sensor's white noise per channel (raw, force first, \[N\], \[N·m\]).
    noise: Vector6<f64>,
    /// Draws the noise.
    rng: ChaCha8Rng,
    /// The robot's clock \[s\].
    clock: f64,
}

impl MyRobot {
    /// The robot with the second gripper open at the pose where the wire will be at `a`.
    fn new(wire: WireParams, a: Vector6<f64>, seed: u64) -> Result<Self, Box<dyn Error>> {
        let truth = KirchhoffModel::from_rod(Rod::new(wire));
        let tip = truth.tip(&a)?;
        Ok(Self {
            truth,
            a,
            tip,
            gripped: false,
            bias: Vector6::new(0.8, -0.5, 1.2, 0.03, -0.02, 0.01),
            noise: Vector6::new(0.02, 0.02, 0.02, 1e-3, 1e-3, 1e-3),
            rng: ChaCha8Rng::seed_from_u64(seed),
            clock: 0.0,
        })
    }

    /// Closes the second gripper on the wire.
    fn grip(&mut self) {
        // REAL ROBOT: close the second gripper (e.g. a gripper action or digital output).
        self.gripped = true;
        self.clock += MOVE_TIME;
    }

    /// The wire's true shape (a real robot has none: motion capture would stand in).
    fn true_shape(&self) -> Result<Vec<nalgebra::Vector3<f64>>, Box<dyn Error>> {
        Ok(self.truth.shape(&self.a, NODES)?.positions)
    }
}

impl Rig for MyRobot {
    type Error = RobotError;

    fn read_ft(&mut self) -> Result<FtSample, RobotError> {
        // REAL ROBOT: read one sample from the sensor driver (force first, sensor frame), and
        // flag the channels it clipped. Here the sensor sits at the clamp (identity mounting).
        let load = if self.gripped {
            Mounting::default().to_sensor(&self.a)
        } else {
            Vector6::zeros()
        };
        let noise = Vector6::from_fn(|i, _| {
            let z: f64 = StandardNormal.sample(&mut self.rng);
            self.noise[i] * z
        });
        self.clock += SAMPLE_PERIOD;
        Ok(FtSample {
            time: self.clock,
            raw: load + self.bias + noise,
            saturated: [false; 6],
        })
    }

    fn gripper_poses(&self) -> Result<GripperPoses, RobotError> {
        // REAL ROBOT: forward kinematics of both arms from the joint encoders, world frame.
        Ok(GripperPoses {
            base: Pose::identity(),
            tip: self.tip,
        })
    }

    fn command(&mut self, command: &Command) -> Result<(), RobotError> {
        // REAL ROBOT: inverse kinematics for both arms, a slow joint trajectory, wait until
        // both arrive and the wire is at rest. Here: the wire's equilibrium at the new pose,
        // by Newton from the current one (it stays on its branch for small moves).
        let b = command.base.inverse() * command.tip;
        if self.gripped {
            self.a = configuration_at(&self.truth, &self.a, &b).ok_or(RobotError::NoEquilibrium)?;
        }
        self.tip = b;
        self.clock += MOVE_TIME;
        Ok(())
    }

    fn time(&self) -> f64 {
        self.clock
    }
}

/// Fails the example (a non-zero exit) with `message` unless `ok`.
fn check(ok: bool, message: String) -> Result<(), Box<dyn Error>> {
    if ok { Ok(()) } else { Err(message.into()) }
}

fn main() -> Result<(), Box<dyn Error>> {
    // The wire the robot holds: a 3 mm, 820 mm nitinol wire. Only `MyRobot` knows it; the
    // steps below read it only to check what they found.
    let true_wire = WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015)?;
    let a_start = from_normalised(&true_wire, &Vector6::new(0.4, 2.2, 0.8, -1.8, 2.8, 0.6));
    let mut robot = MyRobot::new(true_wire, a_start, 7)?;
    let mut rng = ChaCha8Rng::seed_from_u64(1);

    let feedback = tare(&mut robot, &true_wire)?;
    let wire = identify_wire(&mut robot, &feedback, &true_wire, &mut rng)?;
    let model = KirchhoffModel::new(wire);
    estimate_shape(&mut robot, &feedback, model)?;
    control(&mut robot, &feedback, model, &true_wire)?;
    track_plan(&mut robot, &feedback, model, &true_wire)
}

/// Step 1, tare: average the sensor at rest before the second gripper closes on the wire,
/// then grip. Returns the feedback (tared pipeline, rests of [`REST_SAMPLES`]) every later
/// step measures `ã` through.
fn tare(
    robot: &mut MyRobot,
    true_wire: &WireParams,
) -> Result<FtFeedback<Mounting>, Box<dyn Error>> {
    let rest = RestAverage::new(TARE_SAMPLES)?;
    let unloaded: Vec<FtSample> = (0..TARE_SAMPLES)
        .map(|_| robot.read_ft())
        .collect::<Result<_, _>>()?;
    let tare = Tare::from_rest(&rest.average(unloaded.iter().map(Some))?, &Vector6::zeros());
    let tare_error = (tare.offset - robot.bias).abs().max();
    let untared = to_normalised(
        true_wire,
        &Mounting::default().to_configuration(&robot.bias),
    );
    println!(
        "tare:     offset {:.3?} (true {:.3?}), largest error {tare_error:.1e}; untared, ã \
         would be off by {:.2} (normalised)",
        tare.offset.as_slice(),
        robot.bias.as_slice(),
        untared.norm()
    );
    check(tare_error < 5e-3, format!("tare off by {tare_error:.1e}"))?;
    robot.grip();
    let pipeline = FtPipeline::new(
        RestAverage::new(REST_SAMPLES / 2)?,
        tare,
        Mounting::default(),
    );
    Ok(FtFeedback::new(pipeline, REST_SAMPLES))
}

/// Step 2, identify `c` and `L`: measure `ã` at the start and after each small random move
/// from it, return to the start, and fit. Returns the identified wire.
fn identify_wire(
    robot: &mut MyRobot,
    feedback: &FtFeedback<Mounting>,
    true_wire: &WireParams,
    rng: &mut ChaCha8Rng,
) -> Result<WireParams, Box<dyn Error>> {
    let b0 = robot.gripper_poses()?.relative();
    let mut samples = vec![(feedback.measure(robot)?.a, b0)];
    for b in MotionPlan::default().poses(&b0, rng) {
        robot.move_tip(b)?;
        samples.push((
            feedback.measure(robot)?.a,
            robot.gripper_poses()?.relative(),
        ));
    }
    robot.move_tip(b0)?;
    // A nominal guess of the wire: only its radius and load matter, the search box is wide.
    let guess = KirchhoffModel::new(WireParams::new([0.1, 0.1, 0.1], 1.0, 0.0015)?);
    let estimate = identify(&guess, &samples, &IdentifierParams::default(), rng)?.identified()?;
    let wire = estimate.wire(true_wire.radius())?;
    let c_error = (0..3)
        .map(|i| (wire.c()[i] / true_wire.c()[i] - 1.0).abs())
        .fold(0.0, f64::max);
    let length_error = (wire.length() / true_wire.length() - 1.0).abs();
    println!(
        "identify: c = {:.4?} N·m², L = {:.4} m from {} samples; errors: c {:.2} %, L {:.2} %",
        wire.c(),
        wire.length(),
        samples.len(),
        100.0 * c_error,
        100.0 * length_error
    );
    check(c_error < 0.02, format!("c off by {:.1} %", 100.0 * c_error))?;
    check(
        length_error < 0.02,
        format!("L off by {:.1} %", 100.0 * length_error),
    )?;
    Ok(wire)
}

/// Step 3, shape: the centreline from one F/T measurement, against the true one.
fn estimate_shape(
    robot: &mut MyRobot,
    feedback: &FtFeedback<Mounting>,
    model: KirchhoffModel,
) -> Result<(), Box<dyn Error>> {
    let measured = feedback.measure(robot)?;
    let shape = ShapeEstimator::new(model).estimate(&measured.a)?;
    let shape_error = centreline_distance(
        &shape.shape.positions,
        &robot.true_shape()?,
        DEFAULT_METRIC_SAMPLES,
    )?;
    println!(
        "shape:    mean distance to the true centreline {:.2} mm ({:?})",
        1e3 * shape_error,
        shape.confidence
    );
    check(
        shape_error < 5e-3,
        format!("shape off by {:.1} mm", 1e3 * shape_error),
    )
}

/// Step 4, controller: steer to a goal configuration, given in the identified wire's
/// normalised units (torque in c2/L, force in c2/L²).
fn control(
    robot: &mut MyRobot,
    feedback: &FtFeedback<Mounting>,
    model: KirchhoffModel,
    true_wire: &WireParams,
) -> Result<(), Box<dyn Error>> {
    let settings = ControlParams {
        epsilon: 0.02,
        max_iterations: 150,
        ..ControlParams::default()
    };
    let controller = Controller::new(model, settings)?;
    let goal = from_normalised(model.wire(), &Vector6::new(0.3, 2.6, 0.6, -1.4, 2.4, 0.8));
    let run = controller.run(robot, feedback, &mut AnyPose, &goal)?;
    let truth_error = to_normalised(true_wire, &(robot.a - goal)).norm();
    println!(
        "control:  {} after {} steps, true error {truth_error:.3} (normalised)",
        run.outcome.name(),
        run.steps.len()
    );
    check(
        matches!(run.outcome, Outcome::Reached { .. }) && truth_error < 0.1,
        format!(
            "control ended {:?}, true error {truth_error:.3}",
            run.outcome
        ),
    )
}

/// Step 5, track a plan: waypoints on the straight line in A from here to a second goal, the
/// whole line checked stable and free of self-contact first, executed by the `PathTracker`
/// under the policy of a robot that goes where it is told (no execution noise): the legs'
/// stops, the retreats and undos, the success rule.
fn track_plan(
    robot: &mut MyRobot,
    feedback: &FtFeedback<Mounting>,
    model: KirchhoffModel,
    true_wire: &WireParams,
) -> Result<(), Box<dyn Error>> {
    let start = feedback.measure(robot)?.a;
    let end = from_normalised(model.wire(), &Vector6::new(0.1, 3.0, 0.4, -1.0, 2.0, 1.0));
    check(
        a_connected(model.rod(), &start, &end, 20)?,
        "the plan leaves A_free".into(),
    )?;
    let waypoints = line_in_a(&start, &end, 4);
    let tracker = PathTracker::new(model, TrackingPolicy::for_noise(NoiseModel::None));
    // The observer sees the robot at every rest; `MyRobot` knows its true wire, so it reports
    // how far each leg ended from its waypoint (a real robot would log its own data here).
    let mut rests = 0;
    let mut leg_errors = Vec::new();
    let tracked = tracker.track(
        robot,
        feedback,
        &mut AnyPose,
        &waypoints,
        |robot: &MyRobot, rest: &Rest<'_>| {
            rests += 1;
            if rest.kind == RestKind::LegEnd
                && let Some(waypoint) = waypoints.get(rest.waypoint)
            {
                leg_errors.push(to_normalised(true_wire, &(robot.a - waypoint)).norm());
            }
        },
    )?;
    for (leg, error) in tracked.legs.iter().zip(&leg_errors) {
        println!(
            "plan:     waypoint {}/{}: {} after {} steps, true error {error:.3}",
            leg.waypoint,
            waypoints.len() - 1,
            leg.outcome.name(),
            leg.moves
        );
    }
    check(
        tracked.completed && tracked.legs.len() == waypoints.len() - 1,
        format!("the plan ended {:?}", tracked.end),
    )?;
    check(
        rests == 1 + tracked.moves + tracked.legs.len(),
        format!("{rests} rests observed for {} moves", tracked.moves),
    )?;
    let final_error = to_normalised(true_wire, &(robot.a - end)).norm();
    let final_shape = centreline_distance(
        &model.shape(&end, NODES)?.positions,
        &robot.true_shape()?,
        DEFAULT_METRIC_SAMPLES,
    )?;
    println!(
        "plan:     final true error {final_error:.3} (normalised), {:.2} mm from the planned shape",
        1e3 * final_shape
    );
    let verdict = tracker
        .policy()
        .judge(tracked.completed, false, final_error);
    check(
        verdict.success && final_error < 0.05,
        format!("final error {final_error:.3}"),
    )?;
    check(
        final_shape < 3e-3,
        format!("final shape off by {:.1} mm", 1e3 * final_shape),
    )
}
