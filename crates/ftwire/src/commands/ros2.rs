//! `ftwire ros2 <node>`: the nodes of [`ftwire_ros2::node`]. This command reads the
//! arguments into the nodes' options ([`ftwire_ros2::node::options`], which build and check
//! the params), sets the stop flag on Ctrl-C (SIGINT, SIGTERM, SIGHUP), logs to stderr, and
//! prints the node's summary as one JSON line on stdout.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use ftwire_lab::error::LabError;
use ftwire_lab::plan::{PlanParams, PlanWireParams};
use ftwire_ros2::node::options::{
    ControlOptions, EstimateOptions, IdentifyOptions, ObserveOptions, RobotOptions, SensorOptions,
    load_wire,
};
use ftwire_ros2::node::sim::{SimNodeParams, obstacles, start_or_default};
use ftwire_ros2::node::tf::SimTfFrames;
use ftwire_ros2::node::{NodeError, NodeSettings};
use serde::Serialize;

use crate::cli::ros2::{
    ControlNodeArgs, EstimateNodeArgs, IdentifyNodeArgs, NodeArgs, RobotArgs, Ros2Args, Ros2Node,
    SensorArgs, SimNodeArgs,
};

/// Runs the chosen node until `--duration` ends or Ctrl-C.
pub fn run(args: Ros2Args) -> Result<(), LabError> {
    let stop = stop_on_signals();
    let mut log = |line: &str| errln!("{line}");
    match args.node {
        Ros2Node::Sim(a) => {
            let (settings, params) = (settings(&a.node)?, sim_params(&a)?);
            print_line(ftwire_ros2::node::sim::run(
                &params, settings, &stop, &mut log,
            ))
        }
        Ros2Node::Estimate(a) => {
            let (settings, params) = (settings(&a.node)?, estimate(&a)?.params());
            let params = params.map_err(from_node)?;
            print_line(ftwire_ros2::node::estimate_loop::run(
                &params, settings, &stop, &mut log,
            ))
        }
        Ros2Node::Identify(a) => {
            let (settings, params) = (settings(&a.node)?, identify(&a)?.params());
            let params = params.map_err(from_node)?;
            print_line(ftwire_ros2::node::identify::run(
                &params, settings, &stop, &mut log,
            ))
        }
        Ros2Node::Control(a) => {
            let (settings, params) = (settings(&a.node)?, control(&a, &mut log)?.params());
            let params = params.map_err(from_node)?;
            print_line(ftwire_ros2::node::control::run(
                &params, settings, &stop, &mut log,
            ))
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
            errln!("warning: cannot catch signal {signal} ({e}): Ctrl-C ends without a summary");
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

fn print_line(summary: Result<impl Serialize, NodeError>) -> Result<(), LabError> {
    let line = serde_json::to_string(&summary.map_err(from_node)?)
        .map_err(|e| LabError::no_answer(format!("the summary: {e}")))?;
    outln!("{line}");
    Ok(())
}

fn settings(args: &NodeArgs) -> Result<NodeSettings, LabError> {
    NodeSettings::from_env(args.domain_id, args.duration).map_err(from_node)
}

fn sim_params(a: &SimNodeArgs) -> Result<SimNodeParams, LabError> {
    let wire = load_wire(&a.wire).map_err(from_node)?;
    let boxes: Vec<[f64; 6]> = a.boxes.iter().map(|b| b.0).collect();
    Ok(SimNodeParams {
        start: start_or_default(&wire, a.start.as_ref().map(|s| s.0)).map_err(from_node)?,
        wire,
        gravity: a.gravity,
        setup: a.setup.load()?,
        seed: a.seed.seed,
        rate: a.rate,
        pose_rate: a.pose_rate,
        marker_rate: a.marker_rate,
        tare_samples: a.tare_samples,
        wait_subscriber: a.wait_subscriber,
        tf: SimTfFrames {
            world: a.tf_world_frame.clone(),
            base: a.tf_base_frame.clone(),
            tip: a.tf_tip_frame.clone(),
        },
        obstacles: obstacles(&boxes).map_err(from_node)?,
    })
}

fn sensor(a: &SensorArgs) -> Result<SensorOptions, LabError> {
    Ok(SensorOptions {
        calibration: a.calibration.path().map(std::path::Path::to_path_buf),
        mounting: a.mounting.load()?,
        gravity_in_clamp: a.gravity.given(),
        qos: a.qos.qos(),
        tare: a.tare,
        rate: a.rate,
        wrench_topic: a.wrench_topic.clone(),
        tip_pose_topic: a.tip_pose_topic.clone(),
    })
}

fn estimate(a: &EstimateNodeArgs) -> Result<EstimateOptions, LabError> {
    let o = &a.observe;
    Ok(EstimateOptions {
        wire: a.wire.clone(),
        sensor: sensor(&a.sensor)?,
        points: a.points,
        window: a.window,
        base_frame: a.base_frame.clone(),
        tip_frame: a.tip_frame.clone(),
        tf_stale: a.tf_stale,
        truth_topic: a.truth_topic.clone(),
        contact_miss_mm: a.contact_miss,
        observe: ObserveOptions {
            rest_tolerance_mm: o.rest_tolerance_mm,
            rest_tolerance_deg: o.rest_tolerance_deg,
            rest_dwell: o.rest_dwell,
            rest_settle: o.rest_settle,
            bias_observer: o.bias_observer.on(),
            sensor: o.sensor.clone(),
            pose_error: o.pose_error.model(),
            collision_calibration: o.collision_calibration,
        },
        error_bars: a.error_bars.on(),
        gain_error_pct: a.gain_error,
        model_error: a.model_error,
        record: a.record.clone(),
        force: a.force,
    })
}

fn robot(a: &RobotArgs) -> Result<RobotOptions, LabError> {
    Ok(RobotOptions {
        sensor: sensor(&a.sensor)?,
        rest_samples: a.rest_samples,
        settle_samples: a.settle_samples,
        reach_mm: a.reach_mm,
        reach_deg: a.reach_deg,
        move_timeout: a.move_timeout,
        target_topic: a.target_topic.clone(),
    })
}

fn identify(a: &IdentifyNodeArgs) -> Result<IdentifyOptions, LabError> {
    Ok(IdentifyOptions {
        robot: robot(&a.robot)?,
        samples: a.samples,
        twist_deg: a.twist,
        seed: a.seed.seed,
        residual: a.settings.settings(),
        sensor: a.sensor.clone(),
    })
}

fn control(a: &ControlNodeArgs, log: &mut dyn FnMut(&str)) -> Result<ControlOptions, LabError> {
    Ok(ControlOptions {
        robot: robot(&a.robot)?,
        wire: a.wire.clone(),
        goals: match &a.goal {
            Some(goal) => vec![goal.0.to_vec()],
            None => planned(a, log)?,
        },
        gain: a.gain,
        epsilon: a.epsilon,
        waypoint_epsilon: a.waypoint_epsilon,
        max_step_mm: a.max_step_mm,
        max_step_deg: a.max_step_deg,
        max_steps: a.max_steps,
        contact_miss_mm: a.contact_miss,
        truth_topic: a.truth_topic.clone(),
    })
}

/// The waypoints after the start of the path planned in `--scene`, as `ftwire plan` plans it.
fn planned(a: &ControlNodeArgs, log: &mut dyn FnMut(&str)) -> Result<Vec<Vec<f64>>, LabError> {
    let plan = PlanParams {
        scene: a.scene.clone(),
        wire: PlanWireParams {
            wire: a.wire.clone(),
            ..PlanWireParams::default()
        },
        time_budget: a.time_budget,
        ..PlanParams::default()
    };
    let report = ftwire_lab::plan::run(&plan)?;
    log(&format!(
        "control: planned {} waypoints in {} ({:.2} s); steering along them from the second",
        report.waypoints.len(),
        report.scene,
        report.seconds
    ));
    Ok(report.waypoints.into_iter().skip(1).map(|w| w.a).collect())
}
