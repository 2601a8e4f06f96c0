//! `ftwire ros2 sim` and each other node (`estimate`, `control`, `identify`) as two processes
//! talking ROS 2 (DDS over UDP), in a network namespace whose only device is the loopback, so
//! that no packet leaves the machine. DDS discovery needs only `lo` up in it (its multicast flag and a 224.0.0.0/4 route
//! are not needed). Making the namespace needs root (`unshare -n`); where it is not permitted
//! the tests fail and say so, rather than run on the real network.
//!
//! The sim runs without gravity (the estimator's weightless model then holds exactly) and with
//! the default sensor but no dropouts (a dropout is a sample the sensor never sent, which the
//! estimator would rightly count as lost); the estimator has no calibration, only the
//! simulated sensor's mounting, so its shapes carry the sensor's uncalibrated gain and
//! cross-talk.
#![cfg(feature = "ros2")]

use std::path::Path;
use std::process::Command;

use serde_json::Value;

mod ros2_support;

use ros2_support::{BIN, require_unshare, run_session, temp_dir};

/// Runs the sim for `sim_s` and, 0.3 s later, the estimator for `estimate_s` seconds, in one
/// loopback-only namespace; returns both summaries.
fn run_pair(tag: &str, sim_s: f64, estimate_s: f64) -> (Value, Value) {
    let dir = temp_dir(tag);
    let result = run_pair_in(&dir, sim_s, estimate_s, "");
    let _ = std::fs::remove_dir_all(Path::new(&dir));
    result
}

/// As [`run_pair`], in `dir` (kept), with `extra` options for the estimator.
fn run_pair_in(dir: &Path, sim_s: f64, estimate_s: f64, extra: &str) -> (Value, Value) {
    let node = format!("estimate --truth-topic /wire/truth --duration {estimate_s} {extra}");
    let (sim, estimate, _) = run_nodes(dir, sim_s, &node);
    (sim, estimate)
}

/// In one loopback-only namespace, in `dir`: the sim (gravity off, no dropouts, for at most
/// `sim_s`) and, 0.3 s later, `ftwire ros2 <node_args>` until it ends by itself; then the sim
/// ends with SIGTERM. Returns both summaries and the node's log.
fn run_nodes(dir: &Path, sim_s: f64, node_args: &str) -> (Value, Value, String) {
    require_unshare();
    let sensor = dir.join("sensor.toml");
    std::fs::write(&sensor, "dropout_probability = 0.0\n").expect("a sensor file");
    let out = |name: &str| dir.join(name).display().to_string();
    let script = format!(
        "set -e; ip link set lo up; \
         [ \"$(ip -o link | wc -l)\" = 1 ] || {{ echo 'the namespace has a device besides lo' >&2; exit 97; }}; \
         '{BIN}' ros2 sim --gravity off --sensor '{sensor}' --seed 3 --domain-id 17 \
           --duration {sim_s} > '{sim}' 2> '{sim_err}' & sim=$!; \
         sleep 0.3; \
         '{BIN}' ros2 {node_args} --domain-id 17 > '{node}' 2> '{node_err}'; \
         kill -TERM $sim 2>/dev/null || true; wait",
        sensor = sensor.display(),
        sim = out("sim.json"),
        sim_err = out("sim.err"),
        node = out("node.json"),
        node_err = out("node.err"),
    );
    let status = Command::new("unshare")
        .args(["-n", "sh", "-c", &script])
        .status()
        .expect("runs unshare");
    let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap_or_default();
    assert!(
        status.success(),
        "the nodes failed ({status}):\nsim: {}\nnode: {}",
        read("sim.err"),
        read("node.err")
    );
    let summary = |name: &str, log: &str| -> Value {
        let text = read(name);
        let line = text.lines().last().unwrap_or_default();
        serde_json::from_str(line).unwrap_or_else(|e| {
            panic!(
                "{name} is not one JSON line ({e}): {text:?}\nlog: {}",
                read(log)
            )
        })
    };
    (
        summary("sim.json", "sim.err"),
        summary("node.json", "node.err"),
        read("node.err"),
    )
}

fn count(v: &Value, group: &str, name: &str) -> u64 {
    v[group][name].as_u64().unwrap_or(0)
}

/// The checks both runs share: nothing lost or refused, every sample from the first.
fn check_stream(sim: &Value, estimate: &Value, min_wrenches: u64) {
    assert_eq!(sim["dropouts"], 0, "{sim}");
    assert_eq!(sim["refused"], serde_json::json!({}), "{sim}");
    assert_eq!(estimate["refused"], serde_json::json!({}), "{estimate}");
    assert_eq!(sim["publish_failed"], serde_json::json!({}), "{sim}");
    assert_eq!(
        estimate["publish_failed"],
        serde_json::json!({}),
        "{estimate}"
    );
    let received = count(estimate, "received", "wrench");
    assert!(received >= min_wrenches, "{estimate}");
    assert!(received <= count(sim, "published", "/ft_sensor/wrench"));
    assert_eq!(estimate["lost"], 0, "{estimate}");
    assert_eq!(estimate["out_of_order"], 0, "{estimate}");
    // The clock starts once the estimator listens, so its tare sees the empty gripper.
    assert_eq!(estimate["first_sample"], 0, "{estimate}");
    assert_eq!(estimate["no_shape"], 0, "{estimate}");
    assert!(count(estimate, "published", "shape") > 0, "{estimate}");
    assert_eq!(
        count(estimate, "published", "shape"),
        count(estimate, "published", "status")
    );
}

/// The shapes against the truth, with their error bars: the uncalibrated default sensor's
/// gain and cross-talk (about 1.5 %) given as the gain error, and the model's 0.5 mm at the
/// tip against the simulated rod.
#[test]
fn the_estimate_on_ros2_matches_the_simulators_truth_and_loses_nothing() {
    let dir = temp_dir("short");
    let (sim, estimate) = run_pair_in(&dir, 4.5, 3.0, "--gain-error 1.5 --model-error 6e-4");
    let _ = std::fs::remove_dir_all(&dir);
    check_stream(&sim, &estimate, 2000);
    check_truth(&estimate);
    eprintln!("sim: {sim}\nestimate: {estimate}");
    let sigma = &estimate["sigma"];
    let tip = sigma["tip_mean_mm"].as_f64().unwrap_or(f64::NAN);
    let largest = sigma["tip_max_mm"].as_f64().unwrap_or(f64::NAN);
    assert!(tip > 0.1 && tip <= largest && largest < 50.0, "{sigma}");
    let within = sigma["within_2sigma"].as_f64().unwrap_or(0.0);
    assert!(within >= 0.9, "{sigma}");
}

/// The shapes from the uncalibrated default sensor (its gain and cross-talk of about 1 %)
/// against the true centreline: at least 10 compared, a few mm on average along the wire.
fn check_truth(estimate: &serde_json::Value) {
    let truth = &estimate["truth"];
    assert!(truth["compared"].as_u64().unwrap_or(0) >= 10, "{estimate}");
    let mean = truth["mean_mm"].as_f64().unwrap_or(f64::INFINITY);
    assert!(
        mean < 4.0,
        "mean distance to the truth {mean} mm: {estimate}"
    );
    let worst = truth["worst_mean_mm"].as_f64().unwrap_or(f64::INFINITY);
    assert!(worst < 8.0, "worst mean distance {worst} mm: {estimate}");
}

/// The tip pose from TF (`--base-frame wire_base --tip-frame wire_tip`: the sim's static
/// world → wire_base and dynamic world → wire_tip, composed), with the contact check on: the
/// same shapes and no loss as with the `PoseStamped`, every lookup after the first wrench
/// answered but for the start, and no contact (the tip found is the gripper's).
#[test]
fn the_estimate_with_the_tip_from_tf_frames_matches_the_truth() {
    let dir = temp_dir("tf");
    let bag = dir.join("tf.mcap");
    let (sim, estimate) = run_pair_in(
        &dir,
        4.5,
        3.0,
        &format!(
            "--base-frame wire_base --tip-frame wire_tip --contact-miss 20 --record '{}'",
            bag.display()
        ),
    );
    check_stream(&sim, &estimate, 2000);
    // Each recorded topic carries the QoS the node used (rosbag2's names with Jazzy, rmw's
    // numbers with Humble): /tf_static transient local, the rest volatile; the wrench best
    // effort (the sensor-data default of --qos, which matches the sim's reliable publisher),
    // the rest reliable.
    let reader = ftwire_ros2::bag::BagReader::open(&bag).expect("the recorded bag opens");
    let reliable = ["reliable", "1"];
    for (topic, durability, depth, reliability) in [
        ("/tf_static", ["transient_local", "1"], "0", reliable),
        ("/tf", ["volatile", "2"], "100", reliable),
        (
            "/ft_sensor/wrench",
            ["volatile", "2"],
            "1000",
            ["best_effort", "2"],
        ),
        ("/wire/shape", ["volatile", "2"], "10", reliable),
    ] {
        let qos = &reader.topic(topic).expect("recorded").offered_qos_profiles;
        let has = |key: &str, values: &[&str]| {
            values.iter().any(|v| {
                qos.lines()
                    .any(|l| l.trim_start_matches(['-', ' ']) == format!("{key}: {v}"))
            })
        };
        assert!(has("durability", &durability), "{topic}: {qos}");
        assert!(has("reliability", &reliability), "{topic}: {qos}");
        assert!(has("depth", &[depth]), "{topic}: {qos}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(count(&estimate, "received", "tip_pose"), 0, "{estimate}");
    assert_eq!(count(&estimate, "received", "tf_static"), 1, "{estimate}");
    assert!(count(&estimate, "received", "tf") >= 200, "{estimate}");
    let tf = &estimate["tf"];
    assert_eq!(tf["edges"], 2, "{estimate}");
    assert_eq!(tf["stale"], 0, "{estimate}");
    let answered = tf["answered"].as_u64().unwrap_or(0);
    let missed = tf["not_available"].as_u64().unwrap_or(u64::MAX);
    assert!(answered > 100 && missed < answered / 10, "{estimate}");
    assert_eq!(estimate["contacts"], 0, "{estimate}");
    check_truth(&estimate);
    eprintln!("sim: {sim}\nestimate: {estimate}");
}

/// Giving one TF frame without the other, or with a tip pose topic, is refused before the node
/// starts, naming the options.
#[test]
fn tf_frames_go_together_and_exclude_the_tip_pose_topic() {
    for (args, needle) in [
        (&["--base-frame", "wire_base"][..], "--tip-frame"),
        (
            &[
                "--base-frame",
                "a",
                "--tip-frame",
                "b",
                "--tip-pose-topic",
                "/t",
            ][..],
            "--tip-pose-topic",
        ),
        (&["--tf-stale", "1"][..], "--base-frame"),
        (
            &["--base-frame", "a", "--tip-frame", "a"][..],
            "--tip-frame",
        ),
    ] {
        let output = Command::new(BIN)
            .args(["ros2", "estimate", "--duration", "1"])
            .args(args)
            .output()
            .expect("runs ftwire");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
    }
}

/// `--record` writes every message the estimator received and published into a ROS 2 bag, and
/// `ftwire import mcap` reads the session back: one rest (the sim holds still) whose wrench is
/// the mean of the recorded wrenches after the settle time, and whose pose is the recorded one.
#[test]
fn a_recorded_session_imports_to_its_rest() {
    use ftwire_ros2::bag::BagReader;
    use ftwire_ros2::msg::{PoseStamped, WrenchStamped};

    let dir = temp_dir("record");
    let bag = dir.join("session.mcap");
    let (sim, estimate) = run_pair_in(&dir, 4.5, 3.0, &format!("--record '{}'", bag.display()));
    check_stream(&sim, &estimate, 2000);
    let total = |group: &str| -> u64 {
        estimate[group]
            .as_object()
            .map_or(0, |m| m.values().filter_map(Value::as_u64).sum())
    };
    let written = estimate["recorded"]["written"].as_u64().unwrap_or(0);
    assert_eq!(
        written,
        total("received") + total("published"),
        "{estimate}"
    );
    assert_eq!(estimate["recorded"]["failed"], 0, "{estimate}");

    let reader = BagReader::open(&bag).expect("the recorded bag opens");
    let (mut wrenches, mut pose) = (Vec::new(), None);
    for m in reader.messages() {
        match m.topic.name.as_str() {
            "/ft_sensor/wrench" => {
                wrenches.push(reader.decode::<WrenchStamped>(m).expect("a wrench"))
            }
            "/wire/tip_pose" => pose = Some(reader.decode::<PoseStamped>(m).expect("a pose")),
            _ => {}
        }
    }
    assert_eq!(
        wrenches.len() as u64,
        count(&estimate, "received", "wrench")
    );
    let pose = pose.expect("a tip pose was recorded");

    let log = dir.join("session.jsonl");
    let output = Command::new(BIN)
        .args(["import", "mcap"])
        .arg(&bag)
        .args([
            "--wrench",
            "/ft_sensor/wrench",
            "--tip-pose",
            "/wire/tip_pose",
            "--out",
        ])
        .arg(&log)
        .output()
        .expect("runs import");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let text = std::fs::read_to_string(&log).expect("the log");
    let records: Vec<Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    assert_eq!(records.len(), 1, "{text}");
    let record = &records[0];
    let position = &record["b"]["position"];
    for (i, v) in [
        pose.pose.position.x,
        pose.pose.position.y,
        pose.pose.position.z,
    ]
    .into_iter()
    .enumerate()
    {
        let got = position[i].as_f64().expect("a position");
        assert!((got - v).abs() < 1e-9, "b {position} against {v}");
    }
    // The mean of the recorded wrenches a settle time (1 s, past the 0.5 s tare) into the rest.
    let start = wrenches.first().map_or(0.0, |w| {
        f64::from(w.header.stamp.sec) + 1e-9 * f64::from(w.header.stamp.nanosec)
    });
    let settled: Vec<[f64; 6]> = wrenches
        .iter()
        .filter(|w| {
            f64::from(w.header.stamp.sec) + 1e-9 * f64::from(w.header.stamp.nanosec) >= start + 1.0
        })
        .map(|w| {
            let (f, t) = (w.wrench.force, w.wrench.torque);
            [f.x, f.y, f.z, t.x, t.y, t.z]
        })
        .collect();
    assert!(settled.len() > 1000, "{}", settled.len());
    for j in 0..6 {
        let mean = settled.iter().map(|w| w[j]).sum::<f64>() / settled.len() as f64;
        let got = record["raw"][j].as_f64().expect("raw");
        assert!((got - mean).abs() < 2e-3, "raw[{j}] {got} against {mean}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A minute at 1 kHz: `cargo test --release -p ftwire --features ros2 --test ros2_nodes --
/// --ignored --nocapture` prints the lost samples and the latency from a wrench's arrival to
/// its shape's publication.
#[test]
#[ignore = "a minute of ROS 2 traffic at 1 kHz"]
fn a_minute_at_1_khz() {
    let (sim, estimate) = run_pair("minute", 62.0, 60.0);
    check_stream(&sim, &estimate, 55_000);
    let latency = &estimate["latency_ms"];
    println!(
        "60 s at 1 kHz: {} wrenches received, {} lost, {} dropped as stale; latency median \
         {:.3} ms, p99 {:.3} ms, max {:.3} ms; shape solve median {:.3} ms; truth mean {:.2} mm",
        count(&estimate, "received", "wrench"),
        estimate["lost"],
        estimate["dropped"],
        latency["median"].as_f64().unwrap_or(f64::NAN),
        latency["p99"].as_f64().unwrap_or(f64::NAN),
        latency["max"].as_f64().unwrap_or(f64::NAN),
        estimate["solve_ms"]["median"].as_f64().unwrap_or(f64::NAN),
        estimate["truth"]["mean_mm"].as_f64().unwrap_or(f64::NAN),
    );
    println!("sim: {sim}\nestimate: {estimate}");
}

/// [`run_nodes`] with `ftwire ros2 <node_args> --duration sim_s`, in a fresh folder.
fn run_with_sim(tag: &str, sim_s: f64, node_args: &str) -> (Value, Value, String) {
    let dir = temp_dir(tag);
    let result = run_nodes(&dir, sim_s, &format!("{node_args} --duration {sim_s}"));
    let _ = std::fs::remove_dir_all(Path::new(&dir));
    result
}

/// The checks every moving node shares: nothing lost or refused, every target reached.
fn check_moves(sim: &Value, node: &Value) {
    assert_eq!(sim["refused"], serde_json::json!({}), "{sim}");
    assert_eq!(node["refused"], serde_json::json!({}), "{node}");
    assert_eq!(node["publish_failed"], serde_json::json!({}), "{node}");
    assert_eq!(node["lost"], 0, "{node}");
    assert_eq!(node["unreached"], 0, "{node}");
    assert_eq!(
        count(node, "published", "tip_target"),
        sim["moves"].as_u64().unwrap_or(u64::MAX),
        "every target sent was a move: {node}\n{sim}"
    );
}

#[test]
fn control_on_ros2_steers_the_simulated_wire_to_a_nearby_goal() {
    // The sim starts at (0, 1, 0.5, −1, 0.5, 0) in the wire's units (c2/L = 0.339 N·m,
    // c2/L² = 0.413 N); the goal is about 0.3 away in normalised units.
    let (sim, control, log) = run_with_sim(
        "control",
        20.0,
        "control --goal 0.0,0.3,0.2,-0.33,0.25,0.04 --rest-samples 200 --contact-miss 20 \
         --truth-topic /wire/truth",
    );
    check_moves(&sim, &control);
    assert_eq!(control["outcome"], "reached", "{control}\n{log}");
    let error = control["final_error"].as_f64().unwrap_or(f64::INFINITY);
    assert!(error < 0.05, "final error {error}: {control}");
    let errors = control["errors"].as_array().map_or(0, Vec::len);
    assert!(errors >= 2, "the goal is not at the start: {control}");
    let steps = control["steps"].as_u64().unwrap_or(0);
    assert!((1..=40).contains(&steps), "{control}");
    // One leg of the library's tracker, to the goal.
    assert_eq!(
        control["legs"].as_array().map_or(0, Vec::len),
        1,
        "{control}"
    );
    assert_eq!(control["legs"][0]["moves"], steps, "{control}");
    assert_eq!(control["passed"], 1, "{control}");
    // The true wire against the goal's model shape: the uncalibrated default sensor's gain
    // and cross-talk (about 1 %) leave a few mm.
    let truth = control["truth"]["mean_mm"]
        .as_f64()
        .unwrap_or(f64::INFINITY);
    assert!(
        truth < 6.0,
        "true centreline {truth} mm from the goal's: {control}"
    );
    let miss = control["tip_miss_mm"].as_f64().unwrap_or(f64::INFINITY);
    assert!(
        miss < 20.0,
        "no contact, the model's tip at the gripper: {control}"
    );
    assert_eq!(
        count(&control, "published", "shape"),
        errors as u64,
        "{control}"
    );
    eprintln!("sim: {sim}\ncontrol: {control}");
}

/// A model tip that misses the reported one by more than `--contact-miss` is a contact: the
/// ROS rig ends the run at that rest, before any move.
#[test]
fn control_on_ros2_ends_in_contact_when_the_models_tip_misses_the_gripper() {
    // 10 µm: the uncalibrated default sensor's gain and cross-talk alone put the model's tip
    // a few mm from the gripper, as a force the model does not have would.
    let (sim, control, log) = run_with_sim(
        "contact",
        20.0,
        "control --goal 0.0,0.3,0.2,-0.33,0.25,0.04 --rest-samples 200 --contact-miss 0.01",
    );
    check_moves(&sim, &control);
    assert_eq!(control["outcome"], "contact", "{control}\n{log}");
    assert_eq!(control["steps"], 0, "{control}");
    assert_eq!(count(&control, "published", "tip_target"), 0, "{control}");
    let miss = control["tip_miss_mm"].as_f64().unwrap_or(0.0);
    assert!(miss > 0.01, "{control}");
    assert!(
        log.contains("contact: the model's tip misses the gripper"),
        "{log}"
    );
    assert_eq!(
        control["errors"].as_array().map_or(0, Vec::len),
        1,
        "{control}"
    );
}

/// `--max-steps` bounds the steps of the whole run: the tracker's leg to a far goal is cut by
/// the ROS rig's refusal of the move after the last, and the rest after the last step is
/// still measured against the goal.
#[test]
fn control_on_ros2_stops_after_max_steps_with_the_last_rest_measured() {
    let (sim, control, log) = run_with_sim(
        "max-steps",
        20.0,
        &format!("control --goal {FAR_GOAL} --rest-samples 200 --max-steps 2"),
    );
    check_moves(&sim, &control);
    assert_eq!(control["outcome"], "max_steps", "{control}\n{log}");
    assert_eq!(control["steps"], 2, "{control}");
    assert_eq!(count(&control, "published", "tip_target"), 2, "{control}");
    assert_eq!(control["legs"][0]["moves"], 2, "{control}");
    assert_eq!(control["passed"], 0, "{control}");
    // The start's rest and one after each step.
    let errors = control["errors"].as_array().cloned().unwrap_or_default();
    assert_eq!(errors.len(), 3, "{control}");
    assert_eq!(count(&control, "published", "shape"), 3, "{control}");
    assert!(
        errors.iter().all(|e| e.as_f64().is_some_and(|e| e > 0.1)),
        "the far goal is not reached in two steps: {errors:?}"
    );
    assert_eq!(control["final_error"], errors[2], "{control}");
}

#[test]
fn identify_on_ros2_identifies_the_simulated_wire_within_a_few_percent() {
    // The sim's default sensor's data sheet: the rests' shared bias is estimated with the wire.
    let (sim, identify, log) =
        run_with_sim("identify", 20.0, "identify --seed 1 --sensor distorted");
    check_moves(&sim, &identify);
    assert_eq!(identify["samples"], 5, "{identify}\n{log}");
    let times: Vec<f64> = log
        .lines()
        .filter_map(|l| {
            l.split(", ")
                .nth(1)?
                .split_once(" s after the tare")?
                .0
                .parse()
                .ok()
        })
        .collect();
    assert_eq!(times.len(), 5, "{log}");
    assert!(
        times[0] > 0.0 && times.windows(2).all(|w| w[0] < w[1]),
        "rest times since the tare: {times:?}"
    );
    let estimate = &identify["identified"];
    assert_eq!(estimate["identified"], true, "{identify}");
    let truth = ftwire_lab::wire::WireSpec::load("nitinol-3mm-820")
        .expect("the preset")
        .wire_params()
        .expect("valid");
    let got = |key: &str, i: usize| estimate[key][i].as_f64().unwrap_or(f64::NAN);
    for (i, c) in truth.c().iter().enumerate() {
        let rel = got("c", i) / c - 1.0;
        assert!(
            rel.abs() < 0.04,
            "c{} off by {:.1} %: {identify}",
            i + 1,
            1e2 * rel
        );
    }
    let length = estimate["length"].as_f64().unwrap_or(f64::NAN);
    assert!(
        (length / truth.length() - 1.0).abs() < 0.01,
        "L = {length}: {identify}"
    );
    assert_eq!(estimate["covariance"].as_array().map_or(0, Vec::len), 4);
    assert_eq!(estimate["interval95"].as_array().map_or(0, Vec::len), 4);
    assert_eq!(count(&identify, "published", "identified"), 1);
    eprintln!("sim: {sim}\nidentify: {identify}");
}

#[test]
fn identify_with_every_move_unreached_ends_with_a_clear_error() {
    require_unshare();
    // Targets on a topic the sim does not listen to are never reached: each is counted and
    // skipped, and one sample is too few.
    let script = format!(
        "ip link set lo up; \
         '{BIN}' ros2 sim --gravity off --domain-id 19 --duration 8 > /dev/null 2>&1 & sim=$!; \
         sleep 0.3; \
         '{BIN}' ros2 identify --samples 3 --target-topic /nowhere --move-timeout 0.3 \
           --domain-id 19 --duration 8; code=$?; kill -TERM $sim; wait; exit $code",
    );
    let output = Command::new("unshare")
        .args(["-n", "sh", "-c", &script])
        .output()
        .expect("runs unshare");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("move 1 not reached"), "{stderr}");
    assert!(
        stderr.contains("no estimate from 1 samples (2 of 2 moves unreached"),
        "{stderr}"
    );
}

/// The control node's goal in the observer's tests, about 1.7 from the sim's start in
/// normalised units: its shape's middle lies some 14 cm from the start shape's.
const FAR_GOAL: &str = "0,-0.1,0.3,-0.4,-0.2,0";

/// `control` to [`FAR_GOAL`], resting 0.8 s per step (the estimator's rests need 0.5 s).
fn far_control(steps: usize) -> String {
    format!("control --goal {FAR_GOAL} --rest-samples 800 --max-steps {steps}")
}

/// A number of a summary.
fn number(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or(f64::NAN)
}

/// Six numbers of a summary, normalised by the wire's scales (torque c2/L, force c2/L²).
fn normalised(v: &Value) -> [f64; 6] {
    let wire = ftwire_lab::wire::WireSpec::load("nitinol-3mm-820")
        .expect("the preset")
        .wire_params()
        .expect("valid");
    let (ts, fs) = (wire.torque_scale(), wire.force_scale());
    std::array::from_fn(|i| v[i].as_f64().unwrap_or(f64::NAN) / if i < 3 { ts } else { fs })
}

fn distance(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The simulated sensor without gain errors (what a perfect calibration gives; the bias
/// observer trusts `Γ` to the model's floor, which a 1 % gain error exceeds), drifting three
/// times as fast as the default (6 mN/√s per force channel: a few hundredths in normalised
/// force within the test's 20 s), with its default noise and bias, and without dropouts.
const CALIBRATED_SENSOR: &str = "dropout_probability = 0.0\n\
    bias_random_walk = [0.006, 0.006, 0.006, 0.00024, 0.00024, 0.00024]\n\
    cubic_nonlinearity = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]\n\
    gain = [[1.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0, 0.0, 0.0], \
    [0.0, 0.0, 1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0, 0.0, 0.0], \
    [0.0, 0.0, 0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 0.0, 0.0, 1.0]]\n";

/// `estimate`'s bias observer, fed by the rests of a free closed-loop motion (the control
/// node steering the sim's wire), follows the simulated sensor's drift; the shapes with it are
/// no worse than without; and its collision detector, calibrated on the first moves, finds no
/// contact on the free motion.
#[test]
fn the_bias_observer_on_ros2_follows_the_drift_and_free_motion_has_no_contact() {
    let dir = temp_dir("observe");
    let sensor = dir.join("sensor.toml");
    std::fs::write(&sensor, CALIBRATED_SENSOR).expect("a sensor file");
    // Moves that take no time on the rig's clock, which the sensor drifts by: the drift then
    // runs on the stamps' clock, as the observer assumes.
    let rig = dir.join("rig.toml");
    std::fs::write(
        &rig,
        "linear_speed = 10.0\nangular_speed = 10.0\nsettle_time = 0.0\n",
    )
    .expect("a rig file");
    let estimate = format!(
        "estimate --truth-topic /wire/truth --sensor '{}'",
        sensor.display()
    );
    let session = run_session(
        &dir,
        &format!(
            "--gravity off --seed 3 --sensor '{}' --rig '{}'",
            sensor.display(),
            rig.display()
        ),
        &far_control(22),
        &[estimate.clone(), format!("{estimate} --bias-observer off")],
    );
    let (sim, control) = (&session.sim, &session.mover);
    let (on, on_log) = &session.watchers[0];
    let (off, _) = &session.watchers[1];
    assert_eq!(sim["touching_moves"], 0, "{sim}");
    assert_eq!(count(control, "published", "tip_target"), 22, "{control}");
    for estimate in [on, off] {
        assert_eq!(estimate["first_sample"], 0, "{estimate}");
        assert_eq!(estimate["lost"], 0, "{estimate}");
        assert_eq!(estimate["refused"], serde_json::json!({}), "{estimate}");
        let rests = estimate["rests"].as_u64().unwrap_or(0);
        assert!((18..=23).contains(&rests), "a rest per step: {estimate}");
        assert!(estimate["detector"].is_object(), "calibrated: {estimate}");
        assert_eq!(estimate["contact_moves"], 0, "{estimate}");
        assert_eq!(estimate["contacts"], 0, "{estimate}");
    }
    assert!(off["bias_observer"].is_null(), "{off}");
    let observer = &on["bias_observer"];
    assert!(
        observer["updates"].as_u64().unwrap_or(0) >= 15,
        "{on}\n{on_log}"
    );
    // The estimate against the drift since the tare at the sim's end (a second after the last
    // rest), in normalised units: closer to it than no estimate. Part of it stays, by physics
    // and by the model's own error against the simulator (a force along the wire's chord
    // barely moves its end: docs/drift.md); the shapes show what the rest is worth.
    let truth = normalised(&sim["bias_drift"]);
    let estimate = normalised(&observer["bias"]);
    let size = distance(&truth, &[0.0; 6]);
    assert!(size > 0.02, "the drift is large enough to test: {sim}");
    let error = distance(&estimate, &truth);
    assert!(
        error < size,
        "β̂ {estimate:?} against the drift {truth:?}: {error:.4} of {size:.4}"
    );
    let (with, without) = (
        number(&on["truth"], "mean_mm"),
        number(&off["truth"], "mean_mm"),
    );
    assert!(
        with < without,
        "shapes with the observer {with:.2} mm, without {without:.2} mm"
    );
    eprintln!(
        "β̂ {estimate:?}, drift {truth:?} (normalised); shapes {with:.2} mm with, {without:.2} \
         mm without\nsim: {sim}\nestimate: {on}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A box at the middle of the goal's shape, some 14 cm from the start's: the control node
/// steers the wire into it, and `estimate`'s collision detector (calibrated on the first ten
/// moves, all free) flags the move that touches it, or one of the next, and none before.
#[test]
fn the_collision_detector_on_ros2_flags_the_moves_into_a_box() {
    let dir = temp_dir("collision");
    let sensor = dir.join("sensor.toml");
    std::fs::write(&sensor, "dropout_probability = 0.0\n").expect("a sensor file");
    let session = run_session(
        &dir,
        &format!(
            "--gravity off --seed 3 --sensor '{}' --box 0.393,0.095,0.029,0.01,0.01,0.01",
            sensor.display()
        ),
        &far_control(18),
        &[format!(
            "estimate --sensor '{}' --contact-miss 30",
            sensor.display()
        )],
    );
    let sim = &session.sim;
    let (estimate, log) = &session.watchers[0];
    let first_touch = sim["first_touching_move"]
        .as_u64()
        .expect("the wire touched the box");
    assert!(first_touch > 10, "the calibration's moves are free: {sim}");
    assert!(
        estimate["contact_moves"].as_u64().unwrap_or(0) >= 1,
        "{estimate}\n{log}"
    );
    assert!(
        estimate["contacts"].as_u64().unwrap_or(0) >= 1,
        "{estimate}"
    );
    // Rest 1 is the start; rest k + 1 follows move k.
    let first_alarm = log
        .lines()
        .find(|l| l.ends_with(": CONTACT"))
        .and_then(|l| l.strip_prefix("estimate: rest "))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|k| k.parse::<u64>().ok())
        .expect("a contact in the log")
        - 1;
    assert!(
        (first_touch..=first_touch + 3).contains(&first_alarm),
        "first touch at move {first_touch}, first alarm at move {first_alarm}\n{log}"
    );
    eprintln!("first touch at move {first_touch}, alarm at move {first_alarm}\n{estimate}");
    let _ = std::fs::remove_dir_all(&dir);
}
