//! The experiments of a reproduction and their arguments: the calibrations first, then the
//! experiments that use them, each an `ftwire` command line with its own results folder and log.
//!
//! Beside the simulated tables, the same experiments with the `real-like` recording preset
//! ([`REAL_LIKE_ARGS`]: the sensor as a real recording shows it, its calibration session
//! recorded as single readings), ids ending in [`REAL_LIKE_SUFFIX`]: what to expect on a real
//! rig. A quick run has only the shape's (Table II); a full run also the goal's, the
//! tracking's and the passage's.

use std::ffi::OsString;
use std::path::Path;

use super::params::ReproduceParams;

/// One experiment of a reproduction, run as an `ftwire` command of its own.
#[derive(Debug, Clone, PartialEq)]
pub struct Job {
    /// Its subfolder and name in the report.
    pub id: &'static str,
    /// The `ftwire` arguments that run it (after the program's name), `--seed` and `--out`
    /// included.
    pub args: Vec<OsString>,
    /// Its results folder (`--out`), `<reproduction>/<id>`.
    pub out: std::path::PathBuf,
    /// Where its standard output and error go while it runs, `<reproduction>/<id>.log`; moved
    /// into its results folder as `log.txt` once it has one.
    pub log: std::path::PathBuf,
    /// Expected wall time \[s\] on a 2-core machine, quick and full, announced before the run
    /// (an estimate, not a bound).
    pub expected_s: (f64, f64),
    /// The calibration job whose `calibration.json` it uses (`None`: it is a calibration).
    pub calibration: Option<&'static str>,
}

/// The arguments of the `real-like` recording preset: the sensor of `--sensor real-like` and a
/// calibration session of single readings (`docs/real-rig.md`).
pub const REAL_LIKE_ARGS: [&str; 4] = ["--sensor", "real-like", "--protocol", "single-readings"];

/// The end of a real-like job's id: `shape` beside `shape_real_like`.
pub const REAL_LIKE_SUFFIX: &str = "_real_like";

impl Job {
    /// The expected wall time \[s\] of a quick or a full run.
    pub fn expected(&self, quick: bool) -> f64 {
        if quick {
            self.expected_s.0
        } else {
            self.expected_s.1
        }
    }
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| (*s).to_owned()).collect()
}

impl ReproduceParams {
    /// The calibration jobs of a reproduction into `dir`, the simulated and the real-like
    /// (they run before the others).
    pub fn calibration_jobs(&self, dir: &Path) -> Vec<Job> {
        let trials = if self.quick { "300" } else { "600" };
        let args = strings(&["experiment", "calibrate", "--trials", trials]);
        vec![
            self.job(dir, "calibrate", args.clone(), (25.0, 50.0), None),
            self.real_like_job(dir, "calibrate_real_like", args, (25.0, 50.0), None),
        ]
    }

    /// The `calibration.json` of calibration job `id` in a reproduction into `dir`.
    pub fn calibration_file(&self, dir: &Path, id: &str) -> std::path::PathBuf {
        dir.join(id).join("calibration.json")
    }

    /// The jobs of a reproduction into `dir` that use a calibration, in report order, the
    /// real-like ones last. Quick: the paper's trial counts at three samples only, and of the
    /// real-like ones the shape's; full: every sample count of Figs. 3–4.
    pub fn experiment_jobs(&self, dir: &Path) -> Vec<Job> {
        let quick = self.quick;
        let mut identify = strings(&["experiment", "identify"]);
        if quick {
            identify.extend(strings(&["--samples", "3"]));
        }
        let shape = strings(&["experiment", "shape"]);
        let mut goal = strings(&["experiment", "goal"]);
        if quick {
            goal.extend(strings(&["--pairs", "10"]));
        }
        let mut track = strings(&["experiment", "track"]);
        let mut passage = strings(&["experiment", "passage"]);
        let mut passage_offset = strings(&["experiment", "passage", "--noise-model", "offset"]);
        if quick {
            track.extend(strings(&["--pairs", "2"]));
            // One plan: the choice among candidates costs a plan each (`experiment passage
            // --plan-candidates`).
            passage.extend(strings(&["--attempts", "4", "--plan-candidates", "1"]));
            passage_offset.extend(strings(&["--attempts", "4"]));
        }
        let calibration = |id: &str| {
            vec![
                "--calibration".to_owned(),
                self.calibration_file(dir, id)
                    .to_string_lossy()
                    .into_owned(),
            ]
        };
        let simulated = [
            ("identify", identify, (5.0, 120.0)),
            ("shape", shape.clone(), (10.0, 10.0)),
            ("goal", goal.clone(), (25.0, 70.0)),
            ("track", track.clone(), (50.0, 220.0)),
            ("passage", passage.clone(), (20.0, 230.0)),
            ("passage_offset", passage_offset, (20.0, 170.0)),
        ];
        let mut jobs: Vec<Job> = simulated
            .into_iter()
            .map(|(id, mut args, expected_s)| {
                args.extend(calibration("calibrate"));
                self.job(dir, id, args, expected_s, Some("calibrate"))
            })
            .collect();
        let mut real_like = vec![("shape_real_like", shape, (10.0, 10.0))];
        if !quick {
            real_like.extend([
                ("goal_real_like", goal, (25.0, 70.0)),
                ("track_real_like", track, (50.0, 220.0)),
                ("passage_real_like", passage, (20.0, 230.0)),
            ]);
        }
        for (id, mut args, expected_s) in real_like {
            args.extend(calibration("calibrate_real_like"));
            jobs.push(self.real_like_job(dir, id, args, expected_s, Some("calibrate_real_like")));
        }
        jobs
    }

    /// [`Self::job`] with the real-like recording preset in place of the sensor given.
    fn real_like_job(
        &self,
        dir: &Path,
        id: &'static str,
        mut args: Vec<String>,
        expected_s: (f64, f64),
        calibration: Option<&'static str>,
    ) -> Job {
        args.extend(strings(&REAL_LIKE_ARGS));
        let own = Self {
            sensor: None,
            ..self.clone()
        };
        own.job(dir, id, args, expected_s, calibration)
    }

    /// Job `id` into `dir/<id>`: `args`, then the sensor and rig passed on, the seed and the
    /// results folder.
    fn job(
        &self,
        dir: &Path,
        id: &'static str,
        args: Vec<String>,
        expected_s: (f64, f64),
        calibration: Option<&'static str>,
    ) -> Job {
        let out = dir.join(id);
        let mut args: Vec<OsString> = args.into_iter().map(OsString::from).collect();
        if let Some(sensor) = &self.sensor {
            args.extend(["--sensor".into(), sensor.into()]);
        }
        if let Some(rig) = &self.rig {
            args.extend(["--rig".into(), rig.to_string_lossy().into_owned().into()]);
        }
        args.extend([
            "--seed".into(),
            self.seed.to_string().into(),
            "--out".into(),
            out.clone().into_os_string(),
        ]);
        Job {
            id,
            args,
            out,
            log: dir.join(format!("{id}.log")),
            expected_s,
            calibration,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_job_gets_the_calibration_the_setup_the_seed_and_its_folder() {
        let params = ReproduceParams {
            seed: 7,
            quick: true,
            sensor: Some("undistorted".to_owned()),
            ..ReproduceParams::default()
        };
        let dir = Path::new("/tmp/r");
        let calibrations = params.calibration_jobs(dir);
        assert_eq!(
            calibrations[0].args.join(std::ffi::OsStr::new(" ")),
            "experiment calibrate --trials 300 --sensor undistorted --seed 7 --out /tmp/r/calibrate"
        );
        assert_eq!(
            calibrations[1].args.join(std::ffi::OsStr::new(" ")),
            "experiment calibrate --trials 300 --sensor real-like --protocol single-readings \
             --seed 7 --out /tmp/r/calibrate_real_like"
        );
        let jobs = params.experiment_jobs(dir);
        let ids: Vec<&str> = jobs.iter().map(|j| j.id).collect();
        assert_eq!(
            ids,
            [
                "identify",
                "shape",
                "goal",
                "track",
                "passage",
                "passage_offset",
                "shape_real_like"
            ]
        );
        for job in &jobs {
            let line = job.args.join(std::ffi::OsStr::new(" "));
            let line = line.to_string_lossy();
            let real_like = job.id.ends_with(REAL_LIKE_SUFFIX);
            let (calibration, sensor) = if real_like {
                (
                    "calibrate_real_like",
                    "--sensor real-like --protocol single-readings",
                )
            } else {
                ("calibrate", "--sensor undistorted")
            };
            assert_eq!(job.calibration, Some(calibration));
            assert!(
                line.contains(&format!(
                    "--calibration /tmp/r/{calibration}/calibration.json {sensor} --seed"
                )),
                "{line}"
            );
            assert!(line.ends_with(&format!("--seed 7 --out /tmp/r/{}", job.id)));
            assert_eq!(job.log, dir.join(format!("{}.log", job.id)));
        }
        let full = ReproduceParams {
            quick: false,
            ..params
        };
        let ids: Vec<&str> = full.experiment_jobs(dir).iter().map(|j| j.id).collect();
        assert!(ids.ends_with(&[
            "shape_real_like",
            "goal_real_like",
            "track_real_like",
            "passage_real_like"
        ]));
    }
}
