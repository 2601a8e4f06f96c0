//! The run header of a results folder: what produced a result (version, revision, command,
//! seed, configuration), the first thing in `summary.json`.

use serde::Serialize;

use crate::error::LabError;

/// The `ftwire` version (`Cargo.toml`).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The git revision the binary was built from (`git rev-parse --short HEAD` at build time), or
/// `"unknown"` when git or the repository was not available.
pub const GIT_REVISION: &str = env!("FTWIRE_GIT_REVISION");

/// What produced a result: the first thing in a results folder's `summary.json`.
///
/// The same version, revision, seed and configuration give the same results (timings are kept
/// out of `summary.json` for that reason).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunHeader {
    /// `ftwire` version ([`VERSION`]).
    pub ftwire_version: String,
    /// Git revision of the build ([`GIT_REVISION`], `"unknown"` if not known).
    pub git_revision: String,
    /// The command, e.g. `"experiment"`.
    pub command: String,
    /// The seed of every random choice, if the command makes any.
    pub seed: Option<u64>,
    /// The full configuration: the command's arguments, serialised.
    pub configuration: serde_json::Value,
}

impl RunHeader {
    /// The header of a run of `command` with arguments `configuration`.
    ///
    /// # Errors
    /// Bad input if the configuration cannot be serialised (e.g. a non-string map key).
    ///
    /// # Example
    /// ```
    /// let h = ftwire_app::header::RunHeader::new("demo", Some(7), &[1.0, 2.0])?;
    /// assert_eq!(h.seed, Some(7));
    /// assert_eq!(h.configuration, serde_json::json!([1.0, 2.0]));
    /// assert_eq!(h.ftwire_version, env!("CARGO_PKG_VERSION"));
    /// # Ok::<(), ftwire_app::error::LabError>(())
    /// ```
    pub fn new(
        command: &str,
        seed: Option<u64>,
        configuration: &impl Serialize,
    ) -> Result<Self, LabError> {
        let configuration = serde_json::to_value(configuration).map_err(|e| {
            LabError::bad_input(format!("cannot record the configuration of {command}: {e}"))
        })?;
        Ok(Self {
            ftwire_version: VERSION.to_owned(),
            git_revision: GIT_REVISION.to_owned(),
            command: command.to_owned(),
            seed,
            configuration,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_names_the_build() {
        let h = RunHeader::new("test", None, &serde_json::json!({"a": 1})).expect("serialises");
        assert_eq!(h.ftwire_version, VERSION);
        let hex =
            h.git_revision.len() >= 4 && h.git_revision.chars().all(|c| c.is_ascii_hexdigit());
        assert!(hex || h.git_revision == "unknown", "{}", h.git_revision);
        let v = serde_json::to_value(&h).expect("serialises");
        assert_eq!(v["configuration"]["a"], 1);
        assert!(v["seed"].is_null());
    }
}
