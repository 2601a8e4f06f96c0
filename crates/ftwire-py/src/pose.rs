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
    let width = match shape.as_slice() {
        [n, 4, 4] if *n > 0 => 16,
        [n, w @ (6 | 7)] if *n > 0 => *w,
        _ => {
            return Err(value_error(format!(
                "{name} has shape {shape:?}; allowed are (N, 4, 4) homogeneous matrices, (N, 6) \
                 position [m] and rotation vector [rad], and (N, 7) position [m] and unit \
                 quaternion (x, y, z, w), with N ≥ 1"
            )));
        }
    };
    values
        .chunks_exact(width)
        .enumerate()
        .map(|(i, v)| parse(v, &format!("{name}[{i}]"), &format!("{name}[{i}, ")))
        .collect()
}

/// The argument `name` as one pose of shape `(4, 4)`, `(6,)` or `(7,)` (the forms of
/// [`poses`] without the batch axis).
///
/// # Errors
/// As [`poses`], naming `name`.
pub fn pose(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Pose> {
    let (shape, values) = finite_array(value, name)?;
    if !matches!(shape.as_slice(), [4, 4] | [6] | [7]) {
        return Err(value_error(format!(
            "{name} has shape {shape:?}; allowed are (4, 4) a homogeneous matrix, (6,) position \
             [m] and rotation vector [rad], and (7,) position [m] and unit quaternion (x, y, z, w)"
        )));
    }
    parse(&values, name, &format!("{name}["))
}

/// One pose from its 16, 6 or 7 numbers; `at` names it, `slice` opens its index in messages.
fn parse(v: &[f64], at: &str, slice: &str) -> PyResult<Pose> {
    match v.len() {
        16 => matrix(v, at),
        6 => {
            let angle = Vector3::new(v[3], v[4], v[5]).norm();
            if angle > MAX_ROTATION_ANGLE {
                return Err(value_error(format!(
                    "{slice}3:6] has angle {angle} rad; allowed is at most {MAX_ROTATION_ANGLE} rad"
                )));
            }
            Ok(Pose::from_parts(
                Translation3::new(v[0], v[1], v[2]),
                UnitQuaternion::from_scaled_axis(Vector3::new(v[3], v[4], v[5])),
            ))
        }
        _ => {
            let q = Quaternion::new(v[6], v[3], v[4], v[5]);
            if (q.norm() - 1.0).abs() > UNIT_TOLERANCE {
                return Err(value_error(format!(
                    "{slice}3:7] has norm {}: a unit quaternion (x, y, z, w) is needed",
                    q.norm()
                )));
            }
            Ok(Pose::from_parts(
                Translation3::new(v[0], v[1], v[2]),
                UnitQuaternion::new_normalize(q),
            ))
        }
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

/// `pose` as a row-major homogeneous 4 × 4 float64 array (translation in m).
pub fn to_array<'py>(py: Python<'py>, pose: &Pose) -> Bound<'py, numpy::PyArray2<f64>> {
    let m = pose.to_homogeneous();
    let rows = numpy::ndarray::Array2::from_shape_fn((4, 4), |(i, k)| m[(i, k)]);
    numpy::PyArray2::from_owned_array(py, rows)
}
