//! `ftwire.plan(scene, ...)`: a wire's path among a scene's obstacles by RRT* in `A_free` (or
//! in `Z = A × Q`), `ftwire_lab::plan::run`, what `ftwire plan --json` prints.

use std::path::PathBuf;

use ftwire_lab::error::FrontEnd;
use ftwire_lab::plan::{PlanParams, PlanWireParams, Planner, WaypointJson, run_from};
use numpy::PyArray1;
use numpy::PyArray2;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error::lab_error;
use crate::input::value_error;

/// Plans the wire's path from the scene's configuration `start` to `goal` (RRT*, seeded: the
/// same seed and iteration budget give the same path on any machine; `ftwire plan --json`).
///
/// - scene: the scene file (TOML: the base pose, boxes, named configurations; docs/config.md).
/// - wire: a preset or a wire file (TOML).
/// - seed: the planner's seed.
/// - iterations: the most RRT* iterations (1 to 1 000 000); with time_budget, whichever ends
///   first. For a reproducible path, an iteration budget the time budget does not cut.
/// - time_budget: wall-clock budget [s], in (0, 600].
/// - margin: the clearance [m] the wire's surface keeps from every obstacle and the floor.
/// - max_span: the largest distance between the grippers, as a fraction of the length, (0, 1].
/// - start, goal: configuration names in the scene.
/// - first: stop at the first path found, then shortcut it.
/// - planner: "fixed" (A_free, base gripper held) or "moving" (Z = A × Q).
/// - clearance_weight, clearance_reference [m]: an edge closer than the reference costs its
///   length times 1 + w (reference / clearance − 1).
/// - resample: also resample the path into N + 1 equally spaced waypoints.
///
/// Returns a dict: "waypoints" (N, 6) a [N·m, N], torque first, base clamp frame;
/// "waypoints_normalised" (N, 6); "base" and "tip" (N, 6) the grippers' clamp poses, world
/// frame, position [m] and rotation vector [rad]; "joints" (N, 15) the SDA10F's torso, left
/// arm and right arm joints [rad]; "clearance" (N,) [m] (capped at 0.1); "length" the path's
/// length in normalised a; "cost"; "base_travel" [m]; "min_clearance" [m] (edges included);
/// "iterations", "nodes", "first_path_iteration", "seconds", "first_path_seconds" [s];
/// "resampled": a dict of the per-waypoint arrays, or None.
///
/// Releases the GIL. Raises ValueError for bad input (an unreadable scene, unknown wire,
/// start or goal outside Z_free); RuntimeError when no path is found within the budget.
#[pyfunction]
#[pyo3(signature = (scene, wire = "nitinol-3mm-820", seed = 0, iterations = 1_000_000, time_budget = 2.0, margin = 0.005, max_span = 1.0, start = "start", goal = "goal", first = false, planner = "fixed", clearance_weight = 0.0, clearance_reference = 0.02, resample = None))]
#[allow(clippy::too_many_arguments)]
pub fn plan<'py>(
    py: Python<'py>,
    scene: PathBuf,
    wire: &str,
    seed: u64,
    iterations: usize,
    time_budget: f64,
    margin: f64,
    max_span: f64,
    start: &str,
    goal: &str,
    first: bool,
    planner: &str,
    clearance_weight: f64,
    clearance_reference: f64,
    resample: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let planner = match planner {
        "fixed" => Planner::Fixed,
        "moving" => Planner::Moving,
        other => {
            return Err(value_error(format!(
                "planner = {other:?} is not allowed: \"fixed\" or \"moving\""
            )));
        }
    };
    if !(1..=1_000_000).contains(&iterations) {
        return Err(value_error(format!(
            "iterations = {iterations} is not allowed: 1 to 1000000"
        )));
    }
    let params = PlanParams {
        scene: Some(scene),
        wire: PlanWireParams {
            wire: wire.to_owned(),
            margin,
            max_span,
        },
        start: start.to_owned(),
        goal: goal.to_owned(),
        time_budget,
        iterations,
        first,
        planner,
        clearance_weight,
        clearance_reference,
        resample,
        seed,
    };
    params
        .check_from(FrontEnd::Python)
        .map_err(|e| lab_error(&e, "plan"))?;
    // Ctrl-C ends the wait for the planner (`KeyboardInterrupt`).
    let report = crate::interrupt::interruptible(py, move || run_from(&params, FrontEnd::Python))?
        .map_err(|e| lab_error(&e, "plan"))?;
    let dict = waypoints(py, &report.waypoints)?;
    dict.set_item("length", report.length)?;
    dict.set_item("cost", report.cost)?;
    dict.set_item("base_travel", report.base_travel)?;
    dict.set_item("min_clearance", report.min_clearance)?;
    dict.set_item("iterations", report.iterations)?;
    dict.set_item("nodes", report.nodes)?;
    dict.set_item("first_path_iteration", report.first_path_iteration)?;
    dict.set_item("seconds", report.seconds)?;
    dict.set_item("first_path_seconds", report.first_path_seconds)?;
    match &report.resampled {
        Some(r) => dict.set_item("resampled", waypoints(py, r)?)?,
        None => dict.set_item("resampled", py.None())?,
    }
    Ok(dict)
}

/// The per-waypoint arrays of `list`.
fn waypoints<'py>(py: Python<'py>, list: &[WaypointJson]) -> PyResult<Bound<'py, PyDict>> {
    let n = list.len();
    let table = |width: usize, row: &dyn Fn(&WaypointJson) -> Vec<f64>| -> PyResult<_> {
        let flat: Vec<f64> = list.iter().flat_map(row).collect();
        let array = Array2::from_shape_vec((n, width), flat)
            .map_err(|e| value_error(format!("plan: waypoint arrays: {e}")))?;
        Ok(PyArray2::from_owned_array(py, array))
    };
    let pose = |p: &ftwire_lab::plan::PoseJson| [p.position, p.rotation].concat();
    let dict = PyDict::new(py);
    dict.set_item("waypoints", table(6, &|w| w.a.clone())?)?;
    dict.set_item(
        "waypoints_normalised",
        table(6, &|w| w.a_normalised.clone())?,
    )?;
    dict.set_item("base", table(6, &|w| pose(&w.base))?)?;
    dict.set_item("tip", table(6, &|w| pose(&w.tip))?)?;
    dict.set_item(
        "joints",
        table(15, &|w| {
            [
                vec![w.joints.torso],
                w.joints.left.clone(),
                w.joints.right.clone(),
            ]
            .concat()
        })?,
    )?;
    let clearance: Vec<f64> = list.iter().map(|w| w.clearance).collect();
    dict.set_item("clearance", PyArray1::from_vec(py, clearance))?;
    Ok(dict)
}
