//! The settings of the map fitted on the shape ([`ShapeLossParams`], its defaults and its
//! checks) and the records it is fitted on ([`ShapeSample`]): what a caller gives
//! [`fit_on_shape`](super::fit_on_shape).

use nalgebra::{Point3, Vector3, Vector6};
use serde::Serialize;

use crate::EstimateError;

/// The default [`ShapeLossParams::label_weight`].
pub const DEFAULT_LABEL_WEIGHT: f64 = 1.0;

/// One training or validation record: the map's input, a fixed offset, and the markers.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeSample {
    /// The reading, the map's input (force first, sensor frame \[N, N·m\]).
    pub raw: Vector6<f64>,
    /// Added to the map's output (the drift term at the record's time), torque first.
    pub offset: Vector6<f64>,
    /// The markers the loss measures, base clamp frame \[m\] (at least one).
    pub markers: Vec<Point3<f64>>,
    /// Their arc lengths as fractions of the wire's length; `None`: matched at their closest
    /// points.
    pub fractions: Option<Vec<f64>>,
}

/// Gravity's direction fitted with the map: the loaded model's weight `ρA |g| ĝ`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GravityFit {
    /// The wire's mass per length `ρA` \[kg/m\].
    pub mass_per_length: f64,
    /// `|g|` \[m/s²\].
    pub norm: f64,
    /// A first direction to start from (any length); `None`: the best of the six axis
    /// directions after a few iterations each.
    pub start: Option<[f64; 3]>,
}

/// How the map is fitted on the shape.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeLossParams {
    /// Candidate degrees of the polynomial part, each 2 or 3 (the affine map, degree 1, is
    /// always a candidate).
    pub degrees: Vec<usize>,
    /// Candidate ridge weights of the polynomial part, relative to the mean curvature of the
    /// loss in the affine weights; each finite and > 0.
    pub ridges: Vec<f64>,
    /// Most Gauss–Newton iterations of one candidate, ≥ 1.
    pub max_iterations: usize,
    /// Huber's threshold \[m\]; `None`: `1.345 ×` the robust scale (1.4826 × median) of the
    /// affine start's marker distances, at least 0.2 mm.
    pub huber: Option<f64>,
    /// Nodes of the shapes the closest points are found on, ≥ 2.
    pub nodes: usize,
    /// Weight of the labels beside the shape, relative to the shape's curvature in the
    /// affine weights (finite, ≥ 0): `½ β Σ |(a_i − ℓ_i) ⊘ σ_a|²` keeps the wrench directions
    /// the shape barely sees (a taut wire's tension) near the labels, which the shape alone
    /// leaves free to extrapolate.
    pub label_weight: f64,
    /// Fit gravity's direction too.
    pub gravity: Option<GravityFit>,
}

impl Default for ShapeLossParams {
    fn default() -> Self {
        Self {
            degrees: vec![2, 3],
            ridges: vec![1.0, 1e-1, 1e-2],
            max_iterations: 25,
            huber: None,
            nodes: 101,
            label_weight: DEFAULT_LABEL_WEIGHT,
            gravity: None,
        }
    }
}

impl ShapeLossParams {
    /// Checks the settings before any work.
    pub(super) fn validate(&self) -> Result<(), EstimateError> {
        #[allow(clippy::cast_precision_loss)] // small numbers
        if let Some(&d) = self.degrees.iter().find(|d| !(2..=3).contains(*d)) {
            return Err(EstimateError::InvalidSetting {
                field: "degrees",
                value: d as f64,
                allowed: "polynomial degrees 2 or 3",
            });
        }
        if let Some(&r) = self.ridges.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
            return Err(EstimateError::InvalidSetting {
                field: "ridges",
                value: r,
                allowed: "finite ridge weights > 0",
            });
        }
        #[allow(clippy::cast_precision_loss)] // small numbers
        for (field, value, least) in [
            ("max_iterations", self.max_iterations, 1),
            ("nodes", self.nodes, 2),
        ] {
            if value < least {
                return Err(EstimateError::InvalidSetting {
                    field,
                    value: value as f64,
                    allowed: "at least 1 iteration and 2 nodes",
                });
            }
        }
        if !(self.label_weight.is_finite() && self.label_weight >= 0.0) {
            return Err(EstimateError::InvalidSetting {
                field: "label_weight",
                value: self.label_weight,
                allowed: "a finite weight ≥ 0",
            });
        }
        if let Some(h) = self.huber
            && !(h.is_finite() && h > 0.0)
        {
            return Err(EstimateError::InvalidSetting {
                field: "huber",
                value: h,
                allowed: "a finite distance > 0 [m]",
            });
        }
        if let Some(g) = &self.gravity {
            for (field, value) in [
                ("gravity.mass_per_length", g.mass_per_length),
                ("gravity.norm", g.norm),
            ] {
                if !(value.is_finite() && value > 0.0 && value <= 1e3) {
                    return Err(EstimateError::InvalidSetting {
                        field,
                        value,
                        allowed: "a finite number in (0, 1000]",
                    });
                }
            }
            if let Some(s) = g.start {
                let norm = Vector3::from(s).norm();
                if !(norm.is_finite() && norm > 0.0) {
                    return Err(EstimateError::InvalidSetting {
                        field: "gravity.start",
                        value: norm,
                        allowed: "a finite direction of non-zero length",
                    });
                }
            }
        }
        Ok(())
    }
}
