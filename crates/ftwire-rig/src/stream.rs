//! A stream's own state: the tare, the averaging window and the jump flag.
//!
//! Samples are pushed in the order of their stamps. With a tare, the first `tare` raw
//! readings (nothing in the gripper) are averaged into an offset that every later raw reading
//! loses; then each reading joins a window of the last `window` readings, and the window's
//! mean (raw and gravity averaged, stamped with its newest sample) goes through the
//! measurement's map to `ã`. A reading that carries an `ã` computed elsewhere skips the tare
//! and the window.

use ftwire_core::FtSample;
use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::calibration::CalibrationInput;
use ftwire_estimate::ft::{RestAverage, Tare};
use ftwire_estimate::shape::ShapeEstimator;
use nalgebra::{Vector3, Vector6};

use crate::{Measurement, RawMap, Reading, RigError, ShapeConfidence, Solved};

/// Settings of a [`Stream`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StreamParams {
    /// Raw readings averaged into the tare before any `ã`: 0 (the default: no tare; the map's
    /// input is the raw reading) or at least 2 (the tare measures its own noise).
    pub tare: usize,
    /// Readings averaged into each `ã`, at least 1 (default `1`: each reading alone).
    pub window: usize,
}

impl Default for StreamParams {
    fn default() -> Self {
        Self { tare: 0, window: 1 }
    }
}

/// The tare's progress.
#[derive(Debug, Clone)]
enum TareState {
    Collecting(Vec<FtSample>),
    Done { tare: Tare, time: f64 },
}

/// One stream of readings through a [`Measurement`]: see the module docs.
#[derive(Debug, Clone)]
pub struct Stream {
    params: StreamParams,
    tare: TareState,
    window: Vec<(Vector6<f64>, Option<Vector3<f64>>)>,
    next: usize,
    /// The running sums of the window's raw readings and gravities, and how many of its
    /// readings have gravity (summed afresh once per turn of the window: no rounding drift).
    raw_sum: Vector6<f64>,
    gravity_sum: Vector3<f64>,
    with_gravity: usize,
    flagger: ShapeEstimator<KirchhoffModel>,
}

impl Stream {
    /// A new stream of `measurement` with `params`.
    ///
    /// # Errors
    /// [`RigError::Setting`] for a window of 0, a tare of 1 reading, a tare with a mounting
    /// whose tool weighs on the sensor (the tare would hold the tool's weight at one
    /// orientation only), or a tare before a calibration whose input is raw.
    pub fn new(measurement: &Measurement, params: StreamParams) -> Result<Self, RigError> {
        if params.window == 0 {
            return Err(RigError::Setting(
                "window = 0 is not allowed: at least 1 reading per ã".into(),
            ));
        }
        check_tare(measurement.map(), params.tare)?;
        let tare = if params.tare == 0 {
            TareState::Done {
                tare: Tare::none(),
                time: f64::NAN,
            }
        } else {
            TareState::Collecting(Vec::with_capacity(params.tare))
        };
        Ok(Self {
            params,
            tare,
            window: Vec::with_capacity(params.window),
            next: 0,
            raw_sum: Vector6::zeros(),
            gravity_sum: Vector3::zeros(),
            with_gravity: 0,
            flagger: measurement.flagger(),
        })
    }

    /// The tare and its time (the mean stamp of its readings \[s\]), once taken; `None` before
    /// and without a tare.
    pub fn tare(&self) -> Option<(&Tare, f64)> {
        match &self.tare {
            TareState::Done { tare, time } if !time.is_nan() => Some((tare, *time)),
            _ => None,
        }
    }

    /// Whether the stream is past its tare (always, without one).
    pub fn is_tared(&self) -> bool {
        matches!(self.tare, TareState::Done { .. })
    }

    /// Takes the next reading; returns the reading the measurement maps (tared and averaged
    /// over the window, stamped with its newest sample) and its `ã`, once the tare is done and
    /// the window full; `None` while they fill.
    ///
    /// # Errors
    /// As [`Measurement::a_tilde`]; a failed tare (too few good readings) starts it afresh
    /// and is reported once as [`RigError::Setting`].
    pub fn push(
        &mut self,
        measurement: &Measurement,
        reading: &Reading,
    ) -> Option<Result<(Reading, Vector6<f64>), RigError>> {
        let Some(raw) = reading.raw else {
            return Some(measurement.a_tilde(reading).map(|a| (*reading, a)));
        };
        let tare = match &mut self.tare {
            TareState::Done { tare, .. } => *tare,
            TareState::Collecting(samples) => {
                samples.push(FtSample {
                    time: reading.time,
                    raw,
                    saturated: [false; 6],
                });
                if samples.len() < self.params.tare {
                    return None;
                }
                return match tare_of(samples) {
                    Ok(tare) => {
                        #[allow(clippy::cast_precision_loss)] // a tare far below 2⁵² samples
                        let time =
                            samples.iter().map(|s| s.time).sum::<f64>() / samples.len() as f64;
                        self.tare = TareState::Done { tare, time };
                        None
                    }
                    Err(e) => {
                        samples.clear();
                        Some(Err(RigError::Setting(format!(
                            "the tare failed ({e}); taring again"
                        ))))
                    }
                };
            }
        };
        let entry = (tare.apply(&raw), reading.gravity);
        self.add_to_window(entry);
        if self.window.len() < self.params.window {
            return None;
        }
        #[allow(clippy::cast_precision_loss)] // a window far below 2⁵²
        let n = self.window.len() as f64;
        let gravity = (self.with_gravity == self.window.len()).then(|| self.gravity_sum / n);
        let mean = Reading::raw(reading.time, self.raw_sum / n).with_gravity(gravity);
        Some(measurement.a_tilde(&mean).map(|a| (mean, a)))
    }

    /// Puts `entry` into the window (in place of its oldest reading once full) and keeps the
    /// running sums.
    fn add_to_window(&mut self, entry: (Vector6<f64>, Option<Vector3<f64>>)) {
        if self.window.len() < self.params.window {
            self.window.push(entry);
        } else {
            let (old_raw, old_gravity) = self.window[self.next];
            self.raw_sum -= old_raw;
            if let Some(g) = old_gravity {
                self.gravity_sum -= g;
                self.with_gravity -= 1;
            }
            self.window[self.next] = entry;
        }
        self.raw_sum += entry.0;
        if let Some(g) = entry.1 {
            self.gravity_sum += g;
            self.with_gravity += 1;
        }
        self.next = (self.next + 1) % self.params.window;
        if self.next == 0 {
            self.raw_sum = self.window.iter().map(|(r, _)| r).sum();
            self.gravity_sum = self.window.iter().filter_map(|(_, g)| *g).sum();
        }
    }

    /// The flag of a solved `ã` (or a failed solve), in the stream's order: a jump is a change
    /// from the last solved sample; a failed solve leaves that sample unchanged.
    pub fn flag(&mut self, a: &Vector6<f64>, solved: &Result<Solved, String>) -> ShapeConfidence {
        match solved {
            Ok(s) => self.flagger.flag_solved(a, s.stable).into(),
            Err(_) => ShapeConfidence::NoShape,
        }
    }

    /// Forgets the last sample: the next one is not tested for a jump.
    pub fn reset_jump(&mut self) {
        self.flagger.reset();
    }
}

/// Readings in a tare by default, where `map` allows one ([`default_tare`]).
pub const DEFAULT_TARE: usize = 500;

/// The tare a stream or a node takes by default before `map`: none before a calibration whose
/// input is raw (its map takes each reading as it comes, offset and all) or a mounting with a
/// tool (the tare would hold the tool's weight at one orientation), else [`DEFAULT_TARE`]
/// readings.
pub fn default_tare(map: &RawMap) -> usize {
    if check_tare(map, DEFAULT_TARE).is_ok() {
        DEFAULT_TARE
    } else {
        0
    }
}

/// Whether a tare of `tare` readings may come before `map`: 0 (no tare) always; otherwise at
/// least 2 readings (the tare measures its own noise), a mounting without a tool and no
/// calibration whose input is raw.
///
/// # Errors
/// [`RigError::Setting`] saying which rule `tare` breaks and what is allowed.
pub fn check_tare(map: &RawMap, tare: usize) -> Result<(), RigError> {
    if tare == 0 {
        return Ok(());
    }
    if tare == 1 {
        return Err(RigError::Setting(
            "tare = 1 is not allowed: 0 (no tare) or at least 2 readings".into(),
        ));
    }
    if map.mounting().is_some_and(|m| m.has_tool()) {
        return Err(RigError::Setting(
            "a tare with a mounting that has a tool is not allowed: the tare would hold the \
             tool's weight at one orientation; take the tool's weight out with gravity \
             (no tare), or give a mounting without a tool"
                .into(),
        ));
    }
    if map
        .calibration()
        .is_some_and(|c| c.input() == CalibrationInput::Raw)
    {
        return Err(RigError::Setting(
            "a tare with a calibration whose input is raw (calibration.json's `input`) is \
             not allowed: its map takes each reading as it comes, offset and all; use no \
             tare, or a calibration trained on tared readings (`input: \"tared\"`)"
                .into(),
        ));
    }
    Ok(())
}

/// The tare of `samples`, read with nothing in the gripper: their mean over the good ones (at
/// least half, and at least 2, must be), subtracted from every later reading.
///
/// # Errors
/// [`RigError::Estimate`] when too few readings are good.
pub fn tare_of(samples: &[FtSample]) -> Result<Tare, RigError> {
    let rest = RestAverage::new(samples.len().div_ceil(2).max(2))
        .and_then(|average| average.average(samples.iter().map(Some)))?;
    Ok(Tare::from_rest(&rest, &Vector6::zeros()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MeasurementParams, RawMap};
    use ftwire_core::WireParams;
    use ftwire_estimate::ft::MountingSpec;

    fn measurement() -> Measurement {
        let wire = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid");
        let map = RawMap::new(None, Some(MountingSpec::default())).expect("valid");
        Measurement::new(map, KirchhoffModel::new(wire), MeasurementParams::default())
            .expect("valid")
    }

    /// The tare's mean leaves every later reading, and the window's mean is what is mapped,
    /// stamped with its newest reading.
    #[test]
    fn the_stream_tares_then_averages_a_window_then_maps() {
        let m = measurement();
        let mut stream = Stream::new(&m, StreamParams { tare: 2, window: 3 }).expect("valid");
        let offset = Vector6::new(0.5, -0.2, 0.1, 0.01, 0.02, -0.01);
        let scatter = Vector6::new(1e-3, -2e-3, 1e-3, 1e-4, -1e-4, 2e-4);
        assert!(
            stream
                .push(&m, &Reading::raw(0.0, offset + scatter))
                .is_none()
        );
        assert!(!stream.is_tared());
        assert!(
            stream
                .push(&m, &Reading::raw(0.1, offset - scatter))
                .is_none()
        );
        let (tare, time) = stream.tare().expect("tared");
        assert!((time - 0.05).abs() < 1e-15);
        assert!(
            tare.apply(&offset).norm() < 1e-15,
            "{}",
            tare.apply(&offset)
        );
        let wire = |k: f64| Vector6::new(0.01 * k, 0.02, -0.03, 0.001, 0.002 * k, 0.0);
        assert!(
            stream
                .push(&m, &Reading::raw(0.2, offset + wire(1.0)))
                .is_none()
        );
        assert!(
            stream
                .push(&m, &Reading::raw(0.3, offset + wire(2.0)))
                .is_none()
        );
        let (mean, a) = stream
            .push(&m, &Reading::raw(0.4, offset + wire(3.0)))
            .expect("the window is full")
            .expect("mapped");
        assert_eq!(mean.time, 0.4);
        let expected = m.a_tilde(&Reading::raw(0.4, wire(2.0))).expect("mapped");
        assert!((a - expected).norm() < 1e-15, "{a} vs {expected}");
        // The window slides: the next mean is of readings 2, 3 and 4.
        let (_, a) = stream
            .push(&m, &Reading::raw(0.5, offset + wire(4.0)))
            .expect("full")
            .expect("mapped");
        let expected = m.a_tilde(&Reading::raw(0.5, wire(3.0))).expect("mapped");
        assert!((a - expected).norm() < 1e-15, "{a} vs {expected}");
    }

    #[test]
    fn a_jump_is_flagged_in_order_and_a_failed_solve_has_no_shape() {
        let m = measurement();
        let mut stream = Stream::new(&m, StreamParams::default()).expect("valid");
        let a = Vector6::new(0.0, 0.02, 0.01, -0.05, 0.03, 0.0);
        let solved = m.solve(&a, None);
        assert_eq!(stream.flag(&a, &solved), ShapeConfidence::Confident);
        let far = a * 10.0;
        let solved_far = m.solve(&far, None);
        let flag = stream.flag(&far, &solved_far);
        assert!(
            matches!(flag, ShapeConfidence::Jump | ShapeConfidence::NotStable),
            "{flag:?}"
        );
        let none = m.solve(&Vector6::zeros(), None);
        assert!(none.is_err(), "a = 0 is outside A");
        assert_eq!(
            stream.flag(&Vector6::zeros(), &none),
            ShapeConfidence::NoShape
        );
    }

    #[test]
    fn a_zero_window_and_a_tare_under_a_tool_are_refused() {
        let m = measurement();
        assert!(Stream::new(&m, StreamParams { tare: 0, window: 0 }).is_err());
        assert!(Stream::new(&m, StreamParams { tare: 1, window: 1 }).is_err());
        let tool = MountingSpec {
            tool_mass: 0.2,
            ..MountingSpec::default()
        };
        let wire = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid");
        let m = Measurement::new(
            RawMap::new(None, Some(tool)).expect("valid"),
            KirchhoffModel::new(wire),
            MeasurementParams::default(),
        )
        .expect("valid");
        let error = Stream::new(
            &m,
            StreamParams {
                tare: 10,
                window: 1,
            },
        )
        .expect_err("refused");
        assert!(error.to_string().contains("tool"), "{error}");
    }

    /// A node tares by default only where a tare is allowed: not before a calibration that
    /// takes raw readings (a tare would take its offset out twice), nor under a tool.
    #[test]
    fn the_default_tare_is_none_before_a_raw_calibration_and_a_given_one_is_refused() {
        use ftwire_estimate::calibration::{
            Calibration, CalibrationInput, Dataset, LabelModel, TrainParams,
        };
        let mounting = RawMap::new(None, Some(MountingSpec::default())).expect("valid");
        assert_eq!(default_tare(&mounting), DEFAULT_TARE);
        assert!(check_tare(&mounting, DEFAULT_TARE).is_ok());
        let labels: Vec<Vector6<f64>> = (0..40)
            .map(|k| {
                Vector6::from_fn(|i, _| {
                    f64::from(u8::try_from((k * 7 + i * 3) % 11).expect("small")) - 5.0
                })
            })
            .collect();
        let data = Dataset::new(labels.iter().map(|a| 2.0 * a).collect(), labels).expect("finite");
        let params = TrainParams {
            hidden: vec![],
            max_epochs: 5,
            ..TrainParams::default()
        };
        let calibration = Calibration::train(&data, &params, 1).expect("trains");
        for (input, tare) in [
            (CalibrationInput::Raw, 0),
            (CalibrationInput::Tared, DEFAULT_TARE),
        ] {
            let c = calibration
                .clone()
                .with_provenance(LabelModel::WEIGHTLESS, input)
                .expect("valid");
            let map = RawMap::new(Some(c), None).expect("valid");
            assert_eq!(default_tare(&map), tare, "{input:?}");
            let given = check_tare(&map, 500);
            assert_eq!(given.is_ok(), input == CalibrationInput::Tared, "{given:?}");
            assert!(check_tare(&map, 0).is_ok());
        }
        let tool = MountingSpec {
            tool_mass: 0.2,
            ..MountingSpec::default()
        };
        assert_eq!(
            default_tare(&RawMap::new(None, Some(tool)).expect("valid")),
            0
        );
    }
}
