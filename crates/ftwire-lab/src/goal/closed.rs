//! The closed loop of a goal trial: `ftwire_control::Controller` (eq. 13–14) from `a_s` to
//! `a_g` with the smallest ε of a table, read off at each ε's first stop and at the run's own
//! end.

use ftwire_control::{BiasObserver, CollisionDetector, ControlParams, Controller, Outcome, Run};
use ftwire_estimate::KirchhoffModel;
use ftwire_sim::BoxObstacle;

use super::trial::{Context, Pair, TrialRig, Truth};
use super::tuning::{GAIN, SETTLE_SAMPLES};
use crate::error::LabError;

/// How a closed-loop trial runs.
#[derive(Clone, Copy)]
pub(super) struct ClosedSetup<'a> {
    pub(super) noise: ftwire_control::NoiseModel,
    /// The ε of its trade-off table (it runs with the smallest).
    pub(super) epsilons: &'a [f64],
    pub(super) max_iterations: usize,
    pub(super) detector: Option<CollisionDetector>,
    /// The controller's settling radius (`0`: off; see [`super::SETTLE_RADIUS`]).
    pub(super) settle_radius: f64,
    /// The controller's shape stop \[m\] (`0`: off, the stop is the smallest ε's).
    pub(super) shape_stop: f64,
}

/// One ε's stop on a closed-loop run.
#[derive(Debug, Clone)]
pub(super) struct Stop {
    pub(super) steps: usize,
    pub(super) truth: Truth,
    /// The measured `ã` came within ε.
    pub(super) reached: bool,
    pub(super) failure: Option<String>,
    /// The wire snapped at least once before this stop.
    pub(super) snapped: bool,
}

/// A closed-loop trial.
pub(super) struct ClosedTrial {
    /// One stop per ε of the table, in its order, then the run's own end.
    pub(super) stops: Vec<Stop>,
    pub(super) run: Option<Run>,
    /// Truth at the start and after each step.
    pub(super) truths: Vec<Truth>,
    /// The rig and its feedback where the run left them.
    pub(super) rig: Option<TrialRig>,
}

impl ClosedTrial {
    /// A trial that did not run, with `message`: one failed stop per ε and the end.
    fn failed(epsilons: usize, message: &str) -> Self {
        Self {
            stops: (0..=epsilons)
                .map(|_| Stop {
                    steps: 0,
                    truth: Truth::unknown(),
                    reached: false,
                    failure: Some(message.to_owned()),
                    snapped: false,
                })
                .collect(),
            run: None,
            truths: Vec::new(),
            rig: None,
        }
    }
}

impl Context<'_> {
    /// The closed loop on `pair` with the smallest of `setup.epsilons`, read off at each.
    pub(super) fn closed(
        &self,
        pair: &Pair,
        k: u64,
        setup: &ClosedSetup<'_>,
        obstacles: &[BoxObstacle],
    ) -> Result<ClosedTrial, LabError> {
        let epsilons = setup.epsilons;
        let Some((mut rig, feedback)) = self.rig(pair, k, setup.noise, obstacles)? else {
            return Ok(ClosedTrial::failed(
                epsilons.len(),
                "the simulator could not place the wire",
            ));
        };
        let controller = self.controller(setup)?;
        let mut truths = vec![self.truth(rig.inner(), pair)?];
        let mut truth_error = None;
        let mut reach = self.reach();
        let mut observer = self
            .observer_settings(setup.noise)
            .map(|settings| BiasObserver::new(self.model, settings))
            .transpose()
            .map_err(|e| LabError::bad_input(e.to_string()))?;
        let run = controller.run_with_bias_observer(
            &mut rig,
            &feedback,
            &mut reach,
            &pair.a_g,
            observer.as_mut(),
            |rig, _| match self.truth(rig.inner(), pair) {
                Ok(t) => truths.push(t),
                Err(e) => truth_error = Some(e),
            },
        );
        if let Some(e) = truth_error {
            return Err(e);
        }
        let run = match run {
            Ok(run) => run,
            Err(e) => {
                return Ok(ClosedTrial::failed(
                    epsilons.len(),
                    &format!("refused: {e}"),
                ));
            }
        };
        // The measured distance to the goal at the start and after each step.
        let distances: Vec<f64> = std::iter::once(run.start_estimate)
            .chain(run.steps.iter().map(|s| s.estimate))
            .map(|a| controller.distance(&a, &pair.a_g))
            .collect();
        Ok(ClosedTrial {
            stops: stops(epsilons, &distances, &truths, &run.outcome),
            run: Some(run),
            truths,
            rig: Some((rig, feedback)),
        })
    }

    /// The controller of `setup`: the model, the gain [`GAIN`], the smallest ε of its table,
    /// and its detector if any.
    fn controller(&self, setup: &ClosedSetup<'_>) -> Result<Controller<KirchhoffModel>, LabError> {
        let settings = ControlParams {
            gain: GAIN,
            epsilon: setup.epsilons.iter().copied().fold(f64::INFINITY, f64::min),
            max_iterations: setup.max_iterations,
            settle_radius: setup.settle_radius,
            settle_samples: SETTLE_SAMPLES,
            shape_tolerance: setup.shape_stop,
            ..ControlParams::default()
        };
        let mut controller = Controller::new(self.model, settings)
            .map_err(|e| LabError::bad_input(e.to_string()))?;
        if let Some(d) = setup.detector {
            controller = controller.with_detector(d);
        }
        Ok(controller)
    }
}

/// The stops of a run that ended with `outcome`: for each of `epsilons`, the first rest whose
/// measured distance (`distances`, the start and each step) is below it, else the run's end;
/// then the run's own end (the shape stop's headline). `truths` is the truth at each rest.
fn stops(epsilons: &[f64], distances: &[f64], truths: &[Truth], outcome: &Outcome) -> Vec<Stop> {
    let failure = match outcome {
        Outcome::Reached { .. } | Outcome::IterationLimit { .. } => None,
        Outcome::CollisionDetected { .. } => None,
        other => Some(format!("{}: {other:?}", other.name())),
    };
    let end = distances.len() - 1;
    let truth_at = |steps: usize| truths[steps.min(truths.len() - 1)];
    let mut stops: Vec<Stop> = epsilons
        .iter()
        .map(|&eps| {
            let hit = distances.iter().position(|&d| d < eps);
            let steps = hit.unwrap_or(end);
            Stop {
                steps,
                truth: truth_at(steps),
                reached: hit.is_some(),
                failure: if hit.is_some() { None } else { failure.clone() },
                snapped: truths.iter().take(steps + 1).any(|t| t.snapped),
            }
        })
        .collect();
    let reached = matches!(outcome, Outcome::Reached { .. });
    stops.push(Stop {
        steps: end,
        truth: truth_at(end),
        reached,
        failure: if reached { None } else { failure },
        snapped: truths.iter().any(|t| t.snapped),
    });
    stops
}
