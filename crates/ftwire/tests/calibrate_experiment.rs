//! `ftwire experiment calibrate` (paper §IV-A): the learnt calibration against the simulator's
//! exact inverse (`FtSensor::invert_deterministic`, which only tests may use), and the
//! experiment's summary and weights file.

mod cli_support;

use cli_support::{assert_success, ftwire};
use ftwire_lab::experiment::calibration::run;
use ftwire_lab::experiment::{Gravity, ModelKind};
use ftwire_lab::wire::WireSpec;
use ftwire_sim::{FtSensor, RigParams};
use nalgebra::Vector6;

/// Mean relative error of the torque and force parts of `a` against `truth`.
fn relative(pairs: &[(Vector6<f64>, Vector6<f64>)]) -> (f64, f64) {
    let n = pairs.len() as f64;
    let part = |a: &Vector6<f64>, t: &Vector6<f64>, i: usize| {
        (a.fixed_rows::<3>(i) - t.fixed_rows::<3>(i)).norm() / t.fixed_rows::<3>(i).norm()
    };
    let torque = pairs.iter().map(|(a, t)| part(a, t, 0)).sum::<f64>() / n;
    let force = pairs.iter().map(|(a, t)| part(a, t, 3)).sum::<f64>() / n;
    (torque, force)
}

#[test]
fn the_learnt_calibration_comes_close_to_the_exact_inverse()
-> Result<(), Box<dyn std::error::Error>> {
    let wire = WireSpec::preset("nitinol-3mm-820").ok_or("preset")?;
    let result = run(
        &wire,
        (Gravity::Off, ModelKind::Weightless),
        &ftwire_lab::setup::SimSetup::default(),
        120,
        5,
        |_| {},
    )?;
    // The exact inverse of the sensor's deterministic response; the tare removed the bias.
    let sensor = FtSensor::new(RigParams::default().sensor, 0)?;
    let mut learnt = Vec::new();
    let mut exact = Vec::new();
    let mut mounting = Vec::new();
    for &i in &result.split.test {
        let s = &result.samples[i];
        let inverse = sensor.invert_deterministic(&s.raw, &Vector6::zeros())?;
        learnt.push((result.calibration.apply(&s.raw), s.true_wrench));
        exact.push((inverse.to_vector(), s.true_wrench));
        mounting.push((s.mounting, s.true_wrench));
    }
    let (learnt_t, learnt_f) = relative(&learnt);
    let (exact_t, exact_f) = relative(&exact);
    let (mount_t, mount_f) = relative(&mounting);
    eprintln!(
        "test split ({}): torque/force relative error: learnt {learnt_t:.5}/{learnt_f:.5}, \
         exact inverse {exact_t:.5}/{exact_f:.5}, mounting only {mount_t:.5}/{mount_f:.5}",
        result.split.test.len()
    );
    // The exact inverse leaves only the noise of the average and the tare's error.
    assert!(exact_t < 0.002 && exact_f < 0.005, "{exact_t} {exact_f}");
    // The learnt map, trained on shape-fit labels, is within a few times that, and far better
    // than the mounting alone (which leaves the gain and cross-talk, about 2 %).
    assert!(
        learnt_t < exact_t + 0.004,
        "torque: learnt {learnt_t}, exact {exact_t}"
    );
    assert!(
        learnt_f < exact_f + 0.006,
        "force: learnt {learnt_f}, exact {exact_f}"
    );
    assert!(learnt_t < 0.5 * mount_t && learnt_f < 0.5 * mount_f);
    // The summary says the same.
    let s = &result.summary;
    assert!(s.calibrated.torque_rel < 0.5 * s.raw.torque_rel);
    assert!(s.calibrated.shape_mm < s.raw.shape_mm);
    assert!(
        s.label_fit_mm > 0.2 && s.label_fit_mm < 1.0,
        "{}",
        s.label_fit_mm
    );
    Ok(())
}

#[test]
fn the_experiment_writes_its_summary_and_weights_the_same_for_the_same_seed()
-> Result<(), Box<dyn std::error::Error>> {
    let tmp = std::env::temp_dir().join(format!("ftwire-calibrate-{}", std::process::id()));
    std::fs::create_dir_all(&tmp)?;
    let mut summaries = Vec::new();
    for run in ["a", "b"] {
        let out = tmp.join(run);
        let args = [
            "experiment",
            "calibrate",
            "--trials",
            "40",
            "--gravity",
            "off",
        ];
        let output = ftwire(&[&args[..], &["--out", out.to_str().ok_or("path")?]].concat());
        assert_success(&output, "experiment calibrate");
        let weights =
            ftwire_estimate::calibration::Calibration::load(&out.join("calibration.json"))?;
        assert_eq!(weights.record().samples.train, 28);
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json"))?)?;
        summaries.push(summary["summary"].clone());
        cli_support::assert_golden_summary("calibrate-40-gravity-off", &out);
    }
    // The header differs only by --out.
    assert_eq!(summaries[0], summaries[1], "same seed, same summary");
    let s = &summaries[0];
    for key in ["train", "validation", "test"] {
        assert!(s["samples"][key].as_u64().is_some(), "samples.{key}");
    }
    for map in ["raw", "calibrated"] {
        for key in ["torque_rel", "force_rel", "shape_mm"] {
            assert!(
                s[map][key].as_f64().is_some_and(f64::is_finite),
                "{map}.{key}"
            );
        }
    }
    assert!(s["label_fit_mm"].as_f64().is_some());
    std::fs::remove_dir_all(&tmp)?;
    Ok(())
}
