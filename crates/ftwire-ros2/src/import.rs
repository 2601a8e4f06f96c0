//! From a ROS 2 bag to ftwire's log: one [`LogRecord`] per rest of the second gripper, what
//! `ftwire shape --log`, `identify --log` and `calibrate --log` read (`docs/real-rig.md`).
//!
//! The bag holds three topics:
//! - the wrench, `geometry_msgs/WrenchStamped`, at the sensor's rate (e.g. 1 kHz), in the
//!   sensor frame, force \[N\] and torque \[N·m\] as the sensor gives them;
//! - the tip pose, `geometry_msgs/PoseStamped`: the second gripper's clamp pose relative to the
//!   base clamp, position \[m\];
//! - optionally the markers, `geometry_msgs/PoseArray`: marker positions \[m\] in the base
//!   clamp frame, in order along the wire (marker 0 at the clamp); a non-finite position is a
//!   dropout.
//!
//! Every message's time is its header stamp. A rest is a maximal run of tip poses that all stay
//! within [`RestParams::position_tolerance`] and [`RestParams::angle_tolerance`] of the run's
//! first pose, lasting at least [`RestParams::min_duration`] from its first pose to its last.
//! Over the rest's window, from its start plus [`RestParams::settle`] to its end, the wrench is
//! averaged: the line's `raw`, force first `(f1, f2, f3, τ1, τ2, τ3)`. The tip poses in the same
//! window are averaged into `b` (position, and the rotation as a rotation vector \[rad\]); the
//! last markers message in the rest gives `markers` (a dropout is `null`); `time` is the rest's
//! end \[s\] on the stamps' clock.
//!
//! A message that cannot be used is skipped and counted by reason ([`Skipped`]), never fatal:
//! bytes that do not decode, a non-finite value, a stamp with nanoseconds beyond 10⁹, a tip
//! orientation that is not a unit quaternion, a frame other than the one required, a stamp
//! earlier than the topic's previous one.

use std::path::PathBuf;

use ftwire_estimate::log::{LogPose, LogRecord};
use nalgebra::{Quaternion, Translation3, UnitQuaternion, Vector3};
use serde::Serialize;
use thiserror::Error;

use crate::bag::{BagError, BagMessage, BagReader};
use crate::msg::{self, RosMessage};

/// How a rest is found in the tip poses.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RestParams {
    /// How far the tip may move during a rest, from the rest's first pose \[m\] (default
    /// `1e-3`): above the pose's noise, below the smallest move between rests.
    pub position_tolerance: f64,
    /// How far the tip may turn during a rest, from the rest's first pose \[rad\] (default
    /// `0.01`, 0.57°).
    pub angle_tolerance: f64,
    /// The shortest rest, from its first pose to its last \[s\] (default `1.5`); must exceed
    /// `settle`, so that some of every rest is averaged.
    pub min_duration: f64,
    /// Left out at each rest's start while the wire settles \[s\] (default `1.0`: about 1 s for
    /// a metre of nitinol).
    pub settle: f64,
}

impl Default for RestParams {
    fn default() -> Self {
        Self {
            position_tolerance: 1e-3,
            angle_tolerance: 0.01,
            min_duration: 1.5,
            settle: 1.0,
        }
    }
}

impl RestParams {
    /// Checks every value.
    ///
    /// # Errors
    /// [`ImportError::BadParam`] naming the value and what is allowed.
    pub fn check(&self) -> Result<(), ImportError> {
        let bad = |name: &'static str, value: f64, allowed: &'static str| {
            Err(ImportError::BadParam {
                name,
                value,
                allowed,
            })
        };
        if !(self.position_tolerance.is_finite() && self.position_tolerance > 0.0) {
            return bad(
                "position tolerance [m]",
                self.position_tolerance,
                "a finite number above 0",
            );
        }
        if !(self.angle_tolerance.is_finite()
            && self.angle_tolerance > 0.0
            && self.angle_tolerance <= std::f64::consts::PI)
        {
            return bad(
                "angle tolerance [rad]",
                self.angle_tolerance,
                "above 0 and at most π",
            );
        }
        if !(self.settle.is_finite() && self.settle >= 0.0) {
            return bad("settle time [s]", self.settle, "a finite number, 0 or more");
        }
        if !(self.min_duration.is_finite() && self.min_duration > self.settle) {
            return bad(
                "minimum rest [s]",
                self.min_duration,
                "a finite number above the settle time",
            );
        }
        Ok(())
    }
}

/// What to import.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ImportParams {
    /// The wrench topic (`geometry_msgs/msg/WrenchStamped`).
    pub wrench_topic: String,
    /// The tip pose topic (`geometry_msgs/msg/PoseStamped`).
    pub tip_pose_topic: String,
    /// The markers topic (`geometry_msgs/msg/PoseArray`), if any.
    pub markers_topic: Option<String>,
    /// How rests are found.
    pub rest: RestParams,
    /// The `frame_id` every wrench must have (others are skipped); `None` takes any.
    pub wrench_frame: Option<String>,
    /// The `frame_id` every tip pose must have; `None` takes any.
    pub tip_frame: Option<String>,
    /// The `frame_id` every markers message must have; `None` takes any.
    pub markers_frame: Option<String>,
}

impl ImportParams {
    /// The wrench and tip pose topics with the default rest settings, no markers and no frame
    /// required.
    pub fn new(wrench_topic: impl Into<String>, tip_pose_topic: impl Into<String>) -> Self {
        Self {
            wrench_topic: wrench_topic.into(),
            tip_pose_topic: tip_pose_topic.into(),
            markers_topic: None,
            rest: RestParams::default(),
            wrench_frame: None,
            tip_frame: None,
            markers_frame: None,
        }
    }
}

/// Why a bag could not be imported.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ImportError {
    /// A setting out of range.
    #[error("{name} = {value} is not allowed: {allowed}")]
    BadParam {
        /// The setting, with its unit.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// A topic asked for holds no message.
    #[error("{}: the {role} topic {topic} has no messages in the bag; it has: {available}", path.display())]
    MissingTopic {
        /// The bag.
        path: PathBuf,
        /// What the topic was for (`wrench`, `tip pose`, `markers`).
        role: &'static str,
        /// The topic asked for.
        topic: String,
        /// The bag's topics, `name (type)`.
        available: String,
    },
    /// A topic asked for holds another message type.
    #[error("{}: the {role} topic {topic} holds {found}; it must be {expected}", path.display())]
    WrongType {
        /// The bag.
        path: PathBuf,
        /// What the topic was for.
        role: &'static str,
        /// The topic.
        topic: String,
        /// Its type in the bag.
        found: String,
        /// The type needed.
        expected: &'static str,
    },
    /// The bag itself.
    #[error(transparent)]
    Bag(#[from] BagError),
}

/// Messages skipped, by reason (each counts messages of every topic read).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Skipped {
    /// Bytes that are not a message of the topic's type.
    pub undecodable: usize,
    /// A NaN or infinite wrench or tip pose value.
    pub non_finite: usize,
    /// A stamp whose nanoseconds are 10⁹ or more.
    pub bad_stamp: usize,
    /// A tip orientation whose norm is more than 10⁻³ from 1.
    pub not_unit_quaternion: usize,
    /// A `frame_id` other than the one required.
    pub wrong_frame: usize,
    /// A stamp earlier than the topic's previous message.
    pub backwards: usize,
}

impl Skipped {
    /// Every skipped message.
    pub fn total(&self) -> usize {
        self.undecodable
            + self.non_finite
            + self.bad_stamp
            + self.not_unit_quaternion
            + self.wrong_frame
            + self.backwards
    }
}

/// What an import found.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ImportSummary {
    /// Rests written, one log line each.
    pub rests: usize,
    /// Rests found in the tip poses but left out: no wrench sample in their window.
    pub rests_without_wrench: usize,
    /// Rests written without markers, when a markers topic was given: none in the rest.
    pub rests_without_markers: usize,
    /// Wrench messages read.
    pub wrench_messages: usize,
    /// Wrench samples averaged into the rests.
    pub wrench_samples_used: usize,
    /// Tip pose messages read.
    pub tip_pose_messages: usize,
    /// Markers messages read.
    pub markers_messages: usize,
    /// Messages skipped, by reason.
    pub skipped: Skipped,
}

impl std::fmt::Display for ImportSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = &self.skipped;
        write!(
            f,
            "{} rests ({} without wrench left out), {} of {} wrench samples used, {} tip poses, \
             {} markers messages; skipped {}: {} undecodable, {} non-finite, {} bad stamp, \
             {} not unit quaternion, {} wrong frame, {} backwards",
            self.rests,
            self.rests_without_wrench,
            self.wrench_samples_used,
            self.wrench_messages,
            self.tip_pose_messages,
            self.markers_messages,
            s.total(),
            s.undecodable,
            s.non_finite,
            s.bad_stamp,
            s.not_unit_quaternion,
            s.wrong_frame,
            s.backwards
        )
    }
}

/// The log lines and the summary.
#[derive(Debug, Clone, PartialEq)]
pub struct Import {
    /// One record per rest, in time order.
    pub records: Vec<LogRecord>,
    /// What was found and skipped.
    pub summary: ImportSummary,
}

/// A stamp in nanoseconds, or `None` for nanoseconds out of range.
fn stamp_ns(stamp: &msg::Time) -> Option<i64> {
    (stamp.nanosec < 1_000_000_000)
        .then(|| i64::from(stamp.sec) * 1_000_000_000 + i64::from(stamp.nanosec))
}

/// Nanoseconds to seconds.
fn seconds(ns: i64) -> f64 {
    let sec = ns.div_euclid(1_000_000_000);
    let nanosec = ns.rem_euclid(1_000_000_000);
    sec as f64 + nanosec as f64 * 1e-9
}

/// The usable messages of one topic, in stamp order, with their stamps \[ns\].
struct Stream<T> {
    samples: Vec<(i64, T)>,
    read: usize,
}

/// Reads one topic: decodes, checks frame and stamp order, and converts with `convert`
/// (`Err` names the skip reason).
fn read_topic<M: RosMessage, T>(
    bag: &BagReader,
    topic: &str,
    frame: Option<&str>,
    header: impl Fn(&M) -> &msg::Header,
    convert: impl Fn(&M) -> Result<T, SkipReason>,
    skipped: &mut Skipped,
) -> Stream<T> {
    let mut samples: Vec<(i64, T)> = Vec::new();
    let mut read = 0;
    let on_topic = bag
        .messages()
        .iter()
        .filter(|m: &&BagMessage| m.topic.name == topic);
    for message in on_topic {
        read += 1;
        let Ok(decoded) = bag.decode::<M>(message) else {
            skipped.undecodable += 1;
            continue;
        };
        let h = header(&decoded);
        let Some(t) = stamp_ns(&h.stamp) else {
            skipped.bad_stamp += 1;
            continue;
        };
        if frame.is_some_and(|f| f != h.frame_id) {
            skipped.wrong_frame += 1;
            continue;
        }
        let value = match convert(&decoded) {
            Ok(v) => v,
            Err(SkipReason::NonFinite) => {
                skipped.non_finite += 1;
                continue;
            }
            Err(SkipReason::NotUnit) => {
                skipped.not_unit_quaternion += 1;
                continue;
            }
        };
        if samples.last().is_some_and(|(last, _)| t < *last) {
            skipped.backwards += 1;
            continue;
        }
        samples.push((t, value));
    }
    Stream { samples, read }
}

/// The markers of one message, `None` for a dropout.
type Markers = Vec<Option<[f64; 3]>>;

/// Why a decoded message is skipped.
enum SkipReason {
    NonFinite,
    NotUnit,
}

/// Checks that `topic` holds messages of type `M`.
fn check_topic<M: RosMessage>(
    bag: &BagReader,
    role: &'static str,
    topic: &str,
) -> Result<(), ImportError> {
    match bag.topic(topic) {
        None => Err(ImportError::MissingTopic {
            path: bag.path().to_path_buf(),
            role,
            topic: topic.to_string(),
            available: bag.topic_list(),
        }),
        Some(t) if t.type_name != M::TYPE_NAME => Err(ImportError::WrongType {
            path: bag.path().to_path_buf(),
            role,
            topic: topic.to_string(),
            found: if t.type_name.is_empty() {
                "messages without a schema".into()
            } else {
                t.type_name.clone()
            },
            expected: M::TYPE_NAME,
        }),
        Some(_) => Ok(()),
    }
}

/// Converts the bag to log lines, one per rest.
///
/// # Errors
/// [`ImportError::BadParam`] for a rest setting out of range; [`ImportError::MissingTopic`]
/// (naming the topics the bag has) or [`ImportError::WrongType`] for a topic asked for. Bad
/// messages are skipped and counted in the summary, never an error; a bag without a rest gives
/// no records.
pub fn import(bag: &BagReader, params: &ImportParams) -> Result<Import, ImportError> {
    params.rest.check()?;
    check_topic::<msg::WrenchStamped>(bag, "wrench", &params.wrench_topic)?;
    check_topic::<msg::PoseStamped>(bag, "tip pose", &params.tip_pose_topic)?;
    if let Some(topic) = &params.markers_topic {
        check_topic::<msg::PoseArray>(bag, "markers", topic)?;
    }
    let mut summary = ImportSummary::default();
    let mut skipped = Skipped::default();

    let wrench = read_topic::<msg::WrenchStamped, _>(
        bag,
        &params.wrench_topic,
        params.wrench_frame.as_deref(),
        |m| &m.header,
        |m| {
            let (f, t) = (m.wrench.force, m.wrench.torque);
            let raw = [f.x, f.y, f.z, t.x, t.y, t.z];
            if raw.iter().all(|v| v.is_finite()) {
                Ok(raw)
            } else {
                Err(SkipReason::NonFinite)
            }
        },
        &mut skipped,
    );
    let poses = read_topic::<msg::PoseStamped, _>(
        bag,
        &params.tip_pose_topic,
        params.tip_frame.as_deref(),
        |m| &m.header,
        |m| {
            let (p, q) = (m.pose.position, m.pose.orientation);
            if ![p.x, p.y, p.z, q.x, q.y, q.z, q.w]
                .iter()
                .all(|v| v.is_finite())
            {
                return Err(SkipReason::NonFinite);
            }
            let q = Quaternion::new(q.w, q.x, q.y, q.z);
            if (q.norm() - 1.0).abs() > 1e-3 {
                return Err(SkipReason::NotUnit);
            }
            Ok((
                Vector3::new(p.x, p.y, p.z),
                UnitQuaternion::from_quaternion(q),
            ))
        },
        &mut skipped,
    );
    let markers = params.markers_topic.as_ref().map(|topic| {
        read_topic::<msg::PoseArray, _>(
            bag,
            topic,
            params.markers_frame.as_deref(),
            |m| &m.header,
            |m| {
                Ok(m.poses
                    .iter()
                    .map(|p| {
                        let x = [p.position.x, p.position.y, p.position.z];
                        x.iter().all(|v| v.is_finite()).then_some(x)
                    })
                    .collect::<Vec<_>>())
            },
            &mut skipped,
        )
    });
    summary.wrench_messages = wrench.read;
    summary.tip_pose_messages = poses.read;
    summary.markers_messages = markers.as_ref().map_or(0, |m| m.read);

    let wrench: Vec<(i64, [f64; 6])> = wrench.samples;
    let poses: Vec<(i64, Vector3<f64>, UnitQuaternion<f64>)> = poses
        .samples
        .into_iter()
        .map(|(t, (p, q))| (t, p, q))
        .collect();
    let markers: Option<Vec<(i64, Markers)>> = markers.map(|m| m.samples);

    let rest = &params.rest;
    let settle_ns = (rest.settle * 1e9).round() as i64;
    let min_ns = (rest.min_duration * 1e9).round() as i64;
    let mut records = Vec::new();
    for (first, last) in rests(
        &poses,
        rest.position_tolerance,
        rest.angle_tolerance,
        min_ns,
    ) {
        let (start, end) = (poses[first].0, poses[last].0);
        let from = start.saturating_add(settle_ns);
        let in_window = |t: i64| t >= from && t <= end;
        let lo = wrench.partition_point(|(t, _)| *t < from);
        let hi = wrench.partition_point(|(t, _)| *t <= end);
        let window = wrench.get(lo..hi).unwrap_or_default();
        if window.is_empty() {
            summary.rests_without_wrench += 1;
            continue;
        }
        let mut raw = [0.0; 6];
        for (_, w) in window {
            for (sum, v) in raw.iter_mut().zip(w) {
                *sum += v;
            }
        }
        let n = window.len() as f64;
        raw.iter_mut().for_each(|v| *v /= n);
        summary.wrench_samples_used += window.len();

        let b = mean_pose(
            poses
                .get(first..=last)
                .unwrap_or_default()
                .iter()
                .filter(|(t, _, _)| in_window(*t)),
        )
        .unwrap_or_else(|| (poses[last].1, poses[last].2));
        let b = LogPose::from_pose(&ftwire_core::Pose::from_parts(Translation3::from(b.0), b.1));

        let markers = markers.as_ref().and_then(|m| {
            let hi = m.partition_point(|(t, _)| *t <= end);
            hi.checked_sub(1)
                .and_then(|i| m.get(i))
                .filter(|(t, _)| *t >= start)
                .map(|(_, points)| points.clone())
        });
        if params.markers_topic.is_some() && markers.is_none() {
            summary.rests_without_markers += 1;
        }
        records.push(LogRecord {
            time: seconds(end),
            raw: Some(raw),
            a: None,
            b: Some(b),
            markers,
            gravity: None,
        });
    }
    summary.rests = records.len();
    summary.skipped = skipped;
    Ok(Import { records, summary })
}

/// The rests in `poses` (stamp-ordered): index ranges `(first, last)`, each a maximal run
/// whose poses stay within the tolerances of its first pose, lasting at least `min_ns`.
fn rests(
    poses: &[(i64, Vector3<f64>, UnitQuaternion<f64>)],
    position_tolerance: f64,
    angle_tolerance: f64,
    min_ns: i64,
) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut first = 0;
    while first < poses.len() {
        let (t0, p0, q0) = &poses[first];
        let mut last = first;
        while let Some((_, p, q)) = poses.get(last + 1) {
            if (p - p0).norm() > position_tolerance || q.angle_to(q0) > angle_tolerance {
                break;
            }
            last += 1;
        }
        if poses[last].0 - t0 >= min_ns {
            out.push((first, last));
        }
        first = last + 1;
    }
    out
}

/// The mean of nearby poses: the mean position, and the normalised mean of the quaternions
/// (each on the first's hemisphere), which is the rotation mean to second order in the spread.
fn mean_pose<'a>(
    poses: impl Iterator<Item = &'a (i64, Vector3<f64>, UnitQuaternion<f64>)>,
) -> Option<(Vector3<f64>, UnitQuaternion<f64>)> {
    let mut n = 0usize;
    let mut position = Vector3::zeros();
    let mut sum = Quaternion::new(0.0, 0.0, 0.0, 0.0);
    let mut reference: Option<Quaternion<f64>> = None;
    for (_, p, q) in poses {
        let q = *q.quaternion();
        let r = *reference.get_or_insert(q);
        sum += if q.dot(&r) < 0.0 { -q } else { q };
        position += p;
        n += 1;
    }
    (n > 0).then(|| (position / n as f64, UnitQuaternion::from_quaternion(sum)))
}
