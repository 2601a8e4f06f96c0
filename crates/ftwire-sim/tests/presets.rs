//! The wire presets solve, and a natural curvature is honoured.

mod common;

use common::pose;
use ftwire_sim::{RodParams, World};
use nalgebra::Isometry3;

#[test]
fn every_preset_reaches_a_stable_bent_equilibrium_under_gravity() {
    for (name, params) in [
        ("nitinol 2 mm × 630 mm", RodParams::nitinol_2mm_630()),
        ("nitinol 3 mm × 910 mm", RodParams::nitinol_3mm_910()),
        ("nitinol 3 mm × 820 mm", RodParams::nitinol_3mm_820()),
        ("cable 3 mm × 920 mm", RodParams::electric_cable_3mm_920()),
    ] {
        let l = params.length;
        let world = World::new(params).expect("valid");
        let tip = pose([0.6 * l, 0.25 * l, 0.1 * l], [0.3, -0.2, 1.0]);
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
        assert!(eq.energies.gravity != 0.0);
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
