//! The mounting transform between the sensor frame and the base clamp frame.

use ftwire_core::{Pose, Wrench, ensure_finite};
use nalgebra::{Vector3, Vector6};

use crate::EstimateError;

/// Where the base clamp sits on the sensor: the pose `sensor_from_clamp`, from the gripper's
/// drawings (or calibrated), mapping clamp-frame coordinates to sensor-frame coordinates.
///
/// The sensor reads the wrench the wire exerts on the base gripper, expressed in the sensor
/// frame about the sensor origin, force first: `s = (R f, R τ + t × R f)` for the clamp-frame
/// wrench `(τ, f)` and `sensor_from_clamp = (R, t)`. [`Mounting::to_configuration`] inverts it.
///
/// # Example
/// ```
/// use ftwire_core::Pose;
/// use ftwire_estimate::ft::Mounting;
/// use nalgebra::{Translation3, UnitQuaternion, Vector6};
///
/// let mounting = Mounting::new(Pose::from_parts(
///     Translation3::new(0.0, 0.0, 0.08),
///     UnitQuaternion::from_euler_angles(0.3, -0.2, 1.0),
/// ))?;
/// let a = Vector6::new(0.01, -0.02, 0.03, 0.4, -0.5, 0.6);
/// let raw = mounting.to_sensor(&a);
/// assert!((mounting.to_configuration(&raw) - a).norm() < 1e-14);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mounting {
    sensor_from_clamp: Pose,
    clamp_from_sensor: Pose,
}

impl Default for Mounting {
    /// The sensor frame is the clamp frame.
    fn default() -> Self {
        Self {
            sensor_from_clamp: Pose::identity(),
            clamp_from_sensor: Pose::identity(),
        }
    }
}

impl Mounting {
    /// A mounting from the pose `sensor_from_clamp`.
    ///
    /// # Errors
    /// [`EstimateError::Core`] when the pose is not finite.
    pub fn new(sensor_from_clamp: Pose) -> Result<Self, EstimateError> {
        ensure_finite(
            "sensor_from_clamp.translation",
            sensor_from_clamp.translation.vector.as_slice(),
        )?;
        ensure_finite(
            "sensor_from_clamp.rotation",
            sensor_from_clamp.rotation.coords.as_slice(),
        )?;
        Ok(Self {
            sensor_from_clamp,
            clamp_from_sensor: sensor_from_clamp.inverse(),
        })
    }

    /// The pose `sensor_from_clamp`.
    pub fn sensor_from_clamp(&self) -> &Pose {
        &self.sensor_from_clamp
    }

    /// A sensor-frame reading (force first, about the sensor origin) as a configuration (torque
    /// first, base clamp frame, about the clamp point).
    pub fn to_configuration(&self, sensor: &Vector6<f64>) -> Vector6<f64> {
        force_first_to_wrench(sensor)
            .transformed(&self.clamp_from_sensor)
            .to_vector()
    }

    /// A configuration as the sensor-frame reading it produces (force first): the inverse of
    /// [`Mounting::to_configuration`].
    pub fn to_sensor(&self, a: &Vector6<f64>) -> Vector6<f64> {
        wrench_to_force_first(&Wrench::from_vector(a).transformed(&self.sensor_from_clamp))
    }
}

/// A force-first 6-vector `(f, τ)` as a wrench.
pub(crate) fn force_first_to_wrench(v: &Vector6<f64>) -> Wrench {
    Wrench::new(
        Vector3::new(v[3], v[4], v[5]),
        Vector3::new(v[0], v[1], v[2]),
    )
}

/// A wrench as a force-first 6-vector `(f, τ)`.
pub(crate) fn wrench_to_force_first(w: &Wrench) -> Vector6<f64> {
    Vector6::new(
        w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    #[test]
    fn a_pure_force_off_the_sensor_origin_reads_as_a_torque() -> Result<(), EstimateError> {
        // The clamp 80 mm along the sensor's z, axes aligned: a force f along clamp x seen by
        // the sensor is f along x plus a torque t × f = 0.08 ez × f ex = 0.08 f ey.
        let mounting = Mounting::new(Pose::from_parts(
            Translation3::new(0.0, 0.0, 0.08),
            UnitQuaternion::identity(),
        ))?;
        let a = Vector6::new(0.0, 0.0, 0.0, 2.0, 0.0, 0.0);
        let raw = mounting.to_sensor(&a);
        assert!((raw - Vector6::new(2.0, 0.0, 0.0, 0.0, 0.16, 0.0)).norm() < 1e-15);
        assert!((mounting.to_configuration(&raw) - a).norm() < 1e-15);
        Ok(())
    }

    #[test]
    fn non_finite_mounting_is_refused() {
        let pose = Pose::from_parts(
            Translation3::new(f64::NAN, 0.0, 0.0),
            UnitQuaternion::identity(),
        );
        assert!(Mounting::new(pose).is_err());
    }
}
