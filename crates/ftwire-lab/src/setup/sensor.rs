//! The simulated F/T sensor: a preset or a TOML sensor file.
//!
//! A sensor file holds any of `ftwire_sim::FtSensorParams`'s keys (force first, sensor frame);
//! the keys it leaves out take the library's defaults, unknown keys are errors:
//!
//! ```toml
//! noise_std = [0.05, 0.05, 0.05, 0.002, 0.002, 0.002]   # white noise σ [N, N·m]
//! rate = 1000.0                                         # [Hz]
//! dropout_probability = 1e-4
//! ```
//!
//! `docs/config.md` lists every key with its unit, default and allowed range.

use std::path::Path;

use ftwire_sim::{FtSensor, FtSensorParams};

use ftwire_app::config::{SetupError, parse_toml, read_toml, value_error};

/// The names of the preset sensors, as `--sensor` takes them.
pub const PRESETS: [&str; 3] = ["distorted", "undistorted", "real-like"];

/// Seconds between two rests of a recorded session (placing the wire, settling, averaging):
/// the session clock of [`RecordedRest::time`](crate::experiment::calibration::RecordedRest::time)
/// and of the sensor's deterministic drift.
pub const REST_INTERVAL: f64 = 3.0;

/// The white noise of one reading of the `real-like` preset \[N, N·m\], force first: the
/// scatter of a real rig's readings at one rest (`shared/DESIGN.md`, "Real recordings"),
/// 0.025 / 0.05 / 0.065 N and 0.007 N·m on the bending torques (sensor τx, τy).
pub const REAL_LIKE_NOISE: [f64; 6] = [0.025, 0.05, 0.065, 0.007, 0.007, 0.002];

/// The hysteresis of the `real-like` preset \[N, N·m\], force first
/// (`ftwire_sim::FtSensorParams::hysteresis`): what makes a static map underfit a real
/// recording. About 0.03 % of the default full scale (500 N, 20 N·m), far inside the
/// 0.1–1 % FS a small six-axis sensor's data sheet allows.
pub const REAL_LIKE_HYSTERESIS: [f64; 6] = [0.12, 0.12, 0.15, 0.012, 0.012, 0.004];

/// A simulated F/T sensor: its name (a preset's, or the file as given) and its settings.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorSpec {
    /// The preset's name, or the path of the sensor file as given.
    pub name: String,
    /// The sensor model's settings, validated.
    pub config: FtSensorParams,
}

impl Default for SensorSpec {
    /// The `distorted` preset: the library's default sensor.
    fn default() -> Self {
        Self {
            name: "distorted".to_owned(),
            config: FtSensorParams::default(),
        }
    }
}

impl SensorSpec {
    /// A preset by name: `distorted`, the library's default sensor (gain and cross-talk of
    /// 1–1.5 %, a mild cubic nonlinearity, noise, bias, drift and dropouts); `undistorted`, the
    /// same without gain, cross-talk and nonlinearity (what a perfect calibration gives);
    /// `real-like`, a sensor as a real recording shows it (`shared/DESIGN.md`, "Real
    /// recordings"): the clamp 0.11 m along the sensor's z, offsets of 1–2 N and 0.1–0.4 N·m
    /// that no tare removes (a rig's log carries them), a torsion channel (sensor τz, the
    /// wire's axis) that reads a fifth of the torque about it, one reading's scatter as a real
    /// rig's ([`REAL_LIKE_NOISE`]) and a hysteresis ([`REAL_LIKE_HYSTERESIS`]). No
    /// deterministic drift: a real recording's residual is uncorrelated beyond two records,
    /// and a map fitted on its first half in time does as well on an interleaved split.
    ///
    /// # Example
    /// ```
    /// use ftwire_lab::setup::SensorSpec;
    /// let sensor = SensorSpec::preset("undistorted").expect("a preset");
    /// assert_eq!(sensor.config.cubic_nonlinearity, [0.0; 6]);
    /// assert!(SensorSpec::preset("perfect").is_none());
    /// ```
    pub fn preset(name: &str) -> Option<Self> {
        let default = FtSensorParams::default();
        let config = match name {
            "distorted" => default,
            "undistorted" => FtSensorParams {
                gain: FtSensorParams::ideal().gain,
                cubic_nonlinearity: [0.0; 6],
                ..default
            },
            "real-like" => real_like(default),
            _ => return None,
        };
        Some(Self {
            name: name.to_owned(),
            config,
        })
    }

    /// Whether this is the `undistorted` preset (the only one without gain errors).
    pub fn is_undistorted(&self) -> bool {
        self.name == "undistorted"
    }

    /// A preset name, or else a path to a sensor file (a name that looks like a path, or where
    /// something exists, is read as a file).
    ///
    /// # Errors
    /// [`SetupError`] naming what was wrong.
    pub fn load(given: &str) -> Result<Self, SetupError> {
        if let Some(sensor) = Self::preset(given) {
            return Ok(sensor);
        }
        let path = Path::new(given);
        if !ftwire_app::config::names_a_file(given) {
            return Err(SetupError::Unknown {
                kind: "sensor",
                given: given.to_owned(),
                allowed: format!(
                    "a preset ({}) or a path to a .toml sensor file",
                    PRESETS.join(", ")
                ),
            });
        }
        let (config, text): (FtSensorParams, _) = read_toml("sensor", path)?;
        Self::checked(config, given, &text)
    }

    /// A sensor from the text of a sensor file (`path` names it in errors).
    ///
    /// # Errors
    /// [`SetupError::Bad`] naming the file, the line and the key.
    pub fn from_toml(text: &str, path: &str) -> Result<Self, SetupError> {
        Self::checked(parse_toml("sensor", text, path)?, path, text)
    }

    fn checked(config: FtSensorParams, path: &str, text: &str) -> Result<Self, SetupError> {
        FtSensor::new(config.clone(), 0).map_err(|e| {
            value_error(
                "sensor",
                (path, text),
                &FtSensorParams::default(),
                e.to_string(),
            )
        })?;
        Ok(Self {
            name: path.to_owned(),
            config,
        })
    }
}

/// The data sheet of the simulated sensor `params`: what a rig would know of it (its white
/// noise, drift and clamp), in the real rig's type, which never sees the simulator.
pub fn data_sheet(params: &FtSensorParams) -> ftwire_rig::DataSheet {
    ftwire_rig::DataSheet {
        noise_std: params.noise_std,
        bias_random_walk: params.bias_random_walk,
        bias_time_constant: params.bias_time_constant,
        clamp_position_in_sensor: params.clamp_position_in_sensor,
        clamp_rotation_in_sensor: params.clamp_rotation_in_sensor,
    }
}

/// The `real-like` preset (see [`SensorSpec::preset`]).
fn real_like(default: FtSensorParams) -> FtSensorParams {
    let mut gain = default.gain;
    // Sensor τz is the torque about the clamp's x, the wire's axis (default rotation).
    gain[5][5] = 0.2;
    FtSensorParams {
        clamp_position_in_sensor: [0.0, 0.0, 0.11],
        gain,
        hysteresis: REAL_LIKE_HYSTERESIS,
        initial_bias: [-1.8, 1.3, 1.8, -0.25, 0.12, 0.35],
        noise_std: REAL_LIKE_NOISE,
        ..default
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &str) -> String {
        match SensorSpec::from_toml(text, "s.toml") {
            Err(e) => e.to_string(),
            Ok(s) => panic!("accepted {s:?}"),
        }
    }

    #[test]
    fn the_init_example_is_the_default_sensor() -> Result<(), Box<dyn std::error::Error>> {
        let text = ftwire_app::init::example("sensor.toml").ok_or("no sensor.toml example")?;
        let sensor = SensorSpec::from_toml(text, "sensor.toml")?;
        assert_eq!(sensor.config, SensorSpec::default().config);
        Ok(())
    }

    #[test]
    fn the_defaults_round_trip_and_an_empty_file_is_the_default()
    -> Result<(), Box<dyn std::error::Error>> {
        let text = toml::to_string(&FtSensorParams::default())?;
        assert_eq!(
            SensorSpec::from_toml(&text, "s.toml")?.config,
            FtSensorParams::default()
        );
        assert_eq!(
            SensorSpec::from_toml("", "s.toml")?.config,
            SensorSpec::default().config
        );
        Ok(())
    }

    /// The real rig's side reads the same files and presets without the simulator
    /// (`ftwire_app::config::sensor`): its presets, its default and its keys must be the
    /// simulator's.
    #[test]
    fn the_real_rigs_data_sheets_are_the_simulated_sensors()
    -> Result<(), Box<dyn std::error::Error>> {
        use ftwire_app::config::sensor::{
            DEFAULT, DataSheetSpec, PRESETS as SHEETS, SIMULATOR_KEYS,
        };
        assert_eq!(SHEETS, PRESETS);
        for name in PRESETS {
            let simulated = SensorSpec::preset(name).ok_or("a preset")?;
            let sheet = DataSheetSpec::preset(name).ok_or("a data sheet")?;
            assert_eq!(sheet.sheet, data_sheet(&simulated.config), "{name}");
        }
        assert_eq!(DEFAULT, data_sheet(&FtSensorParams::default()));
        let table = toml::Table::try_from(FtSensorParams::default())?;
        let mut keys: Vec<&str> = table.keys().map(String::as_str).collect();
        keys.sort_unstable();
        let mut known: Vec<&str> = SIMULATOR_KEYS
            .into_iter()
            .chain(ftwire_rig::DataSheet::KEYS)
            .collect();
        known.sort_unstable();
        assert_eq!(keys, known);
        // A file of the simulator's is a data sheet too, the same one.
        let file = "rate = 500.0\nnoise_std = [0.1, 0.1, 0.1, 0.01, 0.01, 0.01]\n";
        assert_eq!(
            DataSheetSpec::from_toml(file, "s.toml")?.sheet,
            data_sheet(&SensorSpec::from_toml(file, "s.toml")?.config)
        );
        assert_eq!(
            crate::identify::TEMPLATE_RADIUS,
            ftwire_sim::RodParams::default().radius
        );
        Ok(())
    }

    #[test]
    fn a_bad_sensor_file_names_the_file_the_line_and_the_key() {
        let message = error("rate = 500.0\n\nnoise_sdt = [0.1, 0.1, 0.1, 0.0, 0.0, 0.0]\n");
        assert!(message.contains("s.toml"), "{message}");
        assert!(message.contains("line 3"), "{message}");
        assert!(message.contains("noise_sdt"), "{message}");
        let message = error("rate = 500.0\nnoise_std = [0.1, 0.1, -0.1, 0.0, 0.0, 0.0]\n");
        assert!(message.contains("s.toml"), "{message}");
        assert!(message.contains("line 2, key noise_std"), "{message}");
        assert!(message.contains("≥ 0"), "{message}");
        let message = error("dropout_probability = 1.0\n");
        assert!(
            message.contains("line 1, key dropout_probability"),
            "{message}"
        );
        let message = error("rate = \"fast\"\n");
        assert!(
            message.contains("line 1") && message.contains("rate"),
            "{message}"
        );
        assert!(matches!(
            SensorSpec::load("no-such-sensor"),
            Err(SetupError::Unknown { .. })
        ));
    }
}
