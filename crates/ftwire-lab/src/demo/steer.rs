//! The demo's phases 4–5, what the robot does with the identified wire: the plan through the
//! scene, and the plan tracked closed loop, then open loop, with the figure `tracking`.

use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_plan::{Chosen, Scene, Waypoint};
use ftwire_report::{Chart3d, SeriesKind};
use ftwire_rod::Rod;

use super::inputs::Inputs;
use super::phase::{DemoProgress, Phase};
use super::summary::{IdentificationOut, PlanOut, TrackingOut};
use crate::error::{LabError, from_estimate};
use crate::experiment::Gravity;
use crate::results::ResultsFolder;
use crate::scene::box_outline;
use crate::tracking::{Attempt, PlanFailure, Tracking, plan_policy, reexpress};

/// Rests of the closed-loop run drawn in `tracking.png`.
const FIGURE_RESTS: usize = 7;

/// What phase 4 gives.
pub(super) struct Planned {
    /// What the summary keeps.
    pub out: PlanOut,
    /// The chosen plan, with its tracked waypoints.
    pub chosen: Chosen,
    /// The controller's model: the identified one, with gravity in the base clamp frame.
    pub controller_model: KirchhoffModel,
    /// The phase's wall time \[s\].
    pub seconds: f64,
}

/// Phase 4: the plan through the scene for the identified wire (`model`), chosen among
/// candidates where the noise scatters every landing.
pub(super) fn plan(
    inputs: &Inputs,
    model: &KirchhoffModel,
    identification: &IdentificationOut,
    progress: &mut dyn DemoProgress,
) -> Result<Planned, LabError> {
    let Inputs {
        scene,
        scene_name,
        noise,
        seed,
        ..
    } = inputs;
    let phase = Phase::start(progress, 4, "plan through the passage", 1);
    // The controller's model: the identified one, with gravity in the base clamp frame. Where
    // the plan keeps a distance from the folds (under `increment` and `absolute`), it keeps it
    // on this model's, as the passage experiment does.
    let g_clamp = scene.base.rotation.inverse() * Gravity::On.vector();
    let weight = identification.linear_density.unwrap_or(0.0) * g_clamp;
    let controller_model = model
        .with_weight_per_length(weight)
        .map_err(|e| from_estimate(e, "the identified wire's weight"))?;
    // The planner checks shapes with the identified wire's weightless model, as the scene's
    // configurations are the paper model's: with the loaded model's shapes, the fixed
    // iteration budget can find no path for some identified wires. The wire sags a few
    // millimetres from those shapes; the controller tracks the configurations with the
    // loaded model.
    let identified = Rod::new(*model.wire());
    // Under the noises that scatter every landing, the best of `ftwire_plan::PLAN_CANDIDATES`
    // plans by their expected touches, each with its tight waypoints polished away from the
    // boxes (as the passage experiment does). The plan's poses take the loaded model's
    // configurations and shapes: the controller steers to where the plan puts the grippers,
    // and the shape error is against the wire that sags.
    let plans = plan_policy(*noise);
    let chosen = ftwire_plan::choose_plan(
        scene,
        &identified,
        controller_model.rod(),
        plans.validity_tracked(controller_model.rod()),
        &plans,
        *seed,
        ftwire_plan::PLAN_CANDIDATES,
        plans.polishes(),
        |planned| {
            reexpress(&planned.waypoints, &controller_model, &scene.base).map_err(PlanFailure)
        },
    )?;
    let planned = &chosen.planned;
    let out = PlanOut {
        scene: scene_name.clone(),
        iterations: planned.plan.iterations,
        nodes: planned.plan.nodes,
        cost: planned.plan.path.cost,
        min_clearance: planned.plan.path.min_clearance(),
        waypoints: planned.waypoints.len(),
        polish: chosen.polish,
        choice: chosen.choice.clone(),
    };
    let chosen_of = out.choice.as_ref().map_or(String::new(), |c| {
        format!(
            ", plan {} of {} by expected touches",
            c.chosen + 1,
            c.candidates
        )
    });
    let seconds = phase.finish(
        progress,
        &format!(
            "path of length {:.2} (normalised A), {} waypoints, closest approach {:.1} \
             mm{chosen_of}",
            out.cost,
            out.waypoints,
            1e3 * out.min_clearance
        ),
    );
    Ok(Planned {
        out,
        chosen,
        controller_model,
        seconds,
    })
}

/// Phase 5: the plan's `waypoints` tracked closed loop (with the controller's model and the
/// learnt calibration), then open loop, under the demo's noise, and the figure `tracking`;
/// returns what the summary keeps and the phase's seconds.
pub(super) fn track(
    inputs: &Inputs,
    (learnt, controller_model): (&Calibration, &KirchhoffModel),
    waypoints: &[Waypoint],
    folder: &ResultsFolder,
    progress: &mut dyn DemoProgress,
) -> Result<(TrackingOut, f64), LabError> {
    let noise = inputs.noise;
    let phase = Phase::start(progress, 5, "track the plan, closed then open loop", 3);
    let tracking = Tracking {
        wire: &inputs.wire,
        gravity: Gravity::On,
        scene: &inputs.scene,
        calibration: learnt,
        setup: &inputs.setup,
        noise,
        seed: inputs.seed,
        // The paper's gain, the policy's stops.
        policy: ftwire_control::TrackingPolicy {
            gain: ftwire_control::ControlParams::default().gain,
            ..ftwire_control::TrackingPolicy::for_noise(noise)
        },
        arms: true,
        bias_observer: true,
    };
    let detector = tracking.detector(controller_model, waypoints)?;
    progress.step(1);
    let closed = tracking.closed_loop(controller_model, waypoints, detector, 2)?;
    progress.step(2);
    let open = tracking.open_loop(controller_model, waypoints, 2)?;
    scene_chart(&inputs.scene, &closed)
        .write(folder.dir(), "tracking")
        .map_err(|e| LabError::no_answer(format!("figure tracking: {e}")))?;
    let seconds = phase.finish(
        progress,
        &format!(
            "closed loop: {}; open loop: {}",
            verdict(&closed),
            verdict(&open)
        ),
    );
    let out = TrackingOut {
        noise_model: noise.name(),
        detector_threshold: detector.threshold(),
        closed_loop: closed,
        open_loop: open,
    };
    Ok((out, seconds))
}

/// One attempt's outcome in the phase's result line.
fn verdict(a: &Attempt) -> String {
    format!(
        "{} ({} moves{}, final error {:.3}, shape {:.1} mm at the goal)",
        a.verdict(),
        a.steps,
        match (a.touched, a.detected) {
            (true, true) => ", touched an obstacle, detected",
            (true, false) => ", touched an obstacle",
            (false, true) if a.completed => ", a false alarm, retreated",
            (false, true) => ", stopped by a false alarm",
            (false, false) => "",
        },
        a.final_error,
        a.shape_mm.last().copied().unwrap_or(f64::NAN),
    )
}

/// The scene's boxes (their twelve edges) and the true wire at [`FIGURE_RESTS`] rests of
/// `attempt`, evenly spaced from the first to the last.
fn scene_chart(scene: &Scene, attempt: &Attempt) -> Chart3d {
    let mut chart = Chart3d::new("the passage: the true wire, closed loop");
    for b in &scene.boxes {
        chart = chart.with_curve(b.name.clone(), box_outline(b), SeriesKind::Line);
    }
    // A few rests, evenly spaced, and the last: a readable legend.
    let n = attempt.centrelines.len();
    let shown = FIGURE_RESTS.min(n);
    for j in 0..shown {
        let k = if shown > 1 {
            j * (n - 1) / (shown - 1)
        } else {
            0
        };
        if let Some(centreline) = attempt.centrelines.get(k) {
            chart = chart.with_curve(
                format!("after move {}", k + 1),
                centreline.clone(),
                SeriesKind::Line,
            );
        }
    }
    chart
}
