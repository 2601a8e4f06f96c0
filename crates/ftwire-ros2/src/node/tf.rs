//! TF: the second gripper's pose from two frames of the TF tree, for `ftwire ros2 estimate
//! --base-frame F --tip-frame G`.
//!
//! [`TfBuffer`] keeps the latest transform of each edge of the tree (`tf2_msgs/TFMessage` on
//! [`TF_TOPIC`], and on [`TF_STATIC_TOPIC`] the edges that hold forever), one parent per frame
//! as in tf2: an edge is keyed by its child, and a message naming a new parent for a frame
//! re-parents it. [`TfBuffer::lookup`] answers the pose of `tip` in `base` by composing the
//! edges up from each frame to their lowest common ancestor `A`:
//!
//! `T_base_tip = T_A_base⁻¹ · T_A_tip`, with `T_A_f = T_A_f1 · T_f1_f2 · … · T_fn_f` along the
//! chain, each `T_parent_child` the child frame's pose in its parent (`p_parent = R p_child + t`).
//!
//! An edge is refused, and counted by the node under its [`TfRefusal::name`], never acted on:
//! an empty frame id, a value that is not finite, a rotation quaternion whose norm is farther
//! than [`QUATERNION_TOLERANCE`] from 1 (one closer is normalised), an edge that would close a
//! loop (a frame its own ancestor), or a dynamic edge whose stamp is before the one it would
//! replace. A lookup is [`TfMiss::NotAvailable`] until both frames are in one tree, and
//! [`TfMiss::Stale`] when a dynamic edge of its chain is older than the limit before the
//! lookup's time. Guarded by this module's tests and by `crates/ftwire/tests/ros2_nodes.rs`
//! (the sim's TF frames against its `PoseStamped`).

use std::collections::{BTreeMap, BTreeSet};

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use ros2_client::dds::rustdds::mio1::{Interest, Registry, Token};
use ros2_client::qos::{Durability, History, WhenFull};
use ros2_client::{QosProfile, Subscription};
use serde::Serialize;

use ros2_client::MessageInfo;

use super::{Counts, Log, NodeError, RosNode, count, reliable, seconds};
use crate::msg::{
    Header, Quaternion as RosQuaternion, TFMessage, Time, Transform, TransformStamped, Vector3,
};

/// How far an edge's rotation quaternion may be from unit length: closer, it is normalised;
/// farther, the edge is refused (the tolerance of every pose a node reads).
pub use super::pose::QUATERNION_TOLERANCE;

/// The dynamic transforms.
pub const TF_TOPIC: &str = "/tf";
/// The transforms that hold forever (published once, transient local).
pub const TF_STATIC_TOPIC: &str = "/tf_static";
/// The base clamp's frame the sim publishes in TF (the frame of its `PoseStamped`s).
pub const SIM_BASE_FRAME: &str = super::BASE_FRAME;
/// The second gripper's clamp frame the sim publishes in TF.
pub const SIM_TIP_FRAME: &str = "wire_tip";
/// The root frame the sim hangs both clamps from.
pub const SIM_WORLD_FRAME: &str = "world";
/// How old a dynamic edge may be before a lookup refuses it \[s\] (default of
/// [`TfFrames::stale`]).
pub const DEFAULT_STALE: f64 = 0.5;
/// Dynamic TF messages a subscriber queues (tf2's listener depth).
const TF_QUEUE: usize = 100;

/// The QoS of [`TF_TOPIC`]: reliable, volatile, the last 100 kept (tf2's).
pub fn tf_qos() -> QosProfile {
    reliable(TF_QUEUE)
}

/// The QoS of [`TF_STATIC_TOPIC`]: reliable and transient local, so that a late subscriber
/// gets the edges published before it; a subscriber keeps all, a publisher its last message.
pub fn tf_static_qos(publisher: bool) -> QosProfile {
    QosProfile::publisher_default()
        .reliability_reliable(WhenFull::DEFAULT)
        .durability(Durability::TransientLocal)
        .history(if publisher {
            History::KeepLast { depth: 1 }
        } else {
            History::KeepAll
        })
}

/// Why an edge was refused.
#[derive(Debug, Clone, PartialEq)]
pub enum TfRefusal {
    /// An empty parent or child frame id.
    FrameId,
    /// A translation or rotation value that is not finite.
    NonFinite {
        /// The child frame.
        child: String,
    },
    /// A rotation quaternion far from unit length.
    Rotation {
        /// The child frame.
        child: String,
        /// The quaternion's norm.
        norm: f64,
    },
    /// The edge would make a frame its own ancestor.
    Loop {
        /// The parent frame.
        parent: String,
        /// The child frame.
        child: String,
    },
    /// A dynamic edge stamped before the one it would replace.
    Backwards {
        /// The child frame.
        child: String,
        /// Its stamp \[s\].
        stamp: f64,
        /// The stamp of the edge kept \[s\].
        kept: f64,
    },
}

impl TfRefusal {
    /// The reason's name in a node's `refused` counts.
    pub fn name(&self) -> &'static str {
        match self {
            Self::FrameId => "tf_frame_id",
            Self::NonFinite { .. } => "tf_non_finite",
            Self::Rotation { .. } => "tf_rotation",
            Self::Loop { .. } => "tf_loop",
            Self::Backwards { .. } => "tf_backwards",
        }
    }
}

impl std::fmt::Display for TfRefusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::FrameId => write!(f, "an empty frame id"),
            Self::NonFinite { child } => write!(f, "edge to {child:?}: a value is not finite"),
            Self::Rotation { child, norm } => write!(
                f,
                "edge to {child:?}: the rotation's quaternion has norm {norm}, not 1 within \
                 {QUATERNION_TOLERANCE}"
            ),
            Self::Loop { parent, child } => write!(
                f,
                "edge {parent:?} → {child:?}: {child:?} would be its own ancestor"
            ),
            Self::Backwards { child, stamp, kept } => write!(
                f,
                "edge to {child:?}: stamp {stamp} s is before the kept {kept} s"
            ),
        }
    }
}

impl std::error::Error for TfRefusal {}

/// Why a lookup has no answer.
#[derive(Debug, Clone, PartialEq)]
pub enum TfMiss {
    /// The two frames are not (yet) in one tree.
    NotAvailable {
        /// The frame the answer is expressed in.
        base: String,
        /// The frame whose pose is asked for.
        tip: String,
    },
    /// A dynamic edge of the chain is older than the limit.
    Stale {
        /// The edge's child frame.
        child: String,
        /// Its age at the lookup's time \[s\].
        age: f64,
    },
}

impl std::fmt::Display for TfMiss {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NotAvailable { base, tip } => {
                write!(f, "no chain of TF edges from {base:?} to {tip:?} yet")
            }
            Self::Stale { child, age } => {
                write!(f, "the TF edge to {child:?} is {age:.3} s old")
            }
        }
    }
}

impl std::error::Error for TfMiss {}

/// One edge: the child's pose in its parent.
#[derive(Debug, Clone, PartialEq)]
struct Edge {
    parent: String,
    transform: Isometry3<f64>,
    stamp: f64,
    fixed: bool,
}

/// The latest transform of every edge of a TF tree (module docs).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TfBuffer {
    /// By child frame.
    edges: BTreeMap<String, Edge>,
}

impl TfBuffer {
    /// An empty tree.
    pub fn new() -> Self {
        Self::default()
    }

    /// Edges held.
    pub fn len(&self) -> usize {
        self.edges.len()
    }

    /// Whether no edge is held.
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty()
    }

    /// Takes one edge; `fixed` for one from [`TF_STATIC_TOPIC`] (never stale).
    ///
    /// # Errors
    /// A [`TfRefusal`] (module docs); the tree is then unchanged.
    ///
    /// # Example
    /// ```
    /// use ftwire_ros2::msg::{Header, TransformStamped};
    /// use ftwire_ros2::node::tf::TfBuffer;
    /// let edge = |parent: &str, child: &str, x: f64| {
    ///     let mut e = TransformStamped {
    ///         header: Header { frame_id: parent.into(), ..Header::default() },
    ///         child_frame_id: child.into(),
    ///         ..TransformStamped::default()
    ///     };
    ///     e.transform.translation.x = x;
    ///     e
    /// };
    /// let mut tf = TfBuffer::new();
    /// tf.insert(&edge("world", "base", 1.0), true)?;
    /// tf.insert(&edge("world", "tip", 3.0), false)?;
    /// let tip = tf.lookup("base", "tip", 0.0, 0.5)?;
    /// assert!((tip.translation.vector.x - 2.0).abs() < 1e-12);
    /// assert!(tf.insert(&edge("tip", "world", 0.0), false).is_err()); // a loop
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn insert(&mut self, edge: &TransformStamped, fixed: bool) -> Result<(), TfRefusal> {
        let (parent, child) = (&edge.header.frame_id, &edge.child_frame_id);
        if parent.is_empty() || child.is_empty() {
            return Err(TfRefusal::FrameId);
        }
        let (t, q) = (&edge.transform.translation, &edge.transform.rotation);
        if [t.x, t.y, t.z, q.x, q.y, q.z, q.w]
            .iter()
            .any(|v| !v.is_finite())
        {
            return Err(TfRefusal::NonFinite {
                child: child.clone(),
            });
        }
        let quaternion = Quaternion::new(q.w, q.x, q.y, q.z);
        let norm = quaternion.norm();
        if (norm - 1.0).abs() > QUATERNION_TOLERANCE {
            return Err(TfRefusal::Rotation {
                child: child.clone(),
                norm,
            });
        }
        if self.is_ancestor(child, parent) {
            return Err(TfRefusal::Loop {
                parent: parent.clone(),
                child: child.clone(),
            });
        }
        let stamp = seconds(&edge.header.stamp);
        if let Some(kept) = self.edges.get(child)
            && !fixed
            && !kept.fixed
            && stamp < kept.stamp
        {
            return Err(TfRefusal::Backwards {
                child: child.clone(),
                stamp,
                kept: kept.stamp,
            });
        }
        self.edges.insert(
            child.clone(),
            Edge {
                parent: parent.clone(),
                transform: Isometry3::from_parts(
                    Translation3::new(t.x, t.y, t.z),
                    UnitQuaternion::new_normalize(quaternion),
                ),
                stamp,
                fixed,
            },
        );
        Ok(())
    }

    /// Whether `ancestor` is `frame` or one of its ancestors.
    fn is_ancestor(&self, ancestor: &str, frame: &str) -> bool {
        self.chain(frame).contains(&ancestor)
    }

    /// `frame`, its parent, its grandparent, … up to the root. The tree has no loop (insert
    /// refuses one); the walk stops after as many steps as there are edges all the same.
    fn chain<'a>(&'a self, frame: &'a str) -> Vec<&'a str> {
        let mut chain = vec![frame];
        let mut current = frame;
        while let Some(edge) = self.edges.get(current) {
            if chain.len() > self.edges.len() {
                break;
            }
            current = &edge.parent;
            chain.push(current);
        }
        chain
    }

    /// `T_ancestor_frame`: the edges from `ancestor` down to `frame` composed; a dynamic edge
    /// older than `stale` before `now` is a miss.
    fn down_from(
        &self,
        ancestor: &str,
        frame: &str,
        now: f64,
        stale: f64,
    ) -> Result<Isometry3<f64>, TfMiss> {
        let mut pose = Isometry3::identity();
        let mut current = frame;
        while current != ancestor {
            let Some(edge) = self.edges.get(current) else {
                break;
            };
            let age = now - edge.stamp;
            if !edge.fixed && age > stale {
                return Err(TfMiss::Stale {
                    child: current.to_owned(),
                    age,
                });
            }
            pose = edge.transform * pose;
            current = &edge.parent;
        }
        Ok(pose)
    }

    /// The pose of frame `tip` in frame `base` at `now` \[s\] (module docs), with dynamic edges
    /// at most `stale` \[s\] older than `now`.
    ///
    /// # Errors
    /// [`TfMiss::NotAvailable`] until the two frames are in one tree, [`TfMiss::Stale`] when
    /// a dynamic edge of the chain is too old.
    pub fn lookup(
        &self,
        base: &str,
        tip: &str,
        now: f64,
        stale: f64,
    ) -> Result<Isometry3<f64>, TfMiss> {
        let up_from_base: BTreeSet<&str> = self.chain(base).into_iter().collect();
        let Some(ancestor) = self
            .chain(tip)
            .into_iter()
            .find(|f| up_from_base.contains(f))
        else {
            return Err(TfMiss::NotAvailable {
                base: base.to_owned(),
                tip: tip.to_owned(),
            });
        };
        let ancestor_base = self.down_from(ancestor, base, now, stale)?;
        let ancestor_tip = self.down_from(ancestor, tip, now, stale)?;
        Ok(ancestor_base.inverse() * ancestor_tip)
    }
}

/// `--base-frame`, `--tip-frame` and how old a dynamic edge may be.
#[derive(Debug, Clone, PartialEq)]
pub struct TfFrames {
    /// The base clamp's frame in the TF tree: the tip pose is expressed in it.
    pub base: String,
    /// The second gripper's clamp frame in the TF tree.
    pub tip: String,
    /// A dynamic edge older than this before the newest wrench is stale \[s\] (default
    /// [`DEFAULT_STALE`]).
    pub stale: f64,
}

impl TfFrames {
    /// Checks the frames and the limit.
    ///
    /// # Errors
    /// [`NodeError::BadSetting`] for an empty frame, one with a leading `/` or white space
    /// (tf2's frame ids have neither), the same frame twice, or a limit that is not a
    /// positive number of seconds.
    pub fn validate(&self) -> Result<(), NodeError> {
        check_frame("--base-frame", &self.base)?;
        check_frame("--tip-frame", &self.tip)?;
        if self.base == self.tip {
            return Err(NodeError::BadSetting {
                setting: "--tip-frame",
                value: format!("{:?}", self.tip),
                allowed: "a frame other than --base-frame",
            });
        }
        if !(self.stale.is_finite() && self.stale > 0.0) {
            return Err(NodeError::BadSetting {
                setting: "--tf-stale",
                value: self.stale.to_string(),
                allowed: "a positive number of seconds",
            });
        }
        Ok(())
    }
}

/// Checks a TF frame id given as `setting`.
///
/// # Errors
/// [`NodeError::BadSetting`] for an empty frame, one with a leading `/` or white space (tf2's
/// frame ids have neither).
pub(crate) fn check_frame(setting: &'static str, frame: &str) -> Result<(), NodeError> {
    if frame.is_empty() || frame.starts_with('/') || frame.chars().any(char::is_whitespace) {
        return Err(NodeError::BadSetting {
            setting,
            value: format!("{frame:?}"),
            allowed: "a TF frame id: not empty, no leading '/', no white space",
        });
    }
    Ok(())
}

/// The frames `ftwire ros2 sim` publishes in TF: on [`TF_STATIC_TOPIC`] once, `world` →
/// `base` (the base clamp's pose in the robot's world frame, which the sim never moves), and
/// on [`TF_TOPIC`] with each tip pose, `world` → `tip` (the second gripper's clamp). The pose
/// of `tip` in `base` is then the sim's `PoseStamped` on the tip pose topic.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SimTfFrames {
    /// The root (default [`SIM_WORLD_FRAME`]).
    pub world: String,
    /// The base clamp (default [`SIM_BASE_FRAME`]).
    pub base: String,
    /// The second gripper's clamp (default [`SIM_TIP_FRAME`]).
    pub tip: String,
}

impl Default for SimTfFrames {
    fn default() -> Self {
        Self {
            world: SIM_WORLD_FRAME.to_owned(),
            base: SIM_BASE_FRAME.to_owned(),
            tip: SIM_TIP_FRAME.to_owned(),
        }
    }
}

impl SimTfFrames {
    /// Checks the three frames.
    ///
    /// # Errors
    /// [`NodeError::BadSetting`] for a frame that is not a TF frame id, or two the same.
    pub fn validate(&self) -> Result<(), NodeError> {
        check_frame("--tf-world-frame", &self.world)?;
        check_frame("--tf-base-frame", &self.base)?;
        check_frame("--tf-tip-frame", &self.tip)?;
        if self.world == self.base || self.world == self.tip || self.base == self.tip {
            return Err(NodeError::BadSetting {
                setting: "--tf-tip-frame",
                value: format!("{:?}, {:?}, {:?}", self.world, self.base, self.tip),
                allowed: "three different frames (world, base, tip)",
            });
        }
        Ok(())
    }

    /// The edge `world` → `child` with `pose` at `stamp`.
    pub fn edge(&self, child: &str, pose: &Isometry3<f64>, stamp: Time) -> TransformStamped {
        let (t, q) = (&pose.translation.vector, pose.rotation.quaternion());
        TransformStamped {
            header: Header {
                stamp,
                frame_id: self.world.clone(),
            },
            child_frame_id: child.to_owned(),
            transform: Transform {
                translation: Vector3 {
                    x: t.x,
                    y: t.y,
                    z: t.z,
                },
                rotation: RosQuaternion {
                    x: q.i,
                    y: q.j,
                    z: q.k,
                    w: q.w,
                },
            },
        }
    }
}

/// What the TF tip source did, in the estimator's summary.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct TfSummary {
    /// Edges held at the end.
    pub edges: usize,
    /// Lookups of the tip (one per batch of wrenches) answered.
    pub answered: u64,
    /// Lookups before the two frames were in one tree.
    pub not_available: u64,
    /// Lookups with a dynamic edge older than the limit.
    pub stale: u64,
}

/// The TF subscriptions and buffer of a node, and its counts.
pub(crate) struct TfListener {
    tf: Subscription<TFMessage>,
    tf_static: Subscription<TFMessage>,
    buffer: TfBuffer,
    frames: TfFrames,
    summary: TfSummary,
    /// The last line logged about a refusal or a miss (each logged once in a row).
    last_miss: Option<String>,
    /// Whether the last lookup missed (the next answer is logged).
    missing: bool,
}

impl TfListener {
    /// Subscribes to [`TF_TOPIC`] and [`TF_STATIC_TOPIC`].
    pub(crate) fn open(node: &mut RosNode, frames: &TfFrames) -> Result<Self, NodeError> {
        Ok(Self {
            tf: node.subscription::<TFMessage>(TF_TOPIC, &tf_qos())?,
            tf_static: node.subscription::<TFMessage>(TF_STATIC_TOPIC, &tf_static_qos(false))?,
            buffer: TfBuffer::new(),
            frames: frames.clone(),
            summary: TfSummary::default(),
            last_miss: None,
            missing: true,
        })
    }

    /// Registers both subscriptions with a poll, as `first` and `first + 1`.
    pub(crate) fn register(&mut self, registry: &Registry, first: usize) -> std::io::Result<()> {
        registry.register(&mut self.tf, Token(first), Interest::READABLE)?;
        registry.register(&mut self.tf_static, Token(first + 1), Interest::READABLE)
    }

    /// Takes every TF message waiting into the buffer: each counted under its topic in
    /// `received` and passed to `record` (topic, its DDS info, message), each edge refused
    /// counted in `refused` by [`TfRefusal::name`] and logged once in a row.
    pub(crate) fn take(
        &mut self,
        received: &mut Counts,
        refused: &mut Counts,
        record: &mut dyn FnMut(&str, &MessageInfo, &TFMessage),
        log: Log<'_>,
    ) {
        for (topic, fixed) in [(TF_STATIC_TOPIC, true), (TF_TOPIC, false)] {
            let sub = if fixed { &self.tf_static } else { &self.tf };
            loop {
                match sub.take() {
                    Ok(Some((message, info))) => {
                        count(received, if fixed { "tf_static" } else { "tf" });
                        record(topic, &info, &message);
                        for edge in &message.transforms {
                            if let Err(refusal) = self.buffer.insert(edge, fixed) {
                                count(refused, refusal.name());
                                let text = format!("estimate: refused on {topic}: {refusal}");
                                if self.last_miss.as_ref() != Some(&text) {
                                    log(&text);
                                    self.last_miss = Some(text);
                                }
                            }
                        }
                    }
                    Ok(None) => break,
                    Err(_) => count(refused, "malformed"),
                }
            }
        }
    }

    /// The tip's pose in the base frame at `now` \[s\] (the newest wrench's stamp), counted;
    /// a miss logged once in a row.
    pub(crate) fn tip(&mut self, now: f64, log: Log<'_>) -> Option<Isometry3<f64>> {
        let frames = &self.frames;
        match self
            .buffer
            .lookup(&frames.base, &frames.tip, now, frames.stale)
        {
            Ok(pose) => {
                if self.missing {
                    log(&format!(
                        "estimate: the tip pose from TF, {:?} in {:?}",
                        frames.tip, frames.base
                    ));
                    self.missing = false;
                    self.last_miss = None;
                }
                self.summary.answered += 1;
                Some(pose)
            }
            Err(miss) => {
                match miss {
                    TfMiss::NotAvailable { .. } => self.summary.not_available += 1,
                    TfMiss::Stale { .. } => self.summary.stale += 1,
                }
                self.missing = true;
                let text = format!("estimate: no tip pose at t = {now:.3} s: {miss}");
                if self.last_miss.as_ref() != Some(&text) {
                    log(&text);
                    self.last_miss = Some(text);
                }
                None
            }
        }
    }

    /// The counts so far.
    pub(crate) fn summary(&self) -> TfSummary {
        TfSummary {
            edges: self.buffer.len(),
            ..self.summary
        }
    }
}

#[cfg(test)]
mod tests;
