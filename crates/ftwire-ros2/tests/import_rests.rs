//! A synthetic 1 kHz session written as a bag and imported: the rests, their mean wrench
//! (within the noise over √n), `b`, the markers; bad messages skipped and counted; a missing
//! topic named with the topics the bag has.

use std::path::PathBuf;

use ftwire_estimate::log::{read_log, to_line};
use ftwire_ros2::bag::{BagReader, BagWriter};
use ftwire_ros2::import::{ImportError, ImportParams, RestParams, import};
use ftwire_ros2::msg::*;
use nalgebra::{UnitQuaternion, Vector3 as V3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The stamps' epoch: a wall-clock time, as a real bag has.
const EPOCH_SEC: i64 = 1_700_000_000;
/// Uniform noise half-widths: force \[N\] and torque \[N·m\].
const FORCE_NOISE: f64 = 0.3;
const TORQUE_NOISE: f64 = 0.03;
/// Move and rest durations \[ms\].
const MOVE_MS: i64 = 1000;
const REST_MS: i64 = 3000;

fn temp(name: &str) -> PathBuf {
    let path = std::env::temp_dir().join(format!("ftwire-ros2-{}-{name}", std::process::id()));
    std::fs::remove_file(&path).ok();
    path
}

/// The truth of one rest.
struct Rest {
    position: [f64; 3],
    rotation: [f64; 3],
    wrench: [f64; 6],
    markers: Vec<Option<[f64; 3]>>,
}

fn rests() -> Vec<Rest> {
    let markers = |x: f64| {
        vec![
            Some([0.0, 0.0, 0.0]),
            Some([0.1, x, 0.0]),
            Some([0.2, 2.0 * x, -0.01]),
            Some([0.3, 3.0 * x, -0.02]),
        ]
    };
    let mut second = markers(0.02);
    second[2] = None;
    vec![
        Rest {
            position: [0.6, 0.0, 0.0],
            rotation: [0.0, 0.0, 0.2],
            wrench: [1.0, -2.0, 3.0, 0.1, -0.2, 0.3],
            markers: markers(0.01),
        },
        Rest {
            position: [0.55, 0.2, 0.05],
            rotation: [0.1, -0.2, 0.5],
            wrench: [-0.5, 1.5, 2.0, -0.05, 0.15, 0.02],
            markers: second,
        },
        Rest {
            position: [0.5, -0.1, 0.2],
            rotation: [0.0, 0.4, -0.3],
            wrench: [2.5, 0.5, -1.0, 0.2, 0.0, -0.1],
            markers: markers(0.03),
        },
    ]
}

fn time(ms: i64) -> Time {
    let ns = (EPOCH_SEC * 1000 + ms) * 1_000_000;
    Time {
        sec: i32::try_from(ns.div_euclid(1_000_000_000)).expect("fits"),
        nanosec: u32::try_from(ns.rem_euclid(1_000_000_000)).expect("fits"),
    }
}

fn header(ms: i64, frame: &str) -> Header {
    Header {
        stamp: time(ms),
        frame_id: frame.into(),
    }
}

fn log_ns(ms: i64) -> u64 {
    u64::try_from((EPOCH_SEC * 1000 + ms) * 1_000_000).expect("positive")
}

fn pose(p: V3<f64>, q: UnitQuaternion<f64>) -> Pose {
    Pose {
        position: Point {
            x: p.x,
            y: p.y,
            z: p.z,
        },
        orientation: Quaternion {
            x: q.i,
            y: q.j,
            z: q.k,
            w: q.w,
        },
    }
}

fn wrench(w: [f64; 6]) -> Wrench {
    Wrench {
        force: Vector3 {
            x: w[0],
            y: w[1],
            z: w[2],
        },
        torque: Vector3 {
            x: w[3],
            y: w[4],
            z: w[5],
        },
    }
}

/// What the bad session adds.
#[derive(Clone, Copy)]
struct Bad {
    nan_wrench: bool,
    backwards_wrench: bool,
    wrong_frame_wrench: bool,
    nan_tip: bool,
    non_unit_tip: bool,
}

const CLEAN: Bad = Bad {
    nan_wrench: false,
    backwards_wrench: false,
    wrong_frame_wrench: false,
    nan_tip: false,
    non_unit_tip: false,
};

/// Writes the session: per rest, a 1 s move then a 3 s rest whose first second carries a
/// decaying transient, then a last move; wrench at 1 kHz, tip pose at 100 Hz, markers at 20 Hz
/// (none from the third rest on). A rest's last pose is the next move's first (at its start),
/// so each rest lasts 3 s and its window, from 1 s in, holds 2001 wrench samples.
fn write_session(path: &PathBuf, truth: &[Rest], bad: Bad, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut bag = BagWriter::create(path, false).expect("creates");
    let mut previous = (V3::new(0.4, 0.0, 0.0), UnitQuaternion::identity(), [0.0; 6]);
    let mut t0 = 0;
    // After the last rest, one more move away, so that every rest ends the same way.
    let away = Rest {
        position: [0.4, 0.0, 0.1],
        rotation: [0.0; 3],
        wrench: [0.0; 6],
        markers: Vec::new(),
    };
    for (k, rest) in truth.iter().chain([&away]).enumerate() {
        let last = k == truth.len();
        let target = (
            V3::from(rest.position),
            UnitQuaternion::from_scaled_axis(V3::from(rest.rotation)),
            rest.wrench,
        );
        let rest_start = t0 + MOVE_MS;
        let rest_ms = if last { 0 } else { REST_MS };
        for ms in t0..rest_start + rest_ms {
            let in_rest = ms >= rest_start;
            let s = ((ms - t0) as f64 / MOVE_MS as f64).min(1.0);
            // The wrench: the move blends the two rests; a rest adds a transient that settles.
            let mut w = [0.0; 6];
            for (i, wi) in w.iter_mut().enumerate() {
                let transient = if in_rest {
                    2.0 * (-((ms - rest_start) as f64) / 150.0).exp()
                } else {
                    0.0
                };
                let half = if i < 3 { FORCE_NOISE } else { TORQUE_NOISE };
                *wi = previous.2[i]
                    + s * (target.2[i] - previous.2[i])
                    + transient
                    + rng.random_range(-half..=half);
            }
            let mut frame = "ft_sensor";
            let mut stamp_ms = ms;
            let offset = ms - rest_start;
            if k == 1 && in_rest {
                if bad.nan_wrench && offset == 1500 {
                    w[4] = f64::NAN;
                }
                if bad.backwards_wrench && offset == 1600 {
                    stamp_ms = ms - 500;
                }
                if bad.wrong_frame_wrench && offset == 1700 {
                    frame = "other";
                }
            }
            let message = WrenchStamped {
                header: header(stamp_ms, frame),
                wrench: wrench(w),
            };
            bag.write("/ft", log_ns(ms), &message).expect("writes");

            if ms % 10 == 0 {
                let p = previous.0 + s * (target.0 - previous.0);
                let q = previous.1.slerp(&target.1, s);
                let mut tip = PoseStamped {
                    header: header(ms, "base_clamp"),
                    pose: pose(p, q),
                };
                if k == 2 && offset == 2000 && bad.nan_tip {
                    tip.pose.position.y = f64::NAN;
                }
                if k == 2 && offset == 2100 && bad.non_unit_tip {
                    tip.pose.orientation.w *= 2.0;
                }
                bag.write("/tip", log_ns(ms), &tip).expect("writes");
            }
            // None at a move's first instant: the tip is still at the rest there.
            if ms % 50 == 0 && k < 2 && ms != t0 {
                let points = if in_rest {
                    rest.markers.clone()
                } else {
                    vec![Some([9.0, 9.0, 9.0]); 4]
                };
                let nan = f64::NAN;
                let markers = PoseArray {
                    header: header(ms, "base_clamp"),
                    poses: points
                        .iter()
                        .map(|p| {
                            let p = p.unwrap_or([nan, nan, nan]);
                            pose(V3::from(p), UnitQuaternion::identity())
                        })
                        .collect(),
                };
                bag.write("/markers", log_ns(ms), &markers).expect("writes");
            }
        }
        previous = target;
        t0 = rest_start + rest_ms;
    }
    bag.finish().expect("finishes");
}

fn params() -> ImportParams {
    ImportParams {
        markers_topic: Some("/markers".into()),
        ..ImportParams::new("/ft", "/tip")
    }
}

#[test]
fn rests_means_poses_and_markers_are_recovered() {
    let path = temp("session.mcap");
    let truth = rests();
    write_session(&path, &truth, CLEAN, 7);
    let bag = BagReader::open(&path).expect("reads");
    let import = import(&bag, &params()).expect("imports");
    let summary = &import.summary;
    assert_eq!(import.records.len(), 3, "{summary}");
    assert_eq!(summary.rests, 3);
    assert_eq!(summary.skipped.total(), 0, "{summary}");
    assert_eq!(summary.wrench_messages, 3 * 4000 + 1000);
    // Each window: from 1 s after the rest's first pose to its last pose (2.99 s), at 1 kHz.
    assert_eq!(summary.wrench_samples_used, 3 * 2001, "{summary}");
    assert_eq!(summary.rests_without_markers, 1);

    for (k, (record, rest)) in import.records.iter().zip(&truth).enumerate() {
        // The rest's end: its last tip pose.
        let end = (EPOCH_SEC * 1000 + (k as i64 + 1) * (MOVE_MS + REST_MS)) as f64 / 1000.0;
        assert!(
            (record.time - end).abs() < 1e-6,
            "rest {k}: {}",
            record.time
        );
        let raw = record.raw.expect("raw");
        for (i, (got, want)) in raw.iter().zip(&rest.wrench).enumerate() {
            let half = if i < 3 { FORCE_NOISE } else { TORQUE_NOISE };
            let standard_error = half / 3f64.sqrt() / 2001f64.sqrt();
            assert!(
                (got - want).abs() < 4.0 * standard_error,
                "rest {k}, raw[{i}] = {got} vs {want}"
            );
        }
        let b = record.b.expect("b");
        for i in 0..3 {
            assert!((b.position[i] - rest.position[i]).abs() < 1e-12, "{b:?}");
            assert!((b.rotation[i] - rest.rotation[i]).abs() < 1e-9, "{b:?}");
        }
        if k < 2 {
            assert_eq!(record.markers.as_ref(), Some(&rest.markers), "rest {k}");
        } else {
            assert_eq!(record.markers, None);
        }
    }
    // The lines are a log the log commands read.
    let text: String = import
        .records
        .iter()
        .map(|r| to_line(r).expect("a line") + "\n")
        .collect();
    let back = read_log(text.as_bytes()).expect("a valid log");
    assert_eq!(back, import.records);
    assert!(text.contains("null"), "a dropout is null: {text}");
    std::fs::remove_file(&path).ok();
}

#[test]
fn without_the_settle_time_the_transient_biases_the_mean() {
    let path = temp("settle.mcap");
    let truth = rests();
    write_session(&path, &truth, CLEAN, 8);
    let bag = BagReader::open(&path).expect("reads");
    let mut p = params();
    p.rest = RestParams {
        settle: 0.0,
        min_duration: 1.0,
        ..RestParams::default()
    };
    let import = import(&bag, &p).expect("imports");
    let raw = import.records[0].raw.expect("raw");
    // The transient 2 e^(−t/0.15 s) adds about 2·0.15/3 = 0.1 N to the mean of every channel.
    assert!(raw[0] - truth[0].wrench[0] > 0.05, "{raw:?}");
    std::fs::remove_file(&path).ok();
}

#[test]
fn bad_messages_are_skipped_and_counted() {
    let path = temp("bad.mcap");
    let truth = rests();
    let bad = Bad {
        nan_wrench: true,
        backwards_wrench: true,
        wrong_frame_wrench: true,
        nan_tip: true,
        non_unit_tip: true,
    };
    write_session(&path, &truth, bad, 9);
    let bag = BagReader::open(&path).expect("reads");
    let mut p = params();
    p.wrench_frame = Some("ft_sensor".into());
    let import = import(&bag, &p).expect("imports");
    let s = &import.summary;
    assert_eq!(s.skipped.non_finite, 2, "{s}");
    assert_eq!(s.skipped.backwards, 1, "{s}");
    assert_eq!(s.skipped.wrong_frame, 1, "{s}");
    assert_eq!(s.skipped.not_unit_quaternion, 1, "{s}");
    assert_eq!(s.skipped.total(), 5, "{s}");
    // A skipped tip pose does not split its rest; the skipped wrenches leave 3 fewer samples.
    assert_eq!(import.records.len(), 3, "{s}");
    assert_eq!(s.wrench_samples_used, 3 * 2001 - 3, "{s}");
    let raw = import.records[1].raw.expect("raw");
    assert!(raw.iter().all(|v| v.is_finite()));
    assert!((raw[1] - truth[1].wrench[1]).abs() < 0.05, "{raw:?}");

    // Without a required frame, the wrench in the other frame is used.
    let import = ftwire_ros2::import::import(&bag, &params()).expect("imports");
    assert_eq!(import.summary.skipped.wrong_frame, 0);
    assert_eq!(import.summary.wrench_samples_used, 3 * 2001 - 2);
    std::fs::remove_file(&path).ok();
}

#[test]
fn a_missing_or_mistyped_topic_and_bad_settings_are_named() {
    let path = temp("topics.mcap");
    write_session(&path, &rests()[..1], CLEAN, 10);
    let bag = BagReader::open(&path).expect("reads");
    let mut p = params();
    p.wrench_topic = "/wrench".into();
    let error = import(&bag, &p).expect_err("no such topic");
    assert!(matches!(error, ImportError::MissingTopic { .. }));
    let text = error.to_string();
    for needle in [
        "/wrench",
        "/ft (geometry_msgs/msg/WrenchStamped)",
        "/tip (geometry_msgs/msg/PoseStamped)",
        "/markers (geometry_msgs/msg/PoseArray)",
    ] {
        assert!(text.contains(needle), "{text} should name {needle}");
    }
    let mut p = params();
    p.tip_pose_topic = "/ft".into();
    let text = import(&bag, &p).expect_err("wrong type").to_string();
    assert!(
        text.contains("tip pose topic /ft holds geometry_msgs/msg/WrenchStamped")
            && text.contains("must be geometry_msgs/msg/PoseStamped"),
        "{text}"
    );
    let mut p = params();
    p.rest.settle = 2.0;
    let text = import(&bag, &p).expect_err("settle ≥ rest").to_string();
    assert!(text.contains("minimum rest [s] = 1.5"), "{text}");
    std::fs::remove_file(&path).ok();
}
