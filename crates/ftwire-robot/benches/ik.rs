//! Speed of FK and of one IK solve from a nearby seed (target: at most 50 µs).
//!
//! `cargo bench -p ftwire-robot --bench ik`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use ftwire_robot::{
    Arm, ArmJoints, EndFrame, IkParams, IkTarget, LinkRadii, OrientedBox, ReachParams, Robot,
};
use nalgebra::Point3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Random postures within limits, their gripper poses, and seeds 0.05 rad away from them.
fn cases(robot: &Robot, n: usize) -> Vec<(IkTarget, ArmJoints)> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let limits = robot.chain(Arm::Left).limits();
    (0..n)
        .filter_map(|_| {
            let q = ArmJoints::from_fn(|i, _| rng.random_range(limits[i].min..=limits[i].max));
            let seed =
                ArmJoints::from_fn(|i, _| limits[i].clamp(q[i] + rng.random_range(-0.05..=0.05)));
            let pose = robot.fk(Arm::Left, 0.0, &q, EndFrame::Gripper).ok()?;
            let target = IkTarget {
                arm: Arm::Left,
                pose,
                torso: 0.0,
                frame: EndFrame::Gripper,
            };
            Some((target, seed))
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let Ok(robot) = Robot::sda10f() else {
        return;
    };
    let cases = cases(&robot, 256);
    let params = IkParams::default();
    let q = *robot.preferred_posture(Arm::Left);
    c.bench_function("fk_gripper", |b| {
        b.iter(|| robot.fk(Arm::Left, black_box(0.1), black_box(&q), EndFrame::Gripper))
    });
    c.bench_function("jacobian", |b| {
        b.iter(|| robot.jacobian(Arm::Left, black_box(0.1), black_box(&q), EndFrame::Gripper))
    });
    let mut i = 0;
    c.bench_function("ik_nearby_seed", |b| {
        b.iter(|| {
            let (target, seed) = &cases[i % cases.len()];
            i += 1;
            robot.ik(black_box(target), Some(black_box(seed)), &params)
        })
    });
    let reach = ReachParams::default();
    let mut k = 0;
    c.bench_function("reachability_nearby_seed", |b| {
        b.iter(|| {
            let (target, seed) = &cases[k % cases.len()];
            k += 1;
            robot.reachability(black_box(target), black_box(seed), &reach)
        })
    });
    let radii = LinkRadii::default();
    let right = *robot.preferred_posture(Arm::Right);
    c.bench_function("arms_collision", |b| {
        b.iter(|| robot.arms_collision(black_box(0.1), black_box(&q), black_box(&right), &radii))
    });
    let table = OrientedBox::aabb(Point3::new(0.3, -0.6, -0.2), Point3::new(1.2, 0.6, 0.0));
    if let Ok(table) = table {
        c.bench_function("arm_vs_one_box", |b| {
            b.iter(|| {
                robot.arm_obstacle_collision(
                    Arm::Left,
                    black_box(0.1),
                    black_box(&q),
                    &[table],
                    &radii,
                )
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
