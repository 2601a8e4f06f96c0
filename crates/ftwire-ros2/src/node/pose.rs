//! Poses between ROS 2 messages and ftwire: a `geometry_msgs/Pose` read with its checks
//! (finite, a unit quaternion within [`QUATERNION_TOLERANCE`]), and ftwire's poses and points
//! written as messages. Every node that reads a target or a tip pose uses these.

use ftwire_core::Pose;
use nalgebra::{Quaternion, Translation3, UnitQuaternion, Vector3};

use super::BASE_FRAME;
use crate::msg;

/// How far an orientation quaternion may be from unit length before it is refused (one closer
/// is normalised).
pub const QUATERNION_TOLERANCE: f64 = 1e-3;

/// Why a target pose was refused.
#[derive(Debug, Clone, PartialEq)]
pub enum TargetRefusal {
    /// Not in [`BASE_FRAME`].
    FrameId(String),
    /// A coordinate that is not finite.
    NonFinite,
    /// An orientation that is not a unit quaternion.
    BadOrientation(f64),
    /// Out of reach of the wire, or no equilibrium on the way there.
    Unreachable(String),
}

impl TargetRefusal {
    /// The reason's name in the summary.
    pub fn name(&self) -> &'static str {
        match self {
            Self::FrameId(_) => "frame_id",
            Self::NonFinite => "non_finite",
            Self::BadOrientation(_) => "bad_orientation",
            Self::Unreachable(_) => "unreachable",
        }
    }
}

impl std::fmt::Display for TargetRefusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::FrameId(frame) => write!(f, "frame_id {frame:?}, not {BASE_FRAME:?}"),
            Self::NonFinite => write!(f, "a coordinate is not finite"),
            Self::BadOrientation(norm) => {
                write!(f, "the orientation's quaternion has norm {norm}, not 1")
            }
            Self::Unreachable(why) => write!(f, "unreachable: {why}"),
        }
    }
}

/// The pose of a ROS pose.
///
/// # Errors
/// [`TargetRefusal::NonFinite`] or [`TargetRefusal::BadOrientation`].
pub fn pose_of(pose: &msg::Pose) -> Result<Pose, TargetRefusal> {
    let (p, q) = (&pose.position, &pose.orientation);
    if [p.x, p.y, p.z, q.x, q.y, q.z, q.w]
        .iter()
        .any(|v| !v.is_finite())
    {
        return Err(TargetRefusal::NonFinite);
    }
    let quaternion = Quaternion::new(q.w, q.x, q.y, q.z);
    let norm = quaternion.norm();
    if (norm - 1.0).abs() > QUATERNION_TOLERANCE {
        return Err(TargetRefusal::BadOrientation(norm));
    }
    Ok(Pose::from_parts(
        Translation3::new(p.x, p.y, p.z),
        UnitQuaternion::new_normalize(quaternion),
    ))
}

/// The ROS pose of a pose.
pub fn ros_pose(pose: &Pose) -> msg::Pose {
    let t = &pose.translation.vector;
    let q = pose.rotation.quaternion();
    msg::Pose {
        position: ros_point(t),
        orientation: msg::Quaternion {
            x: q.i,
            y: q.j,
            z: q.k,
            w: q.w,
        },
    }
}

/// The ROS point of a vector \[m\].
pub fn ros_point(p: &Vector3<f64>) -> msg::Point {
    msg::Point {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}
