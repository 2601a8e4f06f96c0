//! From `ã` to the wire's shape: the immutable [`Measurement`], its pure [`Measurement::solve`]
//! of one `ã`, and the flag of a solved sample ([`ShapeConfidence`]).

use ftwire_core::ensure_finite;
use ftwire_estimate::shape::{
    Confidence, ModelError, ShapeEstimator, marker_distances, shape_sigma, with_model_error,
};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_rod::Shape;
use nalgebra::{Matrix6, Point3, Vector6};
use serde::{Deserialize, Serialize};

use crate::{RawMap, Reading, RigError};

/// Default number of points of each shape, evenly spaced in arc length, both ends included.
pub const DEFAULT_POINTS: usize = 100;

/// Fewest points of a shape: its two ends.
pub const MIN_POINTS: usize = 2;

/// Most points of a shape: at 10 000 points a record's line is about 600 kB.
pub const MAX_POINTS: usize = 10_000;

/// Nodes of the centreline the markers are measured against (the inner-marker metric). A
/// chord `s` of a bend of radius `R` sags `s²/(8R)` from the curve: with `s = L/99`, 0.1 mm
/// for the 630 mm wire bent to a 5 cm radius.
pub const MARKER_NODES: usize = 100;

/// Default jump threshold (normalised units: torque in `c2/L`, force in `c2/L²`): the shape
/// estimator's default ([`ftwire_estimate::shape::EstimatorParams`]).
pub const DEFAULT_JUMP_THRESHOLD: f64 = 2.0;

/// Settings of a [`Measurement`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasurementParams {
    /// Points of each shape, [`MIN_POINTS`] to [`MAX_POINTS`] (default [`DEFAULT_POINTS`]).
    pub points: usize,
    /// A change of `ã` from the previous sample larger than this, in normalised units, flags
    /// a jump (a possible contact; default [`DEFAULT_JUMP_THRESHOLD`]).
    pub jump_threshold: f64,
    /// The model's own error `e` per metre of arc length \[m/m\]: each `σ(s)` adds
    /// `σ_model(s) = e · s` in quadrature (`None`: not counted).
    pub model_error: Option<ModelError>,
}

impl Default for MeasurementParams {
    fn default() -> Self {
        Self {
            points: DEFAULT_POINTS,
            jump_threshold: DEFAULT_JUMP_THRESHOLD,
            model_error: None,
        }
    }
}

/// How a reading becomes `ã` and a shape: the map ([`RawMap`]), the wire's model (weight-free
/// or loaded: [`crate::WireModelChoice`]) and the settings. Immutable and shared by every
/// stream; its [`Measurement::solve`] is pure, so many samples can be solved in parallel and
/// flagged in order afterwards ([`crate::Stream::flag`]).
#[derive(Debug, Clone)]
pub struct Measurement {
    map: RawMap,
    model: KirchhoffModel,
    params: MeasurementParams,
}

/// One `ã` solved: the shape, its stability and its error bars.
#[derive(Debug, Clone, PartialEq)]
pub struct Solved {
    /// The centreline \[m\] and frames at the measurement's points, base clamp frame.
    pub shape: Shape,
    /// Whether `ã ∈ A_stable`.
    pub stable: bool,
    /// `σ(s)` \[m\] at each point: the RMS radius of the point's first-order error
    /// `sqrt(trace D Σ_ã Dᵀ)`, with the model's error in quadrature; `None` without the
    /// covariance of `ã`, or when a shifted `ã` of the differences has no shape.
    pub sigma: Option<Vec<f64>>,
}

/// Whether a shape can be relied on, and if not why (serialised as `confident`,
/// `not_stable`, `jump`, `no_shape`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShapeConfidence {
    /// `ã ∈ A_stable` and close to the previous sample.
    Confident,
    /// `ã ∉ A_stable`: the model's shape is an equilibrium the wire cannot rest in.
    NotStable,
    /// `ã` jumped from the previous sample by more than the threshold: a possible contact.
    Jump,
    /// The model has no shape for `ã` (outside `A`, a diverged solve).
    NoShape,
}

impl ShapeConfidence {
    /// The flag's name, as serialised: `confident`, `not_stable`, `jump` or `no_shape`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Confident => "confident",
            Self::NotStable => "not_stable",
            Self::Jump => "jump",
            Self::NoShape => "no_shape",
        }
    }

    /// Whether the shape is confident.
    pub fn is_confident(self) -> bool {
        self == Self::Confident
    }

    /// Whether the model has a stable shape (`confident` or `jump`).
    pub fn is_stable(self) -> bool {
        matches!(self, Self::Confident | Self::Jump)
    }
}

impl From<Confidence> for ShapeConfidence {
    fn from(confidence: Confidence) -> Self {
        match confidence {
            Confidence::Confident => Self::Confident,
            Confidence::NotStable => Self::NotStable,
            Confidence::Jump { .. } => Self::Jump,
        }
    }
}

impl Measurement {
    /// The measurement of `map` and `model` with `params`.
    ///
    /// # Errors
    /// [`RigError::Setting`] for points outside `[MIN_POINTS, MAX_POINTS]` or a jump threshold
    /// that is not finite and positive.
    pub fn new(
        map: RawMap,
        model: KirchhoffModel,
        params: MeasurementParams,
    ) -> Result<Self, RigError> {
        if !(MIN_POINTS..=MAX_POINTS).contains(&params.points) {
            return Err(RigError::Setting(format!(
                "points = {} is not allowed: {MIN_POINTS} to {MAX_POINTS} points of a shape",
                params.points
            )));
        }
        if !(params.jump_threshold.is_finite() && params.jump_threshold > 0.0) {
            return Err(RigError::Setting(format!(
                "jump threshold = {} is not allowed: finite and > 0 (normalised units)",
                params.jump_threshold
            )));
        }
        Ok(Self { map, model, params })
    }

    /// The map from a reading to `ã`.
    pub fn map(&self) -> &RawMap {
        &self.map
    }

    /// The wire's model.
    pub fn model(&self) -> &KirchhoffModel {
        &self.model
    }

    /// The settings.
    pub fn params(&self) -> &MeasurementParams {
        &self.params
    }

    /// The reading's `ã` ([`RawMap::a_tilde`]).
    ///
    /// # Errors
    /// As [`RawMap::a_tilde`].
    pub fn a_tilde(&self, reading: &Reading) -> Result<Vector6<f64>, RigError> {
        self.map.a_tilde(reading)
    }

    /// The shape of `a` at the measurement's points, its stability, and with the covariance
    /// `a_covariance` of `ã` its error bars; `Err` says why the model has no shape.
    ///
    /// # Errors
    /// Why the model has no shape: a non-finite `ã`, `ã ∉ A`, a diverged solve.
    pub fn solve(
        &self,
        a: &Vector6<f64>,
        a_covariance: Option<&Matrix6<f64>>,
    ) -> Result<Solved, String> {
        ensure_finite("a_tilde", a.as_slice()).map_err(|e| e.to_string())?;
        let points = self.params.points;
        let shape = self.model.shape(a, points).map_err(|e| e.to_string())?;
        let stable = self.model.is_stable(a).map_err(|e| e.to_string())?;
        let sigma = a_covariance.and_then(|covariance| {
            shape_sigma(&self.model, a, points, covariance)
                .ok()
                .map(|sigma| match &self.params.model_error {
                    Some(e) => with_model_error(&sigma.sigma, e, self.model.wire().length()),
                    None => sigma.sigma,
                })
        });
        Ok(Solved {
            shape,
            stable,
            sigma,
        })
    }

    /// [`inner_marker_mean`] of `a` with this measurement's model, reusing `solved`'s shape
    /// when it has [`MARKER_NODES`] points.
    ///
    /// # Errors
    /// As [`inner_marker_mean`].
    pub fn inner_marker_mean(
        &self,
        a: &Vector6<f64>,
        markers: &[Option<[f64; 3]>],
        solved: &Solved,
    ) -> Result<Option<f64>, String> {
        let reuse = (self.params.points == MARKER_NODES).then_some(&solved.shape);
        inner_markers_to(&self.model, a, markers, reuse)
    }

    /// A new jump flag for a stream of this measurement.
    pub(crate) fn flagger(&self) -> ShapeEstimator<KirchhoffModel> {
        let config = ftwire_estimate::shape::EstimatorParams {
            jump_threshold: self.params.jump_threshold,
            ..Default::default()
        };
        // The threshold was checked in `new`; the node count is the estimator's default.
        ShapeEstimator::new(self.model)
            .with_config(config)
            .unwrap_or_else(|_| ShapeEstimator::new(self.model))
    }
}

/// The paper's marker metric: the mean distance \[m\] of the inner markers (all but the
/// first, at the clamp, and the last, at the gripper) to `model`'s centreline of `a` at
/// [`MARKER_NODES`] nodes, so that it does not depend on how many points a shape is drawn
/// with; `None` without an inner marker seen. Markers not seen are `None`.
///
/// # Errors
/// Why there is no distance: the model has no shape for `a`, or a marker is not finite.
pub fn inner_marker_mean(
    model: &KirchhoffModel,
    a: &Vector6<f64>,
    markers: &[Option<[f64; 3]>],
) -> Result<Option<f64>, String> {
    inner_markers_to(model, a, markers, None)
}

fn inner_markers_to(
    model: &KirchhoffModel,
    a: &Vector6<f64>,
    markers: &[Option<[f64; 3]>],
    curve: Option<&Shape>,
) -> Result<Option<f64>, String> {
    let inner: Vec<Point3<f64>> = markers
        .get(1..markers.len().saturating_sub(1))
        .unwrap_or(&[])
        .iter()
        .flatten()
        .map(|p| Point3::from(*p))
        .collect();
    if inner.is_empty() {
        return Ok(None);
    }
    let dense = match curve {
        Some(_) => None,
        None => Some(model.shape(a, MARKER_NODES).map_err(|e| e.to_string())?),
    };
    let curve = curve.or(dense.as_ref()).ok_or("no centreline")?;
    let d = marker_distances(&inner, &curve.positions).map_err(|e| e.to_string())?;
    #[allow(clippy::cast_precision_loss)] // a handful of markers
    Ok(Some(d.iter().sum::<f64>() / d.len() as f64))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_flags_name_is_its_serialised_form() {
        use ShapeConfidence as C;
        for flag in [C::Confident, C::NotStable, C::Jump, C::NoShape] {
            let json = serde_json::to_value(flag).expect("serialises");
            assert_eq!(json.as_str(), Some(flag.name()), "{flag:?}");
        }
    }
}
