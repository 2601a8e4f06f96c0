//! The simulated rig: what the `Rig` trait reports against the ground truth.

use ftwire_core::{Command, CoreError, GripperPoses, Pose, Rig};
use ftwire_sim::{
    ExecutionErrorParams, FtSensorParams, RigParams, RodParams, SensingError, SimError, SimRig,
    World,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

fn pose(x: f64, y: f64, z: f64, yaw: f64) -> Pose {
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw),
    )
}

fn start() -> GripperPoses {
    GripperPoses {
        base: Pose::identity(),
        tip: pose(0.5, 0.12, 0.0, 0.4),
    }
}

fn world() -> World {
    World::new(RodParams::nitinol_2mm_630().with_edges(40)).expect("valid preset")
}

fn rig(config: RigParams) -> SimRig {
    SimRig::new(world(), start(), config).expect("the start pose has an equilibrium")
}

#[test]
fn ideal_sensor_reports_the_true_base_wrench_force_first_on_clock_ticks() {
    let mut rig = rig(RigParams::ideal());
    let truth = rig.equilibrium().base_wrench;
    let period = 1.0 / rig.config().sensor.rate;
    let mut last = f64::NEG_INFINITY;
    for _ in 0..5 {
        let sample = rig.read_ft().expect("ideal sensor never drops out");
        let expected = [
            truth.force.x,
            truth.force.y,
            truth.force.z,
            truth.torque.x,
            truth.torque.y,
            truth.torque.z,
        ];
        for (got, want) in sample.raw.iter().zip(expected) {
            assert!((got - want).abs() < 1e-12, "raw {got} vs true {want}");
        }
        assert!((sample.time - rig.time()).abs() < 1e-15);
        assert!(sample.time > last, "samples must move forward in time");
        assert!(last.is_infinite() || sample.time - last <= period * (1.0 + 1e-9));
        last = sample.time;
    }
    // A bent wire pushes on the gripper: the wrench is not trivially zero.
    assert!(truth.torque.norm() > 1e-3);
}

#[test]
fn a_clipped_channel_is_flagged_in_the_rig_sample_and_a_normal_one_is_not() {
    // An ideal sensor: nothing clips.
    let mut rig = rig(RigParams::ideal());
    let normal = rig.read_ft().expect("ideal sensor never drops out");
    assert_eq!(normal.saturated, [false; 6]);
    assert!(!normal.is_saturated());

    // The same wire with channel 5 (τ3) given a full scale of half its load: only it clips.
    let load = normal.raw[5];
    assert!(load.abs() > 1e-3, "the bent wire loads τ3");
    let mut full_scale = [1e3; 6];
    full_scale[5] = 0.5 * load.abs();
    let config = RigParams {
        sensor: FtSensorParams {
            full_scale,
            saturation: true,
            ..FtSensorParams::ideal()
        },
        ..RigParams::ideal()
    };
    let mut rig = SimRig::new(world(), start(), config).expect("valid settings");
    let clipped = rig.read_ft().expect("ideal sensor never drops out");
    assert_eq!(clipped.saturated, [false, false, false, false, false, true]);
    assert!(clipped.is_saturated());
    assert!((clipped.raw[5] - full_scale[5].copysign(load)).abs() < 1e-15);
    assert!((clipped.raw[0] - normal.raw[0]).abs() < 1e-15);
}

#[test]
fn command_moves_the_wire_and_the_robot_reports_the_command() {
    let mut rig = rig(RigParams::ideal());
    let before = rig.equilibrium().base_wrench;
    let t0 = rig.time();
    let target = Command {
        base: Pose::identity(),
        tip: pose(0.45, 0.15, 0.02, 0.6),
    };
    rig.command(&target)
        .expect("a small move has an equilibrium");
    let believed = rig.gripper_poses().expect("poses");
    assert_eq!(believed.tip, target.tip);
    // No execution error: the wire's tip clamp is exactly where it was sent.
    let actual = rig.actual_poses();
    assert!((actual.tip.translation.vector - target.tip.translation.vector).norm() < 1e-12);
    assert!((rig.equilibrium().base_wrench.torque - before.torque).norm() > 1e-4);
    // 5 cm or so at 5 cm/s plus settling: the clock moved by about a second.
    assert!(
        rig.time() - t0 > 0.5 && rig.time() - t0 < 3.0,
        "{}",
        rig.time() - t0
    );
}

#[test]
fn execution_error_moves_the_wire_elsewhere_than_the_robot_believes() {
    let config = RigParams {
        execution: ExecutionErrorParams::paper(),
        seed: 7,
        ..RigParams::ideal()
    };
    let mut rig = rig(config);
    let target = Command {
        base: Pose::identity(),
        tip: pose(0.47, 0.14, 0.0, 0.5),
    };
    rig.command(&target).expect("move");
    let believed = rig.gripper_poses().expect("poses");
    let actual = rig.actual_poses();
    assert_eq!(believed.tip, target.tip);
    let miss = (actual.tip.translation.vector - believed.tip.translation.vector).norm()
        + (actual.base.translation.vector - believed.base.translation.vector).norm();
    assert!(
        miss > 1e-4,
        "10 mm execution error left the grippers {miss} m off"
    );
    assert!(miss < 0.15, "{miss}");
}

#[test]
fn same_seed_same_run_other_seed_other_run() {
    let run = |seed| {
        let mut rig = rig(RigParams {
            execution: ExecutionErrorParams::paper(),
            seed,
            ..RigParams::default()
        });
        let mut out = Vec::new();
        for _ in 0..3 {
            match rig.read_ft() {
                Ok(sample) => out.extend(sample.raw.iter().copied()),
                Err(_) => out.push(f64::MAX),
            }
        }
        rig.command(&Command {
            base: Pose::identity(),
            tip: pose(0.48, 0.13, 0.0, 0.45),
        })
        .expect("move");
        out.extend(rig.actual_poses().tip.translation.vector.iter().copied());
        out
    };
    assert_eq!(run(3), run(3));
    assert_ne!(run(3), run(4));
}

#[test]
fn a_dropout_is_an_error_that_consumes_the_tick_and_keeps_the_state() {
    let config = RigParams {
        sensor: FtSensorParams {
            dropout_probability: 1.0 - f64::EPSILON,
            ..FtSensorParams::ideal()
        },
        ..RigParams::ideal()
    };
    let mut rig = rig(config);
    let before = rig.equilibrium().clone();
    let mut ticks = Vec::new();
    for _ in 0..2 {
        match rig.read_ft() {
            Err(SimError::Sensing(SensingError::Dropout { time })) => {
                assert!((time - rig.time()).abs() < 1e-15);
                ticks.push(time);
            }
            other => panic!("expected a dropout, got {other:?}"),
        }
    }
    assert!(ticks[1] > ticks[0], "a dropped tick is consumed: {ticks:?}");
    assert_eq!(rig.equilibrium(), &before);
}

#[test]
fn bad_commands_are_refused_and_nothing_moves() {
    let mut rig = rig(RigParams::ideal());
    let before = rig.equilibrium().clone();
    let believed = rig.gripper_poses().expect("poses");

    let nan = Command {
        base: Pose::identity(),
        tip: pose(f64::NAN, 0.0, 0.0, 0.0),
    };
    assert!(matches!(
        rig.command(&nan),
        Err(SimError::Core(CoreError::NonFinite { .. }))
    ));

    let too_far = Command {
        base: Pose::identity(),
        tip: pose(0.9, 0.0, 0.0, 0.0),
    };
    assert!(matches!(
        rig.command(&too_far),
        Err(SimError::GrippersTooFarApart { .. })
    ));
    assert_eq!(rig.equilibrium(), &before);
    assert_eq!(rig.gripper_poses().expect("poses"), believed);
}

#[test]
fn bad_rig_settings_are_named() {
    for (config, field) in [
        (
            RigParams {
                linear_speed: 0.0,
                ..RigParams::ideal()
            },
            "linear_speed",
        ),
        (
            RigParams {
                angular_speed: f64::NAN,
                ..RigParams::ideal()
            },
            "angular_speed",
        ),
        (
            RigParams {
                settle_time: -1.0,
                ..RigParams::ideal()
            },
            "settle_time",
        ),
        // Times and speeds that would run the sensor's clock beyond its exact range.
        (
            RigParams {
                settle_time: 1e300,
                ..RigParams::ideal()
            },
            "settle_time",
        ),
        (
            RigParams {
                linear_speed: 1e-300,
                ..RigParams::ideal()
            },
            "linear_speed",
        ),
        (
            RigParams {
                angular_speed: 1e300,
                ..RigParams::ideal()
            },
            "angular_speed",
        ),
    ] {
        match SimRig::new(world(), start(), config) {
            Err(SimError::RigSetting { field: f, .. }) => assert_eq!(f, field),
            other => panic!("expected a RigSetting error for {field}, got {other:?}"),
        }
    }
}

#[test]
fn ideal_markers_sit_on_the_wire_from_base_to_tip() {
    let mut rig = rig(RigParams::ideal());
    let frame = rig.observe_markers().expect("markers");
    assert_eq!(frame.positions.len(), 11);
    let first = frame.positions[0].expect("no dropouts in the ideal config");
    let last = frame.positions[10].expect("no dropouts in the ideal config");
    let tip = rig.actual_poses().tip.translation.vector;
    assert!(
        first.coords.norm() < 1e-9,
        "first marker at the base clamp: {first}"
    );
    assert!(
        (last.coords - tip).norm() < 1e-9,
        "last marker at the tip clamp: {last}"
    );
    // Interior markers lie on the simulated centreline (within the chord sagitta of an edge).
    let centreline = rig.equilibrium().centreline();
    for marker in frame.positions.iter().flatten() {
        let nearest = centreline
            .iter()
            .map(|p| (p - marker).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 0.63 / 39.0,
            "marker {marker} is {nearest} m from every node"
        );
    }
}

#[test]
fn the_empty_gripper_reads_only_the_sensor_offset_and_keeps_the_wire() {
    let mut config = RigParams::default();
    config.sensor.dropout_probability = 0.0;
    let mut rig = rig(config);
    let equilibrium = rig.equilibrium().clone();
    let n = 400;
    let mut mean = nalgebra::Vector6::zeros();
    let mut last = f64::NEG_INFINITY;
    for _ in 0..n {
        let sample = rig.read_ft_empty_gripper().expect("no dropouts configured");
        assert!(sample.time > last, "each read takes the next clock tick");
        last = sample.time;
        mean += sample.raw / n as f64;
    }
    // The average is the offset (the drift over 0.4 s is far below the noise): within 4
    // standard errors of the default noise, 0.05 N and 0.002 N·m.
    let bias = rig.sensor().bias();
    let sigma = [0.05, 0.05, 0.05, 0.002, 0.002, 0.002];
    for i in 0..6 {
        let bound = 4.0 * sigma[i] / (n as f64).sqrt();
        assert!(
            (mean[i] - bias[i]).abs() < bound,
            "channel {i}: {} vs {}",
            mean[i],
            bias[i]
        );
    }
    // Reading the empty gripper leaves the wire's equilibrium alone.
    assert_eq!(rig.equilibrium(), &equilibrium);
    assert!((rig.time() - last).abs() < 1e-12);
}

/// Markers glued off the centreline sit at their offset from where ideal markers sit, across
/// the cross-section of the simulated wire, and keep that offset in the wire's material frame
/// when the wire bends and twists anew: rolling the tip turns the inner markers' offsets.
#[test]
fn mounted_markers_turn_with_the_simulated_wire() {
    let mounted = RigParams {
        markers: ftwire_sim::MarkerParams {
            mount_offset: 0.002,
            mount_seed: 4,
            ..ftwire_sim::MarkerParams::ideal()
        },
        ..RigParams::ideal()
    };
    let (mut ideal, mut glued) = (rig(RigParams::ideal()), rig(mounted.clone()));
    let offsets = ftwire_sim::MotionCapture::new(mounted.markers, 0)
        .expect("valid markers")
        .mount_offsets()
        .to_vec();
    let roll = Command {
        base: Pose::identity(),
        tip: start().tip * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 1.2),
    };
    let mut before = Vec::new();
    for step in 0..2 {
        let on_line = ideal.observe_markers().expect("markers");
        let centres = glued.observe_markers().expect("markers");
        let nodes = glued.equilibrium().centreline();
        let h = 0.63 / 39.0;
        let mut moved = Vec::new();
        for (i, ((p, c), o)) in on_line
            .positions
            .iter()
            .zip(&centres.positions)
            .zip(&offsets)
            .enumerate()
        {
            let (Some(p), Some(c)) = (p, c) else {
                panic!("no dropouts in the ideal configuration")
            };
            let d = c - p;
            assert!(
                (d.norm() - o.norm()).abs() < 1e-12,
                "marker {i}: {d} for {o}"
            );
            // Across the wire: normal to the edge the marker sits on, up to the turn of the
            // material frame over half an edge.
            let k = ((i as f64 * 0.063 / h + 0.5).floor() as usize).min(nodes.len() - 2);
            let t = (nodes[k + 1] - nodes[k]).normalize();
            assert!(
                d.dot(&t).abs() < 0.1 * o.norm(),
                "marker {i}: {}",
                d.dot(&t)
            );
            moved.push(d);
        }
        if step == 0 {
            before = moved;
            ideal.command(&roll).expect("the roll has an equilibrium");
            glued.command(&roll).expect("the roll has an equilibrium");
        } else {
            let turned = (1..10)
                .map(|i| before[i].angle(&moved[i]))
                .fold(0.0, f64::max);
            assert!(
                turned > 0.3,
                "the inner offsets turned by at most {turned} rad"
            );
        }
    }
}
