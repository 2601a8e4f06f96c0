//! One sample as a rig gives it, before any map.

use ftwire_estimate::log::LogRecord;
use nalgebra::{Vector3, Vector6};

/// One F/T sample at time `time`, as a rig records or streams it.
///
/// A reading carries either the sensor's `raw` reading or an `ã` that was computed elsewhere
/// (`a`); when it has both, `raw` is used. `gravity` is needed only when the mounting has a
/// tool whose weight is taken out of `raw`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reading {
    /// The sample's time \[s\]: the rig's own clock (Unix time or time since the start).
    pub time: f64,
    /// The sensor's reading, force first \[N ×3, N·m ×3\], sensor frame, not tared.
    pub raw: Option<Vector6<f64>>,
    /// `ã` computed elsewhere, torque first \[N·m ×3, N ×3\], base clamp frame.
    pub a: Option<Vector6<f64>>,
    /// Gravity in the sensor frame \[m/s²\] at this sample, for the tool's weight.
    pub gravity: Option<Vector3<f64>>,
}

impl Reading {
    /// A raw reading (force first, sensor frame) at `time` \[s\], without gravity.
    pub fn raw(time: f64, raw: Vector6<f64>) -> Self {
        Self {
            time,
            raw: Some(raw),
            a: None,
            gravity: None,
        }
    }

    /// An `ã` (torque first, base clamp frame) at `time` \[s\].
    pub fn configuration(time: f64, a: Vector6<f64>) -> Self {
        Self {
            time,
            raw: None,
            a: Some(a),
            gravity: None,
        }
    }

    /// The same reading with gravity `gravity` \[m/s²\] in the sensor frame.
    #[must_use]
    pub fn with_gravity(self, gravity: Option<Vector3<f64>>) -> Self {
        Self { gravity, ..self }
    }
}

impl From<&LogRecord> for Reading {
    fn from(record: &LogRecord) -> Self {
        Self {
            time: record.time,
            raw: record.raw(),
            a: record.a(),
            gravity: record.gravity.map(Vector3::from),
        }
    }
}
