//! `calibrate --log`'s results as text: what `ftwire calibrate --log` prints.

use std::fmt::Write as _;
use std::path::Path;

use crate::calibrate::{LogCalibrateRun, LogCalibrateSummary, LogCalibrateTimings, MapLoss};

impl LogCalibrateRun {
    /// The results as text ([`text`]) with the run's timings; `results` is the folder the run
    /// was written to, named in the last line.
    pub fn text(&self, results: &Path) -> String {
        text(&self.summary, &self.timings, results)
    }
}

/// The results as text: the labels, the split, the map chosen and what it was fitted on, the
/// fitted gravity, the test block's marker and wire distances \[mm\], then the wall times
/// and `results`.
fn text(summary: &LogCalibrateSummary, timings: &LogCalibrateTimings, results: &Path) -> String {
    let s = summary;
    let mut text = String::new();
    let _ = writeln!(
        text,
        "labels: {} of {} records fitted ({} rejected), marker RMS {:.2} mm",
        s.labels.fitted, s.labels.records, s.labels.rejected, s.labels.marker_rms_mm
    );
    let _ = writeln!(
        text,
        "split by time: {} train, {} validation, {} test",
        s.split.train, s.split.validation, s.split.test
    );
    let _ = writeln!(
        text,
        "map: {} fitted on the {} ({})",
        s.fit.map,
        loss_name(s.fit.loss),
        s.fit.chosen_by
    );
    if let Some(g) = s.fit.gravity_in_clamp {
        let _ = writeln!(
            text,
            "gravity in the clamp frame: {:.3}, {:.3}, {:.3} m/s²",
            g[0], g[1], g[2]
        );
    }
    let t = &s.test;
    let _ = writeln!(
        text,
        "test block, mean inner-marker distance: {:.2} mm uncalibrated, {:.2} mm calibrated{} \
         (map fitted on the labels {:.2} mm; labels {:.2} mm)",
        t.raw_marker_mean_mm,
        t.calibrated_marker_mean_mm,
        t.affine_marker_mean_mm
            .map_or_else(String::new, |a| format!(
                ", {a:.2} mm its affine part alone"
            )),
        t.label_map_marker_mean_mm,
        t.label_marker_mean_mm
    );
    let _ = writeln!(
        text,
        "test block, mean distance along the wire to the labels' shapes: {:.2} mm calibrated",
        t.calibrated_wire_mean_mm
    );
    let _ = writeln!(
        text,
        "labels {:.1} s, training {:.1} s, shape fit {:.1} s; results in {}",
        timings.label_s,
        timings.train_s,
        timings.fit_s,
        results.display()
    );
    text
}

/// `shape` or `labels`.
fn loss_name(loss: MapLoss) -> &'static str {
    match loss {
        MapLoss::Shape => "shape",
        MapLoss::Labels => "labels",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibrate::{FitOut, Labels, SplitSizes, TestErrors};
    use ftwire_app::config::wire::WireSpec;

    #[test]
    fn the_text_has_the_labels_the_split_the_map_and_the_test_block() {
        let summary = LogCalibrateSummary {
            wire: WireSpec::preset("nitinol-3mm-820").expect("a preset"),
            labels: Labels {
                records: 40,
                fitted: 39,
                rejected: 1,
                marker_rms_mm: 0.371,
                ..Labels::default()
            },
            split: SplitSizes {
                train: 27,
                validation: 5,
                test: 7,
            },
            test: TestErrors {
                raw_marker_mean_mm: 14.41,
                calibrated_marker_mean_mm: 0.77,
                label_marker_mean_mm: 0.31,
                affine_marker_mean_mm: Some(0.85),
                label_map_marker_mean_mm: 0.88,
                raw_wire_mean_mm: 20.0,
                calibrated_wire_mean_mm: 0.92,
                affine_wire_mean_mm: None,
                label_map_wire_mean_mm: 1.0,
                worse_than_raw: false,
            },
            drift: None,
            fit: FitOut {
                loss: MapLoss::Shape,
                map: "affine+quadratic".to_owned(),
                chosen_by: "validation_marker_mean".to_owned(),
                gravity_in_clamp: Some([0.0, -9.81, 0.0]),
                degree: Some(2),
                ridge: None,
                validation_marker_mean_mm: None,
                huber_mm: None,
                candidates: Vec::new(),
                label_map_validation_marker_mean_mm: None,
                gravity_starts: Vec::new(),
                train_failures: 0,
            },
        };
        let timings = LogCalibrateTimings {
            label_s: 2.81,
            train_s: 0.0,
            fit_s: 0.84,
        };
        let text = text(&summary, &timings, Path::new("cal"));
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines,
            [
                "labels: 39 of 40 records fitted (1 rejected), marker RMS 0.37 mm",
                "split by time: 27 train, 5 validation, 7 test",
                "map: affine+quadratic fitted on the shape (validation_marker_mean)",
                "gravity in the clamp frame: 0.000, -9.810, 0.000 m/s²",
                "test block, mean inner-marker distance: 14.41 mm uncalibrated, 0.77 mm \
                 calibrated, 0.85 mm its affine part alone (map fitted on the labels 0.88 mm; \
                 labels 0.31 mm)",
                "test block, mean distance along the wire to the labels' shapes: 0.92 mm \
                 calibrated",
                "labels 2.8 s, training 0.0 s, shape fit 0.8 s; results in cal",
            ]
        );
    }
}
