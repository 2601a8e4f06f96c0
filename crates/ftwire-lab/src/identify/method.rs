//! How an identification experiment computes `ã` (the residual form, `Form`, is
//! `ftwire_logs::identification`'s).

use serde::Serialize;

/// How `ã` is computed from the tared reading.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Pipeline {
    /// The learnt calibration network (a calibration file, or one run and cached first):
    /// corrects the sensor's gain, cross-talk and nonlinearity.
    #[default]
    Calibrated,
    /// The sensor's mounting transform only (no learnt correction): the sensor's gain error
    /// and cross-talk of about 1 % stay in `ã`. For comparison.
    Mounting,
}
