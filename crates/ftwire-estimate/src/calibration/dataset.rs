//! Labelled calibration samples and their seeded split into training, validation and test sets.

use nalgebra::Vector6;
use rand::Rng;
use rand::seq::SliceRandom;
use serde::{Deserialize, Serialize};

use crate::EstimateError;

/// Fewest training samples: the affine fit has 7 unknowns per output.
pub const MIN_TRAINING_SAMPLES: usize = 8;

/// Labelled calibration samples: raw F/T readings (force first, sensor frame, tared) paired
/// with the configuration `a` each was labelled with (torque first, base clamp frame, for
/// example by shape fitting, eq. 15). Every number is finite.
///
/// # Example
/// ```
/// use ftwire_estimate::calibration::Dataset;
/// use nalgebra::Vector6;
///
/// let data = Dataset::new(vec![Vector6::zeros(); 3], vec![Vector6::zeros(); 3])?;
/// assert_eq!(data.len(), 3);
/// let bad = Dataset::new(vec![Vector6::zeros(); 3], vec![Vector6::zeros(); 2]);
/// assert!(bad.is_err());
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    raw: Vec<Vector6<f64>>,
    labels: Vec<Vector6<f64>>,
}

impl Dataset {
    /// Pairs `raw[i]` with `labels[i]`.
    ///
    /// # Errors
    /// [`EstimateError::SampleCountMismatch`] when the lengths differ;
    /// [`EstimateError::NonFiniteCalibrationSample`] naming the first sample with a non-finite number.
    pub fn new(raw: Vec<Vector6<f64>>, labels: Vec<Vector6<f64>>) -> Result<Self, EstimateError> {
        if raw.len() != labels.len() {
            return Err(EstimateError::SampleCountMismatch {
                raw: raw.len(),
                labels: labels.len(),
                first_unpaired: raw.len().min(labels.len()),
            });
        }
        for (index, (r, l)) in raw.iter().zip(&labels).enumerate() {
            for (field, v) in [("raw", r), ("label", l)] {
                if let Some((component, &value)) =
                    v.iter().enumerate().find(|(_, x)| !x.is_finite())
                {
                    return Err(EstimateError::NonFiniteCalibrationSample {
                        index,
                        field,
                        component,
                        value,
                    });
                }
            }
        }
        Ok(Self { raw, labels })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.raw.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.raw.is_empty()
    }

    /// The raw readings (force first, sensor frame).
    pub fn raw(&self) -> &[Vector6<f64>] {
        &self.raw
    }

    /// The labels `a` (torque first, base clamp frame).
    pub fn labels(&self) -> &[Vector6<f64>] {
        &self.labels
    }

    /// The samples at `indices`, as (raw, label) pairs; indices out of range are skipped.
    pub fn pairs<'a>(
        &'a self,
        indices: &'a [usize],
    ) -> impl Iterator<Item = (&'a Vector6<f64>, &'a Vector6<f64>)> + Clone + 'a {
        indices
            .iter()
            .filter_map(|&i| Some((self.raw.get(i)?, self.labels.get(i)?)))
    }

    /// A partition of the sample indices by `fractions`: drawn at random from `rng`, or, with
    /// [`SplitOrder::Time`], in the samples' order (their time order on a recording): the
    /// first `⌊n · train⌋` samples train, the next `⌊n · validation⌋` validate, the rest test.
    ///
    /// The training split gets `⌊n · train⌋` samples, the validation split `⌊n · validation⌋`,
    /// the test split the rest (possibly none).
    ///
    /// # Errors
    /// [`EstimateError::InvalidSetting`] for fractions out of range;
    /// [`EstimateError::TooFewCalibrationSamples`] when the training split would get fewer than
    /// [`MIN_TRAINING_SAMPLES`] or the validation split none.
    pub fn split<R: Rng + ?Sized>(
        &self,
        fractions: &SplitFractions,
        rng: &mut R,
    ) -> Result<Split, EstimateError> {
        fractions.validate()?;
        let n = self.len();
        #[allow(
            clippy::cast_precision_loss,
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss
        )] // fractions in (0, 1], counts far below 2⁵²
        let count = |fraction: f64| (n as f64 * fraction).floor() as usize;
        let train = count(fractions.train).min(n);
        let validation = count(fractions.validation).min(n - train);
        for (split, got, needed) in [
            ("training", train, MIN_TRAINING_SAMPLES),
            ("validation", validation, 1),
        ] {
            if got < needed {
                return Err(EstimateError::TooFewCalibrationSamples {
                    samples: n,
                    split,
                    got,
                    needed,
                });
            }
        }
        let mut indices: Vec<usize> = (0..n).collect();
        if fractions.order == SplitOrder::Random {
            indices.shuffle(rng);
        }
        let test = indices.split_off(train + validation);
        let validation = indices.split_off(train);
        Ok(Split {
            train: indices,
            validation,
            test,
        })
    }
}

/// How a data set is split: training and validation fractions; the test split is the rest.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SplitFractions {
    /// Fraction of the samples to train on, in `(0, 1]` (default `0.7`).
    pub train: f64,
    /// Fraction for validation (early stopping), in `(0, 1]`, with `train + validation ≤ 1`
    /// (default `0.15`).
    pub validation: f64,
    /// How samples are assigned to the splits (default [`SplitOrder::Random`]; weight files
    /// without this setting read as random, and a random order is not written).
    #[serde(default, skip_serializing_if = "SplitOrder::is_random")]
    pub order: SplitOrder,
}

impl Default for SplitFractions {
    fn default() -> Self {
        Self {
            train: 0.7,
            validation: 0.15,
            order: SplitOrder::Random,
        }
    }
}

/// How a data set is split into training, validation and test samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SplitOrder {
    /// A seeded random partition: right for independent samples, such as the simulator's
    /// re-placed wire with a fresh sensor each time.
    #[default]
    Random,
    /// Blocks of time, in the samples' order: training first, then validation, then test.
    /// Right for a recording, whose sensor drifts: a random split puts neighbours in time on
    /// both sides and hides the drift; this one tests the map as it will be used, later.
    Time,
}

impl SplitOrder {
    /// Whether this is [`SplitOrder::Random`].
    pub fn is_random(&self) -> bool {
        *self == Self::Random
    }
}

impl SplitFractions {
    /// Checks the ranges documented on the fields.
    fn validate(&self) -> Result<(), EstimateError> {
        for (field, value) in [
            ("split.train", self.train),
            ("split.validation", self.validation),
        ] {
            if !(value > 0.0 && value <= 1.0) {
                return Err(EstimateError::InvalidSetting {
                    field,
                    value,
                    allowed: "a fraction in (0, 1]",
                });
            }
        }
        let total = self.train + self.validation;
        if total > 1.0 + 1e-12 {
            return Err(EstimateError::InvalidSetting {
                field: "split.train + split.validation",
                value: total,
                allowed: "at most 1 (the test split takes the rest)",
            });
        }
        Ok(())
    }
}

/// Sample indices of the three splits (disjoint, together every sample once).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Split {
    /// Indices to train on.
    pub train: Vec<usize>,
    /// Indices for early stopping.
    pub validation: Vec<usize>,
    /// Indices held out for the final evaluation (may be empty).
    pub test: Vec<usize>,
}
