//! The demo's phases as they run: reported to a progress and timed.

use std::time::Instant;

/// Where the demo reports its progress: each phase's start, its steps and its one-line
/// result. The `ftwire` binary draws a bar per phase on a terminal and prints the results on
/// stderr.
pub trait DemoProgress {
    /// Phase `number` (1 to [`PHASES`](super::PHASES)), `name`, started; it has `steps` steps.
    fn phase_started(&mut self, number: usize, name: &str, steps: usize);

    /// `done` steps of the phase under way are done.
    fn step(&mut self, done: usize);

    /// Phase `number`, `name`, ended after `seconds` of wall time with `result`, one line of
    /// text.
    fn phase_finished(&mut self, number: usize, name: &str, result: &str, seconds: f64);
}

/// A phase under way: reported to the progress and timed.
pub(super) struct Phase {
    number: usize,
    name: &'static str,
    start: Instant,
}

impl Phase {
    /// Reports the start of phase `number` with `steps` steps.
    pub(super) fn start(
        progress: &mut dyn DemoProgress,
        number: usize,
        name: &'static str,
        steps: usize,
    ) -> Self {
        progress.phase_started(number, name, steps);
        Self {
            number,
            name,
            start: Instant::now(),
        }
    }

    /// Reports the end of the phase with a one-line result; returns its wall time \[s\].
    pub(super) fn finish(self, progress: &mut dyn DemoProgress, result: &str) -> f64 {
        let seconds = self.start.elapsed().as_secs_f64();
        progress.phase_finished(self.number, self.name, result, seconds);
        seconds
    }
}
