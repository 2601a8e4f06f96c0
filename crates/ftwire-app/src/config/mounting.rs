//! A real sensor's mounting file (`--mounting FILE.toml` of the log commands).
//!
//! ```toml
//! clamp_position_in_sensor = [0.0, 0.0, 0.11]       # the clamp point in the sensor frame [m]
//! clamp_rotation_in_sensor = [-1.2092, -1.2092, -1.2092]  # rotation vector [rad]
//! tool_mass = 0.35                                   # [kg], the tool below the sensor
//! tool_centre_of_mass = [0.0, 0.0, 0.05]             # [m], sensor frame
//! ```
//!
//! The keys are those of `ftwire_estimate::ft::MountingSpec` (the clamp pose with the simulated
//! sensor file's names and meanings); keys left out take its defaults, unknown keys are errors.
//! `docs/config.md` lists every key.

use std::path::Path;

use ftwire_estimate::ft::MountingSpec;

use super::file::{SetupError, read_toml, value_error};

/// Reads and checks a mounting file; `None` gives the default mounting (the simulated
/// sensor's).
///
/// # Errors
/// [`SetupError`] naming the file, the line and the key.
pub fn load(path: Option<&Path>) -> Result<MountingSpec, SetupError> {
    let Some(path) = path else {
        return Ok(MountingSpec::default());
    };
    let (spec, text): (MountingSpec, _) = read_toml("mounting", path)?;
    spec.validate().map_err(|e| {
        value_error(
            "mounting",
            (&path.display().to_string(), &text),
            &MountingSpec::default(),
            e.to_string(),
        )
    })?;
    Ok(spec)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bad_value_names_its_line_and_key() {
        let dir = std::env::temp_dir().join(format!("ftwire-mounting-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary folder");
        let file = dir.join("mounting.toml");
        std::fs::write(
            &file,
            "clamp_position_in_sensor = [0, 0, 0.11]\ntool_mass = -2\n",
        )
        .expect("written");
        let message = load(Some(&file)).expect_err("refused").to_string();
        assert!(
            message.contains("line 2") && message.contains("tool_mass"),
            "{message}"
        );
        std::fs::write(&file, "clamp_position = [0, 0, 0.11]\n").expect("written");
        let message = load(Some(&file)).expect_err("refused").to_string();
        assert!(message.contains("clamp_position"), "{message}");
        std::fs::write(&file, "clamp_position_in_sensor = [0, 0, 0.11]\n").expect("written");
        let spec = load(Some(&file)).expect("read");
        assert_eq!(spec.clamp_position_in_sensor, [0.0, 0.0, 0.11]);
        assert_eq!(load(None).expect("default"), MountingSpec::default());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
