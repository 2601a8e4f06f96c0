#![doc = include_str!("../README.md")]

// The discrete elastic rod and its solvers.
mod banded;
mod cold_start;
mod continuation;
mod discrete_rod;
mod dual;
mod energy;
mod equilibrium;
mod error;
mod guess;
mod motion;
mod newton;
mod obstacle;
mod settings;
mod simulator;
mod solve;
mod state;
mod transport;
mod world;

pub use cold_start::{COARSE_EDGES, MAX_BEND};
pub use discrete_rod::{DiscreteRod, RodParams};
pub use energy::Energies;
pub use equilibrium::Equilibrium;
pub use error::SimError;
pub use motion::{ColdStart, Motion, SnapEvent};
pub use newton::Convergence;
pub use obstacle::{BoxObstacle, Floor, Obstacle};
pub use settings::{ContinuationParams, NewtonParams};
pub use simulator::Simulator;
pub use state::{InitialGuess, RodState};
pub use world::{DEFAULT_CONTACT_STIFFNESS, World};

// sensing and acting
pub mod execution;
pub mod markers;
pub mod rig;
pub mod sensor;
pub use execution::{ExecutionErrorModel, ExecutionErrorParams};
pub use markers::{MarkerFrame, MarkerParams, MotionCapture, SectionFrames, point_at_arc_length};
pub use rig::{RigParams, SimRig};
pub use sensor::{FtSensor, FtSensorParams, SensingError};
