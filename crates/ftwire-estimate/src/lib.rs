#![doc = include_str!("../README.md")]

pub mod calibration;
mod error;
pub mod ft;
pub mod identify;
pub mod log;
pub mod model;
pub mod shape;

pub use calibration::Calibration;
pub use error::EstimateError;
pub use model::{KirchhoffModel, WireModel};
