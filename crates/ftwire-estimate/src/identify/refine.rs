//! Local refinement: Levenberg–Marquardt on the stacked residual over the search vector `θ`
//! (`ln c`, `L`; see [`super::parameters`]), started from the swarm's best.
//!
//! The Jacobian `∂r/∂θ` is taken by central finite differences, `h_j = step · max(1, |θ_j|)`.
//! That is adequate here: there are at most 4 parameters, so a Jacobian costs 8 residual
//! evaluations, each one tip solve per sample (microseconds); the residual is smooth in `θ`
//! and computed by a fixed-order integrator accurate to about `1e-12`, so with `step = 1e-5`
//! the truncation error (`~h²`) and the rounding error (`~1e-12/h`) are both near `1e-7`
//! relative, far below what the fit needs. An analytic `∂Γ/∂c` would need a further
//! variational ODE for each parameter. The test `lm_jacobian_matches_known_derivative` checks
//! the `L` column against the closed form `∂/∂L log(Γ⁻¹ b) = −(u(L), e1)` at an exact fit, and
//! every column against a second step size.
//!
//! Steps are damped with Marquardt's scaling, `(JᵀJ + λ diag(JᵀJ)) δ = −Jᵀr`, and projected
//! onto the search box.

use nalgebra::{DMatrix, DVector};

use crate::EstimateError;

/// Levenberg–Marquardt settings (a parameter bundle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevenbergMarquardt {
    /// Largest number of accepted or rejected steps (default `40`).
    pub max_iterations: usize,
    /// Relative finite-difference step (default `1e-5`; see the module docs).
    pub fd_step: f64,
    /// Stop when a step lowers the cost by less than this fraction (default `1e-12`).
    pub cost_tolerance: f64,
    /// Stop when the step's largest component is below this (default `1e-11`).
    pub step_tolerance: f64,
    /// Initial damping `λ` (default `1e-3`).
    pub initial_damping: f64,
}

impl Default for LevenbergMarquardt {
    fn default() -> Self {
        Self {
            max_iterations: 40,
            fd_step: 1e-5,
            cost_tolerance: 1e-12,
            step_tolerance: 1e-11,
            initial_damping: 1e-3,
        }
    }
}

/// The result of a refinement.
#[derive(Debug, Clone, PartialEq)]
pub struct Refined {
    /// The final parameters.
    pub theta: Vec<f64>,
    /// The stacked residual there.
    pub residual: DVector<f64>,
    /// `∂r/∂θ` there (central differences).
    pub jacobian: DMatrix<f64>,
    /// `‖r‖²`.
    pub cost: f64,
    /// Steps taken (accepted or rejected).
    pub iterations: usize,
    /// Residual evaluations made.
    pub evaluations: usize,
}

impl LevenbergMarquardt {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] naming the first bad field.
    pub fn validate(&self) -> Result<(), EstimateError> {
        let checks = [
            (
                "refine.fd_step",
                self.fd_step,
                self.fd_step > 0.0 && self.fd_step < 0.1,
            ),
            (
                "refine.cost_tolerance",
                self.cost_tolerance,
                self.cost_tolerance >= 0.0,
            ),
            (
                "refine.step_tolerance",
                self.step_tolerance,
                self.step_tolerance >= 0.0,
            ),
            (
                "refine.initial_damping",
                self.initial_damping,
                self.initial_damping > 0.0,
            ),
        ];
        for (field, value, ok) in checks {
            if !(ok && value.is_finite()) {
                return Err(EstimateError::BadIdentifySetting {
                    field,
                    value,
                    allowed: "finite; fd_step in (0, 0.1), tolerances >= 0, damping > 0",
                });
            }
        }
        Ok(())
    }

    /// `∂r/∂θ` by central differences with relative step `step`, clamped to the box (a
    /// one-sided difference at a bound).
    pub fn jacobian<F: Fn(&[f64]) -> DVector<f64>>(
        residual: &F,
        theta: &[f64],
        lower: &[f64],
        upper: &[f64],
        step: f64,
        rows: usize,
    ) -> DMatrix<f64> {
        let mut jac = DMatrix::zeros(rows, theta.len());
        let mut x = theta.to_vec();
        for j in 0..theta.len() {
            let h = step * theta[j].abs().max(1.0);
            let lo = lower.get(j).copied().unwrap_or(f64::NEG_INFINITY);
            let hi = upper.get(j).copied().unwrap_or(f64::INFINITY);
            let (plus, minus) = ((theta[j] + h).min(hi), (theta[j] - h).max(lo));
            x[j] = plus;
            let rp = residual(&x);
            x[j] = minus;
            let rm = residual(&x);
            x[j] = theta[j];
            if plus > minus {
                jac.set_column(j, &((rp - rm) / (plus - minus)));
            }
        }
        jac
    }

    /// Minimises `‖r(θ)‖²` from `start` inside `[lower, upper]`.
    pub fn minimise<F: Fn(&[f64]) -> DVector<f64>>(
        &self,
        residual: &F,
        start: &[f64],
        lower: &[f64],
        upper: &[f64],
    ) -> Refined {
        let n = start.len();
        let mut theta = start.to_vec();
        let mut r = residual(&theta);
        let rows = r.len();
        let mut cost = r.norm_squared();
        let mut evaluations = 1;
        let mut lambda = self.initial_damping;
        let mut jac = Self::jacobian(residual, &theta, lower, upper, self.fd_step, rows);
        evaluations += 2 * n;
        let mut iterations = 0;
        while iterations < self.max_iterations {
            iterations += 1;
            let jtj = jac.transpose() * &jac;
            let g = jac.transpose() * &r;
            let mut a = jtj.clone();
            for i in 0..n {
                a[(i, i)] += lambda * jtj[(i, i)].max(1e-12);
            }
            let Some(delta) = a.cholesky().map(|ch| ch.solve(&(-g))) else {
                lambda *= 10.0;
                continue;
            };
            let trial: Vec<f64> = (0..n)
                .map(|i| {
                    let lo = lower.get(i).copied().unwrap_or(f64::NEG_INFINITY);
                    let hi = upper.get(i).copied().unwrap_or(f64::INFINITY);
                    (theta[i] + delta[i]).clamp(lo, hi)
                })
                .collect();
            let step = trial
                .iter()
                .zip(&theta)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            let rt = residual(&trial);
            evaluations += 1;
            let trial_cost = rt.norm_squared();
            if trial_cost < cost {
                let decrease = (cost - trial_cost) / cost.max(f64::MIN_POSITIVE);
                theta = trial;
                r = rt;
                cost = trial_cost;
                lambda = (lambda / 3.0).max(1e-12);
                jac = Self::jacobian(residual, &theta, lower, upper, self.fd_step, rows);
                evaluations += 2 * n;
                if decrease < self.cost_tolerance || step < self.step_tolerance {
                    break;
                }
            } else {
                lambda *= 4.0;
                if step < self.step_tolerance || lambda > 1e12 {
                    break;
                }
            }
        }
        Refined {
            theta,
            residual: r,
            jacobian: jac,
            cost,
            iterations,
            evaluations,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_nonlinear_least_squares_problem() {
        // Exponential fit y = p0 exp(p1 t) to exact data.
        let ts: Vec<f64> = (0..10).map(|i| f64::from(i) * 0.2).collect();
        let residual = |p: &[f64]| {
            DVector::from_iterator(
                ts.len(),
                ts.iter()
                    .map(|t| p[0] * (p[1] * t).exp() - 2.0 * (-0.7 * t).exp()),
            )
        };
        let lm = LevenbergMarquardt::default();
        let out = lm.minimise(&residual, &[1.0, 0.0], &[0.1, -5.0], &[10.0, 5.0]);
        assert!((out.theta[0] - 2.0).abs() < 1e-8, "{:?}", out.theta);
        assert!((out.theta[1] + 0.7).abs() < 1e-8, "{:?}", out.theta);
    }

    #[test]
    fn respects_the_box() {
        let residual = |p: &[f64]| DVector::from_vec(vec![p[0] - 3.0]);
        let out = LevenbergMarquardt::default().minimise(&residual, &[0.0], &[-1.0], &[1.0]);
        assert!((out.theta[0] - 1.0).abs() < 1e-12);
    }
}
