//! The robot as a node that moves the wire sees it: the F/T samples tared and averaged over a
//! rest, the second gripper's reported pose, and targets sent on [`TIP_TARGET_TOPIC`] and
//! waited for. Shared by [`super::identify`] and [`super::control`].
//!
//! - **tare**: the first `tare` samples received are the sensor's reading with nothing in the
//!   gripper (the sim streams them first), averaged into the tare, as `ftwire ros2 estimate`
//!   does;
//! - **move**: a target is published once; it is *reached* when a tip pose received after it
//!   is within `reach_translation` and `reach_rotation` of it. A target the robot refuses (the
//!   sim logs and drops it) or does not reach within `move_timeout` is reported as unreached;
//! - **window**: after the move, the samples stamped before the reaching tip pose are dropped,
//!   `settle_samples` more are skipped (the wire and the arm ringing out), and the next
//!   `rest_samples` raw samples are the rest's window. The wrench is *settled* when the means
//!   of the window's two halves agree within [`SETTLE_Z`] standard errors in every component;
//!   an unsettled window is taken again (at most [`SETTLE_TRIES`] times, then used and counted
//!   as `unsettled`). [`super::ros_rig`] hands a window's samples to the library's pipeline one
//!   at a time;
//! - **rest**: a window's mean, tared, as [`super::identify`] uses it;
//! - **ã**: the rest's mean through the learnt calibration or the mounting
//!   ([`ftwire_logs::a_tilde`], exactly as `ftwire shape --log` maps a record's `raw`).

use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use ftwire_core::{FtSample, Pose};
use ftwire_estimate::ft::Tare;
use ftwire_logs::RawMap;
use nalgebra::{Point3, Vector6};
use ros2_client::dds::rustdds::mio1::{Events, Interest, Poll, Token};
use ros2_client::{Publisher, Subscription};
use serde::Serialize;

use super::stats::LossCounter;
use super::{
    BASE_FRAME, Counts, NodeError, RosNode, SENSOR_FRAME, WRENCH_QUEUE, count, header, publish,
    reliable, seconds, should_stop,
};
use crate::msg::{Path, PoseStamped, WrenchStamped};
use crate::node::pose::{pose_of, ros_pose};
use crate::node::{a_of_raw, path_points, tare_of};

/// Standard errors by which the means of a rest's two halves may differ in a component.
pub const SETTLE_Z: f64 = 5.0;
/// Rests taken at one pose before an unsettled one is used anyway.
pub const SETTLE_TRIES: usize = 3;
/// Longest wait in one poll, so that a stop or the end of the duration is seen \[ms\].
const POLL_MS: u64 = 20;
/// Most tared samples kept between rests (a minute at 1 kHz).
const MAX_BUFFER: usize = 60_000;

/// How the node reads the sensor and moves the robot.
#[derive(Debug, Clone)]
pub struct RobotParams {
    /// The calibration and mounting: raw readings to `ã`.
    pub map: RawMap,
    /// The wrench subscription's QoS (default sensor data, [`super::SensorQos`]).
    pub qos: super::SensorQos,
    /// Samples of the tare, with nothing in the gripper (0: no tare; none before a
    /// calibration whose input is raw, [`ftwire_rig::stream::check_tare`]).
    pub tare: usize,
    /// The sensor's rate \[Hz\], to count lost samples from the stamps (default 1000).
    pub rate: f64,
    /// Tared samples averaged at each rest, 10 to 100 000 (default 400).
    pub rest_samples: usize,
    /// Samples skipped after a move is reached, before the rest (default 20).
    pub settle_samples: usize,
    /// A target is reached when the tip pose is this close \[m\] (default 1 mm).
    pub reach_translation: f64,
    /// … and turned this little from it \[rad\] (default 1°).
    pub reach_rotation: f64,
    /// Longest wait for a target to be reached \[s\] (default 5).
    pub move_timeout: f64,
    /// The wrench topic.
    pub wrench_topic: String,
    /// The tip pose topic.
    pub tip_pose_topic: String,
    /// The topic targets are sent on.
    pub target_topic: String,
    /// A true centreline to compare with (a simulator's `/wire/truth`).
    pub truth_topic: Option<String>,
}

impl RobotParams {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`NodeError::BadSetting`] naming the option.
    pub fn validate(&self) -> Result<(), NodeError> {
        let bad = |setting, value: String, allowed| {
            Err(NodeError::BadSetting {
                setting,
                value,
                allowed,
            })
        };
        if self.tare > 1_000_000 {
            return bad("--tare", self.tare.to_string(), "0 to 1000000 samples");
        }
        if let Err(e) = ftwire_rig::stream::check_tare(&self.map, self.tare) {
            return bad(
                "--tare",
                format!("{} ({e})", self.tare),
                "0 (no tare) before a calibration whose input is raw; otherwise 0 or at least 2 \
                 samples",
            );
        }
        if !(10..=100_000).contains(&self.rest_samples) {
            return bad(
                "--rest-samples",
                self.rest_samples.to_string(),
                "10 to 100000 samples",
            );
        }
        if self.settle_samples > 100_000 {
            return bad(
                "--settle-samples",
                self.settle_samples.to_string(),
                "0 to 100000 samples",
            );
        }
        if !(self.rate.is_finite() && (1.0..=10_000.0).contains(&self.rate)) {
            return bad(
                "--rate",
                self.rate.to_string(),
                "the sensor's rate, 1 Hz to 10 kHz",
            );
        }
        if !(self.reach_translation.is_finite() && self.reach_translation > 0.0) {
            return bad(
                "--reach-mm",
                (1e3 * self.reach_translation).to_string(),
                "a positive distance in mm",
            );
        }
        if !(self.reach_rotation.is_finite() && self.reach_rotation > 0.0) {
            return bad(
                "--reach-deg",
                self.reach_rotation.to_degrees().to_string(),
                "a positive angle in degrees",
            );
        }
        if !(self.move_timeout.is_finite() && self.move_timeout > 0.0) {
            return bad(
                "--move-timeout",
                self.move_timeout.to_string(),
                "a positive number of seconds",
            );
        }
        if let Some(spec) = self.map.mounting()
            && spec.tool_mass > 0.0
        {
            return bad(
                "--mounting",
                format!("tool_mass = {} kg", spec.tool_mass),
                "a mounting without a tool: the wrench carries no gravity vector to take the \
                 tool's weight out with",
            );
        }
        Ok(())
    }
}

/// Why a wait ended without its answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Halt {
    /// `stop` was set or the duration ended.
    Stopped,
    /// The timeout passed.
    Timeout,
}

/// One rest's window: its raw samples, as they arrived, past the settle point.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Window {
    /// The raw samples (force first, sensor frame), `rest_samples` of them.
    pub samples: Vec<FtSample>,
    /// The second gripper's reported pose at the rest.
    pub tip: Pose,
    /// Whether the two halves agreed.
    pub settled: bool,
}

impl Window {
    /// The mean stamp of the samples \[s\].
    pub fn mean_time(&self) -> f64 {
        mean_time(&self.samples)
    }
}

/// One rest: the mean of the tared samples, and `ã`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rest {
    /// `ã` \[N·m, N\], torque first, base clamp frame.
    pub a: Vector6<f64>,
    /// The second gripper's reported pose at the rest.
    pub tip: Pose,
    /// Whether the two halves agreed.
    pub settled: bool,
    /// The mean stamp of the averaged samples, less the tare's mean stamp \[s\]: when the
    /// rest was read, on the bias drift's clock.
    pub since_tare: f64,
}

/// The counts every moving node reports.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct RobotCounts {
    /// Messages received, by topic.
    pub received: Counts,
    /// Messages published, by topic.
    pub published: Counts,
    /// Messages refused, by reason: `frame_id`, `non_finite`, `bad_orientation`, `malformed`.
    pub refused: Counts,
    /// Messages the middleware would not publish, by topic.
    pub publish_failed: Counts,
    /// Samples missing from the stamp sequence.
    pub lost: u64,
    /// Targets not reached within the timeout (refused by the robot, or too slow).
    pub unreached: u64,
    /// Rests used although their halves disagreed.
    pub unsettled: u64,
    /// Publishers of the wrench topic whose QoS the subscription's (`--qos`) does not match,
    /// so that none of their samples arrive, at the end of the run.
    pub qos_mismatch: u64,
}

/// The ROS side of the robot (module docs).
pub(crate) struct Robot {
    /// The node (kept alive for its subscriptions and publisher).
    node: RosNode,
    wrench_sub: Subscription<WrenchStamped>,
    tip_sub: Subscription<PoseStamped>,
    truth_sub: Option<Subscription<Path>>,
    target_pub: Publisher<PoseStamped>,
    poll: Poll,
    events: Events,
    params: RobotParams,
    tare_samples: Vec<FtSample>,
    tare: Option<Tare>,
    /// The mean stamp of the tare's samples \[s\] (0 without a tare).
    tare_time: f64,
    /// Raw samples since the last window.
    buffer: Vec<FtSample>,
    /// The latest tip pose and its stamp.
    tip: Option<(f64, Pose)>,
    /// Tip poses received since the last target was sent.
    fresh_tips: Vec<(f64, Pose)>,
    /// The latest true centreline.
    truth: Option<Vec<Point3<f64>>>,
    loss: LossCounter,
    /// The counts of the summary.
    pub counts: RobotCounts,
    /// When the node started.
    started: Instant,
    duration: Option<f64>,
}

impl Robot {
    /// The node `name` on `domain_id`, subscribed and polling.
    pub(crate) fn new(
        name: &str,
        params: &RobotParams,
        domain_id: u16,
        duration: Option<f64>,
    ) -> Result<Self, NodeError> {
        params.validate()?;
        let mut node = RosNode::new(name, domain_id)?;
        let small = reliable(10);
        let mut wrench_sub = node.subscription::<WrenchStamped>(
            &params.wrench_topic,
            &params.qos.profile(WRENCH_QUEUE),
        )?;
        let mut tip_sub = node.subscription::<PoseStamped>(&params.tip_pose_topic, &small)?;
        let mut truth_sub = params
            .truth_topic
            .as_deref()
            .map(|topic| node.subscription::<Path>(topic, &small))
            .transpose()?;
        let target_pub = node.publisher::<PoseStamped>(&params.target_topic, &small)?;
        let ros_error = |what: &str, e: std::io::Error| NodeError::Ros {
            what: what.to_owned(),
            message: e.to_string(),
        };
        let poll = Poll::new().map_err(|e| ros_error("a poll", e))?;
        poll.registry()
            .register(&mut wrench_sub, Token(0), Interest::READABLE)
            .map_err(|e| ros_error("a poll of the wrench", e))?;
        poll.registry()
            .register(&mut tip_sub, Token(1), Interest::READABLE)
            .map_err(|e| ros_error("a poll of the tip pose", e))?;
        if let Some(sub) = truth_sub.as_mut() {
            poll.registry()
                .register(sub, Token(2), Interest::READABLE)
                .map_err(|e| ros_error("a poll of the truth", e))?;
        }
        Ok(Self {
            node,
            wrench_sub,
            tip_sub,
            truth_sub,
            target_pub,
            poll,
            events: Events::with_capacity(16),
            params: params.clone(),
            tare_samples: Vec::with_capacity(params.tare),
            tare: (params.tare == 0).then(Tare::none),
            tare_time: 0.0,
            buffer: Vec::new(),
            tip: None,
            fresh_tips: Vec::new(),
            truth: None,
            loss: LossCounter::new(params.rate),
            counts: RobotCounts::default(),
            started: Instant::now(),
            duration,
        })
    }

    /// The ROS node, to create more publishers on.
    pub(crate) fn node(&mut self) -> &mut RosNode {
        &mut self.node
    }

    /// The tare (`None` until its samples are in).
    pub(crate) fn tare(&self) -> Option<&Tare> {
        self.tare.as_ref()
    }

    /// The calibration and mounting the node maps raw readings with.
    pub(crate) fn map(&self) -> &RawMap {
        &self.params.map
    }

    /// The latest tip pose received (relative to the base clamp).
    pub(crate) fn tip(&self) -> Option<Pose> {
        self.tip.map(|(_, p)| p)
    }

    /// The latest true centreline received.
    pub(crate) fn truth(&self) -> Option<&[Point3<f64>]> {
        self.truth.as_deref()
    }

    /// The counts, with the losses so far.
    pub(crate) fn finish_counts(&mut self) -> RobotCounts {
        self.counts.lost = self.loss.lost();
        self.counts.qos_mismatch = self.node.qos_mismatches(
            &self.params.wrench_topic,
            &self.params.qos.profile(WRENCH_QUEUE),
        );
        self.counts.clone()
    }

    fn stopped(&self, stop: &AtomicBool) -> bool {
        should_stop(stop, self.started, self.duration)
    }

    /// Waits for messages (at most one poll period) and takes all of them.
    fn pump(&mut self) -> Result<(), NodeError> {
        if let Err(e) = self
            .poll
            .poll(&mut self.events, Some(Duration::from_millis(POLL_MS)))
            && e.kind() != std::io::ErrorKind::Interrupted
        {
            return Err(NodeError::Ros {
                what: "polling".to_owned(),
                message: e.to_string(),
            });
        }
        self.take_tips();
        self.take_wrenches();
        self.take_truth();
        Ok(())
    }

    fn take_tips(&mut self) {
        loop {
            match self.tip_sub.take() {
                Ok(Some((pose, _))) => {
                    count(&mut self.counts.received, "tip_pose");
                    if pose.header.frame_id != BASE_FRAME {
                        count(&mut self.counts.refused, "frame_id");
                        continue;
                    }
                    match pose_of(&pose.pose) {
                        Ok(p) => {
                            let t = seconds(&pose.header.stamp);
                            self.tip = Some((t, p));
                            self.fresh_tips.push((t, p));
                        }
                        Err(e) => count(&mut self.counts.refused, e.name()),
                    }
                }
                Ok(None) => break,
                Err(_) => count(&mut self.counts.refused, "malformed"),
            }
        }
    }

    fn take_wrenches(&mut self) {
        loop {
            match self.wrench_sub.take() {
                Ok(Some((wrench, _))) => {
                    count(&mut self.counts.received, "wrench");
                    if wrench.header.frame_id != SENSOR_FRAME {
                        count(&mut self.counts.refused, "frame_id");
                        continue;
                    }
                    let (f, m) = (&wrench.wrench.force, &wrench.wrench.torque);
                    let raw = Vector6::new(f.x, f.y, f.z, m.x, m.y, m.z);
                    if raw.iter().any(|v| !v.is_finite()) {
                        count(&mut self.counts.refused, "non_finite");
                        continue;
                    }
                    let t = seconds(&wrench.header.stamp);
                    self.loss.add(t);
                    self.add_sample(t, raw);
                }
                Ok(None) => break,
                Err(_) => count(&mut self.counts.refused, "malformed"),
            }
        }
    }

    fn take_truth(&mut self) {
        let Some(sub) = self.truth_sub.as_ref() else {
            return;
        };
        loop {
            match sub.take() {
                Ok(Some((truth, _))) => {
                    count(&mut self.counts.received, "truth");
                    if truth.header.frame_id != BASE_FRAME {
                        count(&mut self.counts.refused, "frame_id");
                        continue;
                    }
                    let nodes = path_points(&truth);
                    if nodes.iter().all(|p| p.coords.iter().all(|v| v.is_finite())) {
                        self.truth = Some(nodes);
                    } else {
                        count(&mut self.counts.refused, "non_finite");
                    }
                }
                Ok(None) => break,
                Err(_) => count(&mut self.counts.refused, "malformed"),
            }
        }
    }

    /// A raw sample into the tare, or into the buffer.
    fn add_sample(&mut self, time: f64, raw: Vector6<f64>) {
        let sample = FtSample {
            time,
            raw,
            saturated: [false; 6],
        };
        if self.tare.is_none() {
            self.tare_samples.push(sample);
            if self.tare_samples.len() >= self.params.tare {
                match tare_of(&self.tare_samples) {
                    Ok(tare) => {
                        self.tare = Some(tare);
                        self.tare_time = mean_time(&self.tare_samples);
                    }
                    Err(_) => self.tare_samples.clear(),
                }
            }
            return;
        }
        if self.buffer.len() >= MAX_BUFFER {
            self.buffer.drain(..MAX_BUFFER / 2);
        }
        self.buffer.push(sample);
    }

    /// Waits until the tare is done and a tip pose is known; returns the tip pose.
    pub(crate) fn wait_ready(
        &mut self,
        stop: &AtomicBool,
    ) -> Result<Result<Pose, Halt>, NodeError> {
        while self.tare.is_none() || self.tip.is_none() {
            if self.stopped(stop) {
                return Ok(Err(Halt::Stopped));
            }
            self.pump()?;
        }
        Ok(self.tip.map(|(_, p)| p).ok_or(Halt::Stopped))
    }

    /// Sends `target` (relative to the base clamp) and waits until a tip pose received after
    /// it is within the reach tolerances; returns the reaching pose's stamp.
    pub(crate) fn move_to(
        &mut self,
        target: &Pose,
        stop: &AtomicBool,
    ) -> Result<Result<f64, Halt>, NodeError> {
        // Whatever came before the target says nothing of it.
        self.pump()?;
        self.fresh_tips.clear();
        let stamp = self.tip.map_or(0.0, |(t, _)| t);
        let message = PoseStamped {
            header: header(stamp, BASE_FRAME),
            pose: ros_pose(target),
        };
        let topic = "tip_target";
        let counts = &mut self.counts;
        publish(
            &self.target_pub,
            message,
            topic,
            &mut counts.published,
            &mut counts.publish_failed,
        );
        let deadline = Instant::now() + Duration::from_secs_f64(self.params.move_timeout);
        loop {
            if self.stopped(stop) {
                return Ok(Err(Halt::Stopped));
            }
            let (dx, dr) = (self.params.reach_translation, self.params.reach_rotation);
            let reached = self.fresh_tips.iter().find(|(_, p)| {
                (p.translation.vector - target.translation.vector).norm() <= dx
                    && (target.rotation.inverse() * p.rotation).angle() <= dr
            });
            if let Some((t, _)) = reached {
                return Ok(Ok(*t));
            }
            self.fresh_tips.clear();
            if Instant::now() >= deadline {
                self.counts.unreached += 1;
                return Ok(Err(Halt::Timeout));
            }
            self.pump()?;
        }
    }

    /// The window of the rest after the pose stamped `since` (module docs).
    pub(crate) fn window(
        &mut self,
        since: f64,
        stop: &AtomicBool,
    ) -> Result<Result<Window, Halt>, NodeError> {
        let (n, settle) = (self.params.rest_samples, self.params.settle_samples);
        // A sample stamped at the reaching pose's tick or later was read at the new pose.
        let first = since - 0.25 / self.params.rate;
        let mut skip = settle;
        let mut window: Vec<FtSample> = Vec::with_capacity(n);
        let mut tries = 0;
        loop {
            for sample in self.buffer.drain(..) {
                if sample.time < first {
                    continue;
                }
                if skip > 0 {
                    skip -= 1;
                } else if window.len() < n {
                    window.push(sample);
                }
            }
            if window.len() >= n {
                tries += 1;
                let settled = halves_agree(&window);
                if settled || tries >= SETTLE_TRIES {
                    self.counts.unsettled += u64::from(!settled);
                    let Some((_, tip)) = self.tip else {
                        return Ok(Err(Halt::Stopped));
                    };
                    return Ok(Ok(Window {
                        samples: window,
                        tip,
                        settled,
                    }));
                }
                window.clear();
            }
            if self.stopped(stop) {
                return Ok(Err(Halt::Stopped));
            }
            self.pump()?;
        }
    }

    /// The rest after the pose stamped `since`: its window's mean, tared, to `ã`.
    pub(crate) fn rest(
        &mut self,
        since: f64,
        stop: &AtomicBool,
    ) -> Result<Result<Rest, Halt>, NodeError> {
        let window = match self.window(since, stop)? {
            Ok(window) => window,
            Err(halt) => return Ok(Err(halt)),
        };
        let tare = self.tare.unwrap_or_else(Tare::none);
        #[allow(clippy::cast_precision_loss)] // a rest far below 2⁵²
        let mean = window.samples.iter().map(|s| s.raw).sum::<Vector6<f64>>()
            / window.samples.len().max(1) as f64;
        let a = self.a_tilde(&tare.apply(&mean), window.mean_time())?;
        Ok(Ok(Rest {
            a,
            tip: window.tip,
            settled: window.settled,
            since_tare: window.mean_time() - self.tare_time,
        }))
    }

    /// A tared mean through the calibration or the mounting, at its stamp `time` \[s\] (a
    /// calibration's drift at the rest's time, held within its session's span).
    fn a_tilde(&self, mean: &Vector6<f64>, time: f64) -> Result<Vector6<f64>, NodeError> {
        a_of_raw(mean, time, &self.params.map).map_err(NodeError::Incomplete)
    }
}

/// The mean stamp of `samples` \[s\] (0 for none).
fn mean_time(samples: &[FtSample]) -> f64 {
    #[allow(clippy::cast_precision_loss)] // a tare far below 2⁵² samples
    let n = samples.len().max(1) as f64;
    samples.iter().map(|s| s.time).sum::<f64>() / n
}

/// Whether the means of the two halves of `rest` agree within [`SETTLE_Z`] standard errors
/// in every component (a wrench still changing over the rest does not; a tare, a constant
/// offset, changes nothing of it).
pub(crate) fn halves_agree(rest: &[FtSample]) -> bool {
    let rest: Vec<Vector6<f64>> = rest.iter().map(|s| s.raw).collect();
    let half = rest.len() / 2;
    if half < 2 {
        return true;
    }
    #[allow(clippy::cast_precision_loss)] // a rest far below 2⁵²
    let (h, n) = (half as f64, rest.len() as f64);
    let mean = rest.iter().sum::<Vector6<f64>>() / n;
    let first = rest[..half].iter().sum::<Vector6<f64>>() / h;
    let second = rest[half..2 * half].iter().sum::<Vector6<f64>>() / h;
    (0..6).all(|i| {
        let var = rest.iter().map(|w| (w[i] - mean[i]).powi(2)).sum::<f64>() / (n - 1.0);
        // The difference of two means of h samples has variance 2 var / h.
        let se = (2.0 * var / h).sqrt();
        (first[i] - second[i]).abs() <= SETTLE_Z * se.max(1e-12)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_drifting_rest_is_not_settled() {
        let noise = |k: usize| if k.is_multiple_of(2) { 0.01 } else { -0.01 };
        let sample = |raw| FtSample {
            raw,
            ..FtSample::default()
        };
        let flat: Vec<FtSample> = (0..200)
            .map(|k| sample(Vector6::repeat(noise(k))))
            .collect();
        assert!(halves_agree(&flat));
        #[allow(clippy::cast_precision_loss)]
        let ramp: Vec<FtSample> = (0..200)
            .map(|k| sample(Vector6::repeat(noise(k) + 1e-3 * k as f64)))
            .collect();
        assert!(!halves_agree(&ramp));
    }
}
