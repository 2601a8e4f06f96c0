//! `ftwire ros2 sim`: the simulator as a ROS 2 robot.
//!
//! The lab's simulated rig ([`ftwire_lab::experiment::rig::place_among`]: the true wire held
//! with the base clamp at the origin and the second gripper at `Γ(a0)`, the F/T sensor model,
//! the motion capture) behind ROS 2 topics:
//!
//! - every `1 / rate` s one sensor sample, noisy and biased as the sensor model gives it,
//!   force first in the sensor frame, on [`WRENCH_TOPIC`] (frame [`SENSOR_FRAME`]), the `k`-th
//!   stamped `k / rate` exactly. The first `tare_samples` are read with nothing in the base
//!   gripper, as a robot tares its sensor before it picks the wire up; a sensor dropout
//!   publishes nothing for its tick (counted in `dropouts`);
//! - at `pose_rate` the second gripper's pose relative to the base clamp, as the robot reports
//!   it, on [`TIP_POSE_TOPIC`], and the same in TF ([`super::tf::SimTfFrames`]: `world` →
//!   tip clamp on `/tf` with each tip pose, `world` → base clamp once on `/tf_static`); at
//!   `marker_rate` the seen markers (`geometry_msgs/PoseArray`, positions only, dropped markers
//!   left out) on [`MARKERS_TOPIC`], the true centreline on [`TRUTH_TOPIC`], all in
//!   [`BASE_FRAME`], and the sensor's true bias drift since the tare on [`TRUTH_BIAS_TOPIC`]
//!   ([`super::truth_bias`]), and all four again after each move;
//! - each pose on [`TIP_TARGET_TOPIC`] (frame [`BASE_FRAME`]) moves the second gripper there:
//!   the simulator solves the new equilibrium on the receiving thread (the sensor's ticks that
//!   pass meanwhile are published after it, with their own stamps). A target out of reach
//!   (farther than the wire is long, or no equilibrium on the way) is refused, logged and
//!   counted as `unreachable`; the wire stays where it was.
//!
//! The world may hold boxes (`obstacles`) that the wire touches: the contact forces are in the
//! wrench, as in the simulator experiments' collision runs.
//!
//! The clock starts with the first sample, once a subscriber to the wrench is discovered (at
//! most `wait_subscriber` s after the start), so that a receiver that taring from its first
//! samples gets the empty gripper's.

use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use ftwire_core::{Command, FtSample, Rig};
use ftwire_lab::experiment::rig::{place_among, touches, true_centreline};
use ftwire_lab::experiment::{Gravity, ModelKind};
use ftwire_lab::setup::SimSetup;
use ftwire_lab::wire::WireSpec;
use ftwire_sim::{BoxObstacle, SimRig};
use nalgebra::Vector6;
use ros2_client::{Publisher, Subscription};
use serde::Serialize;

use super::tf::{SimTfFrames, TF_STATIC_TOPIC, TF_TOPIC, tf_qos, tf_static_qos};
use super::{
    BASE_FRAME, Counts, Log, MARKERS_TOPIC, NodeError, NodeSettings, RosNode, SENSOR_FRAME,
    TIP_POSE_TOPIC, TIP_TARGET_TOPIC, TRUTH_TOPIC, WRENCH_QUEUE, WRENCH_TOPIC, count, header,
    publish, reliable, seconds, should_stop, sleep_until, tick_stamp,
};
use crate::msg::{self, Path, PoseArray, PoseStamped, StringMsg, TFMessage, WrenchStamped};
use crate::node::path_message;
use crate::node::pose::{TargetRefusal, pose_of, ros_point, ros_pose};
use crate::node::truth_bias::{TRUTH_BIAS_TOPIC, TruthBias};

/// Grace after the first subscriber to the wrench is discovered, before the clock starts
/// \[s\]: both ends then have matched each other's reader and writer.
const MATCH_GRACE: f64 = 0.5;

/// What the simulated robot is.
#[derive(Debug, Clone)]
pub struct SimNodeParams {
    /// The true wire.
    pub wire: WireSpec,
    /// Gravity in the simulated world.
    pub gravity: Gravity,
    /// The start configuration `a0` \[N·m, N\], torque first: the second gripper starts at
    /// `Γ(a0)` of the weightless model.
    pub start: Vector6<f64>,
    /// The simulated sensor and rig.
    pub setup: SimSetup,
    /// Seed of the sensor's noise, drift and dropouts and of the markers' noise.
    pub seed: u64,
    /// F/T samples per second \[Hz\], 1 to 10 000 (default 1000).
    pub rate: f64,
    /// Tip poses per second \[Hz\], at most `rate` (default 100).
    pub pose_rate: f64,
    /// Marker frames and true centrelines per second \[Hz\], at most `rate` (default 10).
    pub marker_rate: f64,
    /// The first samples, read with nothing in the base gripper (default 500).
    pub tare_samples: u64,
    /// Longest wait for a subscriber to the wrench before the clock starts anyway \[s\].
    pub wait_subscriber: f64,
    /// The frames published in TF.
    pub tf: SimTfFrames,
    /// Boxes in the world (base clamp frame) the wire can touch (default none).
    pub obstacles: Vec<BoxObstacle>,
}

/// The end of a run: one JSON line.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimSummary {
    /// `"sim"`.
    pub node: &'static str,
    /// Messages received, by topic.
    pub received: Counts,
    /// Messages published, by topic.
    pub published: Counts,
    /// Messages refused, by reason: `frame_id`, `non_finite`, `bad_orientation`,
    /// `unreachable`, `malformed`.
    pub refused: Counts,
    /// Messages the middleware would not publish, by topic.
    pub publish_failed: Counts,
    /// Sensor ticks without a sample (the sensor model's dropouts).
    pub dropouts: u64,
    /// Moves made to a target.
    pub moves: u64,
    /// Moves after which the wire touches a box (a contact force on some node, as the
    /// experiments score a touch: `ftwire_lab::experiment::rig::touches`).
    pub touching_moves: u64,
    /// The first of them (1 is the first move).
    pub first_touching_move: Option<u64>,
    /// Sensor ticks the loop published later than one period after their time.
    pub late_ticks: u64,
    /// The last tick's index plus one: samples the clock gave.
    pub ticks: u64,
    /// Seconds on the node's clock.
    pub clock_s: f64,
    /// The sensor's true bias drift since the tare at the last sample, in `A` (torque first,
    /// base clamp frame) \[N·m, N\] ([`super::truth_bias`]): ground truth for the estimator's
    /// bias observer.
    pub bias_drift: [f64; 6],
}

/// The sim's start: `given` \[N·m, N\], else (0, 1, 0.5, −1, 0.5, 0) in `wire`'s units (torque
/// `c2/L`, force `c2/L²`).
///
/// # Errors
/// Bad input for a wire without valid parameters.
pub fn start_or_default(
    wire: &WireSpec,
    given: Option<[f64; 6]>,
) -> Result<Vector6<f64>, NodeError> {
    if let Some(a) = given {
        return Ok(Vector6::from(a));
    }
    let params = wire
        .wire_params()
        .map_err(|e| ftwire_app::LabError::bad_input(format!("wire {}: {e}", wire.name)))?;
    Ok(ftwire_rod::from_normalised(
        &params,
        &Vector6::new(0.0, 1.0, 0.5, -1.0, 0.5, 0.0),
    ))
}

/// The boxes of `--box`, each `cx,cy,cz,hx,hy,hz` \[m\] (centre and half extents, base clamp
/// frame).
///
/// # Errors
/// Bad input naming the box.
pub fn obstacles(boxes: &[[f64; 6]]) -> Result<Vec<BoxObstacle>, NodeError> {
    boxes
        .iter()
        .map(|&[cx, cy, cz, hx, hy, hz]| {
            BoxObstacle::new(
                ftwire_core::Pose::translation(cx, cy, cz),
                nalgebra::Vector3::new(hx, hy, hz),
            )
            .map_err(|e| {
                ftwire_app::LabError::bad_input(format!(
                    "--box {:?}: {e}",
                    [cx, cy, cz, hx, hy, hz]
                ))
                .into()
            })
        })
        .collect()
}

impl SimNodeParams {
    fn validate(&self) -> Result<(), NodeError> {
        for (setting, value, max) in [
            ("--rate", self.rate, 10_000.0),
            ("--pose-rate", self.pose_rate, self.rate),
            ("--marker-rate", self.marker_rate, self.rate),
        ] {
            if !(value.is_finite() && value >= 1.0 && value <= max) {
                return Err(NodeError::BadSetting {
                    setting,
                    value: value.to_string(),
                    allowed: "a rate from 1 Hz to 10 kHz, the pose and marker rates at most --rate",
                });
            }
        }
        if !(self.wait_subscriber.is_finite() && self.wait_subscriber >= 0.0) {
            return Err(NodeError::BadSetting {
                setting: "--wait-subscriber",
                value: self.wait_subscriber.to_string(),
                allowed: "a time of 0 s or more",
            });
        }
        self.tf.validate()?;
        if self.start.iter().any(|v| !v.is_finite()) {
            return Err(NodeError::BadSetting {
                setting: "--start",
                value: format!("{:?}", self.start.as_slice()),
                allowed: "six finite numbers",
            });
        }
        Ok(())
    }

    /// The simulated rig at its start.
    ///
    /// # Errors
    /// As [`place_among`].
    pub fn place(&self) -> Result<SimRig, NodeError> {
        Ok(place_among(
            &self.wire,
            self.gravity,
            ModelKind::Weightless,
            &self.start,
            self.setup.rig_config(self.seed),
            &self.obstacles,
        )?)
    }
}

/// Moves the second gripper of `rig` to `target` (a `PoseStamped` relative to the base clamp),
/// keeping the base gripper where the robot believes it is; the rig is unchanged when the
/// target is refused.
///
/// # Errors
/// A [`TargetRefusal`]: another frame, a value that is not finite, an orientation that is not
/// a unit quaternion, or a target the wire cannot reach (the simulator's own check and its
/// equilibrium solve).
pub fn move_to(rig: &mut SimRig, target: &PoseStamped) -> Result<(), TargetRefusal> {
    if target.header.frame_id != BASE_FRAME {
        return Err(TargetRefusal::FrameId(target.header.frame_id.clone()));
    }
    let tip = pose_of(&target.pose)?;
    let base = rig
        .gripper_poses()
        .map_err(|e| TargetRefusal::Unreachable(e.to_string()))?
        .base;
    rig.command_motion(&Command {
        base,
        tip: base * tip,
    })
    .map(|_| ())
    .map_err(|e| TargetRefusal::Unreachable(e.to_string()))
}

/// The ROS message of one F/T sample, stamped `stamp`.
pub fn wrench_message(sample: &FtSample, stamp: msg::Time) -> WrenchStamped {
    let r = &sample.raw;
    WrenchStamped {
        header: msg::Header {
            stamp,
            frame_id: SENSOR_FRAME.to_owned(),
        },
        wrench: msg::Wrench {
            force: msg::Vector3 {
                x: r[0],
                y: r[1],
                z: r[2],
            },
            torque: msg::Vector3 {
                x: r[3],
                y: r[4],
                z: r[5],
            },
        },
    }
}

/// The true centreline of `rig` as a path at `t` \[s\].
pub fn truth_message(rig: &SimRig, t: f64) -> Path {
    path_message(
        header(t, BASE_FRAME),
        true_centreline(rig).iter().map(ros_point),
    )
}

/// The sim's publishers.
struct Publishers {
    wrench: Publisher<WrenchStamped>,
    tip: Publisher<PoseStamped>,
    tf: Publisher<TFMessage>,
    markers: Publisher<PoseArray>,
    truth: Publisher<Path>,
    truth_bias: Publisher<StringMsg>,
}

/// Waits until someone listens to the wrench (or `wait_subscriber` is over), then a grace
/// time for the match to complete: the clock starts after it.
fn wait_for_subscriber(
    node: &RosNode,
    params: &SimNodeParams,
    (stop, started, duration): (&AtomicBool, Instant, Option<f64>),
    log: Log<'_>,
) {
    let wait_end = started + Duration::from_secs_f64(params.wait_subscriber);
    while node.subscription_count(WRENCH_TOPIC) == 0 && Instant::now() < wait_end {
        if should_stop(stop, started, duration) {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    if node.subscription_count(WRENCH_TOPIC) > 0 {
        log("sim: a subscriber to the wrench is discovered; the clock starts");
        sleep_until(
            Instant::now() + Duration::from_secs_f64(MATCH_GRACE),
            Duration::from_secs(1),
        );
    } else {
        log("sim: no subscriber to the wrench yet; the clock starts anyway");
    }
}

/// Takes every target waiting and moves the tip to each in turn; returns whether it moved.
fn take_targets(
    sub: &Subscription<PoseStamped>,
    rig: &mut SimRig,
    summary: &mut SimSummary,
    log: Log<'_>,
) -> bool {
    let mut moved = false;
    loop {
        match sub.take() {
            Ok(Some((target, _))) => {
                count(&mut summary.received, TIP_TARGET_TOPIC);
                match move_to(rig, &target) {
                    Ok(()) => {
                        summary.moves += 1;
                        moved = true;
                        if touches(&rig.equilibrium().contact_forces) {
                            summary.touching_moves += 1;
                            summary.first_touching_move.get_or_insert(summary.moves);
                        }
                        log(&format!(
                            "sim: moved the tip to ({:.4}, {:.4}, {:.4}) m",
                            target.pose.position.x, target.pose.position.y, target.pose.position.z
                        ));
                    }
                    Err(refusal) => {
                        count(&mut summary.refused, refusal.name());
                        log(&format!(
                            "sim: refused a target on {TIP_TARGET_TOPIC}: {refusal}"
                        ));
                    }
                }
            }
            Ok(None) => return moved,
            Err(e) => {
                count(&mut summary.refused, "malformed");
                log(&format!(
                    "sim: refused a message on {TIP_TARGET_TOPIC}: {e:?}"
                ));
            }
        }
    }
}

/// What one tick publishes besides the wrench.
struct TickPlan {
    tip: bool,
    markers: bool,
}

/// Tick `k`: the F/T sample (the empty gripper's during the tare), and the tip pose, the
/// markers and the truth when `plan` says so.
fn tick(
    k: u64,
    rig: &mut SimRig,
    params: &SimNodeParams,
    (publishers, plan): (&Publishers, TickPlan),
    summary: &mut SimSummary,
    truth_bias: &mut TruthBias,
) {
    let stamp = tick_stamp(k, params.rate);
    let t = seconds(&stamp);
    let (published, failed) = (&mut summary.published, &mut summary.publish_failed);
    let sample = if k < params.tare_samples {
        let sample = rig.read_ft_empty_gripper();
        truth_bias.tare_sample(rig);
        sample
    } else {
        rig.read_ft()
    };
    match sample {
        Ok(sample) => publish(
            &publishers.wrench,
            wrench_message(&sample, stamp),
            WRENCH_TOPIC,
            published,
            failed,
        ),
        Err(_) => summary.dropouts += 1,
    }
    if plan.tip
        && let Ok(poses) = rig.gripper_poses()
    {
        let message = PoseStamped {
            header: header(t, BASE_FRAME),
            pose: ros_pose(&poses.relative()),
        };
        publish(&publishers.tip, message, TIP_POSE_TOPIC, published, failed);
        let frames = &params.tf;
        let tf = TFMessage {
            transforms: vec![frames.edge(&frames.tip, &poses.tip, stamp)],
        };
        publish(&publishers.tf, tf, TF_TOPIC, published, failed);
    }
    if plan.markers {
        if let Ok(frame) = rig.observe_markers() {
            let message = PoseArray {
                header: header(t, BASE_FRAME),
                poses: frame
                    .positions
                    .iter()
                    .flatten()
                    .map(|p| msg::Pose {
                        position: ros_point(&p.coords),
                        orientation: msg::Quaternion::default(),
                    })
                    .collect(),
            };
            publish(
                &publishers.markers,
                message,
                MARKERS_TOPIC,
                published,
                failed,
            );
        }
        publish(
            &publishers.truth,
            truth_message(rig, t),
            TRUTH_TOPIC,
            published,
            failed,
        );
        if let Some(message) = truth_bias.message(rig, t) {
            publish(
                &publishers.truth_bias,
                message,
                TRUTH_BIAS_TOPIC,
                published,
                failed,
            );
        }
    }
}

/// Runs the simulated robot (module docs) until `settings.duration` ends or `stop` is set.
///
/// # Errors
/// [`NodeError`] for bad settings, a wire that cannot be placed at `start`, or ROS 2 entities
/// that cannot be created. Bad messages are refused and counted, never errors.
pub fn run(
    params: &SimNodeParams,
    settings: NodeSettings,
    stop: &AtomicBool,
    log: Log<'_>,
) -> Result<SimSummary, NodeError> {
    settings.validate()?;
    params.validate()?;
    let started = Instant::now();
    let mut rig = params.place()?;
    log(&format!(
        "sim: wire {} placed (gravity {}), {} simulator nodes",
        params.wire.name,
        params.gravity,
        true_centreline(&rig).len()
    ));
    let mut node = RosNode::new("ftwire_sim", settings.domain_id)?;
    let small = reliable(10);
    let publishers = Publishers {
        wrench: node.publisher::<WrenchStamped>(WRENCH_TOPIC, &reliable(WRENCH_QUEUE))?,
        tip: node.publisher::<PoseStamped>(TIP_POSE_TOPIC, &small)?,
        markers: node.publisher::<PoseArray>(MARKERS_TOPIC, &small)?,
        truth: node.publisher::<Path>(TRUTH_TOPIC, &small)?,
        tf: node.publisher::<TFMessage>(TF_TOPIC, &tf_qos())?,
        truth_bias: node.publisher::<StringMsg>(TRUTH_BIAS_TOPIC, &small)?,
    };
    // The base clamp never moves: its edge goes out once, kept for late subscribers.
    let tf_static = node.publisher::<TFMessage>(TF_STATIC_TOPIC, &tf_static_qos(true))?;
    let mut truth_bias = TruthBias::new(&params.setup.rig_config(params.seed))?;
    let target_sub = node.subscription::<PoseStamped>(TIP_TARGET_TOPIC, &small)?;
    log(&format!(
        "sim: domain {}; publishing {WRENCH_TOPIC} at {} Hz (frame {SENSOR_FRAME}, the first {} \
         samples with an empty gripper), {TIP_POSE_TOPIC} at {} Hz, {MARKERS_TOPIC} and \
         {TRUTH_TOPIC} at {} Hz (frame {BASE_FRAME}), {TF_TOPIC} ({:?} → {:?}) with the tip pose \
         and {TF_STATIC_TOPIC} ({:?} → {:?}) once; subscribed to {TIP_TARGET_TOPIC}",
        settings.domain_id,
        params.rate,
        params.tare_samples,
        params.pose_rate,
        params.marker_rate,
        params.tf.world,
        params.tf.tip,
        params.tf.world,
        params.tf.base
    ));
    wait_for_subscriber(&node, params, (stop, started, settings.duration), log);

    let mut summary = SimSummary {
        node: "sim",
        received: Counts::new(),
        published: Counts::new(),
        refused: Counts::new(),
        publish_failed: Counts::new(),
        dropouts: 0,
        moves: 0,
        touching_moves: 0,
        first_touching_move: None,
        late_ticks: 0,
        ticks: 0,
        clock_s: 0.0,
        bias_drift: [0.0; 6],
    };
    if let Ok(poses) = rig.gripper_poses() {
        let frames = &params.tf;
        let message = TFMessage {
            transforms: vec![frames.edge(&frames.base, &poses.base, tick_stamp(0, params.rate))],
        };
        let (published, failed) = (&mut summary.published, &mut summary.publish_failed);
        publish(&tf_static, message, TF_STATIC_TOPIC, published, failed);
    }
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // rates checked ≥ 1
    let every = |rate: f64| ((params.rate / rate).round() as u64).max(1);
    let (pose_every, marker_every) = (every(params.pose_rate), every(params.marker_rate));
    let clock = Instant::now();
    let mut k: u64 = 0;
    // After a move the tip, markers and truth go out with the next tick.
    let mut moved = true;
    while !should_stop(stop, started, settings.duration) {
        moved |= take_targets(&target_sub, &mut rig, &mut summary, log);
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // elapsed ≥ 0
        let due = (clock.elapsed().as_secs_f64() * params.rate).floor() as u64;
        while k <= due {
            if due > k + 1 {
                summary.late_ticks += 1;
            }
            let plan = TickPlan {
                tip: moved || k.is_multiple_of(pose_every),
                markers: moved || k.is_multiple_of(marker_every),
            };
            tick(
                k,
                &mut rig,
                params,
                (&publishers, plan),
                &mut summary,
                &mut truth_bias,
            );
            moved = false;
            k += 1;
        }
        #[allow(clippy::cast_precision_loss)] // ticks far below 2⁵²
        let next = clock + Duration::from_secs_f64(k as f64 / params.rate);
        sleep_until(next, Duration::from_millis(20));
    }
    summary.ticks = k;
    summary.clock_s = clock.elapsed().as_secs_f64();
    summary.bias_drift = truth_bias.bias(&rig).into();
    log(&format!(
        "sim: stopped after {k} ticks ({:.1} s on the clock)",
        summary.clock_s
    ));
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> SimNodeParams {
        let wire = WireSpec::load("nitinol-3mm-820").expect("a preset");
        let scales = wire.wire_params().expect("valid");
        SimNodeParams {
            start: ftwire_rod::from_normalised(
                &scales,
                &Vector6::new(0.0, 1.0, 0.5, -1.0, 0.5, 0.0),
            ),
            wire,
            gravity: Gravity::Off,
            setup: SimSetup::default(),
            seed: 0,
            rate: 1000.0,
            pose_rate: 100.0,
            marker_rate: 10.0,
            tare_samples: 0,
            wait_subscriber: 0.0,
            tf: SimTfFrames::default(),
            obstacles: Vec::new(),
        }
    }

    fn target(x: f64, frame: &str) -> PoseStamped {
        PoseStamped {
            header: header(0.0, frame),
            pose: msg::Pose {
                position: msg::Point { x, y: 0.1, z: 0.0 },
                orientation: msg::Quaternion::default(),
            },
        }
    }

    /// The sim's two TF edges, composed by the estimator's buffer, give its `PoseStamped`.
    #[test]
    fn the_tf_edges_compose_to_the_tip_pose() {
        use crate::node::tf::TfBuffer;
        let p = params();
        let rig = p.place().expect("placed");
        let poses = rig.gripper_poses().expect("poses");
        let stamp = tick_stamp(7, p.rate);
        let mut tf = TfBuffer::new();
        tf.insert(
            &p.tf.edge(&p.tf.base, &poses.base, tick_stamp(0, p.rate)),
            true,
        )
        .expect("the static edge");
        tf.insert(&p.tf.edge(&p.tf.tip, &poses.tip, stamp), false)
            .expect("the dynamic edge");
        let got = tf
            .lookup(&p.tf.base, &p.tf.tip, seconds(&stamp), 0.5)
            .expect("a chain");
        let want = poses.relative();
        assert!((got.translation.vector - want.translation.vector).norm() < 1e-12);
        assert!(got.rotation.angle_to(&want.rotation) < 1e-9);
        let bad = SimTfFrames {
            tip: p.tf.world.clone(),
            ..SimTfFrames::default()
        };
        assert!(bad.validate().is_err());
    }

    #[test]
    fn a_target_moves_the_tip_and_a_bad_one_changes_nothing() {
        let mut rig = params().place().expect("placed");
        let before = rig.gripper_poses().expect("poses").relative();
        let far = move_to(&mut rig, &target(5.0, BASE_FRAME)).expect_err("beyond the wire");
        assert_eq!(far.name(), "unreachable");
        let frame = move_to(&mut rig, &target(0.5, "world")).expect_err("another frame");
        assert_eq!(frame.name(), "frame_id");
        let mut nan = target(0.5, BASE_FRAME);
        nan.pose.position.y = f64::NAN;
        assert_eq!(
            move_to(&mut rig, &nan).map_err(|e| e.name()),
            Err("non_finite")
        );
        let mut skew = target(0.5, BASE_FRAME);
        skew.pose.orientation.w = 2.0;
        assert_eq!(
            move_to(&mut rig, &skew).map_err(|e| e.name()),
            Err("bad_orientation")
        );
        let unchanged = rig.gripper_poses().expect("poses").relative();
        assert!((unchanged.translation.vector - before.translation.vector).norm() < 1e-12);
        let mut near = PoseStamped {
            header: header(0.0, BASE_FRAME),
            pose: ros_pose(&before),
        };
        near.pose.position.x -= 0.01;
        move_to(&mut rig, &near).expect("a small move");
        let after = rig.gripper_poses().expect("poses").relative();
        assert!((after.translation.vector.x - (before.translation.vector.x - 0.01)).abs() < 1e-9);
        let truth = truth_message(&rig, 0.5);
        let tip = truth.poses.last().expect("points").pose.position;
        assert!((tip.x - after.translation.vector.x).abs() < 1e-6);
    }
}
