//! The settings of a reproduction, and the checks made on them before anything runs.

use std::path::PathBuf;

use ftwire_report::html::code_span;
use serde::Serialize;

use super::docs;
use crate::error::LabError;
use crate::setup::SimSetup;

/// The settings of a reproduction.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ReproduceParams {
    /// The seed of every random choice (each experiment gets it).
    pub seed: u64,
    /// Reduced trial counts: a few minutes instead of the full run.
    pub quick: bool,
    /// Experiments run at once, at least 1; `None`: the machine's cores.
    pub jobs: Option<usize>,
    /// The simulated F/T sensor passed on to every experiment (a preset or a sensor file);
    /// `None`: the default sensor.
    pub sensor: Option<String>,
    /// The simulated rig file passed on to every experiment; `None`: the library's rig.
    pub rig: Option<PathBuf>,
    /// The folder of the documentation's results page to write after the run ([`docs`]).
    pub docs: Option<PathBuf>,
    /// Replace a results page or folder there that ftwire did not write.
    pub force: bool,
}

impl ReproduceParams {
    /// Experiments run at once: [`ReproduceParams::jobs`], or the machine's cores.
    pub fn jobs(&self) -> usize {
        self.jobs.unwrap_or_else(|| {
            std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
        })
    }

    /// Checks, before anything runs or is written, the sensor and rig files and that the
    /// documentation's page may be written ([`docs::check`]).
    ///
    /// # Errors
    /// Bad input naming the file, the line and the key, or the page or folder that is not
    /// ftwire's, or no jobs.
    pub fn check(&self) -> Result<(), LabError> {
        SimSetup::load(self.sensor.as_deref(), self.rig.as_deref())
            .map_err(|e| LabError::bad_input(e.to_string()))?;
        if let Some(dir) = &self.docs {
            docs::check(dir, self.force)?;
        }
        if self.jobs == Some(0) {
            return Err(LabError::bad_input("--jobs 0: at least 1"));
        }
        Ok(())
    }

    /// The sensor and rig as the report names them (Markdown).
    pub(super) fn sensor_words(&self) -> String {
        match (&self.sensor, &self.rig) {
            (None, None) => "the default F/T sensor".to_owned(),
            (sensor, rig) => format!(
                "the F/T sensor {} and the rig {}",
                code_span(sensor.as_deref().unwrap_or("distorted")),
                code_span(
                    &rig.as_ref()
                        .map_or_else(|| "default".to_owned(), |r| r.display().to_string())
                ),
            ),
        }
    }
}
