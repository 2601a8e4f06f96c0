//! Shared plain data of ftwire, and the [`Rig`] boundary between algorithms and a robot.
//!
//! Every ftwire crate speaks these types. Conventions (see `DESIGN.md`):
//!
//! - Units are SI: metres, radians, newtons, newton-metres, seconds.
//! - A [`Pose`] is an `Isometry3<f64>` mapping coordinates in the child frame to the parent frame.
//! - A [`Wrench`] is ordered **torque first, then force** when flattened to a 6-vector, as the
//!   wire configuration `a = (τ1, τ2, τ3, f1, f2, f3)` is. Raw F/T sensor samples
//!   ([`FtSample`]) are ordered force first, as real sensors report them.
//! - A wire clamp frame has its x axis along the wire's tangent, pointing into the wire at the
//!   base gripper and out of it at the second gripper.
//!
//! ```
//! use ftwire_core::{WireParams, Wrench};
//! use nalgebra::Vector3;
//!
//! let wire = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?;
//! assert_eq!(wire.length(), 0.63);
//! let w = Wrench::new(Vector3::new(0.0, 0.0, 0.1), Vector3::new(-1.0, 0.0, 0.0));
//! assert_eq!(w.to_vector()[2], 0.1);
//! # Ok::<(), ftwire_core::CoreError>(())
//! ```

mod error;
pub mod geometry;
mod rig;
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
