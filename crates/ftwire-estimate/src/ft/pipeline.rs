//! The whole pipeline: screened, averaged, tared, calibrated.

use nalgebra::Vector6;

use super::{Averaged, Mounting, RestAverage, Tare};
use crate::EstimateError;
use ftwire_core::FtSample;

/// A map from a tared raw reading (force first, sensor frame) to a configuration `a` (torque
/// first, base clamp frame): the mounting transform, or a learnt calibration that also undoes
/// the sensor's gain, cross-talk and nonlinearity.
pub trait FtCalibration: Send + Sync {
    /// The configuration for a tared raw reading.
    fn configuration(&self, tared: &Vector6<f64>) -> Vector6<f64>;

    /// The configuration for a tared raw reading taken at `time` \[s, the reading's clock\]:
    /// a map that changes in time (a learnt calibration's drift) is applied at the reading's
    /// own time. The default is [`FtCalibration::configuration`], a map the same at every time.
    fn configuration_at(&self, tared: &Vector6<f64>, time: f64) -> Vector6<f64> {
        let _ = time;
        self.configuration(tared)
    }
}

impl FtCalibration for Mounting {
    fn configuration(&self, tared: &Vector6<f64>) -> Vector6<f64> {
        self.to_configuration(tared)
    }
}

/// One measured configuration `ã`, with what it is worth.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    /// The configuration `ã` (torque first, base clamp frame).
    pub a: Vector6<f64>,
    /// Standard error of each component of `ã` from the averaged noise, propagated through the
    /// calibration (to first order); the tare's own error is not included.
    pub a_std_error: Vector6<f64>,
    /// The averaged raw reading it came from, with the screening report.
    pub raw: Averaged,
}

/// From raw samples at rest to `ã`: screening and averaging ([`RestAverage`]), taring
/// ([`Tare`]), calibration ([`FtCalibration`]). See the [module docs](super) for the lag and
/// noise of each stage.
///
/// # Example
/// ```
/// use ftwire_core::FtSample;
/// use ftwire_estimate::ft::{FtPipeline, Mounting, RestAverage, Tare};
/// use nalgebra::Vector6;
///
/// let pipeline = FtPipeline::new(RestAverage::new(2)?, Tare::none(), Mounting::default());
/// let raw = Vector6::new(1.0, 2.0, 3.0, 0.1, 0.2, 0.3); // force first
/// let samples = [FtSample { time: 0.0, raw, ..Default::default() }; 3];
/// let m = pipeline.measure(samples.iter().map(Some))?;
/// assert!((m.a - Vector6::new(0.1, 0.2, 0.3, 1.0, 2.0, 3.0)).norm() < 1e-15); // torque first
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct FtPipeline<C = Mounting> {
    average: RestAverage,
    tare: Tare,
    calibration: C,
}

impl<C: FtCalibration> FtPipeline<C> {
    /// A pipeline from its stages.
    pub fn new(average: RestAverage, tare: Tare, calibration: C) -> Self {
        Self {
            average,
            tare,
            calibration,
        }
    }

    /// The same pipeline with a new tare.
    #[must_use]
    pub fn with_tare(mut self, tare: Tare) -> Self {
        self.tare = tare;
        self
    }

    /// The averaging stage.
    pub fn rest_average(&self) -> &RestAverage {
        &self.average
    }

    /// The tare.
    pub fn tare(&self) -> &Tare {
        &self.tare
    }

    /// The calibration.
    pub fn calibration(&self) -> &C {
        &self.calibration
    }

    /// `ã` for one already averaged raw reading (no screening): tare, then calibrate.
    pub fn configuration(&self, raw: &Vector6<f64>) -> Vector6<f64> {
        self.calibration.configuration(&self.tare.apply(raw))
    }

    /// `ã` for one already averaged raw reading taken at `time` \[s\]: tare, then calibrate
    /// at that time ([`FtCalibration::configuration_at`]).
    pub fn configuration_at(&self, raw: &Vector6<f64>, time: f64) -> Vector6<f64> {
        self.calibration
            .configuration_at(&self.tare.apply(raw), time)
    }

    /// `ã` from the raw samples of one rest period (`None` for a dropout).
    ///
    /// # Errors
    /// [`EstimateError::TooFewGoodSamples`] when screening leaves too few samples, and
    /// [`EstimateError::NonFiniteConfiguration`] when the calibration returns a non-finite `ã`.
    pub fn measure<'a>(
        &self,
        samples: impl IntoIterator<Item = Option<&'a FtSample>>,
    ) -> Result<Measurement, EstimateError> {
        let raw = self.average.average(samples)?;
        // At the time of the rest's last sample: a drifting map is applied when it was read.
        let a = self.configuration_at(&raw.mean, raw.time);
        if let Some(index) = a.iter().position(|v| !v.is_finite()) {
            return Err(EstimateError::NonFiniteConfiguration {
                index,
                value: a[index],
            });
        }
        // First-order propagation of the mean's noise, with a central-difference Jacobian of
        // the calibration (exact for the linear mounting map).
        let mut variance = Vector6::zeros();
        for j in 0..6 {
            let h = raw.std_error[j];
            if h > 0.0 {
                let mut plus = raw.mean;
                let mut minus = raw.mean;
                plus[j] += h;
                minus[j] -= h;
                let column = (self.configuration_at(&plus, raw.time)
                    - self.configuration_at(&minus, raw.time))
                    / 2.0;
                variance += column.component_mul(&column);
            }
        }
        Ok(Measurement {
            a,
            a_std_error: variance.map(f64::sqrt),
            raw,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ftwire_core::Pose;
    use nalgebra::{Translation3, UnitQuaternion};

    /// A map whose offset drifts with time, as a learnt calibration's drift term does.
    struct Drifting;

    impl FtCalibration for Drifting {
        fn configuration(&self, tared: &Vector6<f64>) -> Vector6<f64> {
            *tared
        }

        fn configuration_at(&self, tared: &Vector6<f64>, time: f64) -> Vector6<f64> {
            tared + Vector6::repeat(0.01 * time)
        }
    }

    /// A rest is mapped at its own time (its last sample's), so that a drift is applied when
    /// the rest was read, not at a fixed time.
    #[test]
    fn a_rest_is_mapped_at_its_time() -> Result<(), EstimateError> {
        let pipeline = FtPipeline::new(RestAverage::new(2)?, Tare::none(), Drifting);
        let raw = Vector6::new(1.0, 2.0, 3.0, 0.1, 0.2, 0.3);
        let samples: Vec<FtSample> = (0..3)
            .map(|k| FtSample {
                time: 10.0 + f64::from(k),
                raw,
                ..Default::default()
            })
            .collect();
        let m = pipeline.measure(samples.iter().map(Some))?;
        assert!(
            (m.a - (raw + Vector6::repeat(0.12))).norm() < 1e-12,
            "{}",
            m.a
        );
        assert_eq!(pipeline.configuration(&raw), raw);
        Ok(())
    }

    #[test]
    fn the_pipeline_undoes_a_known_offset_and_mounting() -> Result<(), EstimateError> {
        let mounting = Mounting::new(Pose::from_parts(
            Translation3::new(0.01, -0.02, 0.08),
            UnitQuaternion::from_euler_angles(0.4, 0.1, -2.0),
        ))?;
        let bias = Vector6::new(0.35, -0.22, 0.61, 0.012, -0.008, 0.005);
        let unloaded = [FtSample {
            time: 0.0,
            raw: bias,
            ..Default::default()
        }; 4];
        let average = RestAverage::new(3)?;
        let tare = Tare::from_rest(
            &average.average(unloaded.iter().map(Some))?,
            &Vector6::zeros(),
        );
        let pipeline = FtPipeline::new(average, tare, mounting);
        let a = Vector6::new(0.02, -0.01, 0.05, -0.3, 0.2, 0.1);
        let raw = mounting.to_sensor(&a) + bias;
        let samples = [-1.0, 1.0, -1.0, 1.0].map(|s| FtSample {
            time: 0.1,
            raw: raw + Vector6::repeat(1e-3 * s),
            ..Default::default()
        });
        let m = pipeline.measure(samples.iter().map(Some))?;
        assert!((m.a - a).norm() < 1e-12, "{:?}", m.a - a);
        // The propagated error is the rotated per-channel error: non-zero on every component.
        assert!(m.a_std_error.iter().all(|&e| e > 0.0 && e < 1e-2));
        Ok(())
    }
}
