//! The experiments that roll a plan out, as library calls: `track` (Table IV) and `passage`
//! (§IV-E) run with tiny settings into a temporary results folder, write their files there,
//! and return the very summaries the `ftwire` binary records for the same settings
//! (`crates/ftwire/tests/golden/`); bad settings are refused before any work.

use std::path::{Path, PathBuf};

use ftwire_control::{NoiseModel, TrackingPolicy};
use ftwire_lab::experiment::{CommonParams, Gravity};
use ftwire_lab::passage::{self, PassageParams};
use ftwire_lab::results::ResultsFolder;
use ftwire_lab::track::{self, TrackParams};
use ftwire_lab::tracking::RolloutParams;
use serde::Serialize;

mod common;

use common::TempDir;

/// The roll-out settings of `--noise-model offset --calibration FILE`, the rest by default.
fn offset(calibration: PathBuf) -> RolloutParams {
    RolloutParams {
        calibration: Some(calibration),
        ..RolloutParams::for_noise(NoiseModel::Offset)
    }
}

/// Asserts that `summary` is the one the binary recorded as `name` (compared as the JSON
/// text it writes, read back).
fn assert_recorded(name: &str, summary: &impl Serialize) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../ftwire/tests/golden")
        .join(format!("{name}.json"));
    let text = std::fs::read_to_string(&path).expect("the recorded summary");
    let recorded: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let ours: serde_json::Value =
        serde_json::from_str(&serde_json::to_string(summary).expect("serialises")).expect("JSON");
    assert_eq!(ours, recorded["summary"], "{name}");
}

fn exists(folder: &ResultsFolder, file: &str) -> bool {
    folder.dir().join(file).is_file()
}

/// `experiment track --pairs 1 --gravity off --noise-model offset --seed 2`. Most of its time
/// is drawing a pair whose ends the arms reach.
#[test]
fn track_gives_the_recorded_summary_and_writes_its_files() {
    let dir = TempDir::new("track");
    let (_calibrated, calibration) = dir.calibration();
    let folder = dir.results("track");
    let settings = TrackParams {
        common: CommonParams {
            seed: 2,
            gravity: Gravity::Off,
            ..CommonParams::default()
        },
        rollout: offset(calibration),
        pairs: 1,
        ..TrackParams::default()
    };
    let mut lines = Vec::new();
    let run = track::run(&settings, &folder, &mut |l| lines.push(l.to_owned())).expect("runs");
    assert_recorded("track-offset-seed2", &run.summary);
    assert_eq!(run.timings.plan_ms.len(), 1);
    assert!(
        lines.iter().any(|l| l.starts_with("1 pairs planned")),
        "{lines:?}"
    );
    for file in ["pairs.csv", "waypoints.csv", "track_path_in_a.png"] {
        assert!(exists(&folder, file), "{file}");
    }
    assert!(!exists(&folder, "calibration.json"), "a given calibration");
}

/// `experiment passage --attempts 2 --noise-model offset --seed 5`.
#[test]
fn passage_gives_the_recorded_summary_and_writes_its_files() {
    let dir = TempDir::new("passage");
    let (_calibrated, calibration) = dir.calibration();
    let folder = dir.results("passage");
    let settings = PassageParams {
        common: CommonParams {
            seed: 5,
            ..CommonParams::default()
        },
        rollout: offset(calibration),
        attempts: 2,
        ..PassageParams::default()
    };
    let run = passage::run(&settings, &folder, &mut |_| {}).expect("runs");
    assert_recorded("passage-offset-seed5", &run.summary);
    assert!(run.timings.plan_ms > 0.0 && run.timings.candidate_plan_ms.is_none());
    for file in ["attempts.csv", "waypoints.csv", "passage_scene.png"] {
        assert!(exists(&folder, file), "{file}");
    }
}

#[test]
fn bad_settings_are_refused_before_any_work() {
    let policy = TrackingPolicy {
        gain: 1.5,
        ..TrackingPolicy::for_noise(NoiseModel::Increment)
    };
    let bad_gain = RolloutParams {
        policy,
        ..RolloutParams::default()
    };
    let track_cases = [
        TrackParams {
            pairs: 0,
            ..TrackParams::default()
        },
        TrackParams {
            rollout: bad_gain.clone(),
            ..TrackParams::default()
        },
        TrackParams {
            common: CommonParams {
                wire: Some("no-such-wire".to_owned()),
                ..CommonParams::default()
            },
            ..TrackParams::default()
        },
    ];
    for settings in track_cases {
        let e = settings.check().expect_err("bad input");
        assert_eq!(e.exit_code(), 2, "{e}");
    }
    let passage_cases = [
        PassageParams {
            attempts: 0,
            ..PassageParams::default()
        },
        PassageParams {
            plan_candidates: 0,
            ..PassageParams::default()
        },
        PassageParams {
            rollout: bad_gain,
            ..PassageParams::default()
        },
        PassageParams {
            scene: Some("/no/such/scene.toml".into()),
            ..PassageParams::default()
        },
    ];
    for settings in passage_cases {
        let e = settings.check().expect_err("bad input");
        assert_eq!(e.exit_code(), 2, "{e}");
    }
    assert!(TrackParams::default().check().is_ok());
    assert!(PassageParams::default().check().is_ok());
}
