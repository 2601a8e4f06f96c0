//! Shape estimation at sensor rate: the calibrated F/T configuration `ã` → the wire's
//! centreline (paper §II-B, §IV-C), with a confidence flag.
//!
//! The estimate is the model's shape `Φ(ã)`. It is flagged as not confident when `ã` is not in
//! `A_stable` (the model's shape is then an equilibrium the wire cannot rest in) or when `ã`
//! jumped from the previous sample by more than a threshold in normalised units: a wire moved
//! smoothly by the grippers changes `a` gradually at sensor rate, so a jump points to a contact
//! with an obstacle or a snap (§IV-E), where the contact-free model does not hold.

use ftwire_core::ensure_finite;
use ftwire_rod::{Shape, to_normalised};
use nalgebra::Vector6;

use crate::shape::{ConfigurationStd, ModelError, setting, shape_sigma, with_model_error};
use crate::{EstimateError, WireModel};

/// Settings of the shape estimator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EstimatorParams {
    /// Shape nodes, uniformly spaced in arc length, both ends included (default `64`; at least
    /// 50 so that metrics can compare 50 arc lengths).
    pub nodes: usize,
    /// A change of `ã` from the previous sample larger than this (Euclidean norm in normalised
    /// units: torque in `c2/L`, force in `c2/L²`) is flagged as a jump (default `2.0`). The
    /// default is a starting point, not tuned: the threshold must sit above the calibrated
    /// sensor's noise and a smooth motion's change per sample, and below the change a contact
    /// causes; the collision-detection experiment should set it.
    pub jump_threshold: f64,
}

impl Default for EstimatorParams {
    fn default() -> Self {
        Self {
            nodes: 64,
            jump_threshold: 2.0,
        }
    }
}

/// Fewest shape nodes the estimator accepts.
pub const MIN_ESTIMATE_NODES: usize = 50;

/// Whether a shape estimate can be relied on, and if not why.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Confidence {
    /// `ã ∈ A_stable` and close to the previous sample.
    Confident,
    /// `ã` is not in `A_stable`. Takes precedence over a jump.
    NotStable,
    /// `ã` changed from the previous sample by `change` (normalised units), more than
    /// `threshold`: a possible contact.
    Jump {
        /// `‖z − z_prev‖` in normalised units.
        change: f64,
        /// The configured threshold.
        threshold: f64,
    },
}

impl Confidence {
    /// Whether the estimate is [`Confidence::Confident`].
    pub fn is_confident(&self) -> bool {
        matches!(self, Self::Confident)
    }
}

/// One shape estimate.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeEstimate {
    /// The estimated shape: positions \[m\] and frames at the configured nodes, base clamp
    /// frame.
    pub shape: Shape,
    /// The confidence flag.
    pub confidence: Confidence,
    /// `ã` in normalised units.
    pub normalised: Vector6<f64>,
    /// `σ(s)` \[m\] at each node of `shape`: the RMS radius of the point's first-order error
    /// ([`shape_sigma`]), with the model's own error added in quadrature when it was given
    /// ([`ShapeEstimator::with_model_error`], [`with_model_error`]); `None` unless the
    /// estimator was given the standard deviations of `ã` or the model error.
    pub sigma: Option<Vec<f64>>,
}

/// Estimates the wire's shape from each calibrated F/T configuration `ã`, and flags samples it
/// cannot trust. Keeps the last sample to measure jumps.
///
/// # Example
/// ```
/// use ftwire_core::WireParams;
/// use ftwire_estimate::KirchhoffModel;
/// use ftwire_estimate::shape::{Confidence, ShapeEstimator};
/// use nalgebra::Vector6;
/// let model = KirchhoffModel::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
/// let mut estimator = ShapeEstimator::new(model);
/// let a = Vector6::new(0.0, 0.02, 0.01, -0.05, 0.03, 0.0);
/// let estimate = estimator.estimate(&a)?;
/// assert_eq!(estimate.shape.len(), 64);
/// assert_eq!(estimate.confidence, Confidence::Confident);
/// // A sudden large change of the wrench: flagged.
/// let jumped = estimator.estimate(&(a * 10.0))?;
/// assert!(matches!(jumped.confidence, Confidence::Jump { .. }));
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeEstimator<M> {
    model: M,
    config: EstimatorParams,
    a_std: Option<ConfigurationStd>,
    model_error: Option<ModelError>,
    previous: Option<Vector6<f64>>,
}

impl<M: WireModel> ShapeEstimator<M> {
    /// An estimator with the default settings.
    #[must_use]
    pub fn new(model: M) -> Self {
        Self {
            model,
            config: EstimatorParams::default(),
            a_std: None,
            model_error: None,
            previous: None,
        }
    }

    /// The same estimator with other settings (the last sample kept).
    ///
    /// # Errors
    /// [`EstimateError::BadShapeSetting`] if `nodes < 50` or above the model's limit of
    /// 1 000 000, or the jump threshold is not finite and positive.
    pub fn with_config(self, config: EstimatorParams) -> Result<Self, EstimateError> {
        setting::count(
            "nodes",
            config.nodes,
            MIN_ESTIMATE_NODES,
            ftwire_rod::rod::MAX_NODES,
            "50 to 1000000",
        )?;
        setting::positive(
            "jump_threshold",
            config.jump_threshold,
            "finite and > 0 (normalised units)",
        )?;
        Ok(Self { config, ..self })
    }

    /// The same estimator with the standard deviations of `ã` (`None`: unknown): each
    /// estimate then carries `σ(s)` at its nodes ([`ShapeEstimate::sigma`]), at the cost of
    /// 12 more shape solves per estimate.
    #[must_use]
    pub fn with_a_std(self, a_std: Option<ConfigurationStd>) -> Self {
        Self { a_std, ..self }
    }

    /// The same estimator with the model's own error (`None`: not counted): each estimate's
    /// `σ(s)` then adds `σ_model(s) = e · s` in quadrature ([`with_model_error`]).
    #[must_use]
    pub fn with_model_error(self, model_error: Option<ModelError>) -> Self {
        Self {
            model_error,
            ..self
        }
    }

    /// The model's own error, if given.
    pub fn model_error(&self) -> Option<&ModelError> {
        self.model_error.as_ref()
    }

    /// The standard deviations of `ã`, if given.
    pub fn a_std(&self) -> Option<&ConfigurationStd> {
        self.a_std.as_ref()
    }

    /// The settings.
    pub fn config(&self) -> &EstimatorParams {
        &self.config
    }

    /// The wire model.
    pub fn model(&self) -> &M {
        &self.model
    }

    /// Forgets the last sample: the next one is not tested for a jump.
    pub fn reset(&mut self) {
        self.previous = None;
    }

    /// The shape for `ã` \[N·m, N\] (torque first, base clamp frame) and its confidence. The
    /// sample becomes the reference for the next jump test, jump or not, so that a lasting
    /// change is flagged once.
    ///
    /// # Errors
    /// [`EstimateError::Core`] naming a non-finite component of `ã` (field `a_tilde`),
    /// [`EstimateError::Model`] for `ã ∉ A` or a diverged solve (also of the shifted `ã` of
    /// [`shape_sigma`], with standard deviations given). Errors leave the last sample
    /// unchanged.
    pub fn estimate(&mut self, a_tilde: &Vector6<f64>) -> Result<ShapeEstimate, EstimateError> {
        ensure_finite("a_tilde", a_tilde.as_slice())?;
        let shape = self.model.shape(a_tilde, self.config.nodes)?;
        let stable = self.model.is_stable(a_tilde)?;
        let sigma_a = match &self.a_std {
            Some(std) => {
                Some(shape_sigma(&self.model, a_tilde, self.config.nodes, &std.covariance())?.sigma)
            }
            None => None,
        };
        let sigma = match (&self.model_error, sigma_a) {
            (Some(e), sigma_a) => {
                let sigma_a = sigma_a.unwrap_or_else(|| vec![0.0; self.config.nodes]);
                Some(with_model_error(&sigma_a, e, self.model.wire().length()))
            }
            (None, sigma_a) => sigma_a,
        };
        let confidence = self.flag_solved(a_tilde, stable);
        Ok(ShapeEstimate {
            shape,
            confidence,
            normalised: to_normalised(self.model.wire(), a_tilde),
            sigma,
        })
    }

    /// The confidence of a sample whose shape the caller solved itself, given whether
    /// `ã ∈ A_stable` (`stable`, from [`WireModel::is_stable`]): the flag and the update of the
    /// last sample that [`ShapeEstimator::estimate`] makes after its solve. This lets a caller
    /// solve many samples in parallel and flag them afterwards; give it, in order, only the
    /// samples that were solved (a failed solve leaves the last sample unchanged, as in
    /// `estimate`). Guarded by `flagging_solved_samples_is_estimating_them`.
    pub fn flag_solved(&mut self, a_tilde: &Vector6<f64>, stable: bool) -> Confidence {
        let normalised = to_normalised(self.model.wire(), a_tilde);
        let change = self.previous.map(|previous| (normalised - previous).norm());
        self.previous = Some(normalised);
        match change {
            _ if !stable => Confidence::NotStable,
            Some(change) if change > self.config.jump_threshold => Confidence::Jump {
                change,
                threshold: self.config.jump_threshold,
            },
            _ => Confidence::Confident,
        }
    }
}
