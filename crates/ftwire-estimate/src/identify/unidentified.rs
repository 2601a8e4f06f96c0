//! Why an identification estimate is not trusted.

use thiserror::Error;

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
