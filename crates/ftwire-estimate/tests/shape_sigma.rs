//! The shape's error bars: the central differences of `shape_jacobians` against the analytic
//! `∂p(s)/∂a` of `centreline_point` at every node over random configurations of two wires,
//! `σ = sqrt(trace D Σ Dᵀ)`, the estimator's `sigma`, and bad standard deviations refused.

use ftwire_core::WireParams;
use ftwire_estimate::shape::{
    ConfigurationStd, ShapeEstimator, centreline_point, shape_jacobians, shape_sigma,
};
use ftwire_estimate::{EstimateError, KirchhoffModel, WireModel};
use ftwire_rod::from_normalised;
use ftwire_rod::sampling::Sampler;
use nalgebra::{Matrix6, Vector6};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn two_mm() -> Result<KirchhoffModel, EstimateError> {
    Ok(KirchhoffModel::new(WireParams::new(
        [0.042, 0.055, 0.055],
        0.63,
        0.001,
    )?))
}

fn three_mm() -> Result<KirchhoffModel, EstimateError> {
    Ok(KirchhoffModel::new(WireParams::new(
        [0.214, 0.278, 0.278],
        0.82,
        0.0015,
    )?))
}

/// At every node of a 64-node shape, each column of the difference Jacobian (in normalised
/// units: times `c2/L` or `c2/L²`) agrees with the analytic one to 1e-4 of the node's
/// Jacobian norm.
#[test]
fn differences_match_the_analytic_jacobian_at_every_node() -> Result<(), EstimateError> {
    const NODES: usize = 64;
    let mut worst: f64 = 0.0;
    for (model, seed) in [(two_mm()?, 21), (three_mm()?, 22)] {
        let wire = *model.wire();
        let scales = from_normalised(&wire, &Vector6::repeat(1.0));
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let sampler = Sampler::new(10.0)?;
        for _ in 0..6 {
            let a = sampler.sample_a(model.rod(), &mut rng);
            let differences = shape_jacobians(&model, &a, NODES)?;
            let shape = model.shape(&a, NODES)?;
            for (node, d) in differences.iter().enumerate() {
                let s = shape.arc_length[node];
                let analytic = centreline_point(&model, &a, s, true)?.jacobian;
                let scale = (analytic * Matrix6::from_diagonal(&scales)).norm() + 1e-9;
                for i in 0..6 {
                    let error = (d.column(i) - analytic.column(i)).norm() * scales[i] / scale;
                    worst = worst.max(error);
                    assert!(
                        error <= 1e-4,
                        "column {i} at node {node} (s = {s}), a = {a:?}: relative error {error}"
                    );
                }
            }
        }
    }
    eprintln!("worst relative column error: {worst:.2e}");
    Ok(())
}

#[test]
fn sigma_is_the_root_of_the_trace_of_the_point_covariance() -> Result<(), EstimateError> {
    let model = two_mm()?;
    let a = Vector6::new(0.01, 0.02, 0.01, -0.05, 0.03, 0.02);
    let std = ConfigurationStd::new([2e-4, 1e-4, 3e-4, 5e-3, 1e-2, 2e-3])?;
    let sigma = shape_sigma(&model, &a, 50, &std.covariance())?;
    let jacobians = shape_jacobians(&model, &a, 50)?;
    assert_eq!(sigma.sigma.len(), 50);
    for ((s, c), d) in sigma.sigma.iter().zip(&sigma.covariance).zip(&jacobians) {
        // trace(D Σ Dᵀ) = Σ_j σ_j² ‖D e_j‖².
        let trace: f64 = (0..6)
            .map(|j| (std.std()[j] * d.column(j).norm()).powi(2))
            .sum();
        assert!(
            (s * s - trace).abs() <= 1e-12 * trace.max(1e-30),
            "{s}² vs {trace}"
        );
        assert!((c - c.transpose()).amax() <= 1e-18);
        assert!(c.symmetric_eigenvalues().min() >= -1e-18);
    }
    // The clamp is fixed, the tip moves.
    assert!(sigma.sigma[0] < 1e-12);
    assert!(sigma.sigma[49] > 1e-4);
    // σ is linear in the standard deviations.
    let double = ConfigurationStd::new(std.std().map(|v| 2.0 * v).into())?;
    let twice = shape_sigma(&model, &a, 50, &double.covariance())?;
    for (s, t) in sigma.sigma.iter().zip(&twice.sigma) {
        assert!((2.0 * s - t).abs() <= 1e-12 + 1e-9 * t);
    }
    Ok(())
}

#[test]
fn the_estimator_carries_sigma_only_when_given_the_standard_deviations() -> Result<(), EstimateError>
{
    let model = two_mm()?;
    let a = Vector6::new(0.0, 0.02, 0.01, -0.05, 0.03, 0.0);
    let mut plain = ShapeEstimator::new(model);
    assert!(plain.estimate(&a)?.sigma.is_none());
    let std = ConfigurationStd::new([1e-4, 1e-4, 1e-4, 1e-2, 1e-2, 1e-2])?;
    let mut with = ShapeEstimator::new(model).with_a_std(Some(std));
    let estimate = with.estimate(&a)?;
    let sigma = estimate.sigma.expect("sigma with standard deviations");
    assert_eq!(sigma.len(), estimate.shape.len());
    let direct = shape_sigma(&model, &a, 64, &std.covariance())?;
    assert_eq!(sigma, direct.sigma);
    // The shape itself is the same.
    assert_eq!(estimate.shape, plain.estimate(&a)?.shape);
    Ok(())
}

#[test]
fn bad_standard_deviations_are_refused_by_name() {
    for (i, bad) in [f64::NAN, -1e-3, f64::INFINITY, 1e308]
        .into_iter()
        .enumerate()
    {
        let mut std = [0.0; 6];
        std[i + 1] = bad;
        let message = ConfigurationStd::new(std)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(message.contains("a_std"), "{message}");
        assert!(message.contains("from 0 to"), "{message}");
    }
    assert!(ConfigurationStd::new([0.0; 6]).is_ok());
}
