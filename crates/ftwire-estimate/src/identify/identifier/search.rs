//! Steps 1 to 3 of the driver's search ([`Identifier`]): the search boxes for the current
//! samples, the coarse constraints, the fine fits from the swarm's distinct bests, and whether
//! a fit is in the wrong basin.

use rand::Rng;

use super::Identifier;
use super::objectives::{Objectives, SearchSpace, clamp, prior_linear_density};
use crate::identify::parameters::L_MIN;
use crate::identify::refine::Refined;
use crate::identify::{
    Estimate, ParameterConstraints, ResidualForm, Sample, Swarm, Unidentified, Weights,
};
use crate::{EstimateError, WireModel};

/// Most samples of a fit whose samples share the sensor's bias or gain
/// ([`MeasurementNoise`](crate::identify::MeasurementNoise) with a bias drift or a gain error, the
/// absolute residual): their errors are correlated between every pair, so the fit whitens with the
/// Cholesky factor of a dense `6N × 6N` covariance, `3 · 288 N²` bytes (216 MB at this bound), and
/// its time grows as `N³`. More is refused before any work.
pub const MAX_SHARED_SAMPLES: usize = 500;

impl<M: WireModel, R: Rng> Identifier<M, R> {
    /// The search boxes for the current samples and the residual weighting.
    pub(super) fn search_space(&self) -> Result<SearchSpace, EstimateError> {
        let unknowns = self.config.constraints.unknowns();
        let form = self.config.form;
        let required = (2..).find(|m| form.equations(*m) > unknowns).unwrap_or(2);
        if self.samples.len() < required {
            return Err(EstimateError::TooFewSamples {
                samples: self.samples.len(),
                required,
                unknowns,
                form: form.name(),
            });
        }
        if form == ResidualForm::Absolute
            && self.samples.len() > MAX_SHARED_SAMPLES
            && crate::identify::shared::shared_bias(&self.samples, &self.config.noise).is_some()
        {
            return Err(EstimateError::TooManySharedSamples {
                samples: self.samples.len(),
                max: MAX_SHARED_SAMPLES,
            });
        }
        let spread = self
            .config
            .noise
            .pose_spread(self.samples.iter().map(|s| &s.b));
        if spread < self.config.min_motion {
            return Err(EstimateError::DegenerateMotion {
                spread,
                required: self.config.min_motion,
            });
        }
        let chord = self.samples.iter().map(Sample::chord).fold(0.0, f64::max);
        let length_min = L_MIN.max(chord + self.config.length_margin);
        let (lower, upper) = self.config.constraints.bounds(length_min);
        let (coarse_lower, coarse_upper) = self.coarse_constraints().bounds(length_min);
        let (unweighed_lower, unweighed_upper) = ParameterConstraints {
            weight: None,
            ..self.config.constraints
        }
        .bounds(length_min);
        let first_chord = self.samples.first().map_or(0.0, Sample::chord);
        let length_scale = self.config.length_scale.unwrap_or(first_chord.max(0.05));
        Ok(SearchSpace {
            lower,
            upper,
            coarse_lower,
            coarse_upper,
            unweighed_lower,
            unweighed_upper,
            weights: Weights {
                length_scale,
                tangent_rotation: 1.0,
            },
            search_whitening: crate::identify::joint::search_weights(
                &self.samples,
                self.config.form,
                &self.config.noise,
            ),
        })
    }

    /// Step 2 of the driver for one round: the fine fit from each of the swarm's distinct personal
    /// bests ([`IdentifierParams::refine_starts`](super::IdentifierParams::refine_starts), at least
    /// 1 % of the box's narrowest side apart), and the one of lowest `χ²` with its `χ²`; also the
    /// residual evaluations spent.
    ///
    /// Fits are compared by `χ²`, not by the fixed weighting's cost: a wrong basin can leave
    /// small pose residuals where the noise predicts even smaller ones (a far too stiff wire
    /// barely moves with the wrench).
    pub(super) fn refine_round(
        &self,
        objectives: &Objectives<'_, M>,
        swarm: &Swarm,
        space: &SearchSpace,
    ) -> (Option<(Refined, f64)>, usize) {
        let span = space
            .coarse_lower
            .iter()
            .zip(&space.coarse_upper)
            .map(|(l, u)| u - l)
            .fold(f64::INFINITY, f64::min);
        let mut evaluations = 0;
        let mut round_best: Option<(Refined, f64)> = None;
        for start in swarm.distinct_bests(self.config.refine_starts, 0.01 * span) {
            let (refined, spent) = self.refine_from(objectives, &start, space);
            evaluations += spent;
            let chi2 = objectives
                .fine
                .chi_squared(&refined.theta, &self.config.noise)
                .unwrap_or(f64::INFINITY);
            if round_best.as_ref().is_none_or(|(_, b)| chi2 < *b) {
                round_best = Some((refined, chi2));
            }
        }
        (round_best, evaluations)
    }

    /// The fine fit from one coarse start: Levenberg–Marquardt in the coarse parameters, then,
    /// when the configured parameters differ, in those from the coarse optimum (through the
    /// fit without the weight first when the weight is identified); also the residual
    /// evaluations spent.
    fn refine_from(
        &self,
        objectives: &Objectives<'_, M>,
        start: &[f64],
        space: &SearchSpace,
    ) -> (Refined, usize) {
        let coarse = objectives.coarse.constraints;
        let full = objectives.fine.constraints;
        let unweighed = objectives.unweighed.constraints;
        let coarse_residual = |theta: &[f64]| objectives.coarse.evaluate(theta);
        let fine_residual = |theta: &[f64]| objectives.fine.evaluate(theta);
        let unweighed_residual = |theta: &[f64]| objectives.unweighed.evaluate(theta);
        let mut refined = self.config.refine.minimise(
            &coarse_residual,
            start,
            &space.coarse_lower,
            &space.coarse_upper,
        );
        let mut evaluations = refined.evaluations;
        if coarse != full {
            let (mut c, mut length) = coarse.eta(&refined.theta);
            if full.weight.is_some() {
                // Free c and L with the weight at its prior first: the fit with the weight free
                // then starts in the right basin (from the coarse optimum it could trade
                // torsion for weight and wander off).
                let start = clamp(
                    unweighed.theta(c, length, 0.0),
                    &space.unweighed_lower,
                    &space.unweighed_upper,
                );
                let step = self.config.refine.minimise(
                    &unweighed_residual,
                    &start,
                    &space.unweighed_lower,
                    &space.unweighed_upper,
                );
                evaluations += step.evaluations;
                (c, length) = unweighed.eta(&step.theta);
            }
            let lambda = full
                .weight
                .map_or(0.0, |g| prior_linear_density(&self.model, &g));
            let start = clamp(full.theta(c, length, lambda), &space.lower, &space.upper);
            refined =
                self.config
                    .refine
                    .minimise(&fine_residual, &start, &space.lower, &space.upper);
            evaluations += refined.evaluations;
        }
        (refined, evaluations)
    }

    /// Whether a fit is most likely in the wrong basin, to be searched again (step 3): far
    /// above the noise whatever else is wrong with it (a wrong basin is often ill-conditioned
    /// too), or flagged above the noise or at the box's edge.
    pub(super) fn is_wrong_basin(&self, estimate: &Estimate) -> bool {
        estimate.chi2_per_dof > self.config.max_chi2_per_dof
            || matches!(
                estimate.unidentified,
                Some(Unidentified::ResidualAboveNoise { .. } | Unidentified::AtBound { .. })
            )
    }

    /// The constraints of the swarm's coarse search: the configured ones, plus isotropic
    /// bending and the coarse torsion ratio where they leave a parameter free.
    pub(super) fn coarse_constraints(&self) -> ParameterConstraints {
        let k = self.config.constraints;
        ParameterConstraints {
            isotropic: true,
            torsion_ratio: k.torsion_ratio.or(Some(self.config.coarse_torsion_ratio)),
            stiffness_per_length: true,
            // The weight stays at its prior in the coarse search.
            weight: None,
        }
    }
}
