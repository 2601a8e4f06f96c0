//! Collision detection from F/T alone (paper §IV-E): a contact is a force the model does not
//! have, so after a contact the measured change of `ã` stops agreeing with the model's
//! prediction for the commanded motion, `δa ≈ J(L)⁻¹ δb` (eq. 11).
//!
//! Each move `i` has a **miss**, in normalised units (torque in `c2/L`, force in `c2/L²`):
//!
//! ```text
//! m_i = ‖N(ã_{i+1} − ã_i − δa_pred)‖
//! ```
//!
//! On free motion the misses are linearisation error and sensor noise: they shrink as the
//! controller's steps shrink, smoothly. A contact adds a force the model does not have, and the
//! miss **jumps**. The detector's residual is the jump ratio
//!
//! ```text
//! r_i = m_i / (max(m_{i−1}, m_{i−2}) + floor)
//! ```
//!
//! where `floor` is set from the measured sensor noise, so that the ratio of two noise-sized
//! misses stays small. The first move has no history and is never flagged (a contact made
//! there is caught on the next move). The threshold on `r` is calibrated from the residuals of
//! free motions in the same conditions ([`CollisionDetector::calibrate`]): a margin times the
//! largest free residual seen.

use ftwire_core::WireParams;
use ftwire_rod::to_normalised;
use nalgebra::{Matrix6, Vector6};

use crate::ControlError;

/// Fewest finite free-motion residuals [`CollisionDetector::calibrate`] accepts.
pub const MIN_CALIBRATION_RESIDUALS: usize = 10;

/// A calibrated contact test on the relative residual of each move.
///
/// # Example
/// ```
/// use ftwire_control::CollisionDetector;
/// let free = [0.1, 0.2, 0.15, 0.05, 0.3, 0.12, 0.2, 0.1, 0.08, 0.25];
/// let detector = CollisionDetector::calibrate(&free, 2.0, 0.05)?;
/// assert!((detector.threshold() - 0.6).abs() < 1e-12);
/// assert!(detector.is_contact(0.9));
/// assert!(!detector.is_contact(0.3));
/// # Ok::<(), ftwire_control::ControlError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CollisionDetector {
    threshold: f64,
    floor: f64,
}

impl CollisionDetector {
    /// Default margin over the largest free-motion residual.
    pub const DEFAULT_MARGIN: f64 = 2.0;
    /// Default floor of the residual's denominator \[normalised units\].
    pub const DEFAULT_FLOOR: f64 = 0.01;

    /// A detector with a given threshold on the relative residual and a denominator floor
    /// (normalised units).
    ///
    /// # Errors
    /// [`ControlError::BadSetting`] unless both are finite and positive.
    pub fn new(threshold: f64, floor: f64) -> Result<Self, ControlError> {
        for (name, value) in [("threshold", threshold), ("floor", floor)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(ControlError::BadSetting {
                    name,
                    value,
                    allowed: "a finite number > 0",
                });
            }
        }
        Ok(Self { threshold, floor })
    }

    /// Calibrates the threshold as `margin` times the largest of the finite `residuals`
    /// measured on free motion (non-finite ones are ignored).
    ///
    /// # Errors
    /// [`ControlError::TooFewResiduals`] with fewer than [`MIN_CALIBRATION_RESIDUALS`] finite
    /// residuals; [`ControlError::BadSetting`] for a margin below 1 or a bad floor.
    pub fn calibrate(residuals: &[f64], margin: f64, floor: f64) -> Result<Self, ControlError> {
        if !(margin.is_finite() && margin >= 1.0) {
            return Err(ControlError::BadSetting {
                name: "margin",
                value: margin,
                allowed: "a finite number ≥ 1",
            });
        }
        let finite: Vec<f64> = residuals
            .iter()
            .copied()
            .filter(|r| r.is_finite())
            .collect();
        if finite.len() < MIN_CALIBRATION_RESIDUALS {
            return Err(ControlError::TooFewResiduals {
                got: finite.len(),
                needed: MIN_CALIBRATION_RESIDUALS,
            });
        }
        let largest = finite.iter().copied().fold(0.0, f64::max);
        Self::new((margin * largest).max(f64::MIN_POSITIVE), floor)
    }

    /// As [`CollisionDetector::calibrate`], from the `quantile` (in `(0, 1]`) of the finite
    /// residuals instead of the largest: free motions of a real wire can hold rare events the
    /// model does not have either (a snap to another equilibrium branch), which would otherwise
    /// set the threshold.
    ///
    /// # Errors
    /// As [`CollisionDetector::calibrate`], and [`ControlError::BadSetting`] for a quantile
    /// outside `(0, 1]`.
    pub fn calibrate_quantile(
        residuals: &[f64],
        quantile: f64,
        margin: f64,
        floor: f64,
    ) -> Result<Self, ControlError> {
        if !(quantile > 0.0 && quantile <= 1.0) {
            return Err(ControlError::BadSetting {
                name: "quantile",
                value: quantile,
                allowed: "a quantile in (0, 1]",
            });
        }
        let mut finite: Vec<f64> = residuals
            .iter()
            .copied()
            .filter(|r| r.is_finite())
            .collect();
        finite.sort_by(f64::total_cmp);
        let keep = ((quantile * finite.len() as f64).ceil() as usize).min(finite.len());
        finite.truncate(keep.max(MIN_CALIBRATION_RESIDUALS.min(finite.len())));
        Self::calibrate(&finite, margin, floor)
    }

    /// The threshold on the relative residual.
    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    /// The floor of the residual's denominator \[normalised units\].
    pub fn floor(&self) -> f64 {
        self.floor
    }

    /// Whether a residual means a contact.
    pub fn is_contact(&self, residual: f64) -> bool {
        // A non-finite residual is no agreement with the model either.
        residual.is_nan() || residual > self.threshold
    }

    /// The jump ratio of the last of `misses` (see the module docs); `0` without history.
    pub fn residual(&self, misses: &[f64]) -> f64 {
        jump_ratio(misses, self.floor)
    }
}

/// The miss of one move: `‖N(after − before − δa_pred)‖` in normalised units.
pub fn miss(
    wire: &WireParams,
    before: &Vector6<f64>,
    after: &Vector6<f64>,
    predicted_da: &Vector6<f64>,
) -> f64 {
    to_normalised(wire, &(after - before - predicted_da)).norm()
}

/// The jump ratio of the last of `misses` with a given floor (see the module docs); `0` for
/// the first move.
pub fn jump_ratio(misses: &[f64], floor: f64) -> f64 {
    match misses {
        [] | [_] => 0.0,
        [before, last] => last / (before + floor),
        [.., two_back, before, last] => last / (before.max(*two_back) + floor),
    }
}

/// The model's prediction `δa = J(L)⁻¹ δb` for a commanded `δb` (eq. 11), or `None` when
/// `J(L)` is singular.
pub fn predicted_delta_a(jacobian: &Matrix6<f64>, delta_b: &Vector6<f64>) -> Option<Vector6<f64>> {
    jacobian.lu().solve(delta_b)
}
