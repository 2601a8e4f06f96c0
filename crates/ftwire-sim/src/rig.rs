//! The simulated rig: the ground-truth world behind the [`Rig`] trait.
//!
//! [`SimRig`] is what the algorithms see instead of a robot: F/T samples from the
//! [`FtSensor`] model, the gripper poses the robot *believes* it has (the commanded ones), and
//! quasi-static moves that land with the [`ExecutionErrorModel`]'s error. The ground truth — the
//! actual gripper poses, the equilibrium, the true wrench, motion-capture markers — is read
//! through the sim-only methods of [`SimRig`], never through [`Rig`].
//!
//! Time: each F/T read takes the sensor's next clock tick; each move advances the clock by the
//! time the grippers need at [`RigParams::linear_speed`] and [`RigParams::angular_speed`],
//! plus [`RigParams::settle_time`].

use std::ops::RangeInclusive;

use ftwire_core::{Command, FtSample, GripperPoses, Pose, Rig, ensure_finite};

use crate::equilibrium::Equilibrium;
use crate::error::SimError;
use crate::execution::{ExecutionErrorModel, ExecutionErrorParams};
use crate::markers::{MarkerFrame, MarkerParams, MotionCapture, SectionFrames};
use crate::motion::Motion;
use crate::sensor::{FtSensor, FtSensorParams};
use crate::simulator::Simulator;
use crate::world::World;

/// The allowed range of [`RigParams::linear_speed`] \[m/s\] and [`RigParams::angular_speed`]
/// \[rad/s\]: 1 mm/s (or mrad/s) to 10 m/s (or rad/s), beyond any robot arm's either way.
///
/// With these bounds and [`SETTLE_TIME_RANGE`], a move of the grippers (at most a few metres
/// and π rad) takes at most about 10⁴ s on the simulated clock, so a run of 10⁵ moves stays
/// within 10⁹ s: at the sensor's fastest rate ([`crate::sensor::RATE_RANGE`], 1 MHz) that is 10¹⁵
/// clock ticks, below the 2⁵³ ≈ 9·10¹⁵ the clock counts exactly.
pub const SPEED_RANGE: RangeInclusive<f64> = 1e-3..=10.0;

/// The allowed range of [`RigParams::settle_time`] \[s\]: none up to an hour per move (see
/// [`SPEED_RANGE`] for why the clock needs a bound).
pub const SETTLE_TIME_RANGE: RangeInclusive<f64> = 0.0..=3600.0;

/// Settings of a [`SimRig`]: its sensing and acting models, its motion timing and its seed.
#[derive(Debug, Clone, PartialEq)]
pub struct RigParams {
    /// The F/T sensor on the base gripper (default: [`FtSensorParams::default`], the character
    /// of a SensONE-class sensor; [`FtSensorParams::ideal`] switches distortions off).
    pub sensor: FtSensorParams,
    /// Motion capture (default: 11 markers on the centreline, σ = 0.3 mm, 2 % dropouts).
    pub markers: MarkerParams,
    /// Robot execution error (default: none; [`ExecutionErrorParams::paper`] is 10 mm and 3°).
    pub execution: ExecutionErrorParams,
    /// Gripper speed used to time a move \[m/s\], in [`SPEED_RANGE`] (default `0.05`).
    pub linear_speed: f64,
    /// Gripper angular speed used to time a move \[rad/s\], in [`SPEED_RANGE`] (default `0.5`).
    pub angular_speed: f64,
    /// Time to settle after each move \[s\], in [`SETTLE_TIME_RANGE`] (default `0.1`).
    pub settle_time: f64,
    /// Seed of every random choice of the rig: sensor noise, drift and dropouts, marker noise
    /// and dropouts, execution error (default `0`). Same seed, same run. The markers' mounting
    /// offsets have a seed of their own ([`MarkerParams::mount_seed`]).
    pub seed: u64,
}

impl Default for RigParams {
    fn default() -> Self {
        Self {
            sensor: FtSensorParams::default(),
            markers: MarkerParams::default(),
            execution: ExecutionErrorParams::default(),
            linear_speed: 0.05,
            angular_speed: 0.5,
            settle_time: 0.1,
            seed: 0,
        }
    }
}

impl RigParams {
    /// A rig with no distortion at all: ideal sensor, ideal markers, no execution error.
    pub fn ideal() -> Self {
        Self {
            sensor: FtSensorParams::ideal(),
            markers: MarkerParams::ideal(),
            ..Self::default()
        }
    }

    /// Checks every setting as [`SimRig::new`] does: the speeds and settle time here, and the
    /// sensor, marker and execution-error models' own checks. A configuration read from a file
    /// can so be rejected before any rig is built.
    ///
    /// # Errors
    /// [`SimError::RigSetting`] or [`SimError::Sensing`] naming the setting and what is allowed.
    ///
    /// # Example
    /// ```
    /// let mut config = ftwire_sim::RigParams::default();
    /// assert!(config.validate().is_ok());
    /// config.markers.noise_std = -1.0;
    /// assert!(config.validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<(), SimError> {
        FtSensor::new(self.sensor.clone(), 0)?;
        MotionCapture::new(self.markers.clone(), 0)?;
        ExecutionErrorModel::new(self.execution, 0)?;
        for (field, value, allowed) in [
            (
                "linear_speed",
                self.linear_speed,
                "a speed in [0.001, 10] m/s",
            ),
            (
                "angular_speed",
                self.angular_speed,
                "a speed in [0.001, 10] rad/s",
            ),
        ] {
            if !SPEED_RANGE.contains(&value) {
                return Err(SimError::RigSetting {
                    field,
                    value,
                    allowed,
                });
            }
        }
        if !SETTLE_TIME_RANGE.contains(&self.settle_time) {
            return Err(SimError::RigSetting {
                field: "settle_time",
                value: self.settle_time,
                allowed: "a time in [0, 3600] s",
            });
        }
        Ok(())
    }
}

/// Independent streams for the rig's models, derived from one user seed (SplitMix64 finaliser).
fn stream_seed(seed: u64, stream: u64) -> u64 {
    let mut z = seed ^ stream.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The simulated dual-arm rig: the discrete elastic rod between two grippers, a wrist F/T
/// sensor, motion capture and robot execution error.
///
/// # Example
/// ```
/// use ftwire_core::{GripperPoses, Rig};
/// use ftwire_sim::{RigParams, RodParams, SimRig, World};
/// use nalgebra::{Isometry3, Translation3, UnitQuaternion};
///
/// let world = World::new(RodParams::nitinol_2mm_630().with_edges(40))?;
/// let start = GripperPoses {
///     base: Isometry3::identity(),
///     tip: Isometry3::from_parts(Translation3::new(0.5, 0.1, 0.0), UnitQuaternion::identity()),
/// };
/// let mut rig = SimRig::new(world, start, RigParams::ideal())?;
/// let sample = rig.read_ft()?;
/// // The ideal sensor reports the true base wrench, force first.
/// let truth = rig.equilibrium().base_wrench;
/// assert!((sample.raw[0] - truth.force.x).abs() < 1e-12);
/// assert!((sample.raw[5] - truth.torque.z).abs() < 1e-12);
/// # Ok::<(), ftwire_sim::SimError>(())
/// ```
#[derive(Debug, Clone)]
pub struct SimRig {
    sim: Simulator,
    sensor: FtSensor,
    markers: MotionCapture,
    execution: ExecutionErrorModel,
    believed: GripperPoses,
    time: f64,
    config: RigParams,
}

impl SimRig {
    /// Places the wire between grippers at `start` (world frame, exactly: the initial placement
    /// has no execution error) by a cold solve, and builds the rig around it.
    ///
    /// # Errors
    /// [`SimError::RigSetting`] or [`SimError::Sensing`] for a bad setting, and the errors of
    /// [`Simulator::new`].
    pub fn new(world: World, start: GripperPoses, config: RigParams) -> Result<Self, SimError> {
        config.validate()?;
        let sim = Simulator::new(world, &start.base, &start.tip)?;
        Self::from_simulator(sim, config)
    }

    /// Builds the rig around a simulator that already holds an equilibrium; the robot believes
    /// it is exactly where the grippers are.
    ///
    /// # Errors
    /// [`SimError::RigSetting`] or [`SimError::Sensing`] for a bad setting.
    pub fn from_simulator(sim: Simulator, config: RigParams) -> Result<Self, SimError> {
        config.validate()?;
        let (base, tip) = sim.gripper_poses();
        Ok(Self {
            sensor: FtSensor::new(config.sensor.clone(), stream_seed(config.seed, 1))?,
            markers: MotionCapture::new(config.markers.clone(), stream_seed(config.seed, 2))?,
            execution: ExecutionErrorModel::new(config.execution, stream_seed(config.seed, 3))?,
            believed: GripperPoses { base, tip },
            sim,
            time: 0.0,
            config,
        })
    }

    /// Observes the motion-capture markers at the current time, in the world frame
    /// (ground truth with marker noise and dropouts, each marker off the centreline by its
    /// mounting offset in the material frame at its arc length).
    ///
    /// # Errors
    /// [`SimError::Sensing`] if the marker model rejects the centreline.
    pub fn observe_markers(&mut self) -> Result<MarkerFrame, SimError> {
        let equilibrium = self.sim.equilibrium();
        let rod = self.sim.world().rod();
        let arc_lengths: Vec<f64> = (0..rod.nodes()).map(|k| rod.node_arc_length(k)).collect();
        // Mounting offsets turn with the edges' material frames, at the edges' midpoints.
        let frames = equilibrium.material_frames();
        let frame_arc_lengths: Vec<f64> =
            (0..rod.edges()).map(|j| rod.edge_arc_length(j)).collect();
        let frame = self.markers.observe_mounted(
            self.time,
            &equilibrium.centreline(),
            &arc_lengths,
            rod.params().length,
            &SectionFrames {
                frames: &frames,
                arc_lengths: &frame_arc_lengths,
            },
        )?;
        Ok(frame)
    }

    /// Ground truth: the current equilibrium (true base wrench, shape, energy, contacts).
    pub fn equilibrium(&self) -> &Equilibrium {
        self.sim.equilibrium()
    }

    /// Ground truth: where the grippers actually are (world frame), execution error included.
    pub fn actual_poses(&self) -> GripperPoses {
        let (base, tip) = self.sim.gripper_poses();
        GripperPoses { base, tip }
    }

    /// Ground truth: the simulator (world, equilibrium, snap events).
    pub fn simulator(&self) -> &Simulator {
        &self.sim
    }

    /// Ground truth: the F/T sensor model (its true bias, and the exact inverse of its
    /// deterministic part, which algorithms must not use).
    pub fn sensor(&self) -> &FtSensor {
        &self.sensor
    }

    /// The F/T sensor model, to carry its state ([`FtSensor::set_hysteresis_state`]) from
    /// the rig of one rest of a session to the next.
    pub fn sensor_mut(&mut self) -> &mut FtSensor {
        &mut self.sensor
    }

    /// Reads one F/T sample with **nothing in the base gripper**, at the sensor's next clock
    /// tick: the reading a robot takes to tare its sensor before it picks the wire up
    /// (`ftwire_estimate::ft::Tare`). Only the sensor's own offset, drift and noise are in it.
    /// It is a sim-only method: on a real robot the same reading is an ordinary
    /// [`Rig::read_ft`] taken before the wire is in the gripper.
    ///
    /// # Errors
    /// As [`Rig::read_ft`].
    ///
    /// # Example
    /// ```
    /// use ftwire_core::{GripperPoses, Rig};
    /// use ftwire_sim::{RigParams, RodParams, SimRig, World};
    /// use nalgebra::{Isometry3, Translation3, UnitQuaternion};
    ///
    /// let world = World::new(RodParams::nitinol_2mm_630().with_edges(30))?;
    /// let start = GripperPoses {
    ///     base: Isometry3::identity(),
    ///     tip: Isometry3::from_parts(Translation3::new(0.5, 0.1, 0.0), UnitQuaternion::identity()),
    /// };
    /// let mut rig = SimRig::new(world, start, RigParams::ideal())?;
    /// assert_eq!(rig.read_ft_empty_gripper()?.raw, nalgebra::Vector6::zeros());
    /// # Ok::<(), ftwire_sim::SimError>(())
    /// ```
    pub fn read_ft_empty_gripper(&mut self) -> Result<FtSample, SimError> {
        self.read_wrench(&ftwire_core::Wrench::default())
    }

    fn read_wrench(&mut self, wrench: &ftwire_core::Wrench) -> Result<FtSample, SimError> {
        let result = self.sensor.read(wrench, self.time);
        // The sensor consumes its tick even on a dropout; the rig's clock follows it.
        if let Some(tick) = self.sensor.last_sample_time() {
            self.time = self.time.max(tick);
        }
        Ok(result?)
    }

    /// The rig's settings.
    pub fn config(&self) -> &RigParams {
        &self.config
    }

    /// Moves the grippers and returns the motion (with its snap events). As [`Rig::command`].
    ///
    /// A command either completes or changes nothing: when it is refused (a non-finite pose,
    /// grippers farther apart than the wire is long) or the simulator finds no equilibrium on
    /// the way, the equilibrium, the actual and believed gripper poses, the clock and the
    /// execution error's random stream are all as they were before the call
    /// (`tests/rig_failures.rs`), so the caller can retry or command another pose.
    ///
    /// # Errors
    /// As [`Rig::command`].
    pub fn command_motion(&mut self, command: &Command) -> Result<&Motion, SimError> {
        for (field, pose) in [
            ("command.base", &command.base),
            ("command.tip", &command.tip),
        ] {
            ensure_finite(field, pose.translation.vector.as_slice())?;
            ensure_finite(field, pose.rotation.coords.as_slice())?;
        }
        // The simulator keeps the furthest equilibrium a failed motion reached and the
        // execution model has drawn its error: restore both if the motion fails.
        let (sim_before, execution_before) = (self.sim.clone(), self.execution.clone());
        let moved = self
            .execution
            .actual_poses(command)
            .map_err(SimError::from)
            .and_then(|actual| {
                let before = self.actual_poses();
                let duration = self
                    .move_duration(&before.base, &actual.base)
                    .max(self.move_duration(&before.tip, &actual.tip));
                self.sim
                    .move_grippers(&actual.base, &actual.tip)
                    .map(|_| duration)
            });
        match moved {
            Ok(duration) => {
                self.time += duration + self.config.settle_time;
                self.believed = GripperPoses {
                    base: command.base,
                    tip: command.tip,
                };
                self.sim.last_motion().ok_or(SimError::NotSolved)
            }
            Err(error) => {
                self.sim = sim_before;
                self.execution = execution_before;
                Err(error)
            }
        }
    }

    fn move_duration(&self, from: &Pose, to: &Pose) -> f64 {
        let distance = (to.translation.vector - from.translation.vector).norm();
        let angle = from.rotation.angle_to(&to.rotation);
        (distance / self.config.linear_speed).max(angle / self.config.angular_speed)
    }
}

impl Rig for SimRig {
    type Error = SimError;

    /// Reads one F/T sample of the current base wrench at the sensor's next clock tick, with
    /// the channels it clipped flagged in [`FtSample::saturated`].
    ///
    /// # Errors
    /// [`SimError::Sensing`] with [`crate::SensingError::Dropout`] when the sensor misses a tick
    /// (the tick and its time are consumed, as on a real bus).
    fn read_ft(&mut self) -> Result<FtSample, SimError> {
        let wrench = self.sim.equilibrium().base_wrench;
        self.read_wrench(&wrench)
    }

    fn gripper_poses(&self) -> Result<GripperPoses, SimError> {
        Ok(self.believed)
    }

    fn command(&mut self, command: &Command) -> Result<(), SimError> {
        self.command_motion(command).map(|_| ())
    }

    fn time(&self) -> f64 {
        self.time
    }
}
