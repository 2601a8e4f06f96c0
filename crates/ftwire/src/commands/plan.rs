//! `ftwire plan` and `ftwire scene check`: RRT* among a scene's obstacles, and a scene's
//! validation (ftwire-plan does the work).

use std::io::{self, Write};
use std::time::Duration;

use ftwire::output::{self, Report};
use ftwire_core::Pose;
use ftwire_lab::error::{LabError, from_plan};
use ftwire_lab::wire::WireSpec;
use ftwire_plan::{
    Checker, FixedBase, MovingBase, Plan, PlannerParams, Sample, Scene, ValidityParams, plan,
    scene_configuration,
};
use ftwire_robot::Robot;
use ftwire_rod::{Rod, to_normalised};
use serde::Serialize;

use crate::cli::plan::{
    MAX_TIME_BUDGET, PlanArgs, PlanWireArgs, PlannerArg, SceneArgs, SceneCheckArgs, SceneCommand,
};

/// A pose as JSON: position \[m\] and rotation vector \[rad\].
#[derive(Debug, Serialize)]
struct PoseJson {
    position: [f64; 3],
    rotation: [f64; 3],
}

impl From<&Pose> for PoseJson {
    fn from(p: &Pose) -> Self {
        let (t, r) = (p.translation.vector, p.rotation.scaled_axis());
        Self {
            position: [t.x, t.y, t.z],
            rotation: [r.x, r.y, r.z],
        }
    }
}

/// The robot's joints as JSON \[rad\].
#[derive(Debug, Serialize)]
struct JointsJson {
    torso: f64,
    left: Vec<f64>,
    right: Vec<f64>,
}

/// One waypoint of a path.
#[derive(Debug, Serialize)]
struct WaypointJson {
    /// `a` \[N·m, N\], torque first, base clamp frame.
    a: Vec<f64>,
    /// `a` in normalised units.
    a_normalised: Vec<f64>,
    /// World from the base gripper's clamp frame.
    base: PoseJson,
    /// World from the second gripper's clamp frame.
    tip: PoseJson,
    joints: JointsJson,
    /// The wire surface's clearance from the nearest obstacle \[m\] (capped at 0.1).
    clearance: f64,
}

fn waypoint(rod: &Rod, s: &Sample) -> WaypointJson {
    WaypointJson {
        a: s.config.a.as_slice().to_vec(),
        a_normalised: to_normalised(rod.wire(), &s.config.a).as_slice().to_vec(),
        base: (&s.config.base).into(),
        tip: (&s.tip).into(),
        joints: JointsJson {
            torso: s.joints.torso,
            left: s.joints.left.as_slice().to_vec(),
            right: s.joints.right.as_slice().to_vec(),
        },
        clearance: s.clearance,
    }
}

/// The answer of `ftwire plan`.
#[derive(Debug, Serialize)]
struct PlanReport {
    scene: String,
    wire: String,
    planner: &'static str,
    seed: u64,
    start: String,
    goal: String,
    iterations: usize,
    nodes: usize,
    first_path_iteration: usize,
    first_path_seconds: f64,
    seconds: f64,
    cost: f64,
    /// Path length in normalised `a`.
    length: f64,
    /// How far the base gripper travels \[m\].
    base_travel: f64,
    /// The smallest clearance along the path, edges included \[m\].
    min_clearance: f64,
    waypoints: Vec<WaypointJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    resampled: Option<Vec<WaypointJson>>,
}

impl Report for PlanReport {
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        writeln!(
            out,
            "path from {:?} to {:?} in {} ({} planner, wire {}, seed {})",
            self.start, self.goal, self.scene, self.planner, self.wire, self.seed
        )?;
        writeln!(
            out,
            "  first path after {} iterations, {:.3} s; {} iterations, {} nodes, {:.3} s in all",
            self.first_path_iteration,
            self.first_path_seconds,
            self.iterations,
            self.nodes,
            self.seconds
        )?;
        writeln!(
            out,
            "  {} waypoints, length {:.3} (normalised a), cost {:.3}, base travel {:.3} m, \
             smallest clearance {:.1} mm",
            self.waypoints.len(),
            self.length,
            self.cost,
            self.base_travel,
            self.min_clearance * 1e3
        )?;
        for (i, w) in self.waypoints.iter().enumerate() {
            let a: Vec<String> = w.a_normalised.iter().map(|v| format!("{v:.3}")).collect();
            writeln!(out, "  {i:3}  a/scale = [{}]", a.join(", "))?;
        }
        Ok(())
    }
}

/// One named configuration's verdict.
#[derive(Debug, Serialize)]
struct ConfigurationCheck {
    name: String,
    valid: bool,
    /// Why not, when not valid.
    #[serde(skip_serializing_if = "Option::is_none")]
    reason: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    clearance: Option<f64>,
}

/// The answer of `ftwire scene check`.
#[derive(Debug, Serialize)]
struct SceneReport {
    scene: String,
    wire: String,
    obstacles: Vec<String>,
    floor: Option<f64>,
    start: String,
    goal: String,
    configurations: Vec<ConfigurationCheck>,
}

impl Report for SceneReport {
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        writeln!(out, "scene {} (wire {})", self.scene, self.wire)?;
        writeln!(out, "  obstacles: {}", self.obstacles.join(", "))?;
        if let Some(h) = self.floor {
            writeln!(out, "  floor at z = {h} m")?;
        }
        for c in &self.configurations {
            let role = if c.name == self.start {
                " (start)"
            } else if c.name == self.goal {
                " (goal)"
            } else {
                ""
            };
            match (&c.reason, c.clearance) {
                (None, Some(cl)) => writeln!(
                    out,
                    "  {}{role}: in Z_free, clearance {:.1} mm",
                    c.name,
                    cl * 1e3
                )?,
                (reason, _) => writeln!(
                    out,
                    "  {}{role}: NOT in Z_free: {}",
                    c.name,
                    reason.as_deref().unwrap_or("?")
                )?,
            }
        }
        Ok(())
    }
}

/// The scene, the wire model and the checker of a command.
fn setup(
    file: &std::path::Path,
    wire: &PlanWireArgs,
) -> Result<(Scene, WireSpec, Checker), LabError> {
    let scene = Scene::load(file).map_err(|e| from_plan(e, "reading the scene"))?;
    let spec =
        WireSpec::load(&wire.wire).map_err(|e| LabError::bad_input(format!("--wire: {e}")))?;
    let params = spec
        .wire_params()
        .map_err(|e| LabError::bad_input(format!("--wire: {e}")))?;
    let robot = Robot::sda10f().map_err(|e| LabError::bad_input(e.to_string()))?;
    let validity = ValidityParams {
        margin: wire.margin,
        max_span: wire.max_span,
        ..ValidityParams::default()
    };
    let checker = Checker::new(Rod::new(params), robot, &scene, validity)
        .map_err(|e| from_plan(e, "--margin or --max-span"))?;
    Ok((scene, spec, checker))
}

/// Runs `ftwire scene`.
pub fn run_scene(args: &SceneArgs) -> Result<(), LabError> {
    match &args.command {
        SceneCommand::Check(args) => check(args),
    }
}

fn check(args: &SceneCheckArgs) -> Result<(), LabError> {
    let (scene, spec, checker) = setup(&args.file, &args.wire)?;
    let mut configurations = Vec::new();
    for name in scene.configurations.keys() {
        let verdict = scene_configuration(&scene, checker.rod(), name)
            .map_err(|e| e.to_string())
            .and_then(|c| checker.endpoint(&c).map_err(|e| e.to_string()));
        configurations.push(match verdict {
            Ok(s) => ConfigurationCheck {
                name: name.clone(),
                valid: true,
                reason: None,
                clearance: Some(s.clearance),
            },
            Err(reason) => ConfigurationCheck {
                name: name.clone(),
                valid: false,
                reason: Some(reason),
                clearance: None,
            },
        });
    }
    let report = SceneReport {
        scene: args.file.display().to_string(),
        wire: spec.name.clone(),
        obstacles: scene.boxes.iter().map(|b| b.name.clone()).collect(),
        floor: scene.floor,
        start: args.endpoints.start.clone(),
        goal: args.endpoints.goal.clone(),
        configurations,
    };
    output::print(&report, args.json.json)?;
    // The start and goal must exist and be valid.
    for (role, name) in [
        ("start", &args.endpoints.start),
        ("goal", &args.endpoints.goal),
    ] {
        match report.configurations.iter().find(|c| &c.name == name) {
            None => {
                return Err(from_plan(
                    scene.configuration(name).err().unwrap_or_else(|| {
                        ftwire_plan::PlanError::UnknownConfiguration {
                            name: name.clone(),
                            available: String::new(),
                        }
                    }),
                    &format!("--{role}"),
                ));
            }
            Some(c) if !c.valid => {
                return Err(LabError::bad_input(format!(
                    "{}: {role} configuration {name:?} is not in Z_free: {}",
                    report.scene,
                    c.reason.as_deref().unwrap_or("?")
                )));
            }
            Some(_) => {}
        }
    }
    Ok(())
}

/// Runs `ftwire plan`.
pub fn run(args: &PlanArgs) -> Result<(), LabError> {
    let budget = Duration::try_from_secs_f64(args.time_budget)
        .ok()
        .filter(|b| !b.is_zero() && args.time_budget <= MAX_TIME_BUDGET)
        .ok_or_else(|| {
            LabError::bad_input(format!(
                "--time-budget {} s: give more than 0 and at most {MAX_TIME_BUDGET} seconds",
                args.time_budget
            ))
        })?;
    let scene_file = args.scene.path().ok_or_else(|| {
        LabError::bad_input("--scene FILE.toml is required: the scene to plan in")
    })?;
    let (scene, spec, checker) = setup(scene_file, &args.wire)?;
    let file = scene_file.display().to_string();
    let endpoint = |name: &str, role: &'static str| {
        ftwire_plan::scene_endpoint(&scene, &checker, name, role).map_err(|e| from_plan(e, &file))
    };
    let start = endpoint(&args.endpoints.start, "start")?;
    let goal = endpoint(&args.endpoints.goal, "goal")?;
    let params = PlannerParams {
        seed: args.seed.seed,
        time_budget: Some(budget),
        max_iterations: args.iterations,
        stop_at_first: args.first,
        clearance_weight: args.clearance_weight,
        clearance_reference: args.clearance_reference,
        ..PlannerParams::default()
    };
    let wire = *checker.rod().wire();
    let fixed = FixedBase::around(wire, scene.base, &[start.config, goal.config], 2.0);
    let context = format!("planning in {file}");
    let (found, resampled): (Plan, _) = match args.planner {
        PlannerArg::Fixed => {
            let found = plan(&fixed, &checker, &start, &goal.config, &params)
                .map_err(|e| from_plan(e, &context))?;
            let resampled = args
                .resample
                .map(|n| found.path.resample(&fixed, &checker, n));
            (found, resampled)
        }
        PlannerArg::Moving => {
            let space = MovingBase::new(wire, scene.base, 0.0).with_a_box(fixed.lower, fixed.upper);
            let found = plan(&space, &checker, &start, &goal.config, &params)
                .map_err(|e| from_plan(e, &context))?;
            let resampled = args
                .resample
                .map(|n| found.path.resample(&space, &checker, n));
            (found, resampled)
        }
    };
    let resampled = match resampled {
        Some(Ok(r)) => Some(r.iter().map(|s| waypoint(checker.rod(), s)).collect()),
        Some(Err(e)) => {
            return Err(LabError::no_answer(format!(
                "{context}: the path could not be resampled: {e}"
            )));
        }
        None => None,
    };
    let path = &found.path;
    let report = PlanReport {
        scene: file,
        wire: spec.name,
        planner: match args.planner {
            PlannerArg::Fixed => "fixed",
            PlannerArg::Moving => "moving",
        },
        seed: args.seed.seed,
        start: args.endpoints.start.clone(),
        goal: args.endpoints.goal.clone(),
        iterations: found.iterations,
        nodes: found.nodes,
        first_path_iteration: found.first_path_iteration,
        first_path_seconds: found.first_path_seconds,
        seconds: found.seconds,
        cost: path.cost,
        length: path.length(&checker),
        base_travel: path.base_travel(),
        min_clearance: path.min_clearance(),
        waypoints: path
            .waypoints
            .iter()
            .map(|s| waypoint(checker.rod(), s))
            .collect(),
        resampled,
    };
    output::print(&report, args.json.json)
}
