//! Command-line types (clap). One submodule per subcommand.

pub mod calibrate;
pub mod demo;
pub mod experiment;
pub mod groups;
pub mod identify;
#[cfg(feature = "ros2")]
pub mod import;
pub mod init;
pub mod plan;
pub mod reproduce;
pub mod robot;
#[cfg(feature = "ros2")]
pub mod ros2;
pub mod shape;
pub mod sim_equilibrium;
pub mod solve;

use clap::{Parser, Subcommand};

/// Sense and steer an elastic wire with a dual-arm robot from one wrist force/torque sensor.
#[derive(Debug, Parser)]
#[command(name = "ftwire", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// The whole system at work in the simulator: calibrate the sensor, identify a wire it is
    /// not told about, and see its shape from F/T alone.
    Demo(demo::DemoArgs),
    /// Run every experiment of the paper's §IV and write one report beside the paper's tables.
    Reproduce(reproduce::ReproduceArgs),
    /// Solve the Kirchhoff model for a configuration a: shape, tip pose, Jacobian, stability.
    Solve(solve::SolveArgs),
    /// Find an equilibrium of the ground-truth discrete elastic rod between two clamps.
    SimEquilibrium(sim_equilibrium::SimEquilibriumArgs),
    /// Kinematics of the SDA10F dual-arm robot.
    Robot(robot::RobotArgs),
    /// Run an experiment of paper §IV in the simulator; writes a results folder.
    Experiment(experiment::ExperimentArgs),
    /// Learn the F/T calibration from a rig's recording (raw readings and markers on a known
    /// wire).
    Calibrate(calibrate::CalibrateArgs),
    /// Identify a wire's stiffnesses and length from a recorded JSON Lines log.
    Identify(identify::IdentifyArgs),
    /// Estimate the wire's shape for every record of a rig log (JSON Lines), from F/T alone.
    Shape(shape::ShapeArgs),
    /// Plan a path of the wire among a scene's obstacles (RRT* in A_free or in Z = A × Q).
    Plan(plan::PlanArgs),
    /// Scene files: validate one and check its start and goal.
    Scene(plan::SceneArgs),
    /// Write a commented example of each configuration file (wire, sensor, rig, scene) into a
    /// folder.
    Init(init::InitArgs),
    /// ftwire as ROS 2 nodes: the estimator, identification, control and the simulator.
    #[cfg(feature = "ros2")]
    Ros2(ros2::Ros2Args),
    /// Convert a recording made elsewhere (a ROS 2 bag) to ftwire's JSON Lines log.
    #[cfg(feature = "ros2")]
    Import(import::ImportArgs),
}
