//! How a calibration is trained and how it was: the training settings, and the record saved
//! with the weights.

use serde::{Deserialize, Serialize};

use super::{Activation, SplitFractions};
use crate::EstimateError;

/// How to train a calibration. Public fields with [`Default`]; checked when training starts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TrainParams {
    /// Hidden layer widths, each in `1..=MAX_WIDTH`, at most `MAX_HIDDEN_LAYERS` of them;
    /// empty gives an affine network (default `[64, 64]`).
    pub hidden: Vec<usize>,
    /// Activation of the hidden layers (default [`Activation::Tanh`]).
    pub activation: Activation,
    /// Learn the residual over a least-squares affine map from normalised reading to normalised
    /// `a`, and start the network at zero output (its last layer zeroed), so that training
    /// starts from the affine fit and early stopping can only improve on it (default `true`).
    pub residual: bool,
    /// Anchor the map at zero: subtract the trained map's output for a zero reading, so that a
    /// reading of zero gives `a = 0` exactly (default `false`). Set it when the readings are
    /// tared with the gripper empty, as [`crate::ft::FtPipeline`] does: a zero tared reading is
    /// then a zero wrench, while a free map puts its least-squares intercept there, an absolute
    /// error that is nothing on the calibration wire but can be several per cent of a soft
    /// wire's force scale. Only when zero is inside the training readings' range: elsewhere
    /// `F(0)` is an extrapolation (as for a wire whose weight keeps every reading away from
    /// zero). Leave it off for untared readings, whose bias the affine part must learn. Weight
    /// files without this setting read as `false`, so they keep their meaning.
    #[serde(default)]
    pub anchored: bool,
    /// The map of the sensor's own form, zero at a zero reading: for readings tared with the
    /// gripper empty, whose zero is a zero wrench on any wire (default `false`). The linear
    /// part is fitted through the origin in raw units (`a ≈ W raw`, no intercept: mounting,
    /// gain and cross-talk are linear and the tare removed the bias), and the network's
    /// remainder is gated, `ρ(raw) f(z)` with `ρ = q / (1 + q)`, `q = |raw ⊘ σ_raw|²`, so that it
    /// vanishes quadratically at small readings, as a sensor's nonlinearity does (it is cubic
    /// in the reading), and cannot put the calibration wire's label biases or an extrapolation
    /// onto a soft wire's small wrenches. Without it the least-squares intercept and the
    /// network add a few mN (gravity off) at every reading: per cent of a soft wire's forces.
    /// Leave it off for untared readings, whose offset the map must learn. Weight files
    /// without this setting read as `false`, so they keep their meaning.
    #[serde(default)]
    pub through_zero: bool,
    /// Split fractions (default 70 % training, 15 % validation, 15 % test).
    pub split: SplitFractions,
    /// Samples per mini-batch, `≥ 1` (default `32`).
    pub batch_size: usize,
    /// Adam step size, in `(0, 1]` (default `1e-3`).
    pub learning_rate: f64,
    /// Multiply the step size by this factor after `plateau` epochs without a new best
    /// validation loss (since the last best or the last decay), in `(0, 1]`; `1` keeps it
    /// constant (default `0.5`).
    pub decay: f64,
    /// Epochs without a new best validation loss before the step size decays, `≥ 1`
    /// (default `20`).
    pub plateau: usize,
    /// Most passes over the training split, `≥ 1` (default `2000`).
    pub max_epochs: usize,
    /// Stop after this many epochs without a new best validation loss, `≥ 1` (default `100`).
    pub patience: usize,
}

impl Default for TrainParams {
    fn default() -> Self {
        Self {
            hidden: vec![64, 64],
            activation: Activation::Tanh,
            residual: true,
            anchored: false,
            through_zero: false,
            split: SplitFractions::default(),
            batch_size: 32,
            learning_rate: 1e-3,
            decay: 0.5,
            plateau: 20,
            max_epochs: 2000,
            patience: 100,
        }
    }
}

impl TrainParams {
    /// Checks the ranges documented on the fields (the split's are checked by the split).
    pub(super) fn validate(&self) -> Result<(), EstimateError> {
        #[allow(clippy::cast_precision_loss)] // reported values only
        for (field, value) in [
            ("batch_size", self.batch_size),
            ("plateau", self.plateau),
            ("max_epochs", self.max_epochs),
            ("patience", self.patience),
        ] {
            if value == 0 {
                return Err(EstimateError::InvalidSetting {
                    field,
                    value: value as f64,
                    allowed: "an integer ≥ 1",
                });
            }
        }
        if !(self.learning_rate > 0.0 && self.learning_rate <= 1.0) {
            return Err(EstimateError::InvalidSetting {
                field: "learning_rate",
                value: self.learning_rate,
                allowed: "a step size in (0, 1]",
            });
        }
        if !(self.decay > 0.0 && self.decay <= 1.0) {
            return Err(EstimateError::InvalidSetting {
                field: "decay",
                value: self.decay,
                allowed: "a factor in (0, 1]",
            });
        }
        Ok(())
    }
}

/// Why training stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// `patience` epochs passed without a new best validation loss.
    Patience,
    /// `max_epochs` were run.
    MaxEpochs,
    /// A loss became non-finite; the best weights before it are kept.
    Diverged,
}

/// Losses of one epoch (normalised units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EpochLosses {
    /// Mean training loss over the epoch's mini-batches.
    pub train: f64,
    /// Validation loss after the epoch.
    pub validation: f64,
}

/// Sizes of the three splits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SplitSizes {
    /// Training samples.
    pub train: usize,
    /// Validation samples.
    pub validation: usize,
    /// Test samples.
    pub test: usize,
}

/// How a calibration was trained, saved with its weights.
///
/// Losses are the network's mean squared errors over samples and the six outputs, in the units
/// it is trained in: with `residual`, each channel's affine-fit residual divided by its
/// training-split spread, so 1.0 is "as good as the affine fit"; without, each component of `a`
/// standardised, so 1.0 is "as good as predicting the mean". RMS errors are per component of `a`, torque first, in
/// \[N·m\] and \[N\].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrainingRecord {
    /// The seed of the split, the initial weights and the batch order.
    pub seed: u64,
    /// The configuration trained with.
    pub config: TrainParams,
    /// Samples in each split.
    pub samples: SplitSizes,
    /// Epochs run.
    pub epochs: usize,
    /// Epoch of the kept (best validation) weights; 0 means the initial weights.
    pub best_epoch: usize,
    /// Why training stopped.
    pub stop: StopReason,
    /// Validation loss of the initial weights: with `residual`, that of the affine fit alone.
    pub initial_validation_loss: f64,
    /// Validation loss of the kept weights.
    pub validation_loss: f64,
    /// Test loss of the kept weights (`None` without test samples).
    pub test_loss: Option<f64>,
    /// Per-component RMS error of the kept calibration on the test split, torque first
    /// \[N·m, N·m, N·m, N, N, N\] (`None` without test samples).
    pub test_rmse: Option<[f64; 6]>,
    /// Losses of every epoch run, in order.
    pub history: Vec<EpochLosses>,
}
