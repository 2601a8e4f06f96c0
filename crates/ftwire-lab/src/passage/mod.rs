//! The passage experiment (paper §IV-E, Figs. 11–13): steer the wire through a narrow
//! passage between two boxes, by a plan tracked open and closed loop under gripper noise,
//! with the collision detector armed.
//!
//! **Scene.** [`PassageParams::scene`], or the shipped 50 mm passage (`scenes/passage.toml`,
//! made for the default wire [`DEFAULT_WIRE`]). The simulator builds its boxes from the same
//! file.
//!
//! **Plan.** An RRT* plan in `A_free` of the scene from its `start` to its `goal`
//! ([`ftwire_plan::plan_in_scene`]: a fixed iteration budget and seeded restarts, so the same seed gives the
//! same path on any machine), with the wire's weightless model (the scene's configurations are
//! the paper model's), resampled into waypoints `γ_A(i/N)` whose shapes `Φ` and gripper poses
//! `Γ` are those of the estimators' model (`common.model`). Under `increment` and `absolute`,
//! whose every move scatters the wire's landing, [`PassageParams::plan_candidates`] (default
//! `ftwire_plan::PLAN_CANDIDATES`) such plans are made from seeds of their own, each polished
//! for clearance (unless [`PassageParams::polish`] is off), and the one whose waypoints expect
//! the fewest touching landings of one noisy move is tracked ([`choose_plan`]; `plan.choice`).
//! `plan_ms` in `timings.json` is the wall time of all of it, `candidate_plan_ms` each
//! candidate's planning.
//!
//! **Roll-outs.** [`PassageParams::attempts`] (default 50) of each of closed and open loop,
//! attempt `k` of both under the same noise seed. Each places the true wire at the start anew,
//! tares the sensor and reads `ã` through the learnt calibration (`rollout.calibration`, or one
//! run first and cached as `calibration.json`). The closed loop is the controller (eq. 13–14)
//! with the estimators' model, from waypoint to waypoint, with the collision detector armed:
//! its threshold comes from rehearsals of the same path with the obstacles away
//! ([`Tracking::detector`]). After a detection the gripper retreats one move and the leg runs
//! again (`TrackingPolicy::max_retreats` per attempt; the next detection ends it). The open
//! loop rolls the planned gripper poses out with no feedback. Noise: `rollout.noise` (the
//! paper's is `increment`), as in `experiment goal`; the controller's gain and shape stops are
//! `rollout.policy`'s (by default gain 1 under `increment` and `absolute`, 0.5 otherwise, the
//! paper's 0.2; a 6 mm shape stop under `increment` and `absolute`: each leg ends once the
//! model's shape at the measured `ã` is within it of the waypoint's; the `ε` stops otherwise);
//! the SDA10F's arms must reach every commanded pose: an intermediate waypoint they cannot
//! reach is passed over, the leg to the next one starting from where the wire is (`skipped`; a
//! second in a row, or the goal, ends the attempt as `unreachable`). A goal out of their reach
//! (under `offset`, the run's grasp offset moves the pose to command), or a leg's start (under
//! `increment`, the accumulated noise carries the gripper), is brought back once by
//! translating both grippers 1–4 cm along a world axis where the model's wire stays clear
//! (`relocated`; `ftwire_plan::relocation`).
//!
//! **Scoring** (the simulator's truth): an attempt *collided* when the true wire touched a box at
//! any rest (a contact force above [`crate::tracking::CONTACT_FORCE`]); it *completed* when the
//! whole path was executed (no refused waypoint, failed move, sensor fault or detection after
//! the last retreat); it is *at the goal* when it completed within
//! `TrackingPolicy::success_epsilon` of the goal (0.1 without noise and under `offset`, where
//! the last leg stops at 0.02; twice the stop ε under `increment` and `absolute`). It
//! *succeeded* by `TrackingPolicy::success_rule`: completed without touching, and at the goal
//! too without noise and under `offset`; under `increment` and `absolute`, whose every move
//! lands the wire the full noise away, the paper's rule (no collision) with the path
//! completed. `at_goal` is reported for every noise model. `detected` counts collided attempts
//! the detector flagged, `false_alarms` attempts it flagged without a contact, `retreats` the
//! retreats and `recovered` the flagged attempts that completed the path after them (a touch
//! before a retreat still fails the attempt).
//!
//! [`run`] writes `attempts.csv`, `waypoints.csv` (every closed-loop leg, as
//! [`crate::track`] writes it, with whether the true wire touched a box during it),
//! `calibration.json` (when it ran one), and the figures `passage_path_in_a` (Fig. 11: the plan
//! and the roll-outs in two components of normalised `A`), `passage_shape_error` (Fig. 12: the
//! shape error against `Φ(γ_A)` at each waypoint) and `passage_scene` (the boxes, the planned
//! wire at intermediate configurations, and the true wire of the first closed-loop attempt).
//! The caller writes `summary.json` ([`PassageRun::summary`]: `results.{open_loop,closed_loop}`
//! = `{attempts, successes, collisions, detected, ...}`, the same for the same seed) and
//! `timings.json` ([`PassageRun::timings`]). Guarded by `tests/tracking.rs` and the recorded
//! summary of `crates/ftwire/tests/tracking_experiments.rs`.

use std::path::PathBuf;
use std::time::Instant;

use ftwire_control::{BiasObserverParams, CollisionDetector, NoiseModel};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_plan::{
    ChoiceOut, Chosen, PolishOut, Scene, WAYPOINTS, Waypoint, choose_plan, near_obstacles,
    waypoints_along,
};
use ftwire_rod::Rod;
use rayon::prelude::*;
use serde::Serialize;

use crate::csv_table::{CsvTable, fixed, text, value};
use crate::error::{LabError, from_plan};
use crate::experiment::calibration::load_or_run_reporting;
use crate::experiment::stats::mean_std;
use crate::experiment::{CommonParams, ModelKind, Progress};
use crate::results::ResultsFolder;
use crate::scene::PASSAGE;
use crate::tracking::{
    Attempt, PlanFailure, RolloutParams, Tracking, plan_policy, scene_model, waypoints_csv,
};
use crate::wire::WireSpec;

mod figures;
mod rates;

pub(crate) use figures::{component, main_axes};
pub use rates::Rates;

/// The wire by default: the one the shipped passage is made for.
pub const DEFAULT_WIRE: &str = "nitinol-3mm-820";

/// Roll-outs of each mode by default.
pub const DEFAULT_ATTEMPTS: usize = 50;

/// Noise stream of attempt 0 (streams below it are the detector's rehearsals).
const FIRST_STREAM: u64 = 100;

/// The settings of the passage experiment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PassageParams {
    /// The settings every experiment takes (`wire` defaults to [`DEFAULT_WIRE`]; `trials` is
    /// not used: see `attempts`).
    pub common: CommonParams,
    /// The noise, the calibration and how the closed loop tracks.
    pub rollout: RolloutParams,
    /// The scene file; `None`: the shipped 50 mm passage (`scenes/passage.toml`).
    pub scene: Option<PathBuf>,
    /// Roll-outs of each of open and closed loop, at least 1 (default [`DEFAULT_ATTEMPTS`]).
    pub attempts: usize,
    /// Plans made under `increment` and `absolute` noise, each from its own seed, of which the
    /// one expecting the fewest touching landings is tracked (at least 1; default
    /// `ftwire_plan::PLAN_CANDIDATES`; one plan under the other noises).
    pub plan_candidates: usize,
    /// Whether, under `increment` and `absolute` noise, the waypoints whose landings come too
    /// close to a box are moved away from it (`ftwire_plan::PlanPolicy::polish_params`);
    /// `false` tracks them as resampled.
    pub polish: bool,
}

impl Default for PassageParams {
    fn default() -> Self {
        Self {
            common: CommonParams::default(),
            rollout: RolloutParams::default(),
            scene: None,
            attempts: DEFAULT_ATTEMPTS,
            plan_candidates: ftwire_plan::PLAN_CANDIDATES,
            polish: true,
        }
    }
}

impl PassageParams {
    /// The true wire: `common.wire`, or [`DEFAULT_WIRE`].
    ///
    /// # Errors
    /// Bad input for an unknown preset or a bad wire file.
    pub fn wire(&self) -> Result<WireSpec, LabError> {
        self.common.wire_or(DEFAULT_WIRE)
    }

    /// Checks the settings as [`run`] does before any work (the roll-out settings, the
    /// counts, the wire, the scene, the sensor and the rig), so that a caller can refuse bad
    /// input before it opens a results folder.
    ///
    /// # Errors
    /// Bad input naming what is wrong.
    pub fn check(&self) -> Result<(), LabError> {
        self.rollout.check()?;
        if self.attempts == 0 {
            return Err(LabError::bad_input("attempts 0: give at least 1 roll-out"));
        }
        if self.plan_candidates == 0 {
            return Err(LabError::bad_input(
                "plan candidates 0: give at least 1 plan",
            ));
        }
        let wire = self.wire()?;
        let (scene, _) = load_scene(self.scene.as_deref())?;
        self.common.setup()?;
        scene_model(&wire, self.common.gravity, self.common.model(), &scene)?;
        Ok(())
    }
}
/// Both modes' outcome counts.
#[derive(Debug, Clone, Serialize)]
pub struct PassageResults {
    /// The planned gripper poses rolled out with no feedback.
    pub open_loop: Rates,
    /// The controller from waypoint to waypoint, the collision detector armed.
    pub closed_loop: Rates,
}

/// The plan, in the summary.
#[derive(Debug, Clone, Serialize)]
pub struct PlanOut {
    /// The scene file (or `scenes/passage.toml` for the built-in one).
    pub scene: String,
    /// RRT* iterations and tree nodes of the plan found.
    pub iterations: usize,
    /// See `iterations`.
    pub nodes: usize,
    /// Length of the path in normalised `A`.
    pub cost: f64,
    /// Closest approach of the planned wire to a box \[mm\].
    pub min_clearance_mm: f64,
    /// Waypoints tracked (`N + 1`).
    pub waypoints: usize,
    /// Waypoints whose planned wire is within `ftwire_plan::NEAR_CLEARANCE` of a box or the floor
    /// (the legs from and to them stop at `shape_stop_near_mm`), after the polish.
    pub near_waypoints: usize,
    /// What the clearance polish did (`null` without [`PassageParams::polish`], and without noise or under
    /// `offset`, where it does not run: `PlanPolicy::polishes`): waypoints moved, and the
    /// smallest waypoint clearance and landing clearance (`PlanPolicy::polish_params`) of the
    /// tracking model before and after \[mm\].
    pub polish: Option<PolishOut>,
    /// How the plan was chosen among [`PassageParams::plan_candidates`] (`null` without noise and under
    /// `offset`, where one plan is made): each candidate's expected touching landings and the
    /// one tracked (`ftwire_plan::choose_plan`; their planning times are in `timings.json`).
    pub choice: Option<ChoiceOut>,
}

/// `summary.json`'s body (after the run header): the same for the same seed.
#[derive(Debug, Clone, Serialize)]
pub struct PassageSummary {
    /// The true wire's name.
    pub wire: String,
    /// The estimators' model (the waypoints' shapes and poses, the controller's).
    pub model: ModelKind,
    /// The second gripper's execution noise.
    pub noise_model: NoiseModel,
    /// The controller's gain K.
    pub gain: f64,
    /// The closed loop's shape stop \[mm\] (0: the `ε` stops).
    pub shape_stop_mm: f64,
    /// The shape stop \[mm\] of the legs from or to a waypoint near a box
    /// (`TrackingPolicy::near_shape_stop_for`; the same as `shape_stop_mm` where it is not looser).
    pub shape_stop_near_mm: f64,
    /// Most moves toward each waypoint before the last.
    pub waypoint_moves: usize,
    /// The bias observer's settings of the closed loop (`null`: off, or under `absolute`).
    pub bias_observer: Option<BiasObserverParams>,
    /// The success tolerance on the true final configuration \[normalised\].
    pub success_epsilon: f64,
    /// What `successes` counts under this noise model.
    pub success_rule: &'static str,
    /// The collision detector's jump-ratio threshold.
    pub detector_threshold: f64,
    /// Both modes' outcome counts.
    pub results: PassageResults,
    /// The plan tracked.
    pub plan: PlanOut,
}

/// `timings.json`: wall times, apart from the summary.
#[derive(Debug, Clone, Serialize)]
pub struct PassageTimings {
    /// Loading or running the calibration \[s\].
    pub calibration_s: f64,
    /// The plan \[ms\]: every candidate's planning, polish and scoring.
    pub plan_ms: f64,
    /// Each candidate's planning alone \[ms\] (`null` for one that found no path), when the
    /// plan was chosen among candidates (`plan.choice` in the summary); `null` otherwise.
    pub candidate_plan_ms: Option<Vec<Option<f64>>>,
    /// Calibrating the collision detector on rehearsals \[s\].
    pub detector_s: f64,
    /// Every roll-out of both modes \[s\].
    pub attempts_s: f64,
    /// The whole run \[s\].
    pub total_s: f64,
}

/// A finished passage experiment.
#[derive(Debug, Clone)]
pub struct PassageRun {
    /// `summary.json`'s body.
    pub summary: PassageSummary,
    /// `timings.json`.
    pub timings: PassageTimings,
}

/// The scene file `path`, or the shipped passage, and its name.
///
/// # Errors
/// Bad input (exit 2) for a scene file that cannot be read or parsed.
pub fn load_scene(path: Option<&std::path::Path>) -> Result<(Scene, String), LabError> {
    match path {
        Some(path) => Ok((
            Scene::load(path).map_err(|e| from_plan(e, "--scene"))?,
            path.display().to_string(),
        )),
        None => Ok((
            Scene::from_toml(PASSAGE, "scenes/passage.toml")
                .map_err(|e| from_plan(e, "the built-in passage scene"))?,
            "scenes/passage.toml".to_owned(),
        )),
    }
}

/// Runs the passage experiment into `folder` (see the module docs for what it writes),
/// reports its progress (the calibration run first, the plan, each mode's counts) to
/// `progress`, and returns the summary and timings for the caller to write (it does not
/// finish the folder).
///
/// # Errors
/// Bad input for bad settings ([`PassageParams::check`]) or a bad calibration file; no answer
/// when no plan is found or a roll-out cannot start; I/O errors writing the folder.
pub fn run(
    params: &PassageParams,
    folder: &ResultsFolder,
    progress: Progress<'_>,
) -> Result<PassageRun, LabError> {
    let total = Instant::now();
    params.check()?;
    let (common, rollout) = (&params.common, &params.rollout);
    let wire = params.wire()?;
    let (scene, scene_name) = load_scene(params.scene.as_deref())?;
    let setup = common.setup()?;
    let model = scene_model(&wire, common.gravity, common.model(), &scene)?;
    let (calibration, calibration_s) = load_or_run_reporting(
        folder,
        rollout.calibration.as_deref(),
        (common.gravity, common.model()),
        (&setup, common.seed),
        progress,
    )?;
    let tracked = plan(params, &scene, scene_name, &model)?;
    report_plan(&tracked, progress);
    let waypoints = &tracked.waypoints;

    let tracking = Tracking {
        wire: &wire,
        gravity: common.gravity,
        scene: &scene,
        calibration: &calibration,
        setup: &setup,
        noise: rollout.noise,
        seed: common.seed,
        policy: rollout.policy,
        arms: true,
        bias_observer: rollout.bias_observer,
    };
    let started = Instant::now();
    let detector = tracking.detector(&model, waypoints)?;
    let detector_s = started.elapsed().as_secs_f64();
    let started = Instant::now();
    let (closed, open) = roll_out(&tracking, &model, waypoints, detector, params.attempts)?;
    let attempts_s = started.elapsed().as_secs_f64();

    let results = PassageResults {
        open_loop: Rates::of(&open),
        closed_loop: Rates::of(&closed),
    };
    report_results(&results, progress);
    folder.write("attempts.csv", attempts_csv(&closed, &open)?)?;
    folder.write("waypoints.csv", waypoints_csv("attempt", &closed)?)?;
    figures::write_figures(folder, &scene, &model, waypoints, &closed, &open)?;
    let timings = PassageTimings {
        calibration_s,
        plan_ms: 1e3 * tracked.seconds,
        candidate_plan_ms: tracked
            .out
            .choice
            .as_ref()
            .map(|_| tracked.candidate_plan_ms),
        detector_s,
        attempts_s,
        total_s: total.elapsed().as_secs_f64(),
    };
    let policy = &rollout.policy;
    let summary = PassageSummary {
        wire: wire.name.clone(),
        model: common.model(),
        noise_model: rollout.noise,
        gain: policy.gain,
        shape_stop_mm: 1e3 * policy.shape_stop,
        shape_stop_near_mm: 1e3 * policy.near_shape_stop,
        waypoint_moves: policy.through.max_iterations,
        bias_observer: tracking.observer_settings(),
        success_epsilon: policy.success_epsilon,
        success_rule: policy.success_rule(),
        detector_threshold: detector.threshold(),
        results,
        plan: tracked.out,
    };
    Ok(PassageRun { summary, timings })
}

/// The plan tracked: its summary, its waypoints (of the tracking model), the time it took
/// \[s\] and each candidate's planning \[ms\].
struct TrackedPlan {
    out: PlanOut,
    waypoints: Vec<Waypoint>,
    seconds: f64,
    candidate_plan_ms: Vec<Option<f64>>,
}

/// The plan, with the weightless model (the scene's configurations are the paper model's);
/// under the noises that scatter every landing, the best of `plan_candidates` plans by their
/// expected touches, each polished for clearance (when `polish`).
fn plan(
    params: &PassageParams,
    scene: &Scene,
    scene_name: String,
    model: &KirchhoffModel,
) -> Result<TrackedPlan, LabError> {
    let planner_rod = Rod::new(*model.wire());
    let plans = plan_policy(params.rollout.noise);
    let Chosen {
        planned,
        waypoints,
        polish,
        choice,
        seconds,
        candidate_plan_ms,
    } = choose_plan::<PlanFailure>(
        scene,
        &planner_rod,
        model.rod(),
        plans.validity_tracked(model.rod()),
        &plans,
        params.common.seed,
        params.plan_candidates,
        params.polish && plans.polishes(),
        // The waypoints' shapes and gripper poses of the tracking model (the loaded one with
        // gravity on): the open loop rolls out the poses that give `γ_A` on the true, heavy
        // wire.
        |planned| {
            waypoints_along(
                model.rod(),
                &scene.base,
                &planned.plan.path.waypoints,
                WAYPOINTS,
            )
            .map_err(PlanFailure::from)
        },
    )?;
    let out = PlanOut {
        scene: scene_name,
        iterations: planned.plan.iterations,
        nodes: planned.plan.nodes,
        cost: planned.plan.path.cost,
        min_clearance_mm: 1e3 * planned.plan.path.min_clearance(),
        waypoints: planned.waypoints.len(),
        near_waypoints: near_obstacles(scene, model.rod(), &waypoints)
            .map_err(|e| from_plan(e, "the scene"))?
            .iter()
            .filter(|&&near| near)
            .count(),
        polish,
        choice,
    };
    Ok(TrackedPlan {
        out,
        waypoints,
        seconds,
        candidate_plan_ms,
    })
}

/// The plan's lines of progress: its size, the choice among candidates, the polish.
fn report_plan(tracked: &TrackedPlan, progress: Progress<'_>) {
    let plan = &tracked.out;
    progress(&format!(
        "plan: {} waypoints ({} near a box), length {:.2} (normalised A), closest approach {:.1} mm, {:.0} ms",
        plan.waypoints,
        plan.near_waypoints,
        plan.cost,
        plan.min_clearance_mm,
        1e3 * tracked.seconds
    ));
    if let Some(c) = &plan.choice {
        let touches: Vec<String> = c
            .expected_touches
            .iter()
            .map(|t| t.map_or("none".into(), |t| format!("{t:.4}")))
            .collect();
        progress(&format!(
            "choice: plan {} of {} (expected touching landings per pass: {})",
            c.chosen + 1,
            c.candidates,
            touches.join(" / ")
        ));
    }
    if let Some(p) = &plan.polish {
        progress(&format!(
            "polish: {} waypoints moved, closest landing {:.1} → {:.1} mm, closest waypoint {:.1} → {:.1} mm",
            p.moved,
            p.min_landing_clearance_before_mm,
            p.min_landing_clearance_after_mm,
            p.min_clearance_before_mm,
            p.min_clearance_after_mm
        ));
    }
}

/// `attempts` roll-outs of each mode along `waypoints`, in parallel, attempt `k` of both
/// under noise stream `FIRST_STREAM + k`: the closed-loop attempts, then the open-loop ones.
fn roll_out(
    tracking: &Tracking<'_>,
    model: &KirchhoffModel,
    waypoints: &[Waypoint],
    detector: CollisionDetector,
    attempts: usize,
) -> Result<(Vec<Attempt>, Vec<Attempt>), LabError> {
    let streams: Vec<u64> = (0..attempts as u64).map(|k| FIRST_STREAM + k).collect();
    let rollouts: Vec<(Attempt, Attempt)> = streams
        .par_iter()
        .map(|&stream| {
            let closed = tracking.closed_loop(model, waypoints, detector, stream)?;
            let open = tracking.open_loop(model, waypoints, stream)?;
            Ok((closed, open))
        })
        .collect::<Result<_, LabError>>()?;
    Ok(rollouts.into_iter().unzip())
}

/// Each mode's line of progress: successes, collisions, detections, false alarms.
fn report_results(results: &PassageResults, progress: Progress<'_>) {
    for (name, rates) in [
        ("closed loop", &results.closed_loop),
        ("open loop", &results.open_loop),
    ] {
        progress(&format!(
            "{name}: {}/{} successes, {} collisions ({} detected), {} false alarms",
            rates.successes, rates.attempts, rates.collisions, rates.detected, rates.false_alarms
        ));
    }
}

/// `attempts.csv`: one row per attempt and mode.
///
/// # Errors
/// As [`CsvTable::row`].
pub fn attempts_csv(closed: &[Attempt], open: &[Attempt]) -> Result<Vec<u8>, LabError> {
    let mut csv = CsvTable::new(
        "attempts.csv",
        &[
            "mode",
            "attempt",
            "outcome",
            "steps",
            "touched",
            "detected",
            "success",
            "final_error",
            "shape_mean_mm",
            "shape_max_mm",
            "retreats",
            "skipped",
            "relocated",
            "undone",
        ],
    )?;
    for (k, a) in closed.iter().enumerate().chain(open.iter().enumerate()) {
        let (mean, _) = mean_std(&a.shape_mm);
        let max = a.shape_mm.iter().copied().fold(f64::NAN, f64::max);
        csv.row([
            text(a.mode),
            value(k),
            text(&a.outcome),
            value(a.steps),
            value(a.touched),
            value(a.detected),
            value(a.success),
            fixed(a.final_error, 6),
            fixed(mean, 3),
            fixed(max, 3),
            value(a.retreats),
            value(a.skipped),
            value(a.relocated),
            value(a.undone),
        ])?;
    }
    csv.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attempt(outcome: &str, touched: bool, detected: bool, success: bool) -> Attempt {
        Attempt {
            mode: "closed_loop",
            outcome: outcome.to_owned(),
            steps: 10,
            touched,
            detected,
            retreats: 0,
            undone: 0,
            skipped: 0,
            relocated: false,
            final_error: 0.2,
            completed: outcome == "reached",
            at_goal: outcome == "reached" && !touched,
            success,
            shape_mm: vec![1.0, 3.0],
            centrelines: Vec::new(),
            a_true: Vec::new(),
            legs: Vec::new(),
        }
    }

    #[test]
    fn rates_count_collisions_detections_and_false_alarms_apart() {
        let attempts = [
            attempt("reached", false, false, true),
            attempt("collision_detected", true, true, false),
            attempt("collision_detected", false, true, false),
            attempt("reached", true, false, false),
            attempt(
                "refused at waypoint 3: outside A_stable",
                false,
                false,
                false,
            ),
            // A false alarm the retreat recovered: flagged, then the path completed.
            Attempt {
                retreats: 2,
                undone: 3,
                skipped: 1,
                relocated: true,
                ..attempt("reached", false, true, true)
            },
        ];
        let rates = Rates::of(&attempts);
        assert_eq!(rates.attempts, 6);
        assert_eq!(rates.successes, 2);
        assert_eq!(rates.collisions, 2);
        assert_eq!(rates.detected, 1);
        assert_eq!(rates.false_alarms, 2);
        assert_eq!(rates.retreats, 2);
        assert_eq!(rates.recovered, 1);
        assert_eq!(rates.undone, 3);
        assert_eq!(rates.skipped, 1);
        assert_eq!(rates.relocated, 1);
        assert_eq!(rates.ended_early, 1);
        assert_eq!(rates.completed, 3);
        assert_eq!(rates.at_goal, 2);
        assert_eq!(rates.outcomes.get("refused at waypoint 3"), Some(&1));
        assert_eq!(rates.shape_max_mm, 3.0);
        assert_eq!(rates.shape_mean_mm, 2.0);
    }

    #[test]
    fn the_attempts_table_has_one_row_per_attempt_and_mode() {
        let a = attempt("reached", false, false, true);
        let csv = attempts_csv(std::slice::from_ref(&a), &[a.clone(), a.clone()]).expect("a table");
        let csv = String::from_utf8(csv).expect("UTF-8");
        assert_eq!(csv.lines().count(), 4);
        assert!(
            csv.lines()
                .nth(1)
                .is_some_and(|l| l.starts_with("closed_loop,0,"))
        );
    }
}
