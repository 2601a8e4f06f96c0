//! The tracking experiment (paper §IV-D, Table IV, Figs. 8–9): plan paths in `A_free` with
//! RRT* between random start and goal configurations, and track them open and closed loop
//! under gripper noise; the shape error along the path.
//!
//! **Pairs.** [`TrackParams::pairs`] (default 10, the paper's) seeded pairs `(a_s, a_g)` drawn
//! uniformly in the normalised box `[−5, 5]⁶` (as `experiment goal`'s), each in `Z_free` of a
//! scene with no obstacles and the base gripper where the shipped passage holds it (stable, no
//! self-contact, both grippers' poses reachable by the SDA10F's arms), both ends stable under
//! the tracking model too (the loaded one with gravity on: a heavy wire such as the cable can
//! rest where the weightless planner's model has it stable and the true wire has no
//! equilibrium), at least [`MIN_PAIR_DISTANCE`] apart in normalised `A`. A pair the planner
//! finds no path for is replaced by a new draw (counted in `pair_draws`).
//!
//! **Plan and tracking.** RRT* in `A_free` (`ftwire_plan::plan_in_scene`: a fixed iteration
//! budget and seeded restarts) with the wire's weightless model; the path is resampled into
//! waypoints `γ_A(i/N)` whose shapes `Φ` and gripper poses `Γ` are those of the estimators'
//! model (`common.model`). The closed loop runs the controller (eq. 13–14) from waypoint to
//! waypoint on `ã` from the learnt calibration (`rollout.calibration`, or one run first and
//! cached); the open loop rolls out the waypoints' gripper poses. Both under `rollout.noise`
//! (the paper's is `increment`), with the same noise seed per pair, and the closed loop by
//! `rollout.policy` (by default gain 1 under `increment` and `absolute`, 0.5 otherwise, the
//! paper's 0.2; a 6 mm shape stop under `increment` and `absolute`: each leg ends once the
//! model's shape at the measured `ã` is within it of the waypoint's; the `ε` stops otherwise).
//! The collision detector is not armed: there is nothing to collide with, so it could only
//! stop a run by a false alarm ([`crate::passage`] arms it). The arms' kinematics do not limit
//! the closed loop's commanded poses unless [`TrackParams::reach`] is [`ArmReach::Robot`] (as
//! in `experiment goal`, and the paper's noise experiments).
//!
//! **Metric** (Table IV; the simulator's truth): at each waypoint the controller reached (or the
//! roll-out passed), the mean distance between the true centreline and `Φ(γ_A(i/N))` at 100
//! matched arc lengths; `mean_mm`, `std_mm` and `max_mm` over every waypoint of every pair.
//!
//! [`run`] writes `pairs.csv`, `waypoints.csv` (every closed-loop leg: its waypoint, moves,
//! outcome, true shape error, and whether it is scored), `calibration.json` (when it ran one),
//! and the figures `track_path_in_a` (Fig. 8: the plan and both roll-outs of the first pair in
//! two components of normalised `A`) and `track_shape_error` (Fig. 9: the shape error along
//! the path of every pair). The caller writes `summary.json` ([`TrackRun::summary`]:
//! `results.{open_loop,closed_loop}` = `{mean_mm, std_mm, max_mm, ...}`, the same for the same
//! seed) and `timings.json` ([`TrackRun::timings`]: `calibration_s`, each pair's `plan_ms` and
//! their `plan_ms_median`, `tracking_s`, `total_s`). Guarded by `tests/tracking.rs` and the
//! recorded summary of `crates/ftwire/tests/tracking_experiments.rs`.

use std::collections::BTreeMap;
use std::time::Instant;

use ftwire_control::{BiasObserverParams, NoiseModel};
use ftwire_core::Pose;
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_plan::{
    Checker, ConfigurationSpec, PLAN_RESTARTS, Scene, ValidityParams, WAYPOINTS, Waypoint, ZPoint,
    plan_in_scene, waypoints_along,
};
use ftwire_report::{LineChart, Series};
use ftwire_robot::Robot;
use ftwire_rod::sampling::Sampler;
use ftwire_rod::{Rod, to_normalised};
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;

use crate::csv_table::{CsvTable, fixed, text, value};
use crate::error::{LabError, from_plan, from_rod};
use crate::experiment::calibration::load_or_run_reporting;
use crate::experiment::rig::bias_observer;
use crate::experiment::stats::{mean_std, median};
use crate::experiment::{CommonParams, ModelKind, Progress};
use crate::passage::{self, Rates};
use crate::results::ResultsFolder;
use crate::tracking::{Attempt, RolloutParams, Tracking, plan_policy, scene_model, waypoints_csv};
use crate::wire::WireSpec;

/// The wire by default.
pub const DEFAULT_WIRE: &str = "nitinol-3mm-820";
/// Start–goal pairs by default (the paper's).
pub const DEFAULT_PAIRS: usize = 10;
/// Half-width of the normalised box the pairs are drawn from (as `experiment goal`'s).
const PAIR_BOX: f64 = 5.0;
/// Least distance between a pair's start and goal in normalised `A`.
pub const MIN_PAIR_DISTANCE: f64 = 4.0;
/// Draws per requested pair before giving up.
const MAX_DRAWS_PER_PAIR: usize = 200;
/// Noise stream of pair 0.
const FIRST_STREAM: u64 = 100;

/// What limits the closed loop's commanded poses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ArmReach {
    /// No limit from the arms, as the paper's noise experiments and `experiment goal` (under
    /// `increment` noise the believed pose wanders from the true one by a random walk of
    /// 10 mm a move, and soon leaves the arms' workspace).
    Any,
    /// The SDA10F's dual-arm IK and arm collisions: a run stops at a pose they cannot reach.
    Robot,
}

/// The settings of the tracking experiment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackParams {
    /// The settings every experiment takes (`wire` defaults to [`DEFAULT_WIRE`]; `trials` is
    /// not used: see `pairs`).
    pub common: CommonParams,
    /// The noise, the calibration and how the closed loop tracks.
    pub rollout: RolloutParams,
    /// Start–goal pairs, at least 1 (default [`DEFAULT_PAIRS`]).
    pub pairs: usize,
    /// What limits the closed loop's commanded poses (the pairs and the plans are in
    /// `Z_free`, reachable, either way).
    pub reach: ArmReach,
}

impl Default for TrackParams {
    fn default() -> Self {
        Self {
            common: CommonParams::default(),
            rollout: RolloutParams::default(),
            pairs: DEFAULT_PAIRS,
            reach: ArmReach::Any,
        }
    }
}

impl TrackParams {
    /// The true wire: `common.wire`, or [`DEFAULT_WIRE`].
    ///
    /// # Errors
    /// Bad input for an unknown preset or a bad wire file.
    pub fn wire(&self) -> Result<WireSpec, LabError> {
        self.common.wire_or(DEFAULT_WIRE)
    }

    /// Checks the settings as [`run`] does before any work (the roll-out settings, the
    /// count, the wire, the sensor and the rig), so that a caller can refuse bad input before
    /// it opens a results folder.
    ///
    /// # Errors
    /// Bad input naming what is wrong.
    pub fn check(&self) -> Result<(), LabError> {
        self.rollout.check()?;
        if self.pairs == 0 {
            return Err(LabError::bad_input("pairs 0: give at least 1 pair"));
        }
        let wire = self.wire()?;
        self.common.setup()?;
        scene_model(
            &wire,
            self.common.gravity,
            self.common.model(),
            &free_scene()?,
        )?;
        Ok(())
    }
}

/// The scene the pairs are drawn in: no obstacles, the base gripper where the shipped
/// passage holds it.
fn free_scene() -> Result<Scene, LabError> {
    let (passage, _) = passage::load_scene(None)?;
    Ok(Scene {
        base: passage.base,
        boxes: Vec::new(),
        floor: None,
        configurations: BTreeMap::new(),
    })
}

/// Table IV's row of one mode.
#[derive(Debug, Clone, Serialize)]
pub struct Metrics {
    /// Mean shape error along the paths \[mm\].
    pub mean_mm: f64,
    /// Its standard deviation \[mm\].
    pub std_mm: f64,
    /// The largest shape error \[mm\].
    pub max_mm: f64,
    /// Waypoints the statistics cover.
    pub waypoints: usize,
    /// Outcome counts of the runs (`successes` by the summary's `success_rule`).
    pub runs: Rates,
}

/// Table IV: both modes' rows.
#[derive(Debug, Clone, Serialize)]
pub struct TrackResults {
    /// The planned gripper poses rolled out with no feedback.
    pub open_loop: Metrics,
    /// The controller from waypoint to waypoint.
    pub closed_loop: Metrics,
}

/// How the pairs were drawn.
#[derive(Debug, Clone, Default, Serialize)]
pub struct PairDraws {
    /// Pairs drawn.
    pub drawn: usize,
    /// Draws with a start or goal outside `Z_free` (by reason).
    pub invalid: BTreeMap<String, usize>,
    /// Draws whose ends were closer than [`MIN_PAIR_DISTANCE`].
    pub too_close: usize,
    /// Draws the planner found no path for.
    pub no_plan: usize,
}

/// One pair's row of the summary.
#[derive(Debug, Clone, Serialize)]
pub struct PairOut {
    /// The start configuration, normalised.
    pub a_s_normalised: [f64; 6],
    /// The goal configuration, normalised.
    pub a_g_normalised: [f64; 6],
    /// Length of the planned path in normalised `A`.
    pub path_length: f64,
    /// Waypoints tracked.
    pub waypoints: usize,
    /// The closed loop's mean shape error along the path \[mm\].
    pub closed_loop_mean_mm: f64,
    /// The open loop's mean shape error along the path \[mm\].
    pub open_loop_mean_mm: f64,
    /// How the closed loop ended.
    pub closed_loop_outcome: String,
    /// How the open loop ended.
    pub open_loop_outcome: String,
}

/// `summary.json`'s body (after the run header): the same for the same seed.
#[derive(Debug, Clone, Serialize)]
pub struct TrackSummary {
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
    /// Most moves toward each waypoint before the last.
    pub waypoint_moves: usize,
    /// The bias observer's settings of the closed loop (`null`: off, or under `absolute`).
    pub bias_observer: Option<BiasObserverParams>,
    /// Whether the closed loop stopped at poses the arms cannot reach.
    pub reach: ArmReach,
    /// What the runs' `successes` count under this noise model.
    pub success_rule: &'static str,
    /// Pairs planned and tracked.
    pub pairs: usize,
    /// Table IV.
    pub results: TrackResults,
    /// How the pairs were drawn.
    pub pair_draws: PairDraws,
    /// Each pair's row.
    pub per_pair: Vec<PairOut>,
}

/// `timings.json`: wall times, apart from the summary.
#[derive(Debug, Clone, Serialize)]
pub struct TrackTimings {
    /// Loading or running the calibration \[s\].
    pub calibration_s: f64,
    /// Each pair's plan \[ms\].
    pub plan_ms: Vec<f64>,
    /// Their median \[ms\].
    pub plan_ms_median: f64,
    /// Tracking every pair, both modes \[s\].
    pub tracking_s: f64,
    /// The whole run \[s\].
    pub total_s: f64,
}

/// A finished tracking experiment.
#[derive(Debug, Clone)]
pub struct TrackRun {
    /// `summary.json`'s body.
    pub summary: TrackSummary,
    /// `timings.json`.
    pub timings: TrackTimings,
}

/// A planned pair.
struct Planned {
    a_s: Vector6<f64>,
    a_g: Vector6<f64>,
    scene: Scene,
    path_length: f64,
    plan_ms: f64,
    waypoints: Vec<Waypoint>,
}

/// Runs the tracking experiment into `folder` (see the module docs for what it writes),
/// reports its progress (the calibration run first, each pair planned, each mode's Table IV
/// row) to `progress`, and returns the summary and timings for the caller to write (it does
/// not finish the folder).
///
/// # Errors
/// Bad input for bad settings ([`TrackParams::check`]) or a bad calibration file; no answer
/// when too few pairs can be planned or a roll-out cannot start; I/O errors writing the
/// folder.
pub fn run(
    params: &TrackParams,
    folder: &ResultsFolder,
    progress: Progress<'_>,
) -> Result<TrackRun, LabError> {
    let total = Instant::now();
    params.check()?;
    let (common, rollout) = (&params.common, &params.rollout);
    let wire = params.wire()?;
    let free = free_scene()?;
    let setup = common.setup()?;
    let model = scene_model(&wire, common.gravity, common.model(), &free)?;
    let (calibration, calibration_s) = load_or_run_reporting(
        folder,
        rollout.calibration.as_deref(),
        (common.gravity, common.model()),
        (&setup, common.seed),
        &mut *progress,
    )?;
    let (planned, draws) = draw_and_plan(
        &free,
        &Rod::new(*model.wire()),
        model.rod(),
        params.pairs,
        common.seed,
        plan_policy(rollout.noise).validity_tracked(model.rod()),
        progress,
    )?;
    progress(&format!("{} pairs planned ({draws:?})", planned.len()));

    let started = Instant::now();
    let tracking = Tracking {
        wire: &wire,
        gravity: common.gravity,
        scene: &free,
        calibration: &calibration,
        setup: &setup,
        noise: rollout.noise,
        seed: common.seed,
        policy: rollout.policy,
        arms: params.reach == ArmReach::Robot,
        bias_observer: rollout.bias_observer,
    };
    let (closed, open) = track_pairs(&tracking, &model, &planned)?;
    let tracking_s = started.elapsed().as_secs_f64();

    let results = TrackResults {
        open_loop: metrics(&open),
        closed_loop: metrics(&closed),
    };
    for (name, m) in [
        ("closed loop", &results.closed_loop),
        ("open loop", &results.open_loop),
    ] {
        progress(&format!(
            "{name}: shape error along the paths {:.2} ± {:.2} mm (max {:.2} mm)",
            m.mean_mm, m.std_mm, m.max_mm
        ));
    }
    let wire_params = *model.wire();
    let per_pair = per_pair(&wire_params, &planned, &closed, &open);
    folder.write("pairs.csv", pairs_csv(&per_pair)?)?;
    folder.write("waypoints.csv", waypoints_csv("pair", &closed)?)?;
    write_figures(folder, &wire_params, &planned, &closed, &open)?;
    let plan_ms: Vec<f64> = planned.iter().map(|p| p.plan_ms).collect();
    let policy = &rollout.policy;
    let summary = TrackSummary {
        wire: wire.name.clone(),
        model: common.model(),
        noise_model: rollout.noise,
        gain: policy.gain,
        shape_stop_mm: 1e3 * policy.shape_stop,
        waypoint_moves: policy.through.max_iterations,
        bias_observer: bias_observer(&setup, rollout.noise, rollout.bias_observer),
        success_rule: policy.success_rule(),
        reach: params.reach,
        pairs: planned.len(),
        results,
        pair_draws: draws,
        per_pair,
    };
    let timings = TrackTimings {
        calibration_s,
        plan_ms_median: median(&plan_ms),
        plan_ms,
        tracking_s,
        total_s: total.elapsed().as_secs_f64(),
    };
    Ok(TrackRun { summary, timings })
}

/// Tracks every planned pair closed loop (unarmed: nothing to collide with) and open loop, in
/// parallel, pair `k` of both under noise stream `FIRST_STREAM + k` and in its own scene:
/// the closed-loop attempts, then the open-loop ones.
fn track_pairs(
    tracking: &Tracking<'_>,
    model: &KirchhoffModel,
    planned: &[Planned],
) -> Result<(Vec<Attempt>, Vec<Attempt>), LabError> {
    let runs: Vec<(Attempt, Attempt)> = planned
        .par_iter()
        .enumerate()
        .map(|(k, p)| {
            let tracking = Tracking {
                scene: &p.scene,
                ..*tracking
            };
            let stream = FIRST_STREAM + k as u64;
            let closed = tracking.closed_loop_unarmed(model, &p.waypoints, stream)?;
            let open = tracking.open_loop(model, &p.waypoints, stream)?;
            Ok((closed, open))
        })
        .collect::<Result<_, LabError>>()?;
    Ok(runs.into_iter().unzip())
}

/// Each pair's row of the summary.
fn per_pair(
    wire: &ftwire_core::WireParams,
    planned: &[Planned],
    closed: &[Attempt],
    open: &[Attempt],
) -> Vec<PairOut> {
    planned
        .iter()
        .zip(closed.iter().zip(open))
        .map(|(p, (c, o))| PairOut {
            a_s_normalised: to_normalised(wire, &p.a_s).into(),
            a_g_normalised: to_normalised(wire, &p.a_g).into(),
            path_length: p.path_length,
            waypoints: p.waypoints.len(),
            closed_loop_mean_mm: mean_std(&c.shape_mm).0,
            open_loop_mean_mm: mean_std(&o.shape_mm).0,
            closed_loop_outcome: c.outcome.clone(),
            open_loop_outcome: o.outcome.clone(),
        })
        .collect()
}

/// Draws pairs in `Z_free` of `free` and plans each (with `planner`; waypoints of `tracker`)
/// until `count` have a plan, reporting each to `progress`; returns them and how they were
/// drawn.
fn draw_and_plan(
    free: &Scene,
    planner: &Rod,
    tracker: &Rod,
    count: usize,
    seed: u64,
    validity: ValidityParams,
    progress: Progress<'_>,
) -> Result<(Vec<Planned>, PairDraws), LabError> {
    let mut draws = PairDraws::default();
    let robot = Robot::sda10f().map_err(|e| LabError::bad_input(e.to_string()))?;
    let checker = Checker::new(*planner, robot, free, validity)
        .map_err(|e| LabError::bad_input(e.to_string()))?;
    let sampler = Sampler {
        half_width: PAIR_BOX,
        ..Sampler::default()
    };
    let wire = planner.wire();
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(15));
    let mut out = Vec::with_capacity(count);
    while out.len() < count {
        if draws.drawn >= MAX_DRAWS_PER_PAIR * count {
            return Err(LabError::no_answer(format!(
                "planned only {} of {count} pairs in {} draws ({draws:?})",
                out.len(),
                draws.drawn
            )));
        }
        draws.drawn += 1;
        let mut draw = || {
            sampler
                .sample_free(planner, &mut rng)
                .map_err(|e| from_rod(e, "sampling A_free"))
        };
        let (a_s, a_g) = (draw()?, draw()?);
        if (to_normalised(wire, &a_g) - to_normalised(wire, &a_s)).norm() < MIN_PAIR_DISTANCE {
            draws.too_close += 1;
            continue;
        }
        if let Some(key) = unusable(&checker, tracker, &free.base, [a_s, a_g]) {
            *draws.invalid.entry(key).or_insert(0) += 1;
            continue;
        }
        let mut scene = free.clone();
        scene
            .configurations
            .insert("start".to_owned(), ConfigurationSpec::A(a_s));
        scene
            .configurations
            .insert("goal".to_owned(), ConfigurationSpec::A(a_g));
        let pair_seed = seed
            .wrapping_add(PLAN_RESTARTS)
            .wrapping_add(draws.drawn as u64);
        match plan_in_scene(&scene, planner, validity, pair_seed) {
            Ok((plan, _)) => {
                let waypoints =
                    waypoints_along(tracker, &scene.base, &plan.plan.path.waypoints, WAYPOINTS)
                        .map_err(|e| from_plan(e, "a waypoint of the path"))?;
                out.push(Planned {
                    a_s,
                    a_g,
                    scene,
                    path_length: plan.plan.path.cost,
                    plan_ms: 1e3 * plan.seconds,
                    waypoints,
                });
                // Planning a heavy wire's pairs can take minutes: say how far it is.
                progress(&format!(
                    "pair {} / {count} planned ({} draws, {:.1} s)",
                    out.len(),
                    draws.drawn,
                    plan.seconds
                ));
            }
            Err(_) => draws.no_plan += 1,
        }
    }
    Ok((out, draws))
}

/// Why a drawn pair cannot be tracked, as `pair_draws.invalid` counts it (the reason's first
/// words); `None` when both ends rest under the tracking model `tracker` (the loaded one with
/// gravity on: a pair stable only for the weightless planner would put a heavy wire, such as
/// the cable, where the simulator finds no equilibrium) and are in `Z_free` of `checker` with
/// the base gripper at `base`. The stability check, a single solve, goes first; the arms' IK
/// is the costly one.
fn unusable(
    checker: &Checker,
    tracker: &Rod,
    base: &Pose,
    ends: [Vector6<f64>; 2],
) -> Option<String> {
    if ends.iter().any(|a| !tracker.is_stable(a).unwrap_or(false)) {
        return Some("unstable under the tracking model".to_owned());
    }
    let reason = ends
        .iter()
        .find_map(|a| checker.endpoint(&ZPoint { a: *a, base: *base }).err())?;
    Some(
        format!("{reason}")
            .split([':', '('])
            .next()
            .unwrap_or_default()
            .trim()
            .to_owned(),
    )
}

/// Table IV's row over every waypoint of every run.
fn metrics(attempts: &[Attempt]) -> Metrics {
    let all: Vec<f64> = attempts.iter().flat_map(|a| a.shape_mm.clone()).collect();
    let (mean_mm, std_mm) = mean_std(&all);
    Metrics {
        mean_mm,
        std_mm,
        max_mm: all.iter().copied().fold(f64::NAN, f64::max),
        waypoints: all.len(),
        runs: Rates::of(attempts),
    }
}

/// `pairs.csv`: one row per pair.
fn pairs_csv(pairs: &[PairOut]) -> Result<Vec<u8>, LabError> {
    let mut csv = CsvTable::new(
        "pairs.csv",
        &[
            "pair",
            "path_length",
            "waypoints",
            "closed_loop_mean_mm",
            "open_loop_mean_mm",
            "closed_loop_outcome",
            "open_loop_outcome",
        ],
    )?;
    for (k, p) in pairs.iter().enumerate() {
        csv.row([
            value(k),
            fixed(p.path_length, 4),
            value(p.waypoints),
            fixed(p.closed_loop_mean_mm, 3),
            fixed(p.open_loop_mean_mm, 3),
            text(&p.closed_loop_outcome),
            text(&p.open_loop_outcome),
        ])?;
    }
    csv.into_bytes()
}

/// Figs. 8–9.
fn write_figures(
    folder: &ResultsFolder,
    wire: &ftwire_core::WireParams,
    planned: &[Planned],
    closed: &[Attempt],
    open: &[Attempt],
) -> Result<(), LabError> {
    if let (Some(first), Some(c), Some(o)) = (planned.first(), closed.first(), open.first()) {
        let plan: Vec<Vector6<f64>> = first
            .waypoints
            .iter()
            .map(|w| to_normalised(wire, &w.a))
            .collect();
        let (i, j) = passage::main_axes(&plan);
        let project = |a: &Vector6<f64>| (a[i], a[j]);
        let rollout = |a: &Attempt| -> Vec<(f64, f64)> {
            a.a_true
                .iter()
                .map(|x| project(&to_normalised(wire, &Vector6::from(*x))))
                .collect()
        };
        let chart = LineChart::new(
            "pair 0: the plan in A and the roll-outs (true configuration)",
            format!("{} (normalised)", passage::component(i)),
            format!("{} (normalised)", passage::component(j)),
        )
        .with_series(Series::line_points(
            "plan γ_A",
            plan.iter().map(project).collect(),
        ))
        .with_series(Series::line("closed loop", rollout(c)))
        .with_series(Series::line("open loop", rollout(o)));
        folder.write_figure("track_path_in_a", |dir| chart.write(dir, "track_path_in_a"))?;
    }
    let mut errors = LineChart::new(
        "shape error along the planned paths",
        "waypoint",
        "mean distance to Φ(γ_A) [mm]",
    );
    for (k, (c, o)) in closed.iter().zip(open).enumerate() {
        let along = |a: &Attempt| -> Vec<(f64, f64)> {
            a.shape_mm
                .iter()
                .enumerate()
                .map(|(w, &e)| (w as f64 + 1.0, e))
                .collect()
        };
        errors = errors
            .with_series(Series::line(format!("closed {k}"), along(c)))
            .with_series(Series::line(format!("open {k}"), along(o)));
    }
    folder.write_figure("track_shape_error", |dir| {
        errors.write(dir, "track_shape_error")
    })
}

#[cfg(test)]
mod tests {
    use crate::experiment::Gravity;

    use super::*;

    #[test]
    fn table_iv_covers_every_waypoint_of_every_run() {
        let run = |shape_mm: Vec<f64>| Attempt {
            mode: "closed_loop",
            outcome: "reached".to_owned(),
            steps: 3,
            touched: false,
            detected: false,
            retreats: 0,
            undone: 0,
            skipped: 0,
            relocated: false,
            final_error: 0.01,
            completed: true,
            at_goal: true,
            success: true,
            shape_mm,
            centrelines: Vec::new(),
            a_true: Vec::new(),
            legs: Vec::new(),
        };
        let m = metrics(&[run(vec![1.0, 2.0]), run(vec![6.0])]);
        assert_eq!(m.waypoints, 3);
        assert!((m.mean_mm - 3.0).abs() < 1e-12);
        assert_eq!(m.max_mm, 6.0);
        assert_eq!(m.runs.successes, 2);
    }

    #[test]
    fn a_cable_pair_that_rests_only_without_its_weight_is_not_drawn() {
        // The weightless planner's model has the cable stable where its weight makes it
        // unstable: the simulator found no equilibrium at seed 0's second start before this
        // check.
        let wire = WireSpec::preset("cable-3mm-920").expect("a preset");
        let free = free_scene().expect("the passage's base pose");
        let model =
            scene_model(&wire, Gravity::On, ModelKind::Loaded, &free).expect("the loaded model");
        let planner = Rod::new(*model.wire());
        let robot = Robot::sda10f().expect("the robot");
        let checker = Checker::new(
            planner,
            robot,
            &free,
            plan_policy(NoiseModel::Increment).validity(planner.wire().length()),
        )
        .expect("a checker");
        let sampler = Sampler {
            half_width: PAIR_BOX,
            ..Sampler::default()
        };
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        let (mut heavy, mut both) = (None, None);
        for _ in 0..2000 {
            let a = sampler.sample_free(&planner, &mut rng).expect("a sample");
            match model.rod().is_stable(&a) {
                Ok(false) => heavy = heavy.or(Some(a)),
                Ok(true) => both = both.or(Some(a)),
                Err(_) => {}
            }
            if heavy.is_some() && both.is_some() {
                break;
            }
        }
        let (heavy, both) = (heavy.expect("one unstable"), both.expect("one stable"));
        assert_eq!(
            unusable(&checker, model.rod(), &free.base, [both, heavy]).as_deref(),
            Some("unstable under the tracking model")
        );
        assert_eq!(
            unusable(&checker, model.rod(), &free.base, [heavy, both]).as_deref(),
            Some("unstable under the tracking model")
        );
        // Stable under both models: the verdict is Z_free's (reachable, or why not).
        let verdict = unusable(&checker, model.rod(), &free.base, [both, both]);
        assert_ne!(
            verdict.as_deref(),
            Some("unstable under the tracking model")
        );
    }
}
