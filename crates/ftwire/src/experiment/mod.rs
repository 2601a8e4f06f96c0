//! What the experiments of paper §IV share: the common options' values, the simulated rig they
//! run against, and the F/T measurement a real robot would make.
//!
//! The true wire is given to the simulator only; the estimators see what a real rig gives them
//! (raw F/T samples and the believed gripper poses).

pub mod calibration;
pub mod rig;

use clap::ValueEnum;
use nalgebra::Vector3;
use serde::Serialize;

/// Gravity in the simulated world (`--gravity on|off`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Gravity {
    /// Standard gravity, `(0, 0, −9.81)` m/s² in the world frame.
    On,
    /// No gravity: the paper's model assumption holds exactly.
    Off,
}

impl Gravity {
    /// The gravity vector \[m/s²\] in the world frame.
    pub fn vector(self) -> Vector3<f64> {
        match self {
            Self::On => Vector3::new(0.0, 0.0, -9.81),
            Self::Off => Vector3::zeros(),
        }
    }
}

/// Edges of the simulated rod in the experiments: the resolution at which DESIGN.md's agreed
/// accuracy of the simulator against the model holds (N = 100).
pub const SIM_EDGES: usize = 100;
