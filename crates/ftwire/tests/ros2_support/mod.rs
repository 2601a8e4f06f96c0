//! What the ROS 2 node tests share: a folder per test, the loopback-only network namespace,
//! and a session of the sim, a moving node and watchers in it.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

/// The binary under test.
pub const BIN: &str = env!("CARGO_BIN_EXE_ftwire");

/// A fresh folder for one test's files.
pub fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ftwire-ros2-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    dir
}

/// Fails loudly unless a network namespace can be made here.
pub fn require_unshare() {
    let ok = Command::new("unshare")
        .args(["-n", "true"])
        .status()
        .is_ok_and(|s| s.success());
    assert!(
        ok,
        "`unshare -n` is not permitted here (it needs root or CAP_SYS_ADMIN): the ROS 2 node \
         tests run only in a network namespace with nothing but the loopback, and will not use \
         the real network"
    );
}

/// What [`run_session`] returns: the summaries of the sim, the mover and each watcher, and the
/// watchers' logs.
pub struct Session {
    pub sim: Value,
    pub mover: Value,
    pub watchers: Vec<(Value, String)>,
}

/// In one loopback-only namespace, in `dir`: `ftwire ros2 sim <sim_args>`, and 0.3 s later
/// each of `watchers` (`ftwire ros2 <args>`, until stopped) and `mover` (`ftwire ros2 <args>`,
/// until it ends by itself), all started together so that each tares on the sim's first
/// samples; once the mover ends, the watchers and then the sim end with SIGTERM.
pub fn run_session(dir: &Path, sim_args: &str, mover: &str, watchers: &[String]) -> Session {
    require_unshare();
    let out = |name: &str| dir.join(name).display().to_string();
    let mut script = format!(
        "set -e; ip link set lo up; \
         [ \"$(ip -o link | wc -l)\" = 1 ] || {{ echo 'the namespace has a device besides lo' >&2; exit 97; }}; \
         '{BIN}' ros2 sim {sim_args} --domain-id 23 --duration 120 > '{}' 2> '{}' & sim=$!; \
         sleep 0.3; ",
        out("sim.json"),
        out("sim.err"),
    );
    for (i, args) in watchers.iter().enumerate() {
        script += &format!(
            "'{BIN}' ros2 {args} --domain-id 23 > '{}' 2> '{}' & w{i}=$!; ",
            out(&format!("w{i}.json")),
            out(&format!("w{i}.err")),
        );
    }
    script += &format!(
        "code=0; '{BIN}' ros2 {mover} --domain-id 23 > '{}' 2> '{}' || code=$?; ",
        out("mover.json"),
        out("mover.err"),
    );
    for i in 0..watchers.len() {
        script += &format!("kill -TERM $w{i}; wait $w{i} || code=$?; ");
    }
    script += "kill -TERM $sim; wait $sim || true; exit $code";
    let status = Command::new("unshare")
        .args(["-n", "sh", "-c", &script])
        .status()
        .expect("runs unshare");
    let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap_or_default();
    let mut logs = format!("sim: {}\nmover: {}", read("sim.err"), read("mover.err"));
    for i in 0..watchers.len() {
        logs += &format!("\nwatcher {i}: {}", read(&format!("w{i}.err")));
    }
    assert!(status.success(), "the nodes failed ({status}):\n{logs}");
    let summary = |name: &str| -> Value {
        let text = read(name);
        let line = text.lines().last().unwrap_or_default();
        serde_json::from_str(line)
            .unwrap_or_else(|e| panic!("{name} is not one JSON line ({e}): {text:?}\n{logs}"))
    };
    Session {
        sim: summary("sim.json"),
        mover: summary("mover.json"),
        watchers: (0..watchers.len())
            .map(|i| (summary(&format!("w{i}.json")), read(&format!("w{i}.err"))))
            .collect(),
    }
}
