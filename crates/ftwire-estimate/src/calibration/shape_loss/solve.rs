//! The Gauss–Newton solver of the map fitted on the shape: Levenberg–Marquardt on the
//! iteratively reweighted normal equations of [`Problem`], in the map's weights and, when
//! fitted, gravity's two directions.

use nalgebra::{DMatrix, DVector, Matrix6, Vector3};

use super::loss::{Problem, ridge_term, tangent_basis};
use super::theta::Map;
use crate::{EstimateError, WireModel};

/// What a solve ended with.
pub(super) struct Outcome {
    pub(super) loss: f64,
    pub(super) iterations: usize,
}

impl<M: WireModel> Problem<'_, M> {
    /// Levenberg–Marquardt on the map (and gravity) from where they are; `ridge` relative to
    /// the mean curvature in the affine weights. Returns the final objective.
    pub(super) fn solve(
        &self,
        map: &mut Map,
        gravity: &mut Option<Vector3<f64>>,
        ridge: f64,
        max_iterations: usize,
    ) -> Result<Outcome, EstimateError> {
        let width = map.theta.ncols();
        let fit_gravity = gravity.is_some() && self.gravity.is_some();
        let n = 6 * width + if fit_gravity { 2 } else { 0 };
        let sigma = *self.frame.output.std();
        let mut mu = 1e-3;
        let mut lambda = None;
        let mut beta = None;
        let mut loss = f64::INFINITY;
        let mut iterations = 0;
        while iterations < max_iterations {
            iterations += 1;
            let terms = self.evaluate(map, *gravity, true)?;
            if terms.iter().any(Option::is_none) {
                break;
            }
            let mut h = DMatrix::<f64>::zeros(n, n);
            let mut b = DVector::<f64>::zeros(n);
            let mut current = 0.0;
            for (k, t) in terms.iter().flatten().enumerate() {
                current += t.loss;
                let psi = map.psi(&self.z[k]);
                let dg = Matrix6::from_diagonal(&sigma) * t.g * Matrix6::from_diagonal(&sigma);
                let db = sigma.component_mul(&t.b);
                for kk in 0..6 {
                    for ll in kk..6 {
                        let v = dg[(kk, ll)];
                        if v == 0.0 {
                            continue;
                        }
                        for q in 0..width {
                            let vq = v * psi[q];
                            for p in 0..width {
                                h[(kk * width + p, ll * width + q)] += vq * psi[p];
                            }
                        }
                    }
                    for p in 0..width {
                        b[kk * width + p] += db[kk] * psi[p];
                    }
                }
                if fit_gravity {
                    let dc = Matrix6::from_diagonal(&sigma) * t.c;
                    for kk in 0..6 {
                        for col in 0..2 {
                            for p in 0..width {
                                h[(kk * width + p, 6 * width + col)] += dc[(kk, col)] * psi[p];
                            }
                        }
                    }
                    for r in 0..2 {
                        for c in 0..2 {
                            h[(6 * width + r, 6 * width + c)] += t.gg[(r, c)];
                        }
                        b[6 * width + r] += t.bg[r];
                    }
                }
            }
            // Only the blocks on and above the diagonal were summed: mirror them.
            for c in 0..n {
                for r in (c + 1)..n {
                    h[(r, c)] = h[(c, r)];
                }
            }
            let lambda = *lambda.get_or_insert_with(|| {
                #[allow(clippy::cast_precision_loss)] // small sizes
                let mean = (0..6)
                    .flat_map(|kk| (0..7).map(move |p| kk * width + p))
                    .map(|i| h[(i, i)])
                    .sum::<f64>()
                    / 42.0;
                ridge * mean
            });
            let beta = *beta.get_or_insert_with(|| {
                if self.targets.is_empty() {
                    return 0.0;
                }
                // The label term's curvature in an affine weight is β Σ ψ_p², ψ_p of z or 1.
                #[allow(clippy::cast_precision_loss)] // small sizes
                let mean_psi = self.z.iter().map(|z| z.norm_squared() + 1.0).sum::<f64>() / 7.0;
                #[allow(clippy::cast_precision_loss)] // small sizes
                let mean_shape = (0..6)
                    .flat_map(|kk| (0..7).map(move |p| kk * width + p))
                    .map(|i| h[(i, i)])
                    .sum::<f64>()
                    / 42.0;
                self.label_weight * mean_shape / mean_psi.max(f64::MIN_POSITIVE)
            });
            if beta > 0.0 {
                for (k, y) in self.targets.iter().enumerate() {
                    let psi = map.psi(&self.z[k]);
                    let e = &map.theta * &psi;
                    for kk in 0..6 {
                        let ek = e[kk] - y[kk];
                        for q in 0..width {
                            let vq = beta * psi[q];
                            for p in 0..width {
                                h[(kk * width + p, kk * width + q)] += vq * psi[p];
                            }
                            b[kk * width + q] += beta * ek * psi[q];
                        }
                    }
                }
            }
            loss = current + ridge_term(map, lambda) + self.label_term(map, beta);
            for kk in 0..6 {
                for p in 7..width {
                    let i = kk * width + p;
                    h[(i, i)] += lambda;
                    b[i] += lambda * map.theta[(kk, p)];
                }
            }
            let mut accepted = false;
            while mu < 1e10 {
                let mut damped = h.clone();
                for i in 0..n {
                    damped[(i, i)] += mu * h[(i, i)].max(1e-12);
                }
                let Some(chol) = damped.cholesky() else {
                    mu *= 10.0;
                    continue;
                };
                let step = chol.solve(&(-&b));
                let mut next = map.clone();
                for kk in 0..6 {
                    for p in 0..width {
                        next.theta[(kk, p)] += step[kk * width + p];
                    }
                }
                let next_gravity = match (*gravity, fit_gravity) {
                    (Some(g), true) => {
                        let (e1, e2) = tangent_basis(&g);
                        Some((g + step[6 * width] * e1 + step[6 * width + 1] * e2).normalize())
                    }
                    (g, _) => g,
                };
                let next_loss = self.objective(&next, next_gravity, (lambda, beta))?;
                if next_loss < loss {
                    let decrease = (loss - next_loss) / loss.max(f64::MIN_POSITIVE);
                    *map = next;
                    *gravity = next_gravity;
                    loss = next_loss;
                    mu = (mu / 3.0).max(1e-9);
                    accepted = decrease > 1e-7;
                    break;
                }
                mu *= 4.0;
            }
            if !accepted {
                break;
            }
        }
        Ok(Outcome { loss, iterations })
    }
}
