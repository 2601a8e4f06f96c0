//! The result of identification: `η = (c, L)`, its uncertainty, and whether the data identify
//! it.

use ftwire_core::WireParams;
use thiserror::Error;

use crate::EstimateError;

/// Why an estimate is not trusted.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum Unidentified {
    /// The normalised Jacobian of the residual is nearly rank-deficient: some combination of
    /// parameters barely changes the residual, so the data cannot fix it.
    #[error(
        "the residual's Jacobian has relative smallest singular value {condition:e} < \
         {threshold:e}: some combination of parameters is not determined by these data; move the \
         second gripper more, in more directions"
    )]
    IllConditioned {
        /// `σ_min/σ_max` of `∂r/∂(ln c, ln L)`.
        condition: f64,
        /// The smallest accepted value.
        threshold: f64,
    },
    /// The best fit explains the data far worse than the measurement noise would.
    #[error(
        "the best fit leaves χ²/dof = {chi2_per_dof:.3e}, above {threshold}: the model does not \
         fit these data at the assumed noise (wrong basin, untared sensor, or a load the model \
         lacks)"
    )]
    ResidualAboveNoise {
        /// The noise-normalised cost per degree of freedom.
        chi2_per_dof: f64,
        /// The largest accepted value.
        threshold: f64,
    },
    /// A parameter ended on the search box's edge: the optimum may lie outside it.
    #[error("parameter {index} of the search vector ended on the search box's edge ({value})")]
    AtBound {
        /// Index in the search vector (see `identify::parameters`).
        index: usize,
        /// Its value (`ln c` or `L`).
        value: f64,
    },
    /// The search stopped (time budget) before refinement; a provisional estimate.
    #[error("the search is unfinished: {iterations} of {required} swarm iterations, not refined")]
    Unfinished {
        /// Swarm iterations run on the current data.
        iterations: usize,
        /// Swarm iterations required before refinement.
        required: usize,
    },
}

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
