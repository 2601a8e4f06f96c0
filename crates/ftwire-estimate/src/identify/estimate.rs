//! The result of identification: `η = (c, L)`, its uncertainty, and whether the data identify
//! it.

use super::Unidentified;
use crate::EstimateError;
use ftwire_core::WireParams;

/// Identified wire parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Stiffnesses `(c1, c2, c3)` \[N·m²\].
    pub c: [f64; 3],
    /// Length `L` \[m\].
    pub length: f64,
    /// Standard deviations of `c` \[N·m²\], from `s² (JᵀJ)⁻¹` with `s²` the residual
    /// variance per degree of freedom (first order; infinite if unavailable).
    pub c_std: [f64; 3],
    /// Standard deviation of `L` \[m\] (as `c_std`).
    pub length_std: f64,
    /// The linear density `λ` \[kg/m\], when it was identified
    /// ([`super::ParameterConstraints::weight`]).
    pub linear_density: Option<f64>,
    /// Standard deviation of `λ` \[kg/m\] (as `c_std`), when it was identified.
    pub linear_density_std: Option<f64>,
    /// The weighted cost `Σ‖r_i‖²` at the estimate.
    pub cost: f64,
    /// `χ²` per degree of freedom under the configured noise model (about 1 for a fit as good
    /// as the noise allows).
    pub chi2_per_dof: f64,
    /// `σ_min/σ_max` of the residual's Jacobian in `(ln c, ln L)`.
    pub condition: f64,
    /// Samples used.
    pub samples: usize,
    /// Residual evaluations spent so far (each is one model solve per sample).
    pub evaluations: usize,
    /// `None` when the data identify `η`; otherwise why not.
    pub unidentified: Option<Unidentified>,
    /// The first-order covariance of `(c1, c2, c3, L)`, and `λ` when it was identified;
    /// `None` where the fit's information matrix is singular or the search was not refined.
    pub covariance: Option<ParameterCovariance>,
}

/// Two-sided 95 % quantile of the standard normal distribution.
pub const Z95: f64 = 1.959_963_984_540_054;

/// The covariance of the identified parameters, in the order `(c1, c2, c3, L)` then `λ`
/// \[N·m², m, kg/m\]: `Σ_η = G s² (JᵀJ)⁻¹ Gᵀ`, the fit's covariance in the search vector
/// `θ` carried to `η` by `G = ∂η/∂θ`
/// ([`ParameterConstraints::eta_jacobian`](super::ParameterConstraints::eta_jacobian)).
/// Tied parameters are fully correlated with what they are tied to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParameterCovariance {
    dim: usize,
    entries: [[f64; 5]; 5],
}

impl ParameterCovariance {
    /// The covariance of `dim` (4 or 5) parameters from its rows; `None` for another size,
    /// a non-square or non-finite matrix.
    pub fn from_matrix(m: &nalgebra::DMatrix<f64>) -> Option<Self> {
        let dim = m.nrows();
        if !(4..=5).contains(&dim) || m.ncols() != dim || m.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let mut entries = [[0.0; 5]; 5];
        for (i, row) in entries.iter_mut().enumerate().take(dim) {
            for (j, e) in row.iter_mut().enumerate().take(dim) {
                // Symmetrised: the product G Σ Gᵀ is symmetric up to rounding.
                *e = 0.5 * (m[(i, j)] + m[(j, i)]);
            }
        }
        Some(Self { dim, entries })
    }

    /// The number of parameters: 4, or 5 with `λ`.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The rows, `dim × dim`.
    pub fn rows(&self) -> Vec<Vec<f64>> {
        self.entries[..self.dim]
            .iter()
            .map(|row| row[..self.dim].to_vec())
            .collect()
    }

    /// The standard deviation of parameter `i` (`NaN` past `dim`).
    pub fn std(&self, i: usize) -> f64 {
        if i < self.dim {
            self.entries[i][i].max(0.0).sqrt()
        } else {
            f64::NAN
        }
    }
}

impl Estimate {
    /// The estimated wire, with the given radius \[m\] (identification does not estimate it).
    ///
    /// # Errors
    /// [`EstimateError::Core`] if the radius is not finite and positive.
    pub fn wire(&self, radius: f64) -> Result<WireParams, EstimateError> {
        Ok(WireParams::new(self.c, self.length, radius)?)
    }

    /// Whether the data identify `η` (no flag raised).
    pub fn is_identified(&self) -> bool {
        self.unidentified.is_none()
    }

    /// The identified values in the covariance's order: `(c1, c2, c3, L)`, then `λ` when it
    /// was identified.
    pub fn values(&self) -> Vec<f64> {
        let mut v = vec![self.c[0], self.c[1], self.c[2], self.length];
        v.extend(self.linear_density);
        v
    }

    /// The 95 % interval `[value − z σ, value + z σ]` (`z` = [`Z95`]) of each parameter in the
    /// order of [`Self::values`], from the first-order covariance; `None` without one.
    pub fn interval95(&self) -> Option<Vec<[f64; 2]>> {
        let cov = self.covariance.as_ref()?;
        Some(
            self.values()
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    let half = Z95 * cov.std(i);
                    [v - half, v + half]
                })
                .collect(),
        )
    }

    /// The estimate if identified.
    ///
    /// # Errors
    /// [`EstimateError::NotIdentified`] with the reason otherwise.
    pub fn identified(self) -> Result<Self, EstimateError> {
        match self.unidentified {
            None => Ok(self),
            Some(reason) => Err(EstimateError::NotIdentified { reason }),
        }
    }
}
