//! A rig's log as the lab reads it back: the logs the experiments save (`save_log`) replayed
//! through [`ftwire_lab::log`] give the live runs' answers: the identification's estimate
//! for the same samples and seed, and a shape for every record.

use ftwire_lab::experiment::{CommonParams, Gravity};
use ftwire_lab::identify::ResidualParams;
use ftwire_lab::log::identify::{self, IdentifyLogParams};
use ftwire_lab::log::shape::{LogShapes, RecordShape, ShapeLogParams};

mod common;

use common::TempDir;

#[test]
fn a_saved_identification_log_gives_the_live_estimate() {
    let dir = TempDir::new("log-identify");
    let folder = dir.results("identify");
    let settings = ftwire_lab::identify::IdentifyParams {
        common: CommonParams {
            wire: Some("nitinol-2mm-630".to_owned()),
            seed: 3,
            trials: Some(1),
            gravity: Gravity::Off,
            ..CommonParams::default()
        },
        samples: Some(vec![5]),
        pipeline: ftwire_lab::identify::Pipeline::Mounting,
        save_log: true,
        // The log command has no sensor data sheet: it treats the samples' errors as
        // independent, so the live run does too.
        bias_model: false,
        ..ftwire_lab::identify::IdentifyParams::default()
    };
    let run = ftwire_lab::identify::run(&settings, &folder, &mut |_| {}).expect("runs");
    let live = &run.summary.by_samples[0];
    assert_eq!((live.samples, live.estimated), (5, 1));

    let params = IdentifyLogParams {
        log: folder
            .dir()
            .join("logs")
            .join("nitinol-2mm-630-trial0.jsonl"),
        calibration: None,
        mounting: None,
        samples: None,
        residual: ResidualParams::default(),
        gravity: None,
        seed: 3,
    };
    params.check().expect("good settings");
    let samples = identify::samples(&params).expect("the saved log reads");
    assert_eq!(samples.len(), 5, "one record per sample");
    let mut steps = 0;
    let report = identify::estimate(&params, &samples, &mut |_| steps += 1).expect("estimates");
    assert_eq!(report.samples, 5);
    let replayed = [report.c[0], report.c[1], report.c[2], report.length];
    for (name, (l, r)) in ["c1", "c2", "c3", "L"]
        .iter()
        .zip(live.mean.iter().zip(replayed))
    {
        // The log holds the pose as a rotation vector: a rounding-level change.
        assert!((l - r).abs() <= 1e-6 * l.abs(), "{name}: live {l}, log {r}");
    }
    let json = serde_json::to_value(&report).expect("serialises");
    assert_eq!(json["form"], "absolute");
    assert!(json.get("linear_density").is_none(), "weightless: no λ");
    assert!(
        report
            .to_string()
            .starts_with("identified from 5 samples (Absolute residual):")
    );
}

#[test]
fn a_saved_shape_log_gives_a_shape_for_every_record() {
    let dir = TempDir::new("log-shape");
    let (_calibration, weights) = dir.calibration();
    let folder = dir.results("shape");
    let settings = ftwire_lab::shape::ShapeParams {
        common: CommonParams {
            wire: Some("nitinol-2mm-630".to_owned()),
            seed: 3,
            gravity: Gravity::Off,
            ..CommonParams::default()
        },
        configs: Some(2),
        calibration: Some(weights.clone()),
        save_log: true,
        ..ftwire_lab::shape::ShapeParams::default()
    };
    let run = ftwire_lab::shape::run(&settings, &folder, &mut |_| {}).expect("runs");
    let log = folder.dir().join("logs").join("nitinol-2mm-630.jsonl");

    // The log holds raw readings: without the calibration they are refused.
    let mut params = ShapeLogParams {
        log,
        wire: "nitinol-2mm-630".to_owned(),
        calibration: None,
        mounting: None,
        a_std: None,
    };
    let error = LogShapes::new(&params)
        .err()
        .expect("raw needs a calibration");
    assert_eq!(error.kind(), "bad_input");
    params.calibration = Some(weights);
    let shapes: Vec<RecordShape> = LogShapes::new(&params)
        .and_then(Iterator::collect)
        .expect("every record shaped");
    assert_eq!(shapes.len(), run.summary.wires[0].configs);
    for (i, shape) in shapes.iter().enumerate() {
        assert_eq!(shape.record, i);
        assert!(shape.error.is_none(), "{:?}", shape.error);
        assert_eq!(shape.points.as_ref().map(Vec::len), Some(64));
        assert!(shape.confidence.is_some());
        // The markers see the true wire; the estimate is within centimetres of it.
        let mm = shape.marker_mean_mm.expect("the log has markers");
        assert!(mm.is_finite() && mm < 50.0, "{mm}");
        // The calibration's test error gives the raw records their error bars.
        let sigma = shape
            .sigma_mm
            .as_ref()
            .expect("the calibration's test error");
        assert_eq!(sigma.len(), 64);
        assert!(sigma.iter().all(|s| s.is_finite() && *s >= 0.0));
        assert!(sigma[63] > 0.0);
    }
}
