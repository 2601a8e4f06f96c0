//! The calibration network's backpropagation gradient against central finite differences of
//! its loss, on random weights and data, for every activation and several depths.

use ftwire_estimate::calibration::{Activation, Mlp, parameter_count};
use nalgebra::Vector6;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

fn random_vector(rng: &mut ChaCha8Rng, scale: f64) -> Vector6<f64> {
    Vector6::from_fn(|_, _| scale * rng.sample::<f64, _>(StandardNormal))
}

/// Every gradient component matches `(L(θ + h eᵢ) − L(θ − h eᵢ)) / 2h` to within the
/// difference's own error (`h = 1e-6`: truncation ~1e-12, rounding ~1e-10).
fn check(hidden: &[usize], activation: Activation, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // Weights of order one, so that the activations work in their nonlinear range.
    let parameters: Vec<f64> = (0..parameter_count(hidden))
        .map(|_| 0.8 * rng.sample::<f64, _>(StandardNormal))
        .collect();
    let mlp = Mlp::from_parameters(hidden, activation, parameters.clone()).expect("valid net");
    let inputs: Vec<Vector6<f64>> = (0..7).map(|_| random_vector(&mut rng, 1.5)).collect();
    let targets: Vec<Vector6<f64>> = (0..7).map(|_| random_vector(&mut rng, 1.0)).collect();
    let (loss, gradient) = mlp.loss_and_gradient(&inputs, &targets).expect("paired");
    let direct = mlp.loss(&inputs, &targets).expect("paired");
    approx::assert_relative_eq!(loss, direct, max_relative = 1e-12);

    let h = 1e-6;
    let loss_at = |i: usize, delta: f64| {
        let mut p = parameters.clone();
        p[i] += delta;
        Mlp::from_parameters(hidden, activation, p)
            .expect("valid net")
            .loss(&inputs, &targets)
            .expect("paired")
    };
    let mut nonzero = 0;
    for (i, g) in gradient.iter().enumerate() {
        let numeric = (loss_at(i, h) - loss_at(i, -h)) / (2.0 * h);
        assert!(
            (g - numeric).abs() <= 1e-7 * (1.0 + numeric.abs()),
            "{activation:?} {hidden:?} seed {seed}: parameter {i}: backprop {g}, finite \
             difference {numeric}"
        );
        if numeric.abs() > 1e-6 {
            nonzero += 1;
        }
    }
    // The check is not vacuous: most components are far from zero.
    assert!(
        nonzero * 2 > gradient.len(),
        "{nonzero} of {}",
        gradient.len()
    );
}

#[test]
fn tanh_gradient_matches_finite_differences() {
    for seed in 0..4 {
        check(&[5, 4], Activation::Tanh, seed);
        check(&[7], Activation::Tanh, 10 + seed);
        check(&[3, 4, 5], Activation::Tanh, 20 + seed);
    }
}

#[test]
fn gelu_gradient_matches_finite_differences() {
    for seed in 0..4 {
        check(&[5, 4], Activation::Gelu, seed);
        check(&[3, 4, 5], Activation::Gelu, 20 + seed);
    }
}

#[test]
fn affine_network_gradient_matches_finite_differences() {
    check(&[], Activation::Tanh, 3);
}

/// The activations' derivatives against central differences over a range of arguments.
#[test]
fn activation_derivatives_match_finite_differences() {
    let h = 1e-6;
    for activation in [Activation::Tanh, Activation::Gelu] {
        for k in -40..=40 {
            let x = f64::from(k) * 0.1;
            let (value, derivative) = activation.value_and_derivative(x);
            approx::assert_relative_eq!(value, activation.value(x), max_relative = 1e-15);
            let numeric = (activation.value(x + h) - activation.value(x - h)) / (2.0 * h);
            approx::assert_abs_diff_eq!(derivative, numeric, epsilon = 1e-8);
        }
    }
}

/// Mismatched inputs and targets are an error, not a panic.
#[test]
fn mismatched_pairs_are_rejected() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mlp = Mlp::new(&[4], Activation::Tanh, &mut rng).expect("valid net");
    let inputs = vec![Vector6::zeros(); 3];
    let targets = vec![Vector6::zeros(); 2];
    assert!(mlp.loss(&inputs, &targets).is_err());
    assert!(mlp.loss_and_gradient(&inputs, &targets).is_err());
}
