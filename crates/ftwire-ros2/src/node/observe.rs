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
//!    the end of its dwell; the tip must move beyond the tolerances before the next. A rest
//!    is defined by the stamps alone: poses and samples are taken in stamp order whatever
//!    order they arrive in (each stream in its own order; a pose waits for the first sample
//!    stamped after it, a sample for the first pose), so the same stamped streams give the
//!    same rests and the same `ã` in any interleaving.
//! 2. **bias**: `ftwire_control::BiasObserver::update` with the rest (`ã`, its standard
//!    errors, the mean tip pose, the rest's last stamp), built with
//!    [`BiasObserverParams::for_sensor`]'s settings for the node's sensor; every
//!    later `ã` goes into the shape as `BiasObserver::correct(ã) = ã − β̂`, the correction the
//!    experiments' controller steers by.
//! 3. **collision**: between two consecutive rests the move's check,
//!    `ftwire_control::MoveCheck::of_move` (the measured change of the raw `ã` against the
//!    model's Newton prediction for the reported motion `b_i⁻¹ b_{i+1}`, from the first-order
//!    guess `J(L)⁻¹ log(b_i⁻¹ b_{i+1})` at `ã_i`). The first `calibration_moves` moves are
//!    taken as free of contact and calibrate the detector as the goal experiment does
//!    ([`CollisionDetector::from_free_moves`]: floor from the rests' noise, slope and
//!    threshold from the moves); from then on each move's cumulative residual
//!    (`CollisionDetector::residual`) above the threshold is a contact, until a later move's
//!    residual falls back below it. The detector watches the raw `ã`, never the corrected
//!    one, so that a contact is not explained away as drift. It gives no location: the node
//!    draws the contact at the estimated shape's tip.

use std::collections::VecDeque;

use ftwire_control::{
    BiasObserver, BiasObserverParams, CollisionDetector, MoveCheck, predicted_delta_a,
};
use ftwire_core::{FtSample, Pose};
use ftwire_estimate::ft::{FtCalibration, FtPipeline, RestAverage, Tare};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_logs::RawMap;
use ftwire_rod::{se3, to_normalised};
use nalgebra::{Translation3, UnitQuaternion, Vector3, Vector6};
use serde::Serialize;

use super::{NodeError, a_of_raw};

/// Fewest tared samples a rest averages.
pub const MIN_REST_SAMPLES: usize = 10;

/// Most samples a still period keeps while it waits for its dwell (a tip pose topic that
/// stops would otherwise let them grow without end): 10 minutes at 1 kHz.
const MAX_KEPT: usize = 600_000;

/// Most samples that wait for a pose (and poses for a sample) before they are taken anyway:
/// a stream that stops does not hold the other back for more than about 4 s at 1 kHz.
const MAX_WAITING: usize = 4096;

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
    /// Samples and poses received and not yet taken: they are taken in stamp order.
    waiting_samples: VecDeque<FtSample>,
    waiting_poses: VecDeque<(f64, Pose)>,
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
            waiting_samples: VecDeque::new(),
            waiting_poses: VecDeque::new(),
        }
    }

    /// Receives a tared-stream sample (its `time` the stamp); returns the rests it lets the
    /// detector complete (the module docs: stamp order).
    pub fn sample(&mut self, sample: FtSample) -> Vec<RestWindow> {
        self.waiting_samples.push_back(sample);
        self.take_in_order()
    }

    /// Receives a tip pose stamped `time` \[s\]; returns the rests it lets the detector
    /// complete.
    pub fn pose(&mut self, time: f64, pose: &Pose) -> Vec<RestWindow> {
        self.waiting_poses.push_back((time, *pose));
        self.take_in_order()
    }

    /// Takes the waiting samples and poses in stamp order, a sample before a pose of the same
    /// stamp, as far as both streams have come (or one has waited too long).
    fn take_in_order(&mut self) -> Vec<RestWindow> {
        let mut rests = Vec::new();
        loop {
            let sample_first = match (self.waiting_samples.front(), self.waiting_poses.front()) {
                (Some(s), Some((t, _))) => s.time <= *t,
                (Some(_), None) if self.waiting_samples.len() > MAX_WAITING => true,
                (None, Some(_)) if self.waiting_poses.len() > MAX_WAITING => false,
                _ => return rests,
            };
            if sample_first {
                if let Some(sample) = self.waiting_samples.pop_front() {
                    self.take_sample(sample);
                }
            } else if let Some((time, pose)) = self.waiting_poses.pop_front() {
                rests.extend(self.take_pose(time, &pose));
            }
        }
    }

    /// Takes a tared-stream sample, in stamp order.
    fn take_sample(&mut self, sample: FtSample) {
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

    /// Takes a tip pose stamped `time` \[s\], in stamp order; returns the rest it completes,
    /// if any.
    fn take_pose(&mut self, time: f64, pose: &Pose) -> Option<RestWindow> {
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

    /// Takes a raw sample stamped `time` once the tare is known; at the end of a rest it lets
    /// the detector complete (the module docs: stamp order), measures it (with `tare` and
    /// `map`) and runs the observer and the detector on it.
    pub fn sample(
        &mut self,
        time: f64,
        raw: Vector6<f64>,
        tare: Option<Tare>,
        map: &RawMap,
    ) -> Vec<RestEvent> {
        let windows = self.rests.sample(FtSample {
            time,
            raw,
            saturated: [false; 6],
        });
        self.measure(windows, tare, map)
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
        let windows = self.rests.pose(time, pose);
        self.measure(windows, tare, map)
    }

    /// Measures the rests found and runs the observer and the detector on each.
    fn measure(
        &mut self,
        windows: Vec<RestWindow>,
        tare: Option<Tare>,
        map: &RawMap,
    ) -> Vec<RestEvent> {
        let Some(tare) = tare else {
            return Vec::new();
        };
        let mut events = Vec::new();
        for window in windows {
            match measure_rest(&window, tare, map) {
                Ok(rest) => events.extend(self.rest(rest)),
                Err(e) => events.push(RestEvent::Failed(e)),
            }
        }
        events
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
                    match CollisionDetector::from_free_moves(levels, &[&self.checks]) {
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
                        Err(e) => events.push(RestEvent::NotCalibrated(format!(
                            "calibrating the collision detector: {e}"
                        ))),
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

    /// The covariance of the bias estimate at `time` \[s\] (`BiasObserver::bias_covariance`),
    /// once the observer has used a rest; `None` before, or without an observer.
    pub fn bias_covariance(&self, time: f64) -> Option<nalgebra::Matrix6<f64>> {
        self.observer
            .as_ref()
            .filter(|o| o.updates() > 0)
            .map(|o| o.bias_covariance(time))
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
mod tests;
