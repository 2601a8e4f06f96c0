//! The stability test: Euler buckling, the sign of det J at the first grid point, and its sign
//! between grid points against a dense reference.

mod common;

use ftwire_rod::{Integrator, Load, Method, Rod, WireParams, from_normalised, sampling::Sampler};
use nalgebra::{Vector3, Vector6};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// a = (0, 0, 1e-4, −P, 0, 0): stable below the clamped–clamped Euler load 4π² c2 / L², unstable
/// above, with the first sign change of det J at t* = 2π √(c2 / P) within the grid spacing.
#[test]
fn euler_buckling() {
    for (c, length, steps) in [
        ([0.042, 0.055, 0.055], 0.63, 16),
        ([1.0, 2.0, 2.0], 1.5, 64),
    ] {
        let wire = WireParams::new(c, length, 0.001).expect("valid");
        let rod =
            Rod::new(wire).with_integrator(Integrator::new(Method::Rk8, steps).expect("valid"));
        let critical = 4.0 * PI * PI * c[1] / (length * length);
        for ratio in [0.3, 0.6, 0.9, 0.97] {
            let a = Vector6::new(0.0, 0.0, 1e-4, -ratio * critical, 0.0, 0.0);
            let j = rod.jacobian(&a).expect("solves");
            assert!(
                j.stability.stable,
                "P = {ratio} P_crit should be stable: {:?}",
                j.stability.det_j
            );
            assert!(rod.is_stable(&a).expect("solves"));
        }
        for ratio in [1.05, 1.5, 3.0, 8.0] {
            let p = ratio * critical;
            let a = Vector6::new(0.0, 0.0, 1e-4, -p, 0.0, 0.0);
            let j = rod.jacobian(&a).expect("solves");
            assert!(!j.stability.stable, "P = {ratio} P_crit should be unstable");
            assert!(!rod.is_stable(&a).expect("solves"));
            let t_star = 2.0 * PI * (c[1] / p).sqrt();
            let [t0, t1] = j.stability.first_sign_change.expect("a sign change");
            assert!(
                t0 <= t_star && t_star <= t1 && t1 - t0 <= length / steps as f64 + 1e-12,
                "P = {ratio} P_crit: t* = {t_star} not in [{t0}, {t1}]"
            );
        }
    }
}

/// A near-straight wire in tension (f1 > 0) is stable. (With a larger moment the initial
/// value problem curls the wire into loops, `θ'' = (P/c) sin θ`, which may well be unstable.)
#[test]
fn near_straight_tension_is_stable() {
    let wire = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid");
    for p in [0.1, 1.0, 10.0] {
        let a = Vector6::new(0.0, 0.0, 1e-6, p, 0.0, 0.0);
        assert!(Rod::new(wire).is_stable(&a).expect("solves"), "P = {p}");
    }
}

/// The sign of det J at the first grid point agrees with a fine reference, over random
/// configurations; and one plain RK4 step from J(0) = 0 does not (the pitfall this guards).
#[test]
fn first_step_sign_matches_a_fine_reference() {
    let wire = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid");
    let sampler = Sampler::default();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut rk4_wrong = 0;
    let count = 60;
    for _ in 0..count {
        let a = sampler.sample_a(&Rod::new(wire), &mut rng);
        let steps = Rod::new(wire).steps_for_configuration(&a).expect("valid");
        let h = wire.length() / steps as f64;
        let reference = common::reference_at(&wire, &a, h, 1e-13).j.determinant();
        let ours = Rod::new(wire).jacobian(&a).expect("solves").stability.det_j[0];
        assert_eq!(
            ours.signum(),
            reference.signum(),
            "a = {a}: {ours:e} vs {reference:e}"
        );
        assert!((ours - reference).abs() < 1e-3 * reference.abs());
        // A wire of length h solved in one RK4 step has det J(h) from a single step.
        let one = WireParams::new(wire.c(), h, 0.001).expect("valid");
        let rk4 = Rod::new(one).with_integrator(Integrator::new(Method::Rk4, 1).expect("valid"));
        let single = single_step_det(&rk4, &a);
        if single.signum() != reference.signum() {
            rk4_wrong += 1;
        }
    }
    assert!(
        rk4_wrong > count / 4,
        "RK4 single step was wrong only {rk4_wrong} times of {count}"
    );
}

/// det J after a single RK4 step from J(0) = 0 (no substeps).
fn single_step_det(rod: &Rod, a: &Vector6<f64>) -> f64 {
    let naive = rod.with_integrator(rod.integrator().with_first_step_substeps(1).expect("valid"));
    naive.jacobian(a).expect("solves").stability.det_j[0]
}

/// Stable samples really are stable and unstable ones unstable, against the reference sign
/// of det J on a fine grid.
#[test]
fn early_exit_agrees_with_full_test() {
    let wire = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid");
    let rod = Rod::new(wire);
    let sampler = Sampler::default();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut stable = 0;
    for _ in 0..300 {
        let a = from_normalised(&wire, &sampler.sample_normalised(&mut rng));
        let full = rod.jacobian(&a).expect("solves").stability.stable;
        assert_eq!(full, rod.is_stable(&a).expect("solves"));
        stable += usize::from(full);
    }
    assert!(stable > 0 && stable < 300);
}

/// `det J` at the grid points of `rod`'s solve of `a` with `refine` times its steps, from the
/// first grid point of the coarse grid on (`t ≥ h`): a dense reference, and its spacing.
fn dense_det(rod: &Rod, a: &Vector6<f64>, refine: usize) -> (Vec<f64>, f64) {
    let steps = rod.steps_for_configuration(a).expect("in A");
    let dense =
        rod.with_integrator(Integrator::new(Method::Dop853, refine * steps).expect("valid"));
    let stability = dense.jacobian(a).expect("solves").stability;
    (stability.det_j[refine - 1..].to_vec(), stability.spacing)
}

/// Whether every value is finite, non-zero and of one sign.
fn one_sign(values: &[f64]) -> bool {
    let sign = values.first().map_or(0.0, |v| v.signum());
    values
        .iter()
        .all(|v| v.is_finite() && *v != 0.0 && v.signum() == sign)
}

/// Near a fold of the round 2 mm wire's `det J` — two conjugate points that approach each
/// other to within a millimetre near `t = 0.46 m` and part again along a line in `A` — `det J`
/// dips below zero inside one step of the solver while every grid point has the same sign.
/// The solver calls these configurations unstable, with the first sign change in that step,
/// as a dense reference (the solver at 64 times the steps, its grid points only) does.
///
/// The line `a0 + s v` starts in `A_stable` and leaves it; it was found by scanning seeded
/// random lines (stable `a0`, random `v`) for configurations whose grid points agree in sign
/// while the dense reference dips.
#[test]
fn dips_between_grid_points_are_unstable() {
    let wire = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid");
    let rod = Rod::new(wire);
    let a0 = Vector6::new(
        0.5937202326819415,
        0.09252962226563075,
        0.22039784569461396,
        -0.9904921997527287,
        0.22014866194048108,
        0.11854114487421798,
    );
    let v = Vector6::new(
        0.13832697916042744,
        -0.027294213441783757,
        -0.10885668370481945,
        -0.2009459962608535,
        0.2074229968313005,
        -0.08020747584733853,
    );
    let refine = 64;
    assert!(rod.jacobian(&a0).expect("solves").stability.stable);
    assert!(one_sign(&dense_det(&rod, &a0, refine).0));
    let (mut dips, mut narrowest) = (0, f64::INFINITY);
    for i in 0..=50 {
        let s = 2.45 + 0.01 * f64::from(i);
        let a = a0 + s * v;
        let solution = rod.jacobian(&a).expect("solves");
        let stability = &solution.stability;
        let (dense, spacing) = dense_det(&rod, &a, refine);
        let negative: Vec<f64> = dense
            .iter()
            .enumerate()
            .filter(|(_, d)| d.signum() != dense[0].signum())
            .map(|(k, _)| (k + refine) as f64 * spacing)
            .collect();
        if !one_sign(&stability.det_j) || negative.is_empty() {
            continue;
        }
        dips += 1;
        let (first, last) = (negative[0], negative[negative.len() - 1]);
        narrowest = narrowest.min(last - first + spacing);
        // The dip lies inside one step, and the solver reports that step.
        let h = stability.spacing;
        let step = (first / h).floor();
        assert!(
            last < (step + 1.0) * h,
            "s = {s}: dip [{first}, {last}] spans grid points"
        );
        assert!(
            !stability.stable,
            "s = {s}: the dip [{first}, {last}] was missed"
        );
        let [t0, t1] = stability.first_sign_change.expect("a sign change");
        assert!(
            t0 <= first && last <= t1,
            "s = {s}: [{t0}, {t1}] vs [{first}, {last}]"
        );
        assert!(!rod.is_stable(&a).expect("solves"), "s = {s}: early exit");
    }
    assert!(
        dips >= 40,
        "only {dips} configurations dip between grid points"
    );
    assert!(
        narrowest < 0.002,
        "the narrowest dip is {narrowest} m wide: no fold here"
    );
}

/// Over random configurations (half stable, half not; a round and an anisotropic wire, and
/// the round one under its weight), the solver's verdict is the dense reference's: `det J`
/// of one sign at 32 times the grid points (or at 256 times, where the 32-fold grid steps
/// over a dip narrower than its own spacing that the solver found).
#[test]
fn agrees_with_a_dense_reference() {
    let round = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid");
    let anisotropic = WireParams::new([1.3, 1.0, 0.6], 1.0, 0.001).expect("valid");
    let weight = Load::from_gravity(6450.0, 0.001, Vector3::new(0.0, 0.0, -9.81)).expect("valid");
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    for (rod, half_width, count) in [
        (Rod::new(round), 10.0, 300),
        (Rod::new(anisotropic), 7.0, 300),
        (Rod::new(round).with_load(weight), 8.0, 100),
    ] {
        let sampler = Sampler::new(half_width).expect("valid");
        let mut stable = 0;
        for _ in 0..count {
            let a = sampler.sample_a(&rod, &mut rng);
            let ours = rod.jacobian(&a).expect("solves").stability.stable;
            let mut reference = one_sign(&dense_det(&rod, &a, 32).0);
            if ours != reference {
                reference = one_sign(&dense_det(&rod, &a, 256).0);
            }
            assert_eq!(ours, reference, "a = {a}");
            stable += usize::from(ours);
        }
        assert!(
            stable > count / 5 && stable < 4 * count / 5,
            "{stable} of {count} stable"
        );
    }
}

/// The study behind `docs/integrator.md`'s table on the test between grid points: over random
/// configurations of two wires at several sampling half-widths, how often the grid points alone
/// and the full test disagree with the dense reference (32 times the grid points). Run with
/// `cargo test -p ftwire-rod --release --test stability -- --ignored --nocapture study`.
#[test]
#[ignore]
fn study() {
    let wires = [
        ("2 mm nitinol", [0.042, 0.055, 0.055], 0.63),
        ("anisotropic", [1.3, 1.0, 0.6], 1.0),
    ];
    println!(
        "| wire | half-width | configurations | dense unstable | grid points wrong | test wrong |"
    );
    println!("| --- | --- | --- | --- | --- | --- |");
    for (name, c, length) in wires {
        let rod = Rod::new(WireParams::new(c, length, 0.001).expect("valid"));
        for half_width in [5.0, 10.0, 20.0] {
            let sampler = Sampler::new(half_width).expect("valid");
            let mut rng = ChaCha8Rng::seed_from_u64(7);
            let (count, mut unstable, mut grid_wrong, mut wrong) = (2000, 0, 0, 0);
            for _ in 0..count {
                let a = sampler.sample_a(&rod, &mut rng);
                let stability = rod.jacobian(&a).expect("solves").stability;
                let reference = one_sign(&dense_det(&rod, &a, 32).0);
                unstable += usize::from(!reference);
                grid_wrong += usize::from(one_sign(&stability.det_j) != reference);
                wrong += usize::from(stability.stable != reference);
            }
            println!("| {name} | {half_width} | {count} | {unstable} | {grid_wrong} | {wrong} |");
        }
    }
}
