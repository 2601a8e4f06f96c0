//! Sensors of the simulated bench: the wrist force/torque sensor, and the error type shared by
//! the sensing and acting models ([`crate::markers`], [`crate::execution`]).

mod error;
mod wrench;

pub use error::SensingError;
pub use wrench::{
    CLOCK_OFFSET_RANGE, FtSensor, FtSensorParams, MAX_BIAS_TIME_CONSTANT, MAX_CUBIC_NONLINEARITY,
    MAX_HYSTERESIS, RATE_RANGE,
};

pub(crate) use error::{all_in_range, in_range};
