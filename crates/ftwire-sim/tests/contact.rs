//! Contact with a floor and with a thin box.

mod common;

use common::pose;
use ftwire_sim::{BoxObstacle, Floor, RodParams, Simulator, World};
use nalgebra::{Isometry3, Vector3};

/// Force balance on the wire: gripper reactions, weight and contact forces sum to zero.
fn residual_force(eq: &ftwire_sim::Equilibrium, world: &World) -> f64 {
    let rod = world.rod();
    let weight = rod.params().gravity * rod.linear_density() * rod.params().length;
    let on_base = eq.state.base().rotation * eq.base_wrench.force;
    let on_tip = eq.state.tip().rotation * eq.tip_wrench.force;
    let contact: Vector3<f64> = eq.contact_forces.iter().sum();
    // The grippers push the wire with −(wire on gripper).
    (weight + contact - on_base - on_tip).norm()
}

/// The grippers hold the wire with tangents dipping by 0.4 rad, so that it hangs in a U whose
/// bottom is 0.177 m below them. Starting clear of the obstacles (at 0.19 m), they are lowered
/// to `z`.
fn lower_onto(world: &World, z: f64) -> (Simulator, ftwire_sim::Motion) {
    let at = |z: f64| {
        (
            pose([0.0, 0.0, z], [0.0, 0.4, 0.0]),
            pose([0.5, 0.0, z], [0.0, -0.4, 0.0]),
        )
    };
    let (b0, t0) = at(0.19);
    let mut sim = Simulator::new(world.clone(), &b0, &t0).expect("solves");
    assert!(sim.equilibrium().energies.contact == 0.0);
    let (b1, t1) = at(z);
    let motion = sim.move_grippers(&b1, &t1).expect("moves").clone();
    (sim, motion)
}

/// Lowered 1 mm further, the U is pressed hard enough to tip over sideways (the stability check
/// reports a saddle), as a hairpin pushed onto a table does; 1 mm of contact is stable.
#[test]
fn a_hanging_wire_rests_on_the_floor_and_the_forces_balance() {
    let world = World::new(RodParams::nitinol_2mm_630())
        .expect("valid")
        .with_floor(Floor { height: 0.0 })
        .expect("valid");
    let (sim, motion) = lower_onto(&world, 0.178);
    let eq = sim.equilibrium();
    let lowest = eq
        .centreline()
        .iter()
        .map(|p| p.z)
        .fold(f64::INFINITY, f64::min);
    println!(
        "floor: steps {}, iterations {}, lowest node {lowest:e} m, floor force {:?} N, balance {:e} N",
        motion.steps,
        motion.iterations,
        eq.contact_forces[0],
        residual_force(eq, &world)
    );
    let r = world.rod().params().radius;
    assert!(eq.contact_forces[0].z > 0.1);
    assert!(lowest > 0.95 * r && lowest < r);
    assert!(residual_force(eq, &world) < 1e-6 * eq.contact_forces[0].norm());
    assert!(eq.stable_minimum);
}

/// A 1 mm plate under the U: the wire is pressed onto it and never passes through it.
#[test]
fn a_wire_does_not_tunnel_through_a_thin_plate() {
    let plate = BoxObstacle::new(
        Isometry3::translation(0.25, 0.0, 0.0),
        Vector3::new(0.1, 0.1, 0.0005),
    )
    .expect("valid");
    let world = World::new(RodParams::nitinol_2mm_630())
        .expect("valid")
        .with_box(plate);
    let (sim, motion) = lower_onto(&world, 0.165);
    let eq = sim.equilibrium();
    let over_plate: Vec<f64> = eq
        .centreline()
        .iter()
        .filter(|p| (p.x - 0.25).abs() < 0.09)
        .map(|p| p.z)
        .collect();
    let lowest = over_plate.iter().copied().fold(f64::INFINITY, f64::min);
    println!(
        "plate: steps {}, iterations {}, lowest point over the plate {lowest:e} m, plate force {:?}",
        motion.steps, motion.iterations, eq.contact_forces[0]
    );
    assert!(!over_plate.is_empty());
    // Resting on the top face (z = 0.5 mm) with the wire's radius, barely penetrating.
    assert!(lowest > 0.0005 + 0.9 * world.rod().params().radius);
    assert!(eq.contact_forces[0].z > 0.1);
    assert!(residual_force(eq, &world) < 1e-6 * eq.contact_forces[0].norm());
}
