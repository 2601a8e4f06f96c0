//! Arguments of `ftwire ros2 <node>`: ftwire as ROS 2 nodes.

use clap::{Args, Subcommand};

/// `ftwire ros2 <node>`.
#[derive(Debug, Clone, Args)]
pub struct Ros2Args {
    /// The node to run.
    #[command(subcommand)]
    pub node: Ros2Node,
}

/// The nodes.
#[derive(Debug, Clone, Subcommand)]
pub enum Ros2Node {
    /// The simulator as a ROS 2 robot: publishes the wrench, the gripper poses and the markers,
    /// and moves on `/wire/tip_target`.
    Sim,
    /// The wire's shape from F/T at the sensor's rate.
    Estimate,
}
