//! Compute per controller step (target ≤ 100 µs): the control law of eq. 13–14 with the
//! Jacobian at `ã`, the step limits and the stability guard on the predicted configuration,
//! for the weightless model and for the loaded one (the 3 mm / 820 mm nitinol under gravity);
//! and one update of the bias observer at a rest (three Gauss–Newton iterations, each a
//! solve of `J(L)`), which the loop adds when it steers by the drift-corrected `ã` (and, fused
//! with the pose, `BiasObserverParams::fuse_rest`, up to six, stopping once converged); and the
//! shape stop's check at a rest (`Controller::shape_distance`: one shape solve of 50 nodes and
//! the mean distance to the goal's), which the loop adds when it stops on the shape.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use ftwire_control::{BiasObserver, BiasObserverParams, ControlParams, Controller};
use ftwire_core::{Pose, WireParams};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_rod::{Load, from_normalised};
use nalgebra::{Vector3, Vector6};

fn bench(c: &mut Criterion) {
    let wire = WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire");
    let a = from_normalised(&wire, &Vector6::new(0.5, 2.0, 1.0, -2.0, 3.0, 0.5));
    let goal = from_normalised(&wire, &Vector6::new(0.2, 3.0, 0.5, -1.0, 2.0, 1.0));
    let weightless = KirchhoffModel::new(wire);
    let load =
        Load::from_gravity(6450.0, 0.0015, Vector3::new(0.0, 0.0, -9.81)).expect("valid load");
    let loaded = weightless.with_load(load);
    for (name, model) in [("weightless", weightless), ("loaded", loaded)] {
        let controller = Controller::new(model, ControlParams::default()).expect("valid settings");
        c.bench_function(&format!("controller step ({name})"), |b| {
            b.iter(|| {
                controller
                    .plan_step(black_box(&a), black_box(&goal), &Pose::identity())
                    .expect("solves")
            });
        });
        let goal_shape = model.shape(&goal, 50).expect("solves").positions;
        c.bench_function(&format!("shape stop check ({name})"), |b| {
            b.iter(|| {
                controller
                    .shape_distance(black_box(&a), &goal_shape)
                    .expect("solves")
            });
        });
        let tip = model.tip(&a).expect("solves");
        let reading = a + from_normalised(&wire, &Vector6::new(0.0, 0.0, 0.0, 0.01, 0.0, 0.0));
        let std = from_normalised(&wire, &Vector6::repeat(0.01));
        for (kind, fuse_rest) in [("", false), (", fused", true)] {
            let settings = BiasObserverParams {
                fuse_rest,
                ..BiasObserverParams::default()
            };
            c.bench_function(&format!("bias observer update ({name}{kind})"), |b| {
                b.iter_batched(
                    || BiasObserver::new(model, settings).expect("valid"),
                    |mut observer| observer.update(black_box(&reading), &std, &tip, 0.0),
                    criterion::BatchSize::SmallInput,
                );
            });
        }
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
