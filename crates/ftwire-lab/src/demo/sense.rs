//! The demo's phases 1–3, what the robot learns from F/T: the calibration on the known wire,
//! the identification of the wire, and its shape from F/T.

use ftwire_core::WireParams;
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::identify::MotionPlan;
use ftwire_estimate::shape::{DEFAULT_METRIC_SAMPLES, ShapeEstimator, centreline_distance};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_report::{Chart3d, SeriesKind};
use ftwire_rod::Rod;
use ftwire_rod::sampling::Sampler;
use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::inputs::Inputs;
use super::page::FirstShape;
use super::phase::{DemoProgress, Phase};
use super::summary::{CalibrationOut, IdentificationOut, ShapeOut};
use crate::error::{LabError, from_estimate, from_rod};
use crate::experiment::calibration::{self, rig_seed};
use crate::experiment::rig::{measure, pipeline, place_wire, tare, true_centreline};
use crate::experiment::{Gravity, ModelKind};
use crate::identify::{
    Map, Protocol, REST_SAMPLES, Recorded, ResidualParams, flag_name, linear_density,
    loaded_config, record_trial, run_identification, truth,
};
use crate::results::ResultsFolder;
use crate::setup::SimSetup;
use crate::wire::WireSpec;

/// Samples the identification phase identifies from (the paper's smallest useful count).
pub const IDENTIFY_SAMPLES: usize = 3;

/// Phase 1: the calibration on the known wire; its summary, the weights (also written to the
/// folder as `calibration.json`) and the phase's seconds.
pub(super) fn calibrate(
    inputs: &Inputs,
    folder: &ResultsFolder,
    progress: &mut dyn DemoProgress,
) -> Result<(CalibrationOut, Calibration, f64), LabError> {
    let Inputs {
        known,
        setup,
        seed,
        calibration_configs,
        ..
    } = inputs;
    let phase = Phase::start(
        progress,
        1,
        "calibrate the F/T sensor on the known wire",
        *calibration_configs,
    );
    let run = calibration::run(
        known,
        (Gravity::On, ModelKind::Loaded),
        setup,
        *calibration_configs,
        *seed,
        |k| progress.step(k + 1),
    )?;
    let test = &run.summary;
    let out = CalibrationOut {
        wire: known.name.clone(),
        configurations: run.samples.len(),
        raw_torque_rel: test.raw.torque_rel,
        raw_force_rel: test.raw.force_rel,
        calibrated_torque_rel: test.calibrated.torque_rel,
        calibrated_force_rel: test.calibrated.force_rel,
    };
    folder.write(
        "calibration.json",
        run.calibration
            .to_json()
            .map_err(|e| from_estimate(e, "the calibration weights"))?,
    )?;
    let seconds = phase.finish(
        progress,
        &format!(
            "{} on {} configurations: test error torque {:.2} %, force {:.2} % (raw {:.2} %, \
             {:.2} %)",
            known.name,
            out.configurations,
            100.0 * out.calibrated_torque_rel,
            100.0 * out.calibrated_force_rel,
            100.0 * out.raw_torque_rel,
            100.0 * out.raw_force_rel,
        ),
    );
    Ok((out, run.calibration, seconds))
}

/// Phase 2: one identification trial of the wire through the learnt calibration; returns
/// the result, the identified (loaded) model and the phase's seconds.
pub(super) fn identify(
    inputs: &Inputs,
    learnt: &Calibration,
    progress: &mut dyn DemoProgress,
) -> Result<(IdentificationOut, KirchhoffModel, f64), LabError> {
    let wire = &inputs.wire;
    let phase = Phase::start(progress, 2, "identify the wire from F/T", IDENTIFY_SAMPLES);
    let (out, model) = identify_trial(wire, learnt, &inputs.setup, inputs.seed)?;
    progress.step(IDENTIFY_SAMPLES);
    let err = &out.relative_error;
    let seconds = phase.finish(
        progress,
        &format!(
            "c = ({:.4}, {:.4}, {:.4}) N·m², L = {:.4} m against the truth ({:.4}, {:.4}, \
             {:.4}), {:.4}: errors {:.2} / {:.2} / {:.2} / {:.2} %{}",
            out.estimate[0],
            out.estimate[1],
            out.estimate[2],
            out.estimate[3],
            wire.c[0],
            wire.c[1],
            wire.c[2],
            wire.length,
            100.0 * err[0],
            100.0 * err[1],
            100.0 * err[2],
            100.0 * err[3],
            out.flag
                .map_or_else(String::new, |f| format!(" (flagged: {f})")),
        ),
    );
    Ok((out, model, seconds))
}

/// The identification trial of phase 2: [`IDENTIFY_SAMPLES`] rests of the library's
/// identification motion of `wire`, read through the learnt calibration, identified with the
/// loaded model under the known gravity.
fn identify_trial(
    wire: &WireSpec,
    learnt: &Calibration,
    setup: &SimSetup,
    seed: u64,
) -> Result<(IdentificationOut, KirchhoffModel), LabError> {
    let protocol = Protocol {
        plan: MotionPlan {
            moves: IDENTIFY_SAMPLES - 1,
            ..MotionPlan::default()
        },
        rest_samples: REST_SAMPLES,
    };
    let samples = record_trial(
        wire,
        Gravity::On,
        setup,
        Map::Learnt(learnt),
        seed,
        0,
        &protocol,
    )?;
    let pairs: Vec<_> = samples.iter().map(Recorded::sample).collect();
    let config = loaded_config(&ResidualParams::default().config()?, Gravity::On);
    let estimate = run_identification(&pairs, &config, seed)?;
    let truth = truth(wire);
    let eta = [estimate.c[0], estimate.c[1], estimate.c[2], estimate.length];
    let std = [
        estimate.c_std[0],
        estimate.c_std[1],
        estimate.c_std[2],
        estimate.length_std,
    ];
    let relative_error = std::array::from_fn(|j| (eta[j] - truth[j]) / truth[j]);
    let lambda = linear_density(wire);
    // The identified model: the wire's radius is measured (calipers), not identified; it only
    // enters the self-contact test.
    let params = WireParams::new(estimate.c, estimate.length, wire.radius)
        .map_err(|e| LabError::no_answer(format!("the identified wire: {e}")))?;
    let weight = estimate.linear_density.unwrap_or(0.0) * Gravity::On.vector();
    let model = KirchhoffModel::new(params)
        .with_weight_per_length(weight)
        .map_err(|e| from_estimate(e, "the identified wire's weight"))?;
    let out = IdentificationOut {
        samples: pairs.len(),
        estimate: eta,
        std,
        relative_error,
        linear_density: estimate.linear_density,
        linear_density_relative_error: estimate.linear_density.map(|l| (l - lambda) / lambda),
        chi2_per_dof: estimate.chi2_per_dof,
        flag: flag_name(estimate.unidentified.as_ref()),
    };
    Ok((out, model))
}

/// Phase 3: the identified `model`'s shape from `ã` against the true wire, with the figure
/// `shape` of the first configuration; returns the errors, the first configuration's
/// estimated and true centrelines and the phase's seconds.
pub(super) fn shape(
    inputs: &Inputs,
    (learnt, model): (&Calibration, KirchhoffModel),
    folder: &ResultsFolder,
    progress: &mut dyn DemoProgress,
) -> Result<(ShapeOut, Option<FirstShape>, f64), LabError> {
    let wire = &inputs.wire;
    let phase = Phase::start(
        progress,
        3,
        "estimate the shape from F/T",
        inputs.shape_configs,
    );
    let (out, first) = shapes(inputs, learnt, model, &mut |k| progress.step(k))?;
    if let Some((estimate, truth)) = &first {
        let chart = Chart3d::new(format!("{}: shape from F/T against the truth", wire.name))
            .with_curve("truth (simulator)", truth.clone(), SeriesKind::Line)
            .with_curve("estimate from F/T", estimate.clone(), SeriesKind::Line);
        chart
            .write(folder.dir(), "shape")
            .map_err(|e| LabError::no_answer(format!("figure shape: {e}")))?;
    }
    let seconds = phase.finish(
        progress,
        &format!(
            "{} configurations, mean distance to the true wire {:.2} mm",
            out.configurations, out.mean_mm_overall
        ),
    );
    Ok((out, first, seconds))
}

/// The shapes of phase 3: the identified `model`'s shape from `ã` at configurations of
/// `A_free` of the true wire (a placement the simulator cannot hold, or a reading the model
/// cannot solve at, is skipped); returns the errors and the first configuration's estimated
/// and true centrelines, and reports each configuration's start to `progress`.
fn shapes(
    inputs: &Inputs,
    learnt: &Calibration,
    model: KirchhoffModel,
    progress: &mut dyn FnMut(usize),
) -> Result<(ShapeOut, Option<FirstShape>), LabError> {
    let Inputs {
        wire,
        setup,
        seed,
        shape_configs,
        ..
    } = inputs;
    let params = wire
        .wire_params()
        .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?;
    let rod = Rod::new(params);
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5ba9e);
    let sampler = Sampler::default();
    let mut estimator = ShapeEstimator::new(model);
    let mut mean_mm = Vec::with_capacity(*shape_configs);
    let mut first = None;
    for k in 0..*shape_configs {
        progress(k);
        let placed = sampler
            .sample_free(&rod, &mut rng)
            .map_err(|e| from_rod(e, "sampling A_free of the wire"))?;
        let config = setup.rig_config(rig_seed(*seed, k));
        let Ok(mut rig) = place_wire(wire, Gravity::On, &placed, config) else {
            continue;
        };
        let tared = pipeline(tare(&mut rig)?, learnt.clone())?;
        let Ok(measured) = measure(&mut rig, &tared) else {
            continue;
        };
        estimator.reset();
        let Ok(estimate) = estimator.estimate(&measured.a) else {
            continue;
        };
        let truth = true_centreline(&rig);
        let positions = &estimate.shape.positions;
        let distance = centreline_distance(positions, &truth, DEFAULT_METRIC_SAMPLES)
            .map_err(|e| from_estimate(e, "the shape error"))?;
        mean_mm.push(1e3 * distance);
        if first.is_none() {
            let points = |v: &[Vector3<f64>]| v.iter().map(|p| [p.x, p.y, p.z]).collect();
            first = Some((points(positions), points(&truth)));
        }
    }
    progress(*shape_configs);
    if mean_mm.is_empty() {
        return Err(LabError::no_answer(format!(
            "no configuration of {} could be placed and estimated",
            wire.name
        )));
    }
    let overall = mean_mm.iter().sum::<f64>() / mean_mm.len() as f64;
    Ok((
        ShapeOut {
            configurations: mean_mm.len(),
            mean_mm,
            mean_mm_overall: overall,
        },
        first,
    ))
}
