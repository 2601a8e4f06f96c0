//! The simulated sensor's true bias drift, published by `ftwire ros2 sim` on
//! [`TRUTH_BIAS_TOPIC`] for tests: what `ftwire ros2 estimate`'s bias observer estimates.
//!
//! The estimator tares on the sim's first `tare_samples` samples (read with an empty gripper),
//! which removes their mean bias; what is left in every later reading is the drift since then,
//! `b(t) − mean over the tare of b`. Mapped through the sensor's mounting (the simulated
//! sensor's `sensor_from_clamp`, the map an estimator without calibration uses) it is the bias
//! in `A` that the observer's `β̂` estimates. Published as `std_msgs/String` JSON:
//! `{"stamp", "bias", "raw"}`: `bias` torque first in the base clamp frame \[N·m, N\], `raw`
//! force first in the sensor frame \[N, N·m\].

use ftwire_estimate::ft::Mounting;
use ftwire_lab::experiment::rig::mounting;
use ftwire_sim::{RigParams, SimRig};
use nalgebra::Vector6;
use serde::Serialize;

use super::NodeError;
use crate::msg::StringMsg;

/// The simulated sensor's true bias drift since the tare (ground truth, for tests).
pub const TRUTH_BIAS_TOPIC: &str = "/wire/truth_bias";

/// The true bias at the tare and the map to `A`.
pub struct TruthBias {
    mounting: Mounting,
    sum: Vector6<f64>,
    samples: u64,
}

#[derive(Serialize)]
struct Message {
    stamp: f64,
    bias: [f64; 6],
    raw: [f64; 6],
}

impl TruthBias {
    /// For the rig built from `config`.
    ///
    /// # Errors
    /// [`NodeError::Lab`] for a sensor mounting that is not finite.
    pub fn new(config: &RigParams) -> Result<Self, NodeError> {
        Ok(Self {
            mounting: mounting(config)?,
            sum: Vector6::zeros(),
            samples: 0,
        })
    }

    /// Takes the true bias of a tare sample just read.
    pub fn tare_sample(&mut self, rig: &SimRig) {
        self.sum += rig.sensor().bias();
        self.samples += 1;
    }

    /// The drift since the tare (raw: force first, sensor frame) at the last sample read.
    pub fn drift(&self, rig: &SimRig) -> Vector6<f64> {
        #[allow(clippy::cast_precision_loss)] // a tare far below 2⁵² samples
        let at_tare = if self.samples == 0 {
            Vector6::zeros()
        } else {
            self.sum / self.samples as f64
        };
        rig.sensor().bias() - at_tare
    }

    /// The drift since the tare in `A` (torque first, base clamp frame) \[N·m, N\]: what the
    /// bias observer estimates.
    pub fn bias(&self, rig: &SimRig) -> Vector6<f64> {
        self.mounting.to_configuration(&self.drift(rig))
    }

    /// The JSON message at `stamp` \[s\].
    pub fn message(&self, rig: &SimRig, stamp: f64) -> Option<StringMsg> {
        let raw = self.drift(rig);
        let message = Message {
            stamp,
            bias: self.mounting.to_configuration(&raw).into(),
            raw: raw.into(),
        };
        serde_json::to_string(&message)
            .ok()
            .map(|data| StringMsg { data })
    }
}
