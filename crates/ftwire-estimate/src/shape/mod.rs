//! Shape fitting from motion-capture markers (paper §IV-A, eq. 15) and shape estimation from
//! the calibrated F/T configuration `ã` (paper §II-B, §IV-C).
//!
//! - [`Markers`]: the markers of one frame that were seen, at known arc-length fractions.
//! - [`ShapeFitter`]: markers → `a` (eq. 15), a global stage ([`GlobalSearch`],
//!   [`MultiStart`]) then Levenberg–Marquardt ([`LevenbergMarquardt`]) with the analytic
//!   derivative of each marker position ([`centreline_point`]). It labels the calibration
//!   data.
//! - [`ShapeEstimator`]: `ã` → the centreline at sensor rate, with a [`Confidence`] flag
//!   and, given the standard deviations of `ã` ([`ConfigurationStd`]), the standard deviation
//!   of each point ([`shape_sigma`]: `Σ_p = D Σ_ã Dᵀ` to first order).
//! - Metrics: [`centreline_distance`] (matched arc lengths) and [`marker_distances`] (each
//!   marker to the closest point of a polyline).
//!
//! Everything is generic over the [`crate::WireModel`], so a gravity-aware model can be swapped
//! in. Configurations are `(τ, f)` in \[N·m, N\], positions in \[m\], both in the base clamp
//! frame.

mod centreline_point;
mod estimate;
mod fit;
mod global;
mod levenberg_marquardt;
mod markers;
mod metrics;
mod polyline;
mod setting;
mod sigma;

pub use centreline_point::{CentrelinePoint, centreline_point};
pub use estimate::{
    Confidence, EstimatorParams, MIN_ESTIMATE_NODES, ShapeEstimate, ShapeEstimator,
};
pub use fit::{Correspondence, FitParams, ShapeFit, ShapeFitter};
pub use global::{GlobalSearch, MultiStart, SwarmSearch};
pub use levenberg_marquardt::{LevenbergMarquardt, Termination};
pub use markers::{DEFAULT_MARKER_COUNT, MIN_MARKERS, Marker, Markers, evenly_spaced_fractions};
pub use metrics::{
    DEFAULT_METRIC_SAMPLES, MIN_METRIC_SAMPLES, centreline_distance, marker_distances,
};
pub use polyline::{ClosestPoint, closest_point, cumulative_length};
pub use sigma::{
    ConfigurationStd, MAX_MODEL_ERROR, ModelError, RELATIVE_STEP, ShapeSigma, shape_jacobians,
    shape_sigma, with_model_error,
};
