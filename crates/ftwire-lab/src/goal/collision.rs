//! Collision detection in the goal experiment (§IV-E): the detector calibrated on free
//! motions of pairs of its own, its false alarms on the pairs' no-noise closed loops, and the
//! contact runs into a box at the middle of `Φ(a_g)`, each followed by a retreat.

use ftwire_control::{CollisionDetector, MoveCheck, NoiseModel, Outcome, Run, retreat};
use ftwire_rod::to_normalised;
use serde::Serialize;

use super::closed::{ClosedSetup, ClosedTrial};
use super::pairs::obstacle_for;
use super::trial::Context;
use super::trial::Pair;
use super::tuning::MAX_ITERATIONS_NO_NOISE;
use crate::error::LabError;
use crate::experiment::Progress;
use crate::experiment::stats::median;

/// Collision detection: false alarms on free motions, and the contact runs.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Collision {
    /// Free motions on which the detector would have fired.
    pub false_alarms: usize,
    /// Of the false alarms, those raised on a step where the simulator's wire snapped to
    /// another branch (a real disagreement with the model, though no contact).
    pub false_alarms_at_snaps: usize,
    /// Contact runs that touched the box after no earlier alarm (detected or missed).
    pub trials: usize,
    /// Median of `delays` \[steps\].
    pub detection_delay_steps_median: f64,
    /// Free motions checked for false alarms.
    pub free_motions: usize,
    /// Contacts detected on the obstacle motions.
    pub detected: usize,
    /// Contacts missed on the obstacle motions.
    pub missed: usize,
    /// Alarms before any contact on the obstacle motions.
    pub early_alarms: usize,
    /// Obstacle motions that never touched the box, or could not be run.
    pub no_contact: usize,
    /// Detected step minus the first step with a contact force, per detected contact.
    pub delays: Vec<usize>,
    /// The simulator's total contact force at each detection \[N\] (in the order of `delays`).
    pub detection_force_n: Vec<f64>,
    /// The detector's threshold on the residual (see `ftwire_control::CollisionDetector`).
    pub threshold: f64,
    /// The detector's floor \[normalised\].
    pub floor: f64,
    /// The detector's slope \[-\].
    pub slope: f64,
    /// The detector's window \[moves\].
    pub window: usize,
    /// Retreats that found a pose agreeing with the way out.
    pub retreat_agreed: usize,
}

/// Free motions that calibrate the collision detector.
pub(super) const DETECTOR_MOTIONS: usize = 5;
/// The ε of the free motions that calibrate the collision detector and of the contact runs.
const DETECTOR_EPSILON: f64 = 0.05;
/// Obstacle motions of the collision sub-run (at most the run's pairs).
const CONTACT_TRIALS: usize = 10;
/// The seed offset of the trials of the detector's free motions.
const FREE_TRIALS: u64 = 10_000;
/// The seed offset of the trials of the contact runs.
const CONTACT_RUNS: u64 = 20_000;

/// A calibrated detector and the floor \[normalised\] it was calibrated with.
pub(super) struct DetectorSetup {
    pub(super) detector: CollisionDetector,
    pub(super) floor: f64,
}

/// How the detector's free motions and the contact runs go: no noise, [`DETECTOR_EPSILON`],
/// with `detector` if any.
fn free_setup(detector: Option<CollisionDetector>) -> ClosedSetup<'static> {
    ClosedSetup {
        noise: NoiseModel::None,
        epsilons: &[DETECTOR_EPSILON],
        max_iterations: MAX_ITERATIONS_NO_NOISE,
        detector,
        settle_radius: 0.0,
        shape_stop: 0.0,
    }
}

/// The collision detector of a run ([`CollisionDetector::from_free_moves`]): its floor from
/// the median noise of `ã` at rest at the start of `pairs`, its slope and threshold from the
/// moves of their free closed loops (snaps of the true wire, which the model does not have,
/// are rare large residuals on free motion: hence a quantile, not the largest).
///
/// # Errors
/// No answer when the detector cannot be calibrated from those moves; as the trials
/// otherwise.
pub(super) fn calibrate_detector(
    ctx: &Context<'_>,
    pairs: &[Pair],
    progress: Progress<'_>,
) -> Result<DetectorSetup, LabError> {
    let mut noise_levels = Vec::new();
    let mut calibration_runs = Vec::new();
    for (i, pair) in pairs.iter().enumerate() {
        let k = FREE_TRIALS + i as u64;
        if let Some((mut rig, feedback)) = ctx.rig(pair, k, NoiseModel::None, &[])?
            && let Ok(m) = feedback.measure(&mut rig)
        {
            noise_levels.push(to_normalised(&ctx.params, &m.a_std_error).norm());
        }
        let trial = ctx.closed(pair, k, &free_setup(None), &[])?;
        calibration_runs.extend(trial.run);
    }
    let free_moves: Vec<Vec<MoveCheck>> = calibration_runs.iter().map(moves).collect();
    let free_moves: Vec<&[MoveCheck]> = free_moves.iter().map(Vec::as_slice).collect();
    let (detector, floor) = CollisionDetector::from_free_moves(&noise_levels, &free_moves)
        .map_err(|e| LabError::no_answer(format!("calibrating the collision detector: {e}")))?;
    progress(&format!(
        "collision detector: floor {floor:.4}, slope {:.3}, threshold {:.3} from {} free steps",
        detector.slope(),
        detector.threshold(),
        free_moves.iter().map(|m| m.len()).sum::<usize>()
    ));
    Ok(DetectorSetup { detector, floor })
}

/// The checks of `run`'s moves.
fn moves(run: &Run) -> Vec<MoveCheck> {
    run.steps.iter().map(|s| s.check).collect()
}

/// Counts a free closed-loop motion (`closed`, which ran as `run`) in `collision`, and a false
/// alarm if the detector would have fired on it (at a snap of the wire or not).
pub(super) fn count_false_alarm(
    collision: &mut Collision,
    setup: &DetectorSetup,
    closed: &ClosedTrial,
    run: &Run,
) {
    collision.free_motions += 1;
    if let Some(step) = setup.detector.first_alarm(&moves(run)) {
        collision.false_alarms += 1;
        if closed.truths.get(step + 1).is_some_and(|t| t.snapped) {
            collision.false_alarms_at_snaps += 1;
        }
    }
}

/// The collision sub-run: the first [`CONTACT_TRIALS`] pairs run again (no noise) with a box
/// at the middle of `Φ(a_g)` ([`obstacle_for`]) and the detector on; each detection is
/// followed by a retreat. Adds the contacts, delays and retreats to `collision`.
///
/// # Errors
/// As the trials.
pub(super) fn contact_runs(
    ctx: &Context<'_>,
    pairs: &[Pair],
    setup: &DetectorSetup,
    collision: &mut Collision,
) -> Result<(), LabError> {
    for (i, pair) in pairs.iter().take(CONTACT_TRIALS).enumerate() {
        let Some(obstacle) = obstacle_for(pair)? else {
            collision.no_contact += 1;
            continue;
        };
        let k = CONTACT_RUNS + i as u64;
        let trial = ctx.closed(pair, k, &free_setup(Some(setup.detector)), &[obstacle])?;
        let Some(run) = &trial.run else {
            collision.no_contact += 1;
            continue;
        };
        let detected = score_contact(collision, &trial, run);
        if detected
            && let Some((mut rig, feedback)) = trial.rig
            && retreat(&mut rig, &feedback, run, &ctx.params, 10.0 * setup.floor)
                .is_ok_and(|r| r.agreed)
        {
            collision.retreat_agreed += 1;
        }
    }
    collision.detection_delay_steps_median = median(
        &collision
            .delays
            .iter()
            .map(|&d| d as f64)
            .collect::<Vec<_>>(),
    );
    Ok(())
}

/// Scores a contact run (`trial`, which ran as `run`) in `collision`: detected (with its delay
/// and force), missed, an alarm before any contact, or no contact. Returns whether the
/// detector fired.
fn score_contact(collision: &mut Collision, trial: &ClosedTrial, run: &Run) -> bool {
    // truths[j] is the rest after step j − 1 (truths[0] the start).
    let first_contact = trial.truths.iter().position(|t| t.contact);
    let detected = match run.outcome {
        Outcome::CollisionDetected { step, .. } => Some(step + 1),
        _ => None,
    };
    match (first_contact, detected) {
        (None, None) => collision.no_contact += 1,
        (None, Some(_)) => collision.early_alarms += 1,
        (Some(c), Some(d)) if d < c => collision.early_alarms += 1,
        (Some(_), None) => {
            collision.trials += 1;
            collision.missed += 1;
        }
        (Some(c), Some(d)) => {
            collision.trials += 1;
            collision.detected += 1;
            collision.delays.push(d - c);
            collision
                .detection_force_n
                .push(trial.truths.get(d).map_or(f64::NAN, |t| t.contact_force));
        }
    }
    detected.is_some()
}
