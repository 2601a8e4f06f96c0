//! Equilibrium solve times at N = 100 (the 2 mm × 630 mm nitinol wire, gravity on).
//!
//! - `warm_move_1mm_1deg`: from an equilibrium, move the tip gripper by 1 mm and 1° (target
//!   ≤ 2 ms).
//! - `cold_strongly_bent`: from nothing to a strongly bent 3-D pose (target ≤ 100 ms).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use ftwire_sim::{RodParams, World};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

fn pose(p: [f64; 3], r: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(p[0], p[1], p[2]),
        UnitQuaternion::from_scaled_axis(Vector3::new(r[0], r[1], r[2])),
    )
}

fn benches(c: &mut Criterion) {
    let world = World::new(RodParams::nitinol_2mm_630()).expect("valid");
    let base = Isometry3::identity();
    let tip = pose([0.4, 0.2, 0.05], [0.2, -0.3, 1.2]);
    let start = world.solve_cold(&base, &tip).expect("solves").equilibrium;
    let moved = pose([0.401, 0.2, 0.05], [0.2, -0.3, 1.2 + 1f64.to_radians()]);
    c.bench_function("warm_move_1mm_1deg", |b| {
        b.iter(|| {
            world
                .move_grippers(black_box(&start), &base, black_box(&moved))
                .expect("moves")
        })
    });
    // Strongly bent: tip turned back by 150° and twisted, 0.25 m from the base.
    let bent = pose([0.15, 0.2, 0.05], [0.4, 0.3, 2.6]);
    c.bench_function("cold_strongly_bent", |b| {
        b.iter(|| world.solve_cold(&base, black_box(&bent)).expect("solves"))
    });
}

criterion_group!(group, benches);
criterion_main!(group);
