//! Poses given as arrays: `(4, 4)` homogeneous matrices, `(6,)` position and rotation vector
//! (a log's form), or `(7,)` position and unit quaternion `(x, y, z, w)`, scalar last.

use ftwire_core::{MAX_ROTATION_ANGLE, Pose};
use nalgebra::{Matrix3, Quaternion, Rotation3, Translation3, UnitQuaternion, Vector3};
use pyo3::prelude::*;

use crate::input::{finite_array, value_error};

/// How far a rotation matrix may be from orthonormal (`‖RᵀR − I‖`, `|det R − 1|`).
const ORTHONORMAL_TOLERANCE: f64 = 1e-6;
/// How far a quaternion's norm may be from 1.
const UNIT_TOLERANCE: f64 = 1e-6;

/// The argument `name` as `N ≥ 1` poses of shape `(N, 4, 4)`, `(N, 6)` or `(N, 7)`.
///
/// # Errors
/// `ValueError` naming `name` (and the row) for another shape, a value that is not finite, a
/// matrix that is not a rigid transform, a quaternion that is not a unit, or a rotation vector
/// beyond `ftwire_core::MAX_ROTATION_ANGLE`.
pub fn poses(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<Pose>> {
    let (shape, values) = finite_array(value, name)?;
    let bad_shape = || {
        value_error(format!(
            "{name} has shape {shape:?}; allowed are (N, 4, 4) homogeneous matrices, (N, 6) \
             position [m] and rotation vector [rad], and (N, 7) position [m] and unit \
             quaternion (x, y, z, w), with N ≥ 1"
        ))
    };
    match shape.as_slice() {
        [n, 4, 4] if *n > 0 => values
            .chunks_exact(16)
            .enumerate()
            .map(|(i, m)| matrix(m, &format!("{name}[{i}]")))
            .collect(),
        [n, 6] if *n > 0 => values
            .chunks_exact(6)
            .enumerate()
            .map(|(i, v)| {
                let angle = Vector3::new(v[3], v[4], v[5]).norm();
                if angle > MAX_ROTATION_ANGLE {
                    return Err(value_error(format!(
                        "{name}[{i}, 3:6] has angle {angle} rad; allowed is at most \
                         {MAX_ROTATION_ANGLE} rad"
                    )));
                }
                Ok(Pose::from_parts(
                    Translation3::new(v[0], v[1], v[2]),
                    UnitQuaternion::from_scaled_axis(Vector3::new(v[3], v[4], v[5])),
                ))
            })
            .collect(),
        [n, 7] if *n > 0 => values
            .chunks_exact(7)
            .enumerate()
            .map(|(i, v)| {
                let q = Quaternion::new(v[6], v[3], v[4], v[5]);
                if (q.norm() - 1.0).abs() > UNIT_TOLERANCE {
                    return Err(value_error(format!(
                        "{name}[{i}, 3:7] has norm {}: a unit quaternion (x, y, z, w) is needed",
                        q.norm()
                    )));
                }
                Ok(Pose::from_parts(
                    Translation3::new(v[0], v[1], v[2]),
                    UnitQuaternion::new_normalize(q),
                ))
            })
            .collect(),
        _ => Err(bad_shape()),
    }
}

/// A row-major 4 × 4 homogeneous matrix as a pose.
fn matrix(m: &[f64], at: &str) -> PyResult<Pose> {
    let r = Matrix3::new(m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]);
    let off = (r.transpose() * r - Matrix3::identity()).norm();
    let det = r.determinant();
    let last_row = [m[12], m[13], m[14], m[15]];
    if off > ORTHONORMAL_TOLERANCE
        || (det - 1.0).abs() > ORTHONORMAL_TOLERANCE
        || last_row != [0.0, 0.0, 0.0, 1.0]
    {
        return Err(value_error(format!(
            "{at} is not a rigid transform: the rotation block must be orthonormal with \
             determinant 1 (‖RᵀR − I‖ = {off:.3e}, det R = {det}) and the last row (0, 0, 0, 1) \
             (got {last_row:?})"
        )));
    }
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
    Ok(Pose::from_parts(
        Translation3::new(m[3], m[7], m[11]),
        rotation,
    ))
}
