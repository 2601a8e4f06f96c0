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
//! - **stiffness per length** ([`super::ParameterConstraints::stiffness_per_length`]): the
//!   data pin `c/L`, so the basin is a thin valley along `c2 ∝ L`, one grid column in eighty
//!   wide; in `(ln(c2/L), L)` it runs straight along `L`;
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
//!
//! Pieces, one per file: this file the streaming [`Identifier`] and the driver's loop
//! (`run`); `identifier/search` steps 1 to 3 (the search boxes, the fine fits, the wrong
//! basin); `identifier/assess` step 4 and the estimate at an optimum; `identifier/objectives`
//! what one search runs on; `identifier/params` the settings; `identifier/batch` the batch
//! calls.

use std::time::{Duration, Instant};

use ftwire_core::Pose;
use nalgebra::Vector6;
use rand::Rng;

use super::parameters::L_MAX;
use super::refine::Refined;
use super::{Estimate, Sample, Swarm, Unidentified};
use crate::{EstimateError, WireModel};

mod assess;
mod batch;
mod objectives;
mod params;
mod search;
pub use batch::{identify, identify_samples};
pub use objectives::DEFAULT_LINEAR_DENSITY;
use objectives::{Objectives, prior_linear_density, provisional, resume_swarm};
pub use params::IdentifierParams;
pub use search::MAX_SHARED_SAMPLES;

/// Streaming identification for a sensor loop: [`Identifier::push`] samples as they come,
/// [`Identifier::step`] within a time budget each tick.
///
/// The work is a sequence of indivisible units (a swarm iteration: 20 residual evaluations; the
/// refinement: a few hundred), and `step` starts a unit only while its budget lasts, so the results
/// depend only on the data and the seed when each set of samples is run to completion
/// ([`Identifier::run_to_completion`]); how the work is cut into steps does not matter. New samples
/// make the swarm current ([`ParticleSwarm::refresh`](super::ParticleSwarm::refresh)) and restart
/// the iteration count; how far the search got before they arrived does depend on the budgets, so
/// for a reproducible estimate run to completion after the last push.
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

    /// Adds a sample `(ã, b̃)` taken `time` seconds after the sensor was tared: with a bias model
    /// ([`MeasurementNoise::bias`](super::MeasurementNoise::bias)) the final fit then estimates the
    /// bias's drift with the wire ([`super::drift`]).
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
}
