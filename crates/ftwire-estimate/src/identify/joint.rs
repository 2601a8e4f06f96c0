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
    let path = match fine.shared(noise) {
        Some(shared) => {
            let shared = SharedBias {
                own: Some(noise.wrench_covariance()),
                ..shared
            };
            let prior = shared.prior();
            Path::Shared { shared, prior }
        }
        None => Path::Own(noise.wrench_covariance()),
    };
    polish_on(fine, start, noise, refine, (lower, upper), &path)
}

/// [`polish`] on the path's prior `path`.
fn polish_on<M: WireModel>(
    fine: &Residuals<'_, M>,
    start: &[f64],
    noise: &MeasurementNoise,
    refine: &LevenbergMarquardt,
    (lower, upper): (&[f64], &[f64]),
    path: &Path,
) -> Option<JointFit> {
    let n = fine.len() / 6;
    let n = match path {
        Path::Shared { shared, .. } => shared.len(),
        Path::Own(_) => n,
    };
    let original = fine.samples.get(..n)?;
    // The samples' own noise is in the path; what is left per sample is the pose's.
    let w = fine.weights.matrix();
    let pose = w * noise.pose_covariance() * w.transpose();
    let objective = Objective::new(fine, original, path, &pose)?;
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
        let cholesky = path.covariance(&wj, &pose)?;
        // o = G β̂ = −W J β̂, blockwise.
        let mut offset = DVector::zeros(6 * n);
        for (i, j) in wj.iter().enumerate() {
            let b: Vector6<f64> = beta.fixed_rows::<6>(6 * i).into_owned();
            offset.fixed_rows_mut::<6>(6 * i).copy_from(&(-(j * b)));
        }
        let whitening = cholesky.whitening(offset.clone())?;
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
        let next = path.prior_times(&gty);
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
    prior: Prior,
    pose: nalgebra::Cholesky<f64, nalgebra::Const<6>>,
}

/// The path's prior `K`: what the samples share with each sample's own noise (dense
/// `6N × 6N`), or each sample's own noise alone (`K = blockdiag(Σ_a)`, when nothing is shared:
/// every product and solve then block by block, linear in the samples).
#[allow(clippy::large_enum_variant)] // one per fit
enum Path {
    /// `K` with the shared terms, and their model.
    Shared {
        shared: SharedBias,
        prior: DMatrix<f64>,
    },
    /// `Σ_a`, each sample's own noise.
    Own(Matrix6<f64>),
}

/// The Cholesky factor of `K` as [`Objective`] uses it.
#[allow(clippy::large_enum_variant)] // one per fit
enum Prior {
    Shared(nalgebra::Cholesky<f64, nalgebra::Dyn>),
    Own(nalgebra::Cholesky<f64, nalgebra::Const<6>>),
}

/// The Cholesky factor of `C = R + G K Gᵀ`, dense or per sample.
enum Covariance {
    Shared(nalgebra::Cholesky<f64, nalgebra::Dyn>),
    Own(Vec<nalgebra::Cholesky<f64, nalgebra::Const<6>>>),
}

impl Path {
    /// `C = R + G K Gᵀ` from each sample's `W J_i` (`wj`) and the pose covariance, factored;
    /// `None` when it is not positive definite.
    fn covariance(&self, wj: &[Matrix6<f64>], pose: &Matrix6<f64>) -> Option<Covariance> {
        match self {
            Self::Shared { shared, .. } => {
                let own = vec![*pose; wj.len()];
                shared
                    .covariance(wj, &own)
                    .cholesky()
                    .map(Covariance::Shared)
            }
            Self::Own(sigma) => wj
                .iter()
                .map(|j| (pose + j * sigma * j.transpose()).cholesky())
                .collect::<Option<Vec<_>>>()
                .map(Covariance::Own),
        }
    }

    /// `K x`.
    fn prior_times(&self, x: &DVector<f64>) -> DVector<f64> {
        match self {
            Self::Shared { prior, .. } => prior * x,
            Self::Own(sigma) => blockwise(x, |b| sigma * b),
        }
    }
}

impl Covariance {
    /// The whitening `L⁻¹ (r + offset)`.
    fn whitening(&self, offset: DVector<f64>) -> Option<Whitening> {
        Some(match self {
            Self::Shared(c) => Whitening::Joint {
                factor: c.l(),
                offset,
            },
            Self::Own(blocks) => Whitening::BlocksOffset {
                inverse: blocks
                    .iter()
                    .map(|c| c.l().try_inverse())
                    .collect::<Option<Vec<_>>>()?,
                offset,
            },
        })
    }

    /// `C⁻¹ z`.
    fn solve(&self, z: &DVector<f64>) -> DVector<f64> {
        match self {
            Self::Shared(c) => c.solve(z),
            Self::Own(blocks) => {
                let mut i = 0;
                blockwise(z, |b| {
                    let y = blocks.get(i).map_or(b, |c| c.solve(&b));
                    i += 1;
                    y
                })
            }
        }
    }
}

/// `x` with each block of 6 replaced by `f` of it, in order.
fn blockwise(x: &DVector<f64>, mut f: impl FnMut(Vector6<f64>) -> Vector6<f64>) -> DVector<f64> {
    let mut out = x.clone();
    for i in 0..x.len() / 6 {
        let b: Vector6<f64> = x.fixed_rows::<6>(6 * i).into_owned();
        out.fixed_rows_mut::<6>(6 * i).copy_from(&f(b));
    }
    out
}

impl<'a, 'm, M: WireModel> Objective<'a, 'm, M> {
    /// `None` when `K` or `P` is not positive definite.
    fn new(
        fine: &'a Residuals<'m, M>,
        original: &'a [Sample],
        path: &Path,
        pose: &Matrix6<f64>,
    ) -> Option<Self> {
        let prior = match path {
            Path::Shared { prior, .. } => Prior::Shared(prior.clone().cholesky()?),
            Path::Own(sigma) => Prior::Own(sigma.cholesky()?),
        };
        Some(Self {
            fine,
            original,
            prior,
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
        let prior = match &self.prior {
            Prior::Shared(k) => beta.dot(&k.solve(beta)),
            Prior::Own(sigma) => beta.dot(&blockwise(beta, |b| sigma.solve(&b))),
        };
        pose + prior
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identify::{ParameterConstraints, Weights};
    use crate::{KirchhoffModel, WireModel};
    use ftwire_core::WireParams;

    /// The absolute form's residuals of `samples`, unwhitened.
    fn absolute_residuals<'a>(
        model: &'a KirchhoffModel,
        samples: &'a [Sample],
        constraints: ParameterConstraints,
    ) -> Residuals<'a, KirchhoffModel> {
        Residuals {
            model,
            samples,
            form: ResidualForm::Absolute,
            weights: Weights {
                length_scale: 0.5,
                tangent_rotation: 1.0,
            },
            constraints,
            whitening: None,
        }
    }

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
        let residuals = absolute_residuals(&model, &samples, constraints);
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

    /// With nothing shared between the samples, the joint fit block by block (linear in the
    /// samples) is the dense one (`6N × 6N`) to rounding.
    #[test]
    fn the_block_fit_is_the_dense_fit_when_nothing_is_shared() {
        let wire = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid wire");
        let model = KirchhoffModel::new(wire);
        let base = [
            Vector6::new(0.0, 0.02, 0.01, -0.05, 0.03, 0.0),
            Vector6::new(0.005, -0.01, 0.015, 0.02, -0.04, 0.01),
            Vector6::new(-0.004, 0.012, -0.008, 0.06, 0.02, -0.02),
            Vector6::new(0.002, 0.018, 0.004, -0.02, 0.05, 0.015),
        ];
        // Noisy readings of exact poses.
        let samples: Vec<Sample> = (0..12)
            .map(|k| {
                let a = base[k % 4] * (1.0 + 0.01 * (k as f64));
                let b = model.tip(&a).expect("solvable");
                let wiggle = Vector6::from_fn(|i, _| 1e-4 * (((7 * k + 3 * i) % 5) as f64 - 2.0));
                Sample {
                    a: a + wiggle,
                    b,
                    time: None,
                }
            })
            .collect();
        let constraints = ParameterConstraints::default();
        let fine = absolute_residuals(&model, &samples, constraints);
        let noise = MeasurementNoise::default();
        assert!(fine.shared(&noise).is_none(), "nothing is shared");
        let start = constraints.theta([0.05, 0.06, 0.05], 0.62, 0.0);
        let (lower, upper) = constraints.bounds(0.5);
        let refine = LevenbergMarquardt::default();
        let own = noise.wrench_covariance();
        let dense = Path::Shared {
            shared: SharedBias {
                bias: None,
                gain: (Vector6::zeros(), samples.iter().map(|s| s.a).collect()),
                own: Some(own),
            },
            prior: SharedBias {
                bias: None,
                gain: (Vector6::zeros(), samples.iter().map(|s| s.a).collect()),
                own: Some(own),
            }
            .prior(),
        };
        let bounds = (&lower[..], &upper[..]);
        let blocks = polish_on(&fine, &start, &noise, &refine, bounds, &Path::Own(own))
            .expect("the block fit");
        let full =
            polish_on(&fine, &start, &noise, &refine, bounds, &dense).expect("the dense fit");
        let moved = blocks
            .refined
            .theta
            .iter()
            .zip(&start)
            .map(|(t, s)| (t - s).abs())
            .fold(0.0, f64::max);
        assert!(moved > 1e-3, "the fit moved θ by {moved} only");
        for (b, d) in blocks.refined.theta.iter().zip(&full.refined.theta) {
            assert!((b - d).abs() <= 1e-9 * d.abs().max(1.0), "{b} vs {d}");
        }
        assert!(
            (blocks.objective - full.objective).abs() <= 1e-9 * full.objective.abs().max(1.0),
            "{} vs {}",
            blocks.objective,
            full.objective
        );
        assert!(
            (blocks.refined.cost - full.refined.cost).abs() <= 1e-9 * full.refined.cost.max(1.0)
        );
    }
}
