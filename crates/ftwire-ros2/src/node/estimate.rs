//! `ftwire ros2 estimate`: the wire's shape from each F/T sample.
//!
//! For each `geometry_msgs/WrenchStamped` (force first, sensor frame, frame [`SENSOR_FRAME`]),
//! on the thread that receives it:
//!
//! 1. **tare**: the first `tare` samples are the sensor's reading with nothing in the gripper
//!    (the sim streams them first), averaged into the tare (`ftwire_estimate::ft::Tare`);
//! 2. **window**: the mean of the last `window` tared samples (a running sum: white noise falls
//!    as `1/√window`, at a delay of half the window);
//! 3. **ã**: the mean through the learnt calibration or the mounting
//!    ([`ftwire_lab::log::a_tilde`], exactly as `ftwire shape --log` maps a record's `raw`);
//! 4. **shape**: [`ftwire_lab::log::shape::shape_record`], the same call `ftwire shape --log`
//!    makes: the centreline at 64 nodes, `stable` (`ã ∈ A_stable`) and `confident` (stable and
//!    no jump from the previous estimate);
//! 5. **contact** (with `contact_miss`): the reported tip pose against the estimated shape's
//!    tip. A free wire's shape ends at the gripper; a contact is a force the model does not
//!    have, so the estimate's tip misses the gripper. A miss above `contact_miss` is a contact.
//!
//! It publishes the centreline as `nav_msgs/Path` on [`SHAPE_TOPIC`] (frame [`BASE_FRAME`],
//! orientation left at the identity), the wire as a `LINE_STRIP` (green when confident,
//! orange otherwise) with a `SPHERE` at the shape's tip when there is a contact (`DELETE`
//! when none) on [`MARKERS_VIZ_TOPIC`], and `{"stamp", "a", "stable", "confident",
//! "contact"}` on [`STATUS_TOPIC`], each stamped with the wrench's stamp.
//!
//! **Keeping up.** Steps 1–3 are a few hundred floating-point operations per sample; the
//! shape solve costs more. After each wake-up the node takes every sample waiting and runs
//! steps 1–3 on each; it then solves and publishes them in order, but skips a sample that has
//! a newer one behind it and has waited longer than one sensor period since its arrival: a
//! stale sample is counted as `dropped`, never queued, and the latest is always solved. No
//! estimate is published before the window is full. The latency of a publication is the time from the
//! wrench's arrival at the node's DDS reader to the publication of its shape.
//!
//! With `truth_topic` (a simulator's `/wire/truth`), each true centreline received is compared
//! with the latest shape: the distance of each true node to the estimated polyline, averaged
//! per message (`truth_mm`).

use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use ftwire_core::FtSample;
use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::ft::{RestAverage, Tare};
use ftwire_estimate::shape::{ShapeEstimator, marker_distances};
use ftwire_lab::log::shape::shape_record;
use ftwire_lab::log::{LogLine, LogRecord, RawMap, a_tilde};
use ftwire_lab::wire::WireSpec;
use nalgebra::{Point3, Vector3, Vector6};
use ros2_client::MessageInfo;
use ros2_client::dds::rustdds::mio1::{Events, Interest, Poll, Token};
use serde::Serialize;

use super::stats::{LossCounter, Spread};
use super::{
    BASE_FRAME, Counts, Log, MARKERS_VIZ_TOPIC, NodeError, NodeSettings, RosNode, SENSOR_FRAME,
    SHAPE_TOPIC, STATUS_TOPIC, WRENCH_QUEUE, count, publish, reliable, seconds, should_stop,
};
use crate::msg::{
    self, ColorRGBA, Marker, MarkerArray, Path, PoseStamped, StringMsg, WrenchStamped,
};
use crate::node::sim::{pose_of, ros_point};

/// The line width of the drawn wire \[m\].
const LINE_WIDTH: f64 = 0.004;
/// The diameter of the contact sphere \[m\].
const SPHERE_DIAMETER: f64 = 0.03;
/// Longest wait in one poll, so that a stop or the end of the duration is seen \[ms\].
const POLL_MS: u64 = 20;

/// What the estimator listens to and how it maps a reading to `ã`.
#[derive(Debug, Clone)]
pub struct EstimateNodeParams {
    /// The wire the shapes are solved for.
    pub wire: WireSpec,
    /// The calibration and mounting: raw readings to `ã`.
    pub map: RawMap,
    /// Samples of the tare, with nothing in the gripper (0: no tare) (default 500).
    pub tare: usize,
    /// Samples averaged, 1 to 100 000 (default 100).
    pub window: usize,
    /// The sensor's rate \[Hz\], to count lost samples from the stamps (default 1000).
    pub rate: f64,
    /// The wrench topic.
    pub wrench_topic: String,
    /// The tip pose topic.
    pub tip_pose_topic: String,
    /// A true centreline to compare the shapes with (a simulator's `/wire/truth`).
    pub truth_topic: Option<String>,
    /// A tip miss above this is a contact \[m\]; `None`: no contact check.
    pub contact_miss: Option<f64>,
}

/// The comparison with the true centreline.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TruthError {
    /// True centrelines compared.
    pub compared: u64,
    /// The mean over them of the mean distance of the true nodes to the shape \[mm\].
    pub mean_mm: f64,
    /// The largest mean distance of one of them \[mm\].
    pub worst_mean_mm: f64,
    /// The largest distance of one true node to its shape \[mm\].
    pub max_mm: f64,
}

/// The end of a run: one JSON line.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EstimateSummary {
    /// `"estimate"`.
    pub node: &'static str,
    /// Messages received, by topic.
    pub received: Counts,
    /// Messages published, by topic.
    pub published: Counts,
    /// Messages refused, by reason: `frame_id`, `non_finite`, `malformed`.
    pub refused: Counts,
    /// Messages the middleware would not publish, by topic.
    pub publish_failed: Counts,
    /// Samples missing from the stamp sequence (between the first and the last received).
    pub lost: u64,
    /// Samples whose stamp was not after the one before.
    pub out_of_order: u64,
    /// Index `k` of the first sample received (`k / rate` its stamp): 0 when the tare saw the
    /// stream from its start.
    pub first_sample: Option<i64>,
    /// Samples skipped as stale: a newer one had arrived, and they had waited longer than one
    /// sensor period.
    pub dropped: u64,
    /// Samples the model had no shape for.
    pub no_shape: u64,
    /// Estimates flagged not confident.
    pub not_confident: u64,
    /// Estimates with a contact.
    pub contacts: u64,
    /// From a wrench's arrival to its shape's publication \[ms\].
    pub latency_ms: Option<Spread>,
    /// One shape solve (step 4) \[ms\].
    pub solve_ms: Option<Spread>,
    /// The shapes against the truth, with `truth_topic`.
    pub truth: Option<TruthError>,
}

/// The running state of steps 1–3.
struct Pipeline {
    tare_samples: Vec<FtSample>,
    tare_target: usize,
    tare: Option<Tare>,
    window: Vec<Vector6<f64>>,
    next: usize,
    filled: usize,
    sum: Vector6<f64>,
    map: RawMap,
}

impl Pipeline {
    fn new(params: &EstimateNodeParams) -> Self {
        Self {
            tare_samples: Vec::with_capacity(params.tare),
            tare_target: params.tare,
            tare: (params.tare == 0).then(Tare::none),
            window: vec![Vector6::zeros(); params.window],
            next: 0,
            filled: 0,
            sum: Vector6::zeros(),
            map: params.map.clone(),
        }
    }

    /// Takes a raw sample (force first); returns `ã` once the tare is done.
    fn add(&mut self, raw: Vector6<f64>, time: f64) -> Option<Result<Vector6<f64>, String>> {
        let Some(tare) = &self.tare else {
            self.tare_samples.push(FtSample {
                time,
                raw,
                saturated: [false; 6],
            });
            if self.tare_samples.len() >= self.tare_target {
                let rest = RestAverage::new(self.tare_target.div_ceil(2))
                    .and_then(|average| average.average(self.tare_samples.iter().map(Some)))
                    .map_err(|e| e.to_string());
                return match rest {
                    Ok(rest) => {
                        self.tare = Some(Tare::from_rest(&rest, &Vector6::zeros()));
                        None
                    }
                    Err(e) => {
                        self.tare_samples.clear();
                        Some(Err(format!("the tare failed ({e}); taring again")))
                    }
                };
            }
            return None;
        };
        let tared = tare.apply(&raw);
        let len = self.window.len();
        self.sum += tared - self.window[self.next];
        self.window[self.next] = tared;
        self.next = (self.next + 1) % len;
        self.filled = (self.filled + 1).min(len);
        if self.next == 0 {
            // Once per window, the sum afresh: no rounding drift over a long run.
            self.sum = self.window.iter().sum();
        }
        if self.filled < len {
            return None;
        }
        #[allow(clippy::cast_precision_loss)] // a window far below 2⁵²
        let mean = self.sum / len as f64;
        let line = LogLine {
            line: 0,
            record: LogRecord {
                time,
                raw: Some(mean.into()),
                a: None,
                b: None,
                markers: None,
                gravity: None,
            },
        };
        Some(
            a_tilde(&line, &self.map)
                .map_err(|e| e.to_string())
                .and_then(|a| {
                    if a.iter().all(|v| v.is_finite()) {
                        Ok(a)
                    } else {
                        Err("the calibration gave a value that is not finite".to_owned())
                    }
                }),
        )
    }
}

/// A sample waiting for its shape.
struct Pending {
    stamp: msg::Time,
    a: Vector6<f64>,
    /// When it reached the node's DDS reader, ns since the Unix epoch.
    arrival_ns: i64,
}

fn now_ns() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_nanos()).unwrap_or(i64::MAX))
}

fn finite_wrench(w: &msg::Wrench) -> Option<Vector6<f64>> {
    let v = Vector6::new(
        w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z,
    );
    v.iter().all(|x| x.is_finite()).then_some(v)
}

fn arrival(info: &MessageInfo) -> i64 {
    info.received_timestamp()
        .map_or_else(now_ns, |t| t.to_nanos())
}

/// The drawn wire and the contact sphere.
fn markers(
    header: &msg::Header,
    points: &[msg::Point],
    confident: bool,
    contact: Option<&msg::Point>,
) -> MarkerArray {
    let color = if confident {
        ColorRGBA {
            r: 0.1,
            g: 0.8,
            b: 0.2,
            a: 1.0,
        }
    } else {
        ColorRGBA {
            r: 1.0,
            g: 0.55,
            b: 0.0,
            a: 1.0,
        }
    };
    let line = Marker {
        header: header.clone(),
        ns: "wire".to_owned(),
        id: 0,
        kind: Marker::LINE_STRIP,
        action: Marker::ADD,
        scale: msg::Vector3 {
            x: LINE_WIDTH,
            y: 0.0,
            z: 0.0,
        },
        color,
        points: points.to_vec(),
        ..Marker::default()
    };
    let sphere = Marker {
        header: header.clone(),
        ns: "contact".to_owned(),
        id: 0,
        kind: Marker::SPHERE,
        action: if contact.is_some() {
            Marker::ADD
        } else {
            Marker::DELETE
        },
        pose: msg::Pose {
            position: contact.copied().unwrap_or_default(),
            orientation: msg::Quaternion::default(),
        },
        scale: msg::Vector3 {
            x: SPHERE_DIAMETER,
            y: SPHERE_DIAMETER,
            z: SPHERE_DIAMETER,
        },
        color: ColorRGBA {
            r: 1.0,
            g: 0.0,
            b: 0.0,
            a: 0.8,
        },
        ..Marker::default()
    };
    MarkerArray {
        markers: vec![line, sphere],
    }
}

/// The status line of one estimate.
#[derive(Serialize)]
struct Status {
    stamp: f64,
    a: [f64; 6],
    stable: bool,
    confident: bool,
    contact: bool,
}

impl EstimateNodeParams {
    fn validate(&self) -> Result<(), NodeError> {
        if !(1..=100_000).contains(&self.window) {
            return Err(NodeError::BadSetting {
                setting: "--window",
                value: self.window.to_string(),
                allowed: "1 to 100000 samples",
            });
        }
        if self.tare > 1_000_000 {
            return Err(NodeError::BadSetting {
                setting: "--tare",
                value: self.tare.to_string(),
                allowed: "0 to 1000000 samples",
            });
        }
        if !(self.rate.is_finite() && (1.0..=10_000.0).contains(&self.rate)) {
            return Err(NodeError::BadSetting {
                setting: "--rate",
                value: self.rate.to_string(),
                allowed: "the sensor's rate, 1 Hz to 10 kHz",
            });
        }
        if let Some(miss) = self.contact_miss
            && !(miss.is_finite() && miss > 0.0)
        {
            return Err(NodeError::BadSetting {
                setting: "--contact-miss",
                value: (1e3 * miss).to_string(),
                allowed: "a positive distance in mm",
            });
        }
        if let Some(spec) = self.map.mounting()
            && spec.tool_mass > 0.0
        {
            return Err(NodeError::BadSetting {
                setting: "--mounting",
                value: format!("tool_mass = {} kg", spec.tool_mass),
                allowed: "a mounting without a tool: the wrench carries no gravity vector to take \
                          the tool's weight out with",
            });
        }
        Ok(())
    }
}

/// Runs the estimator (module docs) until `settings.duration` ends or `stop` is set.
///
/// # Errors
/// [`NodeError`] for bad settings, a bad wire, or ROS 2 entities that cannot be created. Bad
/// messages are refused and counted, never errors.
#[allow(clippy::too_many_lines)] // one loop: receive, estimate, publish
pub fn run(
    params: &EstimateNodeParams,
    settings: NodeSettings,
    stop: &AtomicBool,
    log: Log<'_>,
) -> Result<EstimateSummary, NodeError> {
    settings.validate()?;
    params.validate()?;
    let started = Instant::now();
    let wire = params
        .wire
        .wire_params()
        .map_err(|e| NodeError::BadSetting {
            setting: "--wire",
            value: format!("{} ({e})", params.wire.name),
            allowed: "a wire with valid parameters",
        })?;
    let mut estimator = ShapeEstimator::new(KirchhoffModel::new(wire));
    let mut node = RosNode::new("ftwire_estimate", settings.domain_id)?;
    let small = reliable(10);
    let mut wrench_sub =
        node.subscription::<WrenchStamped>(&params.wrench_topic, &reliable(WRENCH_QUEUE))?;
    let mut tip_sub = node.subscription::<PoseStamped>(&params.tip_pose_topic, &small)?;
    let mut truth_sub = params
        .truth_topic
        .as_deref()
        .map(|topic| node.subscription::<Path>(topic, &small))
        .transpose()?;
    let shape_pub = node.publisher::<Path>(SHAPE_TOPIC, &small)?;
    let markers_pub = node.publisher::<MarkerArray>(MARKERS_VIZ_TOPIC, &small)?;
    let status_pub = node.publisher::<StringMsg>(STATUS_TOPIC, &small)?;
    log(&format!(
        "estimate: domain {}; subscribed to {} (frame {SENSOR_FRAME}) and {} (frame \
         {BASE_FRAME}){}; publishing {SHAPE_TOPIC}, {MARKERS_VIZ_TOPIC}, {STATUS_TOPIC}; wire \
         {}, tare {} samples, window {}",
        settings.domain_id,
        params.wrench_topic,
        params.tip_pose_topic,
        params
            .truth_topic
            .as_ref()
            .map_or_else(String::new, |t| format!(" and {t}")),
        params.wire.name,
        params.tare,
        params.window
    ));

    let ros_error = |what: &str, e: std::io::Error| NodeError::Ros {
        what: what.to_owned(),
        message: e.to_string(),
    };
    let mut poll = Poll::new().map_err(|e| ros_error("a poll", e))?;
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
    let mut events = Events::with_capacity(16);

    let mut summary = EstimateSummary {
        node: "estimate",
        received: Counts::new(),
        published: Counts::new(),
        refused: Counts::new(),
        publish_failed: Counts::new(),
        lost: 0,
        out_of_order: 0,
        first_sample: None,
        dropped: 0,
        no_shape: 0,
        not_confident: 0,
        contacts: 0,
        latency_ms: None,
        solve_ms: None,
        truth: None,
    };
    let mut pipeline = Pipeline::new(params);
    let mut loss = LossCounter::new(params.rate);
    let mut tip: Option<Vector3<f64>> = None;
    let mut shape: Vec<Vector3<f64>> = Vec::new();
    let mut latencies: Vec<f64> = Vec::with_capacity(1 << 16);
    let mut solves: Vec<f64> = Vec::with_capacity(1 << 16);
    let (mut truth_sum, mut truth_worst, mut truth_max, mut truth_n) = (0.0, 0.0_f64, 0.0_f64, 0);
    let mut index = 0_usize;
    let mut batch: Vec<Pending> = Vec::with_capacity(WRENCH_QUEUE);
    #[allow(clippy::cast_possible_truncation)] // a period of at least 0.1 ms
    let stale_ns = (1e9 / params.rate) as i64;
    let mut tared_logged = params.tare == 0;
    let mut last_error: Option<String> = None;

    while !should_stop(stop, started, settings.duration) {
        if let Err(e) = poll.poll(&mut events, Some(Duration::from_millis(POLL_MS)))
            && e.kind() != std::io::ErrorKind::Interrupted
        {
            return Err(ros_error("polling", e));
        }
        // The tip pose first: the contact check of this batch uses the latest.
        loop {
            match tip_sub.take() {
                Ok(Some((pose, _))) => {
                    count(&mut summary.received, "tip_pose");
                    if pose.header.frame_id != BASE_FRAME {
                        count(&mut summary.refused, "frame_id");
                    } else {
                        match pose_of(&pose.pose) {
                            Ok(p) => tip = Some(p.translation.vector),
                            Err(_) => count(&mut summary.refused, "non_finite"),
                        }
                    }
                }
                Ok(None) => break,
                Err(_) => count(&mut summary.refused, "malformed"),
            }
        }
        batch.clear();
        loop {
            match wrench_sub.take() {
                Ok(Some((wrench, info))) => {
                    count(&mut summary.received, "wrench");
                    if wrench.header.frame_id != SENSOR_FRAME {
                        count(&mut summary.refused, "frame_id");
                        continue;
                    }
                    let Some(raw) = finite_wrench(&wrench.wrench) else {
                        count(&mut summary.refused, "non_finite");
                        continue;
                    };
                    let t = seconds(&wrench.header.stamp);
                    loss.add(t);
                    match pipeline.add(raw, t) {
                        None => {}
                        Some(Ok(a)) => {
                            batch.push(Pending {
                                stamp: wrench.header.stamp,
                                a,
                                arrival_ns: arrival(&info),
                            });
                        }
                        Some(Err(e)) => {
                            summary.no_shape += 1;
                            if last_error.as_ref() != Some(&e) {
                                log(&format!("estimate: no ã at t = {t:.3} s: {e}"));
                                last_error = Some(e);
                            }
                        }
                    }
                }
                Ok(None) => break,
                Err(_) => count(&mut summary.refused, "malformed"),
            }
        }
        if !tared_logged && pipeline.tare.is_some() {
            tared_logged = true;
            log(&format!(
                "estimate: tared on {} samples from k = {}",
                params.tare,
                loss.first().unwrap_or_default()
            ));
        }
        let waiting = batch.len();
        for (i, sample) in batch.iter().enumerate() {
            // A sample with a newer one behind it, waiting longer than its period: stale.
            if i + 1 < waiting && now_ns() - sample.arrival_ns > stale_ns {
                summary.dropped += 1;
                continue;
            }
            let solve_start = Instant::now();
            let record = LogRecord {
                time: seconds(&sample.stamp),
                raw: None,
                a: Some(sample.a.into()),
                b: None,
                markers: None,
                gravity: None,
            };
            let solved = shape_record(&mut estimator, index, &record, &sample.a);
            index += 1;
            solves.push(1e3 * solve_start.elapsed().as_secs_f64());
            match solved {
                Ok(result) if result.points.is_some() => {
                    let points = result.points.unwrap_or_default();
                    shape.clear();
                    shape.extend(points.iter().map(|p| Vector3::from(*p)));
                    let stable = result.confidence != Some("not_stable");
                    let confident = result.confidence == Some("confident");
                    let contact = match (params.contact_miss, tip, shape.last()) {
                        (Some(miss), Some(tip), Some(end)) if (end - tip).norm() > miss => {
                            Some(ros_point(end))
                        }
                        _ => None,
                    };
                    summary.not_confident += u64::from(!confident);
                    summary.contacts += u64::from(contact.is_some());
                    let header = msg::Header {
                        stamp: sample.stamp,
                        frame_id: BASE_FRAME.to_owned(),
                    };
                    let ros_points: Vec<msg::Point> = shape.iter().map(ros_point).collect();
                    let path = Path {
                        poses: ros_points
                            .iter()
                            .map(|p| PoseStamped {
                                header: header.clone(),
                                pose: msg::Pose {
                                    position: *p,
                                    orientation: msg::Quaternion::default(),
                                },
                            })
                            .collect(),
                        header: header.clone(),
                    };
                    let (published, failed) = (&mut summary.published, &mut summary.publish_failed);
                    publish(&shape_pub, path, "shape", published, failed);
                    let drawn = markers(&header, &ros_points, confident, contact.as_ref());
                    publish(&markers_pub, drawn, "markers_viz", published, failed);
                    let status = Status {
                        stamp: seconds(&sample.stamp),
                        a: sample.a.into(),
                        stable,
                        confident,
                        contact: contact.is_some(),
                    };
                    if let Ok(data) = serde_json::to_string(&status) {
                        publish(&status_pub, StringMsg { data }, "status", published, failed);
                    }
                    #[allow(clippy::cast_precision_loss)] // nanoseconds of a short latency
                    latencies.push(1e-6 * (now_ns() - sample.arrival_ns) as f64);
                }
                Ok(result) => {
                    summary.no_shape += 1;
                    let e = result.error.unwrap_or_default();
                    if last_error.as_ref() != Some(&e) {
                        log(&format!(
                            "estimate: no shape for ã = {:?}: {e}",
                            sample.a.as_slice()
                        ));
                        last_error = Some(e);
                    }
                }
                Err(e) => {
                    summary.no_shape += 1;
                    log(&format!("estimate: {e}"));
                }
            }
        }
        if let Some(sub) = truth_sub.as_ref() {
            loop {
                match sub.take() {
                    Ok(Some((truth, _))) => {
                        count(&mut summary.received, "truth");
                        if truth.header.frame_id != BASE_FRAME {
                            count(&mut summary.refused, "frame_id");
                            continue;
                        }
                        let nodes: Vec<Point3<f64>> = truth
                            .poses
                            .iter()
                            .map(|p| {
                                Point3::new(p.pose.position.x, p.pose.position.y, p.pose.position.z)
                            })
                            .collect();
                        if shape.len() < 2 {
                            continue;
                        }
                        match marker_distances(&nodes, &shape) {
                            Ok(d) if !d.is_empty() => {
                                #[allow(clippy::cast_precision_loss)] // a few hundred nodes
                                let mean = 1e3 * d.iter().sum::<f64>() / d.len() as f64;
                                truth_sum += mean;
                                truth_worst = truth_worst.max(mean);
                                truth_max = d.iter().fold(truth_max, |m, v| m.max(1e3 * v));
                                truth_n += 1;
                            }
                            _ => count(&mut summary.refused, "non_finite"),
                        }
                    }
                    Ok(None) => break,
                    Err(_) => count(&mut summary.refused, "malformed"),
                }
            }
        }
    }
    summary.lost = loss.lost();
    summary.out_of_order = loss.out_of_order();
    summary.first_sample = loss.first();
    summary.latency_ms = Spread::of(&mut latencies);
    summary.solve_ms = Spread::of(&mut solves);
    #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
    if truth_n > 0 {
        summary.truth = Some(TruthError {
            compared: truth_n,
            mean_mm: truth_sum / truth_n as f64,
            worst_mean_mm: truth_worst,
            max_mm: truth_max,
        });
    }
    log(&format!(
        "estimate: stopped; {} wrenches received, {} lost, {} dropped as stale",
        summary.received.get("wrench").copied().unwrap_or(0),
        summary.lost,
        summary.dropped
    ));
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use super::*;
    use ftwire_estimate::ft::MountingSpec;

    fn params(tare: usize, window: usize) -> EstimateNodeParams {
        EstimateNodeParams {
            wire: WireSpec::load("nitinol-3mm-820").expect("a preset"),
            map: RawMap::new(None, Some(MountingSpec::default())).expect("a mounting"),
            tare,
            window,
            rate: 1000.0,
            wrench_topic: "/ft_sensor/wrench".into(),
            tip_pose_topic: "/wire/tip_pose".into(),
            truth_topic: None,
            contact_miss: None,
        }
    }

    #[test]
    fn the_pipeline_tares_then_averages_a_window_then_maps() {
        let p = params(4, 3);
        let mut pipeline = Pipeline::new(&p);
        let offset = Vector6::new(0.3, -0.2, 0.6, 0.01, -0.008, 0.005);
        for i in 0..4 {
            assert!(pipeline.add(offset, f64::from(i) * 1e-3).is_none());
        }
        let load = Vector6::new(0.1, 0.2, -0.3, 0.01, 0.02, 0.0);
        let mut last = Vector6::zeros();
        for i in 0..10 {
            let jitter = if i % 2 == 0 { 0.01 } else { -0.01 };
            let raw = offset + load + Vector6::repeat(jitter);
            match pipeline.add(raw, 0.004 + f64::from(i) * 1e-3) {
                // Nothing until the window is full.
                None => assert!(i < 2, "sample {i}"),
                Some(a) => last = a.expect("mapped"),
            }
        }
        let mounting = MountingSpec::default().mounting().expect("valid");
        // The last three jitters average to −0.01/3.
        let expected = mounting.to_configuration(&(load + Vector6::repeat(-0.01 / 3.0)));
        assert!((last - expected).norm() < 1e-12, "{last} vs {expected}");
    }

    #[test]
    fn a_mounting_with_a_tool_is_refused() {
        let mut p = params(0, 1);
        p.map = RawMap::new(
            None,
            Some(MountingSpec {
                tool_mass: 0.3,
                ..MountingSpec::default()
            }),
        )
        .expect("valid");
        assert!(matches!(
            p.validate(),
            Err(NodeError::BadSetting {
                setting: "--mounting",
                ..
            })
        ));
        assert!(params(0, 0).validate().is_err());
    }

    #[test]
    fn the_drawn_wire_is_green_when_confident_and_the_sphere_is_deleted_without_contact() {
        let h = super::super::header(0.0, BASE_FRAME);
        let points = [
            msg::Point::default(),
            msg::Point {
                x: 0.5,
                y: 0.0,
                z: 0.0,
            },
        ];
        let free = markers(&h, &points, true, None);
        assert_eq!(free.markers[0].kind, Marker::LINE_STRIP);
        assert!(free.markers[0].color.g > free.markers[0].color.r);
        assert_eq!(free.markers[1].action, Marker::DELETE);
        let touched = markers(&h, &points, false, Some(&points[1]));
        assert!(touched.markers[0].color.r > touched.markers[0].color.g);
        assert_eq!(
            (touched.markers[1].kind, touched.markers[1].action),
            (Marker::SPHERE, Marker::ADD)
        );
    }
}
