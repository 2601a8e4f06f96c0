//! Training: bad data and settings give errors naming what is wrong, the same seed gives
//! bit-identical weights, early stopping keeps the best weights, progress is reported.

use ftwire_estimate::EstimateError;
use ftwire_estimate::calibration::{
    Calibration, Dataset, SplitFractions, SplitOrder, StopReason, TrainParams,
};
use nalgebra::Vector6;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A small data set: `raw = M a + k a³` (componentwise) plus noise, force first.
fn data(n: usize, seed: u64) -> Dataset {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let labels: Vec<Vector6<f64>> = (0..n)
        .map(|_| Vector6::from_fn(|_, _| rng.random_range(-1.0..=1.0)))
        .collect();
    let raw = labels
        .iter()
        .map(|a| {
            let swapped = Vector6::new(a[3], a[4], a[5], a[0], a[1], a[2]);
            swapped
                + 0.1 * swapped.map(|x| x * x * x)
                + Vector6::from_fn(|_, _| 1e-3 * rng.random_range(-1.0..=1.0))
        })
        .collect();
    Dataset::new(raw, labels).expect("finite data")
}

fn small() -> TrainParams {
    TrainParams {
        hidden: vec![8, 8],
        max_epochs: 60,
        patience: 15,
        ..TrainParams::default()
    }
}

#[test]
fn non_finite_samples_are_named() {
    let mut raw = vec![Vector6::zeros(); 5];
    let mut labels = vec![Vector6::zeros(); 5];
    raw[3][4] = f64::NAN;
    let error = Dataset::new(raw.clone(), labels.clone()).expect_err("NaN");
    assert!(matches!(
        error,
        EstimateError::NonFiniteCalibrationSample {
            index: 3,
            field: "raw",
            component: 4,
            ..
        }
    ));
    assert!(error.to_string().contains("sample 3"), "{error}");
    raw[3][4] = 0.0;
    labels[2][0] = f64::INFINITY;
    assert!(matches!(
        Dataset::new(raw, labels),
        Err(EstimateError::NonFiniteCalibrationSample {
            index: 2,
            field: "label",
            component: 0,
            ..
        })
    ));
}

#[test]
fn unpaired_samples_are_rejected() {
    let error =
        Dataset::new(vec![Vector6::zeros(); 5], vec![Vector6::zeros(); 4]).expect_err("5 ≠ 4");
    assert_eq!(
        error,
        EstimateError::SampleCountMismatch {
            raw: 5,
            labels: 4,
            first_unpaired: 4
        }
    );
}

#[test]
fn too_few_samples_name_the_split() {
    let error = Calibration::train(&data(10, 1), &small(), 1).expect_err("7 training samples");
    assert!(matches!(
        error,
        EstimateError::TooFewCalibrationSamples {
            samples: 10,
            split: "training",
            got: 7,
            ..
        }
    ));
    let config = TrainParams {
        split: SplitFractions {
            train: 0.95,
            validation: 0.04,
            ..SplitFractions::default()
        },
        ..small()
    };
    let error = Calibration::train(&data(20, 1), &config, 1).expect_err("no validation");
    assert!(matches!(
        error,
        EstimateError::TooFewCalibrationSamples {
            split: "validation",
            got: 0,
            ..
        }
    ));
}

#[test]
fn bad_settings_are_rejected() {
    let d = data(40, 2);
    let cases = [
        TrainParams {
            batch_size: 0,
            ..small()
        },
        TrainParams {
            learning_rate: 0.0,
            ..small()
        },
        TrainParams {
            learning_rate: f64::NAN,
            ..small()
        },
        TrainParams {
            decay: 1.5,
            ..small()
        },
        TrainParams {
            patience: 0,
            ..small()
        },
        TrainParams {
            hidden: vec![8, 0],
            ..small()
        },
        TrainParams {
            hidden: vec![1000],
            ..small()
        },
        TrainParams {
            split: SplitFractions {
                train: 0.8,
                validation: 0.3,
                ..SplitFractions::default()
            },
            ..small()
        },
        TrainParams {
            split: SplitFractions {
                train: -0.1,
                validation: 0.3,
                ..SplitFractions::default()
            },
            ..small()
        },
    ];
    for config in cases {
        let result = Calibration::train(&d, &config, 3);
        assert!(
            matches!(result, Err(EstimateError::InvalidSetting { .. })),
            "{config:?}: {result:?}"
        );
    }
}

#[test]
fn same_seed_gives_bit_identical_weights() {
    let d = data(200, 4);
    let a = Calibration::train(&d, &small(), 17).expect("trains");
    let b = Calibration::train(&d, &small(), 17).expect("trains");
    let c = Calibration::train(&d, &small(), 18).expect("trains");
    assert_eq!(a.mlp().parameters(), b.mlp().parameters());
    assert_eq!(a, b);
    assert_ne!(a.mlp().parameters(), c.mlp().parameters());
}

#[test]
fn early_stopping_keeps_the_best_weights_and_reports_progress() {
    let d = data(200, 5);
    let config = TrainParams {
        patience: 5,
        plateau: 100,
        learning_rate: 0.05,
        max_epochs: 400,
        ..small()
    };
    let mut seen = Vec::new();
    let calibration =
        Calibration::train_with_progress(&d, &config, 9, |p| seen.push(*p)).expect("trains");
    let record = calibration.record();
    assert_eq!(seen.len(), record.epochs);
    assert_eq!(record.history.len(), record.epochs);
    assert!(seen.iter().enumerate().all(|(i, p)| p.epoch == i + 1));
    assert_eq!(record.stop, StopReason::Patience);
    assert_eq!(record.epochs, record.best_epoch + config.patience);
    let best = record
        .history
        .iter()
        .map(|e| e.validation)
        .fold(record.initial_validation_loss, f64::min);
    assert_eq!(record.validation_loss, best);
    if record.best_epoch > 0 {
        assert_eq!(record.history[record.best_epoch - 1].validation, best);
    }
    assert!(record.validation_loss < record.initial_validation_loss);
    assert!(record.test_loss.is_some());
    assert_eq!(
        record.samples.train + record.samples.validation + record.samples.test,
        200
    );
}

/// The residual calibration learns most of the cubic that the affine fit leaves.
#[test]
fn learns_a_nonlinear_sensor() {
    let d = data(400, 6);
    let config = TrainParams {
        hidden: vec![32, 32],
        learning_rate: 3e-3,
        max_epochs: 400,
        patience: 40,
        ..small()
    };
    let calibration = Calibration::train(&d, &config, 2).expect("trains");
    let record = calibration.record();
    assert!(
        record.validation_loss < 0.25 * record.initial_validation_loss,
        "validation loss {} from {}, epochs {} best {}",
        record.validation_loss,
        record.initial_validation_loss,
        record.epochs,
        record.best_epoch
    );
    // Held-out samples agree: the network learnt the sensor, not the training noise.
    let test_loss = record.test_loss.expect("test split");
    assert!(
        test_loss < 0.3 * record.initial_validation_loss,
        "test loss {test_loss}"
    );
}

#[test]
fn a_time_split_keeps_the_order_of_the_samples() -> Result<(), EstimateError> {
    let d = data(40, 4);
    let fractions = SplitFractions {
        order: SplitOrder::Time,
        ..SplitFractions::default()
    };
    let split = d.split(&fractions, &mut ChaCha8Rng::seed_from_u64(1))?;
    assert_eq!(split.train, (0..28).collect::<Vec<_>>());
    assert_eq!(split.validation, (28..34).collect::<Vec<_>>());
    assert_eq!(split.test, (34..40).collect::<Vec<_>>());
    // The random split of the same data is not in order.
    let random = d.split(
        &SplitFractions::default(),
        &mut ChaCha8Rng::seed_from_u64(1),
    )?;
    assert_ne!(random.train, split.train);
    Ok(())
}

/// A map trained `through_zero` is zero at a zero reading, exactly and after a save and load,
/// and still learns the sensor's nonlinear map (its gated network improves on the linear part).
#[test]
fn a_map_through_zero_is_zero_at_zero_and_survives_its_file() {
    let config = TrainParams {
        through_zero: true,
        hidden: vec![16, 16],
        learning_rate: 1e-2,
        max_epochs: 400,
        patience: 100,
        ..small()
    };
    let data = data(300, 4);
    let calibration = Calibration::train(&data, &config, 9).expect("trained");
    assert_eq!(calibration.apply(&Vector6::zeros()), Vector6::zeros());
    let back = Calibration::from_json(&calibration.to_json().expect("json")).expect("loads");
    assert!(back.record().config.through_zero);
    for raw in data.raw().iter().take(20) {
        assert_eq!(back.apply(raw), calibration.apply(raw));
    }
    let record = calibration.record();
    assert!(
        record.validation_loss < 0.5 * record.initial_validation_loss,
        "{} against the linear part's {}",
        record.validation_loss,
        record.initial_validation_loss
    );
}
