//! The outcome counts of a set of roll-outs: what `results.{open_loop,closed_loop}` of the
//! passage summary hold, and the `runs` of each row of Table IV ([`crate::track`]).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::experiment::stats::{mean_std, median};
use crate::tracking::Attempt;

/// The outcome counts of one mode.
#[derive(Debug, Clone, Serialize)]
pub struct Rates {
    /// Roll-outs.
    pub attempts: usize,
    /// Successes by the summary's `success_rule`.
    pub successes: usize,
    /// Completed the whole path (see `ended_early`).
    pub completed: usize,
    /// Completed within `success_epsilon` of the goal (whatever the rule).
    pub at_goal: usize,
    /// The true wire touched a box.
    pub collisions: usize,
    /// Collisions the detector flagged.
    pub detected: usize,
    /// Attempts the detector flagged with no contact.
    pub false_alarms: usize,
    /// Retreats over all attempts (`TrackingPolicy::max_retreats` per attempt at most): after a detection the
    /// gripper moved back one move and the leg ran again.
    pub retreats: usize,
    /// Attempts the detector flagged that still completed the path after their retreats.
    pub recovered: usize,
    /// Legs undone over all attempts (`TrackingPolicy::max_undos` per attempt at most): a leg the
    /// controller stopped because its measured configuration ran away from the waypoint (under
    /// `increment` and `absolute` noise), that ended on a sensor fault, or (under those noises)
    /// whose waypoint the arms could not reach or that was flagged again after a retreat; the
    /// gripper went back to the leg's start and the leg ran again.
    pub undone: usize,
    /// Intermediate waypoints passed over over all attempts because the arms could not reach
    /// them (at most one in a row per attempt).
    pub skipped: usize,
    /// Attempts that moved both grippers by one translation to bring a goal, or a leg's start,
    /// out of the arms' reach back into it (`ftwire_plan::relocation`).
    pub relocated: usize,
    /// Attempts that ended early for another reason than a detection (a waypoint the
    /// controller refused, a failed move, a sensor fault).
    pub ended_early: usize,
    /// Median of the final `‖N(a_true − a_g)‖`.
    pub final_error_median: f64,
    /// Mean and largest shape error against `Φ(γ_A)` over every waypoint reached \[mm\].
    pub shape_mean_mm: f64,
    /// See `shape_mean_mm`.
    pub shape_max_mm: f64,
    /// Median moves.
    pub steps_median: f64,
    /// How the attempts ended, by outcome name.
    pub outcomes: BTreeMap<String, usize>,
}

impl Rates {
    /// The counts of `attempts`.
    pub fn of(attempts: &[Attempt]) -> Self {
        let count = |f: &dyn Fn(&Attempt) -> bool| attempts.iter().filter(|a| f(a)).count();
        let shapes: Vec<f64> = attempts.iter().flat_map(|a| a.shape_mm.clone()).collect();
        let mut outcomes = BTreeMap::new();
        for a in attempts {
            // A refusal's reason carries its waypoint; count by kind.
            let kind = a.outcome.split(':').next().unwrap_or_default().to_owned();
            *outcomes.entry(kind).or_insert(0) += 1;
        }
        Self {
            attempts: attempts.len(),
            successes: count(&|a| a.success),
            completed: count(&|a| a.completed),
            at_goal: count(&|a| a.at_goal),
            collisions: count(&|a| a.touched),
            detected: count(&|a| a.touched && a.detected),
            false_alarms: count(&|a| !a.touched && a.detected),
            retreats: attempts.iter().map(|a| a.retreats).sum(),
            recovered: count(&|a| a.detected && a.completed),
            undone: attempts.iter().map(|a| a.undone).sum(),
            skipped: attempts.iter().map(|a| a.skipped).sum(),
            relocated: count(&|a| a.relocated),
            ended_early: count(&|a| !a.detected && !a.completed),
            final_error_median: median(&attempts.iter().map(|a| a.final_error).collect::<Vec<_>>()),
            shape_mean_mm: mean_std(&shapes).0,
            shape_max_mm: shapes.iter().copied().fold(f64::NAN, f64::max),
            steps_median: median(&attempts.iter().map(|a| a.steps as f64).collect::<Vec<_>>()),
            outcomes,
        }
    }
}
