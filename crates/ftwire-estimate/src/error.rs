//! The error type of `ftwire-estimate`.

use ftwire_core::CoreError;
use ftwire_rod::RodError;
use thiserror::Error;

/// Errors of the estimators.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum EstimateError {
    /// Invalid shared data (for example non-finite or non-positive wire parameters).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// The wire model could not be solved.
    #[error(transparent)]
    Model(#[from] RodError),
}
