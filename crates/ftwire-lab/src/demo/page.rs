//! The demo's `report.html`: its numbers, the figures `shape.png` and `tracking.png`, and three
//! 3-D views (ftwire-report's [`HtmlReport`]): the closed-loop run rest by rest in the scene,
//! the open-loop run waypoint by waypoint against the plan, and the shape from F/T against the
//! truth. The same seed gives the same page.

use std::fmt::Write as _;

use ftwire_core::Pose;
use ftwire_plan::Scene;
use ftwire_plan::Waypoint;
use ftwire_report::html::{code_span, escape_markdown};
use ftwire_report::{HtmlReport, Rotation, Scene3d, Step3};
use nalgebra::Point3;

use super::summary::DemoSummary;
use crate::error::LabError;
use crate::results::ResultsFolder;
use crate::tracking::Attempt;

/// A centreline as plotted points (world frame) \[m\].
pub(super) type Points = Vec<[f64; 3]>;

/// The first configuration of the shape phase: the estimate from F/T and the truth.
pub(super) type FirstShape = (Points, Points);

/// What the page draws besides the summary.
pub(super) struct Drawn<'a> {
    pub scene: &'a Scene,
    pub waypoints: &'a [Waypoint],
    /// The first shape configuration: the estimate from F/T and the truth (world frame).
    pub shape: Option<&'a FirstShape>,
}

fn rotation(pose: &Pose) -> Rotation {
    let m = pose.rotation.to_rotation_matrix();
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

fn origin(pose: &Pose) -> [f64; 3] {
    let t = pose.translation.vector;
    [t.x, t.y, t.z]
}

fn points(centreline: &[Point3<f64>]) -> Points {
    centreline.iter().map(|p| [p.x, p.y, p.z]).collect()
}

/// The scene's boxes in an empty view.
fn with_boxes(title: &str, scene: &Scene) -> Scene3d {
    scene.boxes.iter().fold(Scene3d::new(title), |view, b| {
        let pose = b.geometry.pose();
        let h = b.geometry.half_extents();
        view.with_box(
            b.name.clone(),
            origin(pose),
            [h.x, h.y, h.z],
            rotation(pose),
        )
    })
}

/// A step with the base gripper (its pose) and the other at the centreline's far end.
fn rest(label: String, scene: &Scene, name: &str, centreline: &[[f64; 3]]) -> Step3 {
    let step = Step3::new(label)
        .with_polyline(name, centreline.to_vec())
        .with_gripper("base", origin(&scene.base), Some(rotation(&scene.base)));
    match centreline.last() {
        Some(&tip) => step.with_gripper("tip", tip, None),
        None => step,
    }
}

/// The closed-loop run: the true wire at each rest, with the plan's start and goal.
fn closed_loop_view(scene: &Scene, waypoints: &[Waypoint], closed: &Attempt) -> Scene3d {
    let mut view = with_boxes("closed loop: the true wire at each rest", scene);
    for (name, waypoint) in [
        ("plan: start", waypoints.first()),
        ("plan: goal", waypoints.last()),
    ] {
        if let Some(w) = waypoint {
            view = view.with_polyline(name, points(&w.centreline));
        }
    }
    for (k, centreline) in closed.centrelines.iter().enumerate() {
        view = view.with_step(rest(
            format!("after move {}", k + 1),
            scene,
            "true wire (simulator)",
            centreline,
        ));
    }
    view
}

/// The open-loop run: at each waypoint the plan's shape `Φ(γ_A(i/N))` and the true wire after
/// the move to it, with the second gripper at its planned pose.
fn open_loop_view(scene: &Scene, waypoints: &[Waypoint], open: &Attempt) -> Scene3d {
    let mut view = with_boxes(
        "open loop: the plan and the true wire at each waypoint",
        scene,
    );
    for (i, waypoint) in waypoints.iter().enumerate() {
        let tip = scene.base * waypoint.tip;
        let mut step = Step3::new(format!("waypoint {i} of {}", waypoints.len() - 1))
            .with_polyline("plan Φ(γ_A(i/N))", points(&waypoint.centreline))
            .with_gripper("base", origin(&scene.base), Some(rotation(&scene.base)))
            .with_gripper("tip (planned pose)", origin(&tip), Some(rotation(&tip)));
        // Move k of the roll-out ends at waypoint k + 1.
        if let Some(centreline) = i.checked_sub(1).and_then(|k| open.centrelines.get(k)) {
            step = step.with_polyline("true wire (simulator)", centreline.clone());
        }
        view = view.with_step(step);
    }
    view
}

/// The summary's headline numbers as Markdown.
fn numbers(summary: &DemoSummary) -> String {
    let mut md = String::new();
    let id = &summary.identification;
    let _ = writeln!(
        md,
        "All in the simulator, gravity on; `summary.json` beside this page has every number \
         and the run's configuration.\n\n| phase | result |\n| --- | --- |\n\
         | calibrate | test error torque {:.2} %, force {:.2} % (raw {:.2} %, {:.2} %) on {} \
         configurations of {} |",
        100.0 * summary.calibration.calibrated_torque_rel,
        100.0 * summary.calibration.calibrated_force_rel,
        100.0 * summary.calibration.raw_torque_rel,
        100.0 * summary.calibration.raw_force_rel,
        summary.calibration.configurations,
        escape_markdown(&summary.calibration.wire),
    );
    let _ = writeln!(
        md,
        "| identify {} | errors c1 {:.2} %, c2 {:.2} %, c3 {:.2} %, L {:.2} % from {} samples{} |",
        code_span(&summary.wire.name),
        100.0 * id.relative_error[0],
        100.0 * id.relative_error[1],
        100.0 * id.relative_error[2],
        100.0 * id.relative_error[3],
        id.samples,
        id.flag
            .map_or_else(String::new, |f| format!(" (flagged: {f})")),
    );
    let _ = writeln!(
        md,
        "| shape from F/T | mean distance to the true wire {:.2} mm over {} configurations |",
        summary.shape.mean_mm_overall, summary.shape.configurations,
    );
    let _ = writeln!(
        md,
        "| plan | {} waypoints, path length {:.2} (normalised A), closest approach {:.1} mm |",
        summary.plan.waypoints,
        summary.plan.cost,
        1e3 * summary.plan.min_clearance,
    );
    for a in [&summary.tracking.closed_loop, &summary.tracking.open_loop] {
        let _ = writeln!(
            md,
            "| track, {} | {} after {} moves ({}){}, final error {:.3} |",
            a.mode.replace('_', " "),
            a.verdict(),
            a.steps,
            code_span(&a.outcome),
            if a.touched {
                ", touched an obstacle"
            } else {
                ""
            },
            a.final_error,
        );
    }
    md
}

/// Writes `report.html` into the demo's results folder (after its figures).
pub(super) fn write(
    folder: &ResultsFolder,
    summary: &DemoSummary,
    drawn: &Drawn<'_>,
) -> Result<(), LabError> {
    let figure = |report: HtmlReport, caption: &str, stem: &str| {
        let path = folder.dir().join(format!("{stem}.png"));
        if path.is_file() {
            report
                .with_png_file(caption, &path)
                .map_err(|e| LabError::no_answer(format!("report.html: {e}")))
        } else {
            Ok(report)
        }
    };
    let mut report = HtmlReport::new(format!("ftwire demo: {}", summary.wire.name))
        .with_markdown(&format!("## Results\n\n{}", numbers(summary)));
    report = figure(
        report,
        "shape.png: the shape from F/T against the truth",
        "shape",
    )?;
    report = figure(
        report,
        "tracking.png: the true wire, closed loop",
        "tracking",
    )?;
    let (scene, waypoints) = (drawn.scene, drawn.waypoints);
    report = report
        .with_scene(closed_loop_view(
            scene,
            waypoints,
            &summary.tracking.closed_loop,
        ))
        .with_scene(open_loop_view(
            scene,
            waypoints,
            &summary.tracking.open_loop,
        ));
    if let Some((estimate, truth)) = drawn.shape {
        let step = Step3::new("the first configuration")
            .with_polyline("true wire (simulator)", truth.clone())
            .with_polyline("estimate from F/T", estimate.clone());
        let ends = [truth.first(), truth.last()];
        let step = ends
            .into_iter()
            .flatten()
            .zip(["base", "tip"])
            .fold(step, |s, (&p, name)| s.with_gripper(name, p, None));
        report =
            report.with_scene(Scene3d::new("shape from F/T against the truth").with_step(step));
    }
    folder.write("report.html", report.to_html())
}
