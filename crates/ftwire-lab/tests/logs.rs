//! A rig's log as the lab reads it back: the logs the experiments save (`save_log`) replayed
//! through [`ftwire_lab::log`] give the live runs' answers: the identification's estimate
//! for the same samples and seed, and a shape for every record.

use ftwire_lab::experiment::{CommonParams, Gravity};
use ftwire_lab::identify::ResidualParams;
use ftwire_lab::log::identify::{self, IdentifyLogParams};
use ftwire_lab::log::shape::{DEFAULT_POINTS, LogShapes, ShapeLogParams};
use ftwire_rig::ShapeRecord;

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
        // The simulated rig's pose noise, which the experiment models.
        residual: ResidualParams {
            pose_noise: Some(ftwire_lab::experiment::rig::SIM_POSE_NOISE),
            ..ResidualParams::default()
        },
        gravity: None,
        seed: 3,
        drift: None,
        front_end: Default::default(),
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
    let mut params = ShapeLogParams::new(log, "nitinol-2mm-630");
    let error = LogShapes::new(&params)
        .err()
        .expect("raw needs a calibration");
    assert_eq!(error.kind(), "bad_input");
    params.calibration = Some(weights);
    let shapes: Vec<ShapeRecord> = LogShapes::new(&params)
        .and_then(Iterator::collect)
        .expect("every record shaped");
    assert_eq!(shapes.len(), run.summary.wires[0].configs);
    for (i, shape) in shapes.iter().enumerate() {
        assert!(
            i == 0 || shape.line > shapes[i - 1].line,
            "in the log's order"
        );
        assert!(shape.error.is_none(), "{:?}", shape.error);
        assert_eq!(shape.points.len(), DEFAULT_POINTS);
        // The markers see the true wire; the estimate is within centimetres of it.
        let mm = shape.marker_mean_mm.expect("the log has markers");
        assert!(mm.is_finite() && mm < 50.0, "{mm}");
        // The calibration's test error gives the raw records their error bars.
        let sigma = shape.sigma.as_ref().expect("the calibration's test error");
        assert_eq!(sigma.len(), DEFAULT_POINTS);
        assert!(sigma.iter().all(|s| s.is_finite() && *s >= 0.0));
        assert!(sigma[DEFAULT_POINTS - 1] > 0.0);
    }
}

/// A rig's log of a long identification motion (30 rests, about 95 s) of a soft wire: the log
/// command with the sensor's data sheet (`--sensor`) models the bias the records share and
/// identifies the wire from the log as the live run does; without it, the drift goes into the
/// wire.
#[test]
fn a_long_log_of_a_soft_wire_is_identified_with_the_sensor_s_drift_modelled() {
    let dir = TempDir::new("log-identify-drift");
    let wire = dir.0.join("soft.toml");
    std::fs::write(
        &wire,
        "name = \"soft\"\nc = [0.0315, 0.042, 0.042]\nlength = 0.91\nradius = 0.001\n\
         density = 6450.0\n",
    )
    .expect("the wire file");
    let folder = dir.results("identify");
    let settings = ftwire_lab::identify::IdentifyParams {
        common: CommonParams {
            wire: Some(wire.display().to_string()),
            seed: 2,
            trials: Some(3),
            gravity: Gravity::Off,
            sensor: Some("undistorted".to_owned()),
            ..CommonParams::default()
        },
        samples: Some(vec![30]),
        pipeline: ftwire_lab::identify::Pipeline::Mounting,
        save_log: true,
        ..ftwire_lab::identify::IdentifyParams::default()
    };
    ftwire_lab::identify::run(&settings, &folder, &mut |_| {}).expect("runs");
    let sensor = ftwire_lab::setup::SensorSpec::load("undistorted").expect("a preset");
    let truth = [0.0315, 0.042, 0.042, 0.91];
    let (mut modelled, mut independent) = (0.0, 0.0);
    for trial in 0..3 {
        let log = folder
            .dir()
            .join("logs")
            .join(format!("soft-trial{trial}.jsonl"));
        let mut params = IdentifyLogParams {
            log,
            calibration: None,
            mounting: None,
            samples: None,
            residual: ResidualParams::default(),
            gravity: None,
            seed: 2,
            drift: None,
            front_end: Default::default(),
        };
        let samples = identify::samples(&params).expect("the saved log reads");
        assert_eq!(samples.len(), 30);
        let error = |params: &IdentifyLogParams| {
            let report = identify::estimate(params, &samples, &mut |_| {}).expect("estimates");
            let values = [report.c[0], report.c[1], report.c[2], report.length];
            let errors = values.iter().zip(truth).map(|(v, t)| (v / t - 1.0).abs());
            (report.reason.is_none(), errors.collect::<Vec<f64>>())
        };
        let (_, without) = error(&params);
        params.drift = Some(identify::LogDrift {
            sensor: "undistorted".to_owned(),
            params: ftwire_lab::setup::sensor::data_sheet(&sensor.config),
            rest_samples: ftwire_lab::identify::REST_SAMPLES,
            tare_samples: ftwire_lab::experiment::rig::TARE_SAMPLES,
            tare_time: None,
        });
        let (identified, with) = error(&params);
        assert!(identified, "trial {trial}: {with:?}");
        for e in &with {
            assert!(*e < 0.005, "trial {trial}: {with:?}");
        }
        modelled += with.iter().sum::<f64>();
        independent += without.iter().sum::<f64>();
    }
    assert!(
        modelled < independent,
        "{modelled} with the drift, {independent} without"
    );
}
