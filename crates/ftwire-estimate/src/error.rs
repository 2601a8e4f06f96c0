//! The error type of `ftwire-estimate`.

use ftwire_core::CoreError;
use ftwire_rod::RodError;
use thiserror::Error;

/// Errors of the estimators.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum EstimateError {
    /// Invalid shared data (for example non-finite or non-positive wire parameters).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// The wire model could not be solved.
    #[error(transparent)]
    Model(#[from] RodError),
    // Shape fitting and shape estimation (`shape/`).
    /// A marker frame gave a different number of positions than there are marker fractions.
    #[error(
        "{positions} marker positions were given for {fractions} marker fractions; give one \
         position (or None for a dropout) per fraction"
    )]
    MarkerCountMismatch {
        /// Number of marker fractions `s_k / L`.
        fractions: usize,
        /// Number of positions given.
        positions: usize,
    },
    /// A marker's arc-length fraction is not a finite number in `[0, 1]`.
    #[error("marker {marker} has arc-length fraction {fraction}; it must be finite and in [0, 1]")]
    BadMarkerFraction {
        /// Index of the marker.
        marker: usize,
        /// The offending fraction `s_k / L`.
        fraction: f64,
    },
    /// A marker position has a non-finite coordinate.
    #[error(
        "marker {marker} has coordinate {axis} = {value}, which is not finite; leave a marker \
         that was not seen out (None) instead"
    )]
    NonFiniteMarker {
        /// Index of the marker.
        marker: usize,
        /// The coordinate (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// The offending value \[m\].
        value: f64,
    },
    /// Too few markers were observed to fit a shape.
    #[error("only {observed} markers were observed; a shape fit needs at least {min}")]
    TooFewMarkers {
        /// Markers present in the frame.
        observed: usize,
        /// The fewest accepted.
        min: usize,
    },
    /// A shape fitting or estimation setting is out of its range.
    #[error("shape setting {name} = {value} is invalid; allowed: {allowed}")]
    BadShapeSetting {
        /// The setting's name.
        name: &'static str,
        /// The offending value.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A polyline given to a shape metric has too few points.
    #[error("polyline {name} has {points} points; at least {min} are needed")]
    TooFewPolylinePoints {
        /// Which polyline.
        name: &'static str,
        /// Its number of points.
        points: usize,
        /// The fewest accepted.
        min: usize,
    },
    /// A point given to a shape metric is not finite.
    #[error("{name}[{index}] has coordinate {axis} = {value}, which is not finite")]
    NonFinitePoint {
        /// Which list of points.
        name: &'static str,
        /// Index of the point.
        index: usize,
        /// The coordinate (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// The offending value \[m\].
        value: f64,
    },
    /// No start of the shape fit could be evaluated (every candidate diverged or was unstable).
    #[error(
        "the shape fit found no usable start in {attempts} attempts (every candidate diverged \
         or was unstable)"
    )]
    NoFitStart {
        /// Candidates tried.
        attempts: usize,
    },
}
