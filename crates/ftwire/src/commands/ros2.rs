//! `ftwire ros2 <node>`.

use ftwire_lab::error::LabError;

use crate::cli::ros2::{Ros2Args, Ros2Node};

/// Runs the chosen node until `--duration` ends or Ctrl-C.
pub fn run(args: Ros2Args) -> Result<(), LabError> {
    match args.node {
        Ros2Node::Sim | Ros2Node::Estimate => Err(LabError::bad_input("not built yet")),
    }
}
