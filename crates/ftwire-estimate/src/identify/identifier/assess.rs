//! Step 4 of the driver ([`Identifier`]) and its judgement: the polish on the
//! noise-whitened residuals, and the estimate at an optimum with its uncertainty and its
//! identifiability checks.

use nalgebra::DMatrix;
use rand::Rng;

use super::Identifier;
use super::objectives::SearchSpace;
use crate::identify::refine::Refined;
use crate::identify::{Estimate, LevenbergMarquardt, ParameterCovariance, Residuals, Unidentified};
use crate::{EstimateError, WireModel};

impl<M: WireModel, R: Rng> Identifier<M, R> {
    /// Step 4 of the driver: Levenberg–Marquardt on the noise-whitened residuals from the
    /// search's best fit (generalised least squares, see [`crate::identify::residual`]; for
    /// the absolute form jointly with the samples' path,
    /// [`crate::identify::joint::polish_continued`]), and the estimate there.
    /// `None` when the whitening cannot be computed at the best fit (the model fails at a
    /// sample), or the independent-noise polish ends at a higher `χ²` (never expected: it
    /// starts from the best fit and only accepts steps that lower its cost); the caller keeps
    /// the unpolished estimate then.
    pub(super) fn polish(
        &self,
        fine: &Residuals<'_, M>,
        best: &Refined,
        space: &SearchSpace,
        evaluations: usize,
    ) -> Option<Estimate> {
        let noise = &self.config.noise;
        let bounds = (&space.lower[..], &space.upper[..]);
        let (polished, samples, chi2) = match crate::identify::joint::polish_continued(
            fine,
            &best.theta,
            noise,
            &self.config.refine,
            bounds,
        ) {
            Some(joint) => {
                let chi2 = joint.refined.cost;
                let refined = Refined {
                    evaluations: joint.evaluations,
                    ..joint.refined
                };
                (refined, joint.samples, Some(chi2))
            }
            None => {
                let whitening = fine.whitening(&best.theta, noise).ok()?;
                let whitened = Residuals {
                    whitening: Some(&whitening),
                    ..*fine
                };
                let residual = |theta: &[f64]| whitened.evaluate(theta);
                let polished =
                    self.config
                        .refine
                        .minimise(&residual, &best.theta, bounds.0, bounds.1);
                let before = fine.chi_squared(&best.theta, noise).ok()?;
                let after = fine.chi_squared(&polished.theta, noise).ok()?;
                if after > before {
                    return None;
                }
                (polished, fine.samples.to_vec(), None)
            }
        };
        // Judge the polished fit exactly as the unpolished one: the fixed weighting's cost and
        // Jacobian (its conditioning threshold is in those units), at the polished θ, on the
        // samples the polish ended with.
        let fine = Residuals {
            samples: &samples,
            ..*fine
        };
        let unwhitened = |theta: &[f64]| fine.evaluate(theta);
        let residual = unwhitened(&polished.theta);
        let jacobian = LevenbergMarquardt::jacobian(
            &unwhitened,
            &polished.theta,
            bounds.0,
            bounds.1,
            self.config.refine.fd_step,
            residual.len(),
        );
        let judged = Refined {
            cost: residual.norm_squared(),
            residual,
            jacobian,
            theta: polished.theta.clone(),
            iterations: polished.iterations,
            evaluations: polished.evaluations + 1 + 2 * space.lower.len(),
        };
        let total = evaluations + judged.evaluations;
        self.assess(
            &fine,
            &judged,
            space,
            total,
            Some((&polished.jacobian, chi2)),
        )
        .ok()
    }

    /// The estimate at a refined optimum: uncertainty and identifiability.
    ///
    /// The standard deviations are first order: `s² (JᵀJ)⁻¹` of the fixed weighting's
    /// Jacobian, `s²` its cost per degree of freedom; or, after the polish, `(J_wᵀJ_w)⁻¹` of
    /// the whitened Jacobian `whitened` (the covariance of a generalised least-squares fit),
    /// inflated by `χ²/dof` when the fit is worse than the noise explains; `χ²` is the
    /// polish's own when it gives one (the joint fit's), otherwise the residuals'.
    pub(super) fn assess(
        &self,
        residuals: &Residuals<'_, M>,
        best: &Refined,
        space: &SearchSpace,
        evaluations: usize,
        whitened: Option<(&DMatrix<f64>, Option<f64>)>,
    ) -> Result<Estimate, EstimateError> {
        let (lower, upper) = (&space.lower, &space.upper);
        let constraints = self.config.constraints;
        let (c, length) = constraints.eta(&best.theta);
        let p = best.theta.len();
        let dof = residuals.len().saturating_sub(p).max(1) as f64;
        // Condition in (ln c, ln L, ln λ): scale the L column by L.
        let l = constraints.length_index();
        let mut scaled: DMatrix<f64> = best.jacobian.clone();
        scaled.column_mut(l).scale_mut(length);
        let sv = scaled.singular_values();
        let (smax, smin) = (sv.max(), sv.min());
        let condition = if smax > 0.0 { smin / smax } else { 0.0 };
        let chi2 = match whitened.and_then(|(_, chi2)| chi2) {
            Some(chi2) => chi2,
            None => residuals.chi_squared(&best.theta, &self.config.noise)?,
        };
        let chi2_per_dof = chi2 / dof;
        let (jacobian, s2) = match whitened {
            Some((jw, _)) => (jw, chi2_per_dof.max(1.0)),
            None => (&best.jacobian, best.cost / dof),
        };
        let jtj = jacobian.transpose() * jacobian;
        // The fit's covariance in θ, with the model's own error: a relative variance ε² of
        // every search parameter (the stiffnesses and λ are searched as logarithms, L as
        // itself), which no number of samples lowers.
        let floor = self.config.model_error.powi(2);
        let theta_covariance = jtj.try_inverse().filter(|_| condition > 0.0).map(|inv| {
            let mut cov = inv * s2;
            for i in 0..p {
                cov[(i, i)] += floor * if i == l { length * length } else { 1.0 };
            }
            cov
        });
        let std: Vec<f64> = match &theta_covariance {
            Some(cov) => (0..p).map(|i| cov[(i, i)].max(0.0).sqrt()).collect(),
            None => vec![f64::INFINITY; p],
        };
        let covariance = theta_covariance.and_then(|cov| {
            let g = constraints.eta_jacobian(&best.theta);
            ParameterCovariance::from_matrix(&(&g * cov * g.transpose()))
        });
        let index = constraints.stiffness_index();
        let c_std = [0, 1, 2].map(|i| c[i] * std.get(index[i]).copied().unwrap_or(f64::INFINITY));
        let length_std = std.get(l).copied().unwrap_or(f64::INFINITY);
        let linear_density = constraints.linear_density(&best.theta);
        let linear_density_std =
            linear_density.map(|lambda| lambda * std.get(l + 1).copied().unwrap_or(f64::INFINITY));
        let at_bound = best.theta.iter().enumerate().find(|(i, v)| {
            let (l, u) = (lower[*i], upper[*i]);
            let tol = 1e-6 * (u - l);
            **v <= l + tol || **v >= u - tol
        });
        let unidentified = if condition < self.config.min_condition {
            Some(Unidentified::IllConditioned {
                condition,
                threshold: self.config.min_condition,
            })
        } else if let Some((index, value)) = at_bound {
            Some(Unidentified::AtBound {
                index,
                value: *value,
            })
        } else if chi2_per_dof > self.config.max_chi2_per_dof {
            Some(Unidentified::ResidualAboveNoise {
                chi2_per_dof,
                threshold: self.config.max_chi2_per_dof,
            })
        } else {
            None
        };
        Ok(Estimate {
            c,
            length,
            c_std,
            length_std,
            linear_density,
            linear_density_std,
            cost: best.cost,
            chi2_per_dof,
            condition,
            samples: self.samples.len(),
            evaluations,
            unidentified,
            covariance,
        })
    }
}
