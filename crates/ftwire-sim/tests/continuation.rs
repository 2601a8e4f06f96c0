//! Warm starts, invariance under rigid motion, snaps on a buckling path, and bad inputs.

mod common;

use common::pose;
use ftwire_core::CoreError;
use ftwire_sim::{
    ContinuationParams, InitialGuess, NewtonParams, RodParams, SimError, Simulator, World,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::f64::consts::PI;

fn anisotropic() -> RodParams {
    RodParams {
        stiffness: [0.042, 0.055, 0.070],
        ..RodParams::nitinol_2mm_630()
    }
}

#[test]
fn moving_both_clamps_rigidly_leaves_the_base_wrench_unchanged_without_gravity() {
    let world = World::new(anisotropic().without_gravity()).expect("valid");
    let tip = pose([0.3, 0.2, -0.15], [0.4, 0.9, -0.6]);
    let a = world
        .solve_cold(&Isometry3::identity(), &tip)
        .expect("solves")
        .equilibrium;
    for g in [
        pose([1.0, -2.0, 0.5], [0.3, -1.1, 2.0]),
        pose([-0.2, 0.4, 3.0], [2.5, 0.1, 0.2]),
    ] {
        let b = world
            .solve_cold(&g, &(g * tip))
            .expect("solves")
            .equilibrium;
        let (wa, wb) = (a.base_wrench.to_vector(), b.base_wrench.to_vector());
        let diff = (wa - wb).norm() / wa.norm();
        println!("rigid motion: relative base-wrench difference {diff:e}");
        assert!(diff < 1e-6);
        let (ta, tb) = (a.tip_wrench.to_vector(), b.tip_wrench.to_vector());
        assert!((ta - tb).norm() < 1e-6 * ta.norm());
    }
}

#[test]
fn a_warm_started_move_lands_on_the_cold_solution_of_the_same_branch() {
    let world = World::new(RodParams::nitinol_2mm_630()).expect("valid");
    let tip0 = pose([0.4, 0.2, 0.05], [0.2, -0.3, 1.2]);
    let tip1 = pose([0.401, 0.2, 0.05], [0.2, -0.3, 1.2 + PI / 180.0]);
    let base = Isometry3::identity();
    let mut sim = Simulator::new(world.clone(), &base, &tip0).expect("solves");
    let motion = sim.move_grippers(&base, &tip1).expect("moves");
    assert_eq!(motion.steps, 1);
    assert!(motion.snaps.is_empty());
    let warm = sim.equilibrium().clone();
    let cold = world.solve_cold(&base, &tip1).expect("solves").equilibrium;
    let diff = (warm.base_wrench.to_vector() - cold.base_wrench.to_vector()).norm();
    println!(
        "warm vs cold: {diff:e}, warm iterations {}",
        warm.convergence.iterations
    );
    assert!(diff < 1e-6 * cold.base_wrench.to_vector().norm());
    assert!(warm.convergence.iterations <= 6);
}

#[test]
fn a_long_motion_is_split_into_steps_and_stays_on_its_branch() {
    let world = World::new(RodParams::nitinol_3mm_820()).expect("valid");
    let base = Isometry3::identity();
    let mut sim =
        Simulator::new(world, &base, &pose([0.7, 0.1, 0.0], [0.0, 0.0, 0.3])).expect("solves");
    let target = pose([0.3, 0.35, 0.1], [0.5, 0.2, 2.0]);
    let motion = sim.move_grippers(&base, &target).expect("moves");
    println!(
        "steps {} iterations {} snaps {}",
        motion.steps,
        motion.iterations,
        motion.snaps.len()
    );
    assert!(motion.steps > 5);
    let eq = sim.equilibrium();
    assert!(eq.stable_minimum);
    assert!((eq.state.tip().translation.vector - target.translation.vector).norm() < 1e-12);
}

/// A clamped–clamped arch buckled about its soft axis (bulging +z); turning the tip clamp about
/// its y axis pushes the arch through until the branch ends and it snaps to the other side.
#[test]
fn a_buckled_arch_snaps_through_when_its_tip_is_turned() {
    let params = anisotropic().without_gravity().with_edges(60);
    let l = params.length;
    let world = World::new(params).expect("valid");
    let rod = world.rod().clone();
    let shortening = 0.05 * l;
    let amp = 2.0 * (shortening * l).sqrt() / PI;
    let guess = InitialGuess::from_shape(&rod, |s| {
        let z = 0.5 * amp * (1.0 - (2.0 * PI * s / l).cos());
        let dz = amp * PI / l * (2.0 * PI * s / l).sin();
        Isometry3::from_parts(
            Translation3::new(s * (1.0 - shortening / l), 0.0, z),
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -dz.atan()),
        )
    });
    let base = Isometry3::identity();
    let tip0 = pose([l - shortening, 0.0, 0.0], [0.0, 0.0, 0.0]);
    let eq = world
        .solve_with_guess(&guess, &base, &tip0)
        .expect("solves");
    assert!(eq.stable_minimum);
    let bulge = |eq: &ftwire_sim::Equilibrium| {
        let c = eq.centreline();
        c[c.len() / 2].z
    };
    assert!(bulge(&eq) > 0.0);
    let mut sim = Simulator::from_equilibrium(world, eq);
    // Turn the tip so that the wire must arrive from below (tangent rising: rotation about −y).
    let turned = pose([l - shortening, 0.0, 0.0], [0.0, -1.5, 0.0]);
    let motion = sim.move_grippers(&base, &turned).expect("moves").clone();
    for s in &motion.snaps {
        println!(
            "snap at {:.4}: jump {:.4} m, energy {:.5} -> {:.5} J",
            s.progress, s.max_node_jump, s.energy_before, s.energy_after
        );
    }
    println!("mid-span height after: {}", bulge(sim.equilibrium()));
    assert_eq!(motion.snaps.len(), 1);
    let snap = &motion.snaps[0];
    assert!(snap.energy_after < snap.energy_before);
    assert!(snap.max_node_jump > 0.02 * l);
    assert!(bulge(sim.equilibrium()) < 0.0);
    assert!(sim.equilibrium().stable_minimum);
}

#[test]
fn bad_inputs_get_their_errors() {
    let bad_c = World::new(RodParams {
        stiffness: [0.04, 0.0, 0.05],
        ..RodParams::default()
    });
    assert!(matches!(
        bad_c,
        Err(SimError::Core(CoreError::NotPositive { field: "c2", .. }))
    ));
    // The message names the field and its value.
    let message = bad_c
        .map(|_| ())
        .expect_err("c2 = 0 is refused")
        .to_string();
    assert!(message.contains("c2 = 0"), "{message}");
    let bad_l = World::new(RodParams {
        length: -0.1,
        ..RodParams::default()
    });
    assert!(matches!(
        bad_l,
        Err(SimError::Core(CoreError::NotPositive {
            field: "length",
            ..
        }))
    ));
    let bad_n = World::new(RodParams::default().with_edges(2));
    assert!(matches!(
        bad_n,
        Err(SimError::TooFewEdges { edges: 2, min: 3 })
    ));

    let world = World::new(RodParams::default().with_edges(20)).expect("valid");
    let base = Isometry3::identity();
    let nan_tip = pose([f64::NAN, 0.0, 0.0], [0.0, 0.0, 0.0]);
    assert!(matches!(
        world.solve_cold(&base, &nan_tip),
        Err(SimError::Core(CoreError::NonFinite { .. }))
    ));
    let message = world
        .solve_cold(&base, &nan_tip)
        .expect_err("a NaN tip is refused")
        .to_string();
    assert!(message.contains("tip position[0] = NaN"), "{message}");
    let far = pose([0.7, 0.0, 0.0], [0.0, 0.0, 0.0]);
    assert!(matches!(
        world.solve_cold(&base, &far),
        Err(SimError::GrippersTooFarApart { .. })
    ));
    let short = InitialGuess {
        points: vec![nalgebra::Point3::origin(); 3],
        frames: vec![UnitQuaternion::identity(); 2],
    };
    assert!(matches!(
        world.solve_with_guess(&short, &base, &pose([0.5, 0.0, 0.0], [0.0; 3])),
        Err(SimError::GuessSize {
            what: "points",
            got: 3,
            expected: 21
        })
    ));
    // Every message names what was wrong.
    let msg = world
        .solve_cold(&base, &far)
        .expect_err("too far")
        .to_string();
    assert!(msg.contains("apart"), "{msg}");
}

#[test]
fn a_failed_motion_keeps_the_last_good_state() {
    let world = World::new(RodParams::default().with_edges(20)).expect("valid");
    let base = Isometry3::identity();
    let tip = pose([0.5, 0.1, 0.0], [0.0, 0.0, 0.5]);
    let mut sim = Simulator::new(world.clone(), &base, &tip).expect("solves");
    let before = sim.equilibrium().clone();
    // A crippled solver: one Newton iteration and no subdivision.
    let crippled = world
        .with_newton(NewtonParams {
            max_iterations: 1,
            ..NewtonParams::default()
        })
        .with_continuation(ContinuationParams {
            max_subdivisions: 0,
            ..ContinuationParams::default()
        });
    let mut weak = Simulator::from_equilibrium(crippled, before.clone());
    let result = weak.move_grippers(&base, &pose([0.2, 0.3, 0.1], [1.0, 0.5, 2.0]));
    assert!(
        matches!(result, Err(SimError::NewtonFailed { .. })),
        "{result:?}"
    );
    assert_eq!(weak.equilibrium().state, before.state);
    // The healthy simulator makes the same move.
    sim.move_grippers(&base, &pose([0.2, 0.3, 0.1], [1.0, 0.5, 2.0]))
        .expect("moves");
}

/// A guess that ends 3 cm and 0.3 rad away from the requested tip clamp is solved where it ends
/// and carried over by continuation, landing on the same equilibrium as a cold solve.
#[test]
fn a_guess_that_misses_the_clamps_is_carried_to_them() {
    let world = World::new(anisotropic().without_gravity().with_edges(60)).expect("valid");
    let l = world.rod().params().length;
    let (turn, k) = (0.8, 0.8 / l);
    let arc = |s: f64| {
        Isometry3::from_parts(
            Translation3::new((k * s).sin() / k, (1.0 - (k * s).cos()) / k, 0.0),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), k * s),
        )
    };
    let guess = InitialGuess::from_shape(world.rod(), arc);
    let mut tip = arc(l);
    tip.translation.vector.x -= 0.03;
    tip.rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), turn + 0.3);
    let base = Isometry3::identity();
    let eq = world.solve_with_guess(&guess, &base, &tip).expect("solves");
    let cold = world.solve_cold(&base, &tip).expect("solves").equilibrium;
    let diff = (eq.base_wrench.to_vector() - cold.base_wrench.to_vector()).norm();
    println!("guess vs cold: {diff:e}");
    assert!(eq.stable_minimum);
    assert!(diff < 1e-6 * cold.base_wrench.to_vector().norm());
}

/// A work limit ends a motion once its Newton iterations times edges pass it, and a motion
/// within the limit is the same as without one.
#[test]
fn a_motion_stops_at_its_work_limit() {
    let edges = 20;
    let world = World::new(RodParams::default().with_edges(edges)).expect("valid");
    let base = Isometry3::identity();
    let tip = pose([0.5, 0.1, 0.0], [0.0, 0.0, 0.5]);
    let far = pose([0.2, 0.3, 0.1], [1.0, 0.5, 2.0]);
    let sim = Simulator::new(world.clone(), &base, &tip).expect("solves");
    let limited = |limit: usize| {
        world.clone().with_continuation(ContinuationParams {
            work_limit: Some(limit),
            ..ContinuationParams::default()
        })
    };
    // The move takes many steps of a few iterations each: ten iterations' work is too little.
    let mut tight = Simulator::from_equilibrium(limited(10 * edges), sim.equilibrium().clone());
    let result = tight.move_grippers(&base, &far);
    match result {
        Err(SimError::WorkExhausted {
            iterations,
            edges: e,
            limit,
        }) => {
            assert_eq!(e, edges);
            assert_eq!(limit, 10 * edges);
            assert!(iterations * edges > limit, "{iterations} iterations");
        }
        other => panic!("expected the work limit, got {other:?}"),
    }
    // With room to spare, the limit changes nothing.
    let mut free = sim.clone();
    free.move_grippers(&base, &far).expect("moves");
    let mut roomy =
        Simulator::from_equilibrium(limited(1_000_000 * edges), sim.equilibrium().clone());
    roomy
        .move_grippers(&base, &far)
        .expect("moves within the limit");
    assert_eq!(roomy.equilibrium().state, free.equilibrium().state);
}
