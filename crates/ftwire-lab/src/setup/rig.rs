//! The simulated rig, beyond its sensor: motion capture, the robot's execution error and the
//! timing of its moves, from a TOML rig file.
//!
//! A rig file holds any of these keys; the ones it leaves out take the library's defaults
//! (`ftwire_sim::RigParams::default`), unknown keys are errors:
//!
//! ```toml
//! linear_speed = 0.05       # gripper speed that times a move [m/s], in [0.001, 10]
//! angular_speed = 0.5       # [rad/s], in [0.001, 10]
//! settle_time = 0.1         # after each move [s], in [0, 3600]
//!
//! [markers]                 # motion capture
//! noise_std = 0.0003        # σ per axis [m]
//! mount_offset = 0.0        # each marker's centre off the centreline [m]
//!
//! [execution]               # the simulator's own gripper error (default none)
//! position_std = 0.0        # σ per axis [m]
//! ```
//!
//! The seed of each rig is the experiment's (`--seed`), and the sensor is `--sensor`'s.
//! `docs/config.md` lists every key with its unit, default and allowed range.

use std::path::Path;

use ftwire_sim::{ExecutionErrorParams, MarkerParams, RigParams};
use serde::{Deserialize, Serialize};

use ftwire_app::config::{SetupError, parse_toml, read_toml, value_error};

/// The rig file: `ftwire_sim::RigParams` without its sensor (`--sensor`) and seed (`--seed`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RigSpec {
    /// Gripper speed used to time a move \[m/s\] (default: the library's, `0.05`).
    pub linear_speed: f64,
    /// Gripper angular speed used to time a move \[rad/s\] (default: the library's, `0.5`).
    pub angular_speed: f64,
    /// Time to settle after each move \[s\] (default: the library's, `0.1`).
    pub settle_time: f64,
    /// Motion capture: marker arc-length fractions, noise, dropouts and mounting offsets
    /// (default: the library's, 11 markers on the centreline, 0.3 mm, 2 %).
    pub markers: MarkerParams,
    /// The simulator's own execution error of the grippers (default: none).
    pub execution: ExecutionErrorParams,
}

impl Default for RigSpec {
    /// The library's rig (`RigParams::default`).
    fn default() -> Self {
        let rig = RigParams::default();
        Self {
            linear_speed: rig.linear_speed,
            angular_speed: rig.angular_speed,
            settle_time: rig.settle_time,
            markers: rig.markers,
            execution: rig.execution,
        }
    }
}

impl RigSpec {
    /// The rig from a rig file.
    ///
    /// # Errors
    /// [`SetupError`] naming the file, the line and the key.
    pub fn load(path: &Path) -> Result<Self, SetupError> {
        let (rig, text): (Self, _) = read_toml("rig", path)?;
        rig.checked(&path.display().to_string(), &text)
    }

    /// The rig from the text of a rig file (`path` names it in errors).
    ///
    /// # Errors
    /// [`SetupError::Bad`] naming the file, the line and the key.
    pub fn from_toml(text: &str, path: &str) -> Result<Self, SetupError> {
        parse_toml::<Self>("rig", text, path)?.checked(path, text)
    }

    fn checked(self, path: &str, text: &str) -> Result<Self, SetupError> {
        self.config()
            .validate()
            .map_err(|e| value_error("rig", (path, text), &Self::default(), e.to_string()))?;
        Ok(self)
    }

    /// The simulator's rig settings with this rig, the default sensor and seed 0.
    pub fn config(&self) -> RigParams {
        RigParams {
            markers: self.markers.clone(),
            execution: self.execution,
            linear_speed: self.linear_speed,
            angular_speed: self.angular_speed,
            settle_time: self.settle_time,
            ..RigParams::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_round_trip_and_are_the_librarys() -> Result<(), Box<dyn std::error::Error>> {
        let text = toml::to_string(&RigSpec::default())?;
        assert_eq!(RigSpec::from_toml(&text, "r.toml")?, RigSpec::default());
        assert_eq!(
            RigSpec::from_toml("", "r.toml")?.config(),
            RigParams::default()
        );
        Ok(())
    }

    #[test]
    fn the_init_example_is_the_default_rig() -> Result<(), Box<dyn std::error::Error>> {
        let text = ftwire_app::init::example("rig.toml").ok_or("no rig.toml example")?;
        assert_eq!(RigSpec::from_toml(text, "rig.toml")?, RigSpec::default());
        Ok(())
    }

    #[test]
    fn a_bad_rig_file_names_the_file_the_line_and_the_key() {
        let error = |text: &str| match RigSpec::from_toml(text, "r.toml") {
            Err(e) => e.to_string(),
            Ok(r) => panic!("accepted {r:?}"),
        };
        let message = error("settle_time = 0.2\n[markers]\nnoise = 0.001\n");
        assert!(message.contains("r.toml"), "{message}");
        assert!(message.contains("line 3"), "{message}");
        assert!(message.contains("noise"), "{message}");
        let message = error("linear_speed = 0.0\n");
        assert!(message.contains("line 1, key linear_speed"), "{message}");
        assert!(message.contains("[0.001, 10] m/s"), "{message}");
        let message = error("\nsettle_time = 1e300\n");
        assert!(
            message.contains("line 2, key settle_time")
                && message.contains("1e300")
                && message.contains("[0, 3600] s"),
            "{message}"
        );
        let message = error("[markers]\ndropout_probability = 1.5\n");
        assert!(
            message.contains("line 2, key dropout_probability"),
            "{message}"
        );
        let message = error("[execution]\nposition_std = -0.01\n");
        assert!(message.contains("line 2, key position_std"), "{message}");
    }
}
