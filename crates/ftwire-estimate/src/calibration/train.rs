//! The training driver: seeded split, normalisation, the affine fit, mini-batch Adam on the
//! residual, early stopping on the validation loss, and the training record (`record`) filled
//! in.

use nalgebra::Vector6;
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

use super::adam::Adam;
use super::map::remainder_gate;
use super::mlp::Backprop;
use super::record::{EpochLosses, SplitSizes, StopReason, TrainParams, TrainingRecord};
use super::{Affine, Calibration, Dataset, Mlp, Normaliser};
use crate::EstimateError;

/// What the progress callback sees after each epoch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EpochProgress {
    /// The epoch just finished, from 1.
    pub epoch: usize,
    /// The configured maximum number of epochs.
    pub max_epochs: usize,
    /// Mean training loss over the epoch's mini-batches (normalised units, see
    /// [`TrainingRecord`]).
    pub train_loss: f64,
    /// Validation loss after the epoch (normalised units).
    pub validation_loss: f64,
    /// The epoch with the lowest validation loss so far (0: the initial weights).
    pub best_epoch: usize,
    /// The lowest validation loss so far.
    pub best_validation_loss: f64,
    /// The step size the epoch ran with.
    pub learning_rate: f64,
}

impl Calibration {
    /// Trains a calibration on `data` with `config`; every random choice (split, initial
    /// weights, batch order) comes from `seed`, and the same seed gives bit-identical weights.
    ///
    /// # Errors
    /// As [`Calibration::train_with_progress`].
    ///
    /// # Example
    /// ```
    /// use ftwire_estimate::calibration::{Calibration, Dataset, TrainParams};
    /// use nalgebra::Vector6;
    ///
    /// // A sensor that reads a, force first and with gain 2.
    /// let labels: Vec<Vector6<f64>> = (0..60)
    ///     .map(|k| Vector6::from_fn(|i, _| ((k * (i + 3)) % 17) as f64 - 8.0))
    ///     .collect();
    /// let raw = labels.iter().map(|a| 2.0 * Vector6::new(a[3], a[4], a[5], a[0], a[1], a[2]));
    /// let data = Dataset::new(raw.collect(), labels.clone())?;
    /// let config = TrainParams { hidden: vec![8], max_epochs: 5, ..TrainParams::default() };
    /// let calibration = Calibration::train(&data, &config, 42)?;
    /// let a = calibration.apply(&data.raw()[0]);
    /// assert!((a - labels[0]).norm() < 1e-6 * labels[0].norm().max(1.0));
    /// # Ok::<(), ftwire_estimate::EstimateError>(())
    /// ```
    pub fn train(data: &Dataset, config: &TrainParams, seed: u64) -> Result<Self, EstimateError> {
        Self::train_with_progress(data, config, seed, |_| {})
    }

    /// [`Calibration::train`], calling `progress` after every epoch (for a progress bar).
    ///
    /// # Errors
    /// [`EstimateError::InvalidSetting`] for a configuration out of range;
    /// [`EstimateError::TooFewCalibrationSamples`] when `data` is too small for the split.
    pub fn train_with_progress(
        data: &Dataset,
        config: &TrainParams,
        seed: u64,
        mut progress: impl FnMut(&EpochProgress),
    ) -> Result<Self, EstimateError> {
        config.validate()?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let split = data.split(&config.split, &mut rng)?;
        let problem = Problem::new(data, &split.train, config);
        let train = problem.targets(data, &split.train);
        let validation = problem.targets(data, &split.validation);
        let mut mlp = Mlp::new(&config.hidden, config.activation, &mut rng)?;
        if config.residual {
            mlp.zero_output_layer();
        }
        let mut descent = descend(mlp, &train, &validation, config, &mut rng, &mut progress)?;
        let test_loss = if split.test.is_empty() {
            None
        } else {
            let test = problem.targets(data, &split.test);
            Some(gated_loss(&descent.best, &test)?)
        };
        descent.best.scale_outputs(&problem.scale);
        let record = TrainingRecord {
            seed,
            config: config.clone(),
            samples: SplitSizes {
                train: split.train.len(),
                validation: split.validation.len(),
                test: split.test.len(),
            },
            epochs: descent.history.len(),
            best_epoch: descent.best_epoch,
            stop: descent.stop,
            initial_validation_loss: descent.initial_validation_loss,
            validation_loss: descent.best_validation_loss,
            test_loss,
            test_rmse: None,
            history: descent.history,
        };
        let mut calibration = Self::from_parts(
            problem.input,
            problem.output,
            problem.affine,
            descent.best,
            record,
        );
        if !split.test.is_empty() {
            let rmse = calibration.rmse(data.pairs(&split.test));
            calibration.record.test_rmse = Some(rmse.into());
        }
        Ok(calibration)
    }
}

/// The network's inputs (normalised readings), targets and output gates of some samples.
type Targets = (Vec<Vector6<f64>>, Vec<Vector6<f64>>, Vec<f64>);

/// What the network is trained on, fitted on the training split: the standardisations, the
/// affine part, and the per-channel scale of what the affine part leaves.
struct Problem {
    input: Normaliser,
    output: Normaliser,
    affine: Option<Affine>,
    /// The network's targets are the affine fit's residuals divided by this, per channel (ones
    /// without an affine part).
    scale: Vector6<f64>,
    /// Gate the network's output by [`remainder_gate`] ([`TrainParams::through_zero`]).
    gated: bool,
}

impl Problem {
    fn new(data: &Dataset, train: &[usize], config: &TrainParams) -> Self {
        let input = Normaliser::fit(data.pairs(train).map(|(r, _)| r));
        let output = Normaliser::fit(data.pairs(train).map(|(_, l)| l));
        let mut problem = Self {
            input,
            output,
            affine: None,
            scale: Vector6::repeat(1.0),
            gated: config.through_zero,
        };
        if config.residual {
            let normalised: Vec<_> = data
                .pairs(train)
                .map(|(r, l)| (input.normalise(r), output.normalise(l)))
                .collect();
            let affine = if config.through_zero {
                through_zero(data, train, &input, &output)
            } else {
                Affine::fit(normalised.iter().map(|(z, y)| (z, y)))
            };
            // Each channel's residual in units of its own spread, so that every channel weighs
            // alike in the loss (a channel the affine part fits precisely would otherwise be
            // invisible next to a noisy one).
            let residuals: Vec<_> = normalised
                .iter()
                .map(|(z, y)| y - affine.apply(z))
                .collect();
            problem.scale = *Normaliser::fit(residuals.iter()).std();
            problem.affine = Some(affine);
        }
        problem
    }

    /// The network's inputs (normalised readings), targets and output gates for the samples
    /// at `indices`.
    fn targets(&self, data: &Dataset, indices: &[usize]) -> Targets {
        let mut out: Targets = (Vec::new(), Vec::new(), Vec::new());
        for (r, l) in data.pairs(indices) {
            let z = self.input.normalise(r);
            let y = self.output.normalise(l);
            let left = self.affine.as_ref().map_or(y, |a| y - a.apply(&z));
            out.0.push(z);
            out.1.push(left.component_div(&self.scale));
            out.2.push(if self.gated {
                remainder_gate(&self.input, r)
            } else {
                1.0
            });
        }
        out
    }
}

/// The linear map through the origin in raw units, `a ≈ W raw`, fitted on the samples `train`
/// and written as the affine part in normalised units: with `u = raw ⊘ σ_raw` and
/// `ŷ = a ⊘ σ_a`, the fit `ŷ ≈ B u` is `y = B z + B (μ_raw ⊘ σ_raw) − μ_a ⊘ σ_a` in the
/// normalised `z`, `y`, so that the whole map is zero at a zero reading.
fn through_zero(
    data: &Dataset,
    train: &[usize],
    input: &Normaliser,
    output: &Normaliser,
) -> Affine {
    let scaled: Vec<_> = data
        .pairs(train)
        .map(|(r, l)| (r.component_div(input.std()), l.component_div(output.std())))
        .collect();
    let linear = Affine::fit_linear(scaled.iter().map(|(u, y)| (u, y)));
    let offset = linear.matrix * input.mean().component_div(input.std())
        - output.mean().component_div(output.std());
    Affine {
        matrix: linear.matrix,
        offset,
    }
}

/// The loss `(1 / 6n) Σ |g f(z) − t|²` of the network over `(z, t, g)`.
fn gated_loss(mlp: &Mlp, (inputs, targets, gates): &Targets) -> Result<f64, EstimateError> {
    if inputs.len() != targets.len() || inputs.len() != gates.len() {
        return Err(EstimateError::SampleCountMismatch {
            raw: inputs.len(),
            labels: targets.len(),
            first_unpaired: inputs.len().min(targets.len()).min(gates.len()),
        });
    }
    Ok(super::mlp::mean_squared_error(
        inputs
            .iter()
            .zip(targets)
            .zip(gates)
            .map(|((z, t), g)| (*g * mlp.forward(z) - t).norm_squared()),
        inputs.len(),
    ))
}

/// The outcome of [`descend`].
struct Descent {
    best: Mlp,
    best_epoch: usize,
    best_validation_loss: f64,
    initial_validation_loss: f64,
    stop: StopReason,
    history: Vec<EpochLosses>,
}

/// Mini-batch Adam from `mlp` on the `(inputs, targets)` of `train`, with step decay on
/// plateaus and early stopping on the loss over `validation`, keeping the best weights.
fn descend(
    mut mlp: Mlp,
    train: &Targets,
    validation: &Targets,
    config: &TrainParams,
    rng: &mut ChaCha8Rng,
    progress: &mut impl FnMut(&EpochProgress),
) -> Result<Descent, EstimateError> {
    let (train_z, train_t, train_g) = train;
    let initial_validation_loss = gated_loss(&mlp, validation)?;
    let mut descent = Descent {
        best: mlp.clone(),
        best_epoch: 0,
        best_validation_loss: initial_validation_loss,
        initial_validation_loss,
        stop: StopReason::MaxEpochs,
        history: Vec::new(),
    };
    let mut adam = Adam::new(mlp.parameters().len(), config.learning_rate);
    let mut workspace = Backprop::new(&mlp);
    let mut gradient = vec![0.0; mlp.parameters().len()];
    let mut order: Vec<usize> = (0..train_z.len()).collect();
    let mut last_decay = 0;
    for epoch in 1..=config.max_epochs {
        let learning_rate = adam.learning_rate();
        order.shuffle(rng);
        let mut sum = 0.0;
        for batch in order.chunks(config.batch_size) {
            gradient.fill(0.0);
            let triples = batch
                .iter()
                .filter_map(|&i| Some((train_z.get(i)?, train_t.get(i)?, *train_g.get(i)?)));
            let loss = workspace.accumulate(&mlp, triples, batch.len(), &mut gradient);
            #[allow(clippy::cast_precision_loss)] // batch sizes are far below 2⁵²
            let weight = batch.len() as f64;
            sum += loss * weight;
            adam.step(mlp.parameters_mut(), &gradient);
        }
        #[allow(clippy::cast_precision_loss)] // sample counts are far below 2⁵²
        let train_loss = sum / order.len().max(1) as f64;
        let validation_loss = gated_loss(&mlp, validation)?;
        if !(train_loss.is_finite() && validation_loss.is_finite()) {
            descent.stop = StopReason::Diverged;
            break;
        }
        descent.history.push(EpochLosses {
            train: train_loss,
            validation: validation_loss,
        });
        if validation_loss < descent.best_validation_loss {
            descent.best.clone_from(&mlp);
            descent.best_validation_loss = validation_loss;
            descent.best_epoch = epoch;
        }
        progress(&EpochProgress {
            epoch,
            max_epochs: config.max_epochs,
            train_loss,
            validation_loss,
            best_epoch: descent.best_epoch,
            best_validation_loss: descent.best_validation_loss,
            learning_rate,
        });
        if epoch - descent.best_epoch.max(last_decay) >= config.plateau {
            adam.set_learning_rate(learning_rate * config.decay);
            last_decay = epoch;
        }
        if epoch - descent.best_epoch >= config.patience && epoch < config.max_epochs {
            descent.stop = StopReason::Patience;
            break;
        }
    }
    Ok(descent)
}
