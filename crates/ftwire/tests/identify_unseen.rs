//! Identification of wires the project was not shown, in the simulator:
//! gravity off, the default sensor through the learnt calibration, three samples, the mean
//! absolute relative error of each of `c1, c2, c3, L` at most 0.5 % over 10 trials wherever the
//! force scale `c2/L²` is 60 mN or more (softer wires are reported), for wires
//! drawn at random from `c2 ∈ [0.03, 0.5]` N·m², `c1/c2 ∈ [0.6, 0.9]`, `c3 = c2`,
//! `L ∈ [0.4, 1.2]` m.
//!
//! A survey (ignored: about 15 s a wire in release, after one calibration):
//! `cargo test -p ftwire --release --test identify_unseen -- --ignored --nocapture`.
//! `FTWIRE_UNSEEN_SEED` and `FTWIRE_UNSEEN_WIRES` pick the draw (defaults 7 and 8);
//! `FTWIRE_UNSEEN_REST` sets `--rest-samples` (default the experiment's);
//! `FTWIRE_UNSEEN_GRAVITY=on` runs it with gravity on (the loaded model, its calibration
//! labelled with the loaded model, the issue-16 target of 0.5 % on `c` and `L`).
//! `FTWIRE_UNSEEN_ARGS` adds options to every `experiment identify` (space-separated).
//! `FTWIRE_UNSEEN_UNTIL=PCT` also samples each trial until `--until PCT` (up to
//! `FTWIRE_UNSEEN_LIMIT` samples, default 10) and prints how many samples each wire needed. Every run prints the coverage of the 95 %
//! intervals at three samples over all the wires' trials.

mod cli_support;

use std::fs;
use std::path::PathBuf;

use cli_support::{assert_success, ftwire, numbers};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Young's modulus of nitinol-like wire \[Pa\]: the radius follows from `c2 = E π r⁴ / 4`.
const YOUNG: f64 = 70e9;
/// Nitinol's density \[kg/m³\].
const DENSITY: f64 = 6450.0;

fn env_or(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

#[test]
#[ignore = "survey: about 2 minutes in release"]
fn unseen_wires_identify_within_half_a_percent_from_three_samples() {
    let seed = env_or("FTWIRE_UNSEEN_SEED", 7);
    let count = env_or("FTWIRE_UNSEEN_WIRES", 8);
    let gravity = match std::env::var("FTWIRE_UNSEEN_GRAVITY").as_deref() {
        Ok("on") => "on",
        _ => "off",
    };
    let rest = std::env::var("FTWIRE_UNSEEN_REST").ok();
    let until = std::env::var("FTWIRE_UNSEEN_UNTIL").ok();
    let samples = match until {
        Some(_) => format!("3,{}", env_or("FTWIRE_UNSEEN_LIMIT", 10)),
        None => "3".to_owned(),
    };
    let extra = std::env::var("FTWIRE_UNSEEN_ARGS").unwrap_or_default();
    let dir = std::env::temp_dir().join(format!("ftwire-unseen-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("creates a temporary folder");

    let calibration = dir.join("calibrate");
    let output = ftwire(&[
        "experiment",
        "calibrate",
        "--gravity",
        gravity,
        "--seed",
        &seed.to_string(),
        "--out",
        calibration.to_str().expect("UTF-8"),
    ]);
    assert_success(&output, "the calibration run");
    let weights = calibration.join("calibration.json");

    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut worst = [0.0_f64; 4];
    let mut covered = [0.0_f64; 4];
    let mut until_failures = Vec::new();
    let mut failures = Vec::new();
    for k in 0..count {
        let c2: f64 = (rng.random_range(0.03_f64.ln()..0.5_f64.ln())).exp();
        let ratio: f64 = rng.random_range(0.6..0.9);
        let length: f64 = rng.random_range(0.4..1.2);
        let radius = (4.0 * c2 / (std::f64::consts::PI * YOUNG)).powf(0.25);
        let name = format!("unseen-{k}");
        let file: PathBuf = dir.join(format!("{name}.toml"));
        fs::write(
            &file,
            format!(
                "name = \"{name}\"\nc = [{}, {c2}, {c2}]\nlength = {length}\nradius = {radius}\n\
                 density = {DENSITY}\n",
                ratio * c2
            ),
        )
        .expect("writes the wire file");
        let out = dir.join(&name);
        let seed_text = seed.to_string();
        let mut args = vec![
            "experiment",
            "identify",
            "--gravity",
            gravity,
            "--samples",
            samples.as_str(),
            "--seed",
            &seed_text,
            "--wire",
            file.to_str().expect("UTF-8"),
            "--calibration",
            weights.to_str().expect("UTF-8"),
            "--out",
            out.to_str().expect("UTF-8"),
        ];
        if let Some(rest) = &rest {
            args.extend(["--rest-samples", rest.as_str()]);
        }
        if let Some(until) = &until {
            args.extend(["--until", until.as_str()]);
        }
        args.extend(extra.split_whitespace());
        let output = ftwire(&args);
        assert_success(&output, &name);
        let summary: serde_json::Value =
            serde_json::from_str(&fs::read_to_string(out.join("summary.json")).expect("summary"))
                .expect("JSON");
        let row = &summary["summary"]["by_samples"][0];
        let errors = numbers(&row["mean_abs_relative_error"]);
        println!(
            "gravity {gravity}, {name}: c = ({:.4}, {c2:.4}, {c2:.4}) N·m², L = {length:.3} m, r = {:.2} mm: \
             mean |error| c1 c2 c3 L = {:.3} {:.3} {:.3} {:.3} %, identified {}/{}, coverage {}",
            ratio * c2,
            1e3 * radius,
            100.0 * errors[0],
            100.0 * errors[1],
            100.0 * errors[2],
            100.0 * errors[3],
            row["identified"],
            row["estimated"],
            row["coverage95"],
        );
        for (w, e) in worst.iter_mut().zip(&errors) {
            *w = w.max(*e);
        }
        for (c, share) in covered.iter_mut().zip(numbers(&row["coverage95"])) {
            *c += share / count as f64;
        }
        if until.is_some() {
            let u = &summary["summary"]["until"];
            let largest = numbers(&u["max_abs_relative_error"]);
            println!(
                "  --until: reached {}/{}, samples median {} max {}, largest |error| c1 c2 c3 L = \
                 {:.3} {:.3} {:.3} {:.3} %, coverage {}",
                u["reached"],
                u["trials"],
                u["samples_median"],
                u["samples_max"],
                100.0 * largest[0],
                100.0 * largest[1],
                100.0 * largest[2],
                100.0 * largest[3],
                u["coverage95"],
            );
            if u["reached"] != u["trials"] || largest.iter().any(|e| *e > 0.005) {
                until_failures.push(name.clone());
            }
        }
        // The target at three samples holds where the force scale `c2/L²` is 60 mN or more.
        if c2 / (length * length) >= 0.06 && errors.iter().any(|e| *e > 0.005) {
            failures.push(name);
        }
    }
    println!(
        "worst mean |error| over {count} wires: c1 c2 c3 L = {:.3} {:.3} {:.3} {:.3} %",
        100.0 * worst[0],
        100.0 * worst[1],
        100.0 * worst[2],
        100.0 * worst[3]
    );
    println!(
        "coverage of the 95 % intervals at three samples over every trial: c1 c2 c3 L = \
         {:.3} {:.3} {:.3} {:.3}",
        covered[0], covered[1], covered[2], covered[3]
    );
    if until.is_some() {
        println!("--until not reached or above 0.5 % on: {until_failures:?}");
    }
    let _ = fs::remove_dir_all(&dir);
    assert!(
        failures.is_empty(),
        "above 0.5 % on some parameter: {failures:?}"
    );
}
