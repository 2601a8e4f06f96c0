//! How an identification is run: the residual it minimises and how `ã` is computed.

use ftwire_estimate::identify::ResidualForm;
use serde::Serialize;

/// The residual identification minimises (`ftwire_estimate::identify::ResidualForm`), by the
/// names the summaries use.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Form {
    /// The exact absolute form `log(Γ_η(ã_i)⁻¹ b̃_i)`: reaches the noise floor.
    #[default]
    Absolute,
    /// The paper's eq. 12, `J_η(ã_i) δã_i − δb̃_i`: limited to 2–3 % by its linearisation.
    Eq12,
    /// Eq. 12 with `J` at the midpoint of each step.
    Midpoint,
    /// Exact relative poses of consecutive samples.
    Relative,
}

impl Form {
    /// The library's residual form.
    pub fn residual(self) -> ResidualForm {
        match self {
            Self::Absolute => ResidualForm::Absolute,
            Self::Eq12 => ResidualForm::Eq12,
            Self::Midpoint => ResidualForm::Midpoint,
            Self::Relative => ResidualForm::Relative,
        }
    }
}

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
