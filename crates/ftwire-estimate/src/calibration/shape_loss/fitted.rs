//! What the map fitted on the shape returns: the chosen and the affine maps
//! ([`ShapeFitted`]), every candidate's report ([`Candidate`]) and gravity's starts
//! ([`GravityStart`]).

use serde::Serialize;

use crate::calibration::Calibration;

/// One candidate map as fitted.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Candidate {
    /// Its degree (1: the affine map).
    pub degree: usize,
    /// Its relative ridge weight (0 for the affine map).
    pub ridge: f64,
    /// Gauss–Newton iterations run.
    pub iterations: usize,
    /// Mean marker distance over the training records \[m\].
    pub train_marker_mean: f64,
    /// Mean marker distance over the validation records \[m\] (what chooses).
    pub validation_marker_mean: f64,
    /// Validation records whose shape could not be solved (counted before the distance).
    pub validation_failures: usize,
    /// Gravity in the clamp frame it ended with \[m/s²\] (with a gravity fit).
    pub gravity_in_clamp: Option<[f64; 3]>,
}

/// A gravity start and where the affine fit took it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GravityStart {
    /// The start direction (unit).
    pub start: [f64; 3],
    /// The direction after a few iterations (unit).
    pub end: [f64; 3],
    /// The training loss there (Huber, summed \[m²\]).
    pub loss: f64,
}

/// The map fitted on the shape.
#[derive(Debug, Clone)]
pub struct ShapeFitted {
    /// The chosen map (affine part, and a polynomial part when chosen).
    pub calibration: Calibration,
    /// The affine map fitted on the shape (the first candidate).
    pub affine: Calibration,
    /// Every candidate, the affine map first.
    pub candidates: Vec<Candidate>,
    /// The index of the chosen one.
    pub chosen: usize,
    /// Huber's threshold used \[m\].
    pub huber: f64,
    /// Gravity in the clamp frame of the chosen map \[m/s²\] (with a gravity fit).
    pub gravity_in_clamp: Option<[f64; 3]>,
    /// The gravity starts tried (with a gravity fit and no start given).
    pub gravity_starts: Vec<GravityStart>,
    /// Training records left out because the start map's shape could not be solved.
    pub train_failures: usize,
}
