//! Helpers shared by the integration tests.
#![allow(dead_code)]

use ftwire_core::Pose;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// A pose from a position and a rotation vector.
pub fn pose(p: [f64; 3], r: [f64; 3]) -> Pose {
    Isometry3::from_parts(
        Translation3::new(p[0], p[1], p[2]),
        UnitQuaternion::from_scaled_axis(Vector3::new(r[0], r[1], r[2])),
    )
}

/// Relative error `|a − b| / scale`.
pub fn rel(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / scale
}
