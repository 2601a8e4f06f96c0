//! `ftwire demo`: the whole system at work in the simulator, the README's first command.
//!
//! The five phases (calibrate, identify, shape from F/T, plan, track), their numbers and the
//! files they write are [`ftwire_lab::demo`]'s. This command maps the options to
//! [`DemoParams`] (`--wire`, `--scene`, `--noise-model` with `offset` by default, `--sensor`,
//! `--rig`, `--seed`), draws a bar per phase on a terminal (plain lines otherwise) and prints
//! each phase's result on stderr, and writes `summary.json` (the run header, then `wire`,
//! `calibration`, `identification`, `shape`, `plan`, `tracking`; the same for the same seed)
//! and `timings.json` (each phase's wall time) into the results folder (`--out`, default
//! `results/demo`, written whole or not at all) beside the lab's `calibration.json`,
//! `shape.{png,svg}`, `tracking.{png,svg}` and `report.html`.

use std::io::IsTerminal as _;
use std::time::Duration;

use ftwire_lab::demo::{
    self, CALIBRATION_CONFIGS, DemoParams, DemoProgress, PHASES, SHAPE_CONFIGS,
};
use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::results::OutGuard;
use indicatif::{ProgressBar, ProgressStyle};

use crate::cli::demo::DemoArgs;
use crate::cli::experiment::NoiseModelArg;

/// The lab's settings of `args`.
fn params(args: &DemoArgs) -> DemoParams {
    DemoParams {
        wire: args.wire.clone(),
        seed: args.seed.seed,
        scene: args.scene.file.clone(),
        noise: args.noise.model_or(NoiseModelArg::Offset),
        sensor: args.setup.sensor.clone(),
        rig: args.setup.rig.clone(),
        calibration_configs: CALIBRATION_CONFIGS,
        shape_configs: SHAPE_CONFIGS,
    }
}

/// The demo's progress on stderr: a bar for the phase under way on a terminal, a line when
/// it starts otherwise, and a line with each phase's result.
#[derive(Default)]
struct Bars {
    bar: Option<ProgressBar>,
}

/// A phase's label, `[number/PHASES] name`.
fn label(number: usize, name: &str) -> String {
    format!("[{number}/{PHASES}] {name}")
}

impl DemoProgress for Bars {
    fn phase_started(&mut self, number: usize, name: &str, steps: usize) {
        let label = label(number, name);
        self.bar = std::io::stderr().is_terminal().then(|| {
            let bar = ProgressBar::new(steps as u64);
            let style = ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} {elapsed}")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> ");
            bar.set_style(style);
            bar.set_prefix(label.clone());
            bar.enable_steady_tick(Duration::from_millis(200));
            bar
        });
        if self.bar.is_none() {
            errln!("{label} ...");
        }
    }

    fn step(&mut self, done: usize) {
        if let Some(bar) = &self.bar {
            bar.set_position(done as u64);
        }
    }

    fn phase_finished(&mut self, number: usize, name: &str, result: &str, seconds: f64) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
        errln!("{}: {result} ({seconds:.1} s)", label(number, name));
    }
}

/// Runs the demo: its inputs checked, the folder opened, the five phases, then the folder
/// finished.
pub fn run(args: DemoArgs) -> Result<(), LabError> {
    let params = params(&args);
    params.check()?;
    let inputs = OutGuard::default()
        .input("--wire", &args.wire)
        .input_opt("--scene", args.scene.path())
        .input_opt("--sensor", args.setup.sensor.as_deref())
        .input_opt("--rig", args.setup.rig.as_deref());
    let folder = args.results.open("demo", inputs)?;
    let run = demo::run(&params, &folder, &mut Bars::default())?;
    let header = RunHeader::new("demo", Some(params.seed), &args)?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    outln!(
        "demo done in {:.0} s; results in {}",
        run.timings.total_s,
        target.display()
    );
    Ok(())
}
