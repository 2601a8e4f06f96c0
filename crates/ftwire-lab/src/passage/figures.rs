//! The passage's figures (Figs. 11–12 and the scene), and the projection of a plan in
//! normalised `A` onto the two components it moves along most, which Table IV's figure
//! ([`crate::track`]) shares.

use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_plan::{Scene, Waypoint};
use ftwire_report::{Chart3d, LineChart, Series, SeriesKind};
use ftwire_rod::to_normalised;
use nalgebra::Vector6;

use crate::error::LabError;
use crate::experiment::stats::mean_std;
use crate::results::ResultsFolder;
use crate::scene::box_outline;
use crate::tracking::Attempt;

/// Roll-outs of each mode drawn in the figures.
const FIGURE_ATTEMPTS: usize = 5;

/// Every how many waypoints the planned wire is drawn in `passage_scene`.
const FIGURE_WAYPOINT_STRIDE: usize = 3;

/// The two components of normalised `A` along which the plan moves most.
pub(crate) fn main_axes(normalised: &[Vector6<f64>]) -> (usize, usize) {
    let mut range: Vec<(usize, f64)> = (0..6)
        .map(|i| {
            let (lo, hi) = normalised.iter().fold((f64::MAX, f64::MIN), |(lo, hi), a| {
                (lo.min(a[i]), hi.max(a[i]))
            });
            (i, hi - lo)
        })
        .collect();
    range.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.cmp(&y.0)));
    (range[0].0, range[1].0)
}

/// The name of component `i` of `a`.
pub(crate) fn component(i: usize) -> &'static str {
    ["τ1", "τ2", "τ3", "f1", "f2", "f3"][i.min(5)]
}

/// Figs. 11–12 and the scene.
pub(super) fn write_figures(
    folder: &ResultsFolder,
    scene: &Scene,
    model: &KirchhoffModel,
    waypoints: &[Waypoint],
    closed: &[Attempt],
    open: &[Attempt],
) -> Result<(), LabError> {
    let wire = model.wire();
    let planned: Vec<Vector6<f64>> = waypoints
        .iter()
        .map(|w| to_normalised(wire, &w.a))
        .collect();
    let (i, j) = main_axes(&planned);
    let project = |a: &Vector6<f64>| (a[i], a[j]);
    let mut path = LineChart::new(
        "the plan in A and the roll-outs (true configuration)",
        format!("{} (normalised)", component(i)),
        format!("{} (normalised)", component(j)),
    )
    .with_series(Series::line_points(
        "plan γ_A",
        planned.iter().map(project).collect(),
    ));
    let rollout = |a: &Attempt| -> Vec<(f64, f64)> {
        a.a_true
            .iter()
            .map(|x| project(&to_normalised(wire, &Vector6::from(*x))))
            .collect()
    };
    for (k, a) in closed.iter().take(FIGURE_ATTEMPTS).enumerate() {
        path = path.with_series(Series::line(format!("closed loop {k}"), rollout(a)));
    }
    for (k, a) in open.iter().take(FIGURE_ATTEMPTS).enumerate() {
        path = path.with_series(Series::line(format!("open loop {k}"), rollout(a)));
    }
    folder.write_figure("passage_path_in_a", |dir| {
        path.write(dir, "passage_path_in_a")
    })?;

    let per_waypoint = |attempts: &[Attempt]| -> (Vec<(f64, f64)>, Vec<f64>) {
        let most = attempts.iter().map(|a| a.shape_mm.len()).max().unwrap_or(0);
        (0..most)
            .map(|w| {
                let at: Vec<f64> = attempts
                    .iter()
                    .filter_map(|a| a.shape_mm.get(w).copied())
                    .collect();
                let (mean, std) = mean_std(&at);
                ((w as f64 + 1.0, mean), std)
            })
            .unzip()
    };
    let (closed_points, closed_std) = per_waypoint(closed);
    let (open_points, open_std) = per_waypoint(open);
    let errors = LineChart::new(
        "shape error along the path (mean ± std over the attempts that got there)",
        "waypoint",
        "mean distance to Φ(γ_A) [mm]",
    )
    .with_series(Series::line_points("closed loop", closed_points).with_error_bars(closed_std))
    .with_series(Series::line_points("open loop", open_points).with_error_bars(open_std));
    folder.write_figure("passage_shape_error", |dir| {
        errors.write(dir, "passage_shape_error")
    })?;

    let mut chart = Chart3d::new("the passage: the plan and the first closed-loop attempt");
    for b in &scene.boxes {
        chart = chart.with_curve(b.name.clone(), box_outline(b), SeriesKind::Line);
    }
    for (k, w) in waypoints.iter().enumerate() {
        if k % FIGURE_WAYPOINT_STRIDE == 0 || k + 1 == waypoints.len() {
            let points = w.centreline.iter().map(|p| [p.x, p.y, p.z]).collect();
            chart = chart.with_curve(format!("plan, waypoint {k}"), points, SeriesKind::Line);
        }
    }
    if let Some(last) = closed.first().and_then(|a| a.centrelines.last()) {
        chart = chart.with_curve(
            "closed loop 0, true wire at the end",
            last.clone(),
            SeriesKind::LinePoints,
        );
    }
    folder.write_figure("passage_scene", |dir| chart.write(dir, "passage_scene"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_main_axes_are_those_the_plan_moves_along_most() {
        let path = [
            Vector6::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
            Vector6::new(0.1, 0.0, 3.0, 0.0, -5.0, 0.0),
        ];
        assert_eq!(main_axes(&path), (4, 2));
    }
}
