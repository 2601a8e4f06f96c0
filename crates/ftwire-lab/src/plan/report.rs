//! The answer of a plan ([`PlanReport`]): the path's waypoints with their gripper poses, the
//! robot's joints and the clearance, as JSON (serde) and as text (`Display`).

use std::fmt;

use ftwire_core::Pose;
use ftwire_plan::Sample;
use ftwire_rod::{Rod, to_normalised};
use serde::Serialize;

use super::planner::Planner;

/// A pose as JSON: position \[m\] and rotation vector \[rad\], world frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PoseJson {
    /// The position \[m\].
    pub position: [f64; 3],
    /// The rotation as a rotation vector (axis times angle) \[rad\].
    pub rotation: [f64; 3],
}

impl From<&Pose> for PoseJson {
    fn from(p: &Pose) -> Self {
        let (t, r) = (p.translation.vector, p.rotation.scaled_axis());
        Self {
            position: [t.x, t.y, t.z],
            rotation: [r.x, r.y, r.z],
        }
    }
}

/// The robot's joints as JSON \[rad\].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointsJson {
    /// The torso joint \[rad\].
    pub torso: f64,
    /// The left arm's joints, shoulder first \[rad\].
    pub left: Vec<f64>,
    /// The right arm's joints, shoulder first \[rad\].
    pub right: Vec<f64>,
}

/// One waypoint of a path.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WaypointJson {
    /// `a` \[N·m, N\], torque first, base clamp frame.
    pub a: Vec<f64>,
    /// `a` in normalised units.
    pub a_normalised: Vec<f64>,
    /// World from the base gripper's clamp frame.
    pub base: PoseJson,
    /// World from the second gripper's clamp frame.
    pub tip: PoseJson,
    /// The robot's joints that hold both grippers there.
    pub joints: JointsJson,
    /// The wire surface's clearance from the nearest obstacle \[m\] (capped at 0.1).
    pub clearance: f64,
}

impl WaypointJson {
    /// The waypoint of sample `s` of a path planned with `rod`'s wire.
    pub fn new(rod: &Rod, s: &Sample) -> Self {
        Self {
            a: s.config.a.as_slice().to_vec(),
            a_normalised: to_normalised(rod.wire(), &s.config.a).as_slice().to_vec(),
            base: (&s.config.base).into(),
            tip: (&s.tip).into(),
            joints: JointsJson {
                torso: s.joints.torso,
                left: s.joints.left.as_slice().to_vec(),
                right: s.joints.right.as_slice().to_vec(),
            },
            clearance: s.clearance,
        }
    }
}

/// The answer of a plan ([`super::run`]): the search's counts and times, the path's measures
/// and its waypoints. Its `Display` is the text `ftwire plan` prints (one line per waypoint,
/// each line ending in a newline); its JSON is `ftwire plan --json`'s.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanReport {
    /// The scene file, as given.
    pub scene: String,
    /// The wire's name.
    pub wire: String,
    /// The planning space.
    pub planner: Planner,
    /// The planner's seed.
    pub seed: u64,
    /// The start configuration's name in the scene.
    pub start: String,
    /// The goal configuration's name in the scene.
    pub goal: String,
    /// RRT* iterations run.
    pub iterations: usize,
    /// Nodes in the tree at the end.
    pub nodes: usize,
    /// The iteration that found the first path.
    pub first_path_iteration: usize,
    /// Wall time to the first path \[s\].
    pub first_path_seconds: f64,
    /// Wall time of the whole search \[s\].
    pub seconds: f64,
    /// The path's cost (its length with the clearance penalty).
    pub cost: f64,
    /// Path length in normalised `a`.
    pub length: f64,
    /// How far the base gripper travels \[m\].
    pub base_travel: f64,
    /// The smallest clearance along the path, edges included \[m\].
    pub min_clearance: f64,
    /// The path's waypoints, start to goal.
    pub waypoints: Vec<WaypointJson>,
    /// The path resampled into equally spaced waypoints, when asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resampled: Option<Vec<WaypointJson>>,
}

impl fmt::Display for PlanReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            out,
            "path from {:?} to {:?} in {} ({} planner, wire {}, seed {})",
            self.start, self.goal, self.scene, self.planner, self.wire, self.seed
        )?;
        writeln!(
            out,
            "  first path after {} iterations, {:.3} s; {} iterations, {} nodes, {:.3} s in all",
            self.first_path_iteration,
            self.first_path_seconds,
            self.iterations,
            self.nodes,
            self.seconds
        )?;
        writeln!(
            out,
            "  {} waypoints, length {:.3} (normalised a), cost {:.3}, base travel {:.3} m, \
             smallest clearance {:.1} mm",
            self.waypoints.len(),
            self.length,
            self.cost,
            self.base_travel,
            self.min_clearance * 1e3
        )?;
        for (i, w) in self.waypoints.iter().enumerate() {
            let a: Vec<String> = w.a_normalised.iter().map(|v| format!("{v:.3}")).collect();
            writeln!(out, "  {i:3}  a/scale = [{}]", a.join(", "))?;
        }
        Ok(())
    }
}
