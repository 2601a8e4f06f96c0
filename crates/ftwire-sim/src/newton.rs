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

use crate::banded::{BandedCholesky, BandedSym};
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
///
/// Each iteration: stop if the pinned gradient is within the tolerance; otherwise factor the
/// regularised Hessian ([`Solve::regularised_factor`]), take the Newton direction, stop if it is
/// rounding noise, limit its length ([`Solve::step_length`]) and backtrack until the energy
/// decreases ([`Solve::line_search`]).
pub(crate) fn solve_to(
    world: &World,
    mut state: RodState,
    tolerance: f64,
) -> Result<NewtonResult, NewtonFailure> {
    let settings = world.newton_settings();
    let solve = Solve::new(world, &state, tolerance);
    let mut lambda = 0.0_f64;
    let mut last_residual = f64::INFINITY;
    // The Hessian of the previous iterate, unpinned: at convergence it stands in for the one at
    // the solution (which is within the tolerance of it) for the stability check and the next
    // predictor, saving one Hessian evaluation per solve.
    let mut previous: Option<BandedSym> = None;
    for iteration in 0..=settings.max_iterations {
        let probe = energy::evaluate(world, &state, Order::Gradient);
        let grad = solve.pinned_gradient(&probe.grad);
        let res = residual(world, &grad);
        last_residual = res;
        if res < solve.tolerance {
            let Some(unpinned) = solve.hessian_at_solution(previous.take(), &state) else {
                break;
            };
            let pinned = solve.pinned(&unpinned);
            return Ok(finish(state, probe, unpinned, &pinned, iteration, res));
        }
        let mut eval = energy::evaluate(world, &state, Order::Hessian);
        let Some(unpinned) = eval.hess.take() else {
            break;
        };
        let hess = solve.pinned(&unpinned);
        if iteration == settings.max_iterations || !res.is_finite() {
            break;
        }
        let Some((factor, next_lambda)) = solve.regularised_factor(&hess, lambda) else {
            break;
        };
        lambda = next_lambda;
        let Some((dx, decrement)) = newton_direction(&factor, &grad) else {
            break;
        };
        let extent = solve.extent(&dx);
        if lambda == 0.0 && solve.is_rounding_noise(&extent, res) {
            // The Newton correction is at the level of rounding: the residual left is the
            // floating-point noise of the stiff stretching forces.
            return Ok(finish(state, eval, unpinned, &hess, iteration, res));
        }
        let alpha = solve.step_length(&state, &extent);
        let e0 = eval.energies.total();
        match solve.line_search(&state, &dx, alpha, decrement, e0) {
            Some(mut next) => {
                next.rebase();
                state = next;
                previous = Some(unpinned);
            }
            // Rounding-limited: no descent is measurable any more.
            None if res < 100.0 * solve.tolerance => {
                return Ok(finish(state, eval, unpinned, &hess, iteration, res));
            }
            None => {
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

/// The accepted equilibrium: `unpinned` is the Hessian kept for the caller, `pinned` the same
/// with the clamped degrees of freedom pinned, whose Cholesky factor exists exactly when the
/// equilibrium is a stable minimum.
fn finish(
    state: RodState,
    eval: Evaluation,
    unpinned: BandedSym,
    pinned: &BandedSym,
    iterations: usize,
    residual: f64,
) -> NewtonResult {
    let stable = pinned.cholesky().is_some();
    NewtonResult {
        state,
        eval,
        hessian: unpinned,
        iterations,
        residual,
        stable,
    }
}

/// The Newton direction `dx = −F⁻¹·g` from the factor `F` of the regularised Hessian, and the
/// decrement `−gᵀ·dx`; `None` when the decrement is not a descent (negative or NaN).
fn newton_direction(factor: &BandedCholesky, grad: &[f64]) -> Option<(Vec<f64>, f64)> {
    let mut dx = factor.solve(grad);
    for v in dx.iter_mut() {
        *v = -*v;
    }
    let decrement: f64 = -grad.iter().zip(&dx).map(|(g, d)| g * d).sum::<f64>();
    if decrement.is_nan() || decrement < 0.0 {
        return None;
    }
    Some((dx, decrement))
}

/// The largest node displacement \[m\] and the largest angle change \[rad\] of a step.
struct Extent {
    largest: f64,
    largest_angle: f64,
}

/// The scales of one Newton solve, fixed by the rod and the start state.
struct Solve<'a> {
    world: &'a World,
    /// Edge count `N`.
    n: usize,
    /// Edge length `h` \[m\].
    h: f64,
    /// The clamped degrees of freedom ([`fixed_dofs`]).
    fixed: Vec<usize>,
    /// The regularisation diagonal `D`: `c/h³` for positions, `c1/h` for angles.
    shift: Vec<f64>,
    /// The longest node step without obstacles \[m\].
    free_step: f64,
    /// The rod's energy scale `c_max/L` \[J\].
    energy_scale: f64,
    /// The scaled residual to reach, raised to the rounding noise floor.
    tolerance: f64,
}

impl<'a> Solve<'a> {
    fn new(world: &'a World, state: &RodState, tolerance: f64) -> Self {
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
        // The stretching forces of nodes stored in world coordinates carry rounding noise of
        // about ε·EA·|x|/h; asking for less than a few times that would never terminate.
        let reach = state.nodes.iter().map(|x| x.norm()).fold(l, f64::max);
        let noise = 16.0 * f64::EPSILON * rod.axial_stiffness() * reach / h / (cmax / (l * l));
        Self {
            world,
            n,
            h,
            fixed,
            shift,
            free_step,
            energy_scale,
            tolerance: tolerance.max(noise),
        }
    }

    /// The gradient with the clamped entries zeroed.
    fn pinned_gradient(&self, grad: &[f64]) -> Vec<f64> {
        let mut grad = grad.to_vec();
        for &i in &self.fixed {
            grad[i] = 0.0;
        }
        grad
    }

    /// A copy of `hess` with the clamped degrees of freedom pinned.
    fn pinned(&self, hess: &BandedSym) -> BandedSym {
        let mut pinned = hess.clone();
        for &i in &self.fixed {
            pinned.pin(i);
        }
        pinned
    }

    /// The unpinned Hessian reported at convergence: the previous iterate's if there is one,
    /// else evaluated at `state`.
    fn hessian_at_solution(
        &self,
        previous: Option<BandedSym>,
        state: &RodState,
    ) -> Option<BandedSym> {
        match previous {
            Some(h) => Some(h),
            None => energy::evaluate(self.world, state, Order::Hessian).hess,
        }
    }

    /// Cholesky factor of `H + λD` for the smallest `λ ∈ {0, λ₀·10^k}` that succeeds, starting
    /// from a tenth of the previous iteration's `lambda`; returns the factor and the `λ` to
    /// carry to the next iteration (zero when none was needed).
    fn regularised_factor(&self, hess: &BandedSym, lambda: f64) -> Option<(BandedCholesky, f64)> {
        let mut trial_lambda = if lambda > 0.0 { lambda / 10.0 } else { 0.0 };
        for _ in 0..30 {
            let mut shifted = hess.clone();
            if trial_lambda > 0.0 {
                let s: Vec<f64> = self.shift.iter().map(|d| d * trial_lambda).collect();
                shifted.add_diagonal(&s);
                for &i in &self.fixed {
                    shifted.pin(i);
                }
            }
            if let Some(f) = shifted.cholesky() {
                let next = if trial_lambda < 1e-6 {
                    0.0
                } else {
                    trial_lambda
                };
                return Some((f, next));
            }
            trial_lambda = if trial_lambda == 0.0 {
                1e-6
            } else {
                trial_lambda * 10.0
            };
        }
        None
    }

    /// The largest node displacement and angle change of the step `dx`.
    fn extent(&self, dx: &[f64]) -> Extent {
        let largest = (0..=self.n)
            .map(|k| {
                let d = nalgebra::Vector3::new(dx[x_dof(k, 0)], dx[x_dof(k, 1)], dx[x_dof(k, 2)]);
                d.norm()
            })
            .fold(0.0, f64::max);
        let largest_angle = (0..self.n)
            .map(|j| dx[theta_dof(j)].abs())
            .fold(0.0, f64::max);
        Extent {
            largest,
            largest_angle,
        }
    }

    /// Whether an unregularised Newton step this small, at this residual, is rounding noise.
    fn is_rounding_noise(&self, extent: &Extent, res: f64) -> bool {
        extent.largest < ROUNDING_STEP * self.h
            && extent.largest_angle < ROUNDING_STEP
            && res < ROUNDING_RESIDUAL
    }

    /// The initial step fraction `α ≤ 1`: node steps at most the free step (and, near
    /// obstacles, the contact step limit), angle steps at most 0.5 rad.
    fn step_length(&self, state: &RodState, extent: &Extent) -> f64 {
        let mut alpha: f64 = 1.0;
        let max_step = energy::contact::step_limit(self.world, state)
            .map_or(self.free_step, |limit| self.free_step.min(limit));
        if extent.largest > max_step {
            alpha = max_step / extent.largest;
        }
        if alpha * extent.largest_angle > 0.5 {
            alpha = 0.5 / extent.largest_angle;
        }
        alpha
    }

    /// Backtracking (Armijo) line search from `alpha`, halving until the energy falls by
    /// `10⁻⁴·α·decrement` below `e0`; in the rounding regime (a negligible decrement and a full
    /// step) the full Newton step is taken unchecked. `None` if no trial step descends.
    fn line_search(
        &self,
        state: &RodState,
        dx: &[f64],
        mut alpha: f64,
        decrement: f64,
        e0: f64,
    ) -> Option<RodState> {
        if decrement < 1e-13 * self.energy_scale && alpha == 1.0 {
            return Some(apply_step(state, dx, 1.0));
        }
        for _ in 0..40 {
            let trial = apply_step(state, dx, alpha);
            let e = energy::evaluate(self.world, &trial, Order::Energy)
                .energies
                .total();
            if e.is_finite() && e <= e0 - 1e-4 * alpha * decrement {
                return Some(trial);
            }
            alpha *= 0.5;
        }
        None
    }
}
