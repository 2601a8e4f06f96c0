//! `ftwire plan` and `ftwire scene check`: the arguments as [`ftwire_lab::plan`]'s settings,
//! its answer printed (the lab does the work).

use ftwire_app::output;
use ftwire_lab::error::LabError;
use ftwire_lab::plan::{self, PlanParams, PlanWireParams, Planner, SceneCheckParams};

use crate::cli::plan::{PlanArgs, PlanWireArgs, PlannerArg, SceneArgs, SceneCommand};

/// The lab's wire settings of `args`.
fn wire(args: &PlanWireArgs) -> PlanWireParams {
    PlanWireParams {
        wire: args.wire.clone(),
        margin: args.margin,
        max_span: args.max_span,
    }
}

/// Runs `ftwire scene`.
pub fn run_scene(args: &SceneArgs) -> Result<(), LabError> {
    let SceneCommand::Check(args) = &args.command;
    let report = plan::check_scene(&SceneCheckParams {
        file: args.file.clone(),
        wire: wire(&args.wire),
        start: args.endpoints.start.clone(),
        goal: args.endpoints.goal.clone(),
    })?;
    output::print_display(&report, args.json.json)?;
    report.require_endpoints()
}

/// The lab's settings of `args`.
fn params(args: &PlanArgs) -> PlanParams {
    PlanParams {
        scene: args.scene.file.clone(),
        wire: wire(&args.wire),
        start: args.endpoints.start.clone(),
        goal: args.endpoints.goal.clone(),
        time_budget: args.time_budget,
        iterations: args.iterations,
        first: args.first,
        planner: match args.planner {
            PlannerArg::Fixed => Planner::Fixed,
            PlannerArg::Moving => Planner::Moving,
        },
        clearance_weight: args.clearance_weight,
        clearance_reference: args.clearance_reference,
        resample: args.resample,
        seed: args.seed.seed,
    }
}

/// Runs `ftwire plan`.
pub fn run(args: &PlanArgs) -> Result<(), LabError> {
    let report = plan::run(&params(args))?;
    output::print_display(&report, args.json.json)
}
