//! A plan through a scene for tracking: RRT* with a fixed iteration budget and seeded restarts
//! ([`plan_in_scene`]), and the choice among several such plans by their expected touching
//! landings ([`choose_plan`]).

use std::time::Instant;

use ftwire_robot::Robot;
use ftwire_rod::Rod;
use rayon::prelude::*;
use serde::Serialize;

use crate::{
    Checker, FixedBase, Plan, PlanError, PlanPolicy, PlannerParams, PolishOut, Scene,
    ValidityParams, Waypoint, expected_touches, plan, polish_waypoints, scene_endpoint,
    waypoints_along,
};

/// RRT* iterations of [`plan_in_scene`]'s first attempt (an iteration budget, not a time
/// budget, so that the path does not depend on the machine's speed).
pub const PLAN_ITERATIONS: usize = 1000;

/// Planner restarts of [`plan_in_scene`], each with its own seed drawn from the caller's (a
/// tree grown from unlucky first samples can stall) and twice the budget of the one before
/// (1000, 2000, 4000, 8000 iterations): a `Z_free` narrowed by the margins of
/// [`PlanPolicy::scattered`] needs more than the first budget to a passage's first path.
pub const PLAN_RESTARTS: u64 = 4;

/// Waypoints the plan is resampled into (`N` of `γ_A(i/N)`).
pub const WAYPOINTS: usize = 12;

/// Plans [`choose_plan`] makes by default.
pub const PLAN_CANDIDATES: usize = 4;

/// A plan and its waypoints.
#[derive(Debug, Clone)]
pub struct ScenePlan {
    /// The planner's result.
    pub plan: Plan,
    /// `γ_A(i/N)`, `i = 0..=N` ([`waypoints_along`]).
    pub waypoints: Vec<Waypoint>,
    /// Wall time of the planning \[s\].
    pub seconds: f64,
}

/// Plans from the scene's `start` to its `goal` for the wire model `rod` (fixed base) under
/// the validity settings `validity` ([`PlanPolicy::validity`] for a plan that is to be
/// tracked), with [`PLAN_RESTARTS`] seeded restarts from `seed`, and resamples the path into
/// [`WAYPOINTS`] legs of `rod`. Also returns the checker.
///
/// # Errors
/// [`PlanError::InvalidEndpoint`] for an invalid start or goal; the last restart's
/// [`PlanError::NoPath`] when no path is found; [`PlanError::Robot`] when the robot cannot be
/// loaded.
pub fn plan_in_scene(
    scene: &Scene,
    rod: &Rod,
    validity: ValidityParams,
    seed: u64,
) -> Result<(ScenePlan, Checker), PlanError> {
    let checker = Checker::new(*rod, Robot::sda10f()?, scene, validity)?;
    let start = scene_endpoint(scene, &checker, "start", "start")?;
    let goal = scene_endpoint(scene, &checker, "goal", "goal")?;
    let began = Instant::now();
    let space = FixedBase::around(*rod.wire(), scene.base, &[start.config, goal.config], 2.0);
    let mut last = None;
    let mut found = None;
    for restart in 0..PLAN_RESTARTS {
        let params = PlannerParams {
            seed: seed.wrapping_add(restart.wrapping_mul(0x9e37_79b9_7f4a_7c15)),
            time_budget: None,
            max_iterations: PLAN_ITERATIONS << restart,
            ..PlannerParams::default()
        };
        match plan(&space, &checker, &start, &goal.config, &params) {
            Ok(plan) => {
                found = Some(plan);
                break;
            }
            Err(e) => last = Some(e),
        }
    }
    let found = match (found, last) {
        (Some(found), _) => found,
        (None, Some(e)) => return Err(e),
        (None, None) => return Err(PlanError::EmptyPath),
    };
    let waypoints = waypoints_along(rod, &scene.base, &found.path.waypoints, WAYPOINTS)?;
    let seconds = began.elapsed().as_secs_f64();
    Ok((
        ScenePlan {
            plan: found,
            waypoints,
            seconds,
        },
        checker,
    ))
}

/// The seed of [`choose_plan`]'s candidate `k` from the run's `seed`: `seed` itself for the
/// first, so that one candidate plans as [`plan_in_scene`] does.
pub fn candidate_seed(seed: u64, k: usize) -> u64 {
    seed.wrapping_add((k as u64).wrapping_mul(0xd1b5_4a32_d192_ed03))
}

/// How [`choose_plan`] chose, in the summaries (`plan.choice`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChoiceOut {
    /// Plans made, each from its own seed ([`candidate_seed`]).
    pub candidates: usize,
    /// Each candidate's expected touching landings ([`expected_touches`] of its tracked,
    /// polished waypoints); `null` for a candidate that found no path, or whose waypoints the
    /// tracking model refused.
    pub expected_touches: Vec<Option<f64>>,
    /// The candidate tracked (0-based): the fewest expected touches, the first among equals.
    pub chosen: usize,
}

/// A plan chosen by [`choose_plan`], with its tracked waypoints.
#[derive(Debug)]
pub struct Chosen {
    /// The plan.
    pub planned: ScenePlan,
    /// Its waypoints as tracked (`prepare`d, then polished when asked).
    pub waypoints: Vec<Waypoint>,
    /// What the polish did (`None` when not asked).
    pub polish: Option<PolishOut>,
    /// How it was chosen (`None` when one plan was made without a choice).
    pub choice: Option<ChoiceOut>,
    /// Wall time of all the candidates' planning, preparing, polishing and scoring \[s\].
    pub seconds: f64,
    /// Each candidate's planning wall time \[ms\] (`None` when it found no path), for the
    /// timings (not [`ChoiceOut`], so that the summaries are the same for the same seed).
    pub candidate_plan_ms: Vec<Option<f64>>,
}

/// Plans `candidates` times from the scene's `start` to its `goal` ([`plan_in_scene`] with
/// `planner` and `validity`, from the seeds [`candidate_seed`]), turns each plan into the
/// waypoints tracked with `tracker` (`prepare`, then [`polish_waypoints`] when `polish`), and
/// keeps the one with the fewest [`expected_touches`] under `policy`.
///
/// Why: under fresh noise per move a path's touches are a property of the plan far more than
/// of the run, and one noisy move's landings rank the plans before any roll-out
/// (`docs/design/planning.md`). The choice runs only where [`PlanPolicy::polishes`];
/// otherwise one plan is made and `choice` is `None`. The candidates are made in parallel and
/// compared in order: the same seed chooses the same plan on any machine.
///
/// # Errors
/// The first error (planning, `prepare` or the polish) when no candidate gave waypoints to
/// track; [`PlanError::InvalidParameter`] for no candidates.
#[allow(clippy::too_many_arguments)]
pub fn choose_plan<E: From<PlanError> + Send>(
    scene: &Scene,
    planner: &Rod,
    tracker: &Rod,
    validity: ValidityParams,
    policy: &PlanPolicy,
    seed: u64,
    candidates: usize,
    polish: bool,
    prepare: impl Fn(&ScenePlan) -> Result<Vec<Waypoint>, E> + Sync,
) -> Result<Chosen, E> {
    if candidates == 0 {
        return Err(E::from(PlanError::InvalidParameter {
            name: "candidates",
            value: 0.0,
            allowed: "at least 1 plan",
        }));
    }
    let began = Instant::now();
    let chooses = policy.polishes();
    let candidates = if chooses { candidates } else { 1 };
    let outcomes: Vec<Candidate<E>> = (0..candidates)
        .into_par_iter()
        .map(|k| {
            let planned = match plan_in_scene(scene, planner, validity, candidate_seed(seed, k)) {
                Ok((planned, _)) => planned,
                Err(e) => return (None, Err(E::from(e))),
            };
            let ms = Some(1e3 * planned.seconds);
            // A plan whose waypoints cannot be prepared or polished (the tracking model has no
            // configuration at one of them) is passed over like one not found.
            let prepared = prepare(&planned).and_then(|waypoints| {
                if polish {
                    polish_waypoints(scene, tracker, policy, &waypoints)
                        .map(|(waypoints, out)| (waypoints, Some(out)))
                        .map_err(E::from)
                } else {
                    Ok((waypoints, None))
                }
            });
            let scored = prepared.map(|(waypoints, polished)| {
                let expected = if chooses {
                    expected_touches(scene, tracker, policy, &waypoints).ok()
                } else {
                    None
                };
                let candidate = Chosen {
                    planned,
                    waypoints,
                    polish: polished,
                    choice: None,
                    seconds: 0.0,
                    candidate_plan_ms: Vec::new(),
                };
                (expected, candidate)
            });
            (ms, scored)
        })
        .collect();
    choose(outcomes, chooses, candidates, began)
}

/// A candidate of [`choose_plan`]: its planning time (`None`: no path), and its expected
/// touches with its plan and waypoints, or why it was passed over.
type Candidate<E> = (Option<f64>, Result<(Option<f64>, Chosen), E>);

/// The candidate with the fewest expected touches (the first among equals), with how it was
/// chosen; the first error when none gave waypoints.
fn choose<E: From<PlanError>>(
    outcomes: Vec<Candidate<E>>,
    chooses: bool,
    candidates: usize,
    began: Instant,
) -> Result<Chosen, E> {
    let mut best: Option<(f64, usize, Chosen)> = None;
    let mut first_error = None;
    let mut touches = Vec::with_capacity(candidates);
    let mut plan_ms = Vec::with_capacity(candidates);
    for (k, (ms, scored)) in outcomes.into_iter().enumerate() {
        plan_ms.push(ms);
        match scored {
            Ok((expected, candidate)) => {
                touches.push(expected);
                let score = expected.unwrap_or(f64::INFINITY);
                if best.as_ref().is_none_or(|(least, ..)| score < *least) {
                    best = Some((score, k, candidate));
                }
            }
            Err(e) => {
                first_error.get_or_insert(e);
                touches.push(None);
            }
        }
    }
    let Some((_, chosen, candidate)) = best else {
        return Err(first_error.unwrap_or_else(|| E::from(PlanError::EmptyPath)));
    };
    Ok(Chosen {
        choice: chooses.then_some(ChoiceOut {
            candidates,
            expected_touches: touches,
            chosen,
        }),
        seconds: began.elapsed().as_secs_f64(),
        candidate_plan_ms: plan_ms,
        ..candidate
    })
}
