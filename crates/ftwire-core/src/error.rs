//! The error type of the shared data, and the input checks every ftwire crate uses.

use thiserror::Error;

/// Errors of the shared data types.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum CoreError {
    /// A value that must be finite is NaN or infinite.
    #[error("{field}[{index}] = {value} is not finite; every component must be a finite number")]
    NonFinite {
        /// Name of the offending field.
        field: &'static str,
        /// Index of the offending component (0 for scalars).
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// A value that must be strictly positive is not.
    #[error("{field} = {value} must be finite and > 0")]
    NotPositive {
        /// Name of the offending field.
        field: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A rotation vector whose angle (its norm) exceeds [`MAX_ROTATION_ANGLE`].
    #[error(
        "{field} = {value:?} is not allowed: its angle (the norm) is {angle:e} rad, and a \
         rotation vector's may be at most {max:e} rad (any rotation needs at most π)"
    )]
    RotationTooLarge {
        /// Name of the offending field.
        field: &'static str,
        /// The rotation vector \[rad\].
        value: [f64; 3],
        /// Its norm \[rad\] (infinite when it overflows).
        angle: f64,
        /// The largest norm allowed, [`MAX_ROTATION_ANGLE`] \[rad\].
        max: f64,
    },
    /// A file could not be read (the reader names the file).
    #[error("cannot read it: {message}")]
    Unreadable {
        /// The system's message.
        message: String,
    },
    /// Text that is not valid UTF-8, located as an editor shows it.
    #[error(
        "line {line}, column {column} (byte offset {offset}): byte 0x{byte:02X} is not valid \
         UTF-8; the file must be UTF-8 text"
    )]
    NotUtf8 {
        /// Line of the invalid byte, from 1.
        line: usize,
        /// Its column, in characters from 1.
        column: usize,
        /// Its offset from the start of the text, in bytes from 0.
        offset: usize,
        /// The invalid byte.
        byte: u8,
    },
}

/// The largest angle \[rad\] a rotation vector (axis × angle) may have: 10⁶ rad.
///
/// Any rotation needs an angle of at most π; a larger one is the same rotation plus whole
/// turns, and every turn costs precision. The quaternion of `r` takes `sin` and `cos` of
/// `|r|/2`, which f64 knows only to its relative precision (1.1e-16), so the rotation is off by
/// up to about `1e-16 · |r|` rad: 1e-10 rad at this bound, far below any sensor's or robot's
/// resolution, but more than a radian beyond about 1e16 rad, and beyond about 1e154 rad the
/// norm overflows and the quaternion is NaN. An angle above the bound is a mistake (degrees
/// for radians, a unit slip), not a rotation, and is refused where it is read.
pub const MAX_ROTATION_ANGLE: f64 = 1e6;

/// Checks that a rotation vector (axis × angle, \[rad\]) is finite and its angle at most
/// [`MAX_ROTATION_ANGLE`], naming `field` in the error. Every rotation vector a user or a file
/// gives passes this check before it becomes a quaternion.
///
/// # Example
/// ```
/// use ftwire_core::{CoreError, ensure_rotation_vector};
/// assert!(ensure_rotation_vector("rotation", &[0.0, 0.0, 3.1]).is_ok());
/// assert!(matches!(
///     ensure_rotation_vector("rotation", &[1e300, 0.0, 0.0]),
///     Err(CoreError::RotationTooLarge { angle, .. }) if angle == 1e300
/// ));
/// assert!(ensure_rotation_vector("rotation", &[f64::NAN, 0.0, 0.0]).is_err());
/// ```
pub fn ensure_rotation_vector(field: &'static str, value: &[f64; 3]) -> Result<(), CoreError> {
    ensure_finite(field, value)?;
    let [x, y, z] = *value;
    // `hypot` does not overflow for components near f64::MAX, so the angle is reported right.
    let angle = x.hypot(y).hypot(z);
    if angle <= MAX_ROTATION_ANGLE {
        Ok(())
    } else {
        Err(CoreError::RotationTooLarge {
            field,
            value: *value,
            angle,
            max: MAX_ROTATION_ANGLE,
        })
    }
}

/// Checks that every component of a slice is finite, naming `field` and the first offending
/// component in the error. The one finiteness check of the workspace: other crates wrap
/// [`CoreError`] in their own error with `#[from]`.
///
/// # Example
/// ```
/// assert!(ftwire_core::ensure_finite("a", &[1.0, 2.0]).is_ok());
/// assert!(ftwire_core::ensure_finite("a", &[1.0, f64::NAN]).is_err());
/// ```
pub fn ensure_finite(field: &'static str, values: &[f64]) -> Result<(), CoreError> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(index) => Err(CoreError::NonFinite {
            field,
            index,
            value: values[index],
        }),
    }
}

/// Checks that a value is finite and strictly positive, naming `field` in the error.
///
/// # Example
/// ```
/// use ftwire_core::{CoreError, ensure_positive};
/// assert!(ensure_positive("length", 0.63).is_ok());
/// assert_eq!(
///     ensure_positive("length", 0.0),
///     Err(CoreError::NotPositive { field: "length", value: 0.0 })
/// );
/// ```
pub fn ensure_positive(field: &'static str, value: f64) -> Result<(), CoreError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(CoreError::NotPositive { field, value })
    }
}
