//! Arguments of `ftwire plan` and `ftwire scene check`.

use std::path::PathBuf;

use clap::{Args, Subcommand, ValueEnum};
use ftwire::args::{Count, JsonArgs, SeedArgs, parse_finite};
use ftwire_lab::plan::{ITERATIONS, RESAMPLE};

/// The wire a scene is planned or checked for (a preset or a wire file).
#[derive(Debug, Clone, Args)]
pub struct PlanWireArgs {
    /// A wire preset (nitinol-2mm-630, nitinol-3mm-910, nitinol-3mm-820, cable-3mm-920) or a
    /// wire file (TOML).
    #[arg(long, value_name = "PRESET|FILE", default_value = "nitinol-3mm-820")]
    pub wire: String,

    /// Clearance [m] the wire's surface keeps from every obstacle and the floor.
    #[arg(
        long,
        value_name = "M",
        default_value_t = 0.005,
        allow_hyphen_values = true,
        value_parser = parse_finite
    )]
    pub margin: f64,

    /// Largest distance between the grippers as a fraction of the wire's length, in (0, 1]:
    /// keeps the wire slack (1 = whatever the model allows).
    #[arg(
        long,
        value_name = "FRACTION",
        default_value_t = 1.0,
        allow_hyphen_values = true,
        value_parser = parse_finite
    )]
    pub max_span: f64,
}

/// The start and goal configurations' names in the scene.
#[derive(Debug, Clone, Args)]
pub struct EndpointArgs {
    /// Name of the start configuration in the scene.
    #[arg(long, value_name = "NAME", default_value = "start")]
    pub start: String,

    /// Name of the goal configuration in the scene.
    #[arg(long, value_name = "NAME", default_value = "goal")]
    pub goal: String,
}

/// `ftwire scene`.
#[derive(Debug, Args)]
#[command(after_help = "Exit codes: 0 valid, 2 bad scene or a start/goal outside Z_free.")]
pub struct SceneArgs {
    /// What to do with the scene.
    #[command(subcommand)]
    pub command: SceneCommand,
}

/// The `ftwire scene` subcommands.
#[derive(Debug, Subcommand)]
pub enum SceneCommand {
    /// Validate a scene file and report whether each named configuration is in Z_free.
    Check(SceneCheckArgs),
}

/// `ftwire scene check FILE`.
#[derive(Debug, Args)]
pub struct SceneCheckArgs {
    /// The scene file (TOML; see `scenes/passage.toml`).
    #[arg(value_name = "FILE")]
    pub file: PathBuf,

    /// The wire.
    #[command(flatten)]
    pub wire: PlanWireArgs,

    /// Which configurations are the start and the goal.
    #[command(flatten)]
    pub endpoints: EndpointArgs,

    /// Output format.
    #[command(flatten)]
    pub json: JsonArgs,
}

/// Which planning space.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum PlannerArg {
    /// RRT* in A_free, the base gripper held at the scene's pose (the paper).
    #[default]
    Fixed,
    /// RRT* in Z = A × Q, the base gripper moving too (within 0.15 m and 0.5 rad).
    Moving,
}

/// `ftwire plan`.
#[derive(Debug, Args)]
#[command(after_help = "Examples:\n  \
    ftwire plan --scene scenes/passage.toml --wire nitinol-3mm-820 --json\n  \
    ftwire plan --scene scenes/passage.toml --planner moving --time-budget 5 --seed 3\n\n\
    Exit codes: 0 a path, 1 no path within the budget, 2 bad input (a bad scene, a start or\n\
    goal outside Z_free).")]
pub struct PlanArgs {
    /// The scene to plan in (`--scene`, required).
    #[command(flatten)]
    pub scene: crate::cli::groups::SceneArgs,

    /// The wire.
    #[command(flatten)]
    pub wire: PlanWireArgs,

    /// Which configurations are the start and the goal.
    #[command(flatten)]
    pub endpoints: EndpointArgs,

    /// Wall-clock budget [s], more than 0 and at most 600: the best path found by then is
    /// returned (anytime).
    #[arg(
        long,
        value_name = "S",
        default_value_t = 2.0,
        allow_hyphen_values = true,
        value_parser = parse_finite
    )]
    pub time_budget: f64,

    /// Most iterations, 1 to 1000000 (with --time-budget, whichever ends first); the same seed
    /// and iteration count give the same path.
    #[arg(long, value_name = "N", default_value_t = 1_000_000, value_parser = Count(ITERATIONS))]
    pub iterations: usize,

    /// Stop at the first path found (then shortcut it).
    #[arg(long)]
    pub first: bool,

    /// Which planning space.
    #[arg(long, value_enum, default_value_t = PlannerArg::Fixed)]
    pub planner: PlannerArg,

    /// Weight w of the clearance penalty: an edge closer than --clearance-reference to an
    /// obstacle costs its length times 1 + w (reference / clearance − 1).
    #[arg(
        long,
        value_name = "W",
        default_value_t = 0.0,
        allow_hyphen_values = true,
        value_parser = parse_finite
    )]
    pub clearance_weight: f64,

    /// Clearance [m] below which an edge is penalised (with --clearance-weight).
    #[arg(long, value_name = "M", default_value_t = 0.02, value_parser = parse_finite)]
    pub clearance_reference: f64,

    /// Also print the path resampled into N + 1 equally spaced waypoints γ(i/N), N from 1 to
    /// 100000.
    #[arg(long, value_name = "N", value_parser = Count(RESAMPLE))]
    pub resample: Option<usize>,

    /// The planner's seed.
    #[command(flatten)]
    pub seed: SeedArgs,

    /// Output format.
    #[command(flatten)]
    pub json: JsonArgs,
}
