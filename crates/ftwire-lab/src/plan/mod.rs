//! A wire's path among a scene's obstacles ([`run`]: RRT* in `A_free` or in `Z = A × Q`,
//! `ftwire plan`) and a scene's check ([`check_scene`]: each named configuration in `Z_free`
//! or not, `ftwire scene check`). `ftwire-plan` does the work; this module reads the scene
//! and the wire, builds the validity checker on the SDA10F, and reports.
//!
//! The answers ([`PlanReport`], [`SceneReport`]) serialise to the commands' JSON and display
//! as their text. Guarded by the `ftwire` binary's `tests/plan_cli.rs` and by
//! `tests/plan.rs` of this crate.

mod check;
mod planner;
mod report;

use std::path::{Path, PathBuf};
use std::time::Duration;

use ftwire_app::input::CountRange;
use ftwire_plan::{
    Checker, FixedBase, MovingBase, Plan, PlannerParams, Sample, Scene, ValidityParams, plan,
    scene_endpoint,
};
use ftwire_robot::Robot;
use ftwire_rod::Rod;
use serde::Serialize;

pub use check::{ConfigurationCheck, SceneCheckParams, SceneReport, check_scene};
pub use planner::Planner;
pub use report::{JointsJson, PlanReport, PoseJson, WaypointJson};

use crate::error::{FrontEnd, LabError, from_plan};
use crate::wire::WireSpec;

/// Largest time budget \[s\]. The tree keeps every node's sample, its wire's centreline
/// among it (a few kilobytes), and grows by a few hundred nodes a second at most, so ten
/// minutes keep it under a gigabyte.
pub const MAX_TIME_BUDGET: f64 = 600.0;

/// `--iterations`: its default, which `--time-budget` ends first on any machine at the
/// default budget; both bound the tree.
pub const ITERATIONS: CountRange = CountRange::new(1, 1_000_000);

/// `--resample`: each resampled waypoint is solved, checked and printed whole (a kilobyte or
/// two in memory and in the output), so the cap bounds both at a few hundred megabytes.
pub const RESAMPLE: CountRange = CountRange::new(1, 100_000);

/// The wire a scene is planned or checked for, and how far from the obstacles it must stay.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanWireParams {
    /// A wire preset or a wire file (TOML) (default `nitinol-3mm-820`).
    pub wire: String,
    /// Clearance \[m\] the wire's surface keeps from every obstacle and the floor (default
    /// `0.005`).
    pub margin: f64,
    /// Largest distance between the grippers as a fraction of the wire's length, in (0, 1]
    /// (default `1.0`: whatever the model allows).
    pub max_span: f64,
}

impl Default for PlanWireParams {
    fn default() -> Self {
        Self {
            wire: "nitinol-3mm-820".to_owned(),
            margin: 0.005,
            max_span: 1.0,
        }
    }
}

/// The settings of a plan (`ftwire plan`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanParams {
    /// The scene file (TOML); required ([`PlanParams::check`] refuses `None`).
    pub scene: Option<PathBuf>,
    /// The wire and the validity margins.
    pub wire: PlanWireParams,
    /// The start configuration's name in the scene (default `start`).
    pub start: String,
    /// The goal configuration's name in the scene (default `goal`).
    pub goal: String,
    /// Wall-clock budget \[s\], more than 0 and at most [`MAX_TIME_BUDGET`] (default `2.0`):
    /// the best path found by then is returned (anytime).
    pub time_budget: f64,
    /// Most iterations (default `1_000_000`); whichever of it and the budget ends first.
    pub iterations: usize,
    /// Stop at the first path found, then shortcut it (default `false`).
    pub first: bool,
    /// The planning space (default [`Planner::Fixed`]).
    pub planner: Planner,
    /// Weight `w` of the clearance penalty: an edge closer than `clearance_reference` to an
    /// obstacle costs its length times `1 + w (reference / clearance − 1)` (default `0.0`).
    pub clearance_weight: f64,
    /// Clearance \[m\] below which an edge is penalised (default `0.02`).
    pub clearance_reference: f64,
    /// Also resample the path into `N + 1` equally spaced waypoints `γ(i/N)` (default none).
    pub resample: Option<usize>,
    /// The planner's seed (default `0`).
    pub seed: u64,
}

impl Default for PlanParams {
    fn default() -> Self {
        Self {
            scene: None,
            wire: PlanWireParams::default(),
            start: "start".to_owned(),
            goal: "goal".to_owned(),
            time_budget: 2.0,
            iterations: 1_000_000,
            first: false,
            planner: Planner::Fixed,
            clearance_weight: 0.0,
            clearance_reference: 0.02,
            resample: None,
            seed: 0,
        }
    }
}

impl PlanParams {
    /// Checks the time budget and that a scene is given, as [`run`] does first.
    ///
    /// # Errors
    /// Bad input naming the option (`--time-budget`, `--scene`) and what is allowed.
    pub fn check(&self) -> Result<(), LabError> {
        self.check_from(FrontEnd::Cli)
    }

    /// [`PlanParams::check`], its errors naming the inputs as `front_end` spells them
    /// (`time_budget` for Python).
    ///
    /// # Errors
    /// As [`PlanParams::check`].
    pub fn check_from(&self, front_end: FrontEnd) -> Result<(), LabError> {
        self.budget(front_end)?;
        self.scene_file(front_end)?;
        Ok(())
    }

    /// The time budget as a duration.
    fn budget(&self, front_end: FrontEnd) -> Result<Duration, LabError> {
        Duration::try_from_secs_f64(self.time_budget)
            .ok()
            .filter(|b| !b.is_zero() && self.time_budget <= MAX_TIME_BUDGET)
            .ok_or_else(|| {
                LabError::bad_input(format!(
                    "{} {} s: give more than 0 and at most {MAX_TIME_BUDGET} seconds",
                    front_end.spell("--time-budget"),
                    self.time_budget
                ))
            })
    }

    /// The scene file.
    fn scene_file(&self, front_end: FrontEnd) -> Result<&Path, LabError> {
        self.scene.as_deref().ok_or_else(|| {
            LabError::bad_input(format!(
                "{} FILE.toml is required: the scene to plan in",
                front_end.spell("--scene")
            ))
        })
    }

    /// The planner's settings under `budget`.
    fn planner(&self, budget: Duration) -> PlannerParams {
        PlannerParams {
            seed: self.seed,
            time_budget: Some(budget),
            max_iterations: self.iterations,
            stop_at_first: self.first,
            clearance_weight: self.clearance_weight,
            clearance_reference: self.clearance_reference,
            ..PlannerParams::default()
        }
    }
}

/// The scene, the wire model and the checker of a plan or a check.
fn setup(
    file: &Path,
    wire: &PlanWireParams,
    front_end: FrontEnd,
) -> Result<(Scene, WireSpec, Checker), LabError> {
    let scene = Scene::load(file).map_err(|e| from_plan(e, "reading the scene"))?;
    let wire_error = |e: &dyn std::fmt::Display| {
        LabError::bad_input(format!("{}: {e}", front_end.spell("--wire")))
    };
    let spec = WireSpec::load(&wire.wire).map_err(|e| wire_error(&e))?;
    let params = spec.wire_params().map_err(|e| wire_error(&e))?;
    let robot = Robot::sda10f().map_err(|e| LabError::bad_input(e.to_string()))?;
    let validity = ValidityParams {
        margin: wire.margin,
        max_span: wire.max_span,
        ..ValidityParams::default()
    };
    let margins = format!(
        "{} or {}",
        front_end.spell("--margin"),
        front_end.spell("--max-span")
    );
    let checker = Checker::new(Rod::new(params), robot, &scene, validity)
        .map_err(|e| from_plan(e, &margins))?;
    Ok((scene, spec, checker))
}

/// Plans a path of the wire from the scene's start to its goal (RRT* in `params.planner`'s
/// space, seeded by `params.seed`, until the budget or the iterations end).
///
/// # Errors
/// Bad input for bad settings ([`PlanParams::check`]), an unreadable scene, an unknown wire,
/// bad margins, or a start or goal outside `Z_free`; no answer when no path is found within
/// the budget or the path cannot be resampled.
pub fn run(params: &PlanParams) -> Result<PlanReport, LabError> {
    run_from(params, FrontEnd::Cli)
}

/// [`run`], its errors naming the inputs as `front_end` spells them (`time_budget`,
/// `wire` for Python).
///
/// # Errors
/// As [`run`].
pub fn run_from(params: &PlanParams, front_end: FrontEnd) -> Result<PlanReport, LabError> {
    let budget = params.budget(front_end)?;
    let scene_file = params.scene_file(front_end)?;
    let (scene, spec, checker) = setup(scene_file, &params.wire, front_end)?;
    let file = scene_file.display().to_string();
    let endpoint = |name: &str, role: &'static str| {
        scene_endpoint(&scene, &checker, name, role).map_err(|e| from_plan(e, &file))
    };
    let start = endpoint(&params.start, "start")?;
    let goal = endpoint(&params.goal, "goal")?;
    let context = format!("planning in {file}");
    let (found, resampled) = search(params, budget, &scene, &checker, &start, &goal)
        .map_err(|e| from_plan(e, &context))?;
    let waypoints = |samples: &[Sample]| -> Vec<WaypointJson> {
        samples
            .iter()
            .map(|s| WaypointJson::new(checker.rod(), s))
            .collect()
    };
    let resampled = match resampled {
        Some(Ok(r)) => Some(waypoints(&r)),
        Some(Err(e)) => {
            return Err(LabError::no_answer(format!(
                "{context}: the path could not be resampled: {e}"
            )));
        }
        None => None,
    };
    let path = &found.path;
    Ok(PlanReport {
        scene: file,
        wire: spec.name,
        planner: params.planner,
        seed: params.seed,
        start: params.start.clone(),
        goal: params.goal.clone(),
        iterations: found.iterations,
        nodes: found.nodes,
        first_path_iteration: found.first_path_iteration,
        first_path_seconds: found.first_path_seconds,
        seconds: found.seconds,
        cost: path.cost,
        length: path.length(&checker),
        base_travel: path.base_travel(),
        min_clearance: path.min_clearance(),
        waypoints: waypoints(&path.waypoints),
        resampled,
    })
}

/// A path resampled into equally spaced waypoints, or why it could not be.
type Resampled = Result<Vec<Sample>, ftwire_plan::Invalid>;

/// RRT* in the chosen space, then the resampling if asked for.
fn search(
    params: &PlanParams,
    budget: Duration,
    scene: &Scene,
    checker: &Checker,
    start: &Sample,
    goal: &Sample,
) -> Result<(Plan, Option<Resampled>), ftwire_plan::PlanError> {
    let settings = params.planner(budget);
    let wire = *checker.rod().wire();
    let fixed = FixedBase::around(wire, scene.base, &[start.config, goal.config], 2.0);
    Ok(match params.planner {
        Planner::Fixed => {
            let found = plan(&fixed, checker, start, &goal.config, &settings)?;
            let resampled = params
                .resample
                .map(|n| found.path.resample(&fixed, checker, n));
            (found, resampled)
        }
        Planner::Moving => {
            let space = MovingBase::new(wire, scene.base, 0.0).with_a_box(fixed.lower, fixed.upper);
            let found = plan(&space, checker, start, &goal.config, &settings)?;
            let resampled = params
                .resample
                .map(|n| found.path.resample(&space, checker, n));
            (found, resampled)
        }
    })
}
