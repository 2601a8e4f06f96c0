//! The F/T calibration of paper §IV-A as the experiments run it: collect raw readings and
//! motion-capture markers on a known wire, label each reading by shape fitting (eq. 15), and
//! train the network (`ftwire_estimate::calibration`). `ftwire experiment calibrate` runs it
//! and reports it; `ftwire experiment shape` (and later `goal`, `track`, `passage`) run it or
//! load a cached one ([`load_or_run`]).
//!
//! **Collection.** Each of the `K` configurations `a_k` is a seeded uniform sample of `A_free`
//! of the known wire (`ftwire_rod::sampling::Sampler`, default box). The operator places the
//! wire at `Γ(a_k)` anew for every sample, and the robot tares its sensor on the empty gripper
//! before it grips the wire (as it does at every re-grip); then it averages
//! [`super::rig::SAMPLES_PER_REST`] samples at rest and the motion-capture system takes one frame of
//! the 11 markers (noise and dropouts). Re-placing rather than moving from one configuration
//! to the next keeps every sample on the intended equilibrium branch (a long move can snap the
//! wire) and makes the samples independent. A placement the simulator cannot solve, a rest with
//! too few good samples or a marker frame with too few markers is skipped and counted, and so
//! is a label that disagrees with the tared mounting-only reading by more than the sensor's own
//! errors ([`label_disagrees`]): the markers of a taut wire barely show its tension, so the
//! fit can land on another configuration of nearly the same shape, and a handful of such
//! labels (3–6 of 600) pulled the least-squares affine part far enough that, on seeds 2 and 3,
//! the calibrated map was worse than the raw reading (0.7–0.8 % torque, 1.3–1.9 % force
//! against 0.08–0.09 % and 0.13–0.18 % with them rejected).
//!
//! With [`Protocol::SingleReadings`] the session is recorded as a real rig logs it instead:
//! a walk through `A_free` in steps of the second gripper of about 17 mm that sweeps one
//! region again and again ([`WALK_RADIUS`]), tared once, one reading per record at 4 Hz, two
//! or three records at some rests, the sensor's hysteresis carried from rest to rest, the
//! markers glued off the centreline ([`RECORDING_MOUNT_OFFSET`]), and a wire whose bending
//! softens as nitinol's does ([`RECORDING_SOFTENING_STRAIN`]), which no model knows. The
//! label check above needs a reading tared just before it, so it is left out there.
//!
//! **Labels.** `ShapeFitter` with the known wire's model fits the markers (eq. 15). With the
//! paper's weight-free model (`--model kirchhoff`) and gravity on, the model cannot follow the
//! sag exactly: the label is the weight-free configuration closest to the markers, so the
//! network learns the map to *that* `a` and absorbs part of gravity, as the paper's network
//! does on its real wire, and only on this wire. With the loaded model (`--model loaded`, the
//! known wire's weight and rest curvature; [`super::known_model`]) the label is the true
//! wrench up to the fit's noise, so the network learns only the sensor's distortion, which
//! carries over to any wire.
//!
//! **Evaluation** (on the test split only, against the ground truth the binary alone sees):
//! the relative error of the torque and force parts against the true base wrench, and the mean
//! distance between `Φ(ã)` and the simulator's centreline at 100 matched arc lengths; for the
//! network and for the tared mounting-only pipeline.

use std::path::Path;
use std::time::Instant;

use ftwire_estimate::EstimateError;
use ftwire_estimate::calibration::{
    Calibration, CalibrationInput, Dataset, LabelModel, Split, TrainParams,
};
use ftwire_estimate::shape::{DEFAULT_METRIC_SAMPLES, Markers, ShapeFitter, centreline_distance};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_rod::Rod;
use ftwire_rod::sampling::Sampler;
use nalgebra::{Vector3, Vector6};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use super::rig::{
    measure, mounting, pipeline, place_softened_wire, place_wire, tare, true_centreline,
};
use super::{Gravity, ModelKind, known_model};
use crate::error::{LabError, from_estimate, from_rod};
use crate::setup::{Protocol, SimSetup};
use crate::wire::WireSpec;
use ftwire_core::Rig;

/// The session clock's step, with the sensor setup whose drift it paces.
pub use crate::setup::sensor::REST_INTERVAL;

/// The known wire the calibration is collected on by default: the 3 mm nitinol wire of 820 mm,
/// the stiffest of the presets relative to its weight, so that gravity bends it least.
pub const KNOWN_WIRE: &str = "nitinol-3mm-820";

/// Configurations collected by default (`--trials` of `experiment calibrate`).
pub const DEFAULT_SAMPLES: usize = 600;

/// Nodes of the model shapes compared with the ground truth.
const SHAPE_NODES: usize = 64;

/// One collected configuration: what the robot measured, the label, and the ground truth.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationSample {
    /// The configuration the wire was placed at (sampled from `A_free` of the known wire).
    pub placed: Vector6<f64>,
    /// The tared raw reading averaged at rest, force first, sensor frame \[N, N·m\].
    pub raw: Vector6<f64>,
    /// `ã` of the tared mounting-only pipeline, torque first, base clamp frame.
    pub mounting: Vector6<f64>,
    /// Ground truth: the wire's wrench on the base gripper, torque first, base clamp frame.
    pub true_wrench: Vector6<f64>,
    /// Ground truth: the simulator's centreline \[m\], base clamp frame (= world frame).
    pub truth: Vec<Vector3<f64>>,
    /// The label: the shape fit of the markers (eq. 15).
    pub label: Vector6<f64>,
    /// RMS marker residual of the label's fit \[m\].
    pub label_rms: f64,
}

/// The errors of one configuration map on the test split.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MapErrors {
    /// Mean of `‖τ̃ − τ‖ / ‖τ‖` against the true base wrench.
    pub torque_rel: f64,
    /// Mean of `‖f̃ − f‖ / ‖f‖` against the true base wrench.
    pub force_rel: f64,
    /// Mean distance \[mm\] between `Φ(ã)` and the true centreline at 100 matched arc lengths.
    pub shape_mm: f64,
}

/// Sizes of the train, validation and test splits.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SampleCounts {
    /// Training samples.
    pub train: usize,
    /// Validation samples.
    pub validation: usize,
    /// Test samples.
    pub test: usize,
}

/// Configurations that could not be used, by reason.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Skipped {
    /// The simulator could not place the wire there.
    pub placement: usize,
    /// Too few good F/T samples at rest.
    pub measurement: usize,
    /// Too few markers seen, or the fit failed.
    pub label: usize,
    /// The label disagrees with the mounting-only reading by more than the sensor's own
    /// errors can explain ([`label_disagrees`]): a shape fit that found another configuration
    /// with nearly the same shape (a taut wire's tension barely shows in its shape).
    pub label_outlier: usize,
}

/// Relative disagreement, per part (torque, force), between a label and the mounting-only
/// reading beyond which the label is rejected: the sensor's gain, cross-talk and
/// nonlinearity are a few per cent.
pub const LABEL_DISAGREEMENT: f64 = 0.1;

/// Absolute slack of the label check \[N·m, N\]: the averaged noise and bias drift of a
/// reading, several times over.
pub const LABEL_SLACK: (f64, f64) = (0.01, 0.05);

/// Whether a label disagrees with the tared mounting-only reading `mounting` (both torque
/// first) by more than [`LABEL_DISAGREEMENT`] of its size plus [`LABEL_SLACK`], in torque or
/// in force. Uses only what a real rig has: no ground truth.
pub fn label_disagrees(label: &Vector6<f64>, mounting: &Vector6<f64>) -> bool {
    let part = |start: usize, slack: f64| {
        let l = label.fixed_rows::<3>(start);
        (mounting.fixed_rows::<3>(start) - l).norm() > LABEL_DISAGREEMENT * l.norm() + slack
    };
    part(0, LABEL_SLACK.0) || part(3, LABEL_SLACK.1)
}

/// `summary.json` of `ftwire experiment calibrate`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CalibrationSummary {
    /// The known wire.
    pub wire: WireSpec,
    /// The model that labelled the samples (`--model`).
    pub model: ModelKind,
    /// The split sizes.
    pub samples: SampleCounts,
    /// The tared mounting-only pipeline on the test split.
    pub raw: MapErrors,
    /// The learnt calibration on the test split.
    pub calibrated: MapErrors,
    /// Mean RMS marker residual of the labels' fits \[mm\] (all samples).
    pub label_fit_mm: f64,
    /// Mean distance \[mm\] between the labels' shapes `Φ(label)` and the true centreline (all
    /// samples): what the weight-free model can do at best on this wire.
    pub label_shape_mm: f64,
    /// Configurations skipped, by reason.
    pub skipped: Skipped,
}

/// Wall-clock times of a calibration run \[s\] (kept apart from the summary).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CalibrationTimings {
    /// Placing, measuring and labelling every configuration.
    pub collect_s: f64,
    /// Training the network.
    pub train_s: f64,
}

/// A finished calibration run.
#[derive(Debug, Clone)]
pub struct CalibrationRun {
    /// The learnt calibration.
    pub calibration: Calibration,
    /// Every used configuration, in collection order.
    pub samples: Vec<CalibrationSample>,
    /// Every rest measured, labelled or not, as a rig logs it ([`RecordedRest`]).
    pub recording: Vec<RecordedRest>,
    /// The train/validation/test split (indices into `samples`), as training drew it.
    pub split: Split,
    /// The summary.
    pub summary: CalibrationSummary,
    /// Timings.
    pub timings: CalibrationTimings,
}

/// One rest as a rig records it: the time on the session clock, the raw reading averaged at
/// rest (not tared: a real log carries the sensor's offsets), and the marker frame; with the
/// simulator's true centreline beside it for tests (a rig has none).
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedRest {
    /// Time \[s\] on the session clock: `k` [`REST_INTERVAL`]s plus the rig's time at the rest.
    pub time: f64,
    /// The raw reading averaged at rest, force first, sensor frame \[N, N·m\], not tared.
    pub raw: Vector6<f64>,
    /// The markers, base clamp frame \[m\] (`None` for a dropout).
    pub markers: Vec<Option<Vector3<f64>>>,
    /// Ground truth: the simulator's centreline \[m\], base clamp frame.
    pub truth: Vec<Vector3<f64>>,
}

/// The rig settings of configuration `k` of a session: the sensor's deterministic drift
/// (`bias_drift_rate`) carried over the session as an initial bias of `ḃ t_k`, `t_k = k`
/// [`REST_INTERVAL`], since every configuration is placed in a rig of its own.
fn session_config(mut config: ftwire_sim::RigParams, k: usize) -> ftwire_sim::RigParams {
    #[allow(clippy::cast_precision_loss)] // k far below 2⁵²
    let t = k as f64 * REST_INTERVAL;
    let sensor = &mut config.sensor;
    for (bias, rate) in sensor.initial_bias.iter_mut().zip(sensor.bias_drift_rate) {
        *bias += rate * t;
    }
    sensor.bias_drift_rate = [0.0; 6];
    config
}

/// The seed of the simulated rig of configuration `k` of a run seeded `seed`.
pub fn rig_seed(seed: u64, k: usize) -> u64 {
    seed.wrapping_mul(1_000_003).wrapping_add(k as u64)
}

/// Collects `count` configurations on `wire` in the rig `setup` (see the module docs);
/// `progress(k)` is called after each. Returns the labelled samples, the skips, and the
/// recording of every rest measured (labelled or not), as a rig would log it.
///
/// # Errors
/// Bad input for a bad wire; no answer when `A_free` cannot be sampled.
pub fn collect(
    wire: &WireSpec,
    (gravity, kind): (Gravity, ModelKind),
    setup: &SimSetup,
    count: usize,
    seed: u64,
    mut progress: impl FnMut(usize),
) -> Result<(Vec<CalibrationSample>, Skipped, Vec<RecordedRest>), LabError> {
    let model = known_model(wire, gravity, kind)?;
    // The configurations are placed as the weight-free model gives them, whatever the labels'
    // model, so that both models label the same collection.
    let rod = Rod::new(*model.wire());
    let fitter = ShapeFitter::new(model);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let sampler = Sampler::default();
    let single = setup.protocol == Protocol::SingleReadings;
    let mut walk = Walk::default();
    let mut session_tare = None;
    let mut samples = Vec::with_capacity(count);
    let mut skipped = Skipped::default();
    let mut recording = Vec::with_capacity(count);
    for k in 0..count {
        let placed = if single {
            walk.next(&rod, &sampler, &mut rng)?
        } else {
            sampler
                .sample_free(&rod, &mut rng)
                .map_err(|e| from_rod(e, "sampling A_free of the known wire"))?
        };
        progress(k);
        let mut config = session_config(setup.rig_config(rig_seed(seed, k)), k);
        if single {
            config.markers = recording_markers(config.markers, seed);
        }
        let rig = if single {
            let softening = RECORDING_SOFTENING_STRAIN / wire.radius;
            place_softened_wire(wire, gravity, &placed, config.clone(), softening)
        } else {
            place_wire(wire, gravity, &placed, config.clone())
        };
        let Ok(mut rig) = rig else {
            walk.lost();
            skipped.placement += 1;
            continue;
        };
        let tare = match (single, session_tare) {
            (true, Some(t)) => t,
            _ => tare(&mut rig)?,
        };
        if single {
            session_tare = Some(tare);
            rig.sensor_mut()
                .set_hysteresis_state(walk.hysteresis)
                .map_err(|e| LabError::no_answer(format!("the sensor's load history: {e}")))?;
        }
        let tared = pipeline(tare, mounting(&config)?)?;
        let (raw, a, first_frame) = if single {
            let records = walk.records_at_rest(&mut rng);
            let mut first = None;
            for j in 0..records {
                let Some(sample) = single_reading(&mut rig) else {
                    continue;
                };
                #[allow(clippy::cast_precision_loss)] // small counts
                let time = k as f64 * REST_INTERVAL + j as f64 / SINGLE_READING_RATE;
                let (rest, frame) = observe(&mut rig, time, sample)?;
                recording.push(rest);
                first.get_or_insert((sample, frame));
            }
            walk.hysteresis = rig.sensor().hysteresis_state();
            let Some((sample, frame)) = first else {
                skipped.measurement += 1;
                continue;
            };
            (sample, tared.configuration(&sample), frame)
        } else {
            let Ok(measured) = measure(&mut rig, &tared) else {
                skipped.measurement += 1;
                continue;
            };
            #[allow(clippy::cast_precision_loss)] // k far below 2⁵²
            let time = k as f64 * REST_INTERVAL + measured.raw.time;
            let (rest, frame) = observe(&mut rig, time, measured.raw.mean)?;
            recording.push(rest);
            (measured.raw.mean, measured.a, frame)
        };
        let fit = Markers::new(&config.markers.fractions, &first_frame.positions)
            .and_then(|markers| fitter.fit(&markers, &mut rng));
        let Ok(fit) = fit else {
            skipped.label += 1;
            continue;
        };
        // The check needs a reading tared just before it; a single-readings session is
        // tared once, so its drift and hysteresis are what the check would catch.
        if !single && label_disagrees(&fit.a, &a) {
            skipped.label_outlier += 1;
            continue;
        }
        let equilibrium = rig.equilibrium();
        samples.push(CalibrationSample {
            placed,
            raw: tared.tare().apply(&raw),
            mounting: a,
            true_wrench: equilibrium.base_wrench.to_vector(),
            truth: true_centreline(&rig),
            label: fit.a,
            label_rms: fit.rms,
        });
    }
    Ok((samples, skipped, recording))
}

/// One frame of the markers now, and the record a rig logs of it with the reading `raw` at
/// `time` on the session clock (the simulator's centreline beside it).
fn observe(
    rig: &mut ftwire_sim::SimRig,
    time: f64,
    raw: Vector6<f64>,
) -> Result<(RecordedRest, ftwire_sim::MarkerFrame), LabError> {
    let frame = rig
        .observe_markers()
        .map_err(|e| crate::error::from_sim(e, "observing the markers"))?;
    let rest = RecordedRest {
        time,
        raw,
        markers: frame
            .positions
            .iter()
            .map(|p| p.map(|p| p.coords))
            .collect(),
        truth: true_centreline(rig),
    };
    Ok((rest, frame))
}

/// The markers' mounting offset \[m\] in a [`Protocol::SingleReadings`] recording
/// (`ftwire_sim::MarkerParams::mount_offset`): how far each marker's centre sits from the
/// wire's centreline.
///
/// A real rig's marker is a reflective ball glued on the side of the wire, so its centre sits
/// `r + D/2` from the wire's axis, in a direction of its own. For a ball of `D = 1.5` mm on the
/// 2 mm wire (`r = 1` mm) that is 1.75 mm. A shape fit absorbs little of it (the offsets point
/// every way) and leaves, with the cameras' noise, the real recording's label residual,
/// 1.5–1.8 mm RMS (`shared/DESIGN.md`, "Real recordings"); a 3 mm ball (2.5 mm) leaves 2.4 mm.
pub const RECORDING_MOUNT_OFFSET: f64 = 0.00175;

/// The markers of a [`Protocol::SingleReadings`] recording: the rig's, glued off the
/// centreline by [`RECORDING_MOUNT_OFFSET`] unless the rig file sets an offset of its own, one
/// marker set for the whole session (drawn from the run's `seed`, not from each rest's rig).
fn recording_markers(mut markers: ftwire_sim::MarkerParams, seed: u64) -> ftwire_sim::MarkerParams {
    if markers.mount_offset <= 0.0 {
        markers.mount_offset = RECORDING_MOUNT_OFFSET;
        markers.mount_seed = seed;
    }
    markers
}

/// The surface strain `κs·radius` at which the wire of a [`Protocol::SingleReadings`]
/// recording softens in bending (`ftwire_sim::RodParams::bending_softening`: its secant
/// stiffness `c/√2` at `κs`). A real nitinol wire of a recording bends to 0.6–1.1 % surface
/// strain (curvatures of 6–11 1/m on the 2 mm wire), where its austenite starts to transform
/// and a linear model's stiffness is an average: what a static map must learn beside the
/// sensor's. It is bounded by the labels: the weight-free model must still fit the markers to
/// a real recording's 1.5–1.8 mm RMS (`shared/DESIGN.md`, "Real recordings").
pub const RECORDING_SOFTENING_STRAIN: f64 = 0.025;

/// Records per second of [`Protocol::SingleReadings`] \[Hz\]: a real rig's log rate.
pub const SINGLE_READING_RATE: f64 = 4.0;

/// The second gripper's step between two rests of [`Protocol::SingleReadings`] \[m\].
pub const SINGLE_READING_STEP: f64 = 0.017;

/// How far the walk of [`Protocol::SingleReadings`] goes from its first configuration, in
/// normalised `a`. A rig's session sweeps one region of the wire's configurations again and
/// again: on a real recording a map fitted on the first half in time does as well on an
/// interleaved split as on the second half (`shared/DESIGN.md`, "Real recordings"). An
/// unbounded walk instead leaves the first half's region (its tip up to 1.1 m from where it
/// started over 450 rests), and a map fitted there extrapolates. At this radius the tip stays
/// within 0.1–0.2 m of its start, and a 17 mm step crosses the region in tens of rests.
pub const WALK_RADIUS: f64 = 2.0;

/// Directions tried for one step of the walk before it starts anew at a sample of `A_free`.
const WALK_ATTEMPTS: usize = 40;

/// One reading of the sensor, the next that does not drop out (`None` after ten dropouts).
fn single_reading(rig: &mut ftwire_sim::SimRig) -> Option<Vector6<f64>> {
    (0..10).find_map(|_| rig.read_ft().ok()).map(|s| s.raw)
}

/// The walk of [`Protocol::SingleReadings`] through `A_free`: each rest a step of the second
/// gripper of [`SINGLE_READING_STEP`] (twice that one time in five) from the last, and the
/// sensor's load history carried along.
#[derive(Debug, Default)]
struct Walk {
    /// The walk's first configuration: it stays within [`WALK_RADIUS`] of it.
    home: Option<Vector6<f64>>,
    /// Whether the last configuration given is the first one (a start or a restart there).
    at_home: bool,
    last: Option<Vector6<f64>>,
    hysteresis: Option<Vector6<f64>>,
}

impl Walk {
    /// The next configuration: a step in a random direction of normalised `a`, scaled so that
    /// the gripper moves by the step, within [`WALK_RADIUS`] of the first configuration (a
    /// sample of `A_free`); back at the first configuration when no direction stays in
    /// `A_free` and within the radius, or after a failed placement.
    fn next(
        &mut self,
        rod: &Rod,
        sampler: &Sampler,
        rng: &mut ChaCha8Rng,
    ) -> Result<Vector6<f64>, LabError> {
        let fresh = |rng: &mut ChaCha8Rng| {
            sampler
                .sample_free(rod, rng)
                .map_err(|e| from_rod(e, "sampling A_free of the known wire"))
        };
        let wire = rod.wire();
        let Some(a) = self.last else {
            let a = match self.home {
                Some(home) => ftwire_rod::from_normalised(wire, &home),
                None => fresh(rng)?,
            };
            self.home.get_or_insert(ftwire_rod::to_normalised(wire, &a));
            self.at_home = true;
            self.last = Some(a);
            return Ok(a);
        };
        let home = self.home.unwrap_or_default();
        let z = ftwire_rod::to_normalised(wire, &a);
        let tip = |z: &Vector6<f64>| {
            rod.tip(&ftwire_rod::from_normalised(wire, z))
                .ok()
                .map(|p| p.translation.vector)
        };
        let target = if rng.random::<f64>() < 0.2 {
            2.0 * SINGLE_READING_STEP
        } else {
            SINGLE_READING_STEP
        };
        let here = tip(&z);
        for _ in 0..WALK_ATTEMPTS {
            let Some(here) = here else { break };
            let d: Vector6<f64> = Vector6::from_fn(|_, _| rng.random_range(-1.0..=1.0)).normalize();
            let probe = 0.2;
            let Some(moved) = tip(&(z + probe * d)) else {
                continue;
            };
            let per_unit = (moved - here).norm() / probe;
            if per_unit <= 0.0 {
                continue;
            }
            let next = z + (target / per_unit) * d;
            if next.amax() > sampler.half_width || (next - home).norm() > WALK_RADIUS {
                continue;
            }
            let b = ftwire_rod::from_normalised(wire, &next);
            let free = rod.is_stable(&b).unwrap_or(false)
                && rod
                    .solve(&b, ftwire_rod::DEFAULT_NODES)
                    .is_ok_and(|s| s.is_free());
            let step = tip(&next).map(|t| (t - here).norm());
            if free && step.is_some_and(|s| (0.5 * target..=2.0 * target).contains(&s)) {
                self.at_home = false;
                self.last = Some(b);
                return Ok(b);
            }
        }
        self.last = None;
        self.next(rod, sampler, rng)
    }

    /// A placement failed: the next rest starts anew, at the first configuration, or at a new
    /// first configuration when the first is where the placement failed.
    fn lost(&mut self) {
        if self.at_home {
            self.home = None;
        }
        self.last = None;
    }

    /// Records at this rest: one, two (one rest in five) or three (one in ten).
    fn records_at_rest(&self, rng: &mut ChaCha8Rng) -> usize {
        let u: f64 = rng.random();
        if u < 0.1 {
            3
        } else if u < 0.3 {
            2
        } else {
            1
        }
    }
}

/// The mean distance \[m\] between `Φ(a)` of `model` and a true centreline (100 matched arc
/// lengths).
///
/// # Errors
/// No answer when the model cannot solve at `a`.
pub fn shape_error(
    model: &KirchhoffModel,
    a: &Vector6<f64>,
    truth: &[Vector3<f64>],
) -> Result<f64, LabError> {
    let shape = model
        .shape(a, SHAPE_NODES)
        .map_err(|e| from_estimate(e, "the model's shape"))?;
    centreline_distance(&shape.positions, truth, DEFAULT_METRIC_SAMPLES)
        .map_err(|e| from_estimate(e, "the shape error"))
}

/// The errors of a map (`a_of` of each sample) on the samples `indices`.
///
/// # Errors
/// As [`shape_error`].
pub fn map_errors(
    model: &KirchhoffModel,
    samples: &[CalibrationSample],
    indices: &[usize],
    a_of: impl Fn(&CalibrationSample) -> Vector6<f64>,
) -> Result<MapErrors, LabError> {
    let (mut torque, mut force, mut shape, mut n) = (0.0, 0.0, 0.0, 0_usize);
    for sample in indices.iter().filter_map(|&i| samples.get(i)) {
        let a = a_of(sample);
        let t = sample.true_wrench;
        torque += (a.fixed_rows::<3>(0) - t.fixed_rows::<3>(0)).norm()
            / t.fixed_rows::<3>(0).norm().max(f64::MIN_POSITIVE);
        force += (a.fixed_rows::<3>(3) - t.fixed_rows::<3>(3)).norm()
            / t.fixed_rows::<3>(3).norm().max(f64::MIN_POSITIVE);
        shape += shape_error(model, &a, &sample.truth)?;
        n += 1;
    }
    let n = n.max(1) as f64;
    Ok(MapErrors {
        torque_rel: torque / n,
        force_rel: force / n,
        shape_mm: 1e3 * shape / n,
    })
}

/// The model the experiments' labels are made with, as `calibration.json` records it: the
/// loaded model under `gravity` (base clamp frame), or the weight-free one (also for the
/// loaded model with gravity off, which has no weight).
///
/// # Errors
/// As [`LabelModel::loaded`].
pub fn label_model(gravity: Gravity, kind: ModelKind) -> Result<LabelModel, EstimateError> {
    let g = gravity.vector();
    match kind {
        ModelKind::Loaded if g.norm() > 0.0 => LabelModel::loaded(g.into()),
        _ => Ok(LabelModel::WEIGHTLESS),
    }
}

/// How the experiments train a calibration: the default [`TrainParams`] with
/// [`TrainParams::through_zero`], since their readings are tared with the gripper empty. The
/// sensor's map then carries over to wires of any wrench scale: it has no intercept and its
/// network's remainder vanishes at small readings (docs/calibration.md, "Across wrench
/// scales"). Not [`TrainParams::anchored`]: with gravity on, the calibration wire's readings
/// never come near zero, and a free map's value there is an extrapolation.
pub fn train_params() -> TrainParams {
    TrainParams {
        through_zero: true,
        ..TrainParams::default()
    }
}

/// Collects `count` configurations on `wire` in the rig `setup`, trains the network with
/// [`train_params`] and `seed`, and evaluates it (see the module docs).
///
/// # Errors
/// Bad input for a bad wire or too few usable samples for the split; no answer when the
/// collection fails.
pub fn run(
    wire: &WireSpec,
    (gravity, kind): (Gravity, ModelKind),
    setup: &SimSetup,
    count: usize,
    seed: u64,
    progress: impl FnMut(usize),
) -> Result<CalibrationRun, LabError> {
    let start = Instant::now();
    let (samples, skipped, recording) =
        collect(wire, (gravity, kind), setup, count, seed, progress)?;
    let collect_s = start.elapsed().as_secs_f64();
    let data = Dataset::new(
        samples.iter().map(|s| s.raw).collect(),
        samples.iter().map(|s| s.label).collect(),
    )
    .map_err(|e| from_estimate(e, "the calibration data"))?;
    let config = train_params();
    let start = Instant::now();
    let calibration = Calibration::train(&data, &config, seed)
        .and_then(|c| c.with_provenance(label_model(gravity, kind)?, CalibrationInput::Tared))
        .map_err(|e| {
            from_estimate(
                e,
                &format!("training the calibration on {count} configurations"),
            )
        })?;
    let train_s = start.elapsed().as_secs_f64();
    // `Calibration::train` draws its split first from ChaCha8(seed): the same draw here gives
    // the same indices.
    let split = data
        .split(&config.split, &mut ChaCha8Rng::seed_from_u64(seed))
        .map_err(|e| from_estimate(e, "the calibration split"))?;
    let model = known_model(wire, gravity, kind)?;
    let raw = map_errors(&model, &samples, &split.test, |s| s.mounting)?;
    let calibrated = map_errors(&model, &samples, &split.test, |s| calibration.apply(&s.raw))?;
    let all: Vec<usize> = (0..samples.len()).collect();
    let label_shape = map_errors(&model, &samples, &all, |s| s.label)?.shape_mm;
    let n = samples.len().max(1) as f64;
    let summary = CalibrationSummary {
        wire: wire.clone(),
        model: kind,
        samples: SampleCounts {
            train: split.train.len(),
            validation: split.validation.len(),
            test: split.test.len(),
        },
        raw,
        calibrated,
        label_fit_mm: 1e3 * samples.iter().map(|s| s.label_rms).sum::<f64>() / n,
        label_shape_mm: label_shape,
        skipped,
    };
    Ok(CalibrationRun {
        calibration,
        samples,
        recording,
        split,
        summary,
        timings: CalibrationTimings { collect_s, train_s },
    })
}

/// The calibration weights of `file`, or else a fresh run on [`KNOWN_WIRE`] with
/// [`DEFAULT_SAMPLES`] configurations in the rig `setup`, whose sensor the network then learns
/// (the experiments that need a calibration cache it in
/// their results folder as `calibration.json`). Returns the run when one was made.
///
/// # Errors
/// Bad input for an unreadable or invalid weights file; as [`run`] otherwise.
pub fn load_or_run(
    file: Option<&Path>,
    (gravity, kind): (Gravity, ModelKind),
    setup: &SimSetup,
    seed: u64,
    progress: impl FnMut(usize),
) -> Result<(Calibration, Option<CalibrationRun>), LabError> {
    if let Some(path) = file {
        let calibration = Calibration::load(path)
            .map_err(|e| LabError::bad_input(format!("--calibration {}: {e}", path.display())))?;
        return Ok((calibration, None));
    }
    let wire = WireSpec::preset(KNOWN_WIRE)
        .ok_or_else(|| LabError::bad_input(format!("no preset {KNOWN_WIRE}")))?;
    let run = run(
        &wire,
        (gravity, kind),
        setup,
        DEFAULT_SAMPLES,
        seed,
        progress,
    )?;
    Ok((run.calibration.clone(), Some(run)))
}

/// [`load_or_run`] for an experiment writing `folder`: says when it calibrates first to
/// `progress`, and caches a fresh run's weights there as `calibration.json`. Returns the
/// calibration and the time it took \[s\].
///
/// # Errors
/// As [`load_or_run`], and the folder's write errors.
pub fn load_or_run_reporting(
    folder: &crate::results::ResultsFolder,
    file: Option<&Path>,
    (gravity, kind): (Gravity, ModelKind),
    (setup, seed): (&SimSetup, u64),
    progress: super::Progress<'_>,
) -> Result<(Calibration, f64), LabError> {
    if file.is_none() {
        progress("no --calibration: calibrating on the known wire first");
    }
    let start = Instant::now();
    let (calibration, calibration_run) = load_or_run(file, (gravity, kind), setup, seed, |_| {})?;
    let seconds = start.elapsed().as_secs_f64();
    if calibration_run.is_some() {
        let json = calibration
            .to_json()
            .map_err(|e| from_estimate(e, "writing the calibration weights"))?;
        folder.write("calibration.json", json)?;
    }
    Ok((calibration, seconds))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_label_is_rejected_only_beyond_the_sensors_own_errors() {
        let label = Vector6::new(0.5, -0.2, 0.1, 4.0, -3.0, 2.0);
        // A 2 % gain error and some noise: kept.
        let close = label * 1.02 + Vector6::repeat(0.003);
        assert!(!label_disagrees(&label, &close));
        // The same shape fitted with another tension: the force is 30 % off.
        let mut taut = label;
        taut[3] *= 1.3;
        assert!(label_disagrees(&label, &taut));
        // A torque off by half: rejected on the torque alone.
        let mut twisted = label;
        twisted[0] *= 1.5;
        assert!(label_disagrees(&label, &twisted));
        // Near zero the slack keeps a noise-sized difference.
        let small = Vector6::repeat(1e-3);
        assert!(!label_disagrees(&small, &(small * 3.0)));
    }

    /// The single-readings walk stays within its radius of where it started, and its second
    /// half revisits the region of its first (the time split a rig's session gives).
    #[test]
    fn the_walk_sweeps_one_region_again_and_again() -> Result<(), Box<dyn std::error::Error>> {
        let wire = WireSpec::preset("nitinol-2mm-630")
            .ok_or("no preset")?
            .wire_params()?;
        let rod = Rod::new(wire);
        let sampler = Sampler::default();
        for seed in 1..=3 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut walk = Walk::default();
            let z: Vec<Vector6<f64>> = (0..160)
                .map(|_| {
                    walk.next(&rod, &sampler, &mut rng)
                        .map(|a| ftwire_rod::to_normalised(&wire, &a))
                })
                .collect::<Result<_, _>>()?;
            let home = z[0];
            let far = z.iter().map(|z| (z - home).norm()).fold(0.0, f64::max);
            assert!(far <= WALK_RADIUS + 1e-9, "seed {seed}: {far} from home");
            // The tips [m]: within a region of a few tenths of a metre (an unbounded walk of
            // this many 17 mm steps goes further), its second half near its first.
            let tips: Vec<Vector3<f64>> = z
                .iter()
                .map(|z| rod.tip(&ftwire_rod::from_normalised(&wire, z)))
                .map(|t| t.map(|t| t.translation.vector))
                .collect::<Result<_, _>>()?;
            let spread = tips
                .iter()
                .map(|t| (t - tips[0]).norm())
                .fold(0.0, f64::max);
            assert!(
                spread < 0.25,
                "seed {seed}: the tip went {spread} m from its start"
            );
            let (first, second) = tips.split_at(tips.len() / 2);
            let mut nearest: Vec<f64> = second
                .iter()
                .map(|b| {
                    first
                        .iter()
                        .map(|a| (a - b).norm())
                        .fold(f64::INFINITY, f64::min)
                })
                .collect();
            nearest.sort_by(f64::total_cmp);
            let median = nearest[nearest.len() / 2];
            assert!(
                median < 2.0 * SINGLE_READING_STEP,
                "seed {seed}: the second half's tips are a median {median} m from the first's"
            );
            let mut steps: Vec<f64> = tips.windows(2).map(|w| (w[1] - w[0]).norm()).collect();
            steps.sort_by(f64::total_cmp);
            let step = steps[steps.len() / 2];
            assert!(
                (0.010..0.030).contains(&step),
                "seed {seed}: median step {step} m"
            );
        }
        Ok(())
    }
}
