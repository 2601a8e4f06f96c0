//! A sensor's data sheet as a real rig's commands take it (`--sensor` of `shape --log` and
//! `identify --log`): a preset's name or a TOML sensor file.
//!
//! ```toml
//! noise_std = [0.025, 0.05, 0.065, 0.007, 0.007, 0.002]   # one reading's σ [N, N·m], force first
//! bias_random_walk = [0.002, 0.002, 0.002, 8e-5, 8e-5, 8e-5]   # drift intensity [per √s]
//! bias_time_constant = 600.0                              # [s]
//! clamp_position_in_sensor = [0.0, 0.0, 0.11]             # [m]
//! clamp_rotation_in_sensor = [-1.2092, -1.2092, -1.2092]  # rotation vector [rad]
//! ```
//!
//! The file is the simulated sensor's file (`docs/config.md`): the keys only a simulator reads
//! ([`SIMULATOR_KEYS`]: its gain, nonlinearity, clock …) are accepted and not read here, any
//! other key is an error, and the keys left out take the default sensor's values
//! ([`DEFAULT`]). The presets' numbers are the simulator's presets' (a test of `ftwire-lab`
//! checks them; this crate never depends on the simulator).

use std::path::Path;

use ftwire_rig::DataSheet;

use super::{SetupError, line_of, names_a_file};

/// The names of the preset sensors, as `--sensor` takes them.
pub const PRESETS: [&str; 3] = ["distorted", "undistorted", "real-like"];

/// The keys of a sensor file that only the simulator reads.
pub const SIMULATOR_KEYS: [&str; 10] = [
    "gain",
    "cubic_nonlinearity",
    "hysteresis",
    "full_scale",
    "saturation",
    "initial_bias",
    "bias_drift_rate",
    "rate",
    "clock_offset",
    "dropout_probability",
];

/// The default sensor's data sheet (the `distorted` and `undistorted` presets'; a file's
/// missing keys): 0.05 N and 2 mN·m of white noise per reading, a drift of 2 mN/√s and
/// 80 µN·m/√s with a 600 s time constant, the clamp 0.08 m along the sensor's z and turned by
/// −120° about (1, 1, 1).
pub const DEFAULT: DataSheet = DataSheet {
    noise_std: [0.05, 0.05, 0.05, 0.002, 0.002, 0.002],
    bias_random_walk: [0.002, 0.002, 0.002, 8e-5, 8e-5, 8e-5],
    bias_time_constant: 600.0,
    clamp_position_in_sensor: [0.0, 0.0, 0.08],
    // −2π/3 about (1, 1, 1)/√3, as a rotation vector.
    clamp_rotation_in_sensor: [
        -2.0 * std::f64::consts::FRAC_PI_3 / SQRT_3,
        -2.0 * std::f64::consts::FRAC_PI_3 / SQRT_3,
        -2.0 * std::f64::consts::FRAC_PI_3 / SQRT_3,
    ],
};

const SQRT_3: f64 = 1.732_050_807_568_877_2;

/// A sensor's data sheet: its name (a preset's, or the file as given) and the numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct DataSheetSpec {
    /// The preset's name, or the path of the sensor file as given.
    pub name: String,
    /// The data sheet, validated.
    pub sheet: DataSheet,
}

impl DataSheetSpec {
    /// A preset by name: `distorted` and `undistorted` (the default sensor's data sheet, see
    /// [`DEFAULT`]), `real-like` (one reading's scatter as a real rig's, 0.025 / 0.05 / 0.065 N
    /// and 7 mN·m on the bending torques, the clamp 0.11 m along the sensor's z).
    pub fn preset(name: &str) -> Option<Self> {
        let sheet = match name {
            "distorted" | "undistorted" => DEFAULT,
            "real-like" => DataSheet {
                noise_std: [0.025, 0.05, 0.065, 0.007, 0.007, 0.002],
                clamp_position_in_sensor: [0.0, 0.0, 0.11],
                ..DEFAULT
            },
            _ => return None,
        };
        Some(Self {
            name: name.to_owned(),
            sheet,
        })
    }

    /// A preset name, or else a path to a sensor file (a name that looks like a path, or where
    /// something exists, is read as a file).
    ///
    /// # Errors
    /// [`SetupError`] naming what was wrong: the file, the line and the key.
    pub fn load(given: &str) -> Result<Self, SetupError> {
        if let Some(sheet) = Self::preset(given) {
            return Ok(sheet);
        }
        if !names_a_file(given) {
            return Err(SetupError::Unknown {
                kind: "sensor",
                given: given.to_owned(),
                allowed: format!(
                    "a preset ({}) or a path to a .toml sensor file",
                    PRESETS.join(", ")
                ),
            });
        }
        let (table, text): (toml::Table, _) = super::read_toml("sensor", Path::new(given))?;
        Self::from_table(table, &text, given)
    }

    /// A data sheet from the text of a sensor file (`path` names it in errors).
    ///
    /// # Errors
    /// [`SetupError::Bad`] naming the file, the line and the key.
    pub fn from_toml(text: &str, path: &str) -> Result<Self, SetupError> {
        Self::from_table(super::parse_toml("sensor", text, path)?, text, path)
    }

    fn from_table(mut table: toml::Table, text: &str, path: &str) -> Result<Self, SetupError> {
        let bad = |key: &str, message: String| {
            let at = line_of(text, key).map_or_else(String::new, |l| format!("line {l}, "));
            SetupError::Bad {
                kind: "sensor",
                path: path.to_owned(),
                message: format!("{at}key {key}: {message}"),
            }
        };
        let mut defaults =
            toml::Table::try_from(DEFAULT).map_err(|e| bad("noise_std", e.to_string()))?;
        for (key, value) in std::mem::take(&mut table) {
            if DataSheet::KEYS.contains(&key.as_str()) {
                defaults.insert(key, value);
            } else if !SIMULATOR_KEYS.contains(&key.as_str()) {
                return Err(bad(
                    &key,
                    format!(
                        "unknown key; a sensor file holds {} (and the simulator's {})",
                        DataSheet::KEYS.join(", "),
                        SIMULATOR_KEYS.join(", ")
                    ),
                ));
            }
        }
        let sheet: DataSheet = defaults.clone().try_into().map_err(|e: toml::de::Error| {
            let key = DataSheet::KEYS
                .into_iter()
                .find(|k| e.to_string().contains(k))
                .unwrap_or("noise_std");
            bad(key, e.to_string().trim_end().to_owned())
        })?;
        sheet.validate().map_err(|e| {
            let message = e.to_string();
            let key = DataSheet::KEYS
                .into_iter()
                .find(|k| message.contains(k))
                .unwrap_or("noise_std");
            bad(key, message)
        })?;
        Ok(Self {
            name: path.to_owned(),
            sheet,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &str) -> String {
        match DataSheetSpec::from_toml(text, "s.toml") {
            Err(e) => e.to_string(),
            Ok(s) => panic!("accepted {s:?}"),
        }
    }

    #[test]
    fn an_empty_file_is_the_default_and_simulator_keys_are_accepted() -> Result<(), SetupError> {
        assert_eq!(DataSheetSpec::from_toml("", "s.toml")?.sheet, DEFAULT);
        let text = "rate = 500.0\ngain = [[1.0, 0, 0, 0, 0, 0]]\nnoise_std = [0.1, 0.1, 0.1, 0.0, 0.0, 0.0]\n";
        let sheet = DataSheetSpec::from_toml(text, "s.toml")?.sheet;
        assert_eq!(sheet.noise_std, [0.1, 0.1, 0.1, 0.0, 0.0, 0.0]);
        assert_eq!(sheet.bias_time_constant, DEFAULT.bias_time_constant);
        Ok(())
    }

    #[test]
    fn a_bad_sensor_file_names_the_file_the_line_and_the_key() {
        let message = error("rate = 500.0\n\nnoise_sdt = [0.1, 0.1, 0.1, 0.0, 0.0, 0.0]\n");
        assert!(
            message.contains("s.toml") && message.contains("line 3, key noise_sdt"),
            "{message}"
        );
        let message = error("noise_std = [0.1, 0.1, -0.1, 0.0, 0.0, 0.0]\n");
        assert!(message.contains("line 1, key noise_std"), "{message}");
        assert!(message.contains("≥ 0"), "{message}");
        let message = error("bias_time_constant = \"long\"\n");
        assert!(message.contains("bias_time_constant"), "{message}");
        assert!(matches!(
            DataSheetSpec::load("no-such-sensor"),
            Err(SetupError::Unknown { .. })
        ));
    }
}
