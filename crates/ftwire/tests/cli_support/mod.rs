//! Running the built `ftwire` binary from the CLI tests.
#![allow(dead_code)]

use std::io::Write;
use std::process::{Command, Output, Stdio};

#[path = "../golden/compare.rs"]
mod compare;

/// Runs `ftwire args` with no input.
pub fn ftwire(args: &[&str]) -> Output {
    ftwire_with_input(args, None)
}

/// Runs `ftwire args` with `stdin` written to its input (then closed).
pub fn ftwire_with_input(args: &[&str], stdin: Option<&str>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ftwire"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let input = child.stdin.take().expect("stdin");
    if let Some(text) = stdin {
        let mut input = input;
        input.write_all(text.as_bytes()).expect("writes stdin");
    }
    child.wait_with_output().expect("finishes")
}

/// Stdout as one JSON value.
pub fn json(output: &Output) -> serde_json::Value {
    serde_json::from_slice(&output.stdout).unwrap_or_else(|e| {
        panic!(
            "stdout is not JSON ({e}): {}\nstderr: {}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        )
    })
}

/// A JSON array of numbers.
pub fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("{v} is not an array"))
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

/// Asserts the exit code, and that stderr contains `needle` and no panic.
pub fn assert_exit(output: &Output, code: i32, needle: &str, what: &str) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(code), "{what}: {stderr}");
    assert!(
        stderr.contains(needle),
        "{what}: expected {needle:?} in {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
}

/// Asserts success (exit 0), printing stderr otherwise.
pub fn assert_success(output: &Output, what: &str) {
    assert_eq!(
        output.status.code(),
        Some(0),
        "{what}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// Both spellings of an option whose value may start with a minus sign: `--opt -1,2,3` and
/// `--opt=-1,2,3`.
pub fn both_forms(option: &str, value: &str) -> [Vec<String>; 2] {
    [
        vec![option.to_owned(), value.to_owned()],
        vec![format!("{option}={value}")],
    ]
}

/// Runs a small calibration (`ftwire experiment calibrate`, 40 configurations, gravity off)
/// into `dir/cal` and returns the path of its weights, `dir/cal/calibration.json`: enough for a
/// test that needs learnt weights, in a few seconds.
pub fn tiny_calibration(dir: &std::path::Path) -> std::path::PathBuf {
    let cal = dir.join("cal");
    let out = cal.to_str().expect("a UTF-8 path");
    let output = ftwire(&[
        "experiment",
        "calibrate",
        "--trials",
        "40",
        "--gravity",
        "off",
        "--out",
        out,
    ]);
    assert_success(&output, "experiment calibrate");
    cal.join("calibration.json")
}

/// A fresh folder `ftwire-<tag>-<pid>` under the system's temporary folder, removed on drop.
pub struct TempDir(pub std::path::PathBuf);

impl TempDir {
    /// Creates the folder, emptied of what an earlier run left.
    pub fn new(tag: &str) -> Self {
        let path = std::env::temp_dir().join(format!("ftwire-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).expect("creates a temporary folder");
        Self(path)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The recorded summaries: `tests/golden/NAME.json`.
fn golden_path(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("golden")
        .join(format!("{name}.json"))
}

/// Asserts that the results folder `out` holds the summary recorded as `name`: the run
/// header's command and seed and the whole `summary` of `summary.json` (the configuration
/// names temporary paths, and the version and revision change), compared value for value,
/// numbers within the tolerances of `tests/golden/compare.rs` (the CPU's arithmetic may differ
/// in the last bits). The recording guards the move of the experiments between crates: the
/// same seed must give the same results. `FTWIRE_RECORD_GOLDEN=1` records it anew, for a
/// change that is meant to change the results (say why in the commit).
pub fn assert_golden_summary(name: &str, out: &std::path::Path) {
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    let run: serde_json::Value = serde_json::from_str(&text).expect("summary.json is JSON");
    let kept = serde_json::json!({
        "command": run["header"]["command"],
        "seed": run["header"]["seed"],
        "summary": run["summary"],
    });
    let path = golden_path(name);
    if std::env::var_os("FTWIRE_RECORD_GOLDEN").is_some() {
        let text = serde_json::to_string_pretty(&kept).expect("serialises") + "\n";
        std::fs::create_dir_all(path.parent().expect("a folder")).expect("creates golden/");
        std::fs::write(&path, text).expect("records the golden summary");
        return;
    }
    let recorded = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (FTWIRE_RECORD_GOLDEN=1 records it)",
            path.display()
        )
    });
    let recorded: serde_json::Value = serde_json::from_str(&recorded).expect("golden is JSON");
    if let Some(difference) = compare::first_difference(&kept, &recorded, name, "") {
        panic!(
            "the summary of {name} differs from {} (now against recorded): {difference}",
            path.display()
        );
    }
}
