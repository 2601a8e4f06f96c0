//! A six-axis F/T sensor's data sheet: what a rig knows of its sensor's noise without a
//! simulator, and the error of `ã` it implies.
//!
//! The white noise of one reading, the bias drift (a first-order Gauss–Markov process per
//! channel: intensity `q` per √s, time constant `τ`), and where the clamp sits in the sensor
//! frame. Force first, in the sensor's own frame, as the sensor reports. The simulated sensor
//! of `ftwire-sim` is described by the same keys (its `FtSensorParams` holds these and more),
//! so one file can describe both.

use ftwire_core::Pose;
use ftwire_estimate::ft::Mounting;
use ftwire_estimate::identify::{BiasDrift, MeasurementNoise};
use nalgebra::{Matrix6, Translation3, UnitQuaternion, Vector3, Vector6};
use serde::{Deserialize, Serialize};

use crate::RigError;

/// The data sheet of an F/T sensor (force first, sensor frame).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DataSheet {
    /// White noise of one reading, σ per channel \[N, N·m\].
    pub noise_std: [f64; 6],
    /// Bias drift intensity `q` per channel \[N/√s, N·m/√s\].
    pub bias_random_walk: [f64; 6],
    /// The bias drift's time constant `τ` \[s\] (`f64::INFINITY`: a random walk).
    pub bias_time_constant: f64,
    /// The clamp point in the sensor frame \[m\].
    pub clamp_position_in_sensor: [f64; 3],
    /// The clamp's rotation in the sensor frame, a rotation vector \[rad\].
    pub clamp_rotation_in_sensor: [f64; 3],
}

impl DataSheet {
    /// The keys of a data sheet, as a sensor file spells them.
    pub const KEYS: [&'static str; 5] = [
        "noise_std",
        "bias_random_walk",
        "bias_time_constant",
        "clamp_position_in_sensor",
        "clamp_rotation_in_sensor",
    ];

    /// The pose of the clamp frame in the sensor frame.
    pub fn sensor_from_clamp(&self) -> Pose {
        Pose::from_parts(
            Translation3::from(Vector3::from(self.clamp_position_in_sensor)),
            UnitQuaternion::from_scaled_axis(Vector3::from(self.clamp_rotation_in_sensor)),
        )
    }

    /// Checks every value: noise and drift finite and ≥ 0, `τ` in `(0, 1e9]` or infinite, the
    /// clamp's pose finite.
    ///
    /// # Errors
    /// [`RigError::Setting`] naming the key, the value and what is allowed.
    pub fn validate(&self) -> Result<(), RigError> {
        for (key, values) in [
            ("noise_std", self.noise_std),
            ("bias_random_walk", self.bias_random_walk),
        ] {
            // At most a reading's size (1e4 N, 1e3 N·m): a wider σ squares past `f64`.
            let limits = [ftwire_estimate::log::MAX_FORCE; 3]
                .into_iter()
                .chain([ftwire_estimate::log::MAX_TORQUE; 3]);
            if let Some((v, _)) = values
                .iter()
                .zip(limits)
                .find(|(v, max)| !(v.is_finite() && (0.0..=*max).contains(*v)))
            {
                return Err(RigError::Setting(format!(
                    "{key} holds {}: each entry is finite, ≥ 0 and at most 1e4 N (force) or \
                     1e3 N·m (torque)",
                    ftwire_core::text::Number(*v)
                )));
            }
        }
        let tau = self.bias_time_constant;
        if tau.is_nan() || tau <= 0.0 || (tau.is_finite() && tau > 1e9) {
            return Err(RigError::Setting(format!(
                "bias_time_constant = {tau}: a time constant > 0 and ≤ 1e9 [s] (inf: a random \
                 walk)"
            )));
        }
        for (key, values) in [
            ("clamp_position_in_sensor", self.clamp_position_in_sensor),
            ("clamp_rotation_in_sensor", self.clamp_rotation_in_sensor),
        ] {
            if let Some(v) = values.iter().find(|v| !v.is_finite()) {
                return Err(RigError::Setting(format!(
                    "{key} holds {v}: each entry is finite"
                )));
            }
        }
        Ok(())
    }

    /// The error of `ã` this sensor gives, mounted by `mount`, with `rest_samples` readings
    /// averaged per sample and `tare_samples` in the tare: the rest's white noise (its
    /// covariance mapped by the mounting's wrench transform, so a force's noise becomes a
    /// torque's a lever arm away) and the tare's offset and its drift since the tare
    /// ([`BiasDrift::from_sensor`]). A count of 0 is taken as 1.
    ///
    /// # Errors
    /// [`RigError::Setting`] for a data sheet [`Self::validate`] refuses, or a drift the
    /// estimation layer refuses.
    pub fn noise(
        &self,
        mount: &Mounting,
        rest_samples: usize,
        tare_samples: usize,
    ) -> Result<MeasurementNoise, RigError> {
        self.validate()?;
        let to_a =
            Matrix6::from_fn(|row, column| mount.to_configuration(&Vector6::ith(column, 1.0))[row]);
        let scaled = |n: usize| self.noise_std.map(|s| s / (n.max(1) as f64).sqrt());
        let bias = BiasDrift::from_sensor(
            &to_a,
            scaled(tare_samples),
            self.bias_random_walk,
            self.bias_time_constant,
        )
        .map_err(|e| RigError::Setting(format!("the sensor's drift: {e}")))?;
        let rest = scaled(rest_samples);
        let rest =
            to_a * Matrix6::from_diagonal(&Vector6::from(rest.map(|s| s * s))) * to_a.transpose();
        let largest =
            |range: std::ops::Range<usize>| range.map(|i| rest[(i, i)]).fold(0.0, f64::max).sqrt();
        // The rest's own noise keeps the mounting's correlation of torque and force; a channel
        // without noise keeps a floor far below any sensor's, so the covariance stays invertible.
        let floor = Matrix6::from_diagonal(&Vector6::repeat(1e-30));
        Ok(MeasurementNoise {
            torque: largest(0..3).max(f64::MIN_POSITIVE),
            force: largest(3..6).max(f64::MIN_POSITIVE),
            wrench: Some(rest + floor),
            bias: Some(bias),
            ..MeasurementNoise::default()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sheet() -> DataSheet {
        DataSheet {
            noise_std: [0.05, 0.05, 0.05, 0.002, 0.002, 0.002],
            bias_random_walk: [0.002, 0.002, 0.002, 8e-5, 8e-5, 8e-5],
            bias_time_constant: 600.0,
            clamp_position_in_sensor: [0.0, 0.0, 0.08],
            clamp_rotation_in_sensor: [0.0; 3],
        }
    }

    #[test]
    fn a_rest_of_n_readings_has_the_noise_of_one_over_root_n() -> Result<(), RigError> {
        let mount = Mounting::new(Pose::identity())?;
        let one = sheet().noise(&mount, 1, 1)?;
        let hundred = sheet().noise(&mount, 100, 1)?;
        // ã is torque first: the torque channels carry the sensor's torque noise.
        assert!((one.torque - 0.002).abs() < 1e-12, "{}", one.torque);
        assert!((one.force - 0.05).abs() < 1e-12, "{}", one.force);
        assert!((hundred.force - 0.005).abs() < 1e-12, "{}", hundred.force);
        Ok(())
    }

    #[test]
    fn a_force_noise_becomes_a_torque_noise_a_lever_arm_away() -> Result<(), RigError> {
        let at = |z: f64| -> Result<f64, RigError> {
            let mut sheet = sheet();
            sheet.noise_std = [0.05, 0.05, 0.05, 0.0, 0.0, 0.0];
            sheet.clamp_position_in_sensor = [0.0, 0.0, z];
            Ok(sheet
                .noise(&Mounting::new(sheet.sensor_from_clamp())?, 1, 1)?
                .torque)
        };
        assert!(at(0.0)? < 1e-9);
        assert!((at(0.1)? - 0.005).abs() < 1e-9, "{}", at(0.1)?);
        Ok(())
    }

    #[test]
    fn bad_values_are_named() {
        let mut bad = sheet();
        bad.noise_std[2] = -1.0;
        assert!(
            bad.validate()
                .is_err_and(|e| e.to_string().contains("noise_std"))
        );
        let mut bad = sheet();
        bad.bias_time_constant = 0.0;
        assert!(
            bad.validate()
                .is_err_and(|e| e.to_string().contains("bias_time_constant = 0"))
        );
        let mut bad = sheet();
        bad.clamp_rotation_in_sensor[0] = f64::NAN;
        assert!(bad.validate().is_err());
        let random_walk = DataSheet {
            bias_time_constant: f64::INFINITY,
            ..sheet()
        };
        assert!(random_walk.validate().is_ok());
    }
}
