//! Robot execution error: where a gripper really goes when it is commanded to a pose.
//!
//! The paper perturbs the gripper motion with normal noise of 10 mm in position and 3° in
//! orientation (Mishani & Sintov, §IV-C). Here each commanded clamp pose `P = (R, p)` becomes
//! the actual pose `P · Δ`, with `Δ = (exp(ω̂), δ)` expressed in the **gripper (clamp) frame**:
//!
//! - `δ ~ N(0, σ_p² I₃)`: each of the three position components has standard deviation `σ_p`;
//! - `ω ~ N(0, σ_θ² I₃)`: a rotation vector with isotropic normal components (the "concentrated
//!   Gaussian" on SO(3)). The rotation angle `|ω|` then has RMS `√3 σ_θ` and follows a Maxwell
//!   distribution; each component of `log(Δ_R)` has standard deviation `σ_θ`.
//!
//! Both are isotropic, so the same distribution results whether the error is read in the
//! gripper frame or in the world frame; the gripper frame only fixes how the sample is built.
//! The robot still reports the commanded pose; this model only produces the actual one.

use ftwire_core::{Command, GripperPoses, Pose, ensure_finite};
use nalgebra::{Translation3, UnitQuaternion, Vector3};
use rand::RngExt;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use crate::sensor::{SensingError, in_range};

/// Parameters of the execution error. The default has no error.
///
/// # Example
/// ```
/// use ftwire_sim::ExecutionErrorParams;
///
/// assert_eq!(ExecutionErrorParams::default().position_std, 0.0);
/// assert_eq!(ExecutionErrorParams::paper().position_std, 0.010);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExecutionErrorParams {
    /// Position error σ per axis of the gripper frame \[m\] (default `0`; the paper's
    /// experiments use `0.010`).
    pub position_std: f64,
    /// Orientation error σ per rotation-vector component about the gripper axes \[rad\]
    /// (default `0`; the paper's experiments use 3° = `0.05236`).
    pub orientation_std: f64,
}

impl ExecutionErrorParams {
    /// The gripper noise of the paper's control experiments: 10 mm and 3°.
    ///
    /// # Example
    /// ```
    /// let paper = ftwire_sim::ExecutionErrorParams::paper();
    /// assert!((paper.orientation_std.to_degrees() - 3.0).abs() < 1e-12);
    /// ```
    #[must_use]
    pub fn paper() -> Self {
        Self {
            position_std: 0.010,
            orientation_std: 3f64.to_radians(),
        }
    }
}

/// The execution-error model: a validated [`ExecutionErrorParams`] and its own seeded random
/// number generator. Same configuration, seed and calls give the same poses.
#[derive(Debug, Clone)]
pub struct ExecutionErrorModel {
    config: ExecutionErrorParams,
    rng: ChaCha8Rng,
}

impl ExecutionErrorModel {
    /// Builds the model from a configuration and a seed.
    ///
    /// # Errors
    /// [`SensingError::OutOfRange`] if a σ is negative or not finite.
    ///
    /// # Example
    /// ```
    /// use ftwire_sim::{ExecutionErrorParams, ExecutionErrorModel};
    ///
    /// assert!(ExecutionErrorModel::new(ExecutionErrorParams::paper(), 9).is_ok());
    /// let bad = ExecutionErrorParams { position_std: -1.0, ..ExecutionErrorParams::paper() };
    /// assert!(ExecutionErrorModel::new(bad, 9).is_err());
    /// ```
    pub fn new(config: ExecutionErrorParams, seed: u64) -> Result<Self, SensingError> {
        in_range("position_std", 0, config.position_std, 0.0, f64::MAX)?;
        in_range("orientation_std", 0, config.orientation_std, 0.0, f64::MAX)?;
        Ok(Self {
            config,
            rng: ChaCha8Rng::seed_from_u64(seed),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &ExecutionErrorParams {
        &self.config
    }

    /// The pose a gripper really reaches when commanded to `commanded` (world from clamp).
    ///
    /// # Errors
    /// [`SensingError::Core`] if the commanded pose is not finite.
    ///
    /// # Example
    /// ```
    /// use ftwire_core::Pose;
    /// use ftwire_sim::{ExecutionErrorParams, ExecutionErrorModel};
    /// use nalgebra::Vector3;
    ///
    /// let commanded = Pose::translation(0.1, 0.2, 0.3);
    /// let mut exact = ExecutionErrorModel::new(ExecutionErrorParams::default(), 1)?;
    /// assert_eq!(exact.actual_pose(&commanded)?, commanded);
    /// let mut noisy = ExecutionErrorModel::new(ExecutionErrorParams::paper(), 1)?;
    /// let actual = noisy.actual_pose(&commanded)?;
    /// assert!((actual.translation.vector - Vector3::new(0.1, 0.2, 0.3)).norm() < 0.1);
    /// # Ok::<(), ftwire_sim::SensingError>(())
    /// ```
    pub fn actual_pose(&mut self, commanded: &Pose) -> Result<Pose, SensingError> {
        ensure_finite(
            "commanded.translation",
            commanded.translation.vector.as_slice(),
        )?;
        ensure_finite("commanded.rotation", commanded.rotation.coords.as_slice())?;
        let position: Vector3<f64> = self.standard_normal3() * self.config.position_std;
        let rotation: Vector3<f64> = self.standard_normal3() * self.config.orientation_std;
        if self.config.position_std == 0.0 && self.config.orientation_std == 0.0 {
            return Ok(*commanded);
        }
        let error = Pose::from_parts(
            Translation3::from(position),
            UnitQuaternion::from_scaled_axis(rotation),
        );
        Ok(commanded * error)
    }

    /// The poses both grippers really reach for `command`, each with its own independent error
    /// (base first, then tip).
    ///
    /// # Errors
    /// [`SensingError::Core`] if a commanded pose is not finite.
    pub fn actual_poses(&mut self, command: &Command) -> Result<GripperPoses, SensingError> {
        Ok(GripperPoses {
            base: self.actual_pose(&command.base)?,
            tip: self.actual_pose(&command.tip)?,
        })
    }

    fn standard_normal3(&mut self) -> Vector3<f64> {
        Vector3::from_fn(|_, _| self.rng.sample::<f64, _>(StandardNormal))
    }
}
