//! `ftwire plan` and `ftwire scene check`: the arguments as [`ftwire_lab::plan`]'s settings,
//! its answer printed (the lab does the work).

use std::fmt::Display;
use std::io::{self, Write};

use ftwire::output::{self, Report};
use ftwire_lab::error::LabError;
use ftwire_lab::plan::{self, PlanParams, PlanWireParams, Planner, SceneCheckParams};
use serde::Serialize;

use crate::cli::plan::{PlanArgs, PlanWireArgs, PlannerArg, SceneArgs, SceneCommand};

/// A lab answer: its JSON with `--json`, its `Display` text otherwise.
#[derive(Serialize)]
#[serde(transparent)]
struct Shown<'a, T>(&'a T);

impl<T: Serialize + Display> Report for Shown<'_, T> {
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        write!(out, "{}", self.0)
    }
}

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
    output::print(&Shown(&report), args.json.json)?;
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
    output::print(&Shown(&report), args.json.json)
}
