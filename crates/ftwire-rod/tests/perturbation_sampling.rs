//! The perturbation map of paper eq. 8–11, and seeded sampling of A, A_stable and A_free.

use ftwire_rod::perturbation::{apply, delta_b, predict};
use ftwire_rod::{Rod, WireParams, batch, sampling::Sampler, to_normalised};
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn rod() -> Rod {
    Rod::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid"))
}

/// δb between Γ(a) and Γ(a + ε d) is J(L) ε d + O(ε²): the first-order error shrinks with ε².
#[test]
fn delta_b_is_j_delta_a_to_first_order() {
    let rod = rod();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let sampler = Sampler::default();
    for _ in 0..10 {
        let a = sampler.sample_stable(&rod, &mut rng).expect("stable");
        let direction = sampler.sample_a(&rod, &mut rng) * 0.01;
        let b = rod.tip(&a).expect("solves");
        let j = rod.jacobian(&a).expect("solves").jacobian;
        let residual = |eps: f64| {
            let db = delta_b(&b, &rod.tip(&(a + direction * eps)).expect("solves"));
            (db - predict(&j, &(direction * eps))).norm()
        };
        let (r1, r2) = (residual(1e-2), residual(5e-3));
        let first = predict(&j, &(direction * 1e-2)).norm();
        assert!(
            r1 < 0.05 * first,
            "residual {r1:e} vs first-order {first:e}"
        );
        assert!(r2 < 0.4 * r1, "not second order: {r1:e} then {r2:e}");
        // And b M(δb) recovers the perturbed pose (eq. 10).
        let next = rod.tip(&(a + direction * 1e-2)).expect("solves");
        let back = apply(&b, &delta_b(&b, &next));
        assert!((back.to_homogeneous() - next.to_homogeneous()).norm() < 1e-12);
    }
}

#[test]
fn sampling_is_seeded_and_lands_in_its_set() {
    let rod = rod();
    let sampler = Sampler::new(30.0).expect("valid");
    let draw = |seed| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..5)
            .map(|_| sampler.sample_free(&rod, &mut rng).expect("free"))
            .collect::<Vec<Vector6<f64>>>()
    };
    let (first, again, other) = (draw(9), draw(9), draw(10));
    assert_eq!(first, again);
    assert_ne!(first, other);
    for a in &first {
        assert!(to_normalised(rod.wire(), a).amax() <= 30.0);
        let s = rod.solve(a, 64).expect("solves");
        assert!(s.jacobian.stability.stable && !s.self_intersecting);
    }
    assert!(Sampler::new(0.0).is_err() && Sampler::new(f64::NAN).is_err());
}

#[test]
fn batch_matches_single_solves() {
    let rod = rod();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let sampler = Sampler::default();
    let configurations: Vec<_> = (0..20).map(|_| sampler.sample_a(&rod, &mut rng)).collect();
    let solved = batch::solve_all(&rod, &configurations, 16);
    let stable = batch::stable_all(&rod, &configurations);
    for ((a, s), st) in configurations.iter().zip(&solved).zip(&stable) {
        let single = rod.solve(a, 16).expect("solves");
        let s = s.as_ref().expect("solves");
        assert_eq!(s, &single);
        assert_eq!(
            *st.as_ref().expect("solves"),
            single.jacobian.stability.stable
        );
    }
}
