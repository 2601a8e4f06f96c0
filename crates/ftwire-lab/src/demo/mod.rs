//! The demo (`ftwire demo`): the whole system at work in the simulator, in five phases.
//!
//! 1. **Calibrate** the F/T sensor on the known wire
//!    ([`crate::experiment::calibration::KNOWN_WIRE`]): F/T and motion capture over
//!    [`DemoParams::calibration_configs`] configurations, labels by shape fitting with the
//!    loaded model, the network trained on them (as the calibration experiment).
//! 2. **Identify** the wire of [`DemoParams::wire`], whose stiffness, length and weight the
//!    demo is not told: the library's identification motion from a random start,
//!    [`IDENTIFY_SAMPLES`] samples through the learnt calibration, the loaded model under the
//!    known gravity (as the identification experiment, one trial).
//! 3. **Shape from F/T**: the identified model's shape from `ã` alone at
//!    [`DemoParams::shape_configs`] configurations of `A_free`, against the simulator's true
//!    wire.
//! 4. **Plan** through the scene ([`DemoParams::scene`], default the shipped 50 mm passage,
//!    `scenes/passage.toml`) with RRT* in `A_free` for the identified wire, a fixed iteration
//!    budget (the same path on any machine), resampled into waypoints; under `increment` and
//!    `absolute` noise the waypoints whose landings come closer than 15 mm to a box are first
//!    moved away from it (`plan.polish`, as the passage experiment).
//! 5. **Track** the plan in the simulator with the scene's obstacles (execution noise
//!    [`DemoParams::noise`], `offset` by default: a real robot's calibration error): closed
//!    loop with the identified loaded model and the collision detector armed (calibrated on a
//!    rehearsal away from the obstacles), then once open loop for contrast; each scored on the
//!    true wire (touched an obstacle, final error, shape against the plan at each waypoint).
//!
//! Gravity is on throughout. [`run`] reports each phase's start, steps and one-line result to
//! a [`DemoProgress`] and writes into the results folder `calibration.json` (the weights),
//! `shape.{png,svg}` (the estimated and the true wire of the first configuration),
//! `tracking.{png,svg}` (the scene's boxes and the true wire at each rest of the closed-loop
//! run) and `report.html` (the numbers, those figures and 3-D views of the runs, one
//! self-contained page). The caller writes `summary.json` ([`DemoRun::summary`]:
//! `wire`, `calibration`, `identification`, `shape`, `plan`, `tracking`, the same for the same
//! seed) and `timings.json` ([`DemoRun::timings`]: each phase's wall time, and each plan
//! candidate's when the plan was chosen among them). Guarded by `tests/demo.rs` and the
//! recorded summary of `crates/ftwire/tests/demo_cli.rs`.

use std::path::PathBuf;
use std::time::Instant;

use ftwire_control::NoiseModel;
use serde::Serialize;

use crate::error::{LabError, from_plan};
use crate::experiment::calibration::KNOWN_WIRE;
use crate::identify::linear_density;
use crate::passage::load_scene;
use crate::results::ResultsFolder;
use crate::setup::SimSetup;
use crate::wire::WireSpec;

mod inputs;
mod page;
mod phase;
mod sense;
mod steer;
mod summary;

use inputs::Inputs;
pub use phase::DemoProgress;
pub use sense::IDENTIFY_SAMPLES;
pub use summary::{
    CalibrationOut, DemoSummary, DemoTimings, IdentificationOut, PlanOut, ShapeOut, TrackingOut,
    WireTruth,
};

/// The wire the demo picks up by default.
pub const DEFAULT_WIRE: &str = "nitinol-3mm-910";

/// Configurations of the calibration phase by default: as many as the calibration
/// experiment collects by default (`crate::experiment::calibration::DEFAULT_SAMPLES`), so
/// that the demo's calibrated map is as good as the experiment's (the summary reports its
/// test error).
pub const CALIBRATION_CONFIGS: usize = 600;

/// Configurations of the shape phase by default.
pub const SHAPE_CONFIGS: usize = 5;

/// The demo's phases, in order (their numbers run from 1 to this).
pub const PHASES: usize = 5;

/// The settings of the demo.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DemoParams {
    /// The wire to pick up, identify and steer: a preset or a wire file (TOML). The demo is
    /// not told its stiffness, length or weight; only the simulator is.
    pub wire: String,
    /// The seed of every random choice.
    pub seed: u64,
    /// The scene file; `None`: the shipped 50 mm passage (`scenes/passage.toml`).
    pub scene: Option<PathBuf>,
    /// Execution noise on the second gripper while tracking.
    pub noise: NoiseModel,
    /// The simulated F/T sensor: a preset name or a sensor file; `None`: the default sensor.
    pub sensor: Option<String>,
    /// The simulated rig file; `None`: the library's rig.
    pub rig: Option<PathBuf>,
    /// Configurations collected in the calibration phase, at least 1.
    pub calibration_configs: usize,
    /// Configurations of `A_free` in the shape phase, at least 1.
    pub shape_configs: usize,
}

impl Default for DemoParams {
    /// `ftwire demo`'s defaults: [`DEFAULT_WIRE`], seed 0, the shipped passage, `offset`
    /// noise, the default sensor and rig, [`CALIBRATION_CONFIGS`] and [`SHAPE_CONFIGS`].
    fn default() -> Self {
        Self {
            wire: DEFAULT_WIRE.to_owned(),
            seed: 0,
            scene: None,
            noise: NoiseModel::Offset,
            sensor: None,
            rig: None,
            calibration_configs: CALIBRATION_CONFIGS,
            shape_configs: SHAPE_CONFIGS,
        }
    }
}

impl DemoParams {
    /// Checks the settings as [`run`] does before any work (the wire, the sensor and rig, the
    /// scene with its `start` and `goal`, the counts), so that a caller can refuse bad input
    /// before it opens a results folder.
    ///
    /// # Errors
    /// Bad input naming what is wrong.
    pub fn check(&self) -> Result<(), LabError> {
        self.inputs().map(|_| ())
    }

    /// The inputs read and checked.
    fn inputs(&self) -> Result<Inputs, LabError> {
        let wire = WireSpec::load(&self.wire).map_err(|e| LabError::bad_input(e.to_string()))?;
        let setup = SimSetup::load(self.sensor.as_deref(), self.rig.as_deref())
            .map_err(|e| LabError::bad_input(e.to_string()))?;
        let (scene, scene_name) = load_scene(self.scene.as_deref())?;
        // The plan of phase 4 runs from the scene's `start` to its `goal`.
        for name in ["start", "goal"] {
            scene
                .configuration(name)
                .map_err(|e| from_plan(e, "--scene"))?;
        }
        let known = WireSpec::preset(KNOWN_WIRE)
            .ok_or_else(|| LabError::bad_input(format!("no preset {KNOWN_WIRE}")))?;
        for (count, what) in [
            (self.calibration_configs, "calibration configurations"),
            (self.shape_configs, "shape configurations"),
        ] {
            if count == 0 {
                return Err(LabError::bad_input(format!("{what} 0: give at least 1")));
            }
        }
        Ok(Inputs {
            wire,
            setup,
            scene,
            scene_name,
            known,
            seed: self.seed,
            noise: self.noise,
            calibration_configs: self.calibration_configs,
            shape_configs: self.shape_configs,
        })
    }
}

/// A finished demo.
#[derive(Debug, Clone)]
pub struct DemoRun {
    /// `summary.json`'s body (after the run header).
    pub summary: DemoSummary,
    /// `timings.json`.
    pub timings: DemoTimings,
}

/// Runs the demo's five phases into `folder` (see the module docs for what it writes), then
/// its page, reporting each phase to `progress`; returns the summary and timings for the
/// caller to write (it does not finish the folder).
///
/// # Errors
/// Bad input for bad settings ([`DemoParams::check`]); no answer when a phase finds none (no
/// usable calibration, identification, shape, plan or tracking start) or a figure cannot be
/// drawn; I/O errors writing the folder.
pub fn run(
    params: &DemoParams,
    folder: &ResultsFolder,
    progress: &mut dyn DemoProgress,
) -> Result<DemoRun, LabError> {
    let total = Instant::now();
    let inputs = params.inputs()?;
    let (calibration, learnt, calibrate_s) = sense::calibrate(&inputs, folder, progress)?;
    let (identification, model, identify_s) = sense::identify(&inputs, &learnt, progress)?;
    let (shape, first, shape_s) = sense::shape(&inputs, (&learnt, model), folder, progress)?;
    let planned = steer::plan(&inputs, &model, &identification, progress)?;
    let chosen = planned.chosen;
    let candidate_plan_ms = chosen.choice.as_ref().map(|_| chosen.candidate_plan_ms);
    let waypoints = chosen.waypoints;
    let (tracking, track_s) = steer::track(
        &inputs,
        (&learnt, &planned.controller_model),
        &waypoints,
        folder,
        progress,
    )?;
    let wire = &inputs.wire;
    let summary = DemoSummary {
        wire: WireTruth {
            name: wire.name.clone(),
            c: wire.c,
            length: wire.length,
            linear_density: linear_density(wire),
        },
        calibration,
        identification,
        shape,
        plan: planned.out,
        tracking,
    };
    let timings = DemoTimings {
        calibrate_s,
        identify_s,
        shape_s,
        plan_s: planned.seconds,
        candidate_plan_ms,
        track_s,
        total_s: total.elapsed().as_secs_f64(),
    };
    let drawn = page::Drawn {
        scene: &inputs.scene,
        waypoints: &waypoints,
        shape: first.as_ref(),
    };
    page::write(folder, &summary, &drawn)?;
    Ok(DemoRun { summary, timings })
}
