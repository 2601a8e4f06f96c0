//! Property tests: arbitrary inputs give results or errors, never panics, and the ground-truth
//! inverse undoes the deterministic sensor response.

use ftwire_core::{Pose, Wrench};
use ftwire_sim::{
    ExecutionErrorModel, ExecutionErrorParams, FtSensor, FtSensorParams, MarkerParams,
    MotionCapture,
};
use nalgebra::{Point3, Quaternion, Translation3, UnitQuaternion, Vector3, Vector6};
use proptest::prelude::*;

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -1e3..1e3,
        1 => -1e308..1e308,
        1 => proptest::num::f64::ANY,
    ]
}

proptest! {
    #[test]
    fn sensor_reads_never_panic(values in prop::array::uniform6(any_f64()), time in any_f64()) {
        let Ok(mut sensor) = FtSensor::new(FtSensorParams::default(), 1) else {
            return Err(TestCaseError::fail("default configuration rejected"));
        };
        let w = Wrench::from_vector(&Vector6::from(values));
        if let Ok(reading) = sensor.read(&w, time) {
            prop_assert!(reading.raw.iter().all(|v| v.is_finite()));
            prop_assert!(reading.time.is_finite());
        }
        let _ = sensor.invert_deterministic(&Vector6::from(values), &Vector6::zeros());
    }

    #[test]
    fn the_inverse_undoes_the_deterministic_response(
        torque in prop::array::uniform3(-8.0..8.0),
        force in prop::array::uniform3(-300.0..300.0),
        bias in prop::array::uniform6(-1.0..1.0),
    ) {
        let Ok(sensor) = FtSensor::new(FtSensorParams::default(), 2) else {
            return Err(TestCaseError::fail("default configuration rejected"));
        };
        let w = Wrench::new(Vector3::from(torque), Vector3::from(force));
        let bias = Vector6::from(bias);
        let raw = sensor.deterministic_response(&w) + bias;
        let back = sensor.invert_deterministic(&raw, &bias);
        prop_assert!(back.is_ok());
        if let Ok(back) = back {
            let error = (back.to_vector() - w.to_vector()).amax();
            prop_assert!(error <= 1e-12 * w.to_vector().amax().max(1.0), "error {}", error);
        }
    }

    #[test]
    fn marker_observation_never_panics(
        points in prop::collection::vec(prop::array::uniform3(any_f64()), 0..6),
        arc_lengths in prop::collection::vec(any_f64(), 0..6),
        length in any_f64(),
        time in any_f64(),
    ) {
        let Ok(mut mocap) = MotionCapture::new(MarkerParams::default(), 3) else {
            return Err(TestCaseError::fail("default configuration rejected"));
        };
        let nodes: Vec<Point3<f64>> = points.iter().map(|&p| Point3::from(p)).collect();
        if let Ok(frame) = mocap.observe(time, &nodes, &arc_lengths, length) {
            prop_assert_eq!(frame.positions.len(), 11);
        }
        let _ = mocap.observe_uniform(time, &nodes, length);
    }

    #[test]
    fn execution_error_never_panics(
        translation in prop::array::uniform3(any_f64()),
        quaternion in prop::array::uniform4(any_f64()),
    ) {
        let Ok(mut model) = ExecutionErrorModel::new(ExecutionErrorParams::paper(), 4) else {
            return Err(TestCaseError::fail("paper configuration rejected"));
        };
        let [w, i, j, k] = quaternion;
        let pose = Pose::from_parts(
            Translation3::from(Vector3::from(translation)),
            UnitQuaternion::new_unchecked(Quaternion::new(w, i, j, k)),
        );
        let _ = model.actual_pose(&pose);
    }
}

#[test]
fn overflowing_wrenches_give_errors_or_finite_readings() {
    for config in [
        FtSensorParams::default(),
        FtSensorParams {
            saturation: false,
            ..FtSensorParams::default()
        },
    ] {
        overflow(config);
    }
}

fn overflow(config: FtSensorParams) {
    let Ok(mut sensor) = FtSensor::new(config, 5) else {
        panic!("configuration rejected");
    };
    let big = f64::MAX;
    let mut time = 0.0;
    for force in [[big, -big, big], [big, big, 0.0], [-big, 0.0, big]] {
        for torque in [[0.0; 3], [big, -big, big]] {
            time += 0.01;
            let w = Wrench::new(Vector3::from(torque), Vector3::from(force));
            if let Ok(reading) = sensor.read(&w, time) {
                assert!(
                    reading.raw.iter().all(|v| v.is_finite()),
                    "{:?}",
                    reading.raw
                );
            }
        }
    }
}
