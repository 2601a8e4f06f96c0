//! `ftwire ros2 <node>`: the nodes of [`ftwire_ros2::node`]. This command reads the
//! arguments, sets the stop flag on Ctrl-C (SIGINT, SIGTERM, SIGHUP), logs to stderr, and
//! prints the node's summary as one JSON line on stdout.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use ftwire_control::{BiasObserverParams, ControlParams, NoiseParams};
use ftwire_lab::config::sensor::DataSheetSpec;
use ftwire_lab::error::LabError;
use ftwire_lab::plan::{PlanParams, PlanWireParams};
use ftwire_lab::wire::WireSpec;
use ftwire_ros2::node::control::ControlNodeParams;
use ftwire_ros2::node::estimate::{EstimateNodeParams, Record};
use ftwire_ros2::node::identify::IdentifyNodeParams;
use ftwire_ros2::node::observe::{ObserveParams, RestParams};
use ftwire_ros2::node::robot::RobotParams;
use ftwire_ros2::node::sigma::ErrorBars;
use ftwire_ros2::node::sim::SimNodeParams;
use ftwire_ros2::node::tf::{SimTfFrames, TfFrames};
use ftwire_ros2::node::{NodeError, NodeSettings};
use ftwire_sim::BoxObstacle;
use nalgebra::Vector6;
use serde::Serialize;

use crate::cli::ros2::{
    ControlNodeArgs, EstimateNodeArgs, IdentifyNodeArgs, NodeArgs, ObserveArgs, RobotArgs,
    Ros2Args, Ros2Node, SimNodeArgs,
};

/// Runs the chosen node until `--duration` ends or Ctrl-C.
pub fn run(args: Ros2Args) -> Result<(), LabError> {
    let stop = stop_on_signals();
    let mut log = |line: &str| eprintln!("{line}");
    match args.node {
        Ros2Node::Sim(args) => {
            let (params, settings) = sim_params(&args)?;
            let summary = ftwire_ros2::node::sim::run(&params, settings, &stop, &mut log)
                .map_err(from_node)?;
            print_line(&summary)
        }
        Ros2Node::Estimate(args) => {
            let (params, settings) = estimate_params(&args)?;
            let summary = ftwire_ros2::node::estimate_loop::run(&params, settings, &stop, &mut log)
                .map_err(from_node)?;
            print_line(&summary)
        }
        Ros2Node::Identify(args) => {
            let (params, settings) = identify_params(&args)?;
            let summary = ftwire_ros2::node::identify::run(&params, settings, &stop, &mut log)
                .map_err(from_node)?;
            print_line(&summary)
        }
        Ros2Node::Control(args) => {
            let (params, settings) = control_params(&args, &mut log)?;
            let summary = ftwire_ros2::node::control::run(&params, settings, &stop, &mut log)
                .map_err(from_node)?;
            print_line(&summary)
        }
    }
}

/// A flag set on SIGINT, SIGTERM or SIGHUP.
fn stop_on_signals() -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    #[cfg(unix)]
    for signal in [
        signal_hook::consts::SIGINT,
        signal_hook::consts::SIGTERM,
        signal_hook::consts::SIGHUP,
    ] {
        if let Err(e) = signal_hook::flag::register(signal, Arc::clone(&stop)) {
            eprintln!("warning: cannot catch signal {signal} ({e}): Ctrl-C ends without a summary");
        }
    }
    stop
}

fn from_node(error: NodeError) -> LabError {
    match error {
        NodeError::Lab(e) => e,
        NodeError::BadSetting { .. } => LabError::bad_input(error.to_string()),
        NodeError::Incomplete(message) => LabError::no_answer(message),
        e => LabError::no_answer(e.to_string()),
    }
}

fn print_line(summary: &impl Serialize) -> Result<(), LabError> {
    let line = serde_json::to_string(summary)
        .map_err(|e| LabError::no_answer(format!("the summary: {e}")))?;
    println!("{line}");
    Ok(())
}

fn settings(args: &NodeArgs) -> Result<NodeSettings, LabError> {
    let domain_id = match args.domain_id {
        Some(id) => id,
        None => match std::env::var("ROS_DOMAIN_ID") {
            Ok(text) if !text.trim().is_empty() => text.trim().parse().map_err(|_| {
                LabError::bad_input(format!(
                    "ROS_DOMAIN_ID={text:?}: give a DDS domain from 0 to 232, or --domain-id"
                ))
            })?,
            _ => 0,
        },
    };
    let settings = NodeSettings {
        domain_id,
        duration: args.duration,
    };
    settings.validate().map_err(from_node)?;
    Ok(settings)
}

fn wire(given: &str) -> Result<WireSpec, LabError> {
    WireSpec::load(given).map_err(|e| LabError::bad_input(format!("--wire: {e}")))
}

fn sim_params(args: &SimNodeArgs) -> Result<(SimNodeParams, NodeSettings), LabError> {
    let settings = settings(&args.node)?;
    let wire = wire(&args.wire)?;
    let start = match &args.start {
        Some(a) => Vector6::from(a.0),
        None => {
            let params = wire
                .wire_params()
                .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?;
            ftwire_rod::from_normalised(&params, &Vector6::new(0.0, 1.0, 0.5, -1.0, 0.5, 0.0))
        }
    };
    let params = SimNodeParams {
        wire,
        gravity: args.gravity,
        start,
        setup: args.setup.load()?,
        seed: args.seed.seed,
        rate: args.rate,
        pose_rate: args.pose_rate,
        marker_rate: args.marker_rate,
        tare_samples: args.tare_samples,
        wait_subscriber: args.wait_subscriber,
        tf: SimTfFrames {
            world: args.tf_world_frame.clone(),
            base: args.tf_base_frame.clone(),
            tip: args.tf_tip_frame.clone(),
        },
        obstacles: args
            .boxes
            .iter()
            .map(|b| {
                let [cx, cy, cz, hx, hy, hz] = b.0;
                BoxObstacle::new(
                    ftwire_core::Pose::translation(cx, cy, cz),
                    nalgebra::Vector3::new(hx, hy, hz),
                )
                .map_err(|e| LabError::bad_input(format!("--box {:?}: {e}", b.0)))
            })
            .collect::<Result<_, _>>()?,
    };
    Ok((params, settings))
}

fn estimate_params(
    args: &EstimateNodeArgs,
) -> Result<(EstimateNodeParams, NodeSettings), LabError> {
    let settings = settings(&args.node)?;
    let map = ftwire_lab::log::raw_map(args.calibration.path(), Some(args.mounting.load()?))?;
    let params = EstimateNodeParams {
        wire: wire(&args.wire)?,
        map,
        gravity_in_clamp: args.gravity.given(),
        points: args.points,
        qos: args.qos.qos(),
        tare: args.tare,
        window: args.window,
        rate: args.rate,
        wrench_topic: args.wrench_topic.clone(),
        tip_pose_topic: args.tip_pose_topic.clone(),
        tf: match (&args.base_frame, &args.tip_frame) {
            (Some(base), Some(tip)) => Some(TfFrames {
                base: base.clone(),
                tip: tip.clone(),
                stale: args.tf_stale,
            }),
            (None, None) => None,
            _ => {
                return Err(LabError::bad_input(
                    "--base-frame and --tip-frame go together: give both, or neither (the tip \
                     pose then comes from --tip-pose-topic)",
                ));
            }
        },
        truth_topic: args.truth_topic.clone(),
        contact_miss: args.contact_miss.map(|mm| 1e-3 * mm),
        observe: observe_params(&args.observe, args.tare)?,
        error_bars: error_bars(args)?,
        record: args.record.clone().map(|path| Record {
            path,
            overwrite: args.force,
        }),
    };
    Ok((params, settings))
}

/// `ftwire ros2 estimate`'s error bars: `--sensor`'s data sheet with the window and the tare
/// and `--gain-error` (`ftwire_lab::identify::data_sheet_noise`), and
/// `--model-error`; `None` with `--error-bars off`.
fn error_bars(args: &EstimateNodeArgs) -> Result<Option<ErrorBars>, LabError> {
    if !args.error_bars.on() {
        return Ok(None);
    }
    let sensor =
        ftwire_lab::setup::SensorSpec::load(args.observe.sensor.as_deref().unwrap_or("distorted"))
            .map_err(|e| LabError::bad_input(format!("--sensor: {e}")))?;
    let mount = args
        .mounting
        .load()?
        .mounting()
        .map_err(|e| LabError::bad_input(format!("--mounting: {e}")))?;
    let noise = ftwire_lab::identify::data_sheet_noise(
        &ftwire_lab::setup::sensor::data_sheet(&sensor.config),
        &mount,
        (args.window, args.tare),
        args.gain_error.map(|pct| 1e-2 * pct),
    )?;
    let model_error = args
        .model_error
        .map(ftwire_estimate::shape::ModelError::new)
        .transpose()
        .map_err(|e| LabError::bad_input(format!("--model-error: {e}")))?;
    Ok(Some(ErrorBars { noise, model_error }))
}

/// The rests, and the bias observer's settings for `--sensor`'s data sheet, a tare of
/// `tare` samples and `--pose-error` ([`ftwire_control::BiasObserverParams::for_sensor`]).
fn observe_params(args: &ObserveArgs, tare: usize) -> Result<ObserveParams, LabError> {
    let sheet = match args.sensor.as_deref() {
        Some(given) => {
            DataSheetSpec::load(given)
                .map_err(|e| LabError::bad_input(format!("--sensor: {e}")))?
                .sheet
        }
        None => ftwire_lab::config::sensor::DEFAULT,
    };
    let bias_observer = args.bias_observer.on().then(|| {
        BiasObserverParams::for_sensor(
            &sheet,
            tare,
            args.pose_error.model(),
            &NoiseParams::default(),
        )
    });
    Ok(ObserveParams {
        rest: RestParams {
            position_tolerance: 1e-3 * args.rest_tolerance_mm,
            angle_tolerance: args.rest_tolerance_deg.to_radians(),
            dwell: args.rest_dwell,
            settle: args.rest_settle,
        },
        bias_observer: bias_observer.flatten(),
        calibration_moves: args.collision_calibration,
    })
}

fn robot_params(args: &RobotArgs, truth_topic: Option<String>) -> Result<RobotParams, LabError> {
    Ok(RobotParams {
        map: ftwire_lab::log::raw_map(args.calibration.path(), Some(args.mounting.load()?))?,
        qos: args.qos.qos(),
        tare: args.tare,
        rate: args.rate,
        rest_samples: args.rest_samples,
        settle_samples: args.settle_samples,
        reach_translation: 1e-3 * args.reach_mm,
        reach_rotation: args.reach_deg.to_radians(),
        move_timeout: args.move_timeout,
        wrench_topic: args.wrench_topic.clone(),
        tip_pose_topic: args.tip_pose_topic.clone(),
        target_topic: args.target_topic.clone(),
        truth_topic,
    })
}

fn identify_params(
    args: &IdentifyNodeArgs,
) -> Result<(IdentifyNodeParams, NodeSettings), LabError> {
    let settings = settings(&args.node)?;
    let mut config = args.settings.settings().config()?;
    if let Some(given) = &args.sensor {
        let sensor = ftwire_lab::setup::SensorSpec::load(given)
            .map_err(|e| LabError::bad_input(format!("--sensor: {e}")))?;
        let mount = args
            .robot
            .mounting
            .load()?
            .mounting()
            .map_err(|e| LabError::bad_input(format!("--mounting: {e}")))?;
        config.noise = args.settings.settings().with_noise_settings(
            ftwire_lab::experiment::rig::identification_noise_of(
                &sensor.config,
                &mount,
                args.robot.rest_samples,
                args.robot.tare,
            )
            .map_err(|e| e.context("--sensor"))?,
        )?;
    }
    let robot = robot_params(&args.robot, None)?;
    // The loaded model (the calibration's, or --gravity-in-clamp): the wire's weight
    // identified with c and L.
    if let Some(g) = ftwire_lab::log::model_gravity(&robot.map, args.robot.gravity.given())? {
        ftwire_rig::WireModelChoice::loaded(g)
            .map_err(|e| LabError::bad_input(format!("--gravity-in-clamp: {e}")))?;
        config.constraints.weight = Some(nalgebra::Vector3::from(g));
        config
            .validate()
            .map_err(|e| LabError::bad_input(format!("--gravity-in-clamp: {e}")))?;
    }
    let params = IdentifyNodeParams {
        robot,
        samples: args.samples,
        twist: args.twist.to_radians(),
        seed: args.seed.seed,
        config,
    };
    Ok((params, settings))
}

/// The goals of `ftwire ros2 control`: `--goal`, or the waypoints after the start of the path
/// planned in `--scene` as `ftwire plan` plans it.
fn goals(args: &ControlNodeArgs, log: &mut dyn FnMut(&str)) -> Result<Vec<Vector6<f64>>, LabError> {
    if let Some(goal) = &args.goal {
        return Ok(vec![Vector6::from(goal.0)]);
    }
    let plan = PlanParams {
        scene: args.scene.clone(),
        wire: PlanWireParams {
            wire: args.wire.clone(),
            ..PlanWireParams::default()
        },
        time_budget: args.time_budget,
        ..PlanParams::default()
    };
    let report = ftwire_lab::plan::run(&plan)?;
    log(&format!(
        "control: planned {} waypoints in {} ({:.2} s); steering along them from the second",
        report.waypoints.len(),
        report.scene,
        report.seconds
    ));
    report
        .waypoints
        .iter()
        .skip(1)
        .map(|w| {
            <[f64; 6]>::try_from(w.a.as_slice())
                .map(Vector6::from)
                .map_err(|_| LabError::no_answer("a planned waypoint without six numbers"))
        })
        .collect()
}

fn control_params(
    args: &ControlNodeArgs,
    log: &mut dyn FnMut(&str),
) -> Result<(ControlNodeParams, NodeSettings), LabError> {
    let settings = settings(&args.node)?;
    let params = ControlNodeParams {
        robot: robot_params(&args.robot, args.truth_topic.clone())?,
        wire: wire(&args.wire)?,
        gravity_in_clamp: args.robot.gravity.given(),
        goals: goals(args, log)?,
        control: ControlParams {
            gain: args.gain,
            epsilon: args.epsilon,
            max_translation: 1e-3 * args.max_step_mm,
            max_rotation: args.max_step_deg.to_radians(),
            ..ControlParams::default()
        },
        waypoint_epsilon: args.waypoint_epsilon,
        max_steps: args.max_steps,
        contact_miss: args.contact_miss.map(|mm| 1e-3 * mm),
    };
    Ok((params, settings))
}
