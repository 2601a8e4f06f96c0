//! Tests of the robot execution-error model.

use approx::assert_abs_diff_eq;
use ftwire_core::{Command, Pose};
use ftwire_sim::{ExecutionErrorModel, ExecutionErrorParams, SensingError};
use nalgebra::{Translation3, UnitQuaternion, Vector3};

fn model(config: ExecutionErrorParams, seed: u64) -> ExecutionErrorModel {
    match ExecutionErrorModel::new(config, seed) {
        Ok(m) => m,
        Err(e) => panic!("valid configuration rejected: {e}"),
    }
}

fn actual(m: &mut ExecutionErrorModel, pose: &Pose) -> Pose {
    match m.actual_pose(pose) {
        Ok(p) => p,
        Err(e) => panic!("unexpected error: {e}"),
    }
}

fn commanded() -> Pose {
    Pose::from_parts(
        Translation3::new(0.4, -0.1, 0.9),
        UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -1.2, 0.7)),
    )
}

fn std(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt()
}

#[test]
fn the_default_configuration_executes_exactly() {
    let mut m = model(ExecutionErrorParams::default(), 1);
    for _ in 0..100 {
        assert_eq!(actual(&mut m, &commanded()), commanded());
    }
    let command = Command {
        base: Pose::identity(),
        tip: commanded(),
    };
    match m.actual_poses(&command) {
        Ok(poses) => {
            assert_eq!(poses.base, command.base);
            assert_eq!(poses.tip, command.tip);
        }
        Err(e) => panic!("unexpected error: {e}"),
    }
}

#[test]
fn paper_errors_have_10_mm_and_3_degree_spread_in_the_gripper_frame() {
    let config = ExecutionErrorParams::paper();
    let mut m = model(config, 2);
    let p = commanded();
    let n = 20_000;
    let mut position = [Vec::new(), Vec::new(), Vec::new()];
    let mut rotation = [Vec::new(), Vec::new(), Vec::new()];
    let mut angle_sq = 0.0;
    for _ in 0..n {
        let error = p.inverse() * actual(&mut m, &p);
        let omega = error.rotation.scaled_axis();
        for i in 0..3 {
            position[i].push(error.translation.vector[i]);
            rotation[i].push(omega[i]);
        }
        angle_sq += error.rotation.angle().powi(2);
    }
    for i in 0..3 {
        let s = std(&position[i]);
        assert!((s / 0.010 - 1.0).abs() < 0.03, "position axis {i}: σ = {s}");
        let s = std(&rotation[i]);
        assert!(
            (s / 3f64.to_radians() - 1.0).abs() < 0.03,
            "rotation axis {i}: σ = {} deg",
            s.to_degrees()
        );
    }
    // The angle of an isotropic normal rotation vector has RMS √3 σ.
    let rms = (angle_sq / n as f64).sqrt();
    assert_abs_diff_eq!(rms / (3f64.sqrt() * 3f64.to_radians()), 1.0, epsilon = 0.03);
}

#[test]
fn base_and_tip_get_independent_errors() {
    let mut m = model(ExecutionErrorParams::paper(), 3);
    let command = Command {
        base: commanded(),
        tip: commanded(),
    };
    match m.actual_poses(&command) {
        Ok(poses) => {
            let gap = (poses.base.translation.vector - poses.tip.translation.vector).norm();
            assert!(gap > 1e-6, "base and tip share their error");
        }
        Err(e) => panic!("unexpected error: {e}"),
    }
}

#[test]
fn the_same_seed_gives_the_same_poses_and_another_seed_does_not() {
    let run = |seed| {
        let mut m = model(ExecutionErrorParams::paper(), seed);
        (0..100)
            .map(|_| actual(&mut m, &commanded()))
            .collect::<Vec<_>>()
    };
    assert_eq!(run(4), run(4));
    assert_ne!(run(4), run(5));
}

#[test]
fn bad_inputs_give_clear_errors() {
    for (config, field) in [
        (
            ExecutionErrorParams {
                position_std: -0.01,
                ..ExecutionErrorParams::paper()
            },
            "position_std",
        ),
        (
            ExecutionErrorParams {
                orientation_std: f64::NAN,
                ..ExecutionErrorParams::paper()
            },
            "orientation_std",
        ),
    ] {
        match ExecutionErrorModel::new(config, 0) {
            Err(SensingError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
            other => panic!("expected an error naming {field}, got {other:?}"),
        }
    }
    let mut m = model(ExecutionErrorParams::paper(), 6);
    let bad = Pose::translation(0.0, f64::NAN, 0.0);
    assert!(matches!(m.actual_pose(&bad), Err(SensingError::Core(_))));
    let command = Command {
        base: Pose::identity(),
        tip: bad,
    };
    assert!(m.actual_poses(&command).is_err());
}

#[test]
fn errors_are_applied_in_the_gripper_frame() {
    // Orientation error only: the gripper turns about its own origin, which stays put.
    let rotation_only = ExecutionErrorParams {
        position_std: 0.0,
        ..ExecutionErrorParams::paper()
    };
    let mut m = model(rotation_only, 7);
    let p = commanded();
    let a = actual(&mut m, &p);
    assert_abs_diff_eq!(a.translation.vector, p.translation.vector, epsilon = 1e-15);
    assert!(a.rotation.angle_to(&p.rotation) > 1e-6);

    // Position error only: the same draw, commanded with another orientation, is the same
    // gripper-frame offset, rotated with the gripper.
    let position_only = ExecutionErrorParams {
        orientation_std: 0.0,
        ..ExecutionErrorParams::paper()
    };
    let at_identity = actual(&mut model(position_only, 8), &Pose::identity());
    let turned = actual(&mut model(position_only, 8), &p);
    let offset = turned.translation.vector - p.translation.vector;
    assert_abs_diff_eq!(
        offset,
        p.rotation * at_identity.translation.vector,
        epsilon = 1e-15
    );
    assert!(at_identity.translation.vector.norm() > 1e-6);
}
