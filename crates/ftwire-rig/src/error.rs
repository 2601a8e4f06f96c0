//! Why a reading has no `ã` or the measurement cannot be set up.
//!
//! The messages say what is wrong with the value and what is allowed; they never name a
//! front end's spelling of an input (a CLI flag, a Python keyword, a ROS parameter): the front
//! end adds that context.

use ftwire_estimate::EstimateError;

/// An error of the rig layer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RigError {
    /// A reading with neither a raw reading nor an `ã`.
    #[error("the reading has neither a raw F/T reading nor an ã")]
    Empty,
    /// A raw reading, but neither a calibration nor a mounting to map it.
    #[error(
        "the reading is a raw F/T reading, and there is neither a calibration to map it to ã \
         nor a mounting to take it through, uncalibrated"
    )]
    NoMap,
    /// A raw reading without gravity while the mounting's tool weighs on the sensor.
    #[error(
        "the reading is a raw F/T reading without gravity: the mounting's tool (tool_mass = \
         {tool_mass} kg) weighs on the sensor, and its weight is taken out with the gravity \
         vector in the sensor frame at each reading"
    )]
    NoGravity {
        /// The tool's mass \[kg\].
        tool_mass: f64,
    },
    /// The map gave a value that is not finite.
    #[error("the map gave ã = {a:?}, which is not finite")]
    NotFinite {
        /// The map's output.
        a: [f64; 6],
    },
    /// A setting outside what is allowed.
    #[error("{0}")]
    Setting(String),
    /// An error of the estimation layer (a model, a mounting, a calibration).
    #[error(transparent)]
    Estimate(#[from] EstimateError),
}
