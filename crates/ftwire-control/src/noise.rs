//! Execution noise on the second gripper's commands, as a [`Rig`] wrapper.
//!
//! Three models (see the control issue and DESIGN.md):
//!
//! - [`NoiseModel::Increment`], the paper's (§IV-D): `N(0, 10 mm)` per axis and `N(0, 3°)` per
//!   rotation-vector component on each control output `δb`. The paper injects the error into
//!   the command it sends, so the robot's encoders know where the gripper went: this model's
//!   [`Rig::gripper_poses`] reports the pose reached, and a command built on it lands with the
//!   next error. Callers that step from the reported pose, as eq. 14 and
//!   [`crate::open_loop::roll_out`] do, see the errors accumulate along a motion:
//!   `actual_{i+1} = actual_i · δb_i · Δ_i`.
//! - [`NoiseModel::Absolute`]: each commanded pose is perturbed independently,
//!   `actual = b · Δ_i` (as the simulator's own execution-error model).
//! - [`NoiseModel::Offset`]: what a real robot has: one calibration error `Δ₀` drawn once per
//!   run from the same 10 mm / 3° distribution, plus a fine repeatability `δ_i` per move (0.1 mm,
//!   0.05°): `actual = b · Δ₀ · δ_i`. A closed loop can remove `Δ₀`; an open loop cannot.
//!
//! Every `Δ` is built in the gripper frame, `(exp(ω̂), δ)` with isotropic normal components.
//! Only the second gripper is perturbed; the base gripper (with the sensor) goes where it is
//! commanded. Under `absolute` and `offset` the error is the robot's own and unknown to it: it
//! believes it is where it commanded. All draws come from one seeded RNG.

use ftwire_core::{Command, FtSample, GripperPoses, Pose, Rig};
use nalgebra::{Translation3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::Serialize;

use crate::ControlError;

/// Which execution noise (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum NoiseModel {
    /// No noise: the grippers go where they are commanded.
    None,
    /// The paper's: an error on each increment `δb`, accumulating along a motion.
    Increment,
    /// Each commanded pose perturbed independently.
    Absolute,
    /// One offset per run plus fine repeatability per move.
    Offset,
}

impl NoiseModel {
    /// The model's name (`none`, `increment`, `absolute`, `offset`).
    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Increment => "increment",
            Self::Absolute => "absolute",
            Self::Offset => "offset",
        }
    }
}

/// Standard deviations of the noise (public fields + `Default`, the paper's values).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NoiseParams {
    /// Position σ per axis \[m\] of an increment, a pose or the offset (default `0.010`).
    pub position_std: f64,
    /// Rotation σ per rotation-vector component \[rad\] (default 3° = `0.05236`).
    pub orientation_std: f64,
    /// Repeatability position σ per axis \[m\] of the `offset` model (default `1e-4`).
    pub repeat_position_std: f64,
    /// Repeatability rotation σ \[rad\] of the `offset` model (default 0.05°).
    pub repeat_orientation_std: f64,
}

impl Default for NoiseParams {
    fn default() -> Self {
        Self {
            position_std: 0.010,
            orientation_std: 3f64.to_radians(),
            repeat_position_std: 1e-4,
            repeat_orientation_std: 0.05f64.to_radians(),
        }
    }
}

/// A [`Rig`] whose second gripper lands with execution noise (see the module docs).
///
/// # Example
/// ```
/// use ftwire_control::{NoiseModel, NoiseParams, NoisyRig};
/// # use ftwire_core::{Command, FtSample, GripperPoses, Pose, Rig};
/// # #[derive(Debug)] struct Still(GripperPoses);
/// # #[derive(Debug, thiserror::Error)] #[error("never")] struct Never;
/// # impl Rig for Still {
/// #     type Error = Never;
/// #     fn read_ft(&mut self) -> Result<FtSample, Never> { Ok(FtSample::default()) }
/// #     fn gripper_poses(&self) -> Result<GripperPoses, Never> { Ok(self.0) }
/// #     fn command(&mut self, c: &Command) -> Result<(), Never> { self.0 = GripperPoses { base: c.base, tip: c.tip }; Ok(()) }
/// #     fn time(&self) -> f64 { 0.0 }
/// # }
/// let start = GripperPoses { base: Pose::identity(), tip: Pose::translation(0.5, 0.0, 0.0) };
/// let mut rig = NoisyRig::new(Still(start), NoiseModel::Offset, NoiseParams::default(), 7)?;
/// let target = Pose::translation(0.5, 0.1, 0.0);
/// rig.move_tip(target)?;
/// // The robot believes it is at the target; the gripper is off by the offset.
/// assert_eq!(rig.gripper_poses()?.tip, target);
/// assert!((rig.inner().0.tip.translation.vector - target.translation.vector).norm() > 1e-4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct NoisyRig<R> {
    inner: R,
    model: NoiseModel,
    settings: NoiseParams,
    rng: ChaCha8Rng,
    believed: GripperPoses,
    offset: Pose,
}

impl<R: Rig> NoisyRig<R> {
    /// Wraps `inner`, which holds the wire where the robot believes it is; `seed` seeds every
    /// draw. The `offset` model draws its offset here and moves `inner`'s second gripper by it
    /// at once: a real robot's calibration error is there from the start, so the wire is held
    /// at `b₀ · Δ₀` before the first command, and no move jumps by the offset.
    ///
    /// # Errors
    /// [`ControlError::BadSetting`] for a negative or non-finite σ; [`ControlError::Rig`] when
    /// `inner` cannot report its poses, or (`offset`) cannot move to the offset pose.
    pub fn new(
        inner: R,
        model: NoiseModel,
        settings: NoiseParams,
        seed: u64,
    ) -> Result<Self, ControlError> {
        for (name, value) in [
            ("position_std", settings.position_std),
            ("orientation_std", settings.orientation_std),
            ("repeat_position_std", settings.repeat_position_std),
            ("repeat_orientation_std", settings.repeat_orientation_std),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(ControlError::BadSetting {
                    name,
                    value,
                    allowed: "a finite σ ≥ 0",
                });
            }
        }
        let believed = inner.gripper_poses().map_err(|e| ControlError::Rig {
            message: e.to_string(),
        })?;
        let mut rig = Self {
            inner,
            model,
            settings,
            rng: ChaCha8Rng::seed_from_u64(seed),
            believed,
            offset: Pose::identity(),
        };
        if model == NoiseModel::Offset {
            rig.offset = rig.draw(settings.position_std, settings.orientation_std);
            // The calibration error is there before the first command: the gripper that
            // picked the wire up was already off by it. Without this the whole offset would
            // arrive with the first move, as a jump no real robot makes.
            let held = Command {
                base: believed.base,
                tip: believed.tip * rig.offset,
            };
            rig.inner.command(&held).map_err(|e| ControlError::Rig {
                message: format!("holding the wire at the offset pose: {e}"),
            })?;
        }
        Ok(rig)
    }

    /// The wrapped rig.
    pub fn inner(&self) -> &R {
        &self.inner
    }

    /// The wrapped rig, mutably (its ground truth, in a simulator).
    pub fn inner_mut(&mut self) -> &mut R {
        &mut self.inner
    }

    /// The noise model.
    pub fn model(&self) -> NoiseModel {
        self.model
    }

    /// The `offset` model's calibration error (identity for the other models).
    pub fn offset(&self) -> &Pose {
        &self.offset
    }

    fn draw(&mut self, position_std: f64, orientation_std: f64) -> Pose {
        let mut normal3 = || Vector3::from_fn(|_, _| self.rng.sample::<f64, _>(StandardNormal));
        let position = normal3() * position_std;
        let rotation = normal3() * orientation_std;
        Pose::from_parts(
            Translation3::from(position),
            UnitQuaternion::from_scaled_axis(rotation),
        )
    }

    /// Where the second gripper really goes when commanded from the believed `from` to `to`.
    fn actual_tip(&mut self, actual_now: &Pose, from: &Pose, to: &Pose) -> Pose {
        let s = self.settings;
        match self.model {
            NoiseModel::None => *to,
            NoiseModel::Increment => {
                actual_now * (from.inverse() * to) * self.draw(s.position_std, s.orientation_std)
            }
            NoiseModel::Absolute => to * self.draw(s.position_std, s.orientation_std),
            NoiseModel::Offset => {
                to * self.offset * self.draw(s.repeat_position_std, s.repeat_orientation_std)
            }
        }
    }
}

impl<R: Rig> Rig for NoisyRig<R> {
    type Error = R::Error;

    fn read_ft(&mut self) -> Result<FtSample, Self::Error> {
        self.inner.read_ft()
    }

    /// The poses the robot reports: where it went under `increment` (the paper injects the
    /// error into the command, so the encoders know), where it was commanded otherwise.
    fn gripper_poses(&self) -> Result<GripperPoses, Self::Error> {
        match self.model {
            NoiseModel::Increment => self.inner.gripper_poses(),
            _ => Ok(self.believed),
        }
    }

    /// Commands the inner rig with the noisy tip pose; on failure nothing changes but the
    /// noise stream (a retry draws a new error).
    fn command(&mut self, command: &Command) -> Result<(), Self::Error> {
        let actual_now = self.inner.gripper_poses()?.tip;
        let from = self.gripper_poses()?.tip;
        let mut tip = self.actual_tip(&actual_now, &from, &command.tip);
        if self.model == NoiseModel::Increment {
            // The reported pose feeds the next command, which lands as the next reported pose:
            // a quaternion's norm error would compound (`inverse` is the conjugate), by about 3×
            // per move, and the wire would be clamped by a non-rotation within a few dozen.
            tip.rotation.renormalize();
        }
        self.inner.command(&Command {
            base: command.base,
            tip,
        })?;
        self.believed = GripperPoses {
            base: command.base,
            tip: command.tip,
        };
        Ok(())
    }

    fn time(&self) -> f64 {
        self.inner.time()
    }
}
