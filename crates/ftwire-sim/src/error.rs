//! The error type of the simulator.

use ftwire_core::CoreError;
use thiserror::Error;

/// Everything that can go wrong when building or solving the simulated world.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SimError {
    /// An input that must be finite (and, for a parameter, positive) is not; the error names
    /// the field and the offending value.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// Too few edges to discretise the rod.
    #[error("the rod needs at least {min} edges, got {edges}")]
    TooFewEdges {
        /// Requested number of edges.
        edges: usize,
        /// Smallest number allowed.
        min: usize,
    },
    /// The clamp points are farther apart than the wire is long.
    #[error(
        "the grippers are {distance} m apart but the wire is only {length} m long; \
         move them to at most {length} m apart"
    )]
    GrippersTooFarApart {
        /// Distance between the clamp points \[m\].
        distance: f64,
        /// Wire length \[m\].
        length: f64,
    },
    /// An initial guess has the wrong number of points or frames.
    #[error("the initial guess has {got} {what}, the rod needs {expected}")]
    GuessSize {
        /// What was counted ("points" or "frames").
        what: &'static str,
        /// Number given.
        got: usize,
        /// Number needed.
        expected: usize,
    },
    /// An initial guess has an edge of (nearly) zero length.
    #[error("edge {edge} of the initial guess has zero length")]
    DegenerateGuess {
        /// Index of the degenerate edge.
        edge: usize,
    },
    /// Newton's method found no equilibrium, even after subdividing the motion.
    #[error(
        "no equilibrium found: Newton failed after {iterations} iterations \
         (residual {residual:e}, step halved {subdivisions} times); a Simulator keeps its last good state"
    )]
    NewtonFailed {
        /// Newton iterations in the last attempt.
        iterations: usize,
        /// Scaled gradient norm at the end of the last attempt.
        residual: f64,
        /// How many times the motion step was halved before giving up.
        subdivisions: usize,
    },
    /// A motion spent its work limit ([`crate::ContinuationParams::work_limit`]) before it
    /// reached its target.
    #[error(
        "no equilibrium found: the motion spent its work limit of {limit} Newton iterations \
         times edges ({iterations} iterations with {edges} edges) before reaching its target"
    )]
    WorkExhausted {
        /// Newton iterations spent by the motion.
        iterations: usize,
        /// Edges of the rod it was solved on.
        edges: usize,
        /// The limit, in Newton iterations times edges.
        limit: usize,
    },
    /// The operation needs a solved equilibrium but there is none yet.
    #[error("no equilibrium has been solved yet; call a solve method first")]
    NotSolved,
    /// A sensing or acting model failed: a bad setting, or a sensor dropout.
    #[error(transparent)]
    Sensing(#[from] crate::sensor::SensingError),
    /// A rig setting is out of its allowed range.
    #[error("rig setting {field} = {value:?} is not allowed: {allowed}")]
    RigSetting {
        /// Name of the setting.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
}
