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
