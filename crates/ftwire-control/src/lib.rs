//! Control of an elastic wire from one wrist F/T sensor (paper §III-C, §IV-D, §IV-E).
//!
//! Workflow:
//! 1. Build an [`FtFeedback`] around the estimation crate's F/T pipeline (tared, calibrated):
//!    it turns the samples of one rest into the measured configuration `ã`.
//! 2. Build a [`Controller`] for a [`ftwire_estimate::WireModel`] (the paper's weightless
//!    Kirchhoff rod, or the loaded one) with [`ControlParams`] (gain `K`, stop threshold `ε`,
//!    step limits, iteration limit), optionally with a [`CollisionDetector`] calibrated on free
//!    motion.
//! 3. [`Controller::run`] steers any [`ftwire_core::Rig`] to a goal `a_g ∈ A_stable` by eq.
//!    13–14, checking every pose with a [`ReachCheck`] ([`RobotReach`] for the SDA10F,
//!    [`AnyPose`] to ignore the robot), and ends with a typed [`Outcome`]. After a detected
//!    contact, [`retreat()`] goes back along the run. [`Controller::run_with_bias_observer`] steers by
//!    `ã` corrected for the sensor's bias drift by a [`BiasObserver`].
//! 4. [`PathTracker`] executes a planned list of waypoints under a [`TrackingPolicy`] (the
//!    legs' stops, retreat, undo, relocation and the success rule per execution noise).
//! 5. The open-loop baselines are in [`open_loop`]; execution noise as the paper adds it, and
//!    two more realistic models, wrap any rig in [`NoisyRig`].
//!
//! Conventions: `a = (τ1, τ2, τ3, f1, f2, f3)`, torque first, the wire's wrench on the base
//! gripper in the base clamp frame; `b` is the second clamp's pose in the base clamp frame and
//! `δb = (w δθ, δx)` rotation first (eq. 8–10); distances in `A` are in normalised units
//! (torque in `c2/L`, force in `c2/L²`; `ftwire_rod::to_normalised`).

mod bias;
mod collision;
mod controller;
mod error;
mod feedback;
mod noise;
pub mod open_loop;
mod reach;
mod retreat;
pub mod tracking;

pub use bias::{BiasObserver, BiasObserverParams};
pub use collision::{
    CollisionDetector, MIN_CALIBRATION_RESIDUALS, MoveCheck, SLOPE_QUANTILE, configuration_at,
    miss, predicted_change, predicted_delta_a,
};
pub use controller::{
    ControlParams, Controller, DIVERGED_RESTS, Outcome, Run, SHAPE_STOP_SAMPLES, StepPlan,
    StepRecord,
};
pub use error::ControlError;
pub use feedback::FtFeedback;
pub use noise::{NoiseModel, NoiseParams, NoisyRig};
pub use reach::{AnyPose, Reach, ReachCheck, RobotReach};
pub use retreat::{Retreat, retreat};
pub use tracking::{
    PathTracker, Relocate, Rest, RestKind, TrackEnd, Tracked, TrackedLeg, TrackingPolicy, Verdict,
};
