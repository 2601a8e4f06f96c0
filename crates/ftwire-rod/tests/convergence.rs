//! Convergence of the fixed-step integrators against the adaptive reference (the study quoted
//! in the `integrator` module docs), and the accuracy requirement at default settings.

mod common;

use ftwire_rod::{Integrator, Method, Rod, WireParams, sampling::Sampler};
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Stable configurations uniform in normalised units in [−30, 30]⁶ (stability judged by a
/// fine solve, independent of the settings under test).
fn stable_sample(wire: &WireParams, count: usize, seed: u64) -> Vec<Vector6<f64>> {
    let fine = Rod::new(*wire).with_integrator(Integrator::new(Method::Rk8, 256).expect("valid"));
    let sampler = Sampler::default();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|_| {
            sampler
                .sample_stable(&fine, &mut rng)
                .expect("a stable sample")
        })
        .collect()
}

/// Worst errors over the sample: tip position / L, tip rotation and J(L) of `Rod::jacobian`
/// (the q + J integration), then tip position / L and rotation of `Rod::tip` (the frame-only
/// integration of q and μ).
fn worst(
    rod: &Rod,
    sample: &[Vector6<f64>],
    refs: &[common::Reference],
) -> (f64, f64, f64, f64, f64) {
    let mut worst = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (a, r) in sample.iter().zip(refs) {
        let s = rod.jacobian(a).expect("solves");
        let e = common::errors(rod.wire(), &s.tip, &s.jacobian, r);
        let tip = rod.tip(a).expect("solves");
        let f = common::errors(rod.wire(), &tip, &s.jacobian, r);
        worst = (
            worst.0.max(e.0),
            worst.1.max(e.1),
            worst.2.max(e.2),
            worst.3.max(f.0),
            worst.4.max(f.1),
        );
    }
    worst
}

fn wires() -> Vec<WireParams> {
    vec![
        WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid"),
        WireParams::new([0.214, 0.278, 0.278], 0.91, 0.0015).expect("valid"),
        WireParams::new([1.3, 1.0, 0.6], 1.0, 0.001).expect("valid"),
    ]
}

#[test]
fn default_meets_the_accuracy_requirement() {
    for (w, wire) in wires().iter().enumerate() {
        let sample = stable_sample(wire, 40, 100 + w as u64);
        let refs: Vec<_> = sample.iter().map(|a| common::reference(wire, a)).collect();
        let (dp, dr, dj, fp, fr) = worst(&Rod::new(*wire), &sample, &refs);
        assert!(dp < 1e-6, "wire {w}: tip position error {dp:e} L");
        assert!(dr < 1e-6, "wire {w}: tip rotation error {dr:e} rad");
        assert!(dj < 1e-5, "wire {w}: J(L) relative error {dj:e}");
        assert!(
            fp < 1e-6,
            "wire {w}: frame-only tip position error {fp:e} L"
        );
        assert!(
            fr < 1e-6,
            "wire {w}: frame-only tip rotation error {fr:e} rad"
        );
    }
}

/// The convergence study: prints worst errors per method and step count. Slow; run with
/// `cargo test -p ftwire-rod --release --test convergence -- --ignored --nocapture study`.
#[test]
#[ignore = "study, prints a table (about a minute in release)"]
fn study() {
    let count = 200;
    for (w, wire) in wires().iter().enumerate() {
        let sample = stable_sample(wire, count, 100 + w as u64);
        let refs: Vec<_> = sample.iter().map(|a| common::reference(wire, a)).collect();
        println!(
            "wire {w}: c = {:?}, L = {}, {count} stable configurations",
            wire.c(),
            wire.length()
        );
        let sigma: Vec<f64> = sample
            .iter()
            .map(|a| ftwire_rod::equations::turning_scale(wire.c(), a) * wire.length())
            .collect();
        let mean_sigma = sigma.iter().sum::<f64>() / sigma.len() as f64;
        let max_sigma = sigma.iter().cloned().fold(0.0, f64::max);
        println!("σL: mean {mean_sigma:.1}, max {max_sigma:.1}");
        println!(
            "| method | steps | mean evals | tip pos / L | tip rot [rad] | J(L) rel | frame-only pos / L | frame-only rot [rad] |"
        );
        let mut settings: Vec<(String, Integrator)> = Vec::new();
        for (method, steps) in [
            (Method::Rk4, 120),
            (Method::Rk4, 240),
            (Method::Rk6, 48),
            (Method::Rk8, 16),
            (Method::Rk8, 24),
            (Method::Rk8, 32),
            (Method::Rk8, 40),
            (Method::Rk8, 48),
            (Method::Dop853, 16),
            (Method::Dop853, 24),
            (Method::Dop853, 32),
        ] {
            settings.push((
                format!("{steps}"),
                Integrator::new(method, steps).expect("valid"),
            ));
        }
        for (method, min, per) in [
            (Method::Rk4, 16, 8.0),
            (Method::Rk6, 8, 3.0),
            (Method::Rk8, 8, 1.0),
            (Method::Rk8, 8, 1.25),
            (Method::Rk8, 8, 1.5),
            (Method::Rk8, 8, 2.0),
            (Method::Rk8, 8, 2.5),
            (Method::Rk8, 8, 3.0),
            (Method::Dop853, 8, 1.25),
            (Method::Dop853, 8, 1.5),
            (Method::Dop853, 8, 1.6),
            (Method::Dop853, 8, 1.75),
            (Method::Dop853, 8, 2.0),
            (Method::Dop853, 8, 2.5),
        ] {
            settings.push((
                format!("max({min}, ⌈{per}·σL⌉)"),
                Integrator::adaptive(method, min, per).expect("valid"),
            ));
        }
        for (label, integrator) in settings {
            let rod = Rod::new(*wire).with_integrator(integrator);
            let (dp, dr, dj, fp, fr) = worst(&rod, &sample, &refs);
            let stages = integrator.method().stages() as f64;
            let evals = sample
                .iter()
                .map(|a| {
                    // The first step's substeps add `substeps − 1` steps.
                    let extra = integrator.first_step_substeps() - 1;
                    (rod.steps_for_configuration(a).expect("valid") + extra) as f64 * stages
                })
                .sum::<f64>()
                / sample.len() as f64;
            println!(
                "| {:?} | {label} | {evals:.0} | {dp:.1e} | {dr:.1e} | {dj:.1e} | {fp:.1e} | {fr:.1e} |",
                integrator.method()
            );
        }
    }
}
