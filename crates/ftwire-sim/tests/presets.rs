//! The wire presets solve and hang in the grippers with their weight, and a natural curvature is
//! honoured.

mod common;

use common::pose;
use std::f64::consts::PI;

use ftwire_core::Pose;
use ftwire_sim::{Equilibrium, RodParams, World};
use nalgebra::{Isometry3, Vector3};

/// The four presets, with a tip pose of the same shape for each.
fn presets() -> [(&'static str, RodParams); 4] {
    [
        ("nitinol 2 mm × 630 mm", RodParams::nitinol_2mm_630()),
        ("nitinol 3 mm × 910 mm", RodParams::nitinol_3mm_910()),
        ("nitinol 3 mm × 820 mm", RodParams::nitinol_3mm_820()),
        ("cable 3 mm × 920 mm", RodParams::electric_cable_3mm_920()),
    ]
}

fn tip_for(params: &RodParams) -> Pose {
    let l = params.length;
    pose([0.6 * l, 0.25 * l, 0.1 * l], [0.3, -0.2, 1.0])
}

/// The force the wire exerts on both grippers together, world frame.
fn total_clamp_force(eq: &Equilibrium) -> Vector3<f64> {
    eq.state.base().rotation * eq.base_wrench.force + eq.state.tip().rotation * eq.tip_wrench.force
}

/// How far the clamp forces may be from balancing the weight: the internal energies are
/// invariant under translation, so the clamp forces sum to the weight plus the sum of the
/// residual forces on the free nodes, each component of which Newton's scaled residual bounds
/// by `residual·c_max/L²` (`NewtonParams::tolerance`); plus rounding.
fn balance_tolerance(world: &World, eq: &Equilibrium, weight: f64) -> f64 {
    let rod = world.rod();
    let l = rod.params().length;
    let free_nodes = (rod.nodes() - 4) as f64;
    free_nodes * eq.convergence.residual * rod.max_stiffness() / (l * l) + 1e-9 * weight
}

#[test]
fn every_preset_hangs_in_the_grippers_with_its_weight() {
    for (name, params) in presets() {
        let tip = tip_for(&params);
        let g = params.gravity;
        let world = World::new(params).expect("valid");
        let eq = world
            .solve_cold(&Isometry3::identity(), &tip)
            .expect("solves")
            .equilibrium;
        println!(
            "{name}: {} iterations, a = {:?}",
            eq.convergence.iterations,
            eq.base_wrench.to_vector()
        );
        assert!(eq.stable_minimum, "{name}");

        // The grippers carry the weight ρ·π·r²·g·L, straight down.
        let rod = world.rod();
        let weight = params.density * PI * params.radius.powi(2) * g.norm() * params.length;
        let force = total_clamp_force(&eq);
        let tolerance = balance_tolerance(&world, &eq, weight);
        println!("{name}: clamp forces {force:?}, weight {weight} N, tolerance {tolerance:e} N");
        assert!(
            tolerance < 1e-3 * weight,
            "{name}: residual too large to test"
        );
        assert!(
            (force - g.normalize() * weight).norm() < tolerance,
            "{name}"
        );

        // The gravity energy is −Σ m_k g·x_k over the nodes.
        let nodes = eq.centreline();
        let expected: f64 = nodes
            .iter()
            .enumerate()
            .map(|(k, x)| -rod.node_mass(k) * g.dot(&x.coords))
            .sum();
        let scale: f64 = nodes
            .iter()
            .enumerate()
            .map(|(k, x)| rod.node_mass(k) * g.norm() * x.coords.norm())
            .sum();
        assert!(
            (eq.energies.gravity - expected).abs() < 1e-12 * scale,
            "{name}: gravity energy {} vs {expected}",
            eq.energies.gravity
        );

        // Gravity pulls the wire down: lower, on average, than the same wire without weight.
        let weightless = World::new(params.without_gravity())
            .expect("valid")
            .solve_cold(&Isometry3::identity(), &tip)
            .expect("solves")
            .equilibrium;
        let mean_z = |eq: &Equilibrium| {
            eq.centreline().iter().map(|x| x.z).sum::<f64>() / nodes.len() as f64
        };
        let sag = mean_z(&weightless) - mean_z(&eq);
        println!("{name}: mean sag {sag} m");
        assert!(sag > 1e-4 * params.length, "{name}: sag {sag} m");

        // Without gravity the clamp forces balance.
        let force = total_clamp_force(&weightless);
        assert!(
            force.norm() < balance_tolerance(&world, &weightless, weight),
            "{name}: {force:?}"
        );
    }
}

/// Clamps placed on the cable's natural arc (curvature 1.5 1/m about body z, gravity off): the
/// wire is at rest, so both grippers feel nothing; a straight placement loads them with c3·κ.
#[test]
fn a_naturally_curved_cable_clamped_on_its_rest_arc_is_unloaded() {
    let params = RodParams::electric_cable_3mm_920().without_gravity();
    let (l, k, c3) = (params.length, params.rest_strain.z, params.stiffness[2]);
    assert!(k > 0.0);
    let world = World::new(params).expect("valid");
    let phi = k * l;
    let on_arc = pose([phi.sin() / k, (1.0 - phi.cos()) / k, 0.0], [0.0, 0.0, phi]);
    let eq = world
        .solve_cold(&Isometry3::identity(), &on_arc)
        .expect("solves")
        .equilibrium;
    let a = eq.base_wrench.to_vector();
    println!("on its rest arc: a = {a:?}");
    assert!(a.fixed_rows::<3>(0).norm() < 1e-3 * c3 * k);
    // The force is mostly axial, where the stiff stretching turns a 1e-9 m mismatch between the
    // discrete and the continuous arc into 1e-5 N; 1 % of the moment scale bounds it.
    assert!(a.fixed_rows::<3>(3).norm() < 1e-2 * c3 * k / l);
    // Straightened, the cable pushes back with its rest curvature.
    let straight = pose([l, 0.0, 0.0], [0.0, 0.0, 0.0]);
    let eq = world
        .solve_cold(&Isometry3::identity(), &straight)
        .expect("solves")
        .equilibrium;
    let a = eq.base_wrench.to_vector();
    println!("straightened: a = {a:?}, expected τ3 = {}", -c3 * k);
    assert!((a[2] + c3 * k).abs() < 1e-3 * c3 * k);
}
