//! One module per subcommand; each exposes `run(args) -> Result<(), LabError>` and `main` maps
//! the error to the exit code.

pub mod calibrate;
pub mod demo;
pub mod experiment;
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

use ftwire_lab::error::LabError;

use crate::cli::{Cli, Command};

/// Runs the chosen subcommand.
pub fn run(cli: Cli) -> Result<(), LabError> {
    match cli.command {
        Command::Demo(args) => demo::run(args),
        Command::Reproduce(args) => reproduce::run(args),
        Command::Solve(args) => solve::run(args),
        Command::SimEquilibrium(args) => sim_equilibrium::run(args),
        Command::Robot(args) => robot::run(args),
        Command::Experiment(args) => experiment::run(args),
        Command::Calibrate(args) => calibrate::run(args),
        Command::Identify(args) => identify::run(args),
        Command::Shape(args) => shape::run(args),
        Command::Plan(args) => plan::run(&args),
        Command::Scene(args) => plan::run_scene(&args),
        Command::Init(args) => init::run(&args),
        #[cfg(feature = "ros2")]
        Command::Ros2(args) => ros2::run(args),
        #[cfg(feature = "ros2")]
        Command::Import(args) => import::run(args),
    }
}
