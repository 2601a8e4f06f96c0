//! The shape experiment's results as text: what `ftwire experiment shape` prints.

use std::fmt::Write as _;
use std::path::Path;

use super::ShapeRun;
use crate::experiment::ModelKind;
use crate::paper::TABLE_II;

impl ShapeRun {
    /// The results as text: one row per wire beside the paper's Table II (the estimators'
    /// model, the other model from the same `ã`, the fused, marker and mounting-only means,
    /// one estimate's median time \[µs\], the relative errors of `ã` \[%\]), then the wall
    /// times and `results`, the folder the run was written to.
    pub fn text(&self, results: &Path) -> String {
        let summary = &self.summary;
        let mut text = String::new();
        let _ = writeln!(
            text,
            "shape: {} model (mean_mm), the {} model from the same ã beside it",
            summary.model.name(),
            summary.model.other().name()
        );
        let _ = writeln!(
            text,
            "{:<18} {:>7} {:>8} {:>7} {:>10} {:>8} {:>10} {:>10} {:>8} {:>9} {:>9} {:>9}",
            "wire",
            "configs",
            "mean_mm",
            "std_mm",
            summary.model.other().name(),
            "fused",
            "marker_mm",
            "mounting",
            "est_us",
            "Table II",
            "torque_%",
            "force_%"
        );
        for (r, (_, estimate_us)) in summary.wires.iter().zip(&self.timings.estimate_us_median) {
            let paper = TABLE_II
                .iter()
                .find(|(n, _)| *n == r.name)
                .map_or_else(|| "-".to_owned(), |(_, v)| format!("{v:.2}"));
            let other = match summary.model {
                ModelKind::Weightless => r.loaded_mean_mm,
                ModelKind::Loaded => r.kirchhoff_mean_mm,
            };
            let _ = writeln!(
                text,
                "{:<18} {:>7} {:>8.2} {:>7.2} {:>10.2} {:>8.2} {:>10.2} {:>10.2} {:>8.1} {:>9} {:>9.3} {:>9.3}",
                r.name,
                r.configs,
                r.mean_mm,
                r.std_mm,
                other,
                r.fused_mean_mm,
                r.marker_mean_mm,
                r.mounting_mean_mm,
                estimate_us,
                paper,
                100.0 * r.torque_rel,
                100.0 * r.force_rel
            );
        }
        let _ = writeln!(
            text,
            "calibration {:.1} s, experiment {:.1} s; results in {}",
            self.timings.calibration_s,
            self.timings.experiment_s,
            results.display()
        );
        text
    }
}
