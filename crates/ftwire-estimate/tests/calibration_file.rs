//! The calibration weights file: a bit-identical round trip, and clear errors for malformed
//! files.

use ftwire_estimate::EstimateError;
use ftwire_estimate::calibration::{Activation, Calibration, Dataset, Drift, TrainParams};
use nalgebra::Vector6;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn trained(residual: bool) -> Calibration {
    trained_with(residual, true)
}

fn trained_with(residual: bool, anchored: bool) -> Calibration {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let labels: Vec<Vector6<f64>> = (0..80)
        .map(|_| Vector6::from_fn(|_, _| rng.random_range(-1.0..=1.0)))
        .collect();
    let raw = labels
        .iter()
        .map(|a| a.map(|x| 2.0 * x + 0.1 * x.powi(3)))
        .collect();
    let data = Dataset::new(raw, labels).expect("finite");
    let config = TrainParams {
        hidden: vec![5, 3],
        activation: Activation::Gelu,
        residual,
        anchored,
        max_epochs: 20,
        ..TrainParams::default()
    };
    Calibration::train(&data, &config, 8).expect("trains")
}

#[test]
fn round_trip_is_bit_identical() {
    for residual in [true, false] {
        let calibration = trained(residual);
        let json = calibration.to_json().expect("serialises");
        let loaded = Calibration::from_json(&json).expect("loads");
        assert_eq!(loaded, calibration);
        let raw = Vector6::new(0.3, -0.2, 0.1, 0.5, -0.7, 0.05);
        assert_eq!(loaded.apply(&raw), calibration.apply(&raw));
        assert_eq!(loaded.to_json().expect("serialises"), json);
    }
}

#[test]
fn save_and_load_through_a_file() {
    let calibration = trained(true);
    let path = std::env::temp_dir().join(format!("ftwire-calibration-{}.json", std::process::id()));
    calibration.save(&path).expect("writes");
    let loaded = Calibration::load(&path);
    let _ = std::fs::remove_file(&path);
    assert_eq!(loaded.expect("reads"), calibration);
    let missing = Calibration::load(std::path::Path::new("/nonexistent/calibration.json"));
    assert!(matches!(
        missing,
        Err(EstimateError::CalibrationIo {
            kind: std::io::ErrorKind::NotFound,
            ..
        })
    ));
}

#[test]
fn a_file_with_a_bom_loads_and_invalid_utf8_is_located() {
    let calibration = trained(false);
    let json = calibration.to_json().expect("serialises");
    let dir = std::env::temp_dir().join(format!("ftwire-calibration-bom-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let with_bom = dir.join("bom.json");
    std::fs::write(
        &with_bom,
        [b"\xEF\xBB\xBF".as_slice(), json.as_bytes()].concat(),
    )
    .expect("writes");
    let loaded = Calibration::load(&with_bom);
    // A key "é" in Latin-1 (the single byte 0xE9, not UTF-8's two) opening line 2.
    let latin1 = dir.join("latin1.json");
    let rest = json.strip_prefix('{').expect("a JSON object");
    std::fs::write(
        &latin1,
        [b"{\n\"\xE9\": 1,".as_slice(), rest.as_bytes()].concat(),
    )
    .expect("writes");
    let bad = Calibration::load(&latin1);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(loaded.expect("a BOM is allowed"), calibration);
    match bad {
        Err(EstimateError::CalibrationSyntax {
            line: 2,
            column: 2,
            message,
        }) => assert!(message.contains("0xE9"), "{message}"),
        other => panic!("expected a syntax error on line 2, column 2, got {other:?}"),
    }
}

#[test]
fn an_anchored_map_reads_zero_at_zero_and_older_files_stay_unanchored() {
    let calibration = trained(true);
    assert!(
        !TrainParams::default().anchored,
        "readings may carry a bias by default"
    );
    let zero = Vector6::zeros();
    let free = trained_with(true, false);
    assert_eq!(free.anchor(), &zero);
    assert_eq!(
        calibration.apply(&zero),
        zero,
        "a tared zero reading is a = 0"
    );
    assert!(
        calibration.anchor().norm() > 0.0,
        "the trained map's intercept is not zero by itself, so the test can fail"
    );
    let raw = Vector6::new(0.3, -0.2, 0.1, 0.5, -0.7, 0.05);
    // A file written before the setting existed has no `anchored` key: it reads unanchored,
    // the map it was saved as.
    let mut value: serde_json::Value =
        serde_json::from_str(&calibration.to_json().expect("serialises")).expect("valid JSON");
    value["training"]["config"]
        .as_object_mut()
        .expect("the training configuration is an object")
        .remove("anchored")
        .expect("the key is written");
    let legacy = Calibration::from_json(&value.to_string()).expect("loads");
    assert!(!legacy.record().config.anchored);
    assert_eq!(legacy.anchor(), &zero);
    let unanchored = calibration.apply(&raw) + calibration.anchor();
    assert!((legacy.apply(&raw) - unanchored).norm() < 1e-12);
}

/// Edits the saved JSON and loads it.
fn load_edited(edit: impl FnOnce(&mut serde_json::Value)) -> Result<Calibration, EstimateError> {
    let json = trained(true).to_json().expect("serialises");
    let mut value: serde_json::Value = serde_json::from_str(&json).expect("valid JSON");
    edit(&mut value);
    Calibration::from_json(&value.to_string())
}

#[test]
fn malformed_files_are_rejected_with_the_reason() {
    assert!(matches!(
        Calibration::from_json("{ not json"),
        Err(EstimateError::CalibrationSyntax { line: 1, .. })
    ));
    assert!(matches!(
        load_edited(|v| v["version"] = 2.into()),
        Err(EstimateError::CalibrationVersion {
            found: 2,
            supported: 1
        })
    ));
    assert!(matches!(
        load_edited(|v| v["format"] = "something-else".into()),
        Err(EstimateError::CalibrationSyntax { .. })
    ));
    assert!(matches!(
        load_edited(|v| v["layers"][1]["weights"][2] = serde_json::json!([1.0, 2.0])),
        Err(EstimateError::CalibrationShape { ref what, expected: 5, found: 2 })
            if what == "layers[1].weights[2]"
    ));
    assert!(matches!(
        load_edited(|v| v["layers"][2]["bias"] = serde_json::json!([0.0])),
        Err(EstimateError::CalibrationShape { ref what, expected: 6, found: 1 })
            if what == "layers[2].bias"
    ));
    assert!(matches!(
        load_edited(|v| v["architecture"]["hidden"] = serde_json::json!([5])),
        Err(EstimateError::CalibrationShape { ref what, expected: 2, found: 3 }) if what == "layers"
    ));
    assert!(matches!(
        load_edited(|v| v["input_normaliser"]["std"][4] = 0.0.into()),
        Err(EstimateError::CalibrationValue { ref what, index: 4, .. })
            if what == "input_normaliser.std"
    ));
    // A huge number is named in exponent notation, not in 309 digits.
    let huge = load_edited(|v| v["layers"][2]["bias"][1] = 1e308.into());
    assert!(
        matches!(&huge, Err(EstimateError::CalibrationValue { what, index: 1, .. }) if what == "layers[2].bias"),
        "{huge:?}"
    );
    let message = huge.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(message.contains("[1] = 1e308 is invalid"), "{message}");
    assert!(matches!(
        load_edited(|v| v["layers"][0]["weights"][1][3] = serde_json::Value::Null),
        Err(EstimateError::CalibrationSyntax { .. })
    ));
    assert!(matches!(
        load_edited(|v| v["architecture"]["extra"] = 1.into()),
        Err(EstimateError::CalibrationSyntax { .. })
    ));
    // A number too large for f64 is rejected, not read as infinity.
    let json = trained(true).to_json().expect("serialises");
    let mut value: serde_json::Value = serde_json::from_str(&json).expect("valid JSON");
    value["affine"]["offset"][0] = 12345.5.into();
    let overflow = value.to_string().replace("12345.5", "1e999");
    assert!(Calibration::from_json(&overflow).is_err());
}

#[test]
fn a_drift_term_round_trips_and_moves_the_map_with_time() {
    let drift = Drift {
        reference_time: 100.0,
        rate: Vector6::new(1e-4, 0.0, -2e-4, 0.0, 3e-3, 0.0),
        span: Some([0.0, 120.0]),
    };
    let calibration = trained(true).with_drift(drift).expect("finite");
    let json = calibration.to_json().expect("serialises");
    let loaded = Calibration::from_json(&json).expect("loads");
    assert_eq!(loaded, calibration);
    let raw = Vector6::new(0.3, -0.2, 0.1, 0.5, -0.7, 0.05);
    assert_eq!(loaded.apply_at(&raw, 100.0), loaded.apply(&raw));
    let later = loaded.apply_at(&raw, 110.0) - loaded.apply(&raw);
    assert!((later - drift.rate * 10.0).norm() < 1e-15);
    // Never extrapolated beyond its session: held at the span's ends, so that a clock an hour
    // or fifty years later (Unix time) gives the same `a`, near the session's.
    let end = loaded.apply_at(&raw, 120.0);
    for time in [120.0 + 3600.0, 1.7e9] {
        assert_eq!(loaded.apply_at(&raw, time), end, "{time}");
    }
    assert_eq!(loaded.apply_at(&raw, -1e9), loaded.apply_at(&raw, 0.0));
    // A file without the span (an older one) leaves the drift out.
    let unspanned = trained(true)
        .with_drift(Drift {
            span: None,
            ..drift
        })
        .expect("finite");
    assert_eq!(unspanned.apply_at(&raw, 110.0), unspanned.apply(&raw));
    let backwards = Drift {
        span: Some([10.0, 0.0]),
        ..drift
    };
    assert!(trained(true).with_drift(backwards).is_err());
    // A map without a drift term ignores the time, and its file has no `drift` key.
    let plain = trained(true);
    assert_eq!(plain.apply_at(&raw, 1e4), plain.apply(&raw));
    assert!(!plain.to_json().expect("serialises").contains("\"drift\""));
    let bad = load_edited(|v| {
        v["drift"] = serde_json::json!({"reference_time": 0.0, "rate": [0, 0, 0, 0, 0, "x"]})
    });
    assert!(bad.is_err());
    assert!(
        trained(true)
            .with_drift(Drift {
                reference_time: f64::NAN,
                ..drift
            })
            .is_err()
    );
}

/// `model` and `input` round-trip; a file without them (an older one) is weightless and raw;
/// a loaded model without a gravity, or a weightless one with one, is refused naming the key.
#[test]
fn the_label_model_and_the_input_round_trip_and_default_to_weightless_raw() {
    use ftwire_estimate::calibration::{CalibrationInput, LabelModel};
    let plain = trained(true);
    assert_eq!(*plain.model(), LabelModel::WEIGHTLESS);
    assert_eq!(plain.input(), CalibrationInput::Raw);
    let loaded_model = LabelModel::loaded([0.0, -9.81, 0.0]).expect("valid");
    let calibration = trained(true)
        .with_provenance(loaded_model, CalibrationInput::Tared)
        .expect("valid");
    let json = calibration.to_json().expect("serialises");
    let value: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    assert_eq!(
        value["model"],
        serde_json::json!({"kind": "loaded", "gravity_in_clamp": [0.0, -9.81, 0.0]})
    );
    assert_eq!(value["input"], "tared");
    let back = Calibration::from_json(&json).expect("loads");
    assert_eq!(back, calibration);
    let old = load_edited(|v| {
        let o = v.as_object_mut().expect("an object");
        o.remove("model");
        o.remove("input");
    })
    .expect("an older file loads");
    assert_eq!(*old.model(), LabelModel::WEIGHTLESS);
    assert_eq!(old.input(), CalibrationInput::Raw);
    for model in [
        serde_json::json!({"kind": "loaded", "gravity_in_clamp": null}),
        serde_json::json!({"kind": "weightless", "gravity_in_clamp": [0, 0, -9.81]}),
        serde_json::json!({"kind": "loaded", "gravity_in_clamp": [0, 0, 1e300]}),
    ] {
        let error = load_edited(|v| v["model"] = model.clone()).expect_err("refused");
        assert!(
            error.to_string().contains("model.gravity_in_clamp"),
            "{model}: {error}"
        );
    }
    assert!(load_edited(|v| v["input"] = "cooked".into()).is_err());
}

/// A file whose numbers load but whose every answer would overflow (an affine weight, a
/// layer weight or a drift rate of 1e308, a std of 1e-300, a test error wider than any
/// reading) is refused at load naming the key.
#[test]
fn damaged_numbers_are_refused_at_load_naming_the_key() {
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let cases: [(&str, Edit); 6] = [
        (
            "affine.matrix[0]",
            Box::new(|v| v["affine"]["matrix"][0][0] = 1e308.into()),
        ),
        (
            "layers[0].weights[0]",
            Box::new(|v| v["layers"][0]["weights"][0][0] = 1e300.into()),
        ),
        (
            "input_normaliser.std",
            Box::new(|v| v["input_normaliser"]["std"][2] = 1e-300.into()),
        ),
        (
            "drift.rate",
            Box::new(|v| {
                v["drift"] = serde_json::json!({
                    "reference_time": 0.0, "rate": [0, 0, 1e308, 0, 0, 0], "span": [0.0, 1.0]
                })
            }),
        ),
        // The test error is every shape's error bar: wider than any reading, or negative,
        // it would give error bars of NaN.
        (
            "training.test_rmse",
            Box::new(|v| v["training"]["test_rmse"] = serde_json::json!([1e308, 0, 0, 0, 0, 0])),
        ),
        (
            "training.test_rmse",
            Box::new(|v| v["training"]["test_rmse"] = serde_json::json!([0, 0, 0, 0, -0.1, 0])),
        ),
    ];
    for (key, edit) in cases {
        let error = load_edited(|v| edit(v)).expect_err(key);
        assert!(error.to_string().contains(key), "{key}: {error}");
    }
}
