//! The error type of the shared data, and the two input checks every ftwire crate uses.

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
