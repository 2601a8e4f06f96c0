//! The error type of `ftwire-rod`.

use ftwire_core::CoreError;
use thiserror::Error;

/// Errors of the Kirchhoff wire model.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RodError {
    /// Invalid shared data (for example wire parameters or a non-finite configuration).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// The configuration lies on the excluded plane `a2 = a3 = a5 = a6 = 0`, outside `A`.
    #[error(
        "configuration a = {a:?} is outside A: a2 = a3 = a5 = a6 = 0 is the plane excluded by \
         eq. 2, where a does not determine the shape; at least one of a2, a3, a5, a6 must be \
         non-zero"
    )]
    OutsideA {
        /// The offending configuration `(τ1, τ2, τ3, f1, f2, f3)`.
        a: [f64; 6],
    },
    /// Too few shape nodes were asked for.
    #[error("nodes = {nodes} is too few; a shape needs at least {min} nodes (both ends)")]
    TooFewNodes {
        /// The requested number of nodes.
        nodes: usize,
        /// The smallest allowed number.
        min: usize,
    },
    /// Too many shape nodes were asked for.
    #[error("nodes = {nodes} is too many; at most {max} nodes are allowed")]
    TooManyNodes {
        /// The requested number of nodes.
        nodes: usize,
        /// The largest allowed number.
        max: usize,
    },
    /// The integrator was configured with an unusable number of steps.
    #[error("integrator steps = {steps} is outside the allowed range {min}..={max}")]
    BadSteps {
        /// The requested number of steps.
        steps: usize,
        /// The smallest allowed number.
        min: usize,
        /// The largest allowed number.
        max: usize,
    },
    /// The integration overflowed (a configuration far too large for the step count).
    #[error(
        "solving a = {a:?} produced non-finite values; the configuration is too large for \
         {steps} integration steps (use more steps or a smaller a)"
    )]
    Diverged {
        /// The configuration.
        a: [f64; 6],
        /// Integration steps used.
        steps: usize,
    },
    /// A sampling range was not a finite positive half-width.
    #[error("sampling half-width {half_width} must be finite and > 0")]
    BadSamplingRange {
        /// The offending half-width (normalised units).
        half_width: f64,
    },
    /// Rejection sampling did not find an accepted configuration within the attempt budget.
    #[error("no configuration of {set} found in {attempts} attempts")]
    SamplingExhausted {
        /// The set being sampled (`"A_stable"` or `"A_free"`).
        set: &'static str,
        /// Attempts made.
        attempts: usize,
    },
}
