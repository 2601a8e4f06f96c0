//! Newton's method on the total energy, with a banded Cholesky solve, regularisation of
//! indefinite Hessians and a backtracking (Armijo) line search.
//!
//! Each iteration assembles the exact gradient and Hessian ([`crate::energy`]), pins the clamped
//! degrees of freedom, and factors `H + λD` with the smallest `λ ∈ {0, λ₀·10^k}` for which
//! Cholesky succeeds (`D` is a diagonal of the rod's own stiffness scales: `c/h³` for positions,
//! `c1/h` for angles). The step is limited in length (and, with obstacles, to half the contact
//! margin so that no sample can cross an obstacle's mid-plane in one step) and then backtracked
//! until the energy decreases sufficiently. After each accepted step the reference frames are
//! moved to the new tangents (time-parallel transport, Bergou et al. 2010, §4.1), which leaves
//! the energy unchanged. The iteration stops when the scaled gradient is below the tolerance; the
//! equilibrium is then a *stable minimum* if the unregularised Hessian is positive definite on
//! the free degrees of freedom.

use crate::banded::BandedSym;
use crate::energy::{self, Evaluation, Order, theta_dof, x_dof};
use crate::state::RodState;
use crate::world::World;

/// Convergence data of one equilibrium solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Convergence {
    /// Whether the residual fell below the tolerance.
    pub converged: bool,
    /// Newton iterations used (summed over continuation steps for a motion).
    pub iterations: usize,
    /// Final scaled residual (see [`crate::NewtonParams::tolerance`]).
    pub residual: f64,
}

/// The result of a successful Newton solve.
pub(crate) struct NewtonResult {
    pub state: RodState,
    pub eval: Evaluation,
    /// The Hessian at the solution, clamped degrees of freedom not pinned.
    pub hessian: BandedSym,
    pub iterations: usize,
    pub residual: f64,
    pub stable: bool,
}

/// A failed Newton solve.
pub(crate) struct NewtonFailure {
    pub iterations: usize,
    pub residual: f64,
}

/// Degrees of freedom held by the clamps (and the unused angle slot).
pub(crate) fn fixed_dofs(n: usize) -> Vec<usize> {
    let mut fixed = Vec::with_capacity(15);
    for k in [0, 1, n - 1, n] {
        for c in 0..3 {
            fixed.push(x_dof(k, c));
        }
    }
    fixed.extend([theta_dof(0), theta_dof(n - 1), theta_dof(n)]);
    fixed
}

/// A Newton correction smaller than this (relative to `h` for nodes, in radians for angles)
/// is rounding noise.
const ROUNDING_STEP: f64 = 1e-11;
/// The largest residual accepted as rounding noise.
const ROUNDING_RESIDUAL: f64 = 1e-5;

/// Scaled residual of a gradient whose fixed entries are zeroed.
fn residual(world: &World, grad: &[f64]) -> f64 {
    let rod = world.rod();
    let l = rod.params().length;
    let c = rod.max_stiffness();
    let (fs, ms) = (c / (l * l), c / l);
    grad.chunks(4)
        .map(|q| {
            let f = q[0].abs().max(q[1].abs()).max(q[2].abs()) / fs;
            f.max(q[3].abs() / ms)
        })
        .fold(0.0, f64::max)
}

fn apply_step(state: &RodState, dx: &[f64], alpha: f64) -> RodState {
    let mut s = state.clone();
    for (k, x) in s.nodes.iter_mut().enumerate() {
        for c in 0..3 {
            x[c] += alpha * dx[x_dof(k, c)];
        }
    }
    for (j, th) in s.theta.iter_mut().enumerate() {
        *th += alpha * dx[theta_dof(j)];
    }
    s
}

/// Runs Newton's method from `state` (whose clamped edges must already be placed).
pub(crate) fn solve(world: &World, state: RodState) -> Result<NewtonResult, NewtonFailure> {
    solve_to(world, state, world.newton_settings().tolerance)
}

/// As [`solve`], to the scaled residual `tolerance` instead of the world's.
pub(crate) fn solve_to(
    world: &World,
    mut state: RodState,
    tolerance: f64,
) -> Result<NewtonResult, NewtonFailure> {
    let settings = world.newton_settings();
    let rod = world.rod();
    let n = rod.edges();
    let h = rod.edge_length();
    let l = rod.params().length;
    let c = rod.params().stiffness;
    let cmax = rod.max_stiffness();
    let energy_scale = cmax / l;
    let fixed = fixed_dofs(n);
    let ndof = energy::dof_count(n);
    let shift: Vec<f64> = (0..ndof)
        .map(|i| {
            if i % 4 == 3 {
                c[0] / h
            } else {
                cmax / (h * h * h)
            }
        })
        .collect();
    let free_step = settings.max_step_fraction * l;
    // The stretching forces of nodes stored in world coordinates carry rounding noise of about
    // ε·EA·|x|/h; asking for less than a few times that would never terminate.
    let reach = state.nodes.iter().map(|x| x.norm()).fold(l, f64::max);
    let noise = 16.0 * f64::EPSILON * rod.axial_stiffness() * reach / h / (cmax / (l * l));
    let tolerance = tolerance.max(noise);
    let mut lambda = 0.0_f64;
    let mut last_residual = f64::INFINITY;
    // The Hessian of the previous iterate, unpinned: at convergence it stands in for the one at
    // the solution (which is within the tolerance of it) for the stability check and the next
    // predictor, saving one Hessian evaluation per solve.
    let mut previous: Option<BandedSym> = None;
    for iteration in 0..=settings.max_iterations {
        let probe = energy::evaluate(world, &state, Order::Gradient);
        let mut grad = probe.grad.clone();
        for &i in &fixed {
            grad[i] = 0.0;
        }
        let res = residual(world, &grad);
        last_residual = res;
        if res < tolerance {
            let unpinned = match previous.take() {
                Some(h) => h,
                None => match energy::evaluate(world, &state, Order::Hessian).hess {
                    Some(h) => h,
                    None => break,
                },
            };
            let mut pinned = unpinned.clone();
            for &i in &fixed {
                pinned.pin(i);
            }
            return Ok(NewtonResult {
                state,
                eval: probe,
                hessian: unpinned,
                iterations: iteration,
                residual: res,
                stable: pinned.cholesky().is_some(),
            });
        }
        let mut eval = energy::evaluate(world, &state, Order::Hessian);
        let Some(mut hess) = eval.hess.take() else {
            break;
        };
        let unpinned = hess.clone();
        for &i in &fixed {
            hess.pin(i);
        }
        if iteration == settings.max_iterations || !res.is_finite() {
            break;
        }
        // Regularised factorisation.
        let mut factor = None;
        let mut trial_lambda = if lambda > 0.0 { lambda / 10.0 } else { 0.0 };
        for _ in 0..30 {
            let mut shifted = hess.clone();
            if trial_lambda > 0.0 {
                let s: Vec<f64> = shift.iter().map(|d| d * trial_lambda).collect();
                shifted.add_diagonal(&s);
                for &i in &fixed {
                    shifted.pin(i);
                }
            }
            if let Some(f) = shifted.cholesky() {
                factor = Some(f);
                break;
            }
            trial_lambda = if trial_lambda == 0.0 {
                1e-6
            } else {
                trial_lambda * 10.0
            };
        }
        let Some(factor) = factor else {
            break;
        };
        lambda = if trial_lambda < 1e-6 {
            0.0
        } else {
            trial_lambda
        };
        let mut dx = factor.solve(&grad);
        for v in dx.iter_mut() {
            *v = -*v;
        }
        let decrement: f64 = -grad.iter().zip(&dx).map(|(g, d)| g * d).sum::<f64>();
        if decrement.is_nan() || decrement < 0.0 {
            break;
        }
        // Step length limits.
        let mut alpha: f64 = 1.0;
        let largest = (0..=n)
            .map(|k| {
                let d = nalgebra::Vector3::new(dx[x_dof(k, 0)], dx[x_dof(k, 1)], dx[x_dof(k, 2)]);
                d.norm()
            })
            .fold(0.0, f64::max);
        let largest_angle = (0..n).map(|j| dx[theta_dof(j)].abs()).fold(0.0, f64::max);
        if lambda == 0.0
            && largest < ROUNDING_STEP * h
            && largest_angle < ROUNDING_STEP
            && res < ROUNDING_RESIDUAL
        {
            // The Newton correction is at the level of rounding: the residual left is the
            // floating-point noise of the stiff stretching forces.
            let stable = hess.cholesky().is_some();
            return Ok(NewtonResult {
                state,
                eval,
                hessian: unpinned,
                iterations: iteration,
                residual: res,
                stable,
            });
        }
        let max_step = energy::contact::step_limit(world, &state)
            .map_or(free_step, |limit| free_step.min(limit));
        if largest > max_step {
            alpha = max_step / largest;
        }
        if alpha * largest_angle > 0.5 {
            alpha = 0.5 / largest_angle;
        }
        // Backtracking line search; in the rounding regime, take the full Newton step.
        let e0 = eval.energies.total();
        let mut accepted = None;
        if decrement < 1e-13 * energy_scale && alpha == 1.0 {
            accepted = Some(apply_step(&state, &dx, 1.0));
        } else {
            for _ in 0..40 {
                let trial = apply_step(&state, &dx, alpha);
                let e = energy::evaluate(world, &trial, Order::Energy)
                    .energies
                    .total();
                if e.is_finite() && e <= e0 - 1e-4 * alpha * decrement {
                    accepted = Some(trial);
                    break;
                }
                alpha *= 0.5;
            }
        }
        match accepted {
            Some(mut next) => {
                next.rebase();
                state = next;
                previous = Some(unpinned);
            }
            None => {
                if res < 100.0 * tolerance {
                    // Rounding-limited: no descent is measurable any more.
                    let stable = hess.cholesky().is_some();
                    return Ok(NewtonResult {
                        state,
                        eval,
                        hessian: unpinned,
                        iterations: iteration,
                        residual: res,
                        stable,
                    });
                }
                return Err(NewtonFailure {
                    iterations: iteration,
                    residual: res,
                });
            }
        }
    }
    Err(NewtonFailure {
        iterations: settings.max_iterations,
        residual: last_residual,
    })
}
