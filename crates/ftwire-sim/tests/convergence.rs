//! Observed order of convergence as the number of edges grows.
//!
//! The clamps sit at the midpoints of ghost half-edges, so both the wrench and the shape should
//! converge as `1/N²`. With `N − 1 = 20, 40, 80, 160` the successive differences must shrink by
//! about 4 each time.

mod common;

use common::pose;
use ftwire_sim::{Equilibrium, RodParams, World};
use nalgebra::{Isometry3, Vector3};

fn solve(edges: usize, params: RodParams, tip: &ftwire_core::Pose) -> Equilibrium {
    let world = World::new(params.with_edges(edges)).expect("valid");
    world
        .solve_cold(&Isometry3::identity(), tip)
        .expect("solves")
        .equilibrium
}

fn midpoints(eq: &Equilibrium) -> Vec<Vector3<f64>> {
    let c = eq.centreline();
    c.windows(2)
        .map(|w| (w[0].coords + w[1].coords) * 0.5)
        .collect()
}

fn orders(params: RodParams, tip: &ftwire_core::Pose, label: &str) {
    let levels = [21, 41, 81, 161];
    let sols: Vec<Equilibrium> = levels.iter().map(|&n| solve(n, params, tip)).collect();
    let mut wrench_diff = Vec::new();
    let mut shape_diff = Vec::new();
    for pair in sols.windows(2) {
        let (coarse, fine) = (&pair[0], &pair[1]);
        assert!(coarse.stable_minimum && fine.stable_minimum);
        let dw = coarse.base_wrench.to_vector() - fine.base_wrench.to_vector();
        wrench_diff.push(dw.norm() / fine.base_wrench.to_vector().norm());
        // Edge j of the coarse rod and edge 2j of the fine one share an arc length.
        let (mc, mf) = (midpoints(coarse), midpoints(fine));
        let d = mc
            .iter()
            .enumerate()
            .map(|(j, p)| (p - mf[2 * j]).norm())
            .fold(0.0, f64::max);
        shape_diff.push(d);
    }
    let order = |d: &[f64]| -> Vec<f64> { d.windows(2).map(|w| (w[0] / w[1]).log2()).collect() };
    let (ow, os) = (order(&wrench_diff), order(&shape_diff));
    println!("{label}: wrench differences {wrench_diff:?}, orders {ow:?}");
    println!("{label}: shape differences [m] {shape_diff:?}, orders {os:?}");
    for o in ow.iter().chain(&os) {
        assert!((1.7..2.4).contains(o), "{label}: observed order {o}");
    }
}

#[test]
fn wrench_and_shape_converge_at_second_order() {
    // A 3-D pose with gravity, anisotropic stiffness and natural curvature.
    let params = RodParams {
        stiffness: [0.042, 0.055, 0.070],
        rest_strain: Vector3::new(0.3, 0.5, -0.8),
        ..RodParams::nitinol_2mm_630()
    };
    let tip = pose([0.35, 0.25, 0.1], [0.3, -0.4, 1.4]);
    orders(params, &tip, "3-D, gravity, natural curvature");
}
