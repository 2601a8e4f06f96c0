//! The settings of the identification driver ([`super::Identifier`]).

use crate::EstimateError;
use crate::identify::{
    LevenbergMarquardt, MeasurementNoise, ParameterConstraints, ParticleSwarm, ResidualForm,
};

/// Identification settings (a parameter bundle; checked when identification starts).
#[derive(Debug, Clone, PartialEq)]
pub struct IdentifierParams {
    /// The residual minimised (default [`ResidualForm::Absolute`]).
    pub form: ResidualForm,
    /// Known relations between the parameters (default none).
    pub constraints: ParameterConstraints,
    /// The reference length `ℓ` \[m\] that divides translation residuals (see
    /// [`crate::identify::residual`]), or `None` for the gripper distance of the first sample, at least
    /// 5 cm (default `None`).
    pub length_scale: Option<f64>,
    /// How much longer than the largest gripper distance `|p(b̃_i)|` the wire must be \[m\]
    /// (default `5e-4`): the lower bound of `L` is `max(0.2, max_i |p(b̃_i)| + margin)`.
    pub length_margin: f64,
    /// The swarm settings (20 particles, `ω = φp = φg = 0.5`, 2 re-injected; its box is
    /// replaced by the search box).
    pub swarm: ParticleSwarm,
    /// Swarm iterations on each new set of samples before refinement (default `20`).
    pub swarm_iterations: usize,
    /// The torsion ratio `c1/c2` of the swarm's coarse search (default `0.8`, a round rod of
    /// Poisson's ratio 0.25), where the fine fit starts `c1` from; see [`crate::identify::identifier`].
    pub coarse_torsion_ratio: f64,
    /// The local refinement (default [`LevenbergMarquardt::default`]).
    pub refine: LevenbergMarquardt,
    /// Distinct swarm personal bests to refine from, best first (default `3`).
    pub refine_starts: usize,
    /// Search rounds at most (default `3`): when the refined fit is far above the noise or on
    /// the box's edge (most likely the wrong basin), the worse half of the swarm is re-injected
    /// at random and the swarm runs [`IdentifierParams::swarm_iterations`] more before refining
    /// again; the best fit of all rounds is kept.
    pub search_rounds: usize,
    /// The measurement noise, to whiten the residuals of the final polish and to test the final
    /// fit (default [`MeasurementNoise::default`]).
    pub noise: MeasurementNoise,
    /// Whether the search's best fit is polished on the noise-whitened residuals (step 4 of
    /// [`crate::identify::identifier`]; default `true`).
    pub polish: bool,
    /// The smallest motion of the second gripper accepted, in noise standard deviations of the
    /// largest pose component (default `10`).
    pub min_motion: f64,
    /// The largest `χ²/dof` accepted (default `25`: a residual RMS 5× the noise).
    pub max_chi2_per_dof: f64,
    /// The smallest `σ_min/σ_max` of the residual's Jacobian in `(ln c, ln L)` accepted
    /// (default `1e-4`: a parameter combination `1e4` times less visible than the best
    /// one is determined `1e4` times less precisely, tens of per cent at this noise).
    pub min_condition: f64,
    /// The wire model's own relative error in each identified parameter against the wire, a
    /// fraction (default `0`): what the model leaves out (a simulator's discretisation, a real
    /// wire's imperfections) biases the estimate by about this much whatever the number of
    /// samples, so `ε²` is added to each parameter's relative variance (`c`, `L` and `λ`;
    /// parameters tied to another share its error).
    pub model_error: f64,
}

impl Default for IdentifierParams {
    fn default() -> Self {
        Self {
            form: ResidualForm::default(),
            constraints: ParameterConstraints::default(),
            length_scale: None,
            length_margin: 5e-4,
            swarm: ParticleSwarm::default(),
            swarm_iterations: 20,
            coarse_torsion_ratio: 0.8,
            refine: LevenbergMarquardt::default(),
            refine_starts: 3,
            search_rounds: 3,
            noise: MeasurementNoise::default(),
            polish: true,
            min_motion: 10.0,
            max_chi2_per_dof: 25.0,
            min_condition: 1e-4,
            model_error: 0.0,
        }
    }
}

impl IdentifierParams {
    /// Checks every setting.
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] naming the first bad one.
    pub fn validate(&self) -> Result<(), EstimateError> {
        self.constraints.validate()?;
        self.noise.validate()?;
        self.refine.validate()?;
        let bad = |field, value: f64, allowed| {
            Err(EstimateError::BadIdentifySetting {
                field,
                value,
                allowed,
            })
        };
        if let Some(l) = self.length_scale.filter(|l| !(l.is_finite() && *l > 0.0)) {
            return bad("length_scale", l, "finite and > 0");
        }
        if !(self.length_margin.is_finite() && self.length_margin >= 0.0) {
            return bad("length_margin", self.length_margin, "finite and >= 0");
        }
        if !(self.coarse_torsion_ratio.is_finite() && self.coarse_torsion_ratio > 0.0) {
            return bad(
                "coarse_torsion_ratio",
                self.coarse_torsion_ratio,
                "finite and > 0",
            );
        }
        if self.refine_starts == 0 {
            return bad("refine_starts", 0.0, "at least 1");
        }
        if self.search_rounds == 0 {
            return bad("search_rounds", 0.0, "at least 1");
        }
        for (field, value) in [
            ("min_motion", self.min_motion),
            ("max_chi2_per_dof", self.max_chi2_per_dof),
            ("min_condition", self.min_condition),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return bad(field, value, "finite and >= 0");
            }
        }
        if !(self.model_error.is_finite() && (0.0..1.0).contains(&self.model_error)) {
            return bad(
                "model_error",
                self.model_error,
                "finite, from 0 to below 1 (a fraction of each parameter)",
            );
        }
        Ok(())
    }
}
