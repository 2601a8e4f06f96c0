//! The stability test: Euler buckling, and the sign of det J at the first grid point.

mod common;

use ftwire_rod::{Integrator, Method, Rod, WireParams, from_normalised, sampling::Sampler};
use nalgebra::Vector6;
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
