//! Levenberg–Marquardt over the 6 normalised components of `a`: the local stage of the shape
//! fit (paper eq. 15).
//!
//! The problem gives `½‖r(z)‖²` and, at the current point, the normal equations `JᵀJ`, `Jᵀr`
//! of its analytic Jacobian; the method solves `(JᵀJ + λ D) δ = −Jᵀr` with Marquardt's scaling
//! `D = diag(JᵀJ)` (floored, so a direction the markers do not see stays damped) and updates
//! `λ` by Nielsen's gain-ratio rule (Madsen, Nielsen & Tingleff, *Methods for non-linear least
//! squares problems*, 2004, §3.2).

use nalgebra::{Matrix6, Vector6};

use crate::EstimateError;
use crate::shape::setting;

/// A least-squares problem in `z ∈ R⁶`.
pub(crate) trait LeastSquares {
    /// `½‖r(z)‖²`, or an error where the model cannot be solved (outside `A`, diverged).
    fn cost(&self, z: &Vector6<f64>) -> Result<f64, EstimateError>;

    /// `½‖r‖²`, `JᵀJ` and `Jᵀr` at `z`.
    fn linearise(&self, z: &Vector6<f64>) -> Result<Normal, EstimateError>;
}

/// The Gauss–Newton normal equations at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Normal {
    /// `½‖r‖²`.
    pub cost: f64,
    /// `JᵀJ`.
    pub jtj: Matrix6<f64>,
    /// `Jᵀr`, the gradient of the cost.
    pub jtr: Vector6<f64>,
}

/// Settings of the local refinement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevenbergMarquardt {
    /// Most Jacobian evaluations (outer iterations) (default `100`).
    pub max_iterations: usize,
    /// Stop when a step is shorter than this, in normalised units of `a` (default `1e-7`).
    pub step_tolerance: f64,
    /// Stop when the largest gradient component `|Jᵀr|∞` is below this (default `1e-14`; the
    /// residuals are in units of `L`).
    pub gradient_tolerance: f64,
    /// Initial damping relative to the largest diagonal entry of `JᵀJ` (default `1e-3`).
    pub initial_damping: f64,
    /// Longest step, in normalised units of `a` (default `2`): a longer Gauss–Newton step is
    /// shortened to this. It keeps trial points where the model is cheap and the linearisation
    /// means something (far out, the solver's adaptive step count grows with `|a|`).
    pub max_step: f64,
}

impl Default for LevenbergMarquardt {
    fn default() -> Self {
        Self {
            max_iterations: 100,
            step_tolerance: 1e-7,
            gradient_tolerance: 1e-14,
            initial_damping: 1e-3,
            max_step: 2.0,
        }
    }
}

/// Why the local refinement stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Termination {
    /// The step became shorter than the step tolerance.
    SmallStep,
    /// The gradient vanished.
    SmallGradient,
    /// The damping grew without finding a step that lowers the cost.
    Stalled,
    /// The iteration budget ran out.
    MaxIterations,
}

impl Termination {
    /// Whether the refinement reached a stationary point (not [`Termination::MaxIterations`]
    /// or [`Termination::Stalled`]).
    pub fn converged(self) -> bool {
        matches!(self, Self::SmallStep | Self::SmallGradient)
    }
}

/// The result of a local refinement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Refined {
    /// The final point.
    pub z: Vector6<f64>,
    /// `½‖r‖²` there.
    pub cost: f64,
    /// Jacobian evaluations made.
    pub iterations: usize,
    /// Why it stopped.
    pub termination: Termination,
}

/// Largest damping before giving up: the step is then negligibly small anyway.
const MAX_DAMPING: f64 = 1e16;
/// Floor of Marquardt's diagonal scaling, relative to its largest entry.
const SCALING_FLOOR: f64 = 1e-9;

impl LevenbergMarquardt {
    pub(crate) fn validate(&self) -> Result<(), EstimateError> {
        let positive = [
            ("local.step_tolerance", self.step_tolerance),
            ("local.gradient_tolerance", self.gradient_tolerance),
            ("local.initial_damping", self.initial_damping),
            ("local.max_step", self.max_step),
        ];
        for (name, value) in positive {
            setting::positive(name, value, "finite and > 0")?;
        }
        setting::count(
            "local.max_iterations",
            self.max_iterations,
            1,
            usize::MAX,
            "at least 1",
        )
    }

    /// Minimises `problem` from `z0`.
    ///
    /// # Errors
    /// When the problem cannot be linearised at `z0` or at an accepted point.
    pub(crate) fn minimise<P: LeastSquares>(
        &self,
        problem: &P,
        z0: &Vector6<f64>,
    ) -> Result<Refined, EstimateError> {
        let mut z = *z0;
        let mut normal = problem.linearise(&z)?;
        let mut damping = self.initial_damping * normal.jtj.diagonal().max();
        let mut growth = 2.0;
        for iteration in 1..=self.max_iterations {
            if normal.jtr.amax() < self.gradient_tolerance {
                return Ok(self.stop(z, normal.cost, iteration, Termination::SmallGradient));
            }
            let diagonal = normal.jtj.diagonal();
            let floor = SCALING_FLOOR * diagonal.max().max(f64::MIN_POSITIVE);
            let scaling = Matrix6::from_diagonal(&diagonal.map(|d| d.max(floor)));
            loop {
                if !(damping.is_finite() && damping < MAX_DAMPING) {
                    return Ok(self.stop(z, normal.cost, iteration, Termination::Stalled));
                }
                let system = normal.jtj + damping * scaling;
                let Some(mut step) = system.cholesky().map(|c| c.solve(&(-normal.jtr))) else {
                    damping *= growth;
                    growth *= 2.0;
                    continue;
                };
                let length = step.norm();
                if length > self.max_step {
                    step *= self.max_step / length;
                }
                let trial = z + step;
                let predicted = -step.dot(&normal.jtr) - 0.5 * step.dot(&(normal.jtj * step));
                let actual = problem
                    .cost(&trial)
                    .map(|c| normal.cost - c)
                    .unwrap_or(f64::NEG_INFINITY);
                if actual > 0.0 && predicted > 0.0 {
                    let rho = actual / predicted;
                    damping *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                    growth = 2.0;
                    z = trial;
                    if step.norm() < self.step_tolerance * (1.0 + z.norm()) {
                        let cost = problem.cost(&z)?;
                        return Ok(self.stop(z, cost, iteration, Termination::SmallStep));
                    }
                    normal = problem.linearise(&z)?;
                    break;
                }
                if step.norm() < self.step_tolerance * (1.0 + z.norm()) {
                    return Ok(self.stop(z, normal.cost, iteration, Termination::SmallStep));
                }
                damping *= growth;
                growth *= 2.0;
            }
        }
        Ok(self.stop(
            z,
            normal.cost,
            self.max_iterations,
            Termination::MaxIterations,
        ))
    }

    fn stop(
        &self,
        z: Vector6<f64>,
        cost: f64,
        iterations: usize,
        termination: Termination,
    ) -> Refined {
        Refined {
            z,
            cost,
            iterations,
            termination,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Rosenbrock in pairs: r = (10 (z1 − z0²), 1 − z0, …), minimum at z = 1.
    struct Rosenbrock;

    impl Rosenbrock {
        fn residuals(z: &Vector6<f64>) -> ([f64; 6], Matrix6<f64>) {
            let mut r = [0.0; 6];
            let mut j = Matrix6::zeros();
            for k in 0..3 {
                let (x, y) = (z[2 * k], z[2 * k + 1]);
                r[2 * k] = 10.0 * (y - x * x);
                r[2 * k + 1] = 1.0 - x;
                j[(2 * k, 2 * k)] = -20.0 * x;
                j[(2 * k, 2 * k + 1)] = 10.0;
                j[(2 * k + 1, 2 * k)] = -1.0;
            }
            (r, j)
        }
    }

    impl LeastSquares for Rosenbrock {
        fn cost(&self, z: &Vector6<f64>) -> Result<f64, EstimateError> {
            Ok(0.5 * Self::residuals(z).0.iter().map(|r| r * r).sum::<f64>())
        }

        fn linearise(&self, z: &Vector6<f64>) -> Result<Normal, EstimateError> {
            let (r, j) = Self::residuals(z);
            let r = Vector6::from_column_slice(&r);
            Ok(Normal {
                cost: 0.5 * r.norm_squared(),
                jtj: j.transpose() * j,
                jtr: j.transpose() * r,
            })
        }
    }

    #[test]
    fn solves_rosenbrock_from_the_classic_start() -> Result<(), EstimateError> {
        let start = Vector6::new(-1.2, 1.0, -1.2, 1.0, 0.5, -0.5);
        let lm = LevenbergMarquardt {
            max_iterations: 200,
            ..LevenbergMarquardt::default()
        };
        let refined = lm.minimise(&Rosenbrock, &start)?;
        assert!(refined.termination.converged(), "{refined:?}");
        assert_relative_eq!(refined.z, Vector6::repeat(1.0), epsilon = 1e-6);
        Ok(())
    }
}
