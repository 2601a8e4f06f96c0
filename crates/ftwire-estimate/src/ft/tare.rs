//! Taring: removing the sensor's offset, measured under a known load.

use nalgebra::Vector6;

use super::Averaged;

/// The offset of the raw reading (force first, sensor frame), measured at rest under a known
/// load and subtracted from every later reading.
///
/// # The procedure on a real robot
/// 1. Before the second gripper closes on the wire — best, before the base gripper picks it up
///    — bring the base arm to the orientation it will hold during the task, and let it come to
///    rest (the gripper's own weight then loads the sensor exactly as it will during the task).
/// 2. Read a rest period of samples (at 1 kHz, 0.5 s is plenty) and average them
///    ([`super::RestAverage`]).
/// 3. `Tare::from_rest(&averaged, &Vector6::zeros())`: the wire exerts nothing yet, so the
///    whole reading is offset. If instead a known load is applied (for example a wire of
///    known stiffness and length held in a known configuration `a`), pass its raw reading
///    `Mounting::to_sensor(a)` as the reference.
/// 4. Repeat when the base gripper's orientation changes, or after a few minutes: the offset
///    drifts with temperature.
///
/// The tare's own noise (`σ/√K` of its rest period) stays in every later reading as a constant
/// offset, so tare with more samples than each measurement uses.
///
/// # Example
/// ```
/// use ftwire_core::FtSample;
/// use ftwire_estimate::ft::{RestAverage, Tare};
/// use nalgebra::Vector6;
///
/// let bias = Vector6::new(0.35, -0.22, 0.61, 0.012, -0.008, 0.005);
/// let unloaded: Vec<FtSample> = (0..10)
///     .map(|i| FtSample { time: i as f64 * 1e-3, raw: bias, ..Default::default() })
///     .collect();
/// let tare = Tare::from_rest(&RestAverage::new(5)?.average(unloaded.iter().map(Some))?, &Vector6::zeros());
/// assert!((tare.apply(&(bias + Vector6::repeat(1.0))) - Vector6::repeat(1.0)).norm() < 1e-15);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Tare {
    /// Offset subtracted from each raw reading (force first, sensor units).
    pub offset: Vector6<f64>,
    /// Standard error of the offset per channel (the tare's own noise).
    pub std_error: Vector6<f64>,
    /// Time the tare was taken \[s\], on the rig's clock (`NaN` for [`Tare::none`]).
    pub time: f64,
}

impl Tare {
    /// No tare: the raw reading is used as it is.
    pub fn none() -> Self {
        Self {
            time: f64::NAN,
            ..Self::default()
        }
    }

    /// The tare from a rest period under a known load whose raw reading (force first, sensor
    /// frame) would be `reference` on a sensor without offset; zero for no load.
    pub fn from_rest(rest: &Averaged, reference: &Vector6<f64>) -> Self {
        Self {
            offset: rest.mean - reference,
            std_error: rest.std_error,
            time: rest.time,
        }
    }

    /// A raw reading with the offset removed.
    pub fn apply(&self, raw: &Vector6<f64>) -> Vector6<f64> {
        raw - self.offset
    }
}
