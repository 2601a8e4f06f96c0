//! The residuals whose sum of squares identification minimises (paper §III-B, eq. 12, and
//! exact forms without its linearisation).
//!
//! # Forms
//! - [`ResidualForm::Absolute`] (default): for each sample, the body twist
//!   `r_i = log(Γ_η(ã_i)⁻¹ b̃_i)` (SE(3) log, angular first): how far the second gripper's
//!   measured pose is from the pose the model predicts from the measured wrench. Exact: zero at
//!   the true `η` without noise. 6 equations per sample.
//! - [`ResidualForm::Eq12`]: the paper's baseline, eq. 12: for consecutive samples,
//!   `r_i = J_η(ã_i) δã_i − δb̃_i` with `δã_i = ã_(i+1) − ã_i` and `δb̃_i` from eq. 9–10
//!   ([`ftwire_rod::perturbation::delta_b`]). Its first-order model `δb ≈ J(L) δa` (eq. 11)
//!   is not exact, which limits it to a few per cent even without noise. 6 equations per pair.
//! - [`ResidualForm::Midpoint`]: eq. 12 with the Jacobian at the midpoint,
//!   `J_η((ã_i + ã_(i+1))/2) δã_i − δb̃_i`: second-order accurate in the step.
//! - [`ResidualForm::Relative`]: the exact relative poses,
//!   `log(Γ_η(ã_i)⁻¹ Γ_η(ã_(i+1))) − log(b̃_i⁻¹ b̃_(i+1))`: no linearisation, but only
//!   differences of poses, like eq. 12.
//!
//! Only the absolute form reaches the noise floor; the forms' errors on the nitinol wires are
//! in `DESIGN.md`.
//!
//! # Weighting
//! Each residual is a twist `(δω [rad], δx [m])`. The translation is divided by a **fixed**
//! reference length `ℓ` ([`Weights::length_scale`]; by default the distance between the
//! grippers in the first sample, `|p(b̃_1)|`), the rotation is left in radians:
//! - units: both halves become dimensionless, so their squares can be added;
//! - comparison: an orientation error `δθ` of the second gripper moves a point at distance `ℓ`
//!   by `ℓ δθ`, so after weighting 1 mm and `1 mm/ℓ` rad count the same; with `ℓ = 0.6 m`,
//!   1° (17.5 mrad) weighs as much as 10.5 mm;
//! - conditioning: the weighted residual of a wire bent on the scale of its length has
//!   rotation and translation parts of the same order, so neither half swamps the other;
//! - fixed, not the current `L`: dividing by the candidate `L` would make the cost fall as `L`
//!   grows, biasing the estimate towards long wires and making the objective no longer a
//!   least-squares fit of the data.
//!
//! # Whitening: the final polish weights by the noise
//! The fixed weighting above is a good cost for the search, but it is not the noise's: the
//! measured wrench `ã` is noisier than the commanded pose `b̃`, and `J(L)` maps its noise into
//! pose residuals that are large along some directions and tiny along others. Once the search
//! has found the basin, the driver polishes the estimate on the **whitened** residuals
//! `L_i⁻¹ W r_i`, with `L_i L_iᵀ = W Σ_i W` the residual's covariance that the [`MeasurementNoise`]
//! predicts (`Σ_i = Σ_b + J_i Σ_a J_iᵀ`, `J_i = J_η(ã_i)` frozen at the polish's start):
//! generalised least squares, the maximum-likelihood fit for Gaussian noise, whose cost is
//! the `χ²` the fit is judged by ([`Residuals::chi_squared`]), and it lowers the error of
//! estimates from few samples.
//!
//! A residual that cannot be evaluated (the model fails for this `η`, e.g. it diverges) is
//! [`PENALTY`] in each of its components, never NaN, so the optimisers see a large finite cost.

use ftwire_core::Pose;
use ftwire_rod::{perturbation::delta_b, se3, to_normalised};
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

use super::shared::{SharedBias, shared_bias};
use super::{MeasurementNoise, ParameterConstraints, Sample};
use crate::{EstimateError, WireModel};

/// The value of each component of a residual that cannot be evaluated: larger than any
/// attainable weighted residual (rotations are at most π, weighted translations at most
/// `2 L_max / ℓ`, 80 for `ℓ` = 5 cm).
pub const PENALTY: f64 = 1e3;

/// The largest load, in normalised units of the candidate wire (`|τ| L/c2`, `|f| L²/c2`,
/// largest component), that a residual is evaluated at; beyond it the sample's residual is
/// [`PENALTY`] without a solve. A normalised torque of 100 bends the wire through about 100 rad
/// (16 turns): never a held wire on a stable branch (the project samples `A_stable` in
/// `[−30, 30]⁶`). The model's step count grows with the load, so without the cap the swarm's
/// particles at tiny stiffnesses cost a hundred times more than the rest.
pub const MAX_NORMALISED_LOAD: f64 = 100.0;

/// Which residual identification minimises (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum ResidualForm {
    /// `log(Γ_η(ã_i)⁻¹ b̃_i)`: exact; the default.
    #[default]
    Absolute,
    /// The paper's eq. 12, `J_η(ã_i) δã_i − δb̃_i`: limited by its linearisation.
    Eq12,
    /// Eq. 12 with `J` at the midpoint of each step.
    Midpoint,
    /// Exact relative poses of consecutive samples.
    Relative,
}

impl ResidualForm {
    /// The form's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Absolute => "absolute",
            Self::Eq12 => "eq. 12",
            Self::Midpoint => "midpoint eq. 12",
            Self::Relative => "relative",
        }
    }

    /// The number of scalar equations `m` samples give.
    pub fn equations(self, samples: usize) -> usize {
        match self {
            Self::Absolute => 6 * samples,
            Self::Eq12 | Self::Midpoint | Self::Relative => 6 * samples.saturating_sub(1),
        }
    }
}

/// The weighting of a twist residual: rotation in radians, translation divided by a fixed
/// length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weights {
    /// `ℓ` \[m\]: the translation part of each residual is divided by it.
    pub length_scale: f64,
    /// The factor on the rotation about the second gripper's x axis (the wire's tangent at
    /// the tip), `1` by default. The swarm's coarse search uses `0`: that component is what
    /// the torsional stiffness sets, and leaving it out makes the coarse cost nearly
    /// independent of the torsion ratio, so the swarm's 3-D search is a 2-D one in effect.
    pub tangent_rotation: f64,
}

impl Weights {
    /// `W ξ` for a twist `ξ = (δω, δx)`.
    pub fn apply(&self, xi: &Vector6<f64>) -> Vector6<f64> {
        let s = 1.0 / self.length_scale;
        let t = self.tangent_rotation;
        Vector6::new(t * xi[0], xi[1], xi[2], s * xi[3], s * xi[4], s * xi[5])
    }

    /// `W` as a matrix.
    pub fn matrix(&self) -> Matrix6<f64> {
        let s = 1.0 / self.length_scale;
        let t = self.tangent_rotation;
        Matrix6::from_diagonal(&Vector6::new(t, 1.0, 1.0, s, s, s))
    }
}

/// The stacked residual of a set of samples as a function of the search vector `θ` (see
/// [`super::parameters`]).
#[derive(Debug, Clone, Copy)]
pub struct Residuals<'a, M: WireModel> {
    /// The model family; its `with_wire` gives the model at each `η`.
    pub model: &'a M,
    /// The samples.
    pub samples: &'a [Sample],
    /// The residual form.
    pub form: ResidualForm,
    /// The weighting.
    pub weights: Weights,
    /// How `θ` maps to `η`.
    pub constraints: ParameterConstraints,
    /// The whitening applied after [`Residuals::weights`] (see the module docs), or `None` for
    /// the weighting alone.
    pub whitening: Option<&'a Whitening>,
}

/// How the stacked residual is whitened after the weighting (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub enum Whitening {
    /// Independent samples: `L_i⁻¹` for each residual block, `L_i L_iᵀ` the block's
    /// covariance.
    Blocks(Vec<Matrix6<f64>>),
    /// Samples that share the sensor's bias ([`super::BiasDrift`]): the lower Cholesky factor
    /// `factor` (`L`) of the stacked residual's covariance, and a constant `offset` (`o`); the
    /// whitened residual is `L⁻¹ (r + o)` (see [`super::joint`]).
    Joint {
        /// `L`, lower triangular.
        factor: DMatrix<f64>,
        /// `o`, one entry per scalar residual.
        offset: DVector<f64>,
    },
    /// [`Whitening::Joint`] when nothing is shared between samples (the stacked covariance is
    /// block diagonal): `L_i⁻¹ (r_i + o_i)` per sample, in time and memory linear in the
    /// samples.
    BlocksOffset {
        /// `L_i⁻¹` of each block.
        inverse: Vec<Matrix6<f64>>,
        /// `o`, one entry per scalar residual.
        offset: DVector<f64>,
    },
}

impl<M: WireModel> Residuals<'_, M> {
    /// The number of scalar residuals.
    pub fn len(&self) -> usize {
        self.form.equations(self.samples.len())
    }

    /// Whether there are no residuals.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// What the samples share under `noise` ([`shared_bias`]), for the absolute form only.
    pub(super) fn shared(&self, noise: &MeasurementNoise) -> Option<SharedBias> {
        if self.form != ResidualForm::Absolute {
            return None;
        }
        shared_bias(self.samples.get(..self.len() / 6)?, noise)
    }

    /// The model at `θ`, or `None` if `θ` maps to an invalid `η`.
    pub fn model_at(&self, theta: &[f64]) -> Option<M> {
        self.try_model_at(theta).ok()
    }

    /// The model at `θ`: its stiffnesses and length, and its weight `λ g` when the linear
    /// density is identified ([`ParameterConstraints::weight`]).
    ///
    /// # Errors
    /// When `θ` maps to an invalid `η` or weight.
    pub fn try_model_at(&self, theta: &[f64]) -> Result<M, EstimateError> {
        let (c, length) = self.constraints.eta(theta);
        let model = self
            .model
            .with_wire(self.model.wire().with_c(c)?.with_length(length)?);
        match (
            self.constraints.weight,
            self.constraints.linear_density(theta),
        ) {
            (Some(g), Some(lambda)) => model.with_weight_per_length(lambda * g),
            _ => Ok(model),
        }
    }

    /// The stacked weighted residual at `θ`; failed evaluations are [`PENALTY`].
    pub fn evaluate(&self, theta: &[f64]) -> DVector<f64> {
        let mut r = DVector::from_element(self.len(), PENALTY);
        let Some(model) = self.model_at(theta) else {
            return r;
        };
        for (i, ri) in self.each(&model).enumerate() {
            if let Some(ri) = ri.filter(|v| v.iter().all(|x| x.is_finite())) {
                r.fixed_rows_mut::<6>(6 * i).copy_from(&ri);
            }
        }
        match self.whitening {
            Some(Whitening::Joint { factor, offset }) if offset.len() == r.len() => {
                let shifted = r + offset;
                factor.solve_lower_triangular(&shifted).unwrap_or(shifted)
            }
            Some(Whitening::BlocksOffset { inverse, offset }) if offset.len() == r.len() => {
                let mut shifted = r + offset;
                for (i, w) in inverse.iter().enumerate() {
                    let block: Vector6<f64> = shifted.fixed_rows::<6>(6 * i).into_owned();
                    shifted.fixed_rows_mut::<6>(6 * i).copy_from(&(w * block));
                }
                shifted
            }
            _ => r,
        }
    }

    /// `Σ‖r_i‖²` at `θ`.
    pub fn cost(&self, theta: &[f64]) -> f64 {
        self.evaluate(theta).norm_squared()
    }

    /// The weighted residual blocks of `model`, `None` where the model fails.
    fn each<'s>(&'s self, model: &'s M) -> impl Iterator<Item = Option<Vector6<f64>>> + 's {
        let n = self.len() / 6;
        (0..n).map(move |i| {
            let raw = match self.form {
                ResidualForm::Absolute => {
                    let s = self.samples.get(i).filter(|s| within_load(model, s))?;
                    absolute(&model.tip(&s.a).ok()?, &s.b)
                }
                ResidualForm::Eq12 => {
                    let s = self.samples.get(i).filter(|s| within_load(model, s))?;
                    let next = self.samples.get(i + 1)?;
                    let j = model.jacobian(&s.a).ok()?.jacobian;
                    j * (next.a - s.a) - delta_b(&s.b, &next.b)
                }
                ResidualForm::Midpoint => {
                    let s = self.samples.get(i).filter(|s| within_load(model, s))?;
                    let next = self.samples.get(i + 1)?;
                    let j = model.jacobian(&(0.5 * (s.a + next.a))).ok()?.jacobian;
                    j * (next.a - s.a) - delta_b(&s.b, &next.b)
                }
                ResidualForm::Relative => {
                    let s = self.samples.get(i).filter(|s| within_load(model, s))?;
                    let next = self.samples.get(i + 1).filter(|s| within_load(model, s))?;
                    let (gi, gn) = (model.tip(&s.a).ok()?, model.tip(&next.a).ok()?);
                    se3::log(&(gi.inverse() * gn)) - se3::log(&(s.b.inverse() * next.b))
                }
            };
            let weighted = self.weights.apply(&raw);
            Some(match self.whitening {
                Some(Whitening::Blocks(blocks)) => blocks.get(i).map_or(weighted, |w| w * weighted),
                _ => weighted,
            })
        })
    }

    /// The whitening at `θ` (see the module docs): per sample, `L_i⁻¹` with `L_i L_iᵀ =
    /// W Σ_i W` the covariance of the weighted residual `i` that `noise` predicts to first
    /// order (`Σ_b + J Σ_a Jᵀ` for the absolute form, twice both terms for the differential
    /// forms, with `J` at the first sample of each pair); or, for the absolute form with a bias
    /// model ([`MeasurementNoise::bias`]) and every sample's time known, or a gain error
    /// ([`MeasurementNoise::gain`]), the Cholesky factor of the stacked covariance with the
    /// shared cross terms `W J_i K_ij J_jᵀ W` ([`super::drift`], `identify/joint.rs`).
    ///
    /// # Errors
    /// The model's error if it cannot be solved at `θ` or at a sample;
    /// [`EstimateError::BadIdentifySetting`] for a covariance that is not positive definite
    /// (never for a valid [`MeasurementNoise`]).
    pub fn whitening(
        &self,
        theta: &[f64],
        noise: &MeasurementNoise,
    ) -> Result<Whitening, EstimateError> {
        let (wj, own) = self.block_covariances(theta, noise)?;
        let n = own.len();
        if let Some(joint) = self.shared(noise) {
            let cov = joint.covariance(&wj, &own);
            let smallest = cov.diagonal().min();
            let factor = cov.cholesky().ok_or_else(|| not_positive(smallest))?.l();
            let offset = DVector::zeros(6 * n);
            return Ok(Whitening::Joint { factor, offset });
        }
        own.into_iter()
            .map(|cov| {
                let l = cov.cholesky().ok_or_else(|| not_positive(cov.min()))?.l();
                l.try_inverse()
                    .ok_or_else(|| not_positive(l.diagonal().min()))
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Whitening::Blocks)
    }

    /// Each sample's `W J_i` and its own residual covariance `W (Σ_b + J_i Σ_a J_iᵀ) W` (twice
    /// for the differential forms) at `θ`.
    ///
    /// # Errors
    /// The model's error if it cannot be solved at `θ` or at a sample.
    pub(super) fn block_covariances(
        &self,
        theta: &[f64],
        noise: &MeasurementNoise,
    ) -> Result<BlockCovariances, EstimateError> {
        let model = self.try_model_at(theta)?;
        let w = self.weights.matrix();
        let (sigma_b, sigma_a) = (noise.pose_covariance(), noise.wrench_covariance());
        let factor = match self.form {
            ResidualForm::Absolute => 1.0,
            ResidualForm::Eq12 | ResidualForm::Midpoint | ResidualForm::Relative => 2.0,
        };
        let n = self.len() / 6;
        let wj = self
            .samples
            .iter()
            .take(n)
            .map(|s| Ok(w * model.jacobian(&s.a)?.jacobian))
            .collect::<Result<Vec<Matrix6<f64>>, EstimateError>>()?;
        let own: Vec<Matrix6<f64>> = wj
            .iter()
            .map(|j| factor * (w * sigma_b * w + j * sigma_a * j.transpose()))
            .collect();
        Ok((wj, own))
    }

    /// The noise-normalised cost `χ² = Σ r_iᵀ Σ_i⁻¹ r_i` at `θ`, where `Σ_i` is the covariance
    /// of `r_i` that `noise` predicts (to first order: `W (Σ_b + J Σ_a Jᵀ) W` for the absolute
    /// form, twice both terms for the differential forms, with `J` at the first sample of
    /// each pair).
    ///
    /// # Errors
    /// The model's error if it cannot be solved at `θ` or at a sample.
    pub fn chi_squared(
        &self,
        theta: &[f64],
        noise: &MeasurementNoise,
    ) -> Result<f64, EstimateError> {
        let whitening = self.whitening(theta, noise)?;
        let whitened = Residuals {
            whitening: Some(&whitening),
            ..*self
        };
        Ok(whitened.cost(theta))
    }
}

/// Each sample's `W J_i` and its own residual covariance ([`Residuals::block_covariances`]).
pub(super) type BlockCovariances = (Vec<Matrix6<f64>>, Vec<Matrix6<f64>>);

/// The error of a residual covariance that is not positive definite.
fn not_positive(value: f64) -> EstimateError {
    EstimateError::BadIdentifySetting {
        field: "noise",
        value,
        allowed: "a positive definite residual covariance",
    }
}

/// Whether the sample's load is at most [`MAX_NORMALISED_LOAD`] for `model`'s wire.
fn within_load<M: WireModel>(model: &M, sample: &Sample) -> bool {
    to_normalised(model.wire(), &sample.a).amax() <= MAX_NORMALISED_LOAD
}

/// `log(Γ⁻¹ b)`: the body twist from the predicted to the measured pose.
fn absolute(predicted: &Pose, measured: &Pose) -> Vector6<f64> {
    se3::log(&(predicted.inverse() * measured))
}
