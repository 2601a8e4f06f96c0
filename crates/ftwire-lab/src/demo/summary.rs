//! What the demo reports: `summary.json`'s body ([`DemoSummary`], one part per phase) and
//! `timings.json` ([`DemoTimings`]).

use ftwire_plan::{ChoiceOut, PolishOut};
use serde::Serialize;

use crate::tracking::Attempt;

/// `summary.json`'s body (after the run header): the same for the same seed.
#[derive(Debug, Clone, Serialize)]
pub struct DemoSummary {
    /// The wire identified (the truth, which only the simulator was given).
    pub wire: WireTruth,
    /// Phase 1: the calibration on the known wire.
    pub calibration: CalibrationOut,
    /// Phase 2: the identification of the wire.
    pub identification: IdentificationOut,
    /// Phase 3: the shape from F/T.
    pub shape: ShapeOut,
    /// Phase 4: the plan through the scene.
    pub plan: PlanOut,
    /// Phase 5: the plan tracked closed and open loop.
    pub tracking: TrackingOut,
}

/// The plan through the scene, in the summary.
#[derive(Debug, Clone, Serialize)]
pub struct PlanOut {
    /// The scene file (or `scenes/passage.toml` for the built-in one).
    pub scene: String,
    /// RRT* iterations of the plan found.
    pub iterations: usize,
    /// Tree nodes of the plan found.
    pub nodes: usize,
    /// Cost and length of the path in normalised `A`.
    pub cost: f64,
    /// Smallest clearance of the wire from an obstacle along the path \[m\].
    pub min_clearance: f64,
    /// Waypoints tracked.
    pub waypoints: usize,
    /// The clearance polish of the tracked waypoints (`ftwire_plan::polish_waypoints`), under the
    /// noises that scatter every landing (`increment`, `absolute`); `null` otherwise, where
    /// the loop converges onto the plan.
    pub polish: Option<PolishOut>,
    /// How the plan was chosen among `ftwire_plan::PLAN_CANDIDATES` under the same noises
    /// (`ftwire_plan::choose_plan`); `null` otherwise.
    pub choice: Option<ChoiceOut>,
}

/// The plan tracked, in the summary.
#[derive(Debug, Clone, Serialize)]
pub struct TrackingOut {
    /// The execution noise's name (`ftwire_control::NoiseModel::name`).
    pub noise_model: &'static str,
    /// The collision detector's threshold on its residual (`ftwire_control::collision`).
    pub detector_threshold: f64,
    /// The controller from waypoint to waypoint, the collision detector armed.
    pub closed_loop: Attempt,
    /// The planned gripper poses rolled out with no feedback.
    pub open_loop: Attempt,
}

/// The true wire, in the summary.
#[derive(Debug, Clone, Serialize)]
pub struct WireTruth {
    /// The wire's name.
    pub name: String,
    /// Its stiffnesses `(c1, c2, c3)` \[N·m²\].
    pub c: [f64; 3],
    /// Its length \[m\].
    pub length: f64,
    /// Its weight per length \[kg/m\].
    pub linear_density: f64,
}

/// The calibration on the known wire, in the summary.
#[derive(Debug, Clone, Serialize)]
pub struct CalibrationOut {
    /// The known wire's name.
    pub wire: String,
    /// Configurations collected (those the simulator could not hold are skipped).
    pub configurations: usize,
    /// Relative error of the torque of `ã` on the test split, raw (mounting only).
    pub raw_torque_rel: f64,
    /// As `raw_torque_rel`, the force.
    pub raw_force_rel: f64,
    /// Relative error of the torque of `ã` on the test split, calibrated.
    pub calibrated_torque_rel: f64,
    /// As `calibrated_torque_rel`, the force.
    pub calibrated_force_rel: f64,
}

/// The identification of the wire, in the summary.
#[derive(Debug, Clone, Serialize)]
pub struct IdentificationOut {
    /// Samples identified from.
    pub samples: usize,
    /// `(c1, c2, c3, L)` estimated.
    pub estimate: [f64; 4],
    /// One standard deviation of each.
    pub std: [f64; 4],
    /// `(estimate − truth) / truth` of each.
    pub relative_error: [f64; 4],
    /// The weight per length estimated \[kg/m\] (`null` when the model identifies none).
    pub linear_density: Option<f64>,
    /// Its `(estimate − truth) / truth`.
    pub linear_density_relative_error: Option<f64>,
    /// `χ²` per degree of freedom of the fit.
    pub chi2_per_dof: f64,
    /// Why the estimate is not trusted (`null`: identified).
    pub flag: Option<&'static str>,
}

/// The shape from F/T, in the summary.
#[derive(Debug, Clone, Serialize)]
pub struct ShapeOut {
    /// Configurations estimated (of [`super::DemoParams::shape_configs`]; a placement the
    /// simulator cannot hold is skipped).
    pub configurations: usize,
    /// Mean distance between the estimated and the true centreline \[mm\], per configuration.
    pub mean_mm: Vec<f64>,
    /// Their mean \[mm\].
    pub mean_mm_overall: f64,
}

/// `timings.json`: wall time of each phase \[s\].
#[derive(Debug, Clone, Serialize)]
pub struct DemoTimings {
    /// Phase 1, the calibration \[s\].
    pub calibrate_s: f64,
    /// Phase 2, the identification \[s\].
    pub identify_s: f64,
    /// Phase 3, the shape from F/T \[s\].
    pub shape_s: f64,
    /// Phase 4, the plan \[s\].
    pub plan_s: f64,
    /// Each plan candidate's planning alone \[ms\] when the plan was chosen among
    /// candidates (`plan.choice` in the summary), `null` otherwise.
    pub candidate_plan_ms: Option<Vec<Option<f64>>>,
    /// Phase 5, the tracking \[s\].
    pub track_s: f64,
    /// The whole run \[s\].
    pub total_s: f64,
}
