//! F/T sensor calibration by a small neural network (paper §IV-A).
//!
//! The raw reading of the wrist F/T sensor (force first, sensor frame, after taring) is not the
//! configuration `a` the model needs (torque first, base clamp frame): the sensor is mounted
//! away from the clamp and rotated, its channels have gains and cross-talk, a mild
//! nonlinearity, a bias, and noise. The paper labels readings with `a` from shape fitting
//! (eq. 15) and trains a network on the pairs; this module is that network.
//!
//! Workflow:
//! 1. Collect pairs into a [`Dataset`] (it rejects non-finite samples and unpaired lists,
//!    naming the sample).
//! 2. [`Calibration::train`] (or [`Calibration::train_with_progress`]) with a [`TrainParams`]
//!    and a seed: a seeded 70/15/15 split ([`SplitFractions`]), per-channel standardisation
//!    fitted on the training split ([`Normaliser`]), a least-squares affine map ([`Affine`])
//!    and an [`Mlp`] (default 6-64-64-6, tanh) trained on what the affine map leaves, by
//!    mini-batch Adam (Kingma and Ba 2015) with early stopping on the validation loss, keeping
//!    the best weights. The [`TrainingRecord`] keeps the seed, configuration, losses and test
//!    errors.
//! 3. [`Calibration::save`] / [`Calibration::load`] the weights file ([`file`](mod@file) documents it).
//! 4. [`Calibration::apply`] maps a reading to `a`, allocation-free.
//!
//! **Residual over an affine map.** Mounting, gain and cross-talk are linear and the bias is
//! an offset, so an affine least-squares fit already explains nearly everything; the network
//! only learns the small nonlinear remainder. Its last layer starts at zero, so training
//! starts exactly at the affine fit and early stopping can only improve on it on the
//! validation split. With few samples this is much better than learning the whole map (see
//! `tests/calibration_synthetic.rs`, which measures both).
//!
//! **Through zero.** For readings tared with the gripper empty, [`TrainParams::through_zero`]
//! fits the linear part without intercept and gates the network's remainder so that it
//! vanishes at small readings: the map is the sensor's own, zero at a zero wrench, and carries
//! over to wires of other wrench scales (guarded by `ftwire-lab`'s `tests/calibration_scales.rs`).
//!
//! **Why hand-written, not `candle`.** `candle-core` + `candle-nn` 0.11 lock 157 packages and
//! take minutes to build; this module is a few hundred lines with no new dependency beyond
//! `serde_json`. A 6-64-64-6 network has about 5 000 parameters, so a forward pass is a few
//! thousand multiply-adds: framework tensors (heap-allocated, dynamically shaped, dispatched per
//! operation) would cost more than the arithmetic, while the plain loops here allocate nothing
//! at inference and are easy to check line by line. Backpropagation for a dense network is
//! short, and its gradient is checked against finite differences
//! (`tests/calibration_gradient.rs`). Training is single-threaded and in a fixed order, so the
//! same seed gives bit-identical weights (`tests/calibration_train.rs`).

mod adam;
mod affine;
mod dataset;
pub mod file;
mod map;
mod mlp;
mod normalise;
mod polynomial;
mod record;
pub mod shape_loss;
mod train;

pub use affine::Affine;
pub use dataset::{Dataset, MIN_TRAINING_SAMPLES, Split, SplitFractions, SplitOrder};
pub use map::{Calibration, CalibrationInput, Drift, LabelModel, LabelModelKind};
pub use mlp::{Activation, MAX_HIDDEN_LAYERS, MAX_WIDTH, Mlp, parameter_count};
pub use normalise::Normaliser;
pub use polynomial::{MAX_FEATURES, MAX_POLYNOMIAL_DEGREE, Polynomial, feature_count, features};
pub use record::{EpochLosses, SplitSizes, StopReason, TrainParams, TrainingRecord};
pub use train::EpochProgress;
