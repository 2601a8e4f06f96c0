//! What the experiments of paper §IV share: the common options' values, the simulated rig they
//! run against, the F/T measurement a real robot would make, and the summary statistics
//! ([`stats`]), and the ranges of their counts ([`limits`]).
//!
//! The true wire is given to the simulator only; the estimators see what a real rig gives them
//! (raw F/T samples and the believed gripper poses).

pub mod calibration;
pub mod coverage;
pub mod limits;
pub mod rig;
pub mod stats;

use ftwire_estimate::KirchhoffModel;
use ftwire_rod::Load;
use nalgebra::Vector3;
use serde::Serialize;

use crate::error::{LabError, from_rod};
use crate::wire::WireSpec;

/// Gravity in the simulated world (`--gravity on|off`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Gravity {
    /// Standard gravity, `(0, 0, −9.81)` m/s² in the world frame.
    On,
    /// No gravity: the paper's model assumption holds exactly.
    Off,
}

impl Gravity {
    /// The gravity vector \[m/s²\] in the world frame.
    pub fn vector(self) -> Vector3<f64> {
        match self {
            Self::On => Vector3::new(0.0, 0.0, -9.81),
            Self::Off => Vector3::zeros(),
        }
    }
}

impl Gravity {
    /// Every value's name, as `--gravity` takes it.
    pub const NAMES: [&'static str; 2] = ["on", "off"];

    /// The value's name (`on`, `off`).
    pub fn name(self) -> &'static str {
        match self {
            Self::On => "on",
            Self::Off => "off",
        }
    }
}

impl std::fmt::Display for Gravity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Gravity {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text {
            "on" => Ok(Self::On),
            "off" => Ok(Self::Off),
            _ => Err(format!("gravity {text:?}: expected on or off")),
        }
    }
}

/// Edges of the simulated rod in the experiments: the resolution at which DESIGN.md's agreed
/// accuracy of the simulator against the model holds (N = 100).
pub const SIM_EDGES: usize = 100;

pub use ftwire_rig::ModelKind;

/// The model of a wire whose parameters are known (the calibration wire, or the wire of a
/// shape experiment, whose `c` and `L` were identified before): the paper's weightless rod,
/// or the loaded rod with the wire's weight `ρ π r² g` under the experiment's gravity (the
/// rig's base clamp sits at the world origin with the world's axes, so gravity in the base
/// clamp frame is the world's) and its natural curvature.
///
/// # Errors
/// Bad input for a wire whose parameters are not valid.
pub fn known_model(
    wire: &WireSpec,
    gravity: Gravity,
    kind: ModelKind,
) -> Result<KirchhoffModel, LabError> {
    known_model_under(wire, gravity.vector(), kind)
}

/// [`known_model`] with gravity `g_clamp` \[m/s²\] given in the base clamp frame (a base
/// clamp turned from the world's axes, as in a scene).
///
/// # Errors
/// Bad input for a wire whose parameters are not valid.
pub fn known_model_under(
    wire: &WireSpec,
    g_clamp: Vector3<f64>,
    kind: ModelKind,
) -> Result<KirchhoffModel, LabError> {
    let params = wire
        .wire_params()
        .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?;
    let model = KirchhoffModel::new(params);
    match kind {
        ModelKind::Weightless => Ok(model),
        ModelKind::Loaded => {
            let load = Load::from_gravity(wire.density, wire.radius, g_clamp)
                .and_then(|load| load.with_natural_curvature(Vector3::from(wire.natural_curvature)))
                .map_err(|e| from_rod(e, "the loaded model of the wire"))?;
            Ok(model.with_load(load))
        }
    }
}

/// The settings every experiment takes (the `ftwire experiment` options of the same names).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CommonParams {
    /// A wire preset or a wire file (TOML) replacing the experiment's default wires; `None`:
    /// the experiment's own.
    pub wire: Option<String>,
    /// The seed of every random choice.
    pub seed: u64,
    /// Trials (for `calibrate`, configurations visited); `None`: the experiment's default.
    pub trials: Option<usize>,
    /// Gravity in the simulated world.
    pub gravity: Gravity,
    /// The estimators' wire model; `None`: [`ModelKind::resolve`]'s default for `gravity`.
    pub model: Option<ModelKind>,
    /// The simulated F/T sensor: a preset name or a sensor file; `None`: the default sensor.
    pub sensor: Option<String>,
    /// The simulated rig file; `None`: the library's rig.
    pub rig: Option<std::path::PathBuf>,
    /// How a calibration session is recorded (the calibration an experiment collects).
    pub protocol: crate::setup::Protocol,
}

impl Default for CommonParams {
    fn default() -> Self {
        Self {
            wire: None,
            seed: 0,
            trials: None,
            gravity: Gravity::On,
            model: None,
            sensor: None,
            rig: None,
            protocol: crate::setup::Protocol::default(),
        }
    }
}

impl CommonParams {
    /// The estimators' model: the given one, or its default for the gravity.
    pub fn model(&self) -> ModelKind {
        ModelKind::resolve(self.model, self.gravity == Gravity::On)
    }

    /// The given wire, or the experiment's `default` wire (a preset name or a file).
    ///
    /// # Errors
    /// Bad input for an unknown preset or a bad wire file.
    pub fn wire_or(&self, default: &str) -> Result<WireSpec, LabError> {
        let name = self.wire.as_deref().unwrap_or(default);
        WireSpec::load(name).map_err(|e| LabError::bad_input(e.to_string()))
    }

    /// `other` with this run's input files (the wire, sensor and rig files, as `--wire`,
    /// `--sensor`, `--rig`): the results folder must not hold any of them.
    pub fn inputs(&self, other: crate::results::OutGuard) -> crate::results::OutGuard {
        other
            .input_opt("--wire", self.wire.as_deref())
            .input_opt("--sensor", self.sensor.as_deref())
            .input_opt("--rig", self.rig.as_deref())
    }

    /// The simulated sensor and rig.
    ///
    /// # Errors
    /// Bad input naming the file, the line and the key.
    pub fn setup(&self) -> Result<crate::setup::SimSetup, LabError> {
        crate::setup::SimSetup::load(self.sensor.as_deref(), self.rig.as_deref())
            .map(|s| s.with_protocol(self.protocol))
            .map_err(|e| LabError::bad_input(e.to_string()))
    }
}

pub use ftwire_app::Progress;
