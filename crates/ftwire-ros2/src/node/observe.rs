//! What `ftwire ros2 estimate` does per rest and per move, beside its shape per sample: the
//! rests of the second gripper found from the streams, the bias observer updated at each, and
//! the collision detector run on each move between two rests. The same library calls as the
//! simulator experiments' closed loops (`ftwire_control::Controller` with a bias observer and
//! a detector):
//!
//! 1. **rest** ([`RestDetector`]): the reported tip pose stays within `position_tolerance`
//!    and `angle_tolerance` of the pose that began a still period for `dwell` seconds (by the
//!    stamps), and the F/T samples of the period span `dwell − settle` from `settle` after its
//!    start (or from the first sample after the tare, for a period that began before the tare
//!    ended). The tared F/T samples stamped from `settle` after its start to the pose that
//!    completed the dwell are averaged (`ftwire_estimate::ft::RestAverage`) and mapped to `ã`
//!    through the calibration or the mounting (as `ftwire shape --log` maps a record's `raw`),
//!    with each component's standard error propagated to first order
//!    (`ftwire_estimate::ft::FtPipeline::measure`); the tip poses of the period are averaged
//!    (positions, and rotation vectors about the first). One still period gives one rest, at
//!    the end of its dwell; the tip must move beyond the tolerances before the next.
//! 2. **bias**: `ftwire_control::BiasObserver::update` with the rest (`ã`, its standard
//!    errors, the mean tip pose, the rest's last stamp), built with
//!    [`ftwire_lab::experiment::rig::bias_observer`]'s settings for the node's sensor; every
//!    later `ã` goes into the shape as `BiasObserver::correct(ã) = ã − β̂`, the correction the
//!    experiments' controller steers by.
//! 3. **collision**: between two consecutive rests the move's check,
//!    `ftwire_control::MoveCheck::of_move` (the measured change of the raw `ã` against the
//!    model's Newton prediction for the reported motion `b_i⁻¹ b_{i+1}`, from the first-order
//!    guess `J(L)⁻¹ log(b_i⁻¹ b_{i+1})` at `ã_i`). The first `calibration_moves` moves are
//!    taken as free of contact and calibrate the detector as the goal experiment does
//!    ([`ftwire_lab::goal::detector_from_free_moves`]: floor from the rests' noise, slope and
//!    threshold from the moves); from then on each move's cumulative residual
//!    (`CollisionDetector::residual`) above the threshold is a contact, until a later move's
//!    residual falls back below it. The detector watches the raw `ã`, never the corrected
//!    one, so that a contact is not explained away as drift. It gives no location: the node
//!    draws the contact at the estimated shape's tip.

use ftwire_control::{
    BiasObserver, BiasObserverParams, CollisionDetector, MoveCheck, predicted_delta_a,
};
use ftwire_core::{FtSample, Pose};
use ftwire_estimate::ft::{FtCalibration, FtPipeline, RestAverage, Tare};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_lab::goal::detector_from_free_moves;
use ftwire_lab::log::RawMap;
use ftwire_rod::{se3, to_normalised};
use nalgebra::{Translation3, UnitQuaternion, Vector3, Vector6};
use serde::Serialize;

use super::{NodeError, a_of_raw};

/// Fewest tared samples a rest averages.
pub const MIN_REST_SAMPLES: usize = 10;

/// Most samples a still period keeps while it waits for its dwell (a tip pose topic that
/// stops would otherwise let them grow without end): 10 minutes at 1 kHz.
const MAX_KEPT: usize = 600_000;

/// How a rest is found in the streams.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RestParams {
    /// The tip moves when its position leaves the still period's first pose by more than
    /// this \[m\] (default `0.001`).
    pub position_tolerance: f64,
    /// … or its orientation by more than this \[rad\] (default 1°).
    pub angle_tolerance: f64,
    /// A still period is a rest once it has lasted this long \[s\] (default `0.5`).
    pub dwell: f64,
    /// Samples of a rest's first `settle` seconds are left out of its average, while the
    /// robot settles \[s\], less than `dwell` (default `0.1`).
    pub settle: f64,
}

impl Default for RestParams {
    fn default() -> Self {
        Self {
            position_tolerance: 1e-3,
            angle_tolerance: 1f64.to_radians(),
            dwell: 0.5,
            settle: 0.1,
        }
    }
}

impl RestParams {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`NodeError::BadSetting`] for a tolerance that is not a positive distance or angle, a
    /// dwell outside 0.01 to 600 s, or a settle time that is negative or not below the dwell.
    pub fn validate(&self) -> Result<(), NodeError> {
        if !(self.position_tolerance.is_finite() && self.position_tolerance > 0.0) {
            return Err(NodeError::BadSetting {
                setting: "--rest-tolerance-mm",
                value: (1e3 * self.position_tolerance).to_string(),
                allowed: "a positive distance in mm",
            });
        }
        if !(self.angle_tolerance.is_finite() && self.angle_tolerance > 0.0) {
            return Err(NodeError::BadSetting {
                setting: "--rest-tolerance-deg",
                value: self.angle_tolerance.to_degrees().to_string(),
                allowed: "a positive angle in degrees",
            });
        }
        if !(self.dwell.is_finite() && (0.01..=600.0).contains(&self.dwell)) {
            return Err(NodeError::BadSetting {
                setting: "--rest-dwell",
                value: self.dwell.to_string(),
                allowed: "0.01 to 600 s",
            });
        }
        if !(self.settle.is_finite() && self.settle >= 0.0 && self.settle < self.dwell) {
            return Err(NodeError::BadSetting {
                setting: "--rest-settle",
                value: self.settle.to_string(),
                allowed: "0 s or more, less than --rest-dwell",
            });
        }
        Ok(())
    }
}

/// One rest found in the streams: its samples and where the tip was.
#[derive(Debug, Clone, PartialEq)]
pub struct RestWindow {
    /// The stamp of the pose that began the still period \[s\].
    pub start: f64,
    /// The stamp of the pose that completed the dwell \[s\].
    pub end: f64,
    /// The raw samples (force first, sensor frame) stamped from `start + settle` to `end`.
    pub samples: Vec<FtSample>,
    /// The mean reported tip pose over the period, relative to the base clamp.
    pub tip: Pose,
}

/// Finds the rests of the second gripper in the tip pose and F/T streams (module docs, step
/// 1). Poses and samples come in any interleaving; each carries its stamp.
#[derive(Debug, Clone)]
pub struct RestDetector {
    params: RestParams,
    /// The first pose of the current still period, with its stamp.
    anchor: Option<(f64, Pose)>,
    /// Sums of the period's positions and rotation vectors (about the anchor's), and their
    /// count.
    position_sum: Vector3<f64>,
    rotation_sum: Vector3<f64>,
    poses: usize,
    /// Samples stamped at or after the anchor, while the period has not given its rest.
    samples: Vec<FtSample>,
    /// The period has given its rest.
    done: bool,
}

impl RestDetector {
    /// A detector with `params` (checked by [`RestParams::validate`]).
    pub fn new(params: RestParams) -> Self {
        Self {
            params,
            anchor: None,
            position_sum: Vector3::zeros(),
            rotation_sum: Vector3::zeros(),
            poses: 0,
            samples: Vec::new(),
            done: false,
        }
    }

    /// Takes a tared-stream sample (its `time` the stamp).
    pub fn sample(&mut self, sample: FtSample) {
        let Some((start, _)) = self.anchor else {
            return;
        };
        if self.done || sample.time < start {
            return;
        }
        if self.samples.len() >= MAX_KEPT {
            self.samples.drain(..MAX_KEPT / 2);
        }
        self.samples.push(sample);
    }

    /// Takes a tip pose stamped `time` \[s\]; returns the rest it completes, if any.
    pub fn pose(&mut self, time: f64, pose: &Pose) -> Option<RestWindow> {
        let Some((start, anchor)) = self.anchor else {
            self.begin(time, pose);
            return None;
        };
        if time < start {
            return None;
        }
        let moved = (pose.translation.vector - anchor.translation.vector).norm()
            > self.params.position_tolerance
            || (anchor.rotation.inverse() * pose.rotation).angle() > self.params.angle_tolerance;
        if moved {
            self.begin(time, pose);
            return None;
        }
        self.position_sum += pose.translation.vector;
        self.rotation_sum += (anchor.rotation.inverse() * pose.rotation).scaled_axis();
        self.poses += 1;
        if self.done || time - start < self.params.dwell {
            return None;
        }
        // The average spans `dwell − settle`, from the settle time or from the first sample
        // after it (a period that began before the tare ended).
        let from = start + self.params.settle;
        let first = self.samples.iter().find(|s| s.time >= from)?.time;
        if time - first < self.params.dwell - self.params.settle - 1e-9 {
            return None;
        }
        let samples: Vec<FtSample> = self
            .samples
            .iter()
            .filter(|s| s.time >= from && s.time <= time)
            .cloned()
            .collect();
        if samples.len() < MIN_REST_SAMPLES {
            return None;
        }
        self.done = true;
        self.samples.clear();
        #[allow(clippy::cast_precision_loss)] // poses of one period, far below 2⁵²
        let n = self.poses as f64;
        let tip = Pose::from_parts(
            Translation3::from(self.position_sum / n),
            anchor.rotation * UnitQuaternion::from_scaled_axis(self.rotation_sum / n),
        );
        Some(RestWindow {
            start,
            end: time,
            samples,
            tip,
        })
    }

    /// A new still period from the pose stamped `time`; samples stamped before it are let go.
    fn begin(&mut self, time: f64, pose: &Pose) {
        self.anchor = Some((time, *pose));
        self.position_sum = pose.translation.vector;
        self.rotation_sum = Vector3::zeros();
        self.poses = 1;
        self.samples.retain(|s| s.time >= time);
        self.done = false;
    }
}

/// The node's raw→`ã` map at one time, as the F/T pipeline's calibration stage.
struct MapAt<'a> {
    map: &'a RawMap,
    time: f64,
}

impl FtCalibration for MapAt<'_> {
    fn configuration(&self, tared: &Vector6<f64>) -> Vector6<f64> {
        a_of_raw(tared, self.time, self.map).unwrap_or_else(|_| Vector6::repeat(f64::NAN))
    }
}

/// One rest measured: `ã` with its standard errors, at the mean tip pose.
#[derive(Debug, Clone, PartialEq)]
pub struct RestSample {
    /// The stamp of the rest's end \[s\].
    pub time: f64,
    /// `ã` of the rest's mean (torque first, base clamp frame) \[N·m, N\].
    pub a: Vector6<f64>,
    /// The standard error of each component of `a` \[N·m, N\].
    pub a_std: Vector6<f64>,
    /// The mean reported tip pose, relative to the base clamp.
    pub tip: Pose,
    /// Samples averaged.
    pub samples: usize,
}

/// `ã` of a rest: its samples tared (`tare`), averaged and mapped through `map`.
///
/// # Errors
/// The pipeline's message when too few samples are good or the map gives a value that is not
/// finite.
pub fn measure_rest(window: &RestWindow, tare: Tare, map: &RawMap) -> Result<RestSample, String> {
    let average = RestAverage::new((window.samples.len() / 2).max(2)).map_err(|e| e.to_string())?;
    let calibration = MapAt {
        map,
        time: window.end,
    };
    let m = FtPipeline::new(average, tare, calibration)
        .measure(window.samples.iter().map(Some))
        .map_err(|e| e.to_string())?;
    Ok(RestSample {
        time: window.end,
        a: m.a,
        a_std: m.a_std_error,
        tip: window.tip,
        samples: window.samples.len(),
    })
}

/// What `estimate` observes per rest and per move.
#[derive(Debug, Clone, PartialEq)]
pub struct ObserveParams {
    /// How rests are found.
    pub rest: RestParams,
    /// The bias observer's settings; `None`: no observer (`--bias-observer off`).
    pub bias_observer: Option<BiasObserverParams>,
    /// Free moves that calibrate the collision detector, at least
    /// [`ftwire_control::MIN_CALIBRATION_RESIDUALS`]; 0: no detector (default 10).
    pub calibration_moves: usize,
}

impl Default for ObserveParams {
    fn default() -> Self {
        Self {
            rest: RestParams::default(),
            bias_observer: Some(BiasObserverParams::default()),
            calibration_moves: 10,
        }
    }
}

impl ObserveParams {
    /// Checks the settings.
    ///
    /// # Errors
    /// As [`RestParams::validate`]; [`NodeError::BadSetting`] for calibration moves between 1
    /// and [`ftwire_control::MIN_CALIBRATION_RESIDUALS`] − 1, or above 10 000.
    pub fn validate(&self) -> Result<(), NodeError> {
        self.rest.validate()?;
        let n = self.calibration_moves;
        if n != 0 && !(ftwire_control::MIN_CALIBRATION_RESIDUALS..=10_000).contains(&n) {
            return Err(NodeError::BadSetting {
                setting: "--collision-calibration",
                value: n.to_string(),
                allowed: "0 (no collision detector) or 10 to 10000 free moves",
            });
        }
        Ok(())
    }
}

/// The collision detector's state.
#[derive(Debug, Clone)]
enum Detector {
    /// No detector.
    Off,
    /// Collecting free moves and the rests' noise to calibrate on.
    Calibrating { noise: Vec<f64> },
    /// Calibrated: each move's residual is tested.
    Armed {
        detector: CollisionDetector,
        floor: f64,
    },
}

/// The calibrated detector, for the summary.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DetectorSummary {
    /// The threshold on the residual.
    pub threshold: f64,
    /// The residual's floor \[normalised\].
    pub floor: f64,
    /// The model's error per unit of the move's bound \[-\].
    pub slope: f64,
    /// Moves summed in the residual.
    pub window: usize,
    /// Free moves it was calibrated on.
    pub calibrated_on: usize,
}

/// The bias observer's counts and estimate, for the summary.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ObserverSummary {
    /// The last estimate `β̂` (torque first, base clamp frame) \[N·m, N\].
    pub bias: [f64; 6],
    /// Rests used.
    pub updates: usize,
    /// Rests beyond the gate, not used.
    pub rejected: usize,
}

/// What happened at one rest, for the log.
#[derive(Debug, Clone, PartialEq)]
pub enum RestEvent {
    /// A rest used: its index (from 1), `ã`'s samples, and the move's residual when armed.
    Rest {
        /// Rests so far.
        index: u64,
        /// The rest's end \[s\].
        time: f64,
        /// Samples averaged.
        samples: usize,
        /// The move's residual, once the detector is armed.
        residual: Option<f64>,
        /// The detector flags the move.
        contact: bool,
        /// The bias observer used the rest (`false`: beyond its gate), with an observer.
        bias_used: Option<bool>,
    },
    /// The detector was calibrated.
    Calibrated(DetectorSummary),
    /// The detector could not be calibrated on the moves so far (it tries again at the next).
    NotCalibrated(String),
    /// A rest that could not be measured.
    Failed(String),
}

/// The per-rest and per-move state of `estimate` (module docs).
pub struct Observer {
    model: KirchhoffModel,
    params: ObserveParams,
    rests: RestDetector,
    observer: Option<BiasObserver<KirchhoffModel>>,
    detector: Detector,
    /// Every move's check, in order.
    checks: Vec<MoveCheck>,
    /// The last rest measured.
    last: Option<RestSample>,
    /// Rests measured.
    pub count: u64,
    /// Moves the detector flagged.
    pub contact_moves: u64,
    /// The last move's residual once armed, and whether it is a contact.
    residual: Option<(f64, bool)>,
}

impl Observer {
    /// The observer of `model`'s wire with `params` (checked by [`ObserveParams::validate`]).
    ///
    /// # Errors
    /// [`NodeError::BadSetting`] for bias observer settings the library refuses.
    pub fn new(model: KirchhoffModel, params: &ObserveParams) -> Result<Self, NodeError> {
        let observer = params
            .bias_observer
            .map(|settings| BiasObserver::new(model, settings))
            .transpose()
            .map_err(|e| NodeError::BadSetting {
                setting: "--sensor",
                value: e.to_string(),
                allowed: "a sensor whose noise and drift give valid bias observer settings",
            })?;
        let detector = if params.calibration_moves == 0 {
            Detector::Off
        } else {
            Detector::Calibrating { noise: Vec::new() }
        };
        Ok(Self {
            model,
            params: params.clone(),
            rests: RestDetector::new(params.rest),
            observer,
            detector,
            checks: Vec::new(),
            last: None,
            count: 0,
            contact_moves: 0,
            residual: None,
        })
    }

    /// Takes a raw sample stamped `time` once the tare is known.
    pub fn sample(&mut self, time: f64, raw: Vector6<f64>) {
        self.rests.sample(FtSample {
            time,
            raw,
            saturated: [false; 6],
        });
    }

    /// Takes a tip pose stamped `time`; at the end of a rest, measures it (with `tare` and
    /// `map`) and runs the observer and the detector on it.
    pub fn pose(
        &mut self,
        time: f64,
        pose: &Pose,
        tare: Option<Tare>,
        map: &RawMap,
    ) -> Vec<RestEvent> {
        let (Some(window), Some(tare)) = (self.rests.pose(time, pose), tare) else {
            return Vec::new();
        };
        match measure_rest(&window, tare, map) {
            Ok(rest) => self.rest(rest),
            Err(e) => vec![RestEvent::Failed(e)],
        }
    }

    /// Runs the bias observer and the collision detector on a measured rest.
    pub fn rest(&mut self, rest: RestSample) -> Vec<RestEvent> {
        let mut events = Vec::new();
        self.count += 1;
        let bias_used = self.observer.as_mut().map(|observer| {
            let before = observer.updates();
            observer.update(&rest.a, &rest.a_std, &rest.tip, rest.time);
            observer.updates() > before
        });
        let noise = to_normalised(self.model.wire(), &rest.a_std).norm();
        if let Some(last) = self.last.take() {
            self.checks.push(self.check(&last, &rest));
        }
        let mut residual = None;
        let mut contact = false;
        match &mut self.detector {
            Detector::Off => {}
            Detector::Calibrating { noise: levels } => {
                levels.push(noise);
                if self.checks.len() >= self.params.calibration_moves {
                    match detector_from_free_moves(levels, &[&self.checks]) {
                        Ok((detector, floor)) => {
                            events.push(RestEvent::Calibrated(DetectorSummary {
                                threshold: detector.threshold(),
                                floor,
                                slope: detector.slope(),
                                window: detector.window(),
                                calibrated_on: self.checks.len(),
                            }));
                            self.detector = Detector::Armed { detector, floor };
                        }
                        Err(e) => events.push(RestEvent::NotCalibrated(e.to_string())),
                    }
                }
            }
            Detector::Armed { detector, .. } => {
                let r = detector.residual(&self.checks);
                contact = detector.is_contact(r);
                residual = Some(r);
                self.residual = Some((r, contact));
                self.contact_moves += u64::from(contact);
            }
        }
        // Only the detector's window of moves is ever summed again.
        let keep = ftwire_control::MIN_CALIBRATION_RESIDUALS.max(self.params.calibration_moves);
        if matches!(self.detector, Detector::Armed { .. }) && self.checks.len() > 2 * keep {
            self.checks.drain(..self.checks.len() - keep);
        }
        events.push(RestEvent::Rest {
            index: self.count,
            time: rest.time,
            samples: rest.samples,
            residual,
            contact,
            bias_used,
        });
        self.last = Some(rest);
        events
    }

    /// The check of the move from rest `before` to rest `after`.
    fn check(&self, before: &RestSample, after: &RestSample) -> MoveCheck {
        let motion = before.tip.inverse() * after.tip;
        let first_order = self
            .model
            .jacobian(&before.a)
            .ok()
            .and_then(|s| predicted_delta_a(&s.jacobian, &se3::log(&motion)))
            .unwrap_or_else(Vector6::zeros);
        MoveCheck::of_move(&self.model, &before.a, &after.a, &motion, &first_order)
    }

    /// `ã` corrected by the bias estimate (`BiasObserver::correct`); `a` itself without an
    /// observer.
    pub fn correct(&self, a: &Vector6<f64>) -> Vector6<f64> {
        self.observer.as_ref().map_or(*a, |o| o.correct(a))
    }

    /// The bias estimate `β̂` (torque first, base clamp frame) \[N·m, N\], with an observer.
    pub fn bias(&self) -> Option<[f64; 6]> {
        self.observer.as_ref().map(|o| o.bias().into())
    }

    /// The last move's residual once the detector is armed, and whether it is a contact.
    pub fn residual(&self) -> Option<(f64, bool)> {
        self.residual
    }

    /// The calibrated detector.
    pub fn detector(&self) -> Option<DetectorSummary> {
        match &self.detector {
            Detector::Armed { detector, floor } => Some(DetectorSummary {
                threshold: detector.threshold(),
                floor: *floor,
                slope: detector.slope(),
                window: detector.window(),
                calibrated_on: self.params.calibration_moves,
            }),
            _ => None,
        }
    }

    /// The bias observer's estimate and counts.
    pub fn observer(&self) -> Option<ObserverSummary> {
        self.observer.as_ref().map(|o| ObserverSummary {
            bias: o.bias().into(),
            updates: o.updates(),
            rejected: o.rejected(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ftwire_core::WireParams;
    use ftwire_rod::from_normalised;

    fn pose(x: f64, angle: f64) -> Pose {
        Pose::from_parts(
            Translation3::new(x, 0.2, 0.0),
            UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, angle)),
        )
    }

    fn sample(time: f64, value: f64) -> FtSample {
        FtSample {
            time,
            raw: Vector6::repeat(value),
            saturated: [false; 6],
        }
    }

    /// Poses at 100 Hz and samples at 1 kHz from `t0` for `seconds`, the samples worth `value`.
    fn feed(
        rests: &mut RestDetector,
        t0: f64,
        seconds: f64,
        at: &Pose,
        value: f64,
    ) -> Vec<RestWindow> {
        let mut found = Vec::new();
        for k in 0..(seconds * 1000.0).round() as usize {
            let t = t0 + k as f64 * 1e-3;
            rests.sample(sample(t, value));
            if k % 10 == 0 {
                found.extend(rests.pose(t, at));
            }
        }
        found
    }

    #[test]
    fn a_still_period_gives_one_rest_after_its_dwell_without_its_settle() {
        let params = RestParams::default();
        let mut rests = RestDetector::new(params);
        let found = feed(&mut rests, 0.0, 2.0, &pose(0.5, 0.0), 1.0);
        assert_eq!(found.len(), 1, "one rest per still period");
        let rest = &found[0];
        assert!((rest.end - params.dwell).abs() < 1e-9, "{}", rest.end);
        let first = rest.samples.first().map_or(f64::NAN, |s| s.time);
        assert!((first - params.settle).abs() < 1e-9, "{first}");
        // Samples from the settle to the dwell, both included, at 1 kHz.
        assert_eq!(rest.samples.len(), 401);
        assert!((rest.tip.translation.vector.x - 0.5).abs() < 1e-12);
    }

    #[test]
    fn a_move_starts_a_new_rest_and_jitter_within_the_tolerance_does_not() {
        let params = RestParams::default();
        let mut rests = RestDetector::new(params);
        assert_eq!(feed(&mut rests, 0.0, 0.3, &pose(0.5, 0.0), 1.0).len(), 0);
        // 0.5 mm and 0.5° of jitter: still.
        let mut found = Vec::new();
        for (i, k) in (300..1000).step_by(10).enumerate() {
            let t = k as f64 * 1e-3;
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            for j in 0..10 {
                rests.sample(sample(t + j as f64 * 1e-3, 1.0));
            }
            found.extend(rests.pose(t, &pose(0.5 + sign * 5e-4, sign * 0.5f64.to_radians())));
        }
        assert_eq!(found.len(), 1);
        // The mean pose of the jitter is the pose it jitters about.
        assert!((found[0].tip.translation.vector.x - 0.5).abs() < 1e-4);
        assert!(found[0].tip.rotation.angle() < 1e-2);
        // A move of 2 mm: a new still period, whose rest averages only its own samples.
        let moved = feed(&mut rests, 1.0, 1.0, &pose(0.502, 0.0), 3.0);
        assert_eq!(moved.len(), 1);
        assert!((moved[0].start - 1.0).abs() < 1e-9);
        assert!(moved[0].samples.iter().all(|s| s.raw[0] == 3.0));
        // A turn of 2° is a move too.
        let turned = feed(&mut rests, 2.0, 0.6, &pose(0.502, 2f64.to_radians()), 5.0);
        assert_eq!(turned.len(), 1);
        assert!((turned[0].start - 2.0).abs() < 1e-9);
    }

    #[test]
    fn a_still_period_from_before_the_tare_rests_once_its_samples_span_the_dwell() {
        let params = RestParams::default();
        let mut rests = RestDetector::new(params);
        // Poses from 0 s, samples (after the tare) from 0.5 s.
        let mut found = Vec::new();
        for k in 0..2000 {
            let t = k as f64 * 1e-3;
            if t >= 0.5 {
                rests.sample(sample(t, 1.0));
            }
            if k % 10 == 0 {
                found.extend(rests.pose(t, &pose(0.5, 0.0)));
            }
        }
        assert_eq!(found.len(), 1);
        assert!((found[0].end - 0.9).abs() < 1e-9, "{}", found[0].end);
        assert_eq!(found[0].samples.len(), 401);
    }

    #[test]
    fn a_still_period_shorter_than_the_dwell_or_without_samples_is_no_rest() {
        let mut rests = RestDetector::new(RestParams::default());
        let mut found = Vec::new();
        for i in 0..10 {
            // Moves every 0.4 s: never a dwell of 0.5 s.
            found.extend(feed(
                &mut rests,
                0.4 * i as f64,
                0.4,
                &pose(0.5 + 0.01 * i as f64, 0.0),
                1.0,
            ));
        }
        assert!(found.is_empty());
        // Poses alone, no F/T samples.
        let mut quiet = RestDetector::new(RestParams::default());
        let none: Vec<RestWindow> = (0..200)
            .filter_map(|k| quiet.pose(k as f64 * 0.01, &pose(0.5, 0.0)))
            .collect();
        assert!(none.is_empty());
    }

    #[test]
    fn rest_settings_are_checked() {
        assert!(RestParams::default().validate().is_ok());
        for bad in [
            RestParams {
                position_tolerance: 0.0,
                ..RestParams::default()
            },
            RestParams {
                angle_tolerance: f64::NAN,
                ..RestParams::default()
            },
            RestParams {
                dwell: 0.0,
                ..RestParams::default()
            },
            RestParams {
                settle: 0.5,
                ..RestParams::default()
            },
        ] {
            assert!(bad.validate().is_err(), "{bad:?}");
        }
        let few = ObserveParams {
            calibration_moves: 3,
            ..ObserveParams::default()
        };
        assert!(few.validate().is_err());
    }

    fn wire() -> WireParams {
        WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire")
    }

    /// Rests of the model's wire at configurations along a motion, read with `bias` added.
    fn rests_along(bias: &Vector6<f64>, n: usize) -> Vec<RestSample> {
        let model = KirchhoffModel::new(wire());
        (0..n)
            .map(|i| {
                let s = i as f64 / n as f64;
                let a = from_normalised(
                    &wire(),
                    &Vector6::new(0.3 * s, 1.0 - s, 0.5, -1.0 + 0.8 * s, 0.5 - s, 0.2 * s),
                );
                RestSample {
                    time: i as f64,
                    a: a + bias,
                    a_std: Vector6::new(1e-5, 1e-5, 1e-5, 1e-3, 1e-3, 1e-3),
                    tip: model.tip(&a).expect("solves"),
                    samples: 400,
                }
            })
            .collect()
    }

    #[test]
    fn the_bias_estimate_moves_to_a_constant_bias_and_free_moves_arm_the_detector() {
        let model = KirchhoffModel::new(wire());
        // A bias of a few of the observer's prior σ, for a robot that reports where its
        // gripper is: the node's settings for the default sensor.
        let bias = Vector6::new(1e-4, 0.0, -1e-4, 0.01, -0.008, 0.006);
        let params = ObserveParams {
            bias_observer: ftwire_lab::experiment::rig::bias_observer(
                &ftwire_lab::setup::SimSetup::default(),
                ftwire_control::NoiseModel::None,
                true,
            ),
            ..ObserveParams::default()
        };
        let mut observer = Observer::new(model, &params).expect("valid");
        let mut calibrated = false;
        for rest in rests_along(&bias, 14) {
            for event in observer.rest(rest) {
                calibrated |= matches!(event, RestEvent::Calibrated(_));
                if let RestEvent::Rest { contact, .. } = event {
                    assert!(!contact, "free moves");
                }
            }
        }
        assert!(calibrated);
        assert_eq!(observer.count, 14);
        let estimate = Vector6::from(observer.bias().expect("an observer"));
        assert!(
            (estimate - bias).norm() < 0.5 * bias.norm(),
            "{estimate} vs {bias}"
        );
        let a = Vector6::new(0.0, 0.1, 0.0, -0.2, 0.1, 0.0);
        assert!((observer.correct(&a) - (a - estimate)).norm() < 1e-15);
        // A force the model does not have, growing over the next moves: a contact.
        let mut contact = false;
        let more = rests_along(&Vector6::zeros(), 20);
        for (i, mut rest) in more.into_iter().skip(14).enumerate() {
            rest.a += bias + Vector6::new(0.0, 0.0, 0.0, 0.0, 0.05 * (i + 1) as f64, 0.0);
            rest.time += 14.0;
            for event in observer.rest(rest) {
                if let RestEvent::Rest { contact: c, .. } = event {
                    contact |= c;
                }
            }
        }
        assert!(contact);
        assert!(observer.contact_moves > 0);
        assert!(observer.residual().is_some_and(|(_, c)| c));
    }
}
