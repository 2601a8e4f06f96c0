//! The one record of a shape, as every front end prints, writes and publishes it.
//!
//! ```json
//! {"line": 3, "time": 0.2, "a": [τ1, τ2, τ3, f1, f2, f3], "points": [[x, y, z], …], "sigma": [σ, …], "stable": true, "confident": true, "confidence": "confident", "marker_mean_mm": 1.2}
//! ```
//!
//! `line` is the record's line in its log (from 1) or the sample's index in a stream (from 0),
//! `time` its time \[s\], `a` its `ã` (torque first, base clamp frame, N·m and N), `points`
//! the centreline evenly spaced in arc length from the base clamp to the tip (base clamp
//! frame, m), `sigma` (only with error bars) `σ(s)` at each point \[m\], `stable` whether
//! `ã ∈ A_stable`, `confident` whether the shape is stable and no jump, `confidence` the
//! typed flag ([`ShapeConfidence`]), `marker_mean_mm` (only with inner markers) the inner
//! markers' mean distance to the centreline \[mm\], and `error` (only without a shape) why
//! the model has none; such a record has `"points": []`.

use serde::{Deserialize, Serialize};

use crate::{ShapeConfidence, Solved};

/// One shape record (the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShapeRecord {
    /// The record's line in its log (from 1), or the sample's index in a stream.
    pub line: usize,
    /// The record's time \[s\].
    pub time: f64,
    /// `ã` (torque first, base clamp frame) \[N·m ×3, N ×3\].
    pub a: [f64; 6],
    /// The centreline \[m\], base clamp frame; empty without a shape.
    pub points: Vec<[f64; 3]>,
    /// `σ(s)` at each point \[m\], with error bars.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<Vec<f64>>,
    /// Whether `ã ∈ A_stable` (false without a shape).
    pub stable: bool,
    /// Whether the shape is confident: stable and no jump.
    pub confident: bool,
    /// The flag.
    pub confidence: ShapeConfidence,
    /// The inner markers' mean distance to the centreline \[mm\], with inner markers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub marker_mean_mm: Option<f64>,
    /// Why the model has no shape.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

impl ShapeRecord {
    /// The record of `solved` (or why there is no shape) at `line` and `time`, for `a`, with
    /// its flag and the inner markers' mean distance \[m\].
    pub fn new(
        (line, time): (usize, f64),
        a: &nalgebra::Vector6<f64>,
        solved: &Result<Solved, String>,
        confidence: ShapeConfidence,
        marker_mean: Option<f64>,
    ) -> Self {
        let (points, sigma, error) = match solved {
            Ok(s) => (
                s.shape.positions.iter().map(|p| [p.x, p.y, p.z]).collect(),
                s.sigma.clone(),
                None,
            ),
            Err(why) => (Vec::new(), None, Some(why.clone())),
        };
        Self {
            line,
            time,
            a: (*a).into(),
            points,
            sigma,
            stable: confidence.is_stable(),
            confident: confidence.is_confident(),
            confidence,
            marker_mean_mm: marker_mean.map(|m| 1e3 * m),
            error,
        }
    }

    /// The tip, the last point, if there is a shape.
    pub fn tip(&self) -> Option<[f64; 3]> {
        self.points.last().copied()
    }
}

/// One line of text: the flag and the tip (± its σ, markers), or why there is no shape.
impl std::fmt::Display for ShapeRecord {
    fn fmt(&self, out: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let head = format!("line {} t = {:.3} s", self.line, self.time);
        let Some(tip) = self.tip() else {
            return writeln!(
                out,
                "{head}: no shape: {}",
                self.error.as_deref().unwrap_or("unknown")
            );
        };
        let sigma = self
            .sigma
            .as_ref()
            .and_then(|s| s.last())
            .map_or_else(String::new, |s| format!(" ± {:.2} mm", 1e3 * s));
        let markers = self
            .marker_mean_mm
            .map_or_else(String::new, |m| format!(", markers {m:.2} mm"));
        let flag = self.confidence.name();
        writeln!(
            out,
            "{head}: {flag}, tip at ({:.4}, {:.4}, {:.4}) m{sigma}{markers}",
            tip[0], tip[1], tip[2]
        )
    }
}
