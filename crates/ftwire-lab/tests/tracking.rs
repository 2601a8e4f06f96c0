//! The experiments that roll a plan out, as library calls: `track` (Table IV) and `passage`
//! (§IV-E) run with tiny settings into a temporary results folder, write their files there,
//! and return the very summaries the `ftwire` binary records for the same settings
//! (`crates/ftwire/tests/golden/`), whose keys and CSV files agree; under the paper's noise the
//! passage's plan is chosen among candidates and polished, or not when polish is off; bad
//! settings are refused before any work. (The binary's `tracking_experiments` test checks only
//! that `ftwire experiment track|passage` passes its options here and writes the folder.)

use std::path::{Path, PathBuf};

use ftwire_control::{NoiseModel, TrackingPolicy};
use ftwire_lab::experiment::{CommonParams, Gravity};
use ftwire_lab::passage::{self, PassageParams};
use ftwire_lab::results::ResultsFolder;
use ftwire_lab::track::{self, TrackParams};
use ftwire_lab::tracking::RolloutParams;
use serde::Serialize;

mod common;
#[path = "../../ftwire/tests/golden/compare.rs"]
mod compare;

use common::TempDir;

/// The roll-out settings of `--noise-model offset --calibration FILE`, the rest by default.
fn offset(calibration: PathBuf) -> RolloutParams {
    RolloutParams {
        calibration: Some(calibration),
        ..RolloutParams::for_noise(NoiseModel::Offset)
    }
}

/// Asserts that `summary` is the one the binary recorded as `name` (compared as the JSON
/// text it writes, read back; numbers within the tolerances of
/// `crates/ftwire/tests/golden/compare.rs`). `FTWIRE_RECORD_GOLDEN=1` records it anew, as the binary's
/// `ftwire COMMAND --seed SEED` would (docs/development.md: for a change meant to change the
/// results).
fn assert_recorded(name: &str, (command, seed): (&str, u64), summary: &impl Serialize) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../ftwire/tests/golden")
        .join(format!("{name}.json"));
    if std::env::var_os("FTWIRE_RECORD_GOLDEN").is_some() {
        let kept = serde_json::json!({
            "command": command,
            "seed": seed,
            "summary": json(summary),
        });
        let text = serde_json::to_string_pretty(&kept).expect("serialises") + "\n";
        std::fs::write(&path, text).expect("records the summary");
        return;
    }
    let text = std::fs::read_to_string(&path).expect("the recorded summary");
    let recorded: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    if let Some(difference) =
        compare::first_difference(&json(summary), &recorded["summary"], name, "")
    {
        panic!(
            "the summary of {name} differs from {} (now against recorded): {difference}",
            path.display()
        );
    }
}

fn exists(folder: &ResultsFolder, file: &str) -> bool {
    folder.dir().join(file).is_file()
}

/// `summary` as the JSON text the binary writes, read back.
fn json(summary: &impl Serialize) -> serde_json::Value {
    serde_json::from_str(&serde_json::to_string(summary).expect("serialises")).expect("JSON")
}

/// The text of `file` in `folder`.
fn read(folder: &ResultsFolder, file: &str) -> String {
    std::fs::read_to_string(folder.dir().join(file)).expect(file)
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
    assert_recorded("track-offset-seed2", ("experiment track", 2), &run.summary);
    assert_eq!(run.timings.plan_ms.len(), 1);
    assert!(
        lines.iter().any(|l| l.starts_with("1 pairs planned")),
        "{lines:?}"
    );
    for file in [
        "pairs.csv",
        "waypoints.csv",
        "track_path_in_a.png",
        "track_shape_error.png",
    ] {
        assert!(exists(&folder, file), "{file}");
    }
    assert!(!exists(&folder, "calibration.json"), "a given calibration");

    let summary = json(&run.summary);
    for mode in ["open_loop", "closed_loop"] {
        let r = &summary["results"][mode];
        let (mean, std, max) = (
            r["mean_mm"].as_f64().expect("mean_mm"),
            r["std_mm"].as_f64().expect("std_mm"),
            r["max_mm"].as_f64().expect("max_mm"),
        );
        assert!(mean > 0.0 && std >= 0.0 && max >= mean, "{mode}: {r}");
    }
    // The plans' time is in the timings, not in the summary.
    assert!(summary.get("plan_ms_median").is_none());
    assert!(run.timings.plan_ms_median > 0.0);
    assert_eq!(summary["pairs"], 1);
    // waypoints.csv: its scored legs are exactly Table IV's closed-loop waypoints.
    let legs = read(&folder, "waypoints.csv");
    let mut rows = legs.lines();
    assert_eq!(
        rows.next(),
        Some("pair,waypoint,moves,outcome,shape_mm,scored,touched")
    );
    let scored: Vec<f64> = rows
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|fields| fields[fields.len() - 2] == "true")
        .map(|fields| fields[fields.len() - 3].parse().expect("shape_mm"))
        .collect();
    let closed = &summary["results"]["closed_loop"];
    assert_eq!(
        Some(scored.len() as u64),
        closed["waypoints"].as_u64(),
        "{legs}"
    );
    let mean = scored.iter().sum::<f64>() / scored.len() as f64;
    let reported = closed["mean_mm"].as_f64().expect("mean_mm");
    assert!((mean - reported).abs() < 1e-3, "{mean} against {reported}");
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
    assert_recorded(
        "passage-offset-seed5",
        ("experiment passage", 5),
        &run.summary,
    );
    assert!(run.timings.plan_ms > 0.0 && run.timings.candidate_plan_ms.is_none());
    for file in [
        "attempts.csv",
        "waypoints.csv",
        "passage_path_in_a.png",
        "passage_shape_error.svg",
        "passage_scene.png",
    ] {
        assert!(exists(&folder, file), "{file}");
    }

    let summary = json(&run.summary);
    for mode in ["open_loop", "closed_loop"] {
        let r = &summary["results"][mode];
        assert_eq!(r["attempts"], 2, "results.{mode}.attempts");
        for key in ["successes", "collisions", "detected"] {
            let n = r[key].as_u64().unwrap_or(u64::MAX);
            assert!(n <= 2, "results.{mode}.{key} = {n}");
        }
        assert!(r["detected"].as_u64() <= r["collisions"].as_u64());
    }
    let closed = &summary["results"]["closed_loop"];
    for key in ["retreats", "recovered", "false_alarms"] {
        assert!(closed[key].as_u64().is_some(), "results.closed_loop.{key}");
    }
    // Under `offset` the defaults are gain 0.5 and the ε stops (no shape stop).
    assert_eq!(summary["gain"], 0.5);
    assert_eq!(summary["shape_stop_mm"], 0.0);
    assert_eq!(summary["shape_stop_near_mm"], 0.0);
    // The plan passes the 50 mm gap: some waypoints are near its boxes.
    assert!(
        summary["plan"]["near_waypoints"]
            .as_u64()
            .is_some_and(|n| n >= 1)
    );
    // The plan's time is in the timings, not in the summary.
    assert!(summary.get("plan_ms").is_none());
    assert!(
        summary["plan"]["waypoints"]
            .as_u64()
            .is_some_and(|n| n >= 2)
    );
    // Under `offset` one plan is made, without a choice, and the loop converges onto it: no
    // clearance polish.
    assert!(summary["plan"]["choice"].is_null());
    assert!(summary["plan"]["polish"].is_null());
    // waypoints.csv: an attempt with a leg that touched a box is counted as a collision.
    let legs = read(&folder, "waypoints.csv");
    assert!(legs.starts_with("attempt,waypoint,moves,outcome,shape_mm,scored,touched\n"));
    let mut touching: Vec<&str> = legs
        .lines()
        .skip(1)
        .filter(|l| l.ends_with(",true"))
        .filter_map(|l| l.split(',').next())
        .collect();
    touching.dedup();
    assert!(legs.lines().count() > 2, "{legs}");
    assert!(
        Some(touching.len() as u64) <= closed["collisions"].as_u64(),
        "{legs}"
    );
}

/// `experiment passage --attempts 1 --seed 5 --plan-candidates N` under the paper's noise
/// (`increment`), with the polish on or off (`--no-polish`).
fn noisy(calibration: PathBuf, plan_candidates: usize, polish: bool) -> PassageParams {
    PassageParams {
        common: CommonParams {
            seed: 5,
            ..CommonParams::default()
        },
        rollout: RolloutParams {
            calibration: Some(calibration),
            ..RolloutParams::default()
        },
        attempts: 1,
        plan_candidates,
        polish,
        ..PassageParams::default()
    }
}

/// Under the paper's noise, of two plans the one expecting fewer touching landings is
/// tracked, and the waypoints whose landings come close to a box are polished: the closest
/// landing moves away, and every waypoint keeps the plan's 15 mm margin.
#[test]
fn under_the_paper_noise_the_plan_is_chosen_and_polished() {
    let dir = TempDir::new("passage-noisy");
    let (_calibrated, calibration) = dir.calibration();
    let folder = dir.results("passage");
    let run = passage::run(&noisy(calibration, 2, true), &folder, &mut |_| {}).expect("runs");
    let polished = json(&run.summary);
    let choice = &polished["plan"]["choice"];
    assert_eq!(choice["candidates"], 2, "{choice}");
    let touches: Vec<f64> = choice["expected_touches"]
        .as_array()
        .expect("plan.choice.expected_touches")
        .iter()
        .map(|t| t.as_f64().unwrap_or(f64::INFINITY))
        .collect();
    assert_eq!(touches.len(), 2, "{choice}");
    let chosen = choice["chosen"].as_u64().expect("plan.choice.chosen") as usize;
    assert!(touches.iter().all(|&t| touches[chosen] <= t), "{choice}");
    assert!(
        touches[..chosen].iter().all(|&t| t > touches[chosen]),
        "{choice}"
    );
    assert!(choice.get("plan_ms").is_none(), "{choice}");
    assert_eq!(
        run.timings.candidate_plan_ms.as_ref().map(Vec::len),
        Some(2),
        "each candidate's planning time"
    );
    let polish = &polished["plan"]["polish"];
    assert_eq!(polish["valid"], true, "{polish}");
    assert!(polish["moved"].as_u64().is_some_and(|n| n >= 1), "{polish}");
    let mm = |key: &str| polish[key].as_f64().unwrap_or(f64::NAN);
    assert!(
        mm("min_landing_clearance_after_mm") > mm("min_landing_clearance_before_mm"),
        "{polish}"
    );
    assert!(mm("min_clearance_after_mm") >= 15.0, "{polish}");
}

/// Without the polish the waypoints are tracked as resampled.
#[test]
fn without_the_polish_the_waypoints_are_tracked_as_resampled() {
    let dir = TempDir::new("passage-unpolished");
    let (_calibrated, calibration) = dir.calibration();
    let folder = dir.results("passage");
    let run = passage::run(&noisy(calibration, 1, false), &folder, &mut |_| {}).expect("runs");
    assert!(json(&run.summary)["plan"]["polish"].is_null());
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
