//! The ground-truth world of ftwire: a discrete elastic rod with gravity and contact, an F/T sensor, markers and a simulated rig.

// sensing and acting
pub mod execution;
pub mod markers;
pub mod sensor;
pub use execution::{ExecutionErrorConfig, ExecutionErrorModel};
pub use markers::{MarkerConfig, MarkerFrame, MotionCapture, point_at_arc_length};
pub use sensor::{FtReading, FtSensor, FtSensorConfig, SensingError};
