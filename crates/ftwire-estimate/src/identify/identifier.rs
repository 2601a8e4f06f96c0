//! The identification driver: batch ([`identify`]) and streaming ([`Identifier`]).
//!
//! One driver owns the loop:
//! 1. **coarse**: a particle swarm ([`super::pso`]) finds the basin in the 2-D space
//!    `(ln(c2/L), L)` of a round rod, `c3 = c2`, `c1 = ν0 c2` (`ν0` =
//!    [`IdentifierParams::coarse_torsion_ratio`], unless the configured constraints fix them),
//!    on a cost without the twist of the second gripper about the wire's tangent, and
//!    Levenberg–Marquardt ([`super::refine`]) polishes the few best distinct personal bests
//!    there;
//! 2. **fine**: Levenberg–Marquardt in the configured parameters, from each coarse optimum;
//!    the lowest cost wins, and is checked for identifiability ([`Estimate`]);
//! 3. **retry**: if that fit is far above the noise or on the box's edge (the wrong basin),
//!    half the swarm is re-injected at random and steps 1–2 run again, up to
//!    [`IdentifierParams::search_rounds`] rounds; the best fit is kept;
//! 4. **polish**: Levenberg–Marquardt from the best fit on the residuals whitened by the
//!    noise's predicted covariance (generalised least squares, [`super::residual`]), which
//!    the fixed weighting of steps 1–3 only approximates; for the absolute form jointly with
//!    what the samples share and each rest's own noise, relinearised at the estimated true
//!    configurations and, with many samples, continued from the fits of fewer
//!    ([`super::joint`]).
//!
//! Why two stages: in the full 4-D box, `c_i ∈ [1e-3, 5]`, the absolute residual is rugged
//! along `c1` (a tiny torsional stiffness spins the wire about its axis), and a 20-particle
//! swarm there can miss the basin of a stiff wire. Three choices make the 2-D coarse search
//! reliable, where the plain `(ln c2, L)` search at a fixed ratio can settle in a wrong basin,
//! at a half or a quarter of the stiffness:
//! - **stiffness per length** ([`ParameterConstraints::stiffness_per_length`]): the data pin
//!   `c/L`, so the basin is a thin valley along `c2 ∝ L`, one grid column in eighty wide; in
//!   `(ln(c2/L), L)` it runs straight along `L`;
//! - **no twist in the coarse cost** ([`super::Weights::tangent_rotation`] `= 0`): the
//!   identification motion twists the wire ([`super::MotionPlan`]), so the twist at the tip
//!   measures `c1`; at the coarse search's fixed ratio it misfits every candidate of a wire
//!   whose ratio differs (0.65 against 0.8), and without it the coarse cost barely depends on
//!   the ratio;
//! - **a stratified, over-sampled start** ([`super::ParticleSwarm::with_candidates`]): each
//!   particle the best of 10 Latin-hypercube candidates, so the narrow valley is found from the
//!   start.
//!
//! Fits are compared by χ² (a far too stiff wire can leave small pose residuals where the noise
//! predicts smaller ones still), and a fit far above the noise is searched again whatever else
//! is flagged (tests `absolute_form_recovers_both_nitinol_wires_…`,
//! `unseen_wires_with_sensor_noise_…`, the ignored `survey`, and the binary's ignored
//! `identify_unseen`). A wire far from these assumptions (`c3/c2` far from 1) can fall outside
//! the fine fit's basin; the result is then flagged by the χ² test, not returned as
//! identified.

use std::time::{Duration, Instant};

use ftwire_core::Pose;
use nalgebra::{DMatrix, Vector3, Vector6};
use rand::Rng;

use super::parameters::{L_MAX, L_MIN, LAMBDA_MAX, LAMBDA_MIN};

/// The prior linear density of a weight identification when the model has none \[kg/m\]:
/// about a 2.5 mm steel or nitinol wire (the paper's nitinol wires are 0.020 and 0.046 kg/m).
pub const DEFAULT_LINEAR_DENSITY: f64 = 0.03;
use super::refine::Refined;
use super::{
    CostFunction, Estimate, LevenbergMarquardt, MeasurementNoise, ParameterConstraints,
    ParameterCovariance, ParticleSwarm, ResidualForm, Residuals, Sample, Swarm, Unidentified,
    Weights, Whitening,
};
use crate::{EstimateError, WireModel};

/// Most samples of a fit whose samples share the sensor's bias or gain
/// ([`MeasurementNoise`] with a bias drift or a gain error, the absolute residual): their
/// errors are correlated between every pair, so the fit whitens with the Cholesky factor of
/// a dense `6N × 6N` covariance, `3 · 288 N²` bytes (216 MB at this bound), and its time
/// grows as `N³`. More is refused before any work.
pub const MAX_SHARED_SAMPLES: usize = 500;

mod batch;
mod params;
pub use batch::{identify, identify_samples};
pub use params::IdentifierParams;

/// Streaming identification for a sensor loop: [`Identifier::push`] samples as they come,
/// [`Identifier::step`] within a time budget each tick.
///
/// The work is a sequence of indivisible units (a swarm iteration: 20 residual evaluations; the
/// refinement: a few hundred), and `step` starts a unit only while its budget lasts, so the
/// results depend only on the data and the seed when each set of samples is run to
/// completion ([`Identifier::run_to_completion`]); how the work is cut into steps does not
/// matter. New samples make the swarm current ([`ParticleSwarm::refresh`]) and restart the
/// iteration count; how far the search got before they arrived does depend on the budgets,
/// so for a reproducible estimate run to completion after the last push.
///
/// # Example
/// ```
/// use std::time::Duration;
/// use ftwire_core::WireParams;
/// use ftwire_estimate::{KirchhoffModel, WireModel, identify::{IdentifierParams, Identifier}};
/// use nalgebra::Vector6;
/// use rand::SeedableRng;
/// let truth = KirchhoffModel::new(WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015)?);
/// let rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
/// let mut id = Identifier::new(truth, IdentifierParams::default(), rng)?;
/// for d in [0.0, 0.5, -0.4] {
///     let a = Vector6::new(0.05 * d, 0.1, 0.05, -0.2 + 0.2 * d, 0.3, 0.1 * d);
///     id.push(a, truth.tip(&a)?)?;
///     let _ = id.step(Duration::from_millis(20)); // an error until there are enough samples
/// }
/// let estimate = id.run_to_completion()?;
/// assert!((estimate.c[1] / 0.278 - 1.0).abs() < 1e-3);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Identifier<M: WireModel, R: Rng> {
    model: M,
    config: IdentifierParams,
    rng: R,
    samples: Vec<Sample>,
    swarm: Option<Swarm>,
    stale: bool,
    refined: Option<Estimate>,
    /// Search rounds completed on the current samples.
    round: usize,
    /// The best refinement on the current samples.
    best: Option<(Refined, f64)>,
    /// Residual evaluations spent in refinements since the start.
    refine_evaluations: usize,
}

impl<M: WireModel, R: Rng> Identifier<M, R> {
    /// A new identifier; `model` gives the model family (its radius and any load are kept), `rng`
    /// all the randomness.
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] for a bad setting.
    pub fn new(model: M, config: IdentifierParams, rng: R) -> Result<Self, EstimateError> {
        config.validate()?;
        // With the linear density identified, the model's weight along `g` is the prior the
        // coarse search holds fixed and the fine fit starts from.
        let model = match config.constraints.weight {
            Some(g) => model.with_weight_per_length(prior_linear_density(&model, &g) * g)?,
            None => model,
        };
        Ok(Self {
            model,
            config,
            rng,
            samples: Vec::new(),
            swarm: None,
            stale: true,
            refined: None,
            round: 0,
            best: None,
            refine_evaluations: 0,
        })
    }

    /// Adds a sample `(ã, b̃)`.
    ///
    /// # Errors
    /// [`EstimateError::NonFiniteSample`], [`EstimateError::SampleOutsideA`] or
    /// [`EstimateError::ChordTooLong`] naming the sample's index; the sample is not added.
    pub fn push(&mut self, a: Vector6<f64>, b: Pose) -> Result<(), EstimateError> {
        let sample = Sample::new(self.samples.len(), a, b)?;
        self.push_sample(sample)
    }

    /// Adds a sample `(ã, b̃)` taken `time` seconds after the sensor was tared: with a bias
    /// model ([`MeasurementNoise::bias`]) the final fit then estimates the bias's drift with the
    /// wire ([`super::drift`]).
    ///
    /// # Errors
    /// As [`Identifier::push`], and [`EstimateError::BadSampleTime`].
    pub fn push_at(&mut self, time: f64, a: Vector6<f64>, b: Pose) -> Result<(), EstimateError> {
        let index = self.samples.len();
        let sample = Sample::new(index, a, b)?.at(index, time)?;
        self.push_sample(sample)
    }

    /// Adds a sample, checked as [`Identifier::push_at`] checks its parts.
    ///
    /// # Errors
    /// As [`Identifier::push_at`].
    pub fn push_sample(&mut self, sample: Sample) -> Result<(), EstimateError> {
        let index = self.samples.len();
        let checked = Sample::new(index, sample.a, sample.b)?;
        let sample = match sample.time {
            Some(time) => checked.at(index, time)?,
            None => checked,
        };
        let max_length = L_MAX - self.config.length_margin;
        if sample.chord() > max_length {
            return Err(EstimateError::ChordTooLong {
                index,
                chord: sample.chord(),
                max_length: L_MAX,
            });
        }
        self.samples.push(sample);
        self.stale = true;
        self.refined = None;
        Ok(())
    }

    /// The samples so far.
    pub fn samples(&self) -> &[Sample] {
        &self.samples
    }

    /// The swarm, once started.
    pub fn swarm(&self) -> Option<&Swarm> {
        self.swarm.as_ref()
    }

    /// Runs swarm iterations and then the refinement while `budget` lasts (each started only
    /// within the budget), and returns the current estimate: refined if the search on the
    /// current samples is complete, otherwise the swarm's best, flagged
    /// [`Unidentified::Unfinished`].
    ///
    /// # Errors
    /// As [`identify`].
    pub fn step(&mut self, budget: Duration) -> Result<Estimate, EstimateError> {
        let start = Instant::now();
        self.run(|| start.elapsed() < budget)
    }

    /// Runs the search on the current samples to completion: deterministic for a given seed
    /// and sequence of pushes.
    ///
    /// # Errors
    /// As [`identify`].
    pub fn run_to_completion(&mut self) -> Result<Estimate, EstimateError> {
        self.run(|| true)
    }

    /// The search boxes for the current samples and the residual weighting.
    fn search_space(&self) -> Result<SearchSpace, EstimateError> {
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
            && super::shared::shared_bias(&self.samples, &self.config.noise).is_some()
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
            search_whitening: super::joint::search_weights(
                &self.samples,
                self.config.form,
                &self.config.noise,
            ),
        })
    }

    /// The driver (module docs): the coarse swarm's iterations of the current round while
    /// `more` allows, then the fine fits from its distinct bests, then a retry round or the
    /// polish. An unfinished round returns the swarm's best, flagged.
    fn run(&mut self, mut more: impl FnMut() -> bool) -> Result<Estimate, EstimateError> {
        if let Some(done) = self.refined {
            return Ok(done);
        }
        let space = self.search_space()?;
        let objectives = Objectives::new(
            &self.model,
            &self.samples,
            &self.config,
            &space,
            self.coarse_constraints(),
        );
        let cost = |theta: &[f64]| objectives.coarse.cost(theta);
        let pso = self
            .config
            .swarm
            .clone()
            .with_bounds(space.coarse_lower.clone(), space.coarse_upper.clone())?;
        let mut swarm = resume_swarm(&pso, &cost, self.swarm.take(), self.stale, &mut self.rng);
        if self.stale {
            self.round = 0;
            self.best = None;
        }
        self.stale = false;
        let outcome = loop {
            // Step 1, coarse: this round's swarm iterations, each started while `more` allows.
            let target = (self.round + 1) * self.config.swarm_iterations;
            while swarm.iterations < target && more() {
                pso.iterate(&cost, &mut swarm, &mut self.rng);
            }
            if swarm.iterations < target || !more() {
                break Ok(provisional(
                    &objectives.coarse,
                    &swarm.best_position,
                    swarm.evaluations + self.refine_evaluations,
                    Unidentified::Unfinished {
                        iterations: swarm.iterations,
                        required: target,
                    },
                ));
            }
            // Step 2, fine: the best fit of this round, kept if it beats the earlier rounds'.
            let (round_best, evaluations) = self.refine_round(&objectives, &swarm, &space);
            self.refine_evaluations += evaluations;
            if let Some(candidate) = round_best
                && self.best.as_ref().is_none_or(|(_, b)| candidate.1 < *b)
            {
                self.best = Some(candidate);
            }
            let Some((best, _)) = self.best.as_ref() else {
                break Err(EstimateError::BadIdentifySetting {
                    field: "refine_starts",
                    value: 0.0,
                    allowed: "at least 1",
                });
            };
            let total = swarm.evaluations + self.refine_evaluations;
            let estimate = match self.assess(&objectives.fine, best, &space, total, None) {
                Ok(estimate) => estimate,
                Err(e) => break Err(e),
            };
            if !self.is_wrong_basin(&estimate) || self.round + 1 >= self.config.search_rounds {
                // Step 4, polish.
                let polished = self
                    .config
                    .polish
                    .then(|| self.polish(&objectives.fine, best, &space, total));
                let estimate = polished.flatten().unwrap_or(estimate);
                self.refined = Some(estimate);
                break Ok(estimate);
            }
            // Step 3, retry: a fit the noise cannot explain is most likely the wrong basin.
            // Scatter the worse half of the swarm and search on.
            self.round += 1;
            let half = swarm.particles.len() / 2;
            pso.reinject(&cost, &mut swarm, &mut self.rng, half);
        };
        self.swarm = Some(swarm);
        outcome
    }

    /// Step 2 of the driver for one round: the fine fit from each of the swarm's distinct
    /// personal bests ([`IdentifierParams::refine_starts`], at least 1 % of the box's
    /// narrowest side apart), and the one of lowest `χ²` with its `χ²`; also the residual
    /// evaluations spent.
    ///
    /// Fits are compared by `χ²`, not by the fixed weighting's cost: a wrong basin can leave
    /// small pose residuals where the noise predicts even smaller ones (a far too stiff wire
    /// barely moves with the wrench).
    fn refine_round(
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
    fn is_wrong_basin(&self, estimate: &Estimate) -> bool {
        estimate.chi2_per_dof > self.config.max_chi2_per_dof
            || matches!(
                estimate.unidentified,
                Some(Unidentified::ResidualAboveNoise { .. } | Unidentified::AtBound { .. })
            )
    }

    /// The constraints of the swarm's coarse search: the configured ones, plus isotropic
    /// bending and the coarse torsion ratio where they leave a parameter free.
    fn coarse_constraints(&self) -> ParameterConstraints {
        let k = self.config.constraints;
        ParameterConstraints {
            isotropic: true,
            torsion_ratio: k.torsion_ratio.or(Some(self.config.coarse_torsion_ratio)),
            stiffness_per_length: true,
            // The weight stays at its prior in the coarse search.
            weight: None,
        }
    }

    /// Step 4 of the driver: Levenberg–Marquardt on the noise-whitened residuals from the
    /// search's best fit (generalised least squares, see [`super::residual`]; for the
    /// absolute form jointly with the samples' path, [`super::joint::polish_continued`]), and
    /// the estimate there.
    /// `None` when the whitening cannot be computed at the best fit (the model fails at a
    /// sample), or the independent-noise polish ends at a higher `χ²` (never expected: it
    /// starts from the best fit and only accepts steps that lower its cost); the caller keeps
    /// the unpolished estimate then.
    fn polish(
        &self,
        fine: &Residuals<'_, M>,
        best: &Refined,
        space: &SearchSpace,
        evaluations: usize,
    ) -> Option<Estimate> {
        let noise = &self.config.noise;
        let bounds = (&space.lower[..], &space.upper[..]);
        let (polished, samples, chi2) = match super::joint::polish_continued(
            fine,
            &best.theta,
            noise,
            &self.config.refine,
            bounds,
        ) {
            Some(joint) => {
                let chi2 = joint.refined.cost;
                let refined = Refined {
                    evaluations: joint.evaluations,
                    ..joint.refined
                };
                (refined, joint.samples, Some(chi2))
            }
            None => {
                let whitening = fine.whitening(&best.theta, noise).ok()?;
                let whitened = Residuals {
                    whitening: Some(&whitening),
                    ..*fine
                };
                let residual = |theta: &[f64]| whitened.evaluate(theta);
                let polished =
                    self.config
                        .refine
                        .minimise(&residual, &best.theta, bounds.0, bounds.1);
                let before = fine.chi_squared(&best.theta, noise).ok()?;
                let after = fine.chi_squared(&polished.theta, noise).ok()?;
                if after > before {
                    return None;
                }
                (polished, fine.samples.to_vec(), None)
            }
        };
        // Judge the polished fit exactly as the unpolished one: the fixed weighting's cost and
        // Jacobian (its conditioning threshold is in those units), at the polished θ, on the
        // samples the polish ended with.
        let fine = Residuals {
            samples: &samples,
            ..*fine
        };
        let unwhitened = |theta: &[f64]| fine.evaluate(theta);
        let residual = unwhitened(&polished.theta);
        let jacobian = LevenbergMarquardt::jacobian(
            &unwhitened,
            &polished.theta,
            bounds.0,
            bounds.1,
            self.config.refine.fd_step,
            residual.len(),
        );
        let judged = Refined {
            cost: residual.norm_squared(),
            residual,
            jacobian,
            theta: polished.theta.clone(),
            iterations: polished.iterations,
            evaluations: polished.evaluations + 1 + 2 * space.lower.len(),
        };
        let total = evaluations + judged.evaluations;
        self.assess(
            &fine,
            &judged,
            space,
            total,
            Some((&polished.jacobian, chi2)),
        )
        .ok()
    }

    /// The estimate at a refined optimum: uncertainty and identifiability.
    ///
    /// The standard deviations are first order: `s² (JᵀJ)⁻¹` of the fixed weighting's
    /// Jacobian, `s²` its cost per degree of freedom; or, after the polish, `(J_wᵀJ_w)⁻¹` of
    /// the whitened Jacobian `whitened` (the covariance of a generalised least-squares fit),
    /// inflated by `χ²/dof` when the fit is worse than the noise explains; `χ²` is the
    /// polish's own when it gives one (the joint fit's), otherwise the residuals'.
    fn assess(
        &self,
        residuals: &Residuals<'_, M>,
        best: &Refined,
        space: &SearchSpace,
        evaluations: usize,
        whitened: Option<(&DMatrix<f64>, Option<f64>)>,
    ) -> Result<Estimate, EstimateError> {
        let (lower, upper) = (&space.lower, &space.upper);
        let constraints = self.config.constraints;
        let (c, length) = constraints.eta(&best.theta);
        let p = best.theta.len();
        let dof = residuals.len().saturating_sub(p).max(1) as f64;
        // Condition in (ln c, ln L, ln λ): scale the L column by L.
        let l = constraints.length_index();
        let mut scaled: DMatrix<f64> = best.jacobian.clone();
        scaled.column_mut(l).scale_mut(length);
        let sv = scaled.singular_values();
        let (smax, smin) = (sv.max(), sv.min());
        let condition = if smax > 0.0 { smin / smax } else { 0.0 };
        let chi2 = match whitened.and_then(|(_, chi2)| chi2) {
            Some(chi2) => chi2,
            None => residuals.chi_squared(&best.theta, &self.config.noise)?,
        };
        let chi2_per_dof = chi2 / dof;
        let (jacobian, s2) = match whitened {
            Some((jw, _)) => (jw, chi2_per_dof.max(1.0)),
            None => (&best.jacobian, best.cost / dof),
        };
        let jtj = jacobian.transpose() * jacobian;
        // The fit's covariance in θ, with the model's own error: a relative variance ε² of
        // every search parameter (the stiffnesses and λ are searched as logarithms, L as
        // itself), which no number of samples lowers.
        let floor = self.config.model_error.powi(2);
        let theta_covariance = jtj.try_inverse().filter(|_| condition > 0.0).map(|inv| {
            let mut cov = inv * s2;
            for i in 0..p {
                cov[(i, i)] += floor * if i == l { length * length } else { 1.0 };
            }
            cov
        });
        let std: Vec<f64> = match &theta_covariance {
            Some(cov) => (0..p).map(|i| cov[(i, i)].max(0.0).sqrt()).collect(),
            None => vec![f64::INFINITY; p],
        };
        let covariance = theta_covariance.and_then(|cov| {
            let g = constraints.eta_jacobian(&best.theta);
            ParameterCovariance::from_matrix(&(&g * cov * g.transpose()))
        });
        let index = constraints.stiffness_index();
        let c_std = [0, 1, 2].map(|i| c[i] * std.get(index[i]).copied().unwrap_or(f64::INFINITY));
        let length_std = std.get(l).copied().unwrap_or(f64::INFINITY);
        let linear_density = constraints.linear_density(&best.theta);
        let linear_density_std =
            linear_density.map(|lambda| lambda * std.get(l + 1).copied().unwrap_or(f64::INFINITY));
        let at_bound = best.theta.iter().enumerate().find(|(i, v)| {
            let (l, u) = (lower[*i], upper[*i]);
            let tol = 1e-6 * (u - l);
            **v <= l + tol || **v >= u - tol
        });
        let unidentified = if condition < self.config.min_condition {
            Some(Unidentified::IllConditioned {
                condition,
                threshold: self.config.min_condition,
            })
        } else if let Some((index, value)) = at_bound {
            Some(Unidentified::AtBound {
                index,
                value: *value,
            })
        } else if chi2_per_dof > self.config.max_chi2_per_dof {
            Some(Unidentified::ResidualAboveNoise {
                chi2_per_dof,
                threshold: self.config.max_chi2_per_dof,
            })
        } else {
            None
        };
        Ok(Estimate {
            c,
            length,
            c_std,
            length_std,
            linear_density,
            linear_density_std,
            cost: best.cost,
            chi2_per_dof,
            condition,
            samples: self.samples.len(),
            evaluations,
            unidentified,
            covariance,
        })
    }
}

/// The search boxes of the fine (configured) and coarse parameterisations, and the weighting.
#[derive(Debug, Clone)]
struct SearchSpace {
    lower: Vec<f64>,
    upper: Vec<f64>,
    coarse_lower: Vec<f64>,
    coarse_upper: Vec<f64>,
    /// The box of the configured parameters without the weight.
    unweighed_lower: Vec<f64>,
    unweighed_upper: Vec<f64>,
    weights: Weights,
    /// The search's per-sample weights under a shared bias ([`super::joint::search_weights`]).
    search_whitening: Option<Whitening>,
}

/// The residuals of one search: the coarse swarm's (coarse parameters, no twist about the
/// tangent), the configured parameters' (the fine fit's), and the configured ones without the
/// weight.
struct Objectives<'a, M: WireModel> {
    coarse: Residuals<'a, M>,
    fine: Residuals<'a, M>,
    unweighed: Residuals<'a, M>,
}

impl<'a, M: WireModel> Objectives<'a, M> {
    fn new(
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
fn resume_swarm<F: CostFunction, R: Rng + ?Sized>(
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
fn clamp(mut theta: Vec<f64>, lower: &[f64], upper: &[f64]) -> Vec<f64> {
    for ((x, l), u) in theta.iter_mut().zip(lower).zip(upper) {
        *x = x.clamp(*l, *u);
    }
    theta
}

/// An unrefined estimate at `theta`: no uncertainty.
fn provisional<M: WireModel>(
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
fn prior_linear_density<M: WireModel>(model: &M, g: &Vector3<f64>) -> f64 {
    let w = model.weight_per_length().dot(g) / g.norm_squared();
    let lambda = if w > 0.0 { w } else { DEFAULT_LINEAR_DENSITY };
    lambda.clamp(LAMBDA_MIN, LAMBDA_MAX)
}
