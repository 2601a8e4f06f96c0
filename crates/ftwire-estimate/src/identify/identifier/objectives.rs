//! What one search of the driver runs on: the boxes of its parameterisations and the
//! weighting ([`SearchSpace`]), its three residuals ([`Objectives`]), the swarm it resumes,
//! the provisional estimate of an unfinished search, and the weight's prior.

use nalgebra::Vector3;
use rand::Rng;

use super::params::IdentifierParams;
use crate::WireModel;
use crate::identify::parameters::{LAMBDA_MAX, LAMBDA_MIN};
use crate::identify::{
    CostFunction, Estimate, ParameterConstraints, ParticleSwarm, Residuals, Sample, Swarm,
    Unidentified, Weights, Whitening,
};

/// The prior linear density of a weight identification when the model has none \[kg/m\]:
/// about a 2.5 mm steel or nitinol wire (the paper's nitinol wires are 0.020 and 0.046 kg/m).
pub const DEFAULT_LINEAR_DENSITY: f64 = 0.03;

/// The search boxes of the fine (configured) and coarse parameterisations, and the weighting.
#[derive(Debug, Clone)]
pub(super) struct SearchSpace {
    pub(super) lower: Vec<f64>,
    pub(super) upper: Vec<f64>,
    pub(super) coarse_lower: Vec<f64>,
    pub(super) coarse_upper: Vec<f64>,
    /// The box of the configured parameters without the weight.
    pub(super) unweighed_lower: Vec<f64>,
    pub(super) unweighed_upper: Vec<f64>,
    pub(super) weights: Weights,
    /// The search's per-sample weights under a shared bias
    /// ([`crate::identify::joint::search_weights`]).
    pub(super) search_whitening: Option<Whitening>,
}

/// The residuals of one search: the coarse swarm's (coarse parameters, no twist about the
/// tangent), the configured parameters' (the fine fit's), and the configured ones without the
/// weight.
pub(super) struct Objectives<'a, M: WireModel> {
    pub(super) coarse: Residuals<'a, M>,
    pub(super) fine: Residuals<'a, M>,
    pub(super) unweighed: Residuals<'a, M>,
}

impl<'a, M: WireModel> Objectives<'a, M> {
    pub(super) fn new(
        model: &'a M,
        samples: &'a [Sample],
        config: &IdentifierParams,
        space: &'a SearchSpace,
        coarse: ParameterConstraints,
    ) -> Self {
        let residuals = |constraints| Residuals {
            model,
            samples,
            form: config.form,
            weights: space.weights,
            constraints,
            whitening: space.search_whitening.as_ref(),
        };
        let full = config.constraints;
        let coarse_weights = Weights {
            tangent_rotation: 0.0,
            ..space.weights
        };
        Self {
            coarse: Residuals {
                weights: coarse_weights,
                ..residuals(coarse)
            },
            fine: residuals(full),
            unweighed: residuals(ParameterConstraints {
                weight: None,
                ..full
            }),
        }
    }
}

/// The swarm to search on: the kept one, refreshed on the samples when they changed
/// (`stale`), or a new one.
pub(super) fn resume_swarm<F: CostFunction, R: Rng + ?Sized>(
    pso: &ParticleSwarm,
    cost: &F,
    kept: Option<Swarm>,
    stale: bool,
    rng: &mut R,
) -> Swarm {
    match kept {
        Some(mut swarm) => {
            if stale {
                pso.refresh(cost, &mut swarm, rng);
            }
            swarm
        }
        None => pso.init(cost, rng),
    }
}

/// `theta` clamped into the box.
pub(super) fn clamp(mut theta: Vec<f64>, lower: &[f64], upper: &[f64]) -> Vec<f64> {
    for ((x, l), u) in theta.iter_mut().zip(lower).zip(upper) {
        *x = x.clamp(*l, *u);
    }
    theta
}

/// An unrefined estimate at `theta`: no uncertainty.
pub(super) fn provisional<M: WireModel>(
    residuals: &Residuals<'_, M>,
    theta: &[f64],
    evaluations: usize,
    reason: Unidentified,
) -> Estimate {
    let (c, length) = residuals.constraints.eta(theta);
    Estimate {
        c,
        length,
        c_std: [f64::INFINITY; 3],
        length_std: f64::INFINITY,
        linear_density: None,
        linear_density_std: None,
        cost: residuals.cost(theta),
        chi2_per_dof: f64::INFINITY,
        condition: 0.0,
        samples: residuals.samples.len(),
        evaluations,
        unidentified: Some(reason),
        covariance: None,
    }
}

/// The prior linear density \[kg/m\] of a weight identification under gravity `g`: the model's
/// own weight along `g`, or [`DEFAULT_LINEAR_DENSITY`] for a weightless model, clamped into
/// the search box.
pub(super) fn prior_linear_density<M: WireModel>(model: &M, g: &Vector3<f64>) -> f64 {
    let w = model.weight_per_length().dot(g) / g.norm_squared();
    let lambda = if w > 0.0 { w } else { DEFAULT_LINEAR_DENSITY };
    lambda.clamp(LAMBDA_MIN, LAMBDA_MAX)
}
