//! The two arms of the SDA10F.

use std::fmt;

use serde::{Deserialize, Serialize};

/// One of the two arms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Arm {
    /// The left arm: carries the F/T sensor and the **base** gripper (wire end `t = 0`).
    Left,
    /// The right arm: carries the **second** gripper (wire end `t = L`).
    Right,
}

impl Arm {
    /// Both arms, left first.
    pub const BOTH: [Arm; 2] = [Arm::Left, Arm::Right];

    pub(crate) fn index(self) -> usize {
        match self {
            Arm::Left => 0,
            Arm::Right => 1,
        }
    }
}

impl fmt::Display for Arm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Arm::Left => "left",
            Arm::Right => "right",
        })
    }
}
