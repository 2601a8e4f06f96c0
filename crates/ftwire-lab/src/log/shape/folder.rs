//! `ftwire shape --log --out DIR`: every record's shape written into a results folder.
//!
//! `shapes.jsonl` holds one line per record, in the log's order:
//!
//! ```json
//! {"line": 3, "time": 0.2, "a": [τ1, τ2, τ3, f1, f2, f3], "points": [[x, y, z], …], "stable": true, "confident": true}
//! ```
//!
//! `line` is the record's line in the log file (from 1, blank and comment lines counted), `a`
//! its `ã` (torque first, base clamp frame, N·m and N), `points` the centreline at `points`
//! nodes evenly spaced in arc length from the base clamp to the tip (base clamp frame, m),
//! `stable` whether `ã ∈ A_stable`, and `confident` whether the estimate is neither unstable
//! nor a jump from the previous record (`ShapeEstimator`'s flag, its default threshold). A record the model cannot
//! solve (`ã ∉ A`, a diverged integration, a calibration output that is not finite) has
//! `"points": []`, `stable` and `confident` false, and an `"error"` saying why.
//!
//! When the standard deviations of the record's `ã` are known (`--a-std`, or the
//! calibration's test error for a `raw` record read through it: [`super`]'s module docs), the
//! line also has `"sigma_mm": [σ, …]` after `points`, as long as `points`: `σ(s)` at each
//! point, the RMS radius of its first-order error \[mm\] (`sqrt(trace D Σ_ã Dᵀ)`,
//! `ftwire_estimate::shape::shape_sigma`), and the summary has `sigma_mean_mm`, the mean over
//! the records with `sigma_mm` of their mean `σ` along the wire. Without them neither key is
//! written and no error bar is computed.
//!
//! The summary ([`ShapeLogSummary`]) counts the records that are not stable and not
//! confident, and measures the shapes against the markers by the paper's metric (Fig. 5):
//! each inner marker's distance to the centreline (the first marker is at the clamp and the
//! last at the gripper, so they say nothing), averaged per record, then over the records with
//! inner markers and a shape. The centreline of that metric has [`MARKER_NODES`] nodes,
//! whatever `points` is, so the metric does not depend on `points`.
//!
//! **Throughput.** The records are independent but for the jump flag, which needs the previous
//! record: the records are solved (the shape, the stability, the markers) in parallel by
//! blocks of [`BLOCK`], then flagged in order ([`ShapeEstimator::flag_solved`]), then their
//! lines are serialised in parallel and written in order. The answer does not depend on the
//! number of threads. `benches/shape_log.rs` measures the records per second.
//!
//! Guarded by `tests/shape_log.rs` (the format, the line numbers, `points`, the summary, the
//! flags across blocks and threads) and `crates/ftwire/tests/shape_log.rs` (the command).

use std::fs::File;
use std::io::Write;
use std::time::Instant;

use ftwire_core::ensure_finite;
use ftwire_estimate::shape::{
    ModelError, ShapeEstimator, marker_distances, shape_sigma, with_model_error,
};
use ftwire_estimate::{EstimateError, KirchhoffModel, WireModel};
use ftwire_rod::Shape;
use nalgebra::{Matrix6, Point3, Vector3, Vector6};
use rayon::prelude::*;
use serde::Serialize;

use super::ShapeLog;
use crate::error::LabError;
use crate::experiment::Progress;
use crate::log::LogLine;
use crate::results::ResultsFolder;

/// Default number of points of each shape in `shapes.jsonl`.
pub const DEFAULT_POINTS: usize = 100;

/// Fewest points of a shape: its two ends.
pub const MIN_POINTS: usize = 2;

/// Most points of a shape: at 10 000 points a record's line is about 600 kB.
pub const MAX_POINTS: usize = 10_000;

/// Nodes of the centreline the markers are measured against (`marker_mean_mm`). A chord `s`
/// of a bend of radius `R` sags `s²/(8R)` from the curve: with `s = L/99`, 0.1 mm for the
/// 630 mm wire bent to a 5 cm radius.
pub const MARKER_NODES: usize = 100;

/// Records solved together before they are flagged and written: bounds the memory of a long
/// log, and gives the threads enough work each.
pub const BLOCK: usize = 2048;

/// Lines serialised by one task into one buffer.
const LINES_PER_BUFFER: usize = 64;

/// Records between two progress lines.
const PROGRESS_EVERY: usize = 100_000;

/// `summary.json` of `shape --log --out`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ShapeLogSummary {
    /// Records in the log (lines of `shapes.jsonl`).
    pub records: usize,
    /// Records whose `ã` is not in `A_stable`, or whose model could not be solved.
    pub not_stable: usize,
    /// Records not flagged confident: not stable, a jump from the previous record, or no
    /// shape.
    pub not_confident: usize,
    /// The mean distance of the inner markers to the estimated centreline \[mm\] (the module
    /// docs); `None` (`null`) when no record has an inner marker and a shape.
    pub marker_mean_mm: Option<f64>,
    /// The mean over the records with error bars of their mean `σ(s)` along the wire \[mm\]
    /// (the module docs); left out when no record has error bars.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma_mean_mm: Option<f64>,
}

/// Wall-clock times (`timings.json`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ShapeLogTimings {
    /// Solving, flagging and writing every record \[s\].
    pub shape_s: f64,
    /// Records per second of `shape_s`.
    pub records_per_s: f64,
}

/// A finished `shape --log --out`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeLogRun {
    /// `summary.json`'s body.
    pub summary: ShapeLogSummary,
    /// `timings.json`.
    pub timings: ShapeLogTimings,
    /// Records the model could not solve (their lines carry an `error`).
    pub no_shape: usize,
}

/// One line of `shapes.jsonl`.
#[derive(Serialize)]
struct ShapeLine<'a> {
    line: usize,
    time: f64,
    a: [f64; 6],
    points: Points<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    sigma_mm: Option<&'a [f64]>,
    stable: bool,
    confident: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<&'a str>,
}

/// A centreline's nodes, written as `[[x, y, z], …]`.
struct Points<'a>(&'a [Vector3<f64>]);

impl Serialize for Points<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.0.iter().map(|p| [p.x, p.y, p.z]))
    }
}

/// One record solved: its shape and stability and its markers' distance.
struct Solved {
    shape: Shape,
    stable: bool,
    /// `σ(s)` at each point \[mm\], if the standard deviations of `ã` are known.
    sigma_mm: Option<Vec<f64>>,
    /// The mean distance of the inner markers to the centreline \[mm\], if it has any.
    marker_mm: Option<f64>,
}

/// Appends the line of a record to `buffer`.
///
/// # Errors
/// No answer if the line cannot be serialised (it can for any values: serde_json writes a
/// number that is not finite as `null`).
fn write_line(
    buffer: &mut Vec<u8>,
    line: &LogLine,
    a: &Vector6<f64>,
    solved: &Result<Solved, String>,
    confident: bool,
) -> Result<(), LabError> {
    let (points, sigma_mm, stable, error) = match solved {
        Ok(s) => (
            s.shape.positions.as_slice(),
            s.sigma_mm.as_deref(),
            s.stable,
            None,
        ),
        Err(why) => (&[][..], None, false, Some(why.as_str())),
    };
    let row = ShapeLine {
        line: line.line,
        time: line.record.time,
        a: (*a).into(),
        points: Points(points),
        sigma_mm,
        stable,
        confident,
        error,
    };
    serde_json::to_writer(&mut *buffer, &row)
        .map_err(|e| LabError::no_answer(format!("line {} of shapes.jsonl: {e}", line.line)))?;
    buffer.push(b'\n');
    Ok(())
}

impl ShapeLog {
    /// Writes `shapes.jsonl` into `folder` ([`ShapeLog::write_shapes`]); the caller ends the
    /// run with the returned summary and timings (`ResultsFolder::finish_run`).
    ///
    /// # Errors
    /// As [`ShapeLog::write_shapes`]; [`LabError::Io`] when the file cannot be written.
    pub fn write(
        &self,
        points: usize,
        folder: &ResultsFolder,
        progress: Progress<'_>,
    ) -> Result<ShapeLogRun, LabError> {
        let path = folder.dir().join("shapes.jsonl");
        let file = File::create(&path).map_err(|e| {
            LabError::io(
                format!("creating shapes.jsonl in {}", folder.dir().display()),
                e,
            )
        })?;
        // The lines are written in buffers of many lines each: no further buffering.
        let mut out = file;
        let run = self.write_shapes(points, &mut out, progress)?;
        out.flush()
            .map_err(|e| LabError::io("writing shapes.jsonl", e))?;
        Ok(run)
    }

    /// Writes every record's line of `shapes.jsonl` (the module docs) to `out`, with `points`
    /// points per shape, and returns the summary. `progress` gets a line every 100 000
    /// records.
    ///
    /// # Errors
    /// Bad input for `points` outside `[MIN_POINTS, MAX_POINTS]` or markers the distance
    /// refuses; [`LabError::Io`] when `out` cannot be written.
    pub fn write_shapes(
        &self,
        points: usize,
        out: &mut impl Write,
        progress: Progress<'_>,
    ) -> Result<ShapeLogRun, LabError> {
        if !(MIN_POINTS..=MAX_POINTS).contains(&points) {
            return Err(LabError::bad_input(format!(
                "--points {points}: at least {MIN_POINTS} and at most {MAX_POINTS}"
            )));
        }
        let start = Instant::now();
        let model = self.model();
        let model_error = self.model_error();
        let mut estimator = ShapeEstimator::new(*model).with_model_error(model_error);
        let mut tally = Tally::default();
        // Each holds the text of LINES_PER_BUFFER lines; kept from block to block.
        let mut buffers: Vec<Vec<u8>> = Vec::new();
        let blocks = self.lines().chunks(BLOCK).zip(self.a_tilde().chunks(BLOCK));
        for (block, (lines, a)) in blocks.enumerate() {
            let first = block * BLOCK;
            let solved: Vec<Result<Solved, String>> = lines
                .par_iter()
                .zip(a)
                .enumerate()
                .map(|(i, (line, a))| {
                    let covariance = self.a_covariance(first + i);
                    solve(
                        model,
                        line,
                        a,
                        points,
                        (covariance.as_ref(), model_error.as_ref()),
                    )
                })
                .collect::<Result<_, _>>()?;
            // The jump flag needs the previous solved record: in order.
            let confident: Vec<bool> = solved
                .iter()
                .zip(a)
                .map(|(s, a)| match s {
                    Ok(s) => estimator.flag_solved(a, s.stable).is_confident(),
                    Err(_) => false,
                })
                .collect();
            buffers.resize_with(lines.len().div_ceil(LINES_PER_BUFFER), Vec::new);
            buffers
                .par_iter_mut()
                .zip(lines.par_chunks(LINES_PER_BUFFER))
                .zip(a.par_chunks(LINES_PER_BUFFER))
                .zip(solved.par_chunks(LINES_PER_BUFFER))
                .zip(confident.par_chunks(LINES_PER_BUFFER))
                .try_for_each(|((((buffer, lines), a), solved), confident)| {
                    buffer.clear();
                    for (((line, a), solved), &confident) in
                        lines.iter().zip(a).zip(solved).zip(confident)
                    {
                        write_line(buffer, line, a, solved, confident)?;
                    }
                    Ok::<(), LabError>(())
                })?;
            for buffer in &buffers {
                out.write_all(buffer)
                    .map_err(|e| LabError::io("writing shapes.jsonl", e))?;
            }
            let before = tally.records / PROGRESS_EVERY;
            tally.add(&solved, &confident);
            if tally.records / PROGRESS_EVERY > before {
                progress(&format!(
                    "shaped {} of {} records",
                    tally.records,
                    self.lines().len()
                ));
            }
        }
        let shape_s = start.elapsed().as_secs_f64();
        #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
        let records_per_s = tally.records as f64 / shape_s.max(f64::MIN_POSITIVE);
        Ok(ShapeLogRun {
            summary: tally.summary(),
            timings: ShapeLogTimings {
                shape_s,
                records_per_s,
            },
            no_shape: tally.no_shape,
        })
    }
}

/// The counts of the summary as the blocks go by.
#[derive(Default)]
struct Tally {
    records: usize,
    not_stable: usize,
    not_confident: usize,
    no_shape: usize,
    marker_sum_mm: f64,
    marker_records: usize,
    sigma_sum_mm: f64,
    sigma_records: usize,
}

impl Tally {
    fn add(&mut self, solved: &[Result<Solved, String>], confident: &[bool]) {
        self.records += solved.len();
        self.not_confident += confident.iter().filter(|c| !**c).count();
        for s in solved {
            match s {
                Ok(s) => {
                    self.not_stable += usize::from(!s.stable);
                    if let Some(mm) = s.marker_mm {
                        self.marker_sum_mm += mm;
                        self.marker_records += 1;
                    }
                    if let Some(sigma) = s.sigma_mm.as_ref().filter(|s| !s.is_empty()) {
                        #[allow(clippy::cast_precision_loss)] // at most MAX_POINTS
                        let mean = sigma.iter().sum::<f64>() / sigma.len() as f64;
                        self.sigma_sum_mm += mean;
                        self.sigma_records += 1;
                    }
                }
                Err(_) => {
                    self.not_stable += 1;
                    self.no_shape += 1;
                }
            }
        }
    }

    fn summary(&self) -> ShapeLogSummary {
        #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
        let marker_mean_mm =
            (self.marker_records > 0).then(|| self.marker_sum_mm / self.marker_records as f64);
        #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
        let sigma_mean_mm =
            (self.sigma_records > 0).then(|| self.sigma_sum_mm / self.sigma_records as f64);
        ShapeLogSummary {
            records: self.records,
            not_stable: self.not_stable,
            not_confident: self.not_confident,
            marker_mean_mm,
            sigma_mean_mm,
        }
    }
}

/// The shape at `points` nodes and the stability of `a`, as `ShapeEstimator::estimate`
/// solves them.
fn shape_and_stability(
    model: &KirchhoffModel,
    a: &Vector6<f64>,
    points: usize,
) -> Result<(Shape, bool), EstimateError> {
    ensure_finite("a_tilde", a.as_slice())?;
    let shape = model.shape(a, points)?;
    let stable = model.is_stable(a)?;
    Ok((shape, stable))
}

/// One record solved, or why the model has no shape for it; with the standard deviations
/// covariance of `ã`, its error bars too (none when a shifted `ã` has no shape).
///
/// # Errors
/// Bad input for markers the distance refuses.
fn solve(
    model: &KirchhoffModel,
    line: &LogLine,
    a: &Vector6<f64>,
    points: usize,
    (a_covariance, model_error): (Option<&Matrix6<f64>>, Option<&ModelError>),
) -> Result<Result<Solved, String>, LabError> {
    let (shape, stable) = match shape_and_stability(model, a, points) {
        Ok(solved) => solved,
        Err(e) => return Ok(Err(e.to_string())),
    };
    let sigma_mm = a_covariance.and_then(|covariance| {
        shape_sigma(model, a, points, covariance)
            .ok()
            .map(|sigma| match model_error {
                Some(e) => with_model_error(&sigma.sigma, e, model.wire().length()),
                None => sigma.sigma,
            })
            .map(|sigma| sigma.iter().map(|s| 1e3 * s).collect())
    });
    let inner: Vec<Point3<f64>> = line
        .record
        .markers
        .as_deref()
        .and_then(|m| m.get(1..m.len().saturating_sub(1)))
        .unwrap_or(&[])
        .iter()
        .flatten()
        .map(|p| Point3::from(*p))
        .collect();
    let marker_mm = if inner.is_empty() {
        None
    } else {
        let dense = if points == MARKER_NODES {
            None
        } else {
            match model.shape(a, MARKER_NODES) {
                Ok(dense) => Some(dense),
                Err(e) => return Ok(Err(e.to_string())),
            }
        };
        let curve = dense.as_ref().unwrap_or(&shape);
        let d = marker_distances(&inner, &curve.positions)
            .map_err(|e| LabError::bad_input(format!("the markers of line {}: {e}", line.line)))?;
        #[allow(clippy::cast_precision_loss)] // a handful of markers
        Some(1e3 * d.iter().sum::<f64>() / d.len() as f64)
    };
    Ok(Ok(Solved {
        shape,
        stable,
        sigma_mm,
        marker_mm,
    }))
}
