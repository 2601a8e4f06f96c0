//! `ftwire demo`: it runs end to end in the simulator, the same seed gives a byte-identical
//! `summary.json` (but for the `--out` folder it names; timings live in `timings.json`) and
//! `report.html`, its answers are the system's (the wire identified and its shape seen from
//! F/T), and bad input is exit 2 with nothing written. With `FTWIRE_DEMO_PAGE=FILE` the
//! demo's `report.html` is also written to FILE, for `.ci/browser-test`.

mod cli_support;

use std::fs;

use cli_support::{assert_exit, assert_success, ftwire, numbers};

#[test]
fn the_demo_identifies_the_wire_and_sees_its_shape_the_same_for_the_same_seed() {
    let dir = std::env::temp_dir().join(format!("ftwire-demo-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("creates a temporary folder");
    let run = |name: &str| {
        let out = dir.join(name);
        let output = ftwire(&["demo", "--seed", "0", "--out", out.to_str().expect("UTF-8")]);
        assert_success(&output, "the demo");
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        (
            fs::read(out.join("summary.json")).expect("summary.json"),
            fs::read(out.join("report.html")).expect("report.html"),
            stderr,
        )
    };
    // Both runs at once, in two folders (the demo is single-threaded; CI has two cores).
    let ((first, first_page, stderr), (second, second_page, _)) = std::thread::scope(|s| {
        let other = s.spawn(|| run("again"));
        let one = run("demo");
        (one, other.join().expect("the second demo"))
    });
    // Not a terminal here: plain progress lines, one per phase and its result.
    for phase in ["[1/5]", "[2/5]", "[3/5]", "[4/5]", "[5/5]"] {
        assert!(stderr.contains(phase), "{phase} in {stderr}");
    }
    cli_support::assert_golden_summary("demo-seed0", &dir.join("demo"));
    let summary: serde_json::Value = serde_json::from_slice(&first).expect("JSON");
    let summary = &summary["summary"];
    let errors = numbers(&summary["identification"]["relative_error"]);
    assert_eq!(errors.len(), 4);
    assert!(
        errors.iter().all(|e| e.abs() < 0.01),
        "c and L within 1 %: {errors:?}"
    );
    assert!(summary["identification"]["flag"].is_null());
    let shape = summary["shape"]["mean_mm_overall"]
        .as_f64()
        .expect("a number");
    assert!(shape < 3.0, "shape from F/T within 3 mm: {shape}");
    let tracking = &summary["tracking"];
    for mode in ["closed_loop", "open_loop"] {
        assert!(tracking[mode]["success"].is_boolean(), "{mode}: {tracking}");
    }
    assert!(
        tracking["closed_loop"]["touched"] == false,
        "closed loop keeps clear of the boxes: {tracking}"
    );
    // The default noise is a real robot's calibration error: the closed loop removes it, the
    // open loop cannot.
    assert_eq!(tracking["noise_model"], "offset");
    // There the loop converges onto the plan: its waypoints are tracked as resampled.
    assert!(summary["plan"]["polish"].is_null(), "{}", summary["plan"]);
    assert!(tracking["closed_loop"]["success"] == true, "{tracking}");
    let final_error = |mode: &str| tracking[mode]["final_error"].as_f64().expect("a number");
    assert!(final_error("closed_loop") < 0.1, "{tracking}");
    assert!(
        final_error("open_loop") > 5.0 * final_error("closed_loop"),
        "{tracking}"
    );
    for file in [
        "timings.json",
        "calibration.json",
        "shape.png",
        "shape.svg",
        "tracking.png",
        "report.html",
    ] {
        assert!(dir.join("demo").join(file).is_file(), "{file}");
    }
    // The page: the three views (closed loop, open loop, shape) and both figures, offline.
    let page = String::from_utf8_lossy(&first_page);
    assert_eq!(page.matches("<div class=\"view\" data-view=").count(), 3);
    assert_eq!(page.matches("src=\"data:image/png;base64,").count(), 2);
    assert!(!page.contains("src=\"http"));
    // The same seed, the same summary.json: byte for byte but for the folder it names.
    let first_text = String::from_utf8_lossy(&first);
    let second_text = String::from_utf8_lossy(&second);
    assert_eq!(
        first_text.replace("/demo\"", "/again\""),
        second_text,
        "the same seed gives the same summary.json"
    );
    assert!(
        first_page == second_page,
        "the same seed gives the same report.html"
    );
    // `ftwire demo`'s page (seed 0 is the default): CI's browser check opens this very page
    // rather than running the demo a third time (.ci/run names the file).
    if let Some(page) = std::env::var_os("FTWIRE_DEMO_PAGE") {
        fs::write(&page, &first_page).expect("writes the page to FTWIRE_DEMO_PAGE");
    }
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn bad_demo_input_is_exit_2_and_writes_nothing() {
    let dir = std::env::temp_dir().join(format!("ftwire-demo-bad-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("creates a temporary folder");
    let out = dir.join("demo");
    let out = out.to_str().expect("UTF-8");
    let output = ftwire(&["demo", "--wire", "copper", "--out", out]);
    assert_exit(&output, 2, "copper", "an unknown wire preset");
    let missing = dir.join("no").join("such").join("demo");
    let output = ftwire(&["demo", "--out", missing.to_str().expect("UTF-8")]);
    assert_exit(&output, 2, "does not exist", "a missing --out parent");
    assert!(!dir.join("demo").exists(), "nothing written");
    let _ = fs::remove_dir_all(&dir);
}
