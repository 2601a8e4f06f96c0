//! The goal experiment's results as text: what `ftwire experiment goal` prints.

use std::fmt::Write as _;
use std::path::Path;

use super::GoalRun;
use crate::paper::TABLE_III;

impl GoalRun {
    /// The results as text: the summary's table beside the paper's Table III, the ε rows, the
    /// steps and the controller step's median time \[µs\], the collision detector's counts,
    /// then the wall times and `results`, the folder the run was written to.
    pub fn text(&self, results: &Path) -> String {
        let s = &self.summary;
        let mut text = String::new();
        let _ = writeln!(
            text,
            "goal: {} ({} model), {} pairs, K = {}, noise model {}",
            s.wire,
            s.model.name(),
            s.pairs,
            s.gain,
            s.noise_model.name()
        );
        let _ = writeln!(
            text,
            "{:<24} {:>9} {:>8} {:>9} {:>7} {:>7} {:>7} {:>9}",
            "", "mean_mm", "std_mm", "a_error", "trials", "failed", "snapped", "no-snap"
        );
        for (name, m) in [
            ("open loop, no noise", &s.results.open_loop.no_noise),
            ("closed loop, no noise", &s.results.closed_loop.no_noise),
            ("open loop, noise", &s.results.open_loop.noise),
            ("closed loop, noise", &s.results.closed_loop.noise),
        ] {
            let _ = writeln!(
                text,
                "{name:<24} {:>9.2} {:>8.2} {:>9.3} {:>7} {:>7} {:>7} {:>9.2}",
                m.mean_mm,
                m.std_mm,
                m.a_error_mean,
                m.trials,
                m.failed,
                m.snapped,
                m.mean_mm_without_snaps
            );
        }
        let [(_, open_free, closed_free), (_, open_noise, closed_noise)] = TABLE_III;
        let _ = writeln!(
            text,
            "paper Table III: open {open_free:.2} / {open_noise:.2}, closed {closed_free:.2} / \
             {closed_noise:.2} (no noise / noise)"
        );
        if s.shape_stop_mm > 0.0 {
            let _ = writeln!(
                text,
                "closed loop, noise: the shape stop at {} mm; the ε rows below are read off those runs",
                s.shape_stop_mm
            );
        }
        for (name, rows) in [
            ("no noise", &s.epsilon_tradeoff.no_noise),
            ("noise", &s.epsilon_tradeoff.noise),
        ] {
            for r in rows {
                let _ = writeln!(
                    text,
                    "ε = {:<5} ({name}): mean {:.2} mm, steps median {}, reached {}/{}",
                    r.epsilon, r.mean_mm, r.steps_median, r.reached, r.trials
                );
            }
        }
        let _ = writeln!(
            text,
            "steps median {} (noise), {} (no noise); controller step {:.1} µs (median)",
            s.steps_median, s.steps_median_no_noise, self.timings.controller_step_us_median
        );
        let c = &s.collision;
        let _ = writeln!(
            text,
            "collision: {} false alarms ({} at snaps) in {} free motions; {} contacts, {} detected, {} missed, delay median {} steps ({:?}), {} early alarms, {} without contact; threshold {:.3}, floor {:.4}",
            c.false_alarms,
            c.false_alarms_at_snaps,
            c.free_motions,
            c.trials,
            c.detected,
            c.missed,
            c.detection_delay_steps_median,
            c.delays,
            c.early_alarms,
            c.no_contact,
            c.threshold,
            c.floor
        );
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
