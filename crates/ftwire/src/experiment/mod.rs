//! What the experiments of paper §IV share: the common options' values, the simulated rig they
//! run against, and the F/T measurement a real robot would make.
//!
//! The true wire is given to the simulator only; the estimators see what a real rig gives them
//! (raw F/T samples and the believed gripper poses).

pub mod calibration;
pub mod rig;
pub mod track;

use clap::ValueEnum;
use ftwire_estimate::KirchhoffModel;
use ftwire_rod::Load;
use nalgebra::Vector3;
use serde::Serialize;

use crate::error::{CliError, from_rod};
use crate::wire::WireSpec;

/// Gravity in the simulated world (`--gravity on|off`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
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

/// Edges of the simulated rod in the experiments: the resolution at which DESIGN.md's agreed
/// accuracy of the simulator against the model holds (N = 100).
pub const SIM_EDGES: usize = 100;

/// The wire model an experiment's estimators use (`--model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ModelKind {
    /// The paper's model: a weightless Kirchhoff rod, straight at rest.
    Kirchhoff,
    /// The loaded Kirchhoff rod (beyond the paper): the wire's weight under gravity and its rest
    /// curvature (`ftwire_rod::Load`).
    Loaded,
}

impl ModelKind {
    /// `--model`, or its default for `gravity`: `loaded` when gravity is on, `kirchhoff`
    /// when it is off (issue 16).
    pub fn resolve(given: Option<Self>, gravity: Gravity) -> Self {
        match (given, gravity) {
            (Some(model), _) => model,
            (None, Gravity::On) => Self::Loaded,
            (None, Gravity::Off) => Self::Kirchhoff,
        }
    }

    /// The model's name in tables and summaries.
    pub fn name(self) -> &'static str {
        match self {
            Self::Kirchhoff => "kirchhoff",
            Self::Loaded => "loaded",
        }
    }

    /// The other model.
    pub fn other(self) -> Self {
        match self {
            Self::Kirchhoff => Self::Loaded,
            Self::Loaded => Self::Kirchhoff,
        }
    }
}

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
) -> Result<KirchhoffModel, CliError> {
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
) -> Result<KirchhoffModel, CliError> {
    let params = wire
        .wire_params()
        .map_err(|e| CliError::bad_input(format!("wire {}: {e}", wire.name)))?;
    let model = KirchhoffModel::new(params);
    match kind {
        ModelKind::Kirchhoff => Ok(model),
        ModelKind::Loaded => {
            let load = Load::from_gravity(wire.density, wire.radius, g_clamp)
                .and_then(|load| load.with_natural_curvature(Vector3::from(wire.natural_curvature)))
                .map_err(|e| from_rod(e, "the loaded model of the wire"))?;
            Ok(model.with_load(load))
        }
    }
}
