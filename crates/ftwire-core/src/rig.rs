use nalgebra::Vector6;
use serde::{Deserialize, Serialize};

use crate::Pose;

/// One raw sample of the wrist force/torque sensor.
///
/// # Example
/// ```
/// use ftwire_core::FtSample;
/// // A sample without a `saturated` field parses, with no channel clipped.
/// let old = r#"{"time": 0.5, "raw": [1.0, 2.0, 3.0, 0.1, 0.2, 0.3]}"#;
/// let sample: FtSample = serde_json::from_str(old)?;
/// assert_eq!(sample.saturated, [false; 6]);
/// assert!(!sample.is_saturated());
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct FtSample {
    /// Time of the sample \[s\] on the rig's clock.
    pub time: f64,
    /// Raw reading `(f1, f2, f3, τ1, τ2, τ3)` — **force first**, as sensors report — in the
    /// sensor's own frame, in the sensor's units (\[N\], \[N·m\]) before calibration.
    pub raw: Vector6<f64>,
    /// Per channel, in the order of `raw` (force first), whether the sensor clipped the channel
    /// at its full scale: such a channel reads the full scale, not the load, and an algorithm
    /// should not trust it (default all `false`, also when a log has no such field).
    #[serde(default)]
    pub saturated: [bool; 6],
}

impl FtSample {
    /// Whether any channel was clipped at its full scale.
    pub fn is_saturated(&self) -> bool {
        self.saturated.iter().any(|&s| s)
    }
}

/// Poses of both grippers in the robot's world frame, as the robot believes them to be.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GripperPoses {
    /// Base gripper clamp frame (the gripper carrying the F/T sensor), world from clamp.
    pub base: Pose,
    /// Second gripper clamp frame, world from clamp.
    pub tip: Pose,
}

impl GripperPoses {
    /// The relative pose `b` of the second gripper in the base gripper's clamp frame.
    pub fn relative(&self) -> Pose {
        self.base.inverse() * self.tip
    }
}

/// A quasi-static motion command: move both grippers to these clamp poses (world frame).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Command {
    /// Target pose of the base gripper clamp frame, world from clamp.
    pub base: Pose,
    /// Target pose of the second gripper clamp frame, world from clamp.
    pub tip: Pose,
}

/// What a real dual-arm robot with one wrist F/T sensor offers the algorithms.
///
/// Algorithms (`ftwire-estimate`, `ftwire-control`, `ftwire-plan`) see the world only through
/// this trait; the simulator implements it (`ftwire_sim::SimRig`), and so can a real robot's
/// driver.
pub trait Rig {
    /// The rig's error type.
    type Error: std::error::Error + Send + Sync + 'static;

    /// Reads one F/T sample, with the channels the sensor clipped flagged in
    /// [`FtSample::saturated`] (may fail on a sensor dropout).
    fn read_ft(&mut self) -> Result<FtSample, Self::Error>;

    /// Reads the gripper poses the robot believes it has (the commanded ones, on a robot with
    /// execution error).
    fn gripper_poses(&self) -> Result<GripperPoses, Self::Error>;

    /// Moves both grippers quasi-statically to the commanded poses and waits until they arrive.
    fn command(&mut self, command: &Command) -> Result<(), Self::Error>;

    /// The rig's clock \[s\].
    fn time(&self) -> f64;

    /// Moves only the second gripper, keeping the base gripper where the robot believes it is.
    fn move_tip(&mut self, tip: Pose) -> Result<(), Self::Error> {
        let base = self.gripper_poses()?.base;
        self.command(&Command { base, tip })
    }
}
