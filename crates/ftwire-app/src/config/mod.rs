//! The settings files a user gives, whether to an experiment or to a real rig's commands: wires
//! (a preset or a TOML file), the sensor's mounting, and the reading of any TOML settings file
//! with errors that name the file, the line and the key. The simulator's own files (its sensor
//! and rig) are read by `ftwire-lab` with the same functions.

mod file;
pub mod mounting;
pub mod sensor;
pub mod wire;

pub use file::{SetupError, line_of, names_a_file, parse_toml, read_toml, value_error};
