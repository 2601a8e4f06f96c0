#![doc = include_str!("../README.md")]

mod error;
pub mod geometry;
mod rig;
pub mod stats;
pub mod text;
mod wire;
mod wrench;

pub use error::{
    CoreError, MAX_ROTATION_ANGLE, ensure_finite, ensure_positive, ensure_rotation_vector,
};
pub use rig::{Command, FtSample, GripperPoses, Rig};
pub use wire::WireParams;
pub use wrench::Wrench;

/// A rigid transform in SE(3): rotation and translation \[m\], child frame to parent frame.
pub type Pose = nalgebra::Isometry3<f64>;
