//! A scene's check ([`check_scene`]): is each named configuration in `Z_free` for the wire,
//! and are the start and the goal among them ([`SceneReport::require_endpoints`]).

use std::fmt;
use std::path::PathBuf;

use ftwire_plan::{PlanError, scene_configuration};
use serde::Serialize;

use super::{PlanWireParams, setup};
use crate::error::{LabError, from_plan};

/// The settings of a scene's check (`ftwire scene check`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneCheckParams {
    /// The scene file (TOML).
    pub file: PathBuf,
    /// The wire and the validity margins.
    pub wire: PlanWireParams,
    /// The start configuration's name in the scene.
    pub start: String,
    /// The goal configuration's name in the scene.
    pub goal: String,
}

/// One named configuration's verdict.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConfigurationCheck {
    /// The configuration's name in the scene.
    pub name: String,
    /// Whether it is in `Z_free`.
    pub valid: bool,
    /// Why not, when not valid.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// The wire surface's clearance from the nearest obstacle \[m\], when valid.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clearance: Option<f64>,
}

/// The answer of a scene's check: its obstacles and each configuration's verdict. Its
/// `Display` is the text `ftwire scene check` prints (each line ending in a newline); its
/// JSON is `ftwire scene check --json`'s.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneReport {
    /// The scene file, as given.
    pub scene: String,
    /// The wire's name.
    pub wire: String,
    /// The obstacles' names, in file order.
    pub obstacles: Vec<String>,
    /// The floor's height \[m\], if the scene has one.
    pub floor: Option<f64>,
    /// The start configuration's name.
    pub start: String,
    /// The goal configuration's name.
    pub goal: String,
    /// Every named configuration's verdict, in the scene's order of names.
    pub configurations: Vec<ConfigurationCheck>,
}

/// Checks every named configuration of the scene `params.file` against `Z_free` of the wire.
///
/// # Errors
/// Bad input for an unreadable scene, an unknown wire, or bad margins (as [`super::run`]).
/// A configuration outside `Z_free` is a verdict in the report, not an error (see
/// [`SceneReport::require_endpoints`]).
pub fn check_scene(params: &SceneCheckParams) -> Result<SceneReport, LabError> {
    let (scene, spec, checker) = setup(&params.file, &params.wire, crate::error::FrontEnd::Cli)?;
    let mut configurations = Vec::new();
    for name in scene.configurations.keys() {
        let verdict = scene_configuration(&scene, checker.rod(), name)
            .map_err(|e| e.to_string())
            .and_then(|c| checker.endpoint(&c).map_err(|e| e.to_string()));
        configurations.push(match verdict {
            Ok(s) => ConfigurationCheck {
                name: name.clone(),
                valid: true,
                reason: None,
                clearance: Some(s.clearance),
            },
            Err(reason) => ConfigurationCheck {
                name: name.clone(),
                valid: false,
                reason: Some(reason),
                clearance: None,
            },
        });
    }
    Ok(SceneReport {
        scene: params.file.display().to_string(),
        wire: spec.name.clone(),
        obstacles: scene.boxes.iter().map(|b| b.name.clone()).collect(),
        floor: scene.floor,
        start: params.start.clone(),
        goal: params.goal.clone(),
        configurations,
    })
}

impl SceneReport {
    /// Whether the start and the goal exist and are in `Z_free`.
    ///
    /// # Errors
    /// Bad input naming the first of them (`--start`, then `--goal`) that the scene lacks or
    /// that is outside `Z_free`, and why.
    pub fn require_endpoints(&self) -> Result<(), LabError> {
        for (role, name) in [("start", &self.start), ("goal", &self.goal)] {
            match self.configurations.iter().find(|c| &c.name == name) {
                None => {
                    let available: Vec<&str> = self
                        .configurations
                        .iter()
                        .map(|c| c.name.as_str())
                        .collect();
                    let error = PlanError::UnknownConfiguration {
                        name: name.clone(),
                        available: available.join(", "),
                    };
                    return Err(from_plan(error, &format!("--{role}")));
                }
                Some(c) if !c.valid => {
                    return Err(LabError::bad_input(format!(
                        "{}: {role} configuration {name:?} is not in Z_free: {}",
                        self.scene,
                        c.reason.as_deref().unwrap_or("?")
                    )));
                }
                Some(_) => {}
            }
        }
        Ok(())
    }
}

impl fmt::Display for SceneReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(out, "scene {} (wire {})", self.scene, self.wire)?;
        writeln!(out, "  obstacles: {}", self.obstacles.join(", "))?;
        if let Some(h) = self.floor {
            writeln!(out, "  floor at z = {h} m")?;
        }
        for c in &self.configurations {
            let role = if c.name == self.start {
                " (start)"
            } else if c.name == self.goal {
                " (goal)"
            } else {
                ""
            };
            match (&c.reason, c.clearance) {
                (None, Some(cl)) => writeln!(
                    out,
                    "  {}{role}: in Z_free, clearance {:.1} mm",
                    c.name,
                    cl * 1e3
                )?,
                (reason, _) => writeln!(
                    out,
                    "  {}{role}: NOT in Z_free: {}",
                    c.name,
                    reason.as_deref().unwrap_or("?")
                )?,
            }
        }
        Ok(())
    }
}
