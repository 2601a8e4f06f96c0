//! Wires as users name them: a preset, or a TOML file.
//!
//! A wire file holds exactly these keys (unknown keys are errors):
//!
//! ```toml
//! name = "nitinol-3mm-820"
//! c = [0.214, 0.278, 0.278]    # stiffnesses c1 (torsion), c2, c3 (bending) [N·m²]
//! length = 0.82                # between the clamp points [m]
//! radius = 0.0015              # [m]
//! density = 6450.0             # [kg/m³]
//! natural_curvature = [0.0, 0.0, 0.0]   # optional: rest twist and curvatures κ1, κ2, κ3 [1/m]
//! ```
//!
//! The presets are the wires of the paper (Table II) and a reel-stored cable; the simulator's
//! presets (`ftwire_sim::RodParams::nitinol_2mm_630` …) hold the same numbers, which a test
//! of `ftwire-lab` checks, since this crate never depends on the simulator.

use std::path::Path;

use ftwire_core::WireParams;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The names of the preset wires, as `--wire` takes them.
pub const PRESETS: [&str; 4] = [
    "nitinol-2mm-630",
    "nitinol-3mm-910",
    "nitinol-3mm-820",
    "cable-3mm-920",
];

/// A wire's name as a file name's stem (figures, logs): characters other than ASCII letters,
/// digits, `-`, `_` and `.` replaced by `_`, so that any name (a wire file's may hold anything)
/// gives one file inside the results folder.
///
/// # Example
/// ```
/// use ftwire_app::config::wire::file_stem;
/// assert_eq!(file_stem("nitinol-2mm-630"), "nitinol-2mm-630");
/// assert_eq!(file_stem("../a b/c"), ".._a_b_c");
/// ```
pub fn file_stem(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// A wire: its name and physical properties.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WireSpec {
    /// Name, for reports.
    pub name: String,
    /// Stiffnesses `(c1, c2, c3)` \[N·m²\]: torsion, bending about body y and z.
    pub c: [f64; 3],
    /// Length between the clamp points \[m\].
    pub length: f64,
    /// Radius \[m\].
    pub radius: f64,
    /// Density \[kg/m³\].
    pub density: f64,
    /// Rest twist and curvatures `(κ1, κ2, κ3)` \[1/m\] in the body frame (default zero: a
    /// straight rest shape).
    #[serde(default)]
    pub natural_curvature: [f64; 3],
}

/// Why a wire could not be had.
#[derive(Debug, Error)]
pub enum WireSpecError {
    /// Neither a preset nor a name of a file (see [`WireSpec::load`]).
    #[error(
        "unknown wire {given:?}: give a preset ({}) or a path to a .toml wire file",
        PRESETS.join(", ")
    )]
    Unknown {
        /// What was given.
        given: String,
    },
    /// The file could not be read.
    #[error("cannot read wire file {path}: {message}")]
    Read {
        /// The file.
        path: String,
        /// The system's message.
        message: String,
    },
    /// The file is not a valid wire file (the message names the line and the key).
    #[error("bad wire file {path}: {message}")]
    Parse {
        /// The file.
        path: String,
        /// What `toml` said, with the line and the key.
        message: String,
    },
    /// A value is out of range.
    #[error(
        "wire {name:?}: {key} = {} is not allowed: {allowed}",
        ftwire_core::text::Number(*value)
    )]
    Value {
        /// The wire.
        name: String,
        /// The key.
        key: &'static str,
        /// The value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
}

/// Smallest stiffness of a wire file \[N·m²\].
pub const MIN_STIFFNESS: f64 = 1e-8;
/// Largest stiffness of a wire file \[N·m²\].
pub const MAX_STIFFNESS: f64 = 1e4;
/// Largest rest curvature of a wire file \[1/m\] (a bend of 1 mm radius).
pub const MAX_CURVATURE: f64 = 1e3;

impl WireSpec {
    /// A preset wire by name, if there is one.
    ///
    /// # Example
    /// ```
    /// let wire = ftwire_app::config::wire::WireSpec::preset("nitinol-3mm-820").expect("a preset");
    /// assert_eq!(wire.c, [0.214, 0.278, 0.278]);
    /// assert!(ftwire_app::config::wire::WireSpec::preset("copper").is_none());
    /// ```
    pub fn preset(name: &str) -> Option<Self> {
        // Nitinol: 6450 kg/m³; c of paper Table II. The cable: copper strands in PVC, c of a
        // 3 mm cable with an effective Young's modulus of about 1.1 GPa, 3000 kg/m³, and a
        // rest curvature of 1.5 1/m about body z from its reel.
        let (c, length, radius, density, natural_curvature) = match name {
            "nitinol-2mm-630" => ([0.042, 0.055, 0.055], 0.63, 0.001, 6450.0, [0.0; 3]),
            "nitinol-3mm-910" => ([0.214, 0.278, 0.278], 0.91, 0.0015, 6450.0, [0.0; 3]),
            "nitinol-3mm-820" => ([0.214, 0.278, 0.278], 0.82, 0.0015, 6450.0, [0.0; 3]),
            "cable-3mm-920" => (
                [0.0030, 0.0045, 0.0045],
                0.92,
                0.0015,
                3000.0,
                [0.0, 0.0, 1.5],
            ),
            _ => return None,
        };
        Some(Self {
            name: name.to_owned(),
            c,
            length,
            radius,
            density,
            natural_curvature,
        })
    }

    /// A preset name, or else a path to a wire file (a name that looks like a path, or where
    /// something exists, is read as a file, so that a file that cannot be read says why).
    ///
    /// # Errors
    /// [`WireSpecError`] naming what was wrong.
    pub fn load(given: &str) -> Result<Self, WireSpecError> {
        if let Some(wire) = Self::preset(given) {
            return Ok(wire);
        }
        if !super::names_a_file(given) {
            return Err(WireSpecError::Unknown {
                given: given.to_owned(),
            });
        }
        let text = ftwire_core::text::read_text(Path::new(given)).map_err(|e| match e {
            ftwire_core::CoreError::Unreadable { message } => WireSpecError::Read {
                path: given.to_owned(),
                message,
            },
            e => WireSpecError::Parse {
                path: given.to_owned(),
                message: e.to_string(),
            },
        })?;
        Self::from_toml(&text, given)
    }

    /// A wire from the text of a wire file (`path` names it in errors).
    ///
    /// # Errors
    /// [`WireSpecError::Parse`] with the line and key, or [`WireSpecError::Value`].
    pub fn from_toml(text: &str, path: &str) -> Result<Self, WireSpecError> {
        let wire: Self = toml::from_str(text).map_err(|e| WireSpecError::Parse {
            path: path.to_owned(),
            message: e.to_string().trim_end().to_owned(),
        })?;
        wire.validate().map_err(|e| match &e {
            // A value out of range: the file, and the line of its key (`c` for `c2`,
            // `natural_curvature` for `natural_curvature[1]`).
            WireSpecError::Value { key, .. } => {
                let name = key.split('[').next().unwrap_or(key);
                let name = if matches!(name, "c1" | "c2" | "c3") {
                    "c"
                } else {
                    name
                };
                let line = super::line_of(text, name)
                    .map_or_else(String::new, |line| format!("line {line}, "));
                WireSpecError::Parse {
                    path: path.to_owned(),
                    message: format!("{line}key {name}: {e}"),
                }
            }
            _ => e,
        })?;
        Ok(wire)
    }

    fn validate(&self) -> Result<(), WireSpecError> {
        let value = |key: &'static str, value: f64, allowed: &'static str| WireSpecError::Value {
            name: self.name.clone(),
            key,
            value,
            allowed,
        };
        // Plausible ranges, far beyond any wire or cable (a 2 mm nitinol wire bends with
        // 0.05 N·m², a 10 mm steel rod with 100): a value outside is a unit slip or a
        // damaged file, and the model has no answer there.
        for (key, v) in ["c1", "c2", "c3"].into_iter().zip(self.c) {
            if !(v.is_finite() && (MIN_STIFFNESS..=MAX_STIFFNESS).contains(&v)) {
                return Err(value(key, v, "a stiffness from 1e-8 to 1e4 N·m²"));
            }
        }
        let ranges = [
            (
                "length",
                self.length,
                (1e-3, 100.0),
                "a length from 1 mm to 100 m",
            ),
            (
                "radius",
                self.radius,
                (0.0, 1.0),
                "a radius > 0 and at most 1 m",
            ),
            (
                "density",
                self.density,
                (0.0, 1e5),
                "a density > 0 and at most 1e5 kg/m³",
            ),
        ];
        for (key, v, (low, high), allowed) in ranges {
            if !(v.is_finite() && v > 0.0 && v >= low && v <= high) {
                return Err(value(key, v, allowed));
            }
        }
        if 2.0 * self.radius >= self.length {
            return Err(value(
                "radius",
                self.radius,
                "less than half the length (a wire, not a disc)",
            ));
        }
        for (key, v) in [
            "natural_curvature[0]",
            "natural_curvature[1]",
            "natural_curvature[2]",
        ]
        .into_iter()
        .zip(self.natural_curvature)
        {
            if !(v.is_finite() && v.abs() <= MAX_CURVATURE) {
                return Err(value(key, v, "a curvature of at most 1e3 1/m in size"));
            }
        }
        Ok(())
    }

    /// The model's wire parameters (stiffness, length, radius).
    ///
    /// # Errors
    /// Never for a validated spec; kept fallible for the core type's own checks.
    pub fn wire_params(&self) -> Result<WireParams, ftwire_core::CoreError> {
        WireParams::new(self.c, self.length, self.radius)
    }
}

/// The rule of wire files ([`WireSpec`]) for a wire given otherwise (command-line options, a
/// batch line): a radius below half the length (a wire, not a disc). `radius` and `length`
/// name the two values in the message, e.g. `--radius` and `--length`.
///
/// # Errors
/// The message, naming both values and the largest radius allowed.
///
/// # Example
/// ```
/// use ftwire_app::config::wire::check_radius;
/// let disc = ftwire_core::WireParams::new([0.1; 3], 0.63, 1.0)?;
/// let e = check_radius(&disc, "--radius", "--length").err().unwrap_or_default();
/// assert!(e.starts_with("--radius 1: "));
/// let wire = ftwire_core::WireParams::new([0.1; 3], 0.63, 0.001)?;
/// assert!(check_radius(&wire, "--radius", "--length").is_ok());
/// # Ok::<(), ftwire_core::CoreError>(())
/// ```
pub fn check_radius(wire: &WireParams, radius: &str, length: &str) -> Result<(), String> {
    if 2.0 * wire.radius() < wire.length() {
        return Ok(());
    }
    Err(format!(
        "{radius} {}: give less than half the wire's length ({length} {} m), a wire, not a disc",
        wire.radius(),
        wire.length()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wire_file_round_trips() -> Result<(), Box<dyn std::error::Error>> {
        let wire = WireSpec::preset("cable-3mm-920").ok_or("preset")?;
        let text = toml::to_string(&wire)?;
        assert_eq!(WireSpec::from_toml(&text, "cable.toml")?, wire);
        Ok(())
    }

    #[test]
    fn a_bad_file_names_the_line_and_the_key() {
        let text = "name = \"w\"\nc = [0.1, 0.1, 0.1]\nlength = 0.5\nradius = 0.001\ndensity = 6450\nstifness = 3\n";
        let message = match WireSpec::from_toml(text, "w.toml") {
            Err(e) => e.to_string(),
            Ok(w) => panic!("accepted {w:?}"),
        };
        assert!(message.contains("w.toml"), "{message}");
        assert!(message.contains("line 6"), "{message}");
        assert!(message.contains("stifness"), "{message}");
        let negative = text
            .replace("stifness = 3\n", "")
            .replace("length = 0.5", "length = -0.5");
        let message = WireSpec::from_toml(&negative, "w.toml")
            .map(|_| ())
            .err()
            .map(|e| e.to_string());
        assert!(
            message.as_ref().is_some_and(|m| m.contains("length = -0.5")
                && m.contains("w.toml")
                && m.contains("line 3, key length")),
            "{message:?}"
        );
        assert!(matches!(
            WireSpec::load("no-such-wire"),
            Err(WireSpecError::Unknown { .. })
        ));
    }

    /// Numbers beyond any wire (a stiffness of 1e308, a length of 1e300, a tiny stiffness) are
    /// refused at load, named as given, not left for the model to find no answer at.
    #[test]
    fn implausible_numbers_are_refused_at_load() {
        let text =
            "name = \"w\"\nc = [0.1, 0.1, 0.1]\nlength = 0.5\nradius = 0.001\ndensity = 6450\n";
        for (from, to, shown) in [
            (
                "c = [0.1, 0.1, 0.1]",
                "c = [1e308, 0.1, 0.1]",
                "c1 = 1e308 ",
            ),
            (
                "c = [0.1, 0.1, 0.1]",
                "c = [0.1, 1e-300, 0.1]",
                "c2 = 1e-300 ",
            ),
            ("length = 0.5", "length = 1e300", "length = 1e300 "),
            ("density = 6450", "density = 1e9", "density = 1000000000 "),
            (
                "\n",
                "\nnatural_curvature = [0.0, 1e308, 0.0]\n",
                "natural_curvature[1] = 1e308 ",
            ),
        ] {
            let message = match WireSpec::from_toml(&text.replacen(from, to, 1), "w.toml") {
                Err(e) => e.to_string(),
                Ok(w) => panic!("accepted {w:?}"),
            };
            assert!(
                message.contains(shown) && message.contains("w.toml"),
                "{message}"
            );
        }
    }
}
