//! Identification of a new wire, `η = (c1, c2, c3, L)`, from measured configurations `ã` and
//! second-gripper poses `b̃` (paper §III-B, eq. 8–12; §IV-B, Table I).
//!
//! Workflow:
//! 1. move the second gripper by small random moves near a stable start pose ([`MotionPlan`]),
//!    recording at each pose the tared, calibrated configuration `ã` (torque first, base clamp
//!    frame) and the pose `b̃` (base clamp frame);
//! 2. batch: [`identify`]`(model, &samples, &config, rng)`; streaming (a 10 Hz loop):
//!    [`Identifier::push`] each sample and [`Identifier::step`] within the tick's budget;
//! 3. check [`Estimate::unidentified`] (or call [`Estimate::identified`]) before trusting the
//!    estimate, and read its standard deviations.
//!
//! Pieces, one per file:
//! - [`residual`]: what is minimised: the exact absolute form `log(Γ_η(ã_i)⁻¹ b̃_i)` (default)
//!   or the paper's eq. 12, and their weighting;
//! - [`parameters`]: the search vector `(ln c, L)`, its box, and the constraints `c3 = c2`,
//!   `c1 = ν c2`;
//! - [`pso`]: a particle swarm with a streaming refresh (global search: the absolute form has
//!   local minima from a start 20 % off);
//! - [`refine`]: Levenberg–Marquardt from the swarm's best (local precision);
//! - [`identifier`]: the driver and the identifiability checks;
//! - [`estimate`]: the result and the reasons it may not be trusted;
//! - [`noise`]: the measurement noise the final fit is judged against;
//! - [`drift`]: the sensor bias all samples share (the tare's offset and its drift), which
//!   the final fit estimates with the wire;
//! - [`motion`]: how to move the second gripper.
//!
//! The model enters only through [`WireModel`](crate::WireModel), so a gravity-aware model can
//! replace [`KirchhoffModel`](crate::KirchhoffModel) without changing this module.

pub mod drift;
pub mod estimate;
pub mod identifier;
mod joint;
pub mod motion;
pub mod noise;
pub mod parameters;
pub mod pso;
pub mod refine;
pub mod residual;
pub mod sample;
mod shared;
pub mod unidentified;

pub use drift::BiasDrift;
pub use estimate::{Estimate, ParameterCovariance, Z95};
pub use identifier::{Identifier, IdentifierParams, identify, identify_samples};
pub use motion::MotionPlan;
pub use noise::MeasurementNoise;
pub use parameters::ParameterConstraints;
pub use pso::{CostFunction, Particle, ParticleSwarm, Swarm};
pub use refine::{LevenbergMarquardt, Refined};
pub use residual::{MAX_NORMALISED_LOAD, PENALTY, ResidualForm, Residuals, Weights, Whitening};
pub use sample::Sample;
pub use unidentified::Unidentified;
