//! Time to the first path in the passage scene (`scenes/passage.toml`, the 3 mm / 820 mm
//! nitinol wire; the target ≤ 0.5 s): RRT* in A_free stopped at its first path, no
//! shortcutting, the endpoints' IK done once outside the timing. Each iteration takes the next
//! seed of 0–15 in turn, so the mean is over the planner's randomness, not one lucky seed.
//!
//! `cargo bench -p ftwire-plan --bench plan`

use std::cell::Cell;
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use ftwire_plan::{Checker, FixedBase, PlannerParams, Scene, ValidityParams, plan, scene_endpoint};
use ftwire_robot::Robot;
use ftwire_rod::{Rod, WireParams};

fn first_path(c: &mut Criterion) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/passage.toml");
    let Ok(scene) = Scene::load(&path) else {
        panic!("cannot read {}", path.display());
    };
    let Ok(wire) = WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015) else {
        panic!("the nitinol wire is valid");
    };
    let rod = Rod::new(wire);
    let (Ok(robot),) = (Robot::sda10f(),) else {
        panic!("the SDA10F loads");
    };
    let Ok(checker) = Checker::new(rod, robot, &scene, ValidityParams::default()) else {
        panic!("default settings are valid");
    };
    let (Ok(start), Ok(goal)) = (
        scene_endpoint(&scene, &checker, "start", "start"),
        scene_endpoint(&scene, &checker, "goal", "goal"),
    ) else {
        panic!("the passage scene's endpoints are valid");
    };
    let space = FixedBase::around(wire, scene.base, &[start.config, goal.config], 2.0);
    let seed = Cell::new(0u64);
    let mut group = c.benchmark_group("passage");
    group.sample_size(16);
    group.bench_function("first_path_seeds_0_to_15", |b| {
        b.iter(|| {
            let params = PlannerParams {
                seed: seed.get(),
                stop_at_first: true,
                shortcut_attempts: 0,
                max_iterations: 20_000,
                ..PlannerParams::default()
            };
            seed.set((seed.get() + 1) % 16);
            black_box(plan(&space, &checker, &start, &goal.config, &params).is_ok())
        });
    });
    group.finish();
}

criterion_group!(benches, first_path);
criterion_main!(benches);
