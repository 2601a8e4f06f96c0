//! Feedback: the measured configuration `ã` at the rig's current rest, through the estimation
//! crate's F/T pipeline (screening, rest averaging, tare, calibration).

use ftwire_core::{FtSample, Rig};
use ftwire_estimate::EstimateError;
use ftwire_estimate::ft::{FtCalibration, FtPipeline, Measurement};

/// Reads `samples` F/T samples at rest and turns them into `ã` with `pipeline`.
///
/// # Example
/// ```
/// use ftwire_control::FtFeedback;
/// use ftwire_estimate::ft::{FtPipeline, Mounting, RestAverage, Tare};
/// let pipeline = FtPipeline::new(RestAverage::new(10)?, Tare::none(), Mounting::default());
/// let feedback = FtFeedback::new(pipeline, 20);
/// assert_eq!(feedback.samples(), 20);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct FtFeedback<C> {
    pipeline: FtPipeline<C>,
    samples: usize,
}

impl<C: FtCalibration> FtFeedback<C> {
    /// Feedback averaging `samples` F/T samples per rest through `pipeline`.
    pub fn new(pipeline: FtPipeline<C>, samples: usize) -> Self {
        Self { pipeline, samples }
    }

    /// Samples read per measurement.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// The pipeline.
    pub fn pipeline(&self) -> &FtPipeline<C> {
        &self.pipeline
    }

    /// One measurement of `ã` at the rig's current rest (a read error counts as a dropout).
    ///
    /// # Errors
    /// As [`FtPipeline::measure`]: too few good samples, or a non-finite `ã`.
    pub fn measure<R: Rig>(&self, rig: &mut R) -> Result<Measurement, EstimateError> {
        self.measure_samples(rig, self.samples)
    }

    /// As [`FtFeedback::measure`], averaging `count` samples instead of
    /// [`FtFeedback::samples`] (the controller's longer rests near the goal).
    ///
    /// # Errors
    /// As [`FtFeedback::measure`].
    pub fn measure_samples<R: Rig>(
        &self,
        rig: &mut R,
        count: usize,
    ) -> Result<Measurement, EstimateError> {
        let samples: Vec<Option<FtSample>> = (0..count).map(|_| rig.read_ft().ok()).collect();
        self.pipeline.measure(samples.iter().map(Option::as_ref))
    }
}
