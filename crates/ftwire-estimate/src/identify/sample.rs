//! One identification sample: a measured configuration `ã` and the second gripper's pose `b̃`.

use ftwire_core::Pose;
use nalgebra::Vector6;

use crate::EstimateError;

/// A measured configuration and the pose it was measured at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// `ã = (τ1, τ2, τ3, f1, f2, f3)` \[N·m, N\]: the wrench the wire exerts on the base
    /// gripper, torque first, in the base clamp frame, tared and calibrated.
    pub a: Vector6<f64>,
    /// `b̃`: the second gripper's clamp pose in the base clamp frame \[m\].
    pub b: Pose,
    /// The time since the sensor was tared \[s\], if known: with a bias model
    /// ([`super::MeasurementNoise::bias`]) it says how far the bias has drifted.
    pub time: Option<f64>,
}

impl Sample {
    /// A checked sample; `index` names it in errors.
    ///
    /// # Errors
    /// [`EstimateError::NonFiniteSample`] for a non-finite component of `a` or `b`,
    /// [`EstimateError::SampleOutsideA`] if `a2 = a3 = a5 = a6 = 0` (eq. 2).
    ///
    /// # Example
    /// ```
    /// use ftwire_estimate::identify::Sample;
    /// use ftwire_core::Pose;
    /// use nalgebra::Vector6;
    /// let bad = Sample::new(4, Vector6::new(0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0), Pose::identity());
    /// assert!(bad.unwrap_err().to_string().contains("sample 4"));
    /// ```
    pub fn new(index: usize, a: Vector6<f64>, b: Pose) -> Result<Self, EstimateError> {
        let non_finite = |field, component, value| EstimateError::NonFiniteSample {
            index,
            field,
            component,
            value,
        };
        for (component, value) in a.iter().enumerate() {
            if !value.is_finite() {
                return Err(non_finite("a", component, *value));
            }
        }
        let q = b.rotation.as_ref().coords;
        let pose = b.translation.vector.iter().chain(q.iter());
        for (component, value) in pose.enumerate() {
            if !value.is_finite() {
                return Err(non_finite("b", component, *value));
            }
        }
        if a[1] == 0.0 && a[2] == 0.0 && a[4] == 0.0 && a[5] == 0.0 {
            return Err(EstimateError::SampleOutsideA { index, a: a.into() });
        }
        Ok(Self { a, b, time: None })
    }

    /// The sample taken `time` seconds after the tare.
    ///
    /// # Errors
    /// [`EstimateError::BadSampleTime`] for a time that is not finite and `>= 0`.
    pub fn at(self, index: usize, time: f64) -> Result<Self, EstimateError> {
        if !(time.is_finite() && time >= 0.0) {
            return Err(EstimateError::BadSampleTime { index, value: time });
        }
        Ok(Self {
            time: Some(time),
            ..self
        })
    }

    /// The distance between the clamp points, `|p(b̃)|` \[m\]: a lower bound on the length.
    pub fn chord(&self) -> f64 {
        self.b.translation.vector.norm()
    }
}
