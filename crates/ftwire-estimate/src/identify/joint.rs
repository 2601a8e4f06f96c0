//! The final fit with what the samples share estimated with the wire: the sensor's bias
//! ([`super::drift`]) and the map's gain error ([`MeasurementNoise::gain`]), and each rest's own
//! noise.
//!
//! The unknowns are `η` and the path `β_1 … β_N` of the samples (the bias, plus
//! `diag(ã_i) γ` for a gain error `γ ~ N(0, diag(g)²)` common to all, plus each rest's own
//! noise `w_i ~ N(0, Σ_a)`); the data are the pose equations `Γ_η(ã_i − β_i) = b̃_i` (up to the
//! pose noise `Σ_b`) and the path's prior `β ~ N(0, K)`,
//! `K_ij = Cov(β(t_i), β(t_j)) + diag(g)² diag(ã_i) diag(ã_j) + δ_ij Σ_a`. Gauss–Newton on all
//! of them, with `β` eliminated at each outer iteration:
//!
//! 1. linearise at the current path estimate `β̂`: the residual of the shifted samples
//!    `ã_i − β̂_i` is `r(η, β) ≈ r(η, β̂) − G (β − β̂)`, with `G = blockdiag(−W J_i)` the
//!    residual's derivative in the sample's `a` (`J_i = J_η(ã_i − β̂_i)`);
//! 2. with `z(η) = r(η, β̂) + G β̂ = G β + pose noise`, `β` marginalises out: minimise
//!    `z(η)ᵀ C⁻¹ z(η)`, `C = R + G K Gᵀ` (`R = W Σ_b W` per sample), by Levenberg–Marquardt
//!    on the whitened `L⁻¹ z` ([`super::Whitening::Joint`], `L Lᵀ = C`);
//! 3. the path's new estimate is its posterior mean, `β̂ = K Gᵀ C⁻¹ z(η̂)`.
//!
//! The first iteration, from `β̂ = 0`, is the generalised least-squares fit linearised at the
//! measured `ã_i`. Later ones linearise at the estimated true `a_i = ã_i − β̂_i`: on a soft wire
//! a rest's noise is several per cent of its force scale, and `Γ` is not linear over that
//! distance, so a fit linearised at the noisy `ã_i` is biased by an amount more samples do not
//! average away (errors in the variables). Each outer iteration must lower the negative
//! log-likelihood `F(θ, β)` ([`Objective`]), or the iterations end at the last that did.
//! Above [`CONTINUATION_ABOVE`] samples the fit is also continued in the samples from the
//! fits of fewer ([`polish_continued`]). The final `χ²` is `z(η̂)ᵀ C⁻¹ z(η̂)`, and the whitened
//! Jacobian's `(JᵀJ)⁻¹` the covariance of `η` with the path marginalised.

use std::cmp::Ordering;

use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

use super::refine::Refined;
use super::shared::SharedBias;
use super::{LevenbergMarquardt, MeasurementNoise, ResidualForm, Residuals, Sample, Whitening};
use crate::WireModel;

/// Outer (relinearisation) iterations at most.
const OUTER_ITERATIONS: usize = 4;

/// Relative change of `θ` (largest component) below which the outer iterations stop.
const THETA_TOLERANCE: f64 = 1e-7;

/// The search's weights under a shared bias: each sample's residual scaled by
/// `√(v₀ / (v₀ + q² k(t_i, t_i)))`, with `v₀` the force variance of a sample's own noise and
/// the tare's offset and `q²` the drift's (means over the force channels). The search's fixed
/// weighting treats every sample alike, so a late sample, whose bias has drifted for a
/// minute, would pull the swarm as hard as the first; these weights are the diagonal of the
/// shared bias's covariance, without the model's Jacobian, so the search's cost stays cheap.
/// `None` without a bias model, a sample's time or the absolute form.
pub(super) fn search_weights(
    samples: &[Sample],
    form: ResidualForm,
    noise: &MeasurementNoise,
) -> Option<Whitening> {
    let bias = noise.bias?;
    if form != ResidualForm::Absolute {
        return None;
    }
    let force = |m: &Matrix6<f64>| (3..6).map(|i| m[(i, i)]).sum::<f64>() / 3.0;
    let v0 = force(&(noise.wrench_covariance() + bias.tare));
    let q2 = force(&bias.rate);
    samples
        .iter()
        .map(|s| {
            let t = s.time?;
            let w = (v0 / (v0 + q2 * bias.kernel(t, t))).sqrt();
            Some(Matrix6::identity() * w)
        })
        .collect::<Option<Vec<_>>>()
        .map(Whitening::Blocks)
}

/// The joint fit: the polished parameters on the last linearisation and the samples shifted
/// by the bias estimate there.
#[derive(Debug, Clone)]
pub(super) struct JointFit {
    /// Levenberg–Marquardt's result on the whitened `L⁻¹ z`: its cost is the final `χ²`, its
    /// Jacobian the whitened one.
    pub refined: Refined,
    /// The samples with `ã_i − β̂_i` (the bias the last iteration linearised about).
    pub samples: Vec<Sample>,
    /// Levenberg–Marquardt's residual evaluations over all iterations.
    pub evaluations: usize,
    /// The objective `F(θ̂, β̂)` ([`Objective`]) there: comparable between fits of the same
    /// samples from different starts.
    pub objective: f64,
}

/// The joint fit from `start` (see the module docs), or `None` for a form other than the
/// absolute one, or when a linearisation cannot be computed (the model fails at a sample).
pub(super) fn polish<M: WireModel>(
    fine: &Residuals<'_, M>,
    start: &[f64],
    noise: &MeasurementNoise,
    refine: &LevenbergMarquardt,
    (lower, upper): (&[f64], &[f64]),
) -> Option<JointFit> {
    if fine.form != ResidualForm::Absolute {
        return None;
    }
    let n = fine.len() / 6;
    let shared = SharedBias {
        own: Some(noise.wrench_covariance()),
        ..fine.shared(noise).unwrap_or_else(|| SharedBias {
            bias: None,
            gain: (
                Vector6::zeros(),
                fine.samples.iter().take(n).map(|s| s.a).collect(),
            ),
            own: None,
        })
    };
    let n = shared.len();
    let k = shared.prior();
    let original = fine.samples.get(..n)?;
    // The samples' own noise is in the path; what is left per sample is the pose's.
    let w = fine.weights.matrix();
    let pose = w * noise.pose_covariance() * w.transpose();
    let objective = Objective::new(fine, original, &k, &pose)?;
    let mut beta = DVector::zeros(6 * n);
    let mut theta = start.to_vec();
    let mut fit: Option<JointFit> = None;
    let mut evaluations = 0;
    let mut last_cost = None;
    for _ in 0..OUTER_ITERATIONS {
        let samples = shifted_by(original, &beta);
        let shifted = Residuals {
            samples: &samples,
            whitening: None,
            ..*fine
        };
        let (wj, _) = shifted.block_covariances(&theta, noise).ok()?;
        let own = vec![pose; wj.len()];
        let cholesky = shared.covariance(&wj, &own).cholesky()?;
        // o = G β̂ = −W J β̂, blockwise.
        let mut offset = DVector::zeros(6 * n);
        for (i, j) in wj.iter().enumerate() {
            let b: Vector6<f64> = beta.fixed_rows::<6>(6 * i).into_owned();
            offset.fixed_rows_mut::<6>(6 * i).copy_from(&(-(j * b)));
        }
        let whitening = Whitening::Joint {
            factor: cholesky.l(),
            offset: offset.clone(),
        };
        let whitened = Residuals {
            whitening: Some(&whitening),
            ..shifted
        };
        let refined = refine.minimise(&|t: &[f64]| whitened.evaluate(t), &theta, lower, upper);
        evaluations += refined.evaluations;
        // β̂ = K Gᵀ C⁻¹ z at the new θ.
        let z = shifted.evaluate(&refined.theta) + &offset;
        let y = cholesky.solve(&z);
        let mut gty = DVector::zeros(6 * n);
        for (i, j) in wj.iter().enumerate() {
            let yi: Vector6<f64> = y.fixed_rows::<6>(6 * i).into_owned();
            gty.fixed_rows_mut::<6>(6 * i)
                .copy_from(&(-(j.transpose() * yi)));
        }
        let change = refined
            .theta
            .iter()
            .zip(&theta)
            .map(|(new, old)| (new - old).abs() / old.abs().max(1.0))
            .fold(0.0, f64::max);
        let next = &k * gty;
        // Gauss–Newton on `F` is undamped: an iteration that does not lower it (a
        // linearisation too far from the estimate, on a soft wire's large relative noise)
        // ends the iterations at the last one that did.
        let cost = objective.cost(&refined.theta, &next);
        evaluations += 1;
        if last_cost.is_some_and(|last: f64| cost.partial_cmp(&last) != Some(Ordering::Less)) {
            break;
        }
        last_cost = Some(cost);
        theta.clone_from(&refined.theta);
        fit = Some(JointFit {
            refined,
            samples,
            evaluations,
            objective: cost,
        });
        beta = next;
        if change < THETA_TOLERANCE {
            break;
        }
    }
    fit
}

/// Sample counts up to which the joint fit from the search's best alone is kept; above, it is
/// also continued from the fits of fewer samples ([`polish_continued`]).
const CONTINUATION_ABOVE: usize = 10;

/// [`polish`], and above [`CONTINUATION_ABOVE`] samples also a continuation in the samples:
/// the first `n/2^m ≥ 5`, …, `n/4`, `n/2` samples polished in turn, each from the last's
/// answer, then all `n` from there; the fit of lower objective `F` is kept. With many
/// samples whose drift is a sizeable part of the force scale the search's fixed weighting
/// leaves its best far enough from the truth that the joint fit from it can end in another
/// basin of `F`; the fit of fewer samples is closer.
pub(super) fn polish_continued<M: WireModel>(
    fine: &Residuals<'_, M>,
    start: &[f64],
    noise: &MeasurementNoise,
    refine: &LevenbergMarquardt,
    bounds: (&[f64], &[f64]),
) -> Option<JointFit> {
    let direct = polish(fine, start, noise, refine, bounds);
    let n = fine.samples.len();
    if n <= CONTINUATION_ABOVE || direct.is_none() {
        return direct;
    }
    let mut counts = Vec::new();
    let mut k = n / 2;
    while k >= 5 {
        counts.push(k);
        k /= 2;
    }
    let mut theta = start.to_vec();
    let mut evaluations = 0;
    for &k in counts.iter().rev() {
        let fewer = Residuals {
            samples: fine.samples.get(..k)?,
            ..*fine
        };
        if let Some(fit) = polish(&fewer, &theta, noise, refine, bounds) {
            evaluations += fit.evaluations;
            theta = fit.refined.theta;
        }
    }
    let continued = polish(fine, &theta, noise, refine, bounds);
    [direct, continued]
        .into_iter()
        .flatten()
        .min_by(|a, b| a.objective.total_cmp(&b.objective))
        .map(|fit| JointFit {
            evaluations: fit.evaluations + evaluations,
            ..fit
        })
}

/// The samples with `ã_i − β_i`.
fn shifted_by(samples: &[Sample], beta: &DVector<f64>) -> Vec<Sample> {
    samples
        .iter()
        .enumerate()
        .map(|(i, s)| Sample {
            a: s.a - beta.fixed_rows::<6>(6 * i),
            ..*s
        })
        .collect()
}

/// The joint fit's objective `F(θ, β) = Σ_i r_iᵀ P⁻¹ r_i + βᵀ K⁻¹ β` (the negative
/// log-likelihood up to a constant): `r_i` the weighted residual of the sample shifted to
/// `ã_i − β_i`, `P` the weighted pose covariance, `K` the path's prior.
struct Objective<'a, 'm, M: WireModel> {
    fine: &'a Residuals<'m, M>,
    original: &'a [Sample],
    prior: nalgebra::Cholesky<f64, nalgebra::Dyn>,
    pose: nalgebra::Cholesky<f64, nalgebra::Const<6>>,
}

impl<'a, 'm, M: WireModel> Objective<'a, 'm, M> {
    /// `None` when `K` or `P` is not positive definite.
    fn new(
        fine: &'a Residuals<'m, M>,
        original: &'a [Sample],
        prior: &DMatrix<f64>,
        pose: &Matrix6<f64>,
    ) -> Option<Self> {
        Some(Self {
            fine,
            original,
            prior: prior.clone().cholesky()?,
            pose: pose.cholesky()?,
        })
    }

    /// `F(θ, β)`; a sample the model cannot solve adds its residual's penalty.
    fn cost(&self, theta: &[f64], beta: &DVector<f64>) -> f64 {
        let samples = shifted_by(self.original, beta);
        let shifted = Residuals {
            samples: &samples,
            whitening: None,
            ..*self.fine
        };
        let r = shifted.evaluate(theta);
        let pose: f64 = (0..samples.len())
            .map(|i| {
                let ri: Vector6<f64> = r.fixed_rows::<6>(6 * i).into_owned();
                ri.dot(&self.pose.solve(&ri))
            })
            .sum();
        pose + beta.dot(&self.prior.solve(beta))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identify::{ParameterConstraints, Weights};
    use crate::{KirchhoffModel, WireModel};
    use ftwire_core::WireParams;

    /// The linearisation's sign: the weighted residual of a sample moves by `−W J δa` when
    /// its `a` moves by `δa`, which `G` and the offset assume.
    #[test]
    fn residual_moves_by_minus_w_j_delta_a() {
        let wire = WireParams::new([0.21, 0.28, 0.28], 0.8, 0.0015).expect("valid wire");
        let model = KirchhoffModel::new(wire);
        let a = Vector6::new(0.01, 0.03, -0.02, -0.1, 0.2, 0.05);
        let b = model.tip(&a).expect("solvable");
        let delta = Vector6::new(1e-5, -2e-5, 1e-5, 3e-5, -1e-5, 2e-5);
        let samples = [
            Sample {
                a,
                b,
                time: Some(1.0),
            },
            Sample {
                a: a + delta,
                b,
                time: Some(1.0),
            },
        ];
        let constraints = ParameterConstraints::default();
        let residuals = Residuals {
            model: &model,
            samples: &samples,
            form: ResidualForm::Absolute,
            weights: Weights {
                length_scale: 0.5,
                tangent_rotation: 1.0,
            },
            constraints,
            whitening: None,
        };
        let theta = constraints.theta(wire.c(), wire.length(), 0.0);
        let r = residuals.evaluate(&theta);
        let moved = r.fixed_rows::<6>(6) - r.fixed_rows::<6>(0);
        let (wj, _) = residuals
            .block_covariances(&theta, &MeasurementNoise::default())
            .expect("solvable");
        let predicted = -(wj[0] * delta);
        assert!(
            (moved - predicted).norm() < 1e-3 * predicted.norm(),
            "{moved} vs {predicted}"
        );
    }
}
