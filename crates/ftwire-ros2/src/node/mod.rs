//! ftwire as ROS 2 nodes, over pure-Rust DDS (`ros2-client`, no ROS installation):
//!
//! - [`sim`]: the simulator as a robot. It streams the wrist F/T sensor's samples
//!   (`geometry_msgs/WrenchStamped` on [`WRENCH_TOPIC`], frame [`SENSOR_FRAME`]), the second
//!   gripper's pose relative to the base clamp ([`TIP_POSE_TOPIC`], frame [`BASE_FRAME`]),
//!   the motion-capture markers ([`MARKERS_TOPIC`]) and the true centreline ([`TRUTH_TOPIC`],
//!   for tests; and the sensor's true bias drift, [`truth_bias`]), and moves the gripper to
//!   each pose on [`TIP_TARGET_TOPIC`];
//! - [`estimate`]: the wire's shape from each F/T sample, published as `nav_msgs/Path`
//!   ([`SHAPE_TOPIC`]), a `visualization_msgs/MarkerArray` ([`MARKERS_VIZ_TOPIC`]) and a JSON
//!   status ([`STATUS_TOPIC`]), with the experiments' bias observer and collision detector
//!   run at the rests it finds in the streams ([`observe`]) and each shape's error bars
//!   ([`sigma`]);
//! - [`identify`]: the identification motion sent on [`TIP_TARGET_TOPIC`], a rest at each pose,
//!   and the identified `c` and `L` with their covariance as JSON on
//!   [`identify::IDENTIFIED_TOPIC`];
//! - [`control`]: the library's path tracker and its closed loop of eq. 13–14 to a goal
//!   configuration (or along a planned path), a rest and a step per iteration, the model's
//!   shape on [`SHAPE_TOPIC`];
//! - [`robot`]: what the last two share: the tare, a target sent and waited for, a rest's
//!   window of samples and its average mapped to `ã`; [`ros_rig`]: that robot as the
//!   library's `Rig`, which `control` tracks its goals on;
//! - [`tf`]: the tip pose from two frames of the TF tree (`/tf`, `/tf_static`), the
//!   estimator's other tip source.
//!
//! Conventions: stamps count from the node's clock start (the sim's first sample is stamp 0;
//! the `k`-th F/T sample is stamped `k / rate` exactly, so that a receiver counts the samples
//! it lost from the stamps); poses and points in metres, in [`BASE_FRAME`] (the base clamp
//! frame, x along the wire's tangent at the clamp); wrenches force first in newtons and
//! newton-metres, as ROS and the sensor give them, and `a` torque first as everywhere in
//! ftwire. A message with another frame, or a value that is not finite, is refused and
//! counted, never acted on.
//!
//! Each node runs until its `duration` ends or `stop` is set (the binary sets it on Ctrl-C),
//! logs what it subscribed and published through `log`, and returns a summary of its counts.
//! Guarded by `crates/ftwire/tests/ros2_nodes.rs` (the sim and each other node in a network
//! namespace with only the loopback device) and the tests of each module.

pub mod control;
pub mod error;
pub mod estimate;
pub mod estimate_loop;
pub mod identify;
pub mod observe;
pub mod options;
pub mod pose;
pub mod robot;
pub mod ros_rig;
pub mod sigma;
#[cfg(feature = "sim")]
pub mod sim;
pub mod stats;
pub mod tf;
#[cfg(feature = "sim")]
pub mod truth_bias;

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use ros2_client::qos::{Durability, History, WhenFull};
use ros2_client::{Context, MessageTypeName, Name, Node, NodeName, NodeOptions, QosProfile};
use ros2_client::{Publisher, Subscription};

pub use error::NodeError;

use ftwire_core::FtSample;
use ftwire_estimate::ft::Tare;
use ftwire_logs::RawMap;
use nalgebra::{Point3, Vector6};

use crate::msg::{self, Header, Path, PoseStamped, RosMessage, Time};

/// The F/T samples.
pub const WRENCH_TOPIC: &str = "/ft_sensor/wrench";
/// The second gripper's pose relative to the base clamp.
pub const TIP_POSE_TOPIC: &str = "/wire/tip_pose";
/// Where the second gripper is to go, relative to the base clamp.
pub const TIP_TARGET_TOPIC: &str = "/wire/tip_target";
/// The motion-capture markers.
pub const MARKERS_TOPIC: &str = "/wire/markers";
/// The simulator's true centreline (ground truth, for tests).
pub const TRUTH_TOPIC: &str = "/wire/truth";
/// The estimated centreline.
pub const SHAPE_TOPIC: &str = "/wire/shape";
/// The estimated wire drawn for RViz.
pub const MARKERS_VIZ_TOPIC: &str = "/wire/markers_viz";
/// The estimator's status, one JSON object per estimate.
pub const STATUS_TOPIC: &str = "/wire/status";

/// The frame of the F/T sensor's readings.
pub const SENSOR_FRAME: &str = "ft_sensor";
/// The base clamp frame: the frame of poses, paths and markers.
pub const BASE_FRAME: &str = "wire_base";

/// F/T samples a publisher or subscriber queues (1 s at 1 kHz): a reliable writer keeps them
/// for a reader that falls behind for a moment, instead of losing them.
pub const WRENCH_QUEUE: usize = 1000;

/// Settings every node takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeSettings {
    /// The DDS domain, 0 to 232 (default: `ROS_DOMAIN_ID`, else 0).
    pub domain_id: u16,
    /// How long to run \[s\]; `None` until stopped.
    pub duration: Option<f64>,
}

impl NodeSettings {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`NodeError::BadSetting`] for a domain above 232 or a duration that is not a finite
    /// positive number of seconds.
    pub fn validate(&self) -> Result<(), NodeError> {
        if self.domain_id > 232 {
            return Err(NodeError::BadSetting {
                setting: "--domain-id",
                value: self.domain_id.to_string(),
                allowed: "a DDS domain from 0 to 232",
            });
        }
        if let Some(d) = self.duration
            && !(d.is_finite() && d > 0.0)
        {
            return Err(NodeError::BadSetting {
                setting: "--duration",
                value: d.to_string(),
                allowed: "a positive number of seconds",
            });
        }
        Ok(())
    }
}

/// Where a node writes its log lines (the binary: stderr).
pub type Log<'a> = &'a mut dyn FnMut(&str);

/// Counts by name (a topic, or a reason for a refusal), serialised as a JSON object.
pub type Counts = BTreeMap<&'static str, u64>;

/// Adds one to `name` in `counts`.
pub(crate) fn count(counts: &mut Counts, name: &'static str) {
    *counts.entry(name).or_insert(0) += 1;
}

/// Whether the node is to end: `stop` set, or `duration` past since `start`.
pub(crate) fn should_stop(stop: &AtomicBool, start: Instant, duration: Option<f64>) -> bool {
    stop.load(Ordering::Relaxed) || duration.is_some_and(|d| start.elapsed().as_secs_f64() >= d)
}

/// A stamp `t` \[s\] (non-negative) as a ROS time.
pub fn stamp(t: f64) -> Time {
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // t ≥ 0, far below 2³¹ s
    let nanos = (t.max(0.0) * 1e9).round() as u64;
    stamp_nanos(nanos)
}

/// A stamp of `nanos` nanoseconds as a ROS time.
pub fn stamp_nanos(nanos: u64) -> Time {
    #[allow(clippy::cast_possible_truncation)] // below 2³¹ s and 10⁹ ns
    Time {
        sec: (nanos / 1_000_000_000) as i32,
        nanosec: (nanos % 1_000_000_000) as u32,
    }
}

/// The stamp of the `k`-th sample of a clock at `rate` Hz: `k / rate` to the nanosecond.
pub fn tick_stamp(k: u64, rate: f64) -> Time {
    #[allow(
        clippy::cast_precision_loss,
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss
    )]
    let nanos = (k as f64 * 1e9 / rate).round() as u64;
    stamp_nanos(nanos)
}

/// A ROS time in seconds.
pub fn seconds(time: &Time) -> f64 {
    f64::from(time.sec) + 1e-9 * f64::from(time.nanosec)
}

/// A header at `t` \[s\] in `frame`.
pub(crate) fn header(t: f64, frame: &str) -> Header {
    Header {
        stamp: stamp(t),
        frame_id: frame.to_owned(),
    }
}

/// Reliable, volatile, the last `depth` messages kept.
pub fn reliable(depth: usize) -> QosProfile {
    QosProfile::publisher_default()
        .reliability_reliable(WhenFull::DEFAULT)
        .durability(Durability::Volatile)
        .history(History::KeepLast { depth })
}

/// The QoS a node subscribes to a sensor topic (the wrench) with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SensorQos {
    /// Best effort, volatile, the last messages kept (ROS 2's `sensor_data` profile, as many
    /// F/T drivers publish): it matches a best-effort publisher and a reliable one.
    #[default]
    SensorData,
    /// Reliable, volatile: matches only a reliable publisher (a best-effort one is never
    /// connected).
    Reliable,
}

impl SensorQos {
    /// The name, as `--qos` spells it.
    pub fn name(self) -> &'static str {
        match self {
            Self::SensorData => "sensor-data",
            Self::Reliable => "reliable",
        }
    }

    /// The profile, the last `depth` messages kept.
    pub fn profile(self, depth: usize) -> QosProfile {
        match self {
            Self::SensorData => reliable(depth).reliability_best_effort(),
            Self::Reliable => reliable(depth),
        }
    }
}

/// A ROS 2 node on its own DDS participant.
pub(crate) struct RosNode {
    node: Node,
    context: Context,
}

impl RosNode {
    /// A node named `name` in `domain_id`, without rosout or parameter services.
    pub(crate) fn new(name: &str, domain_id: u16) -> Result<Self, NodeError> {
        let ros = |what: &str, message: String| NodeError::Ros {
            what: what.to_owned(),
            message,
        };
        let context =
            Context::with_options(ros2_client::context::ContextOptions::new().domain_id(domain_id))
                .map_err(|e| ros("the DDS participant", format!("{e:?}")))?;
        let node_name = NodeName::new("/", name).map_err(|e| ros("the node", format!("{e:?}")))?;
        let node = context
            .new_node(
                node_name,
                NodeOptions::new()
                    .enable_rosout(false)
                    .start_parameter_services(false),
            )
            .map_err(|e| ros("the node", format!("{e:?}")))?;
        Ok(Self { node, context })
    }

    /// Publishers of `topic` discovered on the network whose offered QoS the `requested` one
    /// does not match (DDS's request-offered rule: a best-effort writer and a reliable
    /// reader, a volatile writer and a transient-local reader, …), so that DDS never connects
    /// them: no sample of theirs arrives. Counted from the participant's discovery data,
    /// whose topics carry ROS 2's `rt` prefix.
    pub(crate) fn qos_mismatches(&self, topic: &str, requested: &QosProfile) -> u64 {
        let requested = ros2_client::dds::rustdds::QosPolicies::from(requested);
        let dds_topic = format!("rt{topic}");
        let mismatched = self
            .context
            .domain_participant()
            .discovered_writers()
            .iter()
            .filter(|w| *w.publication_topic_data.topic_name() == dds_topic)
            .filter(|w| {
                w.publication_topic_data
                    .qos()
                    .compliance_failure_wrt(&requested)
                    .is_some()
            })
            .count();
        u64::try_from(mismatched).unwrap_or(u64::MAX)
    }

    fn topic<M: RosMessage>(
        &mut self,
        name: &str,
        qos: &QosProfile,
    ) -> Result<ros2_client::dds::rustdds::Topic, NodeError> {
        let ros = |message: String| NodeError::Ros {
            what: format!("topic {name}"),
            message,
        };
        let topic = Name::parse(name).map_err(|e| NodeError::BadSetting {
            setting: "topic",
            value: format!("{name} ({e:?})"),
            allowed: "an absolute ROS 2 topic name such as /wire/shape",
        })?;
        let (package, kind) = M::TYPE_NAME
            .split_once("/msg/")
            .ok_or_else(|| ros(format!("type name {}", M::TYPE_NAME)))?;
        self.node
            .create_topic(&topic, MessageTypeName::new(package, kind), qos)
            .map_err(|e| ros(format!("{e:?}")))
    }

    /// A publisher of `M` on `name`.
    pub(crate) fn publisher<M: RosMessage>(
        &mut self,
        name: &str,
        qos: &QosProfile,
    ) -> Result<Publisher<M>, NodeError> {
        let topic = self.topic::<M>(name, qos)?;
        self.node
            .create_publisher(&topic, Some(qos.clone()))
            .map_err(|e| NodeError::Ros {
                what: format!("a publisher on {name}"),
                message: format!("{e:?}"),
            })
    }

    /// A subscription to `M` on `name`.
    pub(crate) fn subscription<M: RosMessage + 'static>(
        &mut self,
        name: &str,
        qos: &QosProfile,
    ) -> Result<Subscription<M>, NodeError> {
        let topic = self.topic::<M>(name, qos)?;
        self.node
            .create_subscription(&topic, Some(qos.clone()))
            .map_err(|e| NodeError::Ros {
                what: format!("a subscription to {name}"),
                message: format!("{e:?}"),
            })
    }

    /// Subscriptions to `topic` discovered on the network (any participant).
    #[cfg(feature = "sim")]
    pub(crate) fn subscription_count(&self, topic: &str) -> usize {
        self.node.subscription_count(topic)
    }
}

/// Publishes `message`, counting it under `topic` in `published`, or under `publish_failed`
/// in `refused` when the middleware refuses it.
pub(crate) fn publish<M: serde::Serialize>(
    publisher: &Publisher<M>,
    message: M,
    topic: &'static str,
    published: &mut Counts,
    failed: &mut Counts,
) {
    match publisher.publish(message) {
        Ok(()) => count(published, topic),
        Err(_) => count(failed, topic),
    }
}

/// Sleeps until `deadline`, at most `cap`.
#[cfg(feature = "sim")]
pub(crate) fn sleep_until(deadline: Instant, cap: std::time::Duration) {
    let now = Instant::now();
    if deadline > now {
        std::thread::sleep((deadline - now).min(cap));
    }
}

/// The tare of `samples`, read with nothing in the gripper ([`ftwire_rig::stream::tare_of`]).
pub(crate) fn tare_of(samples: &[FtSample]) -> Result<Tare, String> {
    ftwire_rig::stream::tare_of(samples).map_err(|e| e.to_string())
}

/// `ã` of a tared mean reading (force first, sensor frame) at `time` \[s\]: through the
/// calibration or the mounting by the rig layer's one map ([`ftwire_rig::RawMap::a_tilde`],
/// as `ftwire shape --log` maps a record's `raw`); an answer that is not finite is an error.
pub(crate) fn a_of_raw(
    mean: &Vector6<f64>,
    time: f64,
    map: &RawMap,
) -> Result<Vector6<f64>, String> {
    map.a_tilde(&ftwire_rig::Reading::raw(time, *mean))
        .map_err(|e| e.to_string())
}

/// A `nav_msgs/Path` through `points` (orientations left at the identity), every pose with
/// `header`.
pub(crate) fn path_message(header: Header, points: impl Iterator<Item = msg::Point>) -> Path {
    Path {
        poses: points
            .map(|position| PoseStamped {
                header: header.clone(),
                pose: msg::Pose {
                    position,
                    orientation: msg::Quaternion::default(),
                },
            })
            .collect(),
        header,
    }
}

/// The positions of a path's poses \[m\].
pub(crate) fn path_points(path: &Path) -> Vec<Point3<f64>> {
    path.poses
        .iter()
        .map(|p| Point3::new(p.pose.position.x, p.pose.position.y, p.pose.position.z))
        .collect()
}

/// Checks `--contact-miss` \[m\]: positive when given.
pub(crate) fn check_contact_miss(miss: Option<f64>) -> Result<(), NodeError> {
    match miss {
        Some(miss) if !(miss.is_finite() && miss > 0.0) => Err(NodeError::BadSetting {
            setting: "--contact-miss",
            value: (1e3 * miss).to_string(),
            allowed: "a positive distance in mm",
        }),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A best-effort publisher (as many F/T drivers publish) is a QoS mismatch for a reliable
    /// subscription, and none for the sensor-data one, once discovery has seen it.
    #[test]
    fn a_best_effort_publisher_is_a_mismatch_for_a_reliable_subscription() {
        let domain = 187;
        let topic = "/ftwire_test/qos_wrench";
        let mut driver = RosNode::new("ftwire_test_driver", domain).expect("a node");
        let _publisher = driver
            .publisher::<msg::WrenchStamped>(topic, &SensorQos::SensorData.profile(10))
            .expect("a publisher");
        let mut reader = RosNode::new("ftwire_test_reader", domain).expect("a node");
        let reliable = SensorQos::Reliable.profile(10);
        let _subscription = reader
            .subscription::<msg::WrenchStamped>(topic, &reliable)
            .expect("a subscription");
        let deadline = Instant::now() + std::time::Duration::from_secs(20);
        while reader.qos_mismatches(topic, &reliable) == 0 && Instant::now() < deadline {
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        assert_eq!(reader.qos_mismatches(topic, &reliable), 1);
        assert_eq!(
            reader.qos_mismatches(topic, &SensorQos::SensorData.profile(10)),
            0
        );
        assert_eq!(reader.qos_mismatches("/ftwire_test/other", &reliable), 0);
    }

    #[test]
    fn tick_stamps_are_k_over_rate_to_the_nanosecond() {
        assert_eq!(
            tick_stamp(1234, 1000.0),
            Time {
                sec: 1,
                nanosec: 234_000_000
            }
        );
        let t = tick_stamp(3_600_001, 1000.0);
        assert_eq!((t.sec, t.nanosec), (3600, 1_000_000));
        assert!((seconds(&tick_stamp(7, 300.0)) - 7.0 / 300.0).abs() < 1e-9);
    }

    #[test]
    fn settings_are_checked() {
        let ok = NodeSettings {
            domain_id: 0,
            duration: Some(1.0),
        };
        assert!(ok.validate().is_ok());
        for bad in [
            NodeSettings {
                domain_id: 233,
                ..ok
            },
            NodeSettings {
                duration: Some(f64::NAN),
                ..ok
            },
            NodeSettings {
                duration: Some(0.0),
                ..ok
            },
        ] {
            assert!(bad.validate().is_err(), "{bad:?}");
        }
    }
}
