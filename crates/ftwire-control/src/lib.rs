#![doc = include_str!("../README.md")]

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

pub use bias::{BiasObserver, BiasObserverParams, fuses_rest};
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
