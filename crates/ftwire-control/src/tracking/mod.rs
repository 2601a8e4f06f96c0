//! Path tracking (paper §IV-D–E, and beyond it): a planned list of waypoints executed closed
//! loop on any [`ftwire_core::Rig`].
//!
//! - [`TrackingPolicy`]: every tuning choice of the execution, per execution noise
//!   ([`TrackingPolicy::for_noise`]): the legs' controller settings and stops, the retreats,
//!   undos and relocation, and the success rule ([`TrackingPolicy::judge`]); a user's
//!   gain and stops over it, each checked ([`TrackingPolicy::with_settings`]).
//! - [`PathTracker`]: the controller (eq. 13–14) toward each waypoint in turn under that
//!   policy, with an optional collision detector and bias observer; a caller with ground
//!   truth reads it in the observer called at every [`Rest`].

mod policy;
mod tracker;

pub use policy::{
    DIVERGENCE_NOISY, EPSILON_GOAL, EPSILON_NOISY, EPSILON_THROUGH, EPSILON_THROUGH_NOISY,
    GOAL_REST_SAMPLES, LATE_FRACTION, MAX_ITERATIONS_NOISY, MAX_ITERATIONS_THROUGH,
    MAX_ITERATIONS_THROUGH_NOISY, MAX_RETREATS, MAX_UNDOS, RELOCATION_STEPS, SHAPE_STOP_NEAR_NOISY,
    SHAPE_STOP_NOISY, SUCCESS_EPSILON, TrackingPolicy, Verdict,
};
pub use policy::{PolicyError, PolicySettings};
pub use tracker::{PathTracker, Relocate, Rest, RestKind, TrackEnd, Tracked, TrackedLeg};
