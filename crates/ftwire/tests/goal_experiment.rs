//! `ftwire experiment goal`: a small run writes the summary keys it promises,
//! the same results for the same seed, and refuses bad input.

mod cli_support;

use cli_support::{assert_exit, assert_success, ftwire, tiny_calibration};

fn run_goal(out: &std::path::Path, calibration: &std::path::Path) -> serde_json::Value {
    let output = ftwire(&[
        "experiment",
        "goal",
        "--pairs",
        "2",
        "--gravity",
        "off",
        "--noise-model",
        "offset",
        "--seed",
        "3",
        "--calibration",
        calibration.to_str().expect("a UTF-8 path"),
        "--out",
        out.to_str().expect("a UTF-8 path"),
    ]);
    assert_success(&output, "experiment goal");
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    let summary: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    summary["summary"].clone()
}

#[test]
fn a_small_goal_experiment_writes_the_issue_keys_deterministically() {
    let tmp = std::env::temp_dir().join(format!("ftwire-goal-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).expect("a temporary folder");
    let calibration = tiny_calibration(&tmp);
    let first = run_goal(&tmp.join("a"), &calibration);
    cli_support::assert_golden_summary("goal-offset-seed3", &tmp.join("a"));
    for loop_kind in ["open_loop", "closed_loop"] {
        for variant in ["no_noise", "noise"] {
            let m = &first["results"][loop_kind][variant];
            for key in ["mean_mm", "std_mm", "a_error_mean"] {
                assert!(
                    m[key].is_number(),
                    "results.{loop_kind}.{variant}.{key}: {m}"
                );
            }
            let trials = m["trials"].as_u64().expect("trials");
            let failed = m["failed"].as_u64().expect("failed");
            assert_eq!(trials + failed, 2, "every pair is counted once");
        }
    }
    assert!(first["steps_median"].is_number());
    // The controller's time is in timings.json, not in the summary.
    assert!(first.get("controller_step_us_median").is_none());
    let timings: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(tmp.join("a").join("timings.json")).expect("timings.json"),
    )
    .expect("JSON");
    assert!(
        timings["controller_step_us_median"]
            .as_f64()
            .is_some_and(|t| t > 0.0)
    );
    let c = &first["collision"];
    for key in ["false_alarms", "trials"] {
        assert!(c[key].as_u64().is_some(), "collision.{key}");
    }
    assert!(c["false_alarms"].as_u64() <= c["free_motions"].as_u64());
    assert!(c.get("detection_delay_steps_median").is_some());
    for figure in ["motion_in_a.png", "shape_error_along_motion.svg"] {
        assert!(tmp.join("a").join(figure).is_file(), "{figure}");
    }
    // Same seed, same results.
    let second = run_goal(&tmp.join("b"), &calibration);
    assert_eq!(first, second);
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn zero_pairs_is_bad_input() {
    let output = ftwire(&["experiment", "goal", "--pairs", "0", "--gravity", "off"]);
    assert_exit(&output, 2, "--pairs 0", "goal --pairs 0");
}

#[test]
fn a_negative_shape_stop_is_bad_input() {
    let output = ftwire(&[
        "experiment",
        "goal",
        "--shape-stop",
        "-2",
        "--gravity",
        "off",
    ]);
    assert_exit(&output, 2, "--shape-stop -2", "goal --shape-stop -2");
}
