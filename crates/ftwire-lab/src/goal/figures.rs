//! The goal experiment's figures, of its first pair: the motion in `A` (Fig. 6: the straight
//! line and the measured `ã` of the closed and open loop under noise) and the shape error
//! along the motion (Fig. 7: each loop and variant, and the straight line in `B`).

use ftwire_control::NoiseModel;
use ftwire_control::open_loop::{line_in_a, straight_line_in_b};
use ftwire_estimate::WireModel;
use ftwire_report::{Chart3d, LineChart, Series, SeriesKind};
use ftwire_rod::to_normalised;
use nalgebra::Vector6;

use super::trial::{Context, Pair, Truth};
use super::variant::{Variant, VariantTrials};
use crate::error::{LabError, from_estimate};
use crate::results::ResultsFolder;

/// Writes `motion_in_a` and `shape_error_along_motion` of `pair`, whose trials are `rows`
/// (one per variant of `variants`, in their order).
///
/// # Errors
/// As the straight line in `B`'s roll-out and the folder's writes.
pub(super) fn write(
    folder: &ResultsFolder,
    ctx: &Context<'_>,
    pair: &Pair,
    rows: &[VariantTrials],
    variants: &[Variant; 2],
) -> Result<(), LabError> {
    let point = |a: &Vector6<f64>| {
        let v = to_normalised(&ctx.params, a);
        [v[1], v[2], v[3]]
    };
    let mut chart = Chart3d::new(format!(
        "motion in A (normalised τ2, τ3, f1), pair 0, {} noise",
        variants[1].noise.name()
    ))
    .with_curve(
        "straight line a(σ)",
        line_in_a(&pair.a_s, &pair.a_g, 20)
            .iter()
            .map(point)
            .collect(),
        SeriesKind::Line,
    );
    let mut errors = LineChart::new(
        "shape error along the motion, pair 0",
        "step",
        "mean distance to Φ(a_g) [mm]",
    );
    for (row, variant) in rows.iter().zip(variants) {
        let name = row.variant;
        if let Some(run) = &row.closed.run {
            let stop = row.closed.stops[variant.headline].steps;
            if name == "noise" {
                let path: Vec<[f64; 3]> = std::iter::once(run.start)
                    .chain(run.steps.iter().map(|s| s.measured))
                    .take(stop + 1)
                    .map(|a| point(&a))
                    .collect();
                chart = chart.with_curve("closed loop ã (noise)", path, SeriesKind::Line);
            }
            errors = errors.with_series(Series::line(
                format!("closed loop, {name}"),
                along(row.closed.truths.iter().take(stop + 1)),
            ));
        }
        if name == "noise" {
            let path: Vec<[f64; 3]> = std::iter::once(Some(pair.a_s))
                .chain(row.open.measured.iter().copied())
                .flatten()
                .map(|a| point(&a))
                .collect();
            chart = chart.with_curve("open loop ã (noise)", path, SeriesKind::Line);
        }
        errors = errors.with_series(Series::line(
            format!("open loop, straight line in A, {name}"),
            along(row.open.truths.iter()),
        ));
        if name == "no_noise" {
            // Fig. 7's dotted curve: the straight line in B, same steps, no noise.
            errors = errors.with_series(Series::line(
                "open loop, straight line in B, no_noise",
                along(line_in_b(ctx, pair, row.steps)?.iter()),
            ));
        }
    }
    chart = chart
        .with_curve("start", vec![point(&pair.a_s)], SeriesKind::Points)
        .with_curve("goal", vec![point(&pair.a_g)], SeriesKind::Points);
    folder.write_figure("motion_in_a", |dir| chart.write(dir, "motion_in_a"))?;
    folder.write_figure("shape_error_along_motion", |dir| {
        errors.write(dir, "shape_error_along_motion")
    })?;
    Ok(())
}

/// The shape error \[mm\] at each rest of `truths`, against the rest's index.
fn along<'a>(truths: impl Iterator<Item = &'a Truth>) -> Vec<(f64, f64)> {
    truths
        .enumerate()
        .map(|(j, t)| (j as f64, t.shape_mm))
        .collect()
}

/// The truths of the open loop along the straight line in `B` from `Γ(a_s)` to `Γ(a_g)` in
/// `steps` moves, without noise.
fn line_in_b(ctx: &Context<'_>, pair: &Pair, steps: usize) -> Result<Vec<Truth>, LabError> {
    let b_s = ctx
        .model
        .tip(&pair.a_s)
        .map_err(|e| from_estimate(e, "Γ(a_s)"))?;
    let b_g = ctx
        .model
        .tip(&pair.a_g)
        .map_err(|e| from_estimate(e, "Γ(a_g)"))?;
    let poses =
        straight_line_in_b(&b_s, &b_g, steps).map_err(|e| LabError::no_answer(e.to_string()))?;
    Ok(ctx.open(pair, 0, NoiseModel::None, &poses)?.truths)
}
