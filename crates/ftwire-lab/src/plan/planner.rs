//! Which planning space a plan searches.

use std::fmt;

use serde::Serialize;

/// Which planning space.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Planner {
    /// RRT* in `A_free`, the base gripper held at the scene's pose (the paper).
    #[default]
    Fixed,
    /// RRT* in `Z = A × Q`, the base gripper moving too (within 0.15 m and 0.5 rad).
    Moving,
}

impl fmt::Display for Planner {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Fixed => "fixed",
            Self::Moving => "moving",
        })
    }
}
