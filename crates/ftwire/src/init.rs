//! `ftwire init DIR`: a commented example of each configuration file, as every command that
//! takes one accepts it (`tests/init_cli.rs` runs them).
//!
//! The examples are hand-written TOML under `src/init/`, each key with its unit, default and
//! allowed range in a comment; `docs/config.md` is the full schema. The sensor, rig and
//! mounting examples hold the library's defaults and the wire example the preset
//! `nitinol-3mm-820` (checked by the tests below), so passing them changes nothing but the
//! header of a run.

use std::path::{Path, PathBuf};

use ftwire_lab::error::LabError;

/// The example files, by file name.
pub const EXAMPLES: [(&str, &str); 5] = [
    ("wire.toml", include_str!("init/wire.toml")),
    ("sensor.toml", include_str!("init/sensor.toml")),
    ("rig.toml", include_str!("init/rig.toml")),
    ("scene.toml", include_str!("init/scene.toml")),
    ("mounting.toml", include_str!("init/mounting.toml")),
];

/// Writes the [`EXAMPLES`] into `dir`, creating `dir` when its parent exists. Without `force`
/// no file is written when any of them exists already. Returns the files written.
///
/// # Errors
/// Bad input (exit 2) naming the folder or the file: a missing parent, a `dir` that is a file,
/// an existing example without `force`, a folder that cannot be written.
pub fn write_examples(dir: &Path, force: bool) -> Result<Vec<PathBuf>, LabError> {
    let shown = dir.display();
    if dir.exists() && !dir.is_dir() {
        return Err(LabError::bad_input(format!(
            "{shown} is a file, not a folder"
        )));
    }
    if !dir.exists() {
        let parent = dir.parent().filter(|p| !p.as_os_str().is_empty());
        if let Some(parent) = parent.filter(|p| !p.is_dir()) {
            return Err(LabError::bad_input(format!(
                "cannot create {shown}: its parent {} does not exist",
                parent.display()
            )));
        }
        std::fs::create_dir(dir)
            .map_err(|e| LabError::bad_input(format!("cannot create {shown}: {e}")))?;
    }
    let targets: Vec<(PathBuf, &str)> = EXAMPLES
        .iter()
        .map(|(name, text)| (dir.join(name), *text))
        .collect();
    let existing = targets.iter().find(|(path, _)| path.exists());
    if let Some((path, _)) = existing.filter(|_| !force) {
        return Err(LabError::bad_input(format!(
            "{} exists already; give --force to overwrite it (and the other examples)",
            path.display()
        )));
    }
    for (path, text) in &targets {
        // Each file is written beside its target and renamed into place, so an interrupted run
        // never leaves half a file.
        let partial = path.with_extension("toml.partial");
        std::fs::write(&partial, text)
            .and_then(|()| std::fs::rename(&partial, path))
            .map_err(|e| LabError::bad_input(format!("cannot write {}: {e}", path.display())))?;
    }
    Ok(targets.into_iter().map(|(path, _)| path).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use ftwire_lab::setup::{RigSpec, SensorSpec};
    use ftwire_lab::wire::WireSpec;

    fn example(name: &str) -> &'static str {
        EXAMPLES
            .iter()
            .find(|(n, _)| *n == name)
            .map_or("", |(_, text)| text)
    }

    #[test]
    fn the_examples_parse_and_hold_the_defaults() -> Result<(), Box<dyn std::error::Error>> {
        let wire = WireSpec::from_toml(example("wire.toml"), "wire.toml")?;
        let preset = WireSpec::preset("nitinol-3mm-820").ok_or("preset")?;
        assert_eq!(
            WireSpec {
                name: preset.name.clone(),
                ..wire
            },
            preset
        );
        let sensor = SensorSpec::from_toml(example("sensor.toml"), "sensor.toml")?;
        assert_eq!(sensor.config, SensorSpec::default().config);
        let rig = RigSpec::from_toml(example("rig.toml"), "rig.toml")?;
        assert_eq!(rig, RigSpec::default());
        let scene = ftwire_plan::Scene::from_toml(example("scene.toml"), "scene.toml")?;
        let shipped = ftwire_plan::Scene::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../scenes/passage.toml"
        ))?;
        assert_eq!(scene, shipped);
        let mounting: ftwire_estimate::ft::MountingSpec = toml::from_str(example("mounting.toml"))?;
        assert_eq!(mounting, ftwire_estimate::ft::MountingSpec::default());
        Ok(())
    }
}
