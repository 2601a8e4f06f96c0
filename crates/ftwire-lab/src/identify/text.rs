//! The identification experiment's results as text: what `ftwire experiment identify` prints,
//! per wire the 3-sample row beside the paper's Table I and one line per sample count.

use std::fmt::Write as _;
use std::path::Path;

use super::until::UntilSummary;
use super::{IdentifyRun, IdentifySummary, PARAMETERS};
use crate::paper::TABLE_I;

impl IdentifyRun {
    /// The run's results as text ([`table`]), each sample count with its median identification
    /// time from the run's timings; `results` is the folder the run was written to, named in
    /// the first line.
    pub fn text(&self, results: &Path) -> String {
        let summary = &self.summary;
        let median_ms = |w: usize, n: usize| {
            summary.wires.get(w).map_or(f64::NAN, |r| {
                self.timings.median_ms(summary.model, &r.wire.name, n)
            })
        };
        table(summary, results, &median_ms)
    }
}

/// The results as text: a line of the run's settings and `results` (the folder written); per
/// wire, the 3-sample row (or the smallest count) beside Table I, one line per sample count
/// with its median time \[ms\] from `median_ms` (of the wire's index and the count), the
/// `--until` line and the linear density when there are; then each other model's row of the
/// same data.
pub fn table(
    summary: &IdentifySummary,
    results: &Path,
    median_ms: &dyn Fn(usize, usize) -> f64,
) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "identify: gravity {:?}, {} model, {} sensor, {:?} pipeline{}, {:?} residual, {} \
         trials; results in {}",
        summary.gravity,
        summary.model.name(),
        summary.sensor,
        summary.pipeline,
        summary
            .calibration
            .as_ref()
            .map_or_else(String::new, |c| format!(" ({c})")),
        summary.form,
        summary.trials,
        results.display()
    );
    for (w, result) in summary.wires.iter().enumerate() {
        let paper = TABLE_I
            .iter()
            .find(|(name, _)| *name == result.wire.name)
            .map(|(_, rows)| rows);
        let Some(row) = result
            .by_samples
            .iter()
            .find(|r| r.samples == 3)
            .or_else(|| result.by_samples.first())
        else {
            continue;
        };
        let _ = writeln!(
            text,
            "\n{} ({} samples; {} of {} trials identified)",
            result.wire.name, row.samples, row.identified, summary.trials
        );
        let _ = writeln!(
            text,
            "  {:<3} {:>8} {:>22} {:>10} {:>12}   paper (Table I, 3 samples)",
            "", "true", "estimated", "err(mean)", "mean|err|"
        );
        let truth = [
            result.wire.c[0],
            result.wire.c[1],
            result.wire.c[2],
            result.wire.length,
        ];
        for (j, parameter) in PARAMETERS.iter().enumerate() {
            let paper_text = paper.map_or_else(
                || "—".to_owned(),
                |rows| {
                    let (_, estimate, pm, error) = rows[j];
                    format!("{estimate:.3} ± {pm:.3}, {error:.1} %")
                },
            );
            let _ = writeln!(
                text,
                "  {parameter:<3} {:>8.4} {:>11.5} ± {:<8.5} {:>8.3} % {:>10.3} %   {paper_text}",
                truth[j],
                row.mean[j],
                row.std[j],
                100.0 * row.relative_error[j],
                100.0 * row.mean_abs_relative_error[j],
            );
        }
        let _ = writeln!(
            text,
            "  samples: mean |relative error| c1 c2 c3 L [%] (all; identified only), \
             identified, compute median [ms]"
        );
        for r in &result.by_samples {
            let e = r.mean_abs_relative_error.map(|v| 100.0 * v);
            let t = r.mean_abs_relative_error_identified.map(|v| 100.0 * v);
            let _ = writeln!(
                text,
                "  {:>3}: {:>7.3} {:>7.3} {:>7.3} {:>7.3};  {:>7.3} {:>7.3} {:>7.3} {:>7.3}   \
                 {:>2}/{}   {:>8.1}",
                r.samples,
                e[0],
                e[1],
                e[2],
                e[3],
                t[0],
                t[1],
                t[2],
                t[3],
                r.identified,
                summary.trials,
                median_ms(w, r.samples)
            );
        }
        if let Some(until) = result.until.as_ref() {
            until_line(&mut text, until);
        }
        if let Some(density) = row.linear_density.as_ref() {
            let _ = writeln!(
                text,
                "  linear density ({} samples): true {:.5} kg/m, estimated {:.5} ± {:.5}, \
                 mean |err| {:.2} %",
                row.samples,
                result.wire.linear_density,
                density.mean,
                density.std,
                100.0 * density.mean_abs_relative_error
            );
        }
    }
    for other in summary.by_model.iter().skip(1) {
        let _ = writeln!(
            text,
            "\nthe same data through the {} model (mean |relative error| c1 c2 c3 L [%], \
             identified):",
            other.model.name()
        );
        for result in &other.wires {
            if let Some(r) = result
                .by_samples
                .iter()
                .find(|r| r.samples == 3)
                .or_else(|| result.by_samples.first())
            {
                let e = r.mean_abs_relative_error.map(|v| 100.0 * v);
                let _ = writeln!(
                    text,
                    "  {} ({} samples): {:>7.3} {:>7.3} {:>7.3} {:>7.3}   {:>2}/{}",
                    result.wire.name,
                    r.samples,
                    e[0],
                    e[1],
                    e[2],
                    e[3],
                    r.identified,
                    summary.trials
                );
            }
        }
    }
    text
}

/// The `--until` line of one wire.
fn until_line(text: &mut String, until: &UntilSummary) {
    let e = until.max_abs_relative_error.map(|v| 100.0 * v);
    let _ = writeln!(
        text,
        "  --until {} %: {}/{} reached within {} samples; samples median {}, max {}; \
         largest |relative error| c1 c2 c3 L [%] {:.3} {:.3} {:.3} {:.3}",
        until.target_percent,
        until.reached,
        until.trials,
        until.limit,
        until.samples_median,
        until.samples_max,
        e[0],
        e[1],
        e[2],
        e[3]
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::{Gravity, ModelKind};
    use crate::identify::{
        BySamples, DensityStats, ModelResults, NoiseOut, Pipeline, WireOut, WireResults,
    };
    use ftwire_logs::identification::Form;

    fn row(samples: usize, error: f64) -> BySamples {
        BySamples {
            samples,
            estimated: 2,
            identified: 2,
            mean: [0.042, 0.055, 0.055, 0.63],
            std: [1e-4; 4],
            relative_error: [error; 4],
            mean_abs_relative_error: [error; 4],
            mean_abs_relative_error_identified: [error; 4],
            evaluations_median: 100.0,
            coverage95: [1.0; 4],
            linear_density: Some(DensityStats {
                mean: 0.02,
                std: 0.001,
                mean_abs_relative_error: 0.05,
            }),
        }
    }

    #[test]
    fn the_table_has_the_settings_the_rows_and_the_paper() {
        let wire = WireResults {
            wire: WireOut {
                name: "nitinol-2mm-630".to_owned(),
                c: [0.042, 0.055, 0.055],
                length: 0.63,
                linear_density: 0.0203,
            },
            by_samples: vec![row(2, 0.01), row(3, 0.005)],
            until: Some(UntilSummary {
                target_percent: 5.0,
                limit: 3,
                trials: 2,
                reached: 1,
                samples_median: 2.5,
                samples_max: 3,
                samples: vec![2, 3],
                mean_abs_relative_error: [0.01; 4],
                max_abs_relative_error: [0.02; 4],
                coverage95: [1.0; 4],
            }),
        };
        let summary = IdentifySummary {
            model: ModelKind::Loaded,
            form: Form::Absolute,
            gravity: Gravity::On,
            sensor: "distorted".to_owned(),
            pipeline: Pipeline::Mounting,
            calibration: None,
            trials: 2,
            noise: NoiseOut {
                pose_noise_deg: 0.05,
                pose_noise_mm: 0.1,
                gain_error_percent: 0.0,
                torque_gain_error_percent: 0.0,
                bias_model: true,
                model_floor_percent: 0.01,
            },
            sample_counts: vec![2, 3],
            wire: wire.wire.clone(),
            by_samples: wire.by_samples.clone(),
            until: wire.until.clone(),
            wires: vec![wire.clone()],
            by_model: vec![
                ModelResults {
                    model: ModelKind::Loaded,
                    wires: vec![wire.clone()],
                },
                ModelResults {
                    model: ModelKind::Weightless,
                    wires: vec![wire],
                },
            ],
        };
        let text = table(&summary, Path::new("out"), &|w, n| (10 * w + n) as f64);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "identify: gravity On, loaded model, distorted sensor, Mounting pipeline, Absolute \
             residual, 2 trials; results in out"
        );
        assert_eq!(
            lines[2],
            "nitinol-2mm-630 (3 samples; 2 of 2 trials identified)"
        );
        assert_eq!(
            lines[4],
            "  c1    0.0420     0.04200 ± 0.00010     0.500 %      0.500 %   0.043 ± 0.006, 2.4 %"
        );
        assert!(lines[9].starts_with("    2:   1.000"), "{}", lines[9]);
        assert!(lines[10].ends_with("2/2        3.0"), "{}", lines[10]);
        assert!(
            lines[11]
                .starts_with("  --until 5 %: 1/2 reached within 3 samples; samples median 2.5"),
            "{}",
            lines[11]
        );
        assert!(
            lines[12].contains("estimated 0.02000 ± 0.00100, mean |err| 5.00 %"),
            "{}",
            lines[12]
        );
        assert_eq!(
            lines.last().copied(),
            Some("  nitinol-2mm-630 (3 samples):   0.500   0.500   0.500   0.500    2/2")
        );
    }
}
