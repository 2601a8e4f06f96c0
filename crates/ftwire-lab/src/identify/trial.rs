//! One identification trial in the simulator: the operator places the wire at a random stable
//! start, the robot tares, follows the library's identification motion and records `(ã, b̃)`
//! at each rest; and the trial's JSON Lines log.

use ftwire_core::{Pose, Rig};
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::ft::{FtCalibration, FtPipeline};
use ftwire_estimate::identify::{MotionPlan, Sample};
use ftwire_estimate::log::{LogPose, LogRecord, to_line};
use ftwire_rod::{Rod, from_normalised};
use ftwire_sim::{RigParams, SimRig};
use nalgebra::Vector6;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::error::{EXIT_NO_ANSWER, LabError, from_rod, from_sim};
use crate::experiment::Gravity;
use crate::experiment::rig::{believed_tip, measure_over, mounting, pipeline, place_wire, tare};
use crate::setup::SimSetup;
use crate::wire::{WireSpec, file_stem};

/// Half-width of the box of normalised start configurations (`to_normalised` units): a
/// moderate load, well inside `A_stable` for most draws.
const START_BOX: f64 = 5.0;

/// Start configurations tried per trial before giving up (unstable draws, or a start the
/// simulator cannot hold).
const START_ATTEMPTS: usize = 20;

/// One recorded sample of a trial.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Recorded {
    /// The rig's clock \[s\].
    pub time: f64,
    /// The time since the sensor was tared \[s\].
    pub since_tare: f64,
    /// `ã` (tared, through the map; torque first, base clamp frame).
    pub a: Vector6<f64>,
    /// `b̃`, the believed second-gripper pose relative to the base clamp.
    pub b: Pose,
}

impl Recorded {
    /// The sample identification reads: `(ã, b̃)` and the time since the tare.
    pub fn sample(&self) -> Sample {
        Sample {
            a: self.a,
            b: self.b,
            time: Some(self.since_tare),
        }
    }
}

/// The map from the tared reading to `ã`: the sensor's mounting (built per trial from the
/// rig's configuration), or the learnt calibration.
#[derive(Debug, Clone, Copy)]
pub enum Map<'a> {
    /// The sensor's mounting transform only ([`super::Pipeline::Mounting`]).
    Mounting,
    /// The learnt calibration ([`super::Pipeline::Calibrated`]).
    Learnt(&'a Calibration),
}

/// How a trial moves and measures: the library's motion plan, and the F/T samples averaged at
/// each rest.
#[derive(Debug, Clone)]
pub struct Protocol {
    /// The library's identification motion (its `moves` plus the start are the samples).
    pub plan: MotionPlan,
    /// F/T samples averaged at each rest.
    pub rest_samples: usize,
}

/// Places the wire, tares, follows the motion plan, and records a sample at the start pose and
/// after each of the plan's moves. The start and the rig are drawn from `ChaCha8(seed)` on
/// stream `stream` (one per wire and trial). A start the simulator cannot hold or a move it
/// cannot follow (no answer) starts the trial again from another `a0`.
///
/// # Errors
/// Bad input for a bad wire; no answer when no start of the box could be followed.
pub fn record_trial(
    wire: &WireSpec,
    gravity: Gravity,
    setup: &SimSetup,
    map: Map<'_>,
    seed: u64,
    stream: u64,
    protocol: &Protocol,
) -> Result<Vec<Recorded>, LabError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    let params = wire
        .wire_params()
        .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?;
    let truth = Rod::new(params);
    let mut last = LabError::no_answer(format!(
        "no stable start configuration in [−{START_BOX}, {START_BOX}]⁶ (normalised) after \
         {START_ATTEMPTS} draws"
    ));
    for _ in 0..START_ATTEMPTS {
        let z = Vector6::from_fn(|_, _| rng.random_range(-START_BOX..START_BOX));
        let a0 = from_normalised(&params, &z);
        if !truth
            .is_stable(&a0)
            .map_err(|e| from_rod(e, "checking the start configuration"))?
        {
            continue;
        }
        let config = setup.rig_config(rng.random());
        match follow_plan(wire, gravity, &a0, config, map, protocol, &mut rng) {
            Ok(samples) => return Ok(samples),
            Err(e) if e.exit_code() == EXIT_NO_ANSWER => last = e,
            Err(e) => return Err(e),
        }
    }
    Err(last)
}

/// One attempt of a trial from `a0`: places the wire, tares, and follows the plan through
/// `map`.
fn follow_plan(
    wire: &WireSpec,
    gravity: Gravity,
    a0: &Vector6<f64>,
    config: RigParams,
    map: Map<'_>,
    protocol: &Protocol,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<Recorded>, LabError> {
    let mut rig = place_wire(wire, gravity, a0, config.clone())?;
    let tared = tare(&mut rig)?;
    let tared_at = rig.time();
    let samples = match map {
        Map::Mounting => {
            let pipeline = pipeline(tared, mounting(&config)?)?;
            follow(&mut rig, &pipeline, protocol, rng)
        }
        Map::Learnt(learnt) => {
            let pipeline = pipeline(tared, learnt.clone())?;
            follow(&mut rig, &pipeline, protocol, rng)
        }
    }?;
    Ok(samples
        .into_iter()
        .map(|s| Recorded {
            since_tare: s.time - tared_at,
            ..s
        })
        .collect())
}

/// Records the sample at the current rest, then one after each move of the plan.
fn follow<C: FtCalibration>(
    rig: &mut SimRig,
    pipeline: &FtPipeline<C>,
    protocol: &Protocol,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<Recorded>, LabError> {
    let b0 = believed_tip(rig)?;
    let poses = protocol.plan.poses(&b0, rng);
    let mut samples = Vec::with_capacity(poses.len() + 1);
    samples.push(record(rig, pipeline, protocol.rest_samples)?);
    for b in poses {
        let base = rig
            .gripper_poses()
            .map_err(|e| from_sim(e, "reading the gripper poses"))?
            .base;
        rig.move_tip(base * b)
            .map_err(|e| from_sim(e, "moving the second gripper"))?;
        samples.push(record(rig, pipeline, protocol.rest_samples)?);
    }
    Ok(samples)
}

/// One sample at the rig's current rest.
fn record<C: FtCalibration>(
    rig: &mut SimRig,
    pipeline: &FtPipeline<C>,
    rest_samples: usize,
) -> Result<Recorded, LabError> {
    let a = measure_over(rig, pipeline, rest_samples)?.a;
    Ok(Recorded {
        time: rig.time(),
        since_tare: 0.0,
        a,
        b: believed_tip(rig)?,
    })
}

/// `<wire>-trial<k>.jsonl` (see [`file_stem`]).
pub(super) fn log_name(wire: &str, trial: usize) -> String {
    format!("{}-trial{trial}.jsonl", file_stem(wire))
}

/// A trial's JSON Lines log: each sample's `{time, a, b}` in the format of
/// `ftwire_estimate::log`.
pub(super) fn log_text(samples: &[Recorded]) -> Result<String, LabError> {
    let mut text = String::new();
    for sample in samples {
        let record = LogRecord {
            time: sample.time,
            raw: None,
            a: Some(sample.a.into()),
            b: Some(LogPose::from_pose(&sample.b)),
            markers: None,
            gravity: None,
        };
        let line = to_line(&record).map_err(|e| LabError::no_answer(e.to_string()))?;
        text.push_str(&line);
        text.push('\n');
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_names_are_safe_file_names() {
        assert_eq!(log_name("a b/c", 4), "a_b_c-trial4.jsonl");
    }
}
