//! `SimRig` after a failed call: a refused command or a failed Newton solve changes nothing.
//!
//! The believed poses, the actual poses, the clock, the equilibrium (and the execution error's
//! random stream) must all be as they were before the call. The comparisons are exact on
//! purpose: nothing is recomputed, so the state after the failure is the very state before it.

mod common;

use common::pose;
use ftwire_core::{Command, GripperPoses, Pose, Rig};
use ftwire_sim::{
    ContinuationParams, Equilibrium, ExecutionErrorParams, NewtonParams, RigParams, RodParams,
    SimError, SimRig, Simulator, World,
};

fn start() -> GripperPoses {
    GripperPoses {
        base: Pose::identity(),
        tip: pose([0.5, 0.12, 0.0], [0.0, 0.0, 0.4]),
    }
}

fn params() -> RodParams {
    RodParams::nitinol_2mm_630().with_edges(30)
}

/// Everything a failed call must leave alone.
#[derive(Debug, PartialEq)]
struct Snapshot {
    believed: GripperPoses,
    actual: GripperPoses,
    time: f64,
    equilibrium: Equilibrium,
    snaps: usize,
}

fn snapshot(rig: &SimRig) -> Snapshot {
    Snapshot {
        believed: rig
            .gripper_poses()
            .expect("the sim rig always knows its poses"),
        actual: rig.actual_poses(),
        time: rig.time(),
        equilibrium: rig.equilibrium().clone(),
        snaps: rig.simulator().snaps().len(),
    }
}

/// A rig with execution error, so that a command draws from the execution model's stream.
fn rig_with_execution_error() -> SimRig {
    let config = RigParams {
        execution: ExecutionErrorParams::paper(),
        ..RigParams::ideal()
    };
    let world = World::new(params()).expect("valid preset");
    SimRig::new(world, start(), config).expect("the start pose has an equilibrium")
}

#[test]
fn refused_commands_change_nothing_and_draw_no_execution_error() {
    let mut rig = rig_with_execution_error();
    // Advance the clock first, so that "unchanged" is not "zero".
    rig.read_ft().expect("the ideal sensor never drops out");
    let before = snapshot(&rig);
    let refused = [
        Command {
            base: Pose::identity(),
            tip: pose([f64::NAN, 0.0, 0.0], [0.0; 3]),
        },
        Command {
            base: pose([0.0, 0.0, f64::INFINITY], [0.0; 3]),
            tip: start().tip,
        },
        // The tip 0.9 m from the base: the 0.63 m wire cannot reach (with the execution error
        // of at most centimetres, still too far).
        Command {
            base: Pose::identity(),
            tip: pose([0.9, 0.0, 0.0], [0.0; 3]),
        },
    ];
    for command in &refused {
        assert!(rig.command(command).is_err(), "{command:?} was accepted");
        assert_eq!(snapshot(&rig), before, "{command:?} changed the rig");
    }
    assert!(matches!(
        rig.command(&refused[2]),
        Err(SimError::GrippersTooFarApart { .. })
    ));

    // The refused commands drew no execution error: a good command now lands exactly where it
    // lands on a twin rig that never saw them.
    let mut twin = rig_with_execution_error();
    twin.read_ft().expect("the ideal sensor never drops out");
    let good = Command {
        base: Pose::identity(),
        tip: pose([0.48, 0.14, 0.01], [0.0, 0.0, 0.45]),
    };
    rig.command(&good).expect("a small move succeeds");
    twin.command(&good).expect("a small move succeeds");
    assert_eq!(rig.actual_poses(), twin.actual_poses());
    assert!((rig.time() - twin.time()).abs() < 1e-15);
    assert_eq!(rig.gripper_poses().expect("poses"), good_poses(&good));
    assert!(rig.time() > before.time);
}

fn good_poses(command: &Command) -> GripperPoses {
    GripperPoses {
        base: command.base,
        tip: command.tip,
    }
}

#[test]
fn a_failed_newton_solve_changes_nothing() {
    // The equilibrium at the start pose, then a world whose Newton cannot follow any real move:
    // one iteration per step, to a tolerance no step meets in one, and no step halving.
    let world = World::new(params()).expect("valid preset");
    let start = start();
    let equilibrium = world
        .solve_cold(&start.base, &start.tip)
        .expect("the start pose has an equilibrium")
        .equilibrium;
    let strict = world
        .with_newton(NewtonParams {
            max_iterations: 1,
            tolerance: 1e-12,
            ..NewtonParams::default()
        })
        .with_continuation(ContinuationParams {
            max_subdivisions: 0,
            ..ContinuationParams::default()
        });
    let sim = Simulator::from_equilibrium(strict, equilibrium);
    let mut rig = SimRig::from_simulator(sim, RigParams::ideal()).expect("ideal settings");
    rig.read_ft().expect("the ideal sensor never drops out");
    let before = snapshot(&rig);

    // A move of two continuation steps: the first step already fails.
    let command = Command {
        base: Pose::identity(),
        tip: pose([0.45, 0.2, 0.0], [0.0, 0.0, 0.7]),
    };
    assert!(matches!(
        rig.command(&command),
        Err(SimError::NewtonFailed { .. })
    ));
    assert_eq!(snapshot(&rig), before);

    // The rig still works: the next sample reports the unchanged wrench, one tick later.
    let sample = rig.read_ft().expect("the ideal sensor never drops out");
    let truth = before.equilibrium.base_wrench;
    assert!((sample.raw[0] - truth.force.x).abs() < 1e-15);
    assert!((sample.raw[5] - truth.torque.z).abs() < 1e-15);
    assert!(sample.time > before.time);
}
