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
