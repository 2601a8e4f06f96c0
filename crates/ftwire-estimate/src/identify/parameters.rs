//! The unknowns `η = (c1, c2, c3, L)` and the vector the optimisers search over.
//!
//! The search vector `θ` holds `ln c_i` for the free stiffnesses and `L` itself:
//! - logarithms, because the stiffnesses span three and a half decades (the search box is
//!   `c_i ∈ [1e-3, 5] N·m²`) and the residuals depend on them through `u = μ/c`, so equal steps
//!   in `ln c` are equal relative changes; they also keep `c > 0` without a constraint;
//! - `L` directly: its box is `[max(0.2, max_i |p(b̃_i)| + margin), 2] m`, less than a decade.
//!
//! [`ParameterConstraints`] ties parameters together and removes them from `θ`: isotropic
//! bending (`c3 = c2`) and a known torsion ratio (`c1 = ν c2`). It can also add one: the
//! wire's linear density `λ` \[kg/m\] under a known gravity `g` (the loaded model, weight per
//! length `w = λ g`; [`ParameterConstraints::weight`]), searched as `ln λ` in
//! `[LAMBDA_MIN, LAMBDA_MAX]`. The layout of `θ` is
//! `[ln c1 (unless tied), ln c2, ln c3 (unless isotropic), L, ln λ (if weighed)]`.

use nalgebra::Vector3;

use crate::EstimateError;

/// Smallest stiffness searched for \[N·m²\].
pub const C_MIN: f64 = 1e-3;
/// Largest stiffness searched for \[N·m²\].
pub const C_MAX: f64 = 5.0;
/// Shortest wire searched for \[m\] (the lower bound is raised to the gripper distance).
pub const L_MIN: f64 = 0.2;
/// Longest wire searched for \[m\].
pub const L_MAX: f64 = 2.0;
/// Smallest linear density searched for \[kg/m\] (a 0.07 mm steel wire).
pub const LAMBDA_MIN: f64 = 1e-4;
/// Largest linear density searched for \[kg/m\] (a 6 mm steel rod).
pub const LAMBDA_MAX: f64 = 0.25;

/// Relations between the parameters known before identification; each removes one unknown.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ParameterConstraints {
    /// Isotropic bending, `c3 = c2` (a wire of round cross-section) (default `false`).
    pub isotropic: bool,
    /// A known torsion ratio `ν = c1/c2` (for a round isotropic rod `ν = 1/(1 + Poisson's
    /// ratio)`), or `None` to identify `c1` (default `None`).
    pub torsion_ratio: Option<f64>,
    /// Search the stiffnesses per length, `ln(c_i / L)`, instead of `ln c_i` (default
    /// `false`; the swarm's coarse search sets it). A wire's measured poses pin `c/L` far
    /// more tightly than `c` and `L` apart (the bending angle of a moment `τ` is `τ L / c`),
    /// so in `(ln c2, L)` the cost's basin is a thin diagonal valley along `c2 ∝ L`, a needle
    /// for a swarm: one grid column in eighty wide on a simulated 1 m wire. In
    /// `(ln(c2/L), L)` the valley is straight along `L`. The box is then
    /// `ln(c/L) ∈ [ln(C_MIN/L_MAX), ln(C_MAX/L_MIN)]`.
    pub stiffness_per_length: bool,
    /// Identify the wire's linear density `λ` too, under this gravity vector `g` \[m/s²\] in the
    /// base clamp frame: the model's weight per length becomes `λ g` (needs a model that
    /// carries a weight, [`crate::WireModel::with_weight_per_length`]). `None` (default): the
    /// model's weight, if any, is known and kept.
    pub weight: Option<Vector3<f64>>,
}

impl ParameterConstraints {
    /// Checks the torsion ratio.
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] unless `torsion_ratio` is finite and positive.
    pub fn validate(&self) -> Result<(), EstimateError> {
        if let Some(nu) = self.torsion_ratio
            && !(nu.is_finite() && nu > 0.0)
        {
            return Err(EstimateError::BadIdentifySetting {
                field: "constraints.torsion_ratio",
                value: nu,
                allowed: "finite and > 0",
            });
        }
        if let Some(g) = self.weight
            && !(g.iter().all(|v| v.is_finite()) && g.norm() > 0.0)
        {
            return Err(EstimateError::BadIdentifySetting {
                field: "constraints.weight",
                value: g.norm(),
                allowed: "a finite, non-zero gravity vector",
            });
        }
        Ok(())
    }

    /// The number of free parameters (the length of `θ`): 2 to 5.
    pub fn unknowns(&self) -> usize {
        self.length_index() + 1 + usize::from(self.weight.is_some())
    }

    /// The index of `L` in `θ`.
    pub fn length_index(&self) -> usize {
        1 + usize::from(self.torsion_ratio.is_none()) + usize::from(!self.isotropic)
    }

    /// The linear density `λ` \[kg/m\] of a search vector `θ`, when it is identified.
    pub fn linear_density(&self, theta: &[f64]) -> Option<f64> {
        self.weight?;
        Some(
            theta
                .get(self.length_index() + 1)
                .copied()
                .unwrap_or(f64::NAN)
                .exp(),
        )
    }

    /// `η = (c, L)` of a search vector `θ` (see the module docs for the layout).
    ///
    /// A `θ` of the wrong length gives a non-finite `η`, which every caller treats as a
    /// failed evaluation.
    pub fn eta(&self, theta: &[f64]) -> ([f64; 3], f64) {
        let mut k = 0;
        let mut next = || {
            let v = theta.get(k).copied().unwrap_or(f64::NAN);
            k += 1;
            v
        };
        let ln_c1 = if self.torsion_ratio.is_none() {
            Some(next())
        } else {
            None
        };
        let ln_c2 = next();
        let ln_c3 = if self.isotropic { ln_c2 } else { next() };
        let length = next();
        // Stiffnesses per length are scaled back by L (see `stiffness_per_length`).
        let scale = if self.stiffness_per_length {
            length
        } else {
            1.0
        };
        let (c2, c3) = (ln_c2.exp() * scale, ln_c3.exp() * scale);
        let c1 = match (ln_c1, self.torsion_ratio) {
            (Some(l), _) => l.exp() * scale,
            (None, Some(nu)) => nu * c2,
            (None, None) => f64::NAN,
        };
        ([c1, c2, c3], length)
    }

    /// The search vector `θ` of `η = (c, L)` and the linear density `λ` (tied parameters are
    /// dropped, their values in `c` ignored; `λ` is ignored unless it is identified, and
    /// clamped into the box when it is).
    pub fn theta(&self, c: [f64; 3], length: f64, linear_density: f64) -> Vec<f64> {
        let mut theta = Vec::with_capacity(5);
        let scale = if self.stiffness_per_length {
            length
        } else {
            1.0
        };
        if self.torsion_ratio.is_none() {
            theta.push((c[0] / scale).ln());
        }
        theta.push((c[1] / scale).ln());
        if !self.isotropic {
            theta.push((c[2] / scale).ln());
        }
        theta.push(length);
        if self.weight.is_some() {
            theta.push(linear_density.clamp(LAMBDA_MIN, LAMBDA_MAX).ln());
        }
        theta
    }

    /// The search box `(lower, upper)` for `θ`, with `L ≥ length_min`.
    pub fn bounds(&self, length_min: f64) -> (Vec<f64>, Vec<f64>) {
        let n = self.unknowns();
        let (c_min, c_max) = if self.stiffness_per_length {
            (C_MIN / L_MAX, C_MAX / L_MIN)
        } else {
            (C_MIN, C_MAX)
        };
        let mut lower = vec![c_min.ln(); n];
        let mut upper = vec![c_max.ln(); n];
        let l = self.length_index();
        lower[l] = length_min;
        upper[l] = L_MAX;
        if self.weight.is_some() {
            lower[l + 1] = LAMBDA_MIN.ln();
            upper[l + 1] = LAMBDA_MAX.ln();
        }
        (lower, upper)
    }

    /// `∂η/∂θ` at `θ`: one row per identified quantity `(c1, c2, c3, L)`, then `λ` when it is
    /// identified, one column per entry of `θ`. With `c_i = e^{θ_k} s` (`s = L` per length,
    /// else 1; a tied `c1 = ν c2` follows `c2`'s column), `∂c_i/∂θ_k = c_i` and, per length,
    /// `∂c_i/∂L = c_i/L`; `∂L/∂L = 1`; `∂λ/∂ln λ = λ`. It carries a covariance of `θ` to one of
    /// `η` to first order: `Σ_η = G Σ_θ Gᵀ`.
    pub fn eta_jacobian(&self, theta: &[f64]) -> nalgebra::DMatrix<f64> {
        let (c, length) = self.eta(theta);
        let l = self.length_index();
        let rows = 4 + usize::from(self.weight.is_some());
        let mut g = nalgebra::DMatrix::zeros(rows, theta.len());
        for (i, k) in self.stiffness_index().into_iter().enumerate() {
            if k < theta.len() {
                g[(i, k)] = c[i];
            }
            if self.stiffness_per_length && l < theta.len() {
                g[(i, l)] = c[i] / length;
            }
        }
        if l < theta.len() {
            g[(3, l)] = 1.0;
        }
        if let Some(lambda) = self.linear_density(theta)
            && l + 1 < theta.len()
        {
            g[(4, l + 1)] = lambda;
        }
        g
    }

    /// For each of `c1, c2, c3`, the index in `θ` of the `ln c` it is (or is tied to).
    pub fn stiffness_index(&self) -> [usize; 3] {
        let i2 = usize::from(self.torsion_ratio.is_none());
        let i3 = if self.isotropic { i2 } else { i2 + 1 };
        [if self.torsion_ratio.is_none() { 0 } else { i2 }, i2, i3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn theta_round_trips_for_every_constraint() {
        let weights = [None, Some(Vector3::new(0.0, 0.0, -9.81))];
        for (isotropic, torsion_ratio, weight) in [
            (false, None, weights[0]),
            (true, None, weights[1]),
            (false, Some(0.8), weights[1]),
            (true, Some(0.8), weights[0]),
        ] {
            let k = ParameterConstraints {
                isotropic,
                torsion_ratio,
                stiffness_per_length: false,
                weight,
            };
            let c = [0.8 * 0.3, 0.3, if isotropic { 0.3 } else { 0.4 }];
            let theta = k.theta(c, 0.7, 0.02);
            assert_eq!(theta.len(), k.unknowns());
            assert_eq!(theta[k.length_index()], 0.7);
            let (lower, upper) = k.bounds(0.5);
            assert_eq!((lower.len(), upper.len()), (theta.len(), theta.len()));
            match k.linear_density(&theta) {
                Some(lambda) => assert!((lambda - 0.02).abs() < 1e-15),
                None => assert!(weight.is_none()),
            }
            let (back, length) = k.eta(&theta);
            for i in 0..3 {
                assert!((back[i] - c[i]).abs() < 1e-14);
            }
            assert!((length - 0.7).abs() < 1e-15);
            let idx = k.stiffness_index();
            for i in 0..3 {
                assert!(
                    (theta[idx[i]].exp() - c[i]).abs() < 1e-14 || torsion_ratio.is_some() && i == 0
                );
            }
        }
    }

    #[test]
    fn stiffnesses_per_length_round_trip_and_scale_the_box() {
        let k = ParameterConstraints {
            stiffness_per_length: true,
            ..ParameterConstraints::default()
        };
        let c = [0.2, 0.3, 0.4];
        let theta = k.theta(c, 0.5, 0.0);
        assert!((theta[1] - (0.3_f64 / 0.5).ln()).abs() < 1e-15);
        let (back, length) = k.eta(&theta);
        for i in 0..3 {
            assert!((back[i] - c[i]).abs() < 1e-15, "{back:?}");
        }
        assert_eq!(length, 0.5);
        let (lower, upper) = k.bounds(0.3);
        assert!((lower[1] - (C_MIN / L_MAX).ln()).abs() < 1e-15);
        assert!((upper[1] - (C_MAX / L_MIN).ln()).abs() < 1e-15);
        assert_eq!((lower[3], upper[3]), (0.3, L_MAX));
    }

    #[test]
    fn eta_jacobian_matches_central_differences() {
        let weights = [None, Some(Vector3::new(0.0, 0.0, -9.81))];
        for (isotropic, torsion_ratio, per_length, weight) in [
            (false, None, false, weights[0]),
            (false, None, true, weights[1]),
            (true, Some(0.8), true, weights[0]),
            (false, Some(0.8), false, weights[1]),
        ] {
            let k = ParameterConstraints {
                isotropic,
                torsion_ratio,
                stiffness_per_length: per_length,
                weight,
            };
            let theta = k.theta([0.21, 0.3, 0.37], 0.83, 0.02);
            let g = k.eta_jacobian(&theta);
            assert_eq!(
                (g.nrows(), g.ncols()),
                (4 + usize::from(weight.is_some()), theta.len())
            );
            let eta = |t: &[f64]| {
                let (c, length) = k.eta(t);
                let mut v = vec![c[0], c[1], c[2], length];
                v.extend(k.linear_density(t));
                v
            };
            let h = 1e-6;
            for j in 0..theta.len() {
                let (mut up, mut down) = (theta.clone(), theta.clone());
                up[j] += h;
                down[j] -= h;
                let (eu, ed) = (eta(&up), eta(&down));
                for i in 0..g.nrows() {
                    let fd = (eu[i] - ed[i]) / (2.0 * h);
                    assert!(
                        (fd - g[(i, j)]).abs() < 1e-8 * (1.0 + fd.abs()),
                        "∂η{i}/∂θ{j}: {} against {fd} ({k:?})",
                        g[(i, j)]
                    );
                }
            }
        }
    }

    #[test]
    fn wrong_length_is_not_finite() {
        let k = ParameterConstraints::default();
        let (c, length) = k.eta(&[0.0, 0.0]);
        assert!(!(c.iter().all(|v| v.is_finite()) && length.is_finite()));
    }
}
