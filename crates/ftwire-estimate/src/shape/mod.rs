//! Shape fitting from motion-capture markers (paper §IV-A, eq. 15) and shape estimation from
//! the calibrated F/T configuration `ã` (paper §II-B, §IV-C).
//!
//! - [`Markers`]: the markers of one frame that were seen, at known arc-length fractions.
//! - Metrics: [`centreline_distance`] (matched arc lengths) and [`marker_distances`] (each
//!   marker to the closest point of a polyline).
//!
//! Configurations are `(τ, f)` in \[N·m, N\], positions in \[m\], both in the base clamp
//! frame.

mod markers;
mod metrics;
mod polyline;

pub use markers::{DEFAULT_MARKER_COUNT, MIN_MARKERS, Marker, Markers, evenly_spaced_fractions};
pub use metrics::{
    DEFAULT_METRIC_SAMPLES, MIN_METRIC_SAMPLES, centreline_distance, marker_distances,
};
pub use polyline::{ClosestPoint, closest_point, cumulative_length};
