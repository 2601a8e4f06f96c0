//! `ftwire shape --log --out DIR`: every record's shape written into a results folder.
//!
//! `shapes.jsonl` holds one line per record, in the log's order: the rig layer's one record
//! schema ([`ftwire_rig::record`]: `line, time, a, points, sigma, stable, confident,
//! confidence, marker_mean_mm, error`), the same that `shape --log --json` prints. `line` is
//! the record's line in the log file (from 1, blank and comment lines counted). A record the
//! model cannot solve (`ã ∉ A`, a diverged integration) has `"points": []`, `stable` and
//! `confident` false, and an `"error"` saying why.
//!
//! When the standard deviations of the record's `ã` are known (`--a-std`, `--sensor`, or the
//! calibration's test error for a `raw` record read through it: [`super`]'s module docs), the
//! line also has `"sigma": [σ, …]`, as long as `points`: `σ(s)` at each point \[m\], and the
//! summary has `sigma_mean_mm`, the mean over the records with `sigma` of their mean `σ`
//! along the wire \[mm\]. Without them neither key is written and no error bar is computed.
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
//! blocks of [`BLOCK`], then flagged in order ([`ftwire_rig::Stream::flag`]), then their
//! lines are serialised in parallel and written in order. The answer does not depend on the
//! number of threads. `benches/shape_log.rs` measures the records per second.
//!
//! Guarded by `tests/shape_log.rs` (the format, the line numbers, `points`, the summary, the
//! flags across blocks and threads) and `crates/ftwire/tests/shape_log.rs` (the command).

use std::fs::File;
use std::io::Write;
use std::time::Instant;

use ftwire_rig::{ShapeConfidence, ShapeRecord, Solved};
use rayon::prelude::*;
use serde::Serialize;

use super::ShapeLog;
use ftwire_app::Progress;
use ftwire_app::error::LabError;
use ftwire_app::results::ResultsFolder;

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

/// The summary as a line of text: the counts, and the inner markers' mean distance when
/// there is one.
impl std::fmt::Display for ShapeLogSummary {
    fn fmt(&self, out: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let markers = self.marker_mean_mm.map_or_else(String::new, |m| {
            format!(", inner markers {m:.2} mm from the shapes")
        });
        writeln!(
            out,
            "{} records: {} not stable, {} not confident{markers}",
            self.records, self.not_stable, self.not_confident
        )
    }
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

impl ShapeLogRun {
    /// No answer when the model had no shape for some records (their lines in
    /// `shapes.jsonl` carry the `error`).
    ///
    /// # Errors
    /// No answer (exit 1) naming the count ([`super::no_shape`]).
    pub fn all_shaped(&self) -> Result<(), LabError> {
        super::no_shape(
            self.no_shape,
            self.summary.records,
            "see their `error` in shapes.jsonl",
        )
    }
}

impl ShapeLog {
    /// Writes `shapes.jsonl` into `folder` ([`ShapeLog::write_shapes`]); the caller ends the
    /// run with the returned summary and timings (`ResultsFolder::finish_run`).
    ///
    /// # Errors
    /// As [`ShapeLog::write_shapes`]; [`LabError::Io`] when the file cannot be written.
    pub fn write(
        &self,
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
        let run = self.write_shapes(&mut out, progress)?;
        out.flush()
            .map_err(|e| LabError::io("writing shapes.jsonl", e))?;
        Ok(run)
    }

    /// Writes every record's line of `shapes.jsonl` (the module docs) to `out`, and returns
    /// the summary. `progress` gets a line every 100 000 records.
    ///
    /// # Errors
    /// Bad input for markers the distance refuses; [`LabError::Io`] when `out` cannot be
    /// written.
    pub fn write_shapes(
        &self,
        out: &mut impl Write,
        progress: Progress<'_>,
    ) -> Result<ShapeLogRun, LabError> {
        let start = Instant::now();
        let measurement = self.measurement();
        let mut stream = self.stream()?;
        let mut tally = Tally::default();
        // Each holds the text of LINES_PER_BUFFER lines; kept from block to block.
        let mut buffers: Vec<Vec<u8>> = Vec::new();
        let blocks = self.lines().chunks(BLOCK).zip(self.a_tilde().chunks(BLOCK));
        for (block, (lines, a)) in blocks.enumerate() {
            let first = block * BLOCK;
            let solved: Vec<(Result<Solved, String>, Option<f64>)> = lines
                .par_iter()
                .zip(a)
                .enumerate()
                .map(|(i, (line, a))| {
                    let covariance = self.a_covariance(first + i);
                    let solved = measurement.solve(a, covariance.as_ref());
                    let markers = match (&solved, line.record.markers.as_deref()) {
                        (Ok(s), Some(markers)) => {
                            measurement.inner_marker_mean(a, markers, s).map_err(|e| {
                                LabError::bad_input(format!(
                                    "the markers of line {}: {e}",
                                    line.line
                                ))
                            })?
                        }
                        _ => None,
                    };
                    Ok((solved, markers))
                })
                .collect::<Result<_, LabError>>()?;
            // The jump flag needs the previous solved record: in order.
            let flags: Vec<ShapeConfidence> = solved
                .iter()
                .zip(a)
                .map(|((s, _), a)| stream.flag(a, s))
                .collect();
            let records: Vec<ShapeRecord> = lines
                .par_iter()
                .zip(a)
                .zip(&solved)
                .zip(&flags)
                .map(|(((line, a), (s, markers)), flag)| {
                    ShapeRecord::new((line.line, line.record.time), a, s, *flag, *markers)
                })
                .collect();
            buffers.resize_with(lines.len().div_ceil(LINES_PER_BUFFER), Vec::new);
            buffers
                .par_iter_mut()
                .zip(records.par_chunks(LINES_PER_BUFFER))
                .try_for_each(|(buffer, records)| {
                    buffer.clear();
                    for record in records {
                        serde_json::to_writer(&mut *buffer, record).map_err(|e| {
                            LabError::no_answer(format!(
                                "line {} of shapes.jsonl: {e}",
                                record.line
                            ))
                        })?;
                        buffer.push(b'\n');
                    }
                    Ok::<(), LabError>(())
                })?;
            for buffer in &buffers {
                out.write_all(buffer)
                    .map_err(|e| LabError::io("writing shapes.jsonl", e))?;
            }
            let before = tally.records / PROGRESS_EVERY;
            tally.add(&records);
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
    fn add(&mut self, records: &[ShapeRecord]) {
        self.records += records.len();
        for r in records {
            self.not_confident += usize::from(!r.confident);
            self.not_stable += usize::from(!r.stable);
            self.no_shape += usize::from(r.error.is_some());
            if let Some(mm) = r.marker_mean_mm {
                self.marker_sum_mm += mm;
                self.marker_records += 1;
            }
            if let Some(sigma) = r.sigma.as_ref().filter(|s| !s.is_empty()) {
                #[allow(clippy::cast_precision_loss)] // at most MAX_POINTS
                let mean = sigma.iter().sum::<f64>() / sigma.len() as f64;
                self.sigma_sum_mm += 1e3 * mean;
                self.sigma_records += 1;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_line_has_the_counts_and_the_markers_when_measured() {
        let summary = ShapeLogSummary {
            records: 40,
            not_stable: 1,
            not_confident: 3,
            marker_mean_mm: Some(0.456),
            sigma_mean_mm: None,
        };
        assert_eq!(
            summary.to_string(),
            "40 records: 1 not stable, 3 not confident, inner markers 0.46 mm from the shapes\n"
        );
        let unmeasured = ShapeLogSummary {
            marker_mean_mm: None,
            ..summary
        };
        assert_eq!(
            unmeasured.to_string(),
            "40 records: 1 not stable, 3 not confident\n"
        );
    }
}
