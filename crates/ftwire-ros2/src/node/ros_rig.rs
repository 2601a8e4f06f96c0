//! The robot of a ROS 2 node as an [`ftwire_core::Rig`], so that the library's
//! [`ftwire_control::PathTracker`] (the tracker `ftwire experiment track` runs on the
//! simulator) steers a robot that speaks ROS 2.
//!
//! - **F/T samples**: [`Rig::read_ft`] hands out the raw samples (force first, sensor frame)
//!   of one rest's window at a time ([`super::robot`]: past the reaching tip pose and
//!   `settle_samples`, settled, `rest_samples` long); a read past the window's end takes the
//!   next window, at the same pose. The library's pipeline tares and maps them, with
//!   [`MapCalibration`], the node's raw map (`--calibration` or `--mounting`).
//! - **At each window**, the rig measures `ã` as the pipeline will, publishes the model's shape
//!   at it on [`super::SHAPE_TOPIC`], and with `contact_miss` compares the model's tip `Γ(ã)`
//!   with the reported tip pose: a miss above it is a contact (a force the model does not
//!   have). A contact, a model without an answer at `ã`, a target not reached, the end of the
//!   step budget or a stop ends the run: the rig refuses every later move, with its reason
//!   ([`RosRig::end`]).
//! - **Poses**: the base gripper is the base clamp's frame (the identity: the ROS side gives
//!   the second gripper's pose relative to it); the tip is the latest reported pose.
//! - **Moves**: only the second gripper moves (a command that moves the base gripper is
//!   refused); each target is sent on the target topic and waited for.

use std::sync::atomic::AtomicBool;

use ftwire_core::{Command, FtSample, GripperPoses, Pose, Rig};
use ftwire_estimate::ft::{FtCalibration, FtPipeline, RestAverage, Tare};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_rig::{RawMap, Reading};
use nalgebra::Vector6;
use ros2_client::Publisher;

use super::robot::{Halt, Robot, Window};
use super::{BASE_FRAME, NodeError, header, path_message, publish};
use crate::msg::Path;
use crate::node::pose::ros_point;

/// Nodes of the published shapes.
pub const SHAPE_NODES: usize = 64;

/// A base gripper pose farther than this from the base clamp's frame is a move of it \[m, rad\].
const BASE_TOLERANCE: f64 = 1e-9;

/// The node's raw map (`--calibration`, else `--mounting`) as the pipeline's calibration: a
/// tared raw reading to `ã`, as [`RawMap::a_tilde`] maps it at the rest's stamp (no answer:
/// not finite, which the pipeline refuses). A calibration's drift is held within its own
/// session's span; a reading without a time gets the drift at the span's end, as a later
/// session's reading does.
#[derive(Debug, Clone, PartialEq)]
pub struct MapCalibration(pub RawMap);

impl FtCalibration for MapCalibration {
    fn configuration(&self, tared: &Vector6<f64>) -> Vector6<f64> {
        self.configuration_at(tared, f64::INFINITY)
    }

    fn configuration_at(&self, tared: &Vector6<f64>, time: f64) -> Vector6<f64> {
        self.0
            .a_tilde(&Reading::raw(time, *tared))
            .unwrap_or_else(|_| Vector6::repeat(f64::NAN))
    }
}

/// Why the rig refused a read or a move; the run's end when [`RosRig::end`] holds it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RosRigError {
    /// `stop` was set or the duration ended.
    #[error("stopped (Ctrl-C, a signal or the end of --duration)")]
    Stopped,
    /// The target was not reached in time.
    #[error("the target was not reached within {seconds} s (--move-timeout)")]
    Unreached {
        /// The timeout \[s\].
        seconds: f64,
    },
    /// The model's tip misses the reported one by more than `contact_miss`.
    #[error("contact: the model's tip misses the gripper by {miss_mm:.1} mm (--contact-miss)")]
    Contact {
        /// The miss \[mm\].
        miss_mm: f64,
    },
    /// The model has no shape at the measured `ã`.
    #[error("the model has no shape at ã = {a:?}: {message}")]
    NoModel {
        /// The measured `ã`.
        a: [f64; 6],
        /// The model's message.
        message: String,
    },
    /// The step budget is spent.
    #[error("the budget of {steps} steps is spent (--max-steps)")]
    Budget {
        /// The budget.
        steps: usize,
    },
    /// A command moved the base gripper.
    #[error(
        "the ROS side moves the second gripper only: the base gripper stays at the base \
         clamp's frame (the command moved it by {mm:.3} mm and {deg:.3}°)"
    )]
    BaseMove {
        /// The base's translation \[mm\].
        mm: f64,
        /// The base's rotation \[°\].
        deg: f64,
    },
    /// No tip pose has arrived yet.
    #[error("no tip pose has arrived")]
    NoTipPose,
    /// ROS 2 failed; the node's error is [`RosRig::take_fatal`]'s.
    #[error("ROS 2 failed: {0}")]
    Ros(String),
}

impl RosRigError {
    /// The control node's outcome when this ended its run.
    pub fn outcome(&self) -> &'static str {
        match self {
            Self::Stopped | Self::Ros(_) => "stopped",
            Self::Unreached { .. } => "unreached",
            Self::Contact { .. } => "contact",
            Self::NoModel { .. } => "no_model",
            Self::Budget { .. } => "max_steps",
            Self::BaseMove { .. } | Self::NoTipPose => "command_failed",
        }
    }
}

/// What the rig measured at one window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestRecord {
    /// `ã` \[N·m, N\], torque first, base clamp frame.
    pub a: Vector6<f64>,
    /// The model's tip's miss from the reported tip pose \[m\] (`None`: no model answer).
    pub tip_miss: Option<f64>,
}

/// The ROS robot as a [`Rig`] (module docs).
pub(crate) struct RosRig<'a> {
    robot: Robot,
    stop: &'a AtomicBool,
    pipeline: FtPipeline<MapCalibration>,
    model: KirchhoffModel,
    contact_miss: Option<f64>,
    shape_pub: Publisher<Path>,
    move_timeout: f64,
    /// Most moves; the one after is refused.
    budget: usize,
    moves: usize,
    /// The reaching stamp of the last move (`-∞`: the next window from the newest samples).
    since: f64,
    window: Vec<FtSample>,
    next: usize,
    time: f64,
    rests: Vec<RestRecord>,
    end: Option<RosRigError>,
    fatal: Option<NodeError>,
}

/// How a [`RosRig`] measures and when it ends.
pub(crate) struct RigSettings<'a> {
    /// The model of the shapes and the contact check.
    pub model: KirchhoffModel,
    /// A tip miss above this is a contact \[m\].
    pub contact_miss: Option<f64>,
    /// Most moves.
    pub budget: usize,
    /// The longest wait for a target \[s\] (for the message).
    pub move_timeout: f64,
    /// Where the shapes go.
    pub shape_pub: Publisher<Path>,
    /// Set to stop.
    pub stop: &'a AtomicBool,
}

impl<'a> RosRig<'a> {
    /// The rig over `robot`, tared (after [`Robot::wait_ready`]); the pipeline averages each
    /// rest's `rest_samples`, at least half of them good.
    pub(crate) fn new(
        robot: Robot,
        rest_samples: usize,
        settings: RigSettings<'a>,
    ) -> Result<Self, NodeError> {
        let average =
            RestAverage::new((rest_samples / 2).max(2)).map_err(|e| NodeError::BadSetting {
                setting: "--rest-samples",
                value: format!("{rest_samples} ({e})"),
                allowed: "10 to 100000 samples",
            })?;
        let tare = robot.tare().copied().unwrap_or_else(Tare::none);
        let pipeline = FtPipeline::new(average, tare, MapCalibration(robot.map().clone()));
        Ok(Self {
            robot,
            stop: settings.stop,
            pipeline,
            model: settings.model,
            contact_miss: settings.contact_miss,
            shape_pub: settings.shape_pub,
            move_timeout: settings.move_timeout,
            budget: settings.budget,
            moves: 0,
            since: f64::NEG_INFINITY,
            window: Vec::new(),
            next: 0,
            time: 0.0,
            rests: Vec::new(),
            end: None,
            fatal: None,
        })
    }

    /// The pipeline the windows are measured with (the tare, the map).
    pub(crate) fn pipeline(&self) -> &FtPipeline<MapCalibration> {
        &self.pipeline
    }

    /// What each window measured, in order.
    pub(crate) fn rests(&self) -> &[RestRecord] {
        &self.rests
    }

    /// Why the rig ended the run, if it did.
    pub(crate) fn end(&self) -> Option<&RosRigError> {
        self.end.as_ref()
    }

    /// The ROS error that ended the run, if one did.
    pub(crate) fn take_fatal(&mut self) -> Option<NodeError> {
        self.fatal.take()
    }

    /// The robot back, for its counts and truth.
    pub(crate) fn into_robot(self) -> Robot {
        self.robot
    }

    /// Ends the run with `error` (the first reason stays) and returns it.
    fn ended(&mut self, error: RosRigError) -> RosRigError {
        self.end.get_or_insert(error).clone()
    }

    /// A ROS error: kept for the caller, and the run ends.
    fn failed(&mut self, error: NodeError) -> RosRigError {
        let message = error.to_string();
        self.fatal.get_or_insert(error);
        self.ended(RosRigError::Ros(message))
    }

    /// Takes the next window, measures it and publishes its shape (module docs).
    fn next_window(&mut self) -> Result<(), RosRigError> {
        let window = match self.robot.window(self.since, self.stop) {
            Ok(Ok(window)) => window,
            Ok(Err(_)) => return Err(self.ended(RosRigError::Stopped)),
            Err(e) => return Err(self.failed(e)),
        };
        self.since = f64::NEG_INFINITY;
        self.measure(&window);
        self.window = window.samples;
        self.next = 0;
        Ok(())
    }

    /// `ã` of `window` as the pipeline has it, its shape published, the contact checked.
    fn measure(&mut self, window: &Window) {
        // A window the pipeline refuses has no `ã`: the controller's own measurement says so.
        let Ok(m) = self.pipeline.measure(window.samples.iter().map(Some)) else {
            return;
        };
        let a = m.a;
        if let Ok(shape) = self.model.shape(&a, SHAPE_NODES) {
            let points = shape.positions.iter().map(ros_point);
            let path = path_message(header(window.mean_time(), BASE_FRAME), points);
            let counts = &mut self.robot.counts;
            publish(
                &self.shape_pub,
                path,
                "shape",
                &mut counts.published,
                &mut counts.publish_failed,
            );
        }
        let tip_miss = match self.model.tip(&a) {
            Ok(tip) => Some((tip.translation.vector - window.tip.translation.vector).norm()),
            Err(e) => {
                self.ended(RosRigError::NoModel {
                    a: a.into(),
                    message: e.to_string(),
                });
                None
            }
        };
        if let (Some(miss), Some(limit)) = (tip_miss, self.contact_miss)
            && miss > limit
        {
            self.ended(RosRigError::Contact {
                miss_mm: 1e3 * miss,
            });
        }
        self.rests.push(RestRecord { a, tip_miss });
    }
}

impl Rig for RosRig<'_> {
    type Error = RosRigError;

    fn read_ft(&mut self) -> Result<FtSample, RosRigError> {
        if let Some(end @ (RosRigError::Stopped | RosRigError::Ros(_))) = &self.end {
            return Err(end.clone());
        }
        if self.next >= self.window.len() {
            self.next_window()?;
        }
        let sample = self.window[self.next];
        self.next += 1;
        self.time = sample.time;
        Ok(sample)
    }

    fn gripper_poses(&self) -> Result<GripperPoses, RosRigError> {
        let tip = self.robot.tip().ok_or(RosRigError::NoTipPose)?;
        Ok(GripperPoses {
            base: Pose::identity(),
            tip,
        })
    }

    fn command(&mut self, command: &Command) -> Result<(), RosRigError> {
        if let Some(end) = &self.end {
            return Err(end.clone());
        }
        let (mm, rad) = (
            command.base.translation.vector.norm(),
            command.base.rotation.angle(),
        );
        if mm > BASE_TOLERANCE || rad > BASE_TOLERANCE {
            return Err(RosRigError::BaseMove {
                mm: 1e3 * mm,
                deg: rad.to_degrees(),
            });
        }
        if self.moves >= self.budget {
            return Err(self.ended(RosRigError::Budget { steps: self.budget }));
        }
        match self.robot.move_to(&command.tip, self.stop) {
            Ok(Ok(stamp)) => {
                self.moves += 1;
                self.since = stamp;
                self.window.clear();
                self.next = 0;
                Ok(())
            }
            Ok(Err(Halt::Stopped)) => Err(self.ended(RosRigError::Stopped)),
            Ok(Err(Halt::Timeout)) => Err(self.ended(RosRigError::Unreached {
                seconds: self.move_timeout,
            })),
            Err(e) => Err(self.failed(e)),
        }
    }

    fn time(&self) -> f64 {
        self.time
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ftwire_estimate::ft::MountingSpec;

    #[test]
    fn the_map_calibration_is_the_nodes_raw_map() {
        let map = RawMap::new(None, Some(MountingSpec::default())).expect("a mounting");
        let raw = Vector6::new(0.1, -0.2, 0.3, 0.01, 0.02, -0.01);
        let expected = map.a_tilde(&Reading::raw(0.0, raw)).expect("an ã");
        assert_eq!(MapCalibration(map).configuration(&raw), expected);
        // No map: no answer, which the pipeline refuses as not finite.
        let none = MapCalibration(RawMap::default()).configuration(&raw);
        assert!(none.iter().all(|v| v.is_nan()));
    }

    #[test]
    fn each_end_has_its_outcome_and_says_which_option() {
        let contact = RosRigError::Contact { miss_mm: 12.34 };
        assert_eq!(contact.outcome(), "contact");
        assert!(contact.to_string().contains("12.3 mm (--contact-miss)"));
        assert_eq!(RosRigError::Budget { steps: 3 }.outcome(), "max_steps");
        assert_eq!(
            RosRigError::Unreached { seconds: 5.0 }.outcome(),
            "unreached"
        );
        let base = RosRigError::BaseMove { mm: 1.0, deg: 0.0 };
        assert!(base.to_string().contains("second gripper only"));
    }
}
