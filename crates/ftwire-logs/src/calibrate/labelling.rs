//! The labels of `calibrate --log`: the recording read and checked ([`read`]), then every
//! record's `a` by shape fitting to its markers (eq. 15) on every core ([`label_all`]), or the
//! reason it has none, counted and written to `labels.csv`. A label the markers do not
//! support (too few, a failed fit, a fit far off them) is rejected here, so that it never
//! teaches the map.

use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::log::LogRecord;
use ftwire_estimate::shape::{
    Correspondence, FitParams, Markers, ShapeFitter, evenly_spaced_fractions,
};
use nalgebra::{Point3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use ftwire_app::Progress;
use ftwire_app::csv_table::{CsvTable, text, value};
use ftwire_app::error::{LabError, from_estimate};

use super::labelled::Labelled;
use super::params::{LogCalibrateParams, MIN_MARKERS};
use super::summary::Labels;

/// Records between two progress lines.
const PROGRESS_EVERY: usize = 100;

/// A reading further than this many robust standard deviations (1.4826 × the median absolute
/// deviation) from the session's median in any channel is an outlier: a glitch of the sensor
/// or the logger, not a load the wire put on it. Its label is not fitted and it never teaches
/// the map, whose least-squares start one such reading would decide.
pub const OUTLIER_SCALES: f64 = 25.0;

/// The smallest robust spread of a channel the screen assumes \[N ×3, N·m ×3\], force first:
/// a channel the session hardly loads still scatters by a sensor's noise.
const SPREAD_FLOOR: [f64; 6] = [0.05, 0.05, 0.05, 0.005, 0.005, 0.005];

/// Whether each record's reading is an outlier of the session ([`OUTLIER_SCALES`]).
fn outlier_readings(records: &[LogRecord]) -> Vec<bool> {
    let median = ftwire_core::stats::median;
    let channels: Vec<(f64, f64)> = (0..6)
        .map(|i| {
            let values: Vec<f64> = records.iter().filter_map(|r| r.raw.map(|x| x[i])).collect();
            let centre = median(&values);
            let deviations: Vec<f64> = values.iter().map(|v| (v - centre).abs()).collect();
            (centre, (1.4826 * median(&deviations)).max(SPREAD_FLOOR[i]))
        })
        .collect();
    records
        .iter()
        .map(|r| {
            r.raw.is_some_and(|x| {
                channels
                    .iter()
                    .enumerate()
                    .any(|(i, &(centre, spread))| (x[i] - centre).abs() > OUTLIER_SCALES * spread)
            })
        })
        .collect()
}

/// Reads the log; refuses one without raw readings or markers.
pub(super) fn read(path: &std::path::Path) -> Result<(Vec<LogRecord>, Vec<usize>), LabError> {
    let (lines, records): (Vec<usize>, Vec<LogRecord>) = crate::read_log(path)?
        .into_iter()
        .map(|l| (l.line, l.record))
        .unzip();
    if !records.iter().any(|r| r.raw.is_some()) {
        return Err(LabError::bad_input(format!(
            "--log {}: no record has a raw F/T reading (`raw`): there is nothing to calibrate",
            path.display()
        )));
    }
    if !records.iter().any(|r| r.markers.is_some()) {
        return Err(LabError::bad_input(format!(
            "--log {}: no record has markers (`markers`): the labels come from fitting the \
             wire to them",
            path.display()
        )));
    }
    Ok((records, lines))
}

/// Why a record got no label.
enum Rejection {
    NoRaw,
    OutlierReading,
    FewMarkers,
    FitFailed,
    OffMarkers(f64),
}

/// Labels every record; returns the labelled ones, the counts and `labels.csv`.
pub(super) fn label_all(
    params: &LogCalibrateParams,
    model: &KirchhoffModel,
    (records, lines): (&[LogRecord], &[usize]),
    progress: Progress<'_>,
) -> Result<(Vec<Labelled>, Labels, Vec<u8>), LabError> {
    let fitter = fitter(model, params.marker_fractions.is_some())?;
    let outcomes = fit_in_parallel(params, &fitter, records, progress)?;
    let outliers = outlier_readings(records);
    let mut counts = Labels {
        records: records.len(),
        ..Labels::default()
    };
    let mut csv = CsvTable::new(
        "labels.csv",
        &[
            "line", "time", "status", "rms_mm", "a1", "a2", "a3", "a4", "a5", "a6",
        ],
    )?;
    let mut labelled = Vec::new();
    for (((record, &line), outcome), outlier) in
        records.iter().zip(lines).zip(outcomes).zip(outliers)
    {
        let outcome = if outlier {
            Err(Rejection::OutlierReading)
        } else {
            outcome
        };
        match outcome {
            Ok(l) => {
                let mut cells = vec![value(line), value(record.time), text("fitted")];
                cells.push(value(1e3 * l.rms));
                cells.extend(l.label.iter().map(|&v| value(v)));
                csv.row(cells)?;
                labelled.push(Labelled { line, ..l });
            }
            Err(why) => {
                let (status, rms, count) = match why {
                    Rejection::NoRaw => ("no_raw", None, &mut counts.no_raw),
                    Rejection::OutlierReading => {
                        ("outlier_reading", None, &mut counts.outlier_readings)
                    }
                    Rejection::FewMarkers => ("few_markers", None, &mut counts.few_markers),
                    Rejection::FitFailed => ("fit_failed", None, &mut counts.fit_failed),
                    Rejection::OffMarkers(rms) => {
                        ("off_markers", Some(rms), &mut counts.off_markers)
                    }
                };
                *count += 1;
                let mut cells = vec![value(line), value(record.time), text(status)];
                cells.push(rms.map_or_else(|| text(""), |r| value(1e3 * r)));
                cells.extend((0..6).map(|_| text("")));
                csv.row(cells)?;
            }
        }
    }
    counts.fitted = labelled.len();
    counts.rejected = counts.records - counts.fitted;
    if counts.outlier_readings > 0 {
        progress(&format!(
            "warning: {} of {} readings lie more than {OUTLIER_SCALES} robust standard \
             deviations from the session's median in some channel (a sensor's or a logger's \
             glitch) and are left out (labels.csv: outlier_reading)",
            counts.outlier_readings, counts.records
        ));
    }
    if labelled.is_empty() {
        return Err(LabError::bad_input(format!(
            "--log {}: every record was rejected ({} without raw, {} outlier readings, {} with \
             fewer than {MIN_MARKERS} markers, {} fits failed, {} fits more than {:.1} mm RMS \
             off their markers): nothing to learn from",
            params.log.display(),
            counts.no_raw,
            counts.outlier_readings,
            counts.few_markers,
            counts.fit_failed,
            counts.off_markers,
            1e3 * params.max_label_rms
        )));
    }
    #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
    let n = labelled.len() as f64;
    counts.marker_rms_mm = 1e3 * labelled.iter().map(|l| l.rms).sum::<f64>() / n;
    Ok((labelled, counts, csv.into_bytes()?))
}

/// Every record's label or rejection, fitted on every core: record `k` (0-based) draws from
/// its own generator seeded by `seed` and `k`, so the labels do not depend on the number of
/// threads.
fn fit_in_parallel(
    params: &LogCalibrateParams,
    fitter: &ShapeFitter<KirchhoffModel>,
    records: &[LogRecord],
    progress: Progress<'_>,
) -> Result<Vec<Result<Labelled, Rejection>>, LabError> {
    let threads = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    let chunk = records.len().div_ceil(threads).max(1);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let results: Vec<Result<Vec<_>, LabError>> = std::thread::scope(|scope| {
        let handles: Vec<_> = records
            .chunks(chunk)
            .enumerate()
            .map(|(c, part)| {
                let done = &done;
                scope.spawn(move || {
                    part.iter()
                        .enumerate()
                        .map(|(j, record)| {
                            let k = c * chunk + j;
                            let mut rng = ChaCha8Rng::seed_from_u64(
                                params.seed.wrapping_mul(1_000_003).wrapping_add(k as u64),
                            );
                            done.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                            label_one(params, fitter, record, &mut rng)
                        })
                        .collect::<Result<Vec<_>, LabError>>()
                })
            })
            .collect();
        let mut reported = 0;
        while handles.iter().any(|h| !h.is_finished()) {
            std::thread::sleep(std::time::Duration::from_millis(200));
            let now = done.load(std::sync::atomic::Ordering::Relaxed) / PROGRESS_EVERY;
            if now > reported {
                reported = now;
                progress(&format!("  {} / {}", now * PROGRESS_EVERY, records.len()));
            }
        }
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err(LabError::no_answer("a labelling thread panicked")))
            })
            .collect()
    });
    let mut all = Vec::with_capacity(records.len());
    for part in results {
        all.extend(part?);
    }
    Ok(all)
}

/// The shape fitter: at the markers' arc lengths, or at their closest points.
fn fitter(
    model: &KirchhoffModel,
    arc_lengths: bool,
) -> Result<ShapeFitter<KirchhoffModel>, LabError> {
    let config = FitParams {
        correspondence: if arc_lengths {
            Correspondence::ArcLength
        } else {
            Correspondence::ClosestPoint
        },
        ..FitParams::default()
    };
    ShapeFitter::new(*model)
        .with_config(config)
        .map_err(|e| from_estimate(e, "the shape fitter"))
}

/// One record's label, or why it has none.
fn label_one(
    params: &LogCalibrateParams,
    fitter: &ShapeFitter<KirchhoffModel>,
    record: &LogRecord,
    rng: &mut ChaCha8Rng,
) -> Result<Result<Labelled, Rejection>, LabError> {
    let Some(raw) = record.raw() else {
        return Ok(Err(Rejection::NoRaw));
    };
    let gravity = record.gravity.map(Vector3::from);
    let raw = params
        .mounting
        .compensate(&raw, gravity.as_ref())
        .map_err(|e| {
            LabError::bad_input(format!("--log: the record at time {}: {e}", record.time))
        })?;
    let seen: Vec<Option<Point3<f64>>> = record.markers().unwrap_or_default();
    let observed: Vec<Point3<f64>> = seen.iter().flatten().copied().collect();
    // The inner markers, by their place in the list: not the first (at the clamp) nor the
    // last (at the gripper), whether or not those were seen.
    let inner: Vec<Point3<f64>> = seen
        .get(1..seen.len().saturating_sub(1))
        .unwrap_or(&[])
        .iter()
        .flatten()
        .copied()
        .collect();
    if observed.len() < MIN_MARKERS {
        return Ok(Err(Rejection::FewMarkers));
    }
    let fractions = match &params.marker_fractions {
        Some(f) if f.len() == seen.len() => f.clone(),
        Some(f) => {
            return Err(LabError::bad_input(format!(
                "--marker-fractions has {} fractions but the record at time {} has {} markers",
                f.len(),
                record.time,
                seen.len()
            )));
        }
        // Closest-point matching does not use the fractions; any valid ones do.
        None => evenly_spaced_fractions(seen.len()),
    };
    let fit = Markers::new(&fractions, &seen).and_then(|m| fitter.fit(&m, rng));
    let Ok(fit) = fit else {
        return Ok(Err(Rejection::FitFailed));
    };
    if fit.rms.is_nan() || fit.rms > params.max_label_rms {
        return Ok(Err(Rejection::OffMarkers(fit.rms)));
    }
    let (loss_markers, loss_fractions): (Vec<Point3<f64>>, Vec<f64>) = seen
        .iter()
        .zip(&fractions)
        .skip(1)
        .filter_map(|(p, f)| p.map(|p| (p, *f)))
        .unzip();
    Ok(Ok(Labelled {
        line: 0,
        time: record.time,
        raw,
        label: fit.a,
        rms: fit.rms,
        inner,
        loss_markers,
        loss_fractions: params.marker_fractions.is_some().then_some(loss_fractions),
    }))
}
