//! `ftwire demo`: the whole system at work in the simulator, the README's first command.
//!
//! 1. **Calibrate** the F/T sensor on the known wire ([`KNOWN_WIRE`]): F/T and motion capture
//!    over [`CALIBRATION_CONFIGS`] configurations, labels by shape fitting with the loaded
//!    model, the network trained on them (as `ftwire experiment calibrate`).
//! 2. **Identify** the wire of `--wire`, whose stiffness, length and weight the demo is not
//!    told: the library's identification motion from a random start, three samples through
//!    the learnt calibration, the loaded model under the known gravity (as
//!    `ftwire experiment identify`, one trial).
//! 3. **Shape from F/T**: the identified model's shape from `ã` alone at
//!    [`SHAPE_CONFIGS`] configurations of `A_free`, against the simulator's true wire.
//! 4. **Plan** through the scene (`--scene`, default the shipped 50 mm passage,
//!    `scenes/passage.toml`) with RRT* in `A_free` for the identified wire, a fixed iteration
//!    budget (the same path on any machine), resampled into waypoints; under `increment` and
//!    `absolute` noise the waypoints whose landings come closer than 15 mm to a box are first
//!    moved away from it (`plan.polish`, as `ftwire experiment passage`).
//! 5. **Track** the plan in the simulator with the scene's obstacles (execution noise of
//!    `--noise-model`, `offset` by default: a real robot's calibration error): closed loop with the identified loaded model and the
//!    collision detector armed (calibrated on a rehearsal away from the obstacles), then once
//!    open loop for contrast; each scored on the true wire (touched an obstacle, final error,
//!    shape against the plan at each waypoint).
//!
//! Results folder (`--out`, default `results/demo`, written whole or not at all):
//! `summary.json` (run header, then `wire`, `calibration`, `identification`, `shape`, `plan`,
//! `tracking`; the same for the same seed), `timings.json` (each phase's wall time, and each
//! plan candidate's when the plan was chosen among them),
//! `calibration.json` (the weights), `shape.{png,svg}` (the estimated and the true wire of the
//! first configuration), `tracking.{png,svg}` (the scene's boxes and the true wire at each
//! rest of the closed-loop run), `report.html` (the numbers, those figures and 3-D views of
//! the runs, one self-contained page; [`page`]).

use std::io::IsTerminal as _;
use std::time::{Duration, Instant};

use ftwire_core::WireParams;
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::identify::MotionPlan;
use ftwire_estimate::shape::{DEFAULT_METRIC_SAMPLES, ShapeEstimator, centreline_distance};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_lab::error::{LabError, from_estimate, from_plan, from_rod};
use ftwire_lab::experiment::calibration::{self, KNOWN_WIRE, rig_seed};
use ftwire_lab::experiment::rig::{measure, pipeline, place_wire, tare, true_centreline};
use ftwire_lab::experiment::{Gravity, ModelKind};
use ftwire_lab::header::RunHeader;
use ftwire_lab::identify::{
    Map, Protocol, REST_SAMPLES as IDENTIFY_REST_SAMPLES, ResidualParams, flag_name,
    linear_density, loaded_config, record_trial, run_identification, truth,
};
use ftwire_lab::results::OutGuard;
use ftwire_lab::setup::SimSetup;
use ftwire_lab::tracking::{Attempt, PlanFailure, Tracking, plan_policy, reexpress};
use ftwire_lab::wire::WireSpec;
use ftwire_plan::Scene;
use ftwire_plan::{ChoiceOut, PolishOut};
use ftwire_report::{Chart3d, SeriesKind};
use ftwire_rod::Rod;
use ftwire_rod::sampling::Sampler;
use indicatif::{ProgressBar, ProgressStyle};
use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use crate::cli::demo::DemoArgs;

mod page;

/// Configurations of the calibration phase: as many as `experiment calibrate` collects by
/// default (`ftwire_lab::experiment::calibration::DEFAULT_SAMPLES`), so that the demo's calibrated
/// map is as good as the experiment's (the summary reports its test error).
pub const CALIBRATION_CONFIGS: usize = 600;

/// Samples the identification phase identifies from (the paper's smallest useful count).
pub const IDENTIFY_SAMPLES: usize = 3;

/// Configurations of the shape phase.
pub const SHAPE_CONFIGS: usize = 5;

/// The demo's phases, in order (progress lines and bars are numbered by them).
const PHASES: usize = 5;

/// The default scene, shipped in the repository and built into the binary.
const PASSAGE: &str = ftwire_lab::scene::PASSAGE;

/// `summary.json`'s body.
#[derive(Debug, Serialize)]
struct Summary {
    /// The wire identified (the truth, which only the simulator was given).
    wire: WireTruth,
    calibration: CalibrationOut,
    identification: IdentificationOut,
    shape: ShapeOut,
    plan: PlanOut,
    tracking: TrackingOut,
}

#[derive(Debug, Serialize)]
struct PlanOut {
    scene: String,
    iterations: usize,
    nodes: usize,
    /// Cost and length of the path in normalised `A`.
    cost: f64,
    /// Smallest clearance of the wire from an obstacle along the path \[m\].
    min_clearance: f64,
    waypoints: usize,
    /// The clearance polish of the tracked waypoints (`ftwire_plan::polish_waypoints`), under the
    /// noises that scatter every landing (`increment`, `absolute`); `null` otherwise, where
    /// the loop converges onto the plan.
    polish: Option<PolishOut>,
    /// How the plan was chosen among `ftwire_plan::PLAN_CANDIDATES` under the same noises
    /// (`ftwire_plan::choose_plan`); `null` otherwise.
    choice: Option<ChoiceOut>,
}

#[derive(Debug, Serialize)]
struct TrackingOut {
    noise_model: &'static str,
    /// The collision detector's threshold on its residual (`ftwire_control::collision`).
    detector_threshold: f64,
    closed_loop: Attempt,
    open_loop: Attempt,
}

#[derive(Debug, Serialize)]
struct WireTruth {
    name: String,
    c: [f64; 3],
    length: f64,
    linear_density: f64,
}

#[derive(Debug, Serialize)]
struct CalibrationOut {
    wire: String,
    configurations: usize,
    /// Relative error of `ã` on the test split, torque and force: raw (mounting only) and
    /// calibrated.
    raw_torque_rel: f64,
    raw_force_rel: f64,
    calibrated_torque_rel: f64,
    calibrated_force_rel: f64,
}

#[derive(Debug, Serialize)]
struct IdentificationOut {
    samples: usize,
    /// `(c1, c2, c3, L)` estimated.
    estimate: [f64; 4],
    /// One standard deviation of each.
    std: [f64; 4],
    /// `(estimate − truth) / truth` of each.
    relative_error: [f64; 4],
    linear_density: Option<f64>,
    linear_density_relative_error: Option<f64>,
    chi2_per_dof: f64,
    /// Why the estimate is not trusted (`null`: identified).
    flag: Option<&'static str>,
}

#[derive(Debug, Serialize)]
struct ShapeOut {
    /// Configurations estimated (of [`SHAPE_CONFIGS`]; a placement the simulator cannot hold
    /// is skipped).
    configurations: usize,
    /// Mean distance between the estimated and the true centreline \[mm\], per configuration.
    mean_mm: Vec<f64>,
    /// Their mean \[mm\].
    mean_mm_overall: f64,
}

/// `timings.json`: wall time of each phase \[s\].
#[derive(Debug, Serialize)]
struct Timings {
    calibrate_s: f64,
    identify_s: f64,
    shape_s: f64,
    plan_s: f64,
    /// Each plan candidate's planning alone \[ms\] when the plan was chosen among
    /// candidates (`plan.choice` in the summary), `null` otherwise.
    candidate_plan_ms: Option<Vec<Option<f64>>>,
    track_s: f64,
    total_s: f64,
}

/// Progress of one phase: a bar on a terminal, plain lines otherwise.
struct Phase {
    bar: Option<ProgressBar>,
    label: String,
    start: Instant,
}

impl Phase {
    fn start(index: usize, name: &str, steps: u64) -> Self {
        let label = format!("[{index}/{PHASES}] {name}");
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = ProgressBar::new(steps);
            let style = ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} {elapsed}")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> ");
            bar.set_style(style);
            bar.set_prefix(label.clone());
            bar.enable_steady_tick(Duration::from_millis(200));
            bar
        });
        if bar.is_none() {
            eprintln!("{label} ...");
        }
        Self {
            bar,
            label,
            start: Instant::now(),
        }
    }

    fn set(&self, position: usize) {
        if let Some(bar) = &self.bar {
            bar.set_position(position as u64);
        }
    }

    /// Ends the phase with a one-line result; returns its wall time \[s\].
    fn finish(self, result: &str) -> f64 {
        let seconds = self.start.elapsed().as_secs_f64();
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        eprintln!("{}: {result} ({seconds:.1} s)", self.label);
        seconds
    }
}

/// The demo's inputs, read and checked before any work: a bad one is exit 2 at once.
struct Inputs {
    wire: WireSpec,
    setup: SimSetup,
    scene: Scene,
    scene_name: String,
    known: WireSpec,
    folder: ftwire_lab::results::ResultsFolder,
}

fn inputs(args: &DemoArgs) -> Result<Inputs, LabError> {
    let wire = WireSpec::load(&args.wire).map_err(|e| LabError::bad_input(e.to_string()))?;
    let setup = args.setup.load()?;
    let (scene, scene_name) = match &args.scene.file {
        Some(path) => (
            Scene::load(path).map_err(|e| from_plan(e, "--scene"))?,
            path.display().to_string(),
        ),
        None => (
            Scene::from_toml(PASSAGE, "scenes/passage.toml")
                .map_err(|e| from_plan(e, "the built-in passage scene"))?,
            "scenes/passage.toml".to_owned(),
        ),
    };
    // The plan of phase 4 runs from the scene's `start` to its `goal`.
    for name in ["start", "goal"] {
        scene
            .configuration(name)
            .map_err(|e| from_plan(e, "--scene"))?;
    }
    let known = WireSpec::preset(KNOWN_WIRE)
        .ok_or_else(|| LabError::bad_input(format!("no preset {KNOWN_WIRE}")))?;
    let inputs = OutGuard::default()
        .input("--wire", &args.wire)
        .input_opt("--scene", args.scene.path())
        .input_opt("--sensor", args.setup.sensor.as_deref())
        .input_opt("--rig", args.setup.rig.as_deref());
    let folder = args.results.open("demo", inputs)?;
    Ok(Inputs {
        wire,
        setup,
        scene,
        scene_name,
        known,
        folder,
    })
}

/// Phase 1: the calibration on the known wire; its summary, the weights (also written to the
/// folder) and the phase's seconds.
fn calibrate(
    inputs: &Inputs,
    gravity: Gravity,
    seed: u64,
) -> Result<(CalibrationOut, Calibration, f64), LabError> {
    let Inputs {
        known,
        setup,
        folder,
        ..
    } = inputs;
    let phase = Phase::start(1, "calibrate the F/T sensor on the known wire", 300);
    let run = calibration::run(
        known,
        (gravity, ModelKind::Loaded),
        setup,
        CALIBRATION_CONFIGS,
        seed,
        |k| phase.set(k + 1),
    )?;
    let test = &run.summary;
    let calibration_out = CalibrationOut {
        wire: known.name.clone(),
        configurations: run.samples.len(),
        raw_torque_rel: test.raw.torque_rel,
        raw_force_rel: test.raw.force_rel,
        calibrated_torque_rel: test.calibrated.torque_rel,
        calibrated_force_rel: test.calibrated.force_rel,
    };
    folder.write(
        "calibration.json",
        run.calibration
            .to_json()
            .map_err(|e| from_estimate(e, "the calibration weights"))?,
    )?;
    let calibrate_s = phase.finish(&format!(
        "{} on {} configurations: test error torque {:.2} %, force {:.2} % (raw {:.2} %, {:.2} %)",
        known.name,
        calibration_out.configurations,
        100.0 * calibration_out.calibrated_torque_rel,
        100.0 * calibration_out.calibrated_force_rel,
        100.0 * calibration_out.raw_torque_rel,
        100.0 * calibration_out.raw_force_rel,
    ));
    Ok((calibration_out, run.calibration, calibrate_s))
}

/// Phase 4: the plan through the scene for the identified wire, chosen among candidates
/// where the noise scatters every landing; returns what the summary keeps, the chosen plan,
/// the controller's model and the phase's seconds.
fn plan(
    inputs: &Inputs,
    args: &DemoArgs,
    model: &KirchhoffModel,
    identification: &IdentificationOut,
    seed: u64,
) -> Result<(PlanOut, ftwire_plan::Chosen, KirchhoffModel, f64), LabError> {
    let Inputs {
        scene, scene_name, ..
    } = inputs;
    let gravity = Gravity::On;
    let phase = Phase::start(4, "plan through the passage", 1);
    // The controller's model: the identified one, with gravity in the base clamp frame. Where
    // the plan keeps a distance from the folds (under `increment` and `absolute`), it keeps it
    // on this model's, as `experiment passage` does.
    let g_clamp = scene.base.rotation.inverse() * gravity.vector();
    let weight = summary_density(identification) * g_clamp;
    let controller_model = model
        .with_weight_per_length(weight)
        .map_err(|e| from_estimate(e, "the identified wire's weight"))?;
    // The planner checks shapes with the identified wire's weightless model, as the scene's
    // configurations are the paper model's: with the loaded model's shapes, the fixed
    // iteration budget can find no path for some identified wires. The wire sags a few
    // millimetres from those shapes; the controller tracks the configurations with the
    // loaded model.
    let noise = args
        .noise
        .model_or(crate::cli::experiment::NoiseModelArg::Offset);
    let identified = Rod::new(*model.wire());
    // Under the noises that scatter every landing, the best of `ftwire_plan::PLAN_CANDIDATES`
    // plans by their expected touches, each with its tight waypoints polished away from the
    // boxes (as `experiment passage` does). The plan's poses take the loaded model's
    // configurations and shapes: the controller steers to where the plan puts the grippers,
    // and the shape error is against the wire that sags.
    let plans = plan_policy(noise);
    let chosen = ftwire_plan::choose_plan(
        scene,
        &identified,
        controller_model.rod(),
        plans.validity_tracked(controller_model.rod()),
        &plans,
        seed,
        ftwire_plan::PLAN_CANDIDATES,
        plans.polishes(),
        |planned| {
            reexpress(&planned.waypoints, &controller_model, &scene.base).map_err(PlanFailure)
        },
    )?;
    let planned = &chosen.planned;
    let plan_out = PlanOut {
        scene: scene_name.clone(),
        iterations: planned.plan.iterations,
        nodes: planned.plan.nodes,
        cost: planned.plan.path.cost,
        min_clearance: planned.plan.path.min_clearance(),
        waypoints: planned.waypoints.len(),
        polish: chosen.polish,
        choice: chosen.choice.clone(),
    };
    let chosen_of = plan_out.choice.as_ref().map_or(String::new(), |c| {
        format!(
            ", plan {} of {} by expected touches",
            c.chosen + 1,
            c.candidates
        )
    });
    let plan_s = phase.finish(&format!(
        "path of length {:.2} (normalised A), {} waypoints, closest approach {:.1} mm{chosen_of}",
        plan_out.cost,
        plan_out.waypoints,
        1e3 * plan_out.min_clearance
    ));

    Ok((plan_out, chosen, controller_model, plan_s))
}

/// Phase 5: the plan tracked closed loop, then open loop, under `noise`; returns what the
/// summary keeps and the phase's seconds.
fn track(
    inputs: &Inputs,
    args: &DemoArgs,
    learnt: &Calibration,
    controller_model: &KirchhoffModel,
    waypoints: &[ftwire_plan::Waypoint],
    seed: u64,
) -> Result<(TrackingOut, f64), LabError> {
    let Inputs {
        wire,
        setup,
        scene,
        folder,
        ..
    } = inputs;
    let gravity = Gravity::On;
    let noise = args
        .noise
        .model_or(crate::cli::experiment::NoiseModelArg::Offset);
    let phase = Phase::start(5, "track the plan, closed then open loop", 3);
    let tracking = Tracking {
        wire,
        gravity,
        scene,
        calibration: learnt,
        setup,
        noise,
        seed,
        // The paper's gain, the policy's stops.
        policy: ftwire_control::TrackingPolicy {
            gain: ftwire_control::ControlParams::default().gain,
            ..ftwire_control::TrackingPolicy::for_noise(noise)
        },
        arms: true,
        bias_observer: true,
    };
    let detector = tracking.detector(controller_model, waypoints)?;
    phase.set(1);
    let closed = tracking.closed_loop(controller_model, waypoints, detector, 2)?;
    phase.set(2);
    let open = tracking.open_loop(controller_model, waypoints, 2)?;
    let chart = scene_chart(scene, &closed);
    chart
        .write(folder.dir(), "tracking")
        .map_err(|e| LabError::no_answer(format!("figure tracking: {e}")))?;
    let verdict = |a: &Attempt| {
        format!(
            "{} ({} moves{}, final error {:.3}, shape {:.1} mm at the goal)",
            a.verdict(),
            a.steps,
            match (a.touched, a.detected) {
                (true, true) => ", touched an obstacle, detected",
                (true, false) => ", touched an obstacle",
                (false, true) if a.completed => ", a false alarm, retreated",
                (false, true) => ", stopped by a false alarm",
                (false, false) => "",
            },
            a.final_error,
            a.shape_mm.last().copied().unwrap_or(f64::NAN),
        )
    };
    let track_s = phase.finish(&format!(
        "closed loop: {}; open loop: {}",
        verdict(&closed),
        verdict(&open)
    ));
    let tracking_out = TrackingOut {
        noise_model: noise.name(),
        detector_threshold: detector.threshold(),
        closed_loop: closed,
        open_loop: open,
    };

    Ok((tracking_out, track_s))
}

/// Runs the demo: the five phases in turn, then the summary, the page and the folder.
pub fn run(args: DemoArgs) -> Result<(), LabError> {
    let total = Instant::now();
    let seed = args.seed.seed;
    let inputs = inputs(&args)?;
    let gravity = Gravity::On;
    let (calibration_out, learnt, calibrate_s) = calibrate(&inputs, gravity, seed)?;
    // 2. Identification of the unknown wire.
    let phase = Phase::start(2, "identify the wire from F/T", IDENTIFY_SAMPLES as u64);
    let (identification, model) = identify(&inputs.wire, &learnt, &inputs.setup, seed)?;
    phase.set(IDENTIFY_SAMPLES);
    let err = &identification.relative_error;
    let identify_s = phase.finish(&format!(
        "c = ({:.4}, {:.4}, {:.4}) N·m², L = {:.4} m against the truth ({:.4}, {:.4}, {:.4}), \
         {:.4}: errors {:.2} / {:.2} / {:.2} / {:.2} %{}",
        identification.estimate[0],
        identification.estimate[1],
        identification.estimate[2],
        identification.estimate[3],
        inputs.wire.c[0],
        inputs.wire.c[1],
        inputs.wire.c[2],
        inputs.wire.length,
        100.0 * err[0],
        100.0 * err[1],
        100.0 * err[2],
        100.0 * err[3],
        identification
            .flag
            .map_or_else(String::new, |f| format!(" (flagged: {f})")),
    ));

    // 3. Shape from F/T with the identified model.
    let phase = Phase::start(3, "estimate the shape from F/T", SHAPE_CONFIGS as u64);
    let (shape, first) = shapes(&inputs.wire, (&learnt, &inputs.setup), model, seed, |k| {
        phase.set(k)
    })?;
    if let Some((estimate, truth)) = &first {
        let chart = Chart3d::new(format!(
            "{}: shape from F/T against the truth",
            inputs.wire.name
        ))
        .with_curve("truth (simulator)", truth.clone(), SeriesKind::Line)
        .with_curve("estimate from F/T", estimate.clone(), SeriesKind::Line);
        chart
            .write(inputs.folder.dir(), "shape")
            .map_err(|e| LabError::no_answer(format!("figure shape: {e}")))?;
    }
    let shape_s = phase.finish(&format!(
        "{} configurations, mean distance to the true wire {:.2} mm",
        shape.configurations, shape.mean_mm_overall
    ));

    let (plan_out, chosen, controller_model, plan_s) =
        plan(&inputs, &args, &model, &identification, seed)?;
    let candidate_plan_ms = chosen.choice.as_ref().map(|_| chosen.candidate_plan_ms);
    let waypoints = chosen.waypoints;
    let (tracking_out, track_s) =
        track(&inputs, &args, &learnt, &controller_model, &waypoints, seed)?;

    let summary = Summary {
        wire: WireTruth {
            name: inputs.wire.name.clone(),
            c: inputs.wire.c,
            length: inputs.wire.length,
            linear_density: linear_density(&inputs.wire),
        },
        calibration: calibration_out,
        identification,
        shape,
        plan: plan_out,
        tracking: tracking_out,
    };
    let timings = Timings {
        calibrate_s,
        identify_s,
        shape_s,
        plan_s,
        candidate_plan_ms,
        track_s,
        total_s: total.elapsed().as_secs_f64(),
    };
    let drawn = page::Drawn {
        scene: &inputs.scene,
        waypoints: &waypoints,
        shape: first.as_ref(),
    };
    page::write(&inputs.folder, &summary, &drawn)?;
    let header = RunHeader::new("demo", Some(seed), &args)?;
    let target = inputs.folder.finish_run(&header, &summary, &timings)?;
    println!(
        "demo done in {:.0} s; results in {}",
        timings.total_s,
        target.display()
    );
    Ok(())
}

/// Phase 2: one identification trial of `wire` through the learnt calibration; returns the
/// result and the identified (loaded) model.
fn identify(
    wire: &WireSpec,
    learnt: &Calibration,
    setup: &SimSetup,
    seed: u64,
) -> Result<(IdentificationOut, KirchhoffModel), LabError> {
    let protocol = Protocol {
        plan: MotionPlan {
            moves: IDENTIFY_SAMPLES - 1,
            ..MotionPlan::default()
        },
        rest_samples: IDENTIFY_REST_SAMPLES,
    };
    let samples = record_trial(
        wire,
        Gravity::On,
        setup,
        Map::Learnt(learnt),
        seed,
        0,
        &protocol,
    )?;
    let pairs: Vec<_> = samples.iter().map(|s| (s.a, s.b)).collect();
    let config = loaded_config(&ResidualParams::default().config()?, Gravity::On);
    let estimate = run_identification(&pairs, &config, seed)?;
    let truth = truth(wire);
    let eta = [estimate.c[0], estimate.c[1], estimate.c[2], estimate.length];
    let std = [
        estimate.c_std[0],
        estimate.c_std[1],
        estimate.c_std[2],
        estimate.length_std,
    ];
    let relative_error = std::array::from_fn(|j| (eta[j] - truth[j]) / truth[j]);
    let lambda = linear_density(wire);
    // The identified model: the wire's radius is measured (calipers), not identified; it only
    // enters the self-contact test.
    let params = WireParams::new(estimate.c, estimate.length, wire.radius)
        .map_err(|e| LabError::no_answer(format!("the identified wire: {e}")))?;
    let weight = estimate.linear_density.unwrap_or(0.0) * Gravity::On.vector();
    let model = KirchhoffModel::new(params)
        .with_weight_per_length(weight)
        .map_err(|e| from_estimate(e, "the identified wire's weight"))?;
    let out = IdentificationOut {
        samples: pairs.len(),
        estimate: eta,
        std,
        relative_error,
        linear_density: estimate.linear_density,
        linear_density_relative_error: estimate.linear_density.map(|l| (l - lambda) / lambda),
        chi2_per_dof: estimate.chi2_per_dof,
        flag: flag_name(estimate.unidentified.as_ref()),
    };
    Ok((out, model))
}

/// A centreline as plotted points.
type Points = Vec<[f64; 3]>;

/// Phase 3: the identified model's shape from `ã` at configurations of `A_free` of the true
/// wire; returns the errors and the first configuration's estimated and true centrelines.
fn shapes(
    wire: &WireSpec,
    (learnt, setup): (&Calibration, &SimSetup),
    model: KirchhoffModel,
    seed: u64,
    mut progress: impl FnMut(usize),
) -> Result<(ShapeOut, Option<(Points, Points)>), LabError> {
    let params = wire
        .wire_params()
        .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?;
    let rod = Rod::new(params);
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5ba9e);
    let sampler = Sampler::default();
    let mut estimator = ShapeEstimator::new(model);
    let mut mean_mm = Vec::with_capacity(SHAPE_CONFIGS);
    let mut first = None;
    for k in 0..SHAPE_CONFIGS {
        progress(k);
        let placed = sampler
            .sample_free(&rod, &mut rng)
            .map_err(|e| from_rod(e, "sampling A_free of the wire"))?;
        let config = setup.rig_config(rig_seed(seed, k));
        let Ok(mut rig) = place_wire(wire, Gravity::On, &placed, config) else {
            continue;
        };
        let tared = pipeline(tare(&mut rig)?, learnt.clone())?;
        let Ok(measured) = measure(&mut rig, &tared) else {
            continue;
        };
        estimator.reset();
        let Ok(estimate) = estimator.estimate(&measured.a) else {
            continue;
        };
        let truth = true_centreline(&rig);
        let positions = &estimate.shape.positions;
        let distance = centreline_distance(positions, &truth, DEFAULT_METRIC_SAMPLES)
            .map_err(|e| from_estimate(e, "the shape error"))?;
        mean_mm.push(1e3 * distance);
        if first.is_none() {
            let points = |v: &[Vector3<f64>]| v.iter().map(|p| [p.x, p.y, p.z]).collect();
            first = Some((points(positions), points(&truth)));
        }
    }
    progress(SHAPE_CONFIGS);
    if mean_mm.is_empty() {
        return Err(LabError::no_answer(format!(
            "no configuration of {} could be placed and estimated",
            wire.name
        )));
    }
    let overall = mean_mm.iter().sum::<f64>() / mean_mm.len() as f64;
    Ok((
        ShapeOut {
            configurations: mean_mm.len(),
            mean_mm,
            mean_mm_overall: overall,
        },
        first,
    ))
}

/// The identified linear density (0 when the model did not identify one).
fn summary_density(identification: &IdentificationOut) -> f64 {
    identification.linear_density.unwrap_or(0.0)
}

/// Rests of the closed-loop run drawn in `tracking.png`.
const FIGURE_RESTS: usize = 7;

/// The scene's boxes (their twelve edges) and the true wire at [`FIGURE_RESTS`] rests of
/// `attempt`, evenly spaced from the first to the last.
fn scene_chart(scene: &Scene, attempt: &Attempt) -> Chart3d {
    let mut chart = Chart3d::new("the passage: the true wire, closed loop");
    for b in &scene.boxes {
        chart = chart.with_curve(
            b.name.clone(),
            ftwire_lab::scene::box_outline(b),
            SeriesKind::Line,
        );
    }
    // A few rests, evenly spaced, and the last: a readable legend.
    let n = attempt.centrelines.len();
    let shown = FIGURE_RESTS.min(n);
    for j in 0..shown {
        let k = if shown > 1 {
            j * (n - 1) / (shown - 1)
        } else {
            0
        };
        if let Some(centreline) = attempt.centrelines.get(k) {
            chart = chart.with_curve(
                format!("after move {}", k + 1),
                centreline.clone(),
                SeriesKind::Line,
            );
        }
    }
    chart
}
