//! The test block of `calibrate --log`: each test record's errors for every map compared
//! (the reading through the mounting alone, the kept map, its affine part, the map fitted on
//! the labels, the label itself), at the inner markers (the paper's metric, Fig. 5) and along
//! the wire to the label's shape; their means for `summary.json`, `test.csv`, and the
//! figures `label_fit` and `test_errors`.

use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::ft::Mounting;
use ftwire_estimate::shape::{centreline_distance, marker_distances};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_report::{LineChart, Series};
use nalgebra::{Vector3, Vector6};

use ftwire_app::csv_table::{CsvTable, text, value};
use ftwire_app::error::{LabError, from_estimate};
use ftwire_app::results::ResultsFolder;

use super::labelled::Labelled;
use super::summary::TestErrors;

/// Nodes of the shapes compared with the markers.
const SHAPE_NODES: usize = 101;

/// One test record's errors \[m\]: at the inner markers, and along the wire against the
/// label's shape.
pub(super) struct TestRow {
    line: usize,
    time: f64,
    raw: [f64; 2],
    calibrated: [f64; 2],
    affine: Option<[f64; 2]>,
    label_map: [f64; 2],
    label: f64,
}

/// The models of the test: the labels' and the one the map was fitted with (the loaded
/// model under a fitted gravity).
pub(super) struct TestModels<'a> {
    pub(super) labels: &'a KirchhoffModel,
    pub(super) fitted: &'a KirchhoffModel,
}

/// The maps compared on the test block.
pub(super) struct TestMaps<'a> {
    pub(super) mounting: &'a Mounting,
    pub(super) calibration: &'a Calibration,
    pub(super) affine: Option<&'a Calibration>,
    pub(super) label_map: &'a Calibration,
}

/// The mean distance of the inner markers to `Φ(a)`, and the mean distance along the wire
/// from `Φ(a)` to the label's shape \[m\].
fn distances(
    model: &KirchhoffModel,
    a: &Vector6<f64>,
    l: &Labelled,
    label_shape: &[Vector3<f64>],
) -> Result<[f64; 2], LabError> {
    let shape = model
        .shape(a, SHAPE_NODES)
        .map_err(|e| from_estimate(e, "the shape of a test record"))?;
    let d = marker_distances(&l.inner, &shape.positions)
        .map_err(|e| from_estimate(e, "the marker distances"))?;
    #[allow(clippy::cast_precision_loss)] // a handful of markers
    let markers = d.iter().sum::<f64>() / d.len().max(1) as f64;
    let wire = centreline_distance(&shape.positions, label_shape, SHAPE_NODES)
        .map_err(|e| from_estimate(e, "the distance along the wire"))?;
    Ok([markers, wire])
}

/// The test block's errors, record by record.
pub(super) fn test_errors(
    models: &TestModels<'_>,
    maps: &TestMaps<'_>,
    labelled: &[Labelled],
    test: &[usize],
) -> Result<Vec<TestRow>, LabError> {
    test.iter()
        .filter_map(|&i| labelled.get(i))
        .map(|l| {
            let label_shape = models
                .labels
                .shape(&l.label, SHAPE_NODES)
                .map_err(|e| from_estimate(e, "the shape of a label"))?
                .positions;
            let fitted = |a: &Vector6<f64>| distances(models.fitted, a, l, &label_shape);
            Ok(TestRow {
                line: l.line,
                time: l.time,
                raw: fitted(&maps.mounting.to_configuration(&l.raw))?,
                calibrated: fitted(&maps.calibration.apply_at(&l.raw, l.time))?,
                affine: maps
                    .affine
                    .map(|c| fitted(&c.apply_at(&l.raw, l.time)))
                    .transpose()?,
                label_map: distances(
                    models.labels,
                    &maps.label_map.apply_at(&l.raw, l.time),
                    l,
                    &label_shape,
                )?,
                label: distances(models.labels, &l.label, l, &label_shape)?[0],
            })
        })
        .collect()
}

/// The test block's means \[mm\] (zero for an empty block).
pub(super) fn mean_errors(rows: &[TestRow]) -> TestErrors {
    #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
    let n = rows.len().max(1) as f64;
    let mean = |f: &dyn Fn(&TestRow) -> f64| 1e3 * rows.iter().map(f).sum::<f64>() / n;
    let affine = |k: usize| {
        rows.iter()
            .all(|r| r.affine.is_some())
            .then(|| mean(&|r| r.affine.map_or(0.0, |a| a[k])))
            .filter(|_| !rows.is_empty())
    };
    let raw = mean(&|r| r.raw[0]);
    let calibrated = mean(&|r| r.calibrated[0]);
    TestErrors {
        raw_marker_mean_mm: raw,
        calibrated_marker_mean_mm: calibrated,
        label_marker_mean_mm: mean(&|r| r.label),
        affine_marker_mean_mm: affine(0),
        label_map_marker_mean_mm: mean(&|r| r.label_map[0]),
        raw_wire_mean_mm: mean(&|r| r.raw[1]),
        calibrated_wire_mean_mm: mean(&|r| r.calibrated[1]),
        affine_wire_mean_mm: affine(1),
        label_map_wire_mean_mm: mean(&|r| r.label_map[1]),
        worse_than_raw: calibrated > raw,
    }
}

/// `test.csv`.
pub(super) fn test_csv(rows: &[TestRow]) -> Result<Vec<u8>, LabError> {
    let mut csv = CsvTable::new(
        "test.csv",
        &[
            "line",
            "time",
            "raw_mm",
            "calibrated_mm",
            "label_mm",
            "affine_mm",
            "label_map_mm",
            "raw_wire_mm",
            "calibrated_wire_mm",
            "affine_wire_mm",
            "label_map_wire_mm",
        ],
    )?;
    let mm = |v: f64| value(1e3 * v);
    let opt = |v: Option<f64>| v.map_or_else(|| text(""), mm);
    for r in rows {
        csv.row(vec![
            value(r.line),
            value(r.time),
            mm(r.raw[0]),
            mm(r.calibrated[0]),
            mm(r.label),
            opt(r.affine.map(|a| a[0])),
            mm(r.label_map[0]),
            mm(r.raw[1]),
            mm(r.calibrated[1]),
            opt(r.affine.map(|a| a[1])),
            mm(r.label_map[1]),
        ])?;
    }
    csv.into_bytes()
}

/// `label_fit` (each label's RMS marker residual over time) and `test_errors` (the test
/// block's marker errors over time, uncalibrated and calibrated).
pub(super) fn write_figures(
    folder: &ResultsFolder,
    labelled: &[Labelled],
    rows: &[TestRow],
) -> Result<(), LabError> {
    let fits = LineChart::new(
        "labels: RMS marker residual of each record's shape fit",
        "time [s]",
        "RMS marker residual [mm]",
    )
    .with_series(Series::points(
        "kept labels",
        labelled.iter().map(|l| (l.time, 1e3 * l.rms)).collect(),
    ));
    folder.write_figure("label_fit", |dir| fits.write(dir, "label_fit"))?;
    let errors = LineChart::new(
        "test block: mean inner-marker distance to the shape from F/T",
        "time [s]",
        "mean marker distance [mm]",
    )
    .with_log_y()
    .with_series(Series::points(
        "mounting only",
        rows.iter().map(|r| (r.time, 1e3 * r.raw[0])).collect(),
    ))
    .with_series(Series::points(
        "calibrated",
        rows.iter()
            .map(|r| (r.time, 1e3 * r.calibrated[0]))
            .collect(),
    ))
    .with_series(Series::points(
        "label (floor)",
        rows.iter().map(|r| (r.time, 1e3 * r.label)).collect(),
    ));
    folder.write_figure("test_errors", |dir| errors.write(dir, "test_errors"))
}
