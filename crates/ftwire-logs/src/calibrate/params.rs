//! The settings of `calibrate --log` ([`LogCalibrateParams`], [`MapLoss`]), their defaults
//! and their checks, and the model the labels are solved with: everything the run reads
//! before it reads the recording.

use std::path::PathBuf;

use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::calibration::shape_loss::ShapeLossParams;
use ftwire_estimate::calibration::{LabelModel, SplitOrder, TrainParams};
use ftwire_estimate::ft::MountingSpec;
use serde::Serialize;

use ftwire_app::config::wire::WireSpec;
use ftwire_app::error::LabError;

/// Fewest markers a record needs for a label: the fit has six unknowns and three numbers per
/// marker, and the clamp's marker says nothing.
pub const MIN_MARKERS: usize = 4;

/// Default largest RMS marker residual of a label's fit \[m\]: a few times the about 1 mm of a
/// real rig's markers against its own fitted wire.
pub const DEFAULT_MAX_LABEL_RMS: f64 = 3e-3;

/// The training settings for a recording: a small network (a few hundred records), the split
/// by blocks of time, patience for a small validation block.
pub fn default_train_params() -> TrainParams {
    let mut train = TrainParams {
        hidden: vec![16, 16],
        patience: 200,
        ..TrainParams::default()
    };
    train.split.order = SplitOrder::Time;
    train
}

/// The settings of `calibrate --log`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LogCalibrateParams {
    /// The recording.
    pub log: PathBuf,
    /// The known wire of the recording.
    pub wire: WireSpec,
    /// The sensor's mounting (and tool).
    pub mounting: MountingSpec,
    /// Gravity in the base clamp frame \[m/s²\] for the loaded model; `None`: the paper's
    /// weight-free model.
    pub gravity: Option<[f64; 3]>,
    /// The markers' arc lengths as fractions of the wire's length, in the log's order; `None`:
    /// matched at their closest points.
    pub marker_fractions: Option<Vec<f64>>,
    /// Largest RMS marker residual of a kept label \[m\].
    pub max_label_rms: f64,
    /// How the network is trained (the split is by blocks of time unless set otherwise).
    pub train: TrainParams,
    /// Offer the map a drift term (an offset linear in time, fitted on the training block);
    /// it is kept only when it predicts the validation block better.
    pub drift: bool,
    /// Seed of the fits' global search and of the network's initial weights.
    pub seed: u64,
    /// What the map is fitted on.
    pub loss: MapLoss,
    /// Fit gravity's direction in the clamp frame with the map, of this norm \[m/s²\]
    /// (`--fit-gravity`, `--gravity-norm`); `gravity`, when given, is where it starts. Only
    /// with [`MapLoss::Shape`].
    pub fit_gravity: Option<f64>,
    /// Consecutive records whose markers moved less than this \[m\] are one rest, and their
    /// labels are fitted to the rest's mean markers; zero: every record alone.
    pub rest_tolerance: f64,
    /// The shape fit's candidate maps and iterations (with [`MapLoss::Shape`]).
    pub shape: ShapeLossParams,
}

/// What `calibrate --log` fits the map on (`--loss`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MapLoss {
    /// The markers' distance to the model's shape of the map's `a` (Huber's loss), through
    /// the model's Jacobian; the labels start it and keep a weak pull
    /// (`ftwire_estimate::calibration::shape_loss`); the map fitted on the labels is one more
    /// candidate.
    #[default]
    Shape,
    /// The labels in `a` (least squares, the affine map and the network): the paper's §IV-A.
    Labels,
}

impl MapLoss {
    /// The names `--loss` takes.
    pub const NAMES: [&'static str; 2] = ["shape", "labels"];

    /// The loss of a name of [`Self::NAMES`].
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "shape" => Some(Self::Shape),
            "labels" => Some(Self::Labels),
            _ => None,
        }
    }
}

/// The loss of a name of [`MapLoss::NAMES`], as `--loss` parses it.
impl std::str::FromStr for MapLoss {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, Self::Err> {
        Self::from_name(name)
            .ok_or_else(|| format!("--loss {name}: one of {}", Self::NAMES.join(", ")))
    }
}

/// Default rest tolerance \[m\]: a few times a motion-capture system's jitter, well below
/// a rig's steps between rests (about 17 mm).
pub const DEFAULT_REST_TOLERANCE: f64 = 2e-3;

/// Default `|g|` of `--fit-gravity` \[m/s²\].
pub const STANDARD_GRAVITY: f64 = 9.81;

impl LogCalibrateParams {
    /// Checks the settings before any work.
    ///
    /// # Errors
    /// Bad input naming the value.
    pub fn check(&self) -> Result<(), LabError> {
        self.mounting
            .validate()
            .map_err(|e| LabError::bad_input(format!("--mounting: {e}")))?;
        self.wire
            .wire_params()
            .map_err(|e| LabError::bad_input(format!("--wire {}: {e}", self.wire.name)))?;
        if !(self.max_label_rms.is_finite() && self.max_label_rms > 0.0) {
            return Err(LabError::bad_input(format!(
                "--max-label-rms-mm {}: must be a finite distance > 0 (default {} mm)",
                1e3 * self.max_label_rms,
                1e3 * DEFAULT_MAX_LABEL_RMS
            )));
        }
        if let Some(g) = &self.gravity
            && g.iter().any(|v| !v.is_finite())
        {
            return Err(LabError::bad_input(format!(
                "gravity {g:?}: every component must be finite"
            )));
        }
        if let Some(norm) = self.fit_gravity
            && !(norm.is_finite() && norm > 0.0 && norm <= LabelModel::MAX_GRAVITY)
        {
            return Err(LabError::bad_input(format!(
                "--gravity-norm {norm}: must be a finite acceleration in (0, 100] m/s²"
            )));
        }
        if self.fit_gravity.is_some() && self.loss == MapLoss::Labels {
            return Err(LabError::bad_input(
                "--fit-gravity fits gravity with the map on the shape: it needs --loss shape"
                    .to_owned(),
            ));
        }
        if !(self.rest_tolerance.is_finite() && self.rest_tolerance >= 0.0) {
            return Err(LabError::bad_input(format!(
                "--rest-tolerance-mm {}: must be a finite distance ≥ 0 (0: no pooling)",
                1e3 * self.rest_tolerance
            )));
        }
        if let Some(fractions) = &self.marker_fractions
            && let Some(bad) = fractions
                .iter()
                .find(|f| !(f.is_finite() && (0.0..=1.0).contains(*f)))
        {
            return Err(LabError::bad_input(format!(
                "--marker-fractions: {bad} is not a fraction of the length in [0, 1]"
            )));
        }
        Ok(())
    }

    /// The model the labels are solved with.
    pub(super) fn model(&self) -> Result<KirchhoffModel, LabError> {
        self.model_under(self.gravity)
    }

    /// The model under `gravity` in the clamp frame (`None`: weight-free).
    pub(super) fn model_under(
        &self,
        gravity: Option<[f64; 3]>,
    ) -> Result<KirchhoffModel, LabError> {
        crate::shape::wire_model(&self.wire, gravity)
    }
}
