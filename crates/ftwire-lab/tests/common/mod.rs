//! What the lab's integration tests share: a temporary folder for results.

#![allow(dead_code)]

use std::path::PathBuf;

use ftwire_lab::experiment::{CommonParams, Gravity};
use ftwire_lab::results::{OutGuard, ResultsFolder};

/// A unique empty folder under the system's temporary folder, removed on drop.
pub struct TempDir(pub PathBuf);

impl TempDir {
    pub fn new(tag: &str) -> Self {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let path =
            std::env::temp_dir().join(format!("ftwire-lab-{tag}-{}-{nanos}", std::process::id()));
        std::fs::create_dir_all(&path).expect("a temporary folder");
        Self(path)
    }

    /// A results folder `name` inside.
    pub fn results(&self, name: &str) -> ResultsFolder {
        ResultsFolder::create(&self.0.join(name), &OutGuard::default()).expect("a results folder")
    }

    /// The small calibration the binary's tests use (`experiment calibrate --trials 40
    /// --gravity off`): its results folder (its files live as long as it does) and its
    /// weights' file.
    pub fn calibration(&self) -> (ResultsFolder, PathBuf) {
        let folder = self.results("calibrate");
        let settings = ftwire_lab::calibrate::CalibrateParams {
            common: CommonParams {
                trials: Some(40),
                gravity: Gravity::Off,
                ..CommonParams::default()
            },
            save_log: false,
        };
        ftwire_lab::calibrate::run(&settings, &folder, &mut |_| {}).expect("calibrates");
        let weights = folder.dir().join("calibration.json");
        (folder, weights)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
