//! The bug this file guards: motions snapped the simulated wire to another branch although the
//! model found the whole path stable, because the reference twist of the last vertex (between
//! the tip clamp's edge, whose reference director is the clamp's, and its neighbour's
//! transported one) crossed ±π and `atan2` wrapped it by 2π, which changed the rod's total
//! twist by a full turn at fixed clamps. The reference twist stays on its continuous branch
//! (`RodState::ref_twist`), so turning a clamp past π is an ordinary smooth motion.

mod common;

use common::pose;
use ftwire_sim::{RodParams, Simulator, World};
use nalgebra::Isometry3;
use std::f64::consts::PI;

/// Turns the tip clamp about its own x axis from `from` to `to` \[rad\] in moves of at most
/// π/2 (each move's slerp is then the intended rotation), position fixed at `at`.
fn roll_tip(sim: &mut Simulator, at: [f64; 3], axis: [f64; 3], from: f64, to: f64) -> usize {
    let moves = ((to - from).abs() / (0.5 * PI)).ceil() as usize;
    let mut snaps = 0;
    for k in 1..=moves {
        let angle = from + (to - from) * k as f64 / moves as f64;
        let r = [axis[0] * angle, axis[1] * angle, axis[2] * angle];
        let motion = sim
            .move_grippers(&Isometry3::identity(), &pose(at, r))
            .expect("moves");
        snaps += motion.snaps.len();
    }
    snaps
}

/// A straight wire twisted by 1.5π (below the clamped–clamped twist-buckling moment
/// `≈ 8.99 c2/L`) carries the torque `c1·φ/L`. Before the fix the twist wrapped to `φ − 2π`
/// once the tip passed π: the torque came out as `−c1·π/(2L)`.
#[test]
fn a_straight_wire_twisted_past_half_a_turn_keeps_its_twist() {
    let params = RodParams::nitinol_2mm_630()
        .without_gravity()
        .with_edges(40);
    let (c1, l) = (params.stiffness[0], params.length);
    let world = World::new(params).expect("valid");
    let base = Isometry3::identity();
    let mut sim = Simulator::new(world, &base, &pose([l, 0.0, 0.0], [0.0; 3])).expect("solves");
    let phi = 1.5 * PI;
    let snaps = roll_tip(&mut sim, [l, 0.0, 0.0], [1.0, 0.0, 0.0], 0.0, phi);
    let torque = sim.equilibrium().base_wrench.torque.x;
    let expected = c1 * phi / l;
    println!("torque {torque:.6} N·m, expected {expected:.6}");
    assert_eq!(snaps, 0);
    assert!((torque - expected).abs() < 1e-3 * expected);
    assert!(sim.equilibrium().stable_minimum);
}

/// A bent wire whose tip clamp is rolled about its own tangent by more than a half turn and
/// back: a stable branch all the way (no snap), and the way back lands where it started.
/// Before the fix the roll snapped the wire where the last vertex's reference twist crossed π.
#[test]
fn a_bent_wire_rolled_past_half_a_turn_follows_its_branch_and_returns() {
    let params = RodParams::nitinol_3mm_820()
        .without_gravity()
        .with_edges(60);
    let l = params.length;
    let world = World::new(params).expect("valid");
    let base = Isometry3::identity();
    let at = [0.55 * l, 0.25 * l, 0.0];
    // The tip faces back towards the base (a U-like bend); rolls are about the tip's x axis.
    let yaw = [0.0, 0.0, 0.75 * PI];
    let start = pose(at, yaw);
    let mut sim = Simulator::new(world, &base, &start).expect("solves");
    let w0 = sim.equilibrium().base_wrench.to_vector();
    let e0 = sim.equilibrium().energy();
    let mut snaps = 0;
    let roll = 1.3 * PI;
    let moves = 12;
    let turned = |angle: f64| start * Isometry3::rotation(nalgebra::Vector3::new(angle, 0.0, 0.0));
    for k in 1..=moves {
        let motion = sim
            .move_grippers(&base, &turned(roll * k as f64 / moves as f64))
            .expect("moves");
        snaps += motion.snaps.len();
    }
    let e_turned = sim.equilibrium().energy();
    for k in (0..moves).rev() {
        let motion = sim
            .move_grippers(&base, &turned(roll * k as f64 / moves as f64))
            .expect("moves");
        snaps += motion.snaps.len();
    }
    let w1 = sim.equilibrium().base_wrench.to_vector();
    println!(
        "energy {e0:.4} J → {e_turned:.4} J turned → {:.4} J back; wrench change {:e}",
        sim.equilibrium().energy(),
        (w1 - w0).norm() / w0.norm()
    );
    assert_eq!(snaps, 0);
    assert!((w1 - w0).norm() < 1e-4 * w0.norm());
}
