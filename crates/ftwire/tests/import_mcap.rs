//! `ftwire import mcap`: a bag written by `BagWriter` from a synthetic 1 kHz session becomes a
//! log the log commands read; an existing `--out` is never replaced without `--force`; a
//! missing topic is bad input naming the topics the bag has.
#![cfg(feature = "ros2")]

mod cli_support;

use std::path::{Path, PathBuf};

use cli_support::{assert_exit, ftwire};
use ftwire_estimate::log::read_log;
use ftwire_ros2::bag::BagWriter;
use ftwire_ros2::msg::{
    Header, Point, Pose, PoseArray, PoseStamped, Quaternion, Time, Vector3, Wrench, WrenchStamped,
};

/// A fresh folder for one test.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ftwire-import-{}-{name}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).expect("creates");
    dir
}

fn header(ms: i64) -> Header {
    Header {
        stamp: Time {
            sec: i32::try_from(ms / 1000).expect("fits"),
            nanosec: u32::try_from((ms % 1000) * 1_000_000).expect("fits"),
        },
        frame_id: "base_clamp".into(),
    }
}

fn ns(ms: i64) -> u64 {
    u64::try_from(ms * 1_000_000).expect("positive")
}

/// Two 3 s rests at x = 0.6 m and 0.5 m (1 s moves before each and after the last), the
/// wrench constant per rest (force z = 1 N, then 2 N) with a ±0.2 N alternating ripple, tip
/// poses at 100 Hz, markers at 20 Hz with marker 1 a dropout.
fn write_bag(path: &Path) {
    let mut bag = BagWriter::create(path, false).expect("creates");
    let xs = [0.7, 0.6, 0.5, 0.4];
    let mut ms = 0;
    for k in 0..3 {
        let (from, to) = (xs[k], xs[k + 1]);
        let rest_ms = if k < 2 { 3000 } else { 0 };
        let start = ms;
        while ms < start + 1000 + rest_ms {
            let s = ((ms - start) as f64 / 1000.0).min(1.0);
            let x = from + s * (to - from);
            let fz = (k + 1) as f64 + if ms % 2 == 0 { 0.2 } else { -0.2 };
            let wrench = WrenchStamped {
                header: header(ms),
                wrench: Wrench {
                    force: Vector3 {
                        x: 0.0,
                        y: 0.0,
                        z: fz,
                    },
                    torque: Vector3 {
                        x: 0.0,
                        y: 0.05,
                        z: 0.0,
                    },
                },
            };
            bag.write("/ft", ns(ms), &wrench).expect("writes");
            let pose = Pose {
                position: Point { x, y: 0.0, z: 0.0 },
                orientation: Quaternion::default(),
            };
            if ms % 10 == 0 {
                let tip = PoseStamped {
                    header: header(ms),
                    pose,
                };
                bag.write("/tip", ns(ms), &tip).expect("writes");
            }
            if ms % 50 == 0 && ms != start {
                let dropout = Pose {
                    position: Point {
                        x: f64::NAN,
                        y: f64::NAN,
                        z: f64::NAN,
                    },
                    ..pose
                };
                let markers = PoseArray {
                    header: header(ms),
                    poses: vec![Pose::default(), dropout, pose],
                };
                bag.write("/markers", ns(ms), &markers).expect("writes");
            }
            ms += 1;
        }
    }
    bag.finish().expect("finishes");
}

fn import(bag: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "import",
        "mcap",
        bag.to_str().expect("utf-8"),
        "--wrench",
        "/ft",
        "--tip-pose",
        "/tip",
        "--markers",
        "/markers",
        "--out",
        out.to_str().expect("utf-8"),
    ];
    args.extend_from_slice(extra);
    ftwire(&args)
}

#[test]
fn a_bag_becomes_a_log_the_log_commands_read() {
    let dir = folder("log");
    let bag = dir.join("session.mcap");
    write_bag(&bag);
    let out = dir.join("session.jsonl");
    let output = import(&bag, &out, &[]);
    assert_exit(&output, 0, "2 rests", "import");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.lines().count(), 1, "one summary line: {stderr}");
    let log = read_log(
        std::fs::File::open(&out)
            .map(std::io::BufReader::new)
            .expect("opens"),
    )
    .expect("a valid log");
    assert_eq!(log.len(), 2);
    for (record, (x, fz)) in log.iter().zip([(0.6, 1.0), (0.5, 2.0)]) {
        let raw = record.raw.expect("raw");
        assert!((raw[2] - fz).abs() < 1e-3, "{raw:?}");
        assert!((raw[4] - 0.05).abs() < 1e-9, "{raw:?}");
        let b = record.b.expect("b: identify needs it");
        assert!((b.position[0] - x).abs() < 1e-12, "{b:?}");
        let markers = record.markers.as_ref().expect("markers");
        assert_eq!(markers.len(), 3);
        assert_eq!(markers[1], None, "the dropout is null");
        assert_eq!(markers[2].map(|p| p[0]), Some(x));
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn an_existing_out_is_replaced_only_with_force() {
    let dir = folder("force");
    let bag = dir.join("session.mcap");
    write_bag(&bag);
    let out = dir.join("kept.jsonl");
    std::fs::write(&out, "mine\n").expect("writes");
    let output = import(&bag, &out, &[]);
    assert_exit(&output, 2, &out.display().to_string(), "no --force");
    assert_exit(&output, 2, "--force", "no --force");
    assert_eq!(std::fs::read_to_string(&out).expect("reads"), "mine\n");
    let output = import(&bag, &out, &["--force"]);
    assert_exit(&output, 0, "rests", "--force");
    assert!(
        std::fs::read_to_string(&out)
            .expect("reads")
            .contains("\"raw\"")
    );
    // The bag itself is never the output, even with --force.
    let output = import(&bag, &bag, &["--force"]);
    assert_exit(&output, 2, "is the bag being read", "--out = the bag");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_missing_topic_or_bad_bag_or_bad_setting_is_bad_input() {
    let dir = folder("topics");
    let bag = dir.join("session.mcap");
    write_bag(&bag);
    let out = dir.join("out.jsonl");
    let output = ftwire(&[
        "import",
        "mcap",
        bag.to_str().expect("utf-8"),
        "--wrench",
        "/wrench",
        "--tip-pose",
        "/tip",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert_exit(&output, 2, "/wrench", "missing topic");
    for needle in [
        "/ft (geometry_msgs/msg/WrenchStamped)",
        "/tip (geometry_msgs/msg/PoseStamped)",
        "/markers (geometry_msgs/msg/PoseArray)",
    ] {
        assert_exit(&output, 2, needle, "missing topic names the bag's topics");
    }
    assert!(!out.exists());

    let not_bag = dir.join("notes.mcap");
    std::fs::write(&not_bag, "not a bag").expect("writes");
    let output = import(&not_bag, &out, &[]);
    assert_exit(&output, 2, "not a readable MCAP", "not a bag");
    assert_exit(&output, 2, &not_bag.display().to_string(), "not a bag");

    let output = import(&bag, &out, &["--settle-s", "2"]);
    assert_exit(
        &output,
        2,
        "minimum rest [s] = 1.5",
        "settle beyond the rest",
    );
    let output = import(&bag, &out, &["--rest-position-mm", "-1"]);
    assert_exit(
        &output,
        2,
        "position tolerance [m] = -0.001",
        "negative tolerance",
    );
    std::fs::remove_dir_all(&dir).ok();
}
