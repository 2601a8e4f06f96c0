//! The experiments of a reproduction and their arguments: the calibration first, then the
//! experiments that use it, each an `ftwire` command line with its own results folder and log.

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
}

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
    /// The calibration job of a reproduction into `dir` (it runs alone, before the others).
    pub fn calibration_job(&self, dir: &Path) -> Job {
        let trials = if self.quick { "300" } else { "600" };
        let args = strings(&["experiment", "calibrate", "--trials", trials]);
        self.job(dir, "calibrate", args, (25.0, 50.0))
    }

    /// The calibration's weights in a reproduction into `dir`.
    pub fn calibration_file(&self, dir: &Path) -> std::path::PathBuf {
        dir.join("calibrate").join("calibration.json")
    }

    /// The jobs of a reproduction into `dir` that use the calibration, in report order.
    /// Quick: the paper's trial counts at three samples only; full: every sample count of
    /// Figs. 3–4.
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
        let calibration = self.calibration_file(dir).to_string_lossy().into_owned();
        [
            ("identify", identify, (5.0, 120.0)),
            ("shape", shape, (10.0, 10.0)),
            ("goal", goal, (25.0, 70.0)),
            ("track", track, (50.0, 220.0)),
            ("passage", passage, (20.0, 230.0)),
            ("passage_offset", passage_offset, (20.0, 170.0)),
        ]
        .into_iter()
        .map(|(id, mut args, expected_s)| {
            args.extend(["--calibration".to_owned(), calibration.clone()]);
            self.job(dir, id, args, expected_s)
        })
        .collect()
    }

    /// Job `id` into `dir/<id>`: `args`, then the sensor and rig passed on, the seed and the
    /// results folder.
    fn job(&self, dir: &Path, id: &'static str, args: Vec<String>, expected_s: (f64, f64)) -> Job {
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
        let calibration = params.calibration_job(dir);
        assert_eq!(
            calibration.args.join(std::ffi::OsStr::new(" ")),
            "experiment calibrate --trials 300 --sensor undistorted --seed 7 --out /tmp/r/calibrate"
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
                "passage_offset"
            ]
        );
        for job in &jobs {
            let line = job.args.join(std::ffi::OsStr::new(" "));
            let line = line.to_string_lossy();
            assert!(
                line.contains("--calibration /tmp/r/calibrate/calibration.json --sensor"),
                "{line}"
            );
            assert!(line.ends_with(&format!("--seed 7 --out /tmp/r/{}", job.id)));
            assert_eq!(job.log, dir.join(format!("{}.log", job.id)));
        }
    }
}
