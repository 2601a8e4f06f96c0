//! Scenes: where the base gripper is, the obstacles, and the named start and goal
//! configurations, read from a TOML file.
//!
//! Every pose is in the robot's world frame, the SDA10F's base frame (`torso_base_link`),
//! in metres and radians (rotation vectors). A scene file:
//!
//! ```toml
//! [base]                          # the base gripper's clamp pose (the F/T sensor's gripper)
//! position = [0.45, 0.20, 0.95]   # [m]
//! rotation = [0.0, 0.0, 0.0]      # rotation vector [rad] (default 0)
//!
//! [floor]                         # optional: the half-space below `height` is solid
//! height = 0.0                    # [m], world z
//!
//! [[obstacle]]                    # any number of boxes
//! name = "left block"             # optional, used in messages
//! centre = [0.9, 0.3, 0.9]        # [m]
//! half_extents = [0.1, 0.2, 0.1]  # [m], each > 0
//! rotation = [0.0, 0.0, 0.0]      # rotation vector [rad] (default 0)
//!
//! [configuration.start]           # each named configuration is exactly one of:
//! a = [0.0, 0.1, 0.0, -0.1, 0.0, 0.2]          # a [N·m, N], torque first, base clamp frame
//! [configuration.goal]
//! a_normalised = [0.0, -2.0, 0.0, 1.0, 0.0, 3.0] # a in units of c2/L and c2/L² (any wire)
//! [configuration.elsewhere]
//! tip = { position = [1.2, 0.2, 0.95], rotation = [0.0, 0.0, 3.14] }  # second gripper, world
//! ```
//!
//! Unknown keys, non-finite numbers, rotation vectors of angle beyond
//! `ftwire_core::MAX_ROTATION_ANGLE` and non-positive half extents are errors that name the file,
//! the line and the key or item ([`Scene::from_toml`]). The file is UTF-8 text, a leading
//! byte-order mark allowed (`ftwire_core::text::read_text`).

use std::collections::BTreeMap;
use std::path::Path;

use ftwire_core::{Pose, ensure_rotation_vector};
use ftwire_robot::OrientedBox;
use nalgebra::{Translation3, UnitQuaternion, Vector3, Vector6};
use serde::Deserialize;
use toml::Spanned;

use crate::PlanError;

/// A pose as written in a scene: position and rotation vector.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct PoseToml {
    position: [f64; 3],
    #[serde(default)]
    rotation: [f64; 3],
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FloorToml {
    height: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ObstacleToml {
    name: Option<String>,
    centre: [f64; 3],
    half_extents: [f64; 3],
    #[serde(default)]
    rotation: [f64; 3],
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ConfigurationToml {
    a: Option<[f64; 6]>,
    a_normalised: Option<[f64; 6]>,
    tip: Option<PoseToml>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneToml {
    base: Spanned<PoseToml>,
    floor: Option<Spanned<FloorToml>>,
    #[serde(default)]
    obstacle: Vec<Spanned<ObstacleToml>>,
    #[serde(default)]
    configuration: BTreeMap<String, Spanned<ConfigurationToml>>,
}

/// A box obstacle of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneBox {
    /// Its name (default `obstacle N`, N counted from 1 in file order).
    pub name: String,
    /// The box: world from box (centre \[m\] and orientation; its edges are its axes) and
    /// half extents \[m\], each positive.
    pub geometry: OrientedBox,
}

/// How a named configuration is given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ConfigurationSpec {
    /// A configuration `a` \[N·m, N\] (torque first, base clamp frame).
    A(Vector6<f64>),
    /// A configuration in normalised units (torque / (c2/L), force / (c2/L²)), wire-independent.
    Normalised(Vector6<f64>),
    /// The second gripper's clamp pose in the world frame; the planner finds an `a` for it.
    Tip(Pose),
}

/// A scene: base gripper pose, obstacles, floor, named configurations.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// World from the base gripper's clamp frame.
    pub base: Pose,
    /// Box obstacles.
    pub boxes: Vec<SceneBox>,
    /// Height \[m\] of the floor (world z), if there is one: `z < height` is solid.
    pub floor: Option<f64>,
    /// The named configurations, by name.
    pub configurations: BTreeMap<String, ConfigurationSpec>,
}

/// The line numbers of a text's byte offsets: the offsets of its newlines, found once, so that
/// each look-up is a binary search (a scene of `n` items is read in `O(n log n)`, not by
/// counting from the start of the file for every item).
struct Lines {
    newlines: Vec<usize>,
}

impl Lines {
    fn new(text: &str) -> Self {
        Self {
            newlines: text
                .bytes()
                .enumerate()
                .filter_map(|(i, b)| (b == b'\n').then_some(i))
                .collect(),
        }
    }

    /// Line number (from 1) of byte `offset`: one more than the newlines before it.
    fn of(&self, offset: usize) -> usize {
        self.newlines.partition_point(|&i| i < offset) + 1
    }
}

fn pose_of(position: [f64; 3], rotation: [f64; 3]) -> Pose {
    Pose::from_parts(
        Translation3::new(position[0], position[1], position[2]),
        UnitQuaternion::from_scaled_axis(Vector3::from(rotation)),
    )
}

impl Scene {
    /// Reads a scene file.
    ///
    /// # Errors
    /// [`PlanError::Read`] if the file cannot be read, [`PlanError::Scene`] with the line and
    /// column if it is not UTF-8, else as [`Scene::from_toml`].
    pub fn load(path: impl AsRef<Path>) -> Result<Self, PlanError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = ftwire_core::text::read_text(path).map_err(|e| match e {
            ftwire_core::CoreError::Unreadable { message } => PlanError::Read {
                file: file.clone(),
                message,
            },
            e => PlanError::Scene {
                file: file.clone(),
                message: e.to_string(),
            },
        })?;
        Self::from_toml(&text, &file)
    }

    /// Parses a scene from TOML text; `file` names it in error messages.
    ///
    /// # Errors
    /// [`PlanError::Scene`] naming the file, the line and the key or item for malformed TOML,
    /// an unknown key, a missing key, a non-finite number, a rotation vector whose angle exceeds
    /// `ftwire_core::MAX_ROTATION_ANGLE`, a non-positive half extent, or a
    /// configuration that does not give exactly one of `a`, `a_normalised`, `tip`.
    ///
    /// # Example
    /// ```
    /// use ftwire_plan::Scene;
    /// let text = "[base]\nposition = [0.4, 0.2, 0.9]\n\n[[obstacle]]\ncentre = [1, 0, 0]\nhalf_extents = [0.1, 0.1, 0.1]\n";
    /// let scene = Scene::from_toml(text, "demo.toml")?;
    /// assert_eq!(scene.boxes.len(), 1);
    /// let bad = text.replace("0.1, 0.1, 0.1", "0.1, 0.0, 0.1");
    /// let message = Scene::from_toml(&bad, "demo.toml").unwrap_err().to_string();
    /// assert!(message.contains("demo.toml") && message.contains("line 4") && message.contains("half_extents"));
    /// # Ok::<(), ftwire_plan::PlanError>(())
    /// ```
    pub fn from_toml(text: &str, file: &str) -> Result<Self, PlanError> {
        let bad = |message: String| PlanError::Scene {
            file: file.to_string(),
            message,
        };
        let lines = Lines::new(text);
        let line_of = |offset: usize| lines.of(offset);
        let raw: SceneToml = toml::from_str(text).map_err(|e| {
            let line = e.span().map(|s| line_of(s.start));
            let what = e.message().trim_end().to_string();
            bad(match line {
                Some(l) => format!("line {l}: {what}"),
                None => what,
            })
        })?;
        let finite = |line: usize, item: &str, key: &str, values: &[f64]| match values
            .iter()
            .position(|v| !v.is_finite())
        {
            Some(i) => Err(bad(format!(
                "line {line}: {item}: {key}[{i}] = {} is not a finite number",
                values[i]
            ))),
            None => Ok(()),
        };

        // A rotation vector's angle is bounded too (`ftwire_core::MAX_ROTATION_ANGLE`).
        let rotation = |line: usize, item: &str, key: &'static str, values: &[f64; 3]| {
            finite(line, item, key, values)?;
            ensure_rotation_vector(key, values)
                .map_err(|e| bad(format!("line {line}: {item}: {e}")))
        };

        let base_line = line_of(raw.base.span().start);
        let base = raw.base.get_ref();
        finite(base_line, "[base]", "position", &base.position)?;
        rotation(base_line, "[base]", "rotation", &base.rotation)?;
        let base = pose_of(base.position, base.rotation);

        let floor = match &raw.floor {
            Some(f) => {
                let line = line_of(f.span().start);
                finite(line, "[floor]", "height", &[f.get_ref().height])?;
                Some(f.get_ref().height)
            }
            None => None,
        };

        let mut boxes = Vec::with_capacity(raw.obstacle.len());
        for (i, spanned) in raw.obstacle.iter().enumerate() {
            let line = line_of(spanned.span().start);
            let o = spanned.get_ref();
            let name = o
                .name
                .clone()
                .unwrap_or_else(|| format!("obstacle {}", i + 1));
            let item = format!("obstacle {:?}", name);
            finite(line, &item, "centre", &o.centre)?;
            finite(line, &item, "half_extents", &o.half_extents)?;
            rotation(line, &item, "rotation", &o.rotation)?;
            if let Some(k) = o.half_extents.iter().position(|&h| h <= 0.0) {
                return Err(bad(format!(
                    "line {line}: {item}: half_extents[{k}] = {} m must be positive",
                    o.half_extents[k]
                )));
            }
            let geometry =
                OrientedBox::new(pose_of(o.centre, o.rotation), Vector3::from(o.half_extents))
                    .map_err(|e| bad(format!("line {line}: {item}: {e}")))?;
            boxes.push(SceneBox { name, geometry });
        }

        let mut configurations = BTreeMap::new();
        for (name, spanned) in &raw.configuration {
            let line = line_of(spanned.span().start);
            let c = spanned.get_ref();
            let item = format!("configuration {name:?}");
            let spec = match (&c.a, &c.a_normalised, &c.tip) {
                (Some(a), None, None) => {
                    finite(line, &item, "a", a)?;
                    ConfigurationSpec::A(Vector6::from_row_slice(a))
                }
                (None, Some(a), None) => {
                    finite(line, &item, "a_normalised", a)?;
                    ConfigurationSpec::Normalised(Vector6::from_row_slice(a))
                }
                (None, None, Some(t)) => {
                    finite(line, &item, "tip.position", &t.position)?;
                    rotation(line, &item, "tip.rotation", &t.rotation)?;
                    ConfigurationSpec::Tip(pose_of(t.position, t.rotation))
                }
                _ => {
                    return Err(bad(format!(
                        "line {line}: {item}: give exactly one of `a`, `a_normalised`, `tip`"
                    )));
                }
            };
            configurations.insert(name.clone(), spec);
        }
        Ok(Self {
            base,
            boxes,
            floor,
            configurations,
        })
    }

    /// The named configuration.
    ///
    /// # Errors
    /// [`PlanError::UnknownConfiguration`] listing the names the scene has.
    pub fn configuration(&self, name: &str) -> Result<&ConfigurationSpec, PlanError> {
        self.configurations
            .get(name)
            .ok_or_else(|| PlanError::UnknownConfiguration {
                name: name.to_string(),
                available: self
                    .configurations
                    .keys()
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }

    /// The boxes as [`OrientedBox`]es, in file order.
    pub fn oriented_boxes(&self) -> Vec<OrientedBox> {
        self.boxes.iter().map(|b| b.geometry).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_numbers_count_the_newlines_before_the_offset() {
        let text = "a\nbc\n\n\u{e9}d\ne";
        let lines = Lines::new(text);
        for offset in 0..=text.len() {
            let naive = text.as_bytes()[..offset]
                .iter()
                .filter(|&&b| b == b'\n')
                .count()
                + 1;
            assert_eq!(lines.of(offset), naive, "offset {offset}");
        }
    }

    /// Many obstacles: the error on the last one names its line.
    #[test]
    fn an_error_in_the_last_of_many_obstacles_names_its_line() {
        let count = 5000;
        let mut text = String::from("[base]\nposition = [0.4, 0.2, 0.9]\n");
        for k in 0..count {
            let half = if k + 1 == count { "0.0" } else { "0.1" };
            text.push_str(&format!(
                "[[obstacle]]\ncentre = [{k}, 0, 0]\nhalf_extents = [0.1, {half}, 0.1]\n"
            ));
        }
        let message = Scene::from_toml(&text, "many.toml")
            .expect_err("a flat box")
            .to_string();
        // Two lines of [base], then three lines per obstacle.
        let line = 2 + 3 * (count - 1) + 1;
        assert!(
            message.contains(&format!("line {line}: obstacle \"obstacle {count}\"")),
            "{message}"
        );
        assert!(message.contains("half_extents[1]"), "{message}");
    }
}
