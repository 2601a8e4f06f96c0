//! A real sensor's mounting as a user writes it: where the base clamp sits on the sensor, and
//! optionally the tool hanging below the sensor, whose weight the sensor also reads.
//!
//! The keys and meanings of the clamp pose are those of the simulated sensor's file
//! (`ftwire_sim::FtSensorParams`): `clamp_position_in_sensor` \[m\] and
//! `clamp_rotation_in_sensor` (rotation vector \[rad\]), the pose `sensor_from_clamp`.
//!
//! **Tool weight.** A tool of mass `m` with its centre of mass at `c` (sensor frame) adds to the
//! reading, force first, `(m g_s, c × m g_s)` where `g_s` is the gravity vector in the sensor
//! frame at that record (it turns with the wrist). [`MountingSpec::compensate`] subtracts it.
//! Guarded by the tests of this module.

use ftwire_core::{Pose, ensure_finite, ensure_rotation_vector};
use nalgebra::{Translation3, UnitQuaternion, Vector3, Vector6};
use serde::{Deserialize, Serialize};

use super::Mounting;
use crate::EstimateError;

/// The largest tool mass accepted \[kg\]: a wrist sensor carries grippers, not payloads of a
/// tonne; a larger value is a unit mistake.
pub const MAX_TOOL_MASS: f64 = 1000.0;

/// The farthest the clamp or the tool's centre of mass may be from the sensor \[m\]: a
/// wrist's tool is centimetres long; a larger value is a unit mistake (millimetres given as
/// metres), and would turn a reading's force into an implausible torque.
pub const MAX_LEVER: f64 = 10.0;

/// The mounting file's contents (TOML). Missing keys take their defaults; unknown keys are
/// errors.
///
/// # Example
/// ```
/// use ftwire_estimate::ft::MountingSpec;
/// let spec: MountingSpec = toml::from_str("clamp_position_in_sensor = [0.0, 0.0, 0.11]")?;
/// assert_eq!(spec.tool_mass, 0.0);
/// assert!(spec.mounting().is_ok());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MountingSpec {
    /// Position of the clamp point in the sensor frame \[m\] (default `[0, 0, 0.08]`, the
    /// simulated sensor's).
    pub clamp_position_in_sensor: [f64; 3],
    /// Orientation of the clamp frame in the sensor frame as a rotation vector \[rad\]
    /// (default `−(2π/3)/√3 · (1, 1, 1)`: clamp x, y, z along sensor z, x, y).
    pub clamp_rotation_in_sensor: [f64; 3],
    /// Mass of the tool below the sensor (gripper and clamp, not the wire) \[kg\], in
    /// `[0, MAX_TOOL_MASS]` (default `0`: the rig compensates it, or there is none).
    pub tool_mass: f64,
    /// The tool's centre of mass in the sensor frame \[m\] (default `[0, 0, 0]`).
    pub tool_centre_of_mass: [f64; 3],
}

impl Default for MountingSpec {
    fn default() -> Self {
        let r = -2.0 * std::f64::consts::FRAC_PI_3 / 3f64.sqrt();
        Self {
            clamp_position_in_sensor: [0.0, 0.0, 0.08],
            clamp_rotation_in_sensor: [r, r, r],
            tool_mass: 0.0,
            tool_centre_of_mass: [0.0; 3],
        }
    }
}

impl MountingSpec {
    /// Checks every value.
    ///
    /// # Errors
    /// [`EstimateError::Core`] naming a non-finite value or a rotation vector beyond
    /// `ftwire_core::MAX_ROTATION_ANGLE`; [`EstimateError::InvalidSetting`] for a tool mass
    /// outside `[0, MAX_TOOL_MASS]`, or a clamp or centre of mass farther than [`MAX_LEVER`].
    pub fn validate(&self) -> Result<(), EstimateError> {
        ensure_finite("clamp_position_in_sensor", &self.clamp_position_in_sensor)?;
        ensure_rotation_vector("clamp_rotation_in_sensor", &self.clamp_rotation_in_sensor)?;
        ensure_finite("tool_centre_of_mass", &self.tool_centre_of_mass)?;
        for (field, point) in [
            ("clamp_position_in_sensor", self.clamp_position_in_sensor),
            ("tool_centre_of_mass", self.tool_centre_of_mass),
        ] {
            // The largest component first, so that a huge one is named as given, not as the
            // infinite norm it would make.
            let largest = point.iter().copied().fold(0.0_f64, |m, v| m.max(v.abs()));
            let distance = if largest > MAX_LEVER {
                largest
            } else {
                Vector3::from(point).norm()
            };
            if distance > MAX_LEVER {
                return Err(EstimateError::InvalidSetting {
                    field,
                    value: distance,
                    allowed: "a point at most 10 m from the sensor (its distance is the value)",
                });
            }
        }
        if !(0.0..=MAX_TOOL_MASS).contains(&self.tool_mass) {
            return Err(EstimateError::InvalidSetting {
                field: "tool_mass",
                value: self.tool_mass,
                allowed: "a mass in [0, 1000] kg",
            });
        }
        Ok(())
    }

    /// The pose `sensor_from_clamp`.
    pub fn sensor_from_clamp(&self) -> Pose {
        Pose::from_parts(
            Translation3::from(Vector3::from(self.clamp_position_in_sensor)),
            UnitQuaternion::from_scaled_axis(Vector3::from(self.clamp_rotation_in_sensor)),
        )
    }

    /// The mounting transform.
    ///
    /// # Errors
    /// As [`MountingSpec::validate`].
    pub fn mounting(&self) -> Result<Mounting, EstimateError> {
        self.validate()?;
        Mounting::new(self.sensor_from_clamp())
    }

    /// Whether a tool weight is to be compensated (a record then needs its gravity vector).
    pub fn has_tool(&self) -> bool {
        self.tool_mass > 0.0
    }

    /// The tool's own reading, force first, sensor frame: `(m g, c × m g)` for the gravity
    /// vector `gravity` \[m/s²\] in the sensor frame.
    pub fn tool_reading(&self, gravity: &Vector3<f64>) -> Vector6<f64> {
        let force = gravity * self.tool_mass;
        let torque = Vector3::from(self.tool_centre_of_mass).cross(&force);
        Vector6::new(force.x, force.y, force.z, torque.x, torque.y, torque.z)
    }

    /// A raw reading with the tool's weight taken out. `gravity` is needed when there is a
    /// tool; without a tool the reading is returned as it is.
    ///
    /// # Errors
    /// [`EstimateError::InvalidSetting`] when there is a tool and `gravity` is `None`.
    pub fn compensate(
        &self,
        raw: &Vector6<f64>,
        gravity: Option<&Vector3<f64>>,
    ) -> Result<Vector6<f64>, EstimateError> {
        if !self.has_tool() {
            return Ok(*raw);
        }
        let gravity = gravity.ok_or(EstimateError::NoGravity {
            tool_mass: self.tool_mass,
        })?;
        Ok(raw - self.tool_reading(gravity))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_is_the_simulated_sensors_mounting() -> Result<(), EstimateError> {
        let spec = MountingSpec::default();
        let mounting = spec.mounting()?;
        // Clamp x (the wire's tangent) lies along sensor z.
        let along = mounting.sensor_from_clamp().rotation * Vector3::x();
        assert!((along - Vector3::z()).norm() < 1e-12);
        Ok(())
    }

    #[test]
    fn a_lever_in_millimetres_given_as_metres_is_refused() {
        for spec in [
            MountingSpec {
                tool_centre_of_mass: [0.0, 0.0, 40.0],
                ..MountingSpec::default()
            },
            MountingSpec {
                clamp_position_in_sensor: [0.0, 0.0, 110.0],
                ..MountingSpec::default()
            },
        ] {
            let e = spec
                .validate()
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default();
            assert!(e.contains("at most 10 m"), "{e}");
        }
        let near = MountingSpec {
            tool_centre_of_mass: [0.0, 0.0, 0.04],
            ..MountingSpec::default()
        };
        assert!(near.validate().is_ok());
    }

    #[test]
    fn a_tools_weight_is_taken_out() -> Result<(), EstimateError> {
        let spec = MountingSpec {
            tool_mass: 0.5,
            tool_centre_of_mass: [0.0, 0.0, 0.04],
            ..MountingSpec::default()
        };
        let g = Vector3::new(0.0, -9.81, 0.0);
        let weight = spec.tool_reading(&g);
        // F = m g = (0, −4.905, 0); τ = c × F = 0.04 ez × (−4.905 ey) = +0.1962 ex.
        assert!((weight - Vector6::new(0.0, -4.905, 0.0, 0.1962, 0.0, 0.0)).norm() < 1e-12);
        let raw = Vector6::new(1.0, 2.0, 3.0, 0.1, 0.2, 0.3);
        let back = spec.compensate(&(raw + weight), Some(&g))?;
        assert!((back - raw).norm() < 1e-12);
        assert!(spec.compensate(&raw, None).is_err());
        assert_eq!(MountingSpec::default().compensate(&raw, None)?, raw);
        Ok(())
    }

    #[test]
    fn bad_values_are_named() {
        let bad = MountingSpec {
            tool_mass: -1.0,
            ..MountingSpec::default()
        };
        assert!(
            bad.validate()
                .expect_err("refused")
                .to_string()
                .contains("tool_mass")
        );
        // A huge value is named as given, not as an infinite distance or in 309 digits.
        for (bad, shown) in [
            (
                MountingSpec {
                    clamp_position_in_sensor: [0.0, 0.0, 1e308],
                    ..MountingSpec::default()
                },
                "clamp_position_in_sensor = 1e308 ",
            ),
            (
                MountingSpec {
                    tool_mass: 1e308,
                    ..MountingSpec::default()
                },
                "tool_mass = 1e308 ",
            ),
        ] {
            let message = bad.validate().expect_err("refused").to_string();
            assert!(message.contains(shown), "{message}");
        }
        let bad = MountingSpec {
            clamp_position_in_sensor: [0.0, f64::NAN, 0.0],
            ..MountingSpec::default()
        };
        assert!(
            bad.validate()
                .expect_err("refused")
                .to_string()
                .contains("clamp_position_in_sensor")
        );
    }
}
