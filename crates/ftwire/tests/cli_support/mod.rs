//! Running the built `ftwire` binary from the CLI tests.
#![allow(dead_code)]

use std::io::Write;
use std::process::{Command, Output, Stdio};

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
