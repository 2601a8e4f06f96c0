//! Estimation from one wrist force/torque sensor (paper §III-A, §III-B, §IV-A to §IV-C).
//!
//! Algorithms here see the world only as a real robot would give it: raw F/T samples and the
//! gripper poses the robot believes it has (the `ftwire_core::Rig` boundary). They never depend
//! on the simulator.
//!
//! Conventions (see `DESIGN.md`): SI units; a configuration `a = (τ1, τ2, τ3, f1, f2, f3)` is
//! the wrench the wire exerts on the base gripper, **torque first**, in the base clamp frame;
//! raw F/T samples are **force first**, in the sensor frame; the second gripper's pose `b` is
//! relative to the base clamp frame.
//!
//! Every estimator takes its wire model through the [`WireModel`] trait, so that the paper's
//! Kirchhoff model ([`KirchhoffModel`]) can be swapped for a gravity-aware one without touching
//! the estimators.
//!
//! [`calibration`] learns the map from a raw F/T reading to `a` from labelled samples (§IV-A):
//! train a [`Calibration`] once, save it, load it in every command that reads the sensor.

pub mod calibration;
mod error;
pub mod ft;
pub mod identify;
pub mod log;
pub mod model;
pub mod shape;

pub use calibration::Calibration;
pub use error::EstimateError;
pub use model::{KirchhoffModel, WireModel};
