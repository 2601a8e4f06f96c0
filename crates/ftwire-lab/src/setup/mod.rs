//! The simulated rig's setup as users give it: the F/T sensor (a preset or a TOML file) and the
//! rig (a TOML file), as [`crate::wire`] does for wires.
//!
//! Every key, its unit, default and allowed range is in `docs/config.md`; `ftwire init DIR`
//! writes a commented example of each file. Missing keys take the library's defaults
//! (`ftwire_sim::FtSensorParams::default`, `ftwire_sim::RigParams::default`), unknown keys are
//! errors, and every error names the file, and the line and the key where there is one. Files
//! are UTF-8 text, a leading byte-order mark allowed (`ftwire_core::text::read_text`); a name
//! that looks like a path is read as one (`names_a_file`), so that its read error is reported.
//! With neither file, [`SimSetup::default`] is exactly the rig the experiments have always
//! run against.

pub mod rig;
pub mod sensor;

use std::path::Path;

use ftwire_sim::RigParams;

pub use ftwire_app::config::{SetupError, mounting};
pub use rig::RigSpec;
pub use sensor::SensorSpec;

/// The simulated rig of a run: its F/T sensor and the rest of the rig.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SimSetup {
    /// The F/T sensor on the base gripper.
    pub sensor: SensorSpec,
    /// Motion capture, execution error and motion timing.
    pub rig: RigSpec,
    /// How a calibration session is recorded.
    pub protocol: Protocol,
}

/// How a calibration session is recorded (`--protocol`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Protocol {
    /// Each configuration an independent sample of `A_free`, placed anew, the sensor tared
    /// on the empty gripper before it, the reading averaged over a rest (the paper's
    /// collection).
    #[default]
    Rests,
    /// As a real rig logs a session (`shared/DESIGN.md`, "Real recordings"): the second
    /// gripper steps about 17 mm (sometimes twice that) from one rest to the next, the
    /// sensor is tared once, each record holds one reading of the sensor at 4 Hz, and some
    /// rests have 2 or 3 records. The sensor's load history (its hysteresis) carries over
    /// from rest to rest. The markers are balls glued off the centreline, one set for the
    /// session (`experiment::calibration::RECORDING_MOUNT_OFFSET`). The wire softens in
    /// bending as nitinol does (`experiment::calibration::RECORDING_SOFTENING_STRAIN`),
    /// which the models, linear in bending, do not describe.
    SingleReadings,
}

impl Protocol {
    /// The names `--protocol` takes.
    pub const NAMES: [&'static str; 2] = ["rests", "single-readings"];

    /// The protocol of a name of [`Self::NAMES`].
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "rests" => Some(Self::Rests),
            "single-readings" => Some(Self::SingleReadings),
            _ => None,
        }
    }
}

impl SimSetup {
    /// `--sensor PRESET|FILE.toml` and `--rig FILE.toml`, each defaulting to the library's.
    ///
    /// # Errors
    /// [`SetupError`] naming the file, the line and the key.
    pub fn load(sensor: Option<&str>, rig: Option<&Path>) -> Result<Self, SetupError> {
        Ok(Self {
            sensor: sensor.map_or_else(|| Ok(SensorSpec::default()), SensorSpec::load)?,
            rig: rig.map_or_else(|| Ok(RigSpec::default()), RigSpec::load)?,
            protocol: Protocol::default(),
        })
    }

    /// The setup with a calibration session recorded by `protocol`.
    #[must_use]
    pub fn with_protocol(self, protocol: Protocol) -> Self {
        Self { protocol, ..self }
    }

    /// The simulator's rig settings with the rig's `seed`.
    ///
    /// # Example
    /// ```
    /// use ftwire_lab::setup::SimSetup;
    /// use ftwire_sim::RigParams;
    /// // Without files: the rig the experiments have always used.
    /// assert_eq!(SimSetup::default().rig_config(7), RigParams { seed: 7, ..RigParams::default() });
    /// ```
    pub fn rig_config(&self, seed: u64) -> RigParams {
        RigParams {
            sensor: self.sensor.config.clone(),
            seed,
            ..self.rig.config()
        }
    }
}
