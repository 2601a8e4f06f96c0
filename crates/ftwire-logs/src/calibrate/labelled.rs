//! One labelled record of a recording: what the map and the drift term are fitted on.

use nalgebra::{Point3, Vector6};

/// One labelled record.
pub(super) struct Labelled {
    pub(super) line: usize,
    pub(super) time: f64,
    pub(super) raw: Vector6<f64>,
    pub(super) label: Vector6<f64>,
    pub(super) rms: f64,
    /// The observed inner markers (neither the first nor the last of the list), base clamp
    /// frame.
    pub(super) inner: Vec<Point3<f64>>,
    /// The observed markers the map's shape loss measures: every one but the first (at the
    /// clamp, where every shape is), base clamp frame.
    pub(super) loss_markers: Vec<Point3<f64>>,
    /// Their arc-length fractions, when the log's markers have known ones.
    pub(super) loss_fractions: Option<Vec<f64>>,
}
