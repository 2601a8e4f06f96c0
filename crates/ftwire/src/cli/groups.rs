//! Argument groups that several commands share, each declared once and flattened
//! (`#[command(flatten)]`) where it is used, so an option means the same everywhere.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use ftwire_control::NoiseModel;
use serde::Serialize;

/// `--calibration FILE`: the learnt F/T calibration.
#[derive(Debug, Clone, Default, Args, Serialize)]
pub struct CalibrationArgs {
    /// Learnt calibration weights (`calibration.json`, from `ftwire experiment calibrate`).
    /// The experiments without it first run a calibration on the default known wire (this
    /// run's `--gravity` and `--seed`) and cache it in the results folder; `identify --log`
    /// and `shape --log` take records that carry `raw` through it, at each record's time
    /// (records with `a` are used as they are).
    #[arg(long = "calibration", id = "calibration", value_name = "FILE")]
    #[serde(rename = "calibration")]
    pub file: Option<PathBuf>,
}

impl CalibrationArgs {
    /// The file, if given.
    pub fn path(&self) -> Option<&Path> {
        self.file.as_deref()
    }
}

/// `--gravity-in-clamp X,Y,Z`: the loaded model of the wire, with its weight.
#[derive(Debug, Clone, Default, Args, Serialize)]
pub struct GravityInClampArgs {
    /// Gravity in the base clamp frame [m/s²] for the loaded model (the wire's weight; e.g.
    /// `0,0,-9.81` with the clamp level), norm above 0 and at most 100 [default: the
    /// weight-free model of the paper].
    #[arg(long = "gravity-in-clamp", id = "gravity_in_clamp", value_name = "X,Y,Z", value_parser = ftwire::args::parse_numbers::<3>, allow_hyphen_values = true)]
    #[serde(rename = "gravity_in_clamp", skip_serializing_if = "Option::is_none")]
    pub vector: Option<ftwire::args::Numbers<3>>,
}

impl GravityInClampArgs {
    /// The vector, if given.
    pub fn given(&self) -> Option<[f64; 3]> {
        self.vector.as_ref().map(|g| g.0)
    }
}

/// `--mounting FILE.toml`: a real sensor's mounting (and tool weight).
#[derive(Debug, Clone, Default, Args, Serialize)]
pub struct MountingArgs {
    /// The sensor's mounting (TOML: `clamp_position_in_sensor` [m], `clamp_rotation_in_sensor`
    /// [rad], optionally `tool_mass` [kg] and `tool_centre_of_mass` [m] for the tool's weight,
    /// taken out of `raw` with each record's `gravity`; `ftwire init` writes an example,
    /// `docs/config.md` lists the keys) [default: the simulated sensor's mounting]. In
    /// `identify --log` and `shape --log`, without --calibration, `raw` goes through the
    /// mounting alone (uncalibrated).
    #[arg(long = "mounting", id = "mounting", value_name = "FILE.toml")]
    #[serde(rename = "mounting", skip_serializing_if = "Option::is_none")]
    pub file: Option<PathBuf>,
}

impl MountingArgs {
    /// The mounting: the file's, or the default.
    ///
    /// # Errors
    /// Bad input naming the file, the line and the key.
    pub fn load(&self) -> Result<ftwire_estimate::ft::MountingSpec, ftwire_lab::LabError> {
        ftwire_lab::setup::mounting::load(self.file.as_deref())
            .map_err(|e| ftwire_lab::LabError::bad_input(format!("--mounting: {e}")))
    }

    /// The file's mounting, or `None` when `--mounting` is not given (the log commands then
    /// take `raw` readings through the calibration alone).
    ///
    /// # Errors
    /// As [`MountingArgs::load`].
    pub fn given(&self) -> Result<Option<ftwire_estimate::ft::MountingSpec>, ftwire_lab::LabError> {
        self.file.as_ref().map(|_| self.load()).transpose()
    }
}

/// `--scene FILE.toml`: a planning scene.
#[derive(Debug, Clone, Default, Args, Serialize)]
pub struct SceneArgs {
    /// The planning scene (TOML: boxes, base pose, start and goal; `docs/config.md`)
    /// [default for `demo` and `experiment passage`: the shipped 50 mm passage,
    /// `scenes/passage.toml`; `plan` needs one].
    #[arg(long = "scene", id = "scene", value_name = "FILE.toml")]
    #[serde(rename = "scene")]
    pub file: Option<PathBuf>,
}

impl SceneArgs {
    /// The file, if given.
    pub fn path(&self) -> Option<&Path> {
        self.file.as_deref()
    }
}

/// `--noise-model`: execution noise on the second gripper.
#[derive(Debug, Clone, Copy, Default, Args, Serialize)]
pub struct NoiseModelArgs {
    /// Execution noise on the second gripper (`ftwire_control::NoisyRig`): `increment`, the
    /// paper's, 10 mm and 3° on each step; `absolute`, each commanded pose off by a new
    /// 10 mm / 3°; `offset`, a real robot's, one unknown 10 mm / 3° calibration error plus
    /// fine repeatability, which the closed loop removes and the open loop cannot; `none`
    /// [default: `increment` in the experiments, `offset` in the demo].
    #[arg(
        long = "noise-model",
        id = "noise-model",
        value_enum,
        value_name = "MODEL"
    )]
    #[serde(rename = "noise_model")]
    pub model: Option<NoiseModelArg>,
}

impl NoiseModelArgs {
    /// The given model, or the command's `default`.
    pub fn or(&self, default: NoiseModelArg) -> NoiseModelArg {
        self.model.unwrap_or(default)
    }

    /// The library's model of [`NoiseModelArgs::or`].
    pub fn model_or(&self, default: NoiseModelArg) -> NoiseModel {
        self.or(default).model()
    }
}

/// The closed loop of the experiments that steer the wire (`goal`, `track`, `passage`): the
/// noise it runs under, the calibration it reads F/T through, the bias observer and the shape
/// stop.
#[derive(Debug, Clone, Args, Serialize)]
pub struct ClosedLoopArgs {
    /// The gripper noise of the noisy runs.
    #[command(flatten)]
    #[serde(flatten)]
    pub noise: NoiseModelArgs,
    /// The learnt calibration.
    #[command(flatten)]
    #[serde(flatten)]
    pub calibration: CalibrationArgs,
    /// Steer the closed loop without noise and under `offset` and `increment` by `ã` corrected
    /// for the F/T sensor's bias drift (`ftwire_control::BiasObserver`, from the model and the
    /// reported poses, one over a whole path), and without noise and under `increment`, where
    /// the robot knows where its gripper is, by each rest fused with that pose (`fuse_rest`);
    /// `off` steers by the tared `ã` alone.
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub bias_observer: OnOff,
    /// The closed loop's shape stop in mm: a run (`goal`'s noisy runs) or a leg (`track`,
    /// `passage`) ends once the model's shape at the measured `ã` is within this mean distance
    /// of the goal's (instead of the `ε` stop); 0 switches it off [default: 6 under
    /// `increment` and `absolute`, off otherwise]. Under `increment` and `absolute` a leg from
    /// or to a waypoint whose planned wire is within 25 mm of a box stops at no less than
    /// 10 mm (`--near-shape-stop`).
    #[arg(long, value_name = "MM", allow_hyphen_values = true, value_parser = ftwire::args::parse_finite)]
    pub shape_stop: Option<f64>,
}

impl ClosedLoopArgs {
    /// `--noise-model`, `increment` (the paper's) by default.
    pub fn noise_model(&self) -> NoiseModelArg {
        self.noise.or(NoiseModelArg::Increment)
    }
}

/// The execution noise of `ftwire experiment goal` (`--noise-model`; see
/// `ftwire_control::NoisyRig`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum NoiseModelArg {
    /// The paper's: N(0, 10 mm) and N(0, 3°) on each control output δb; accumulates.
    Increment,
    /// Each commanded pose perturbed independently by 10 mm / 3°.
    Absolute,
    /// One 10 mm / 3° offset per run plus 0.1 mm / 0.05° repeatability per move.
    Offset,
    /// None: the grippers go where they are commanded.
    None,
}

impl NoiseModelArg {
    /// The library's model.
    pub fn model(self) -> ftwire_control::NoiseModel {
        match self {
            Self::Increment => ftwire_control::NoiseModel::Increment,
            Self::Absolute => ftwire_control::NoiseModel::Absolute,
            Self::Offset => ftwire_control::NoiseModel::Offset,
            Self::None => ftwire_control::NoiseModel::None,
        }
    }
}

/// A switch (`on|off`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum OnOff {
    /// Switched on.
    On,
    /// Switched off.
    Off,
}

impl OnOff {
    /// Whether it is on.
    pub fn on(self) -> bool {
        self == Self::On
    }
}
