//! The commented example of each configuration file (`ftwire init DIR` writes them), as every
//! command that takes one accepts it (the binary's `tests/init_cli.rs` runs them).
//!
//! The examples are hand-written TOML under `src/init/`, each key with its unit, default and
//! allowed range in a comment; `docs/config.md` is the full schema. The sensor, rig and
//! mounting examples hold the library's defaults and the wire example the preset
//! `nitinol-3mm-820` (checked by the tests below; the simulator's sensor and rig, which this
//! crate never sees, by `ftwire-lab`'s `setup` tests), so passing them changes nothing but the
//! header of a run.

use std::path::{Path, PathBuf};

use crate::error::LabError;

/// The example files, by file name.
pub const EXAMPLES: [(&str, &str); 5] = [
    ("wire.toml", include_str!("init/wire.toml")),
    ("sensor.toml", include_str!("init/sensor.toml")),
    ("rig.toml", include_str!("init/rig.toml")),
    ("scene.toml", include_str!("init/scene.toml")),
    ("mounting.toml", include_str!("init/mounting.toml")),
];

/// The text of the example file `name` (`wire.toml`, ...), if there is one.
pub fn example(name: &str) -> Option<&'static str> {
    EXAMPLES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, text)| *text)
}

/// Writes the [`EXAMPLES`] into `dir`, creating `dir` when its parent exists. Without `force`
/// no file is written when any of them exists already. Returns the files written.
///
/// `force_option` is the overwrite switch as the caller's front end spells it (`--force` on
/// the command line), named in the error that refuses to overwrite.
///
/// # Errors
/// Bad input (exit 2) naming the folder or the file: a missing parent, a `dir` that is a file,
/// an existing example without `force`, a folder that cannot be written.
///
/// # Example
/// ```
/// let dir = std::env::temp_dir().join(format!("ftwire-app-init-doc-{}", std::process::id()));
/// let written = ftwire_app::init::write_examples(&dir, false, "--force").expect("written");
/// assert_eq!(written.len(), ftwire_app::init::EXAMPLES.len());
/// let again = ftwire_app::init::write_examples(&dir, false, "--force").expect_err("exists");
/// assert!(again.to_string().contains("give --force to overwrite it"), "{again}");
/// std::fs::remove_dir_all(&dir).expect("removed");
/// ```
pub fn write_examples(
    dir: &Path,
    force: bool,
    force_option: &str,
) -> Result<Vec<PathBuf>, LabError> {
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
            "{} exists already; give {force_option} to overwrite it (and the other examples)",
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
    use crate::config::sensor::{DEFAULT, DataSheetSpec};
    use crate::config::wire::WireSpec;

    /// The example file `name`, or an empty text.
    fn text(name: &str) -> &'static str {
        example(name).unwrap_or_default()
    }

    #[test]
    fn the_examples_parse_and_hold_the_defaults() -> Result<(), Box<dyn std::error::Error>> {
        let wire = WireSpec::from_toml(text("wire.toml"), "wire.toml")?;
        let preset = WireSpec::preset("nitinol-3mm-820").ok_or("preset")?;
        assert_eq!(
            WireSpec {
                name: preset.name.clone(),
                ..wire
            },
            preset
        );
        let sheet = DataSheetSpec::from_toml(text("sensor.toml"), "sensor.toml")?;
        assert_eq!(sheet.sheet, DEFAULT);
        let scene = ftwire_plan::Scene::from_toml(text("scene.toml"), "scene.toml")?;
        let shipped = ftwire_plan::Scene::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../scenes/passage.toml"
        ))?;
        assert_eq!(scene, shipped);
        let mounting: ftwire_estimate::ft::MountingSpec = toml::from_str(text("mounting.toml"))?;
        assert_eq!(mounting, ftwire_estimate::ft::MountingSpec::default());
        Ok(())
    }
}
