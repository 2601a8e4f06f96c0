//! Shape estimation from `ã` at sensor rate: the shape is the model's, the confidence flag
//! catches unstable configurations and jumps, bad input is named.

use ftwire_core::{CoreError, WireParams};
use ftwire_estimate::shape::{Confidence, EstimatorParams, ShapeEstimator};
use ftwire_estimate::{EstimateError, KirchhoffModel, WireModel};
use ftwire_rod::{RodError, from_normalised};
use nalgebra::Vector6;

fn model() -> Result<KirchhoffModel, EstimateError> {
    Ok(KirchhoffModel::new(WireParams::new(
        [0.042, 0.055, 0.055],
        0.63,
        0.001,
    )?))
}

#[test]
fn the_estimate_is_the_model_shape() -> Result<(), EstimateError> {
    let model = model()?;
    let mut estimator = ShapeEstimator::new(model);
    let a = from_normalised(model.wire(), &Vector6::new(0.5, 2.0, -1.0, -3.0, 1.5, 0.5));
    let estimate = estimator.estimate(&a)?;
    assert_eq!(estimate.confidence, Confidence::Confident);
    let shape = model.shape(&a, 64)?;
    assert_eq!(estimate.shape.len(), 64);
    for (p, q) in estimate.shape.positions.iter().zip(&shape.positions) {
        assert!((p - q).norm() < 1e-12);
    }
    Ok(())
}

#[test]
fn unstable_configurations_are_flagged() -> Result<(), EstimateError> {
    let model = model()?;
    let mut estimator = ShapeEstimator::new(model);
    // Compressed beyond the clamped–clamped Euler load 4π² c2 / L² (≈ 39.5 normalised).
    let buckled = from_normalised(model.wire(), &Vector6::new(0.0, 0.0, 1e-3, -50.0, 0.0, 0.0));
    assert_eq!(
        estimator.estimate(&buckled)?.confidence,
        Confidence::NotStable
    );
    Ok(())
}

#[test]
fn jumps_are_flagged_once_and_reset_forgets() -> Result<(), EstimateError> {
    let model = model()?;
    let config = EstimatorParams {
        jump_threshold: 1.0,
        ..EstimatorParams::default()
    };
    let mut estimator = ShapeEstimator::new(model).with_config(config)?;
    let z = Vector6::new(0.5, 2.0, -1.0, -3.0, 1.5, 0.5);
    let a = |z: Vector6<f64>| from_normalised(model.wire(), &z);
    assert!(estimator.estimate(&a(z))?.confidence.is_confident());
    // A slow drift, 0.5 normalised units per sample: confident.
    let drift = Vector6::new(0.0, 0.3, 0.0, 0.4, 0.0, 0.0);
    assert!(estimator.estimate(&a(z + drift))?.confidence.is_confident());
    // A sudden step of 2 normalised units: a jump, measured in normalised units.
    let step = Vector6::new(0.0, 0.0, 2.0, 0.0, 0.0, 0.0);
    match estimator.estimate(&a(z + drift + step))?.confidence {
        Confidence::Jump { change, threshold } => {
            assert!((change - 2.0).abs() < 1e-9, "{change}");
            assert!((threshold - 1.0).abs() < 1e-15);
        }
        other => panic!("expected a jump, got {other:?}"),
    }
    // The new level is the reference now: the next sample is confident again.
    assert!(
        estimator
            .estimate(&a(z + drift + step))?
            .confidence
            .is_confident()
    );
    // After reset, even a large change is not a jump.
    estimator.reset();
    assert!(estimator.estimate(&a(z))?.confidence.is_confident());
    Ok(())
}

#[test]
fn bad_input_is_named_and_leaves_the_state() -> Result<(), EstimateError> {
    let model = model()?;
    let mut estimator = ShapeEstimator::new(model).with_config(EstimatorParams {
        jump_threshold: 1.0,
        ..EstimatorParams::default()
    })?;
    let z = Vector6::new(0.5, 2.0, -1.0, -3.0, 1.5, 0.5);
    let a = from_normalised(model.wire(), &z);
    estimator.estimate(&a)?;
    let mut bad = a;
    bad[4] = f64::NAN;
    assert!(matches!(
        estimator.estimate(&bad),
        Err(EstimateError::Core(CoreError::NonFinite { field: "a_tilde", index: 4, value }))
            if value.is_nan()
    ));
    let outside = Vector6::new(0.1, 0.0, 0.0, -0.2, 0.0, 0.0);
    assert!(matches!(
        estimator.estimate(&outside),
        Err(EstimateError::Model(RodError::OutsideA { .. }))
    ));
    // The errors did not replace the reference sample: a is still confident.
    assert!(estimator.estimate(&a)?.confidence.is_confident());
    for nodes in [49, 2_000_000] {
        let config = EstimatorParams {
            nodes,
            ..EstimatorParams::default()
        };
        assert!(matches!(
            ShapeEstimator::new(model).with_config(config),
            Err(EstimateError::BadShapeSetting { name: "nodes", .. })
        ));
    }
    let config = EstimatorParams {
        jump_threshold: f64::INFINITY,
        ..EstimatorParams::default()
    };
    assert!(matches!(
        ShapeEstimator::new(model).with_config(config),
        Err(EstimateError::BadShapeSetting {
            name: "jump_threshold",
            ..
        })
    ));
    Ok(())
}

/// Solving samples apart (in parallel, say) and flagging them in order gives `estimate`'s
/// flags, with a failed solve skipped as `estimate` skips it.
#[test]
fn flagging_solved_samples_is_estimating_them() -> Result<(), EstimateError> {
    let model = model()?;
    let config = EstimatorParams {
        jump_threshold: 1.0,
        ..EstimatorParams::default()
    };
    let z = Vector6::new(0.5, 2.0, -1.0, -3.0, 1.5, 0.5);
    let a = |z: Vector6<f64>| from_normalised(model.wire(), &z);
    let samples = [
        a(z),
        a(z + Vector6::new(0.0, 0.3, 0.0, 0.4, 0.0, 0.0)),
        Vector6::new(0.1, 0.0, 0.0, -0.2, 0.0, 0.0), // outside A: no solve
        a(z + Vector6::new(0.0, 0.0, 2.0, 0.0, 0.0, 0.0)),
        a(Vector6::new(0.0, 0.0, 1e-3, -50.0, 0.0, 0.0)), // buckled
        a(z),
    ];
    let mut estimating = ShapeEstimator::new(model).with_config(config)?;
    let mut flagging = ShapeEstimator::new(model).with_config(config)?;
    for sample in &samples {
        let estimated = estimating.estimate(sample).map(|e| e.confidence);
        let flagged = model
            .is_stable(sample)
            .map(|stable| flagging.flag_solved(sample, stable));
        match (estimated, flagged) {
            (Ok(e), Ok(f)) => assert_eq!(e, f),
            (Err(_), Err(_)) => {}
            other => panic!("{sample:?}: {other:?}"),
        }
    }
    Ok(())
}
