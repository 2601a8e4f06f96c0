//! Projection of a configuration onto the inextensible rods of its edge lengths.
//!
//! A predictor that moves nodes independently stretches the edges to second order in the step
//! (an edge turned by α grows by α²/2), and with the stiff stretching energy that error
//! dominates the first Newton iterations. Before Newton starts, the continuation therefore
//! projects the predicted free nodes onto the constraint set `|e_j| = h` with the smallest
//! displacement (fast projection, Goldenthal et al. 2007): Gauss–Newton steps
//! `Δx = −Jᵀ (J Jᵀ)⁻¹ C` with a tridiagonal `J Jᵀ`.

use nalgebra::Vector3;

use crate::state::RodState;

/// Projects the free nodes `2..=N−2` so that edges `1..=N−2` have length `h`. Leaves the state
/// unchanged if the projection does not converge (e.g. clamps pulled taut).
pub(crate) fn project_lengths(state: &mut RodState, h: f64) {
    let n = state.edges();
    if n < 4 {
        return;
    }
    let mut x = state.nodes.clone();
    let m = n - 2; // constraints on edges 1..=N−2
    for _ in 0..20 {
        let t: Vec<Vector3<f64>> = (1..=m).map(|j| (x[j + 1] - x[j]).normalize()).collect();
        let c: Vec<f64> = (1..=m).map(|j| (x[j + 1] - x[j]).norm() - h).collect();
        let worst = c.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        if worst < 1e-12 * h {
            break;
        }
        // J Jᵀ: constraint k (edge k+1) touches nodes k+1 (free if k ≥ 1) and k+2 (free if k ≤ m−2).
        let free = |node: usize| (2..=n - 2).contains(&node);
        let mut diag = vec![0.0; m];
        let mut off = vec![0.0; m.saturating_sub(1)];
        for k in 0..m {
            let (a, b) = (k + 1, k + 2);
            diag[k] = f64::from(u8::from(free(a))) + f64::from(u8::from(free(b)));
            if k + 1 < m {
                // Constraints k and k+1 share node k+2: ∂C_k/∂x = t_k, ∂C_{k+1}/∂x = −t_{k+1}.
                off[k] = -t[k].dot(&t[k + 1]);
            }
        }
        // Thomas algorithm for (J Jᵀ) λ = C.
        let mut cp = vec![0.0; m];
        let mut dp = vec![0.0; m];
        let mut ok = true;
        for k in 0..m {
            let lower = if k > 0 { off[k - 1] } else { 0.0 };
            let denom = diag[k] - lower * if k > 0 { cp[k - 1] } else { 0.0 };
            if denom.is_nan() || denom.abs() <= 1e-12 {
                ok = false;
                break;
            }
            cp[k] = if k + 1 < m { off[k] / denom } else { 0.0 };
            dp[k] = (c[k] - lower * if k > 0 { dp[k - 1] } else { 0.0 }) / denom;
        }
        if !ok {
            return;
        }
        let mut lambda = dp;
        for k in (0..m.saturating_sub(1)).rev() {
            lambda[k] -= cp[k] * lambda[k + 1];
        }
        // Δx = −Jᵀ λ on free nodes.
        for k in 0..m {
            let (a, b) = (k + 1, k + 2);
            if free(a) {
                x[a] += t[k] * lambda[k];
            }
            if free(b) {
                x[b] -= t[k] * lambda[k];
            }
        }
        if x.iter().any(|v| !v.iter().all(|c| c.is_finite())) {
            return;
        }
    }
    let moved = x
        .iter()
        .zip(&state.nodes)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    let worst = (1..=m)
        .map(|j| ((x[j + 1] - x[j]).norm() - h).abs())
        .fold(0.0, f64::max);
    if worst < 1e-6 * h && moved < 0.1 * h * n as f64 {
        state.nodes = x;
        state.rebase();
    }
}
