//! The Levenberg–Marquardt Jacobian of the identification residual against a known derivative
//! and against a second finite-difference step.

mod identify_common;

use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::identify::{
    LevenbergMarquardt, ParameterConstraints, ResidualForm, Residuals, Sample, Weights,
};
use ftwire_estimate::{EstimateError, WireModel};
use identify_common::{samples, thick, thin};

/// Three exact samples of `model` (seeded) as identification samples.
fn exact_samples(model: &KirchhoffModel, seed: u64) -> Result<Vec<Sample>, EstimateError> {
    samples(model, seed, 3, 0.5, None)?
        .iter()
        .enumerate()
        .map(|(i, (a, b))| Sample::new(i, *a, *b))
        .collect()
}

/// The absolute residual of `samples`, default constraints, `ℓ = 0.5 m`, unwhitened.
fn absolute<'a>(model: &'a KirchhoffModel, samples: &'a [Sample]) -> Residuals<'a, KirchhoffModel> {
    Residuals {
        model,
        samples,
        form: ResidualForm::Absolute,
        weights: Weights {
            length_scale: 0.5,
            tangent_rotation: 1.0,
        },
        constraints: ParameterConstraints::default(),
        whitening: None,
    }
}

#[test]
fn lm_jacobian_matches_known_derivative() -> Result<(), EstimateError> {
    for model in [thick()?, thin()?] {
        for seed in 0..4 {
            let samples = exact_samples(&model, 500 + seed)?;
            let residuals = absolute(&model, &samples);
            let (constraints, weights) = (residuals.constraints, residuals.weights);
            let wire = model.wire();
            let theta = constraints.theta(wire.c(), wire.length(), 0.0);
            let f = |x: &[f64]| residuals.evaluate(x);
            let (lower, upper) = constraints.bounds(0.2);
            let jac =
                LevenbergMarquardt::jacobian(&f, &theta, &lower, &upper, 1e-5, residuals.len());
            // At an exact fit, ∂/∂L log(Γ_L⁻¹ b) = −(u(L), e1), u = μ(L)/c (the body twist of
            // q at the tip, paper eq. 1).
            let c = wire.c();
            for (i, s) in samples.iter().enumerate() {
                let mu = model.jacobian(&s.a)?.costate_tip;
                let xi =
                    nalgebra::Vector6::new(mu[0] / c[0], mu[1] / c[1], mu[2] / c[2], 1.0, 0.0, 0.0);
                let expected = -weights.apply(&xi);
                let got = jac.fixed_view::<6, 1>(6 * i, 3).into_owned();
                let gap = (got - expected).norm() / expected.norm();
                assert!(
                    gap < 1e-6,
                    "seed {seed} sample {i}: L column off by {gap:.1e}"
                );
            }
            // Every column against a step ten times larger.
            let coarse =
                LevenbergMarquardt::jacobian(&f, &theta, &lower, &upper, 1e-4, residuals.len());
            let gap = (&coarse - &jac).norm() / jac.norm();
            assert!(
                gap < 1e-5,
                "seed {seed}: steps 1e-4 and 1e-5 differ by {gap:.1e}"
            );
        }
    }
    Ok(())
}

/// The whitening of each residual turns the covariance the noise model predicts into the
/// identity: `L_i⁻¹ W (Σ_b + J_i Σ_a J_iᵀ) W L_i⁻ᵀ = I`, with `J_i` solved here independently.
#[test]
fn whitening_makes_the_predicted_residual_covariance_the_identity() -> Result<(), EstimateError> {
    let noise = ftwire_estimate::identify::MeasurementNoise::default();
    for model in [thick()?, thin()?] {
        let samples = exact_samples(&model, 700)?;
        let residuals = absolute(&model, &samples);
        let (constraints, weights) = (residuals.constraints, residuals.weights);
        let wire = model.wire();
        let theta = constraints.theta(wire.c(), wire.length(), 0.0);
        let whitened = residuals.whitening(&theta, &noise)?;
        let ftwire_estimate::identify::Whitening::Blocks(whitening) = &whitened else {
            panic!("samples without times are whitened one by one");
        };
        assert_eq!(whitening.len(), samples.len());
        let w = weights.matrix();
        for (white, s) in whitening.iter().zip(&samples) {
            let j = model.jacobian(&s.a)?.jacobian;
            let cov =
                w * (noise.pose_covariance() + j * noise.wrench_covariance() * j.transpose()) * w;
            let identity = white * cov * white.transpose();
            let gap = (identity - nalgebra::Matrix6::identity()).amax();
            assert!(
                gap < 1e-9,
                "whitened covariance off the identity by {gap:.1e}"
            );
        }
        // χ² is the whitened cost.
        let whitened = Residuals {
            whitening: Some(&whitened),
            ..residuals
        };
        let chi2 = residuals.chi_squared(&theta, &noise)?;
        assert!((chi2 - whitened.cost(&theta)).abs() <= 1e-12 * chi2.max(1e-300));
    }
    Ok(())
}
