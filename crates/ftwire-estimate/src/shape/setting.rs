//! Validation of the shape module's settings: one error shape for every out-of-range value.

use crate::EstimateError;

/// `value` must be finite and positive.
pub(crate) fn positive(
    name: &'static str,
    value: f64,
    allowed: &'static str,
) -> Result<(), EstimateError> {
    if value.is_finite() && value > 0.0 {
        return Ok(());
    }
    Err(EstimateError::BadShapeSetting {
        name,
        value,
        allowed,
    })
}

/// `value` must lie in `min..=max`.
pub(crate) fn count(
    name: &'static str,
    value: usize,
    min: usize,
    max: usize,
    allowed: &'static str,
) -> Result<(), EstimateError> {
    if (min..=max).contains(&value) {
        return Ok(());
    }
    Err(EstimateError::BadShapeSetting {
        name,
        value: value as f64,
        allowed,
    })
}
