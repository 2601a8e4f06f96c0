//! The six-axis force/torque sensor on the base gripper.
//!
//! The sensor turns the true wrench that the wire exerts on the base gripper into a raw reading,
//! in this order:
//!
//! 1. **Mounting**: the wrench, given in the base clamp frame about the clamp point (torque
//!    first), is re-expressed in the sensor frame about the sensor origin, with the pose
//!    `sensor_from_clamp` ([`FtSensorParams::clamp_position_in_sensor`],
//!    [`FtSensorParams::clamp_rotation_in_sensor`]), and reordered force first:
//!    `s = (R f, R τ + t × R f)`.
//! 2. **Gain and cross-talk**: `g = G s` with a 6×6 matrix `G` near the identity.
//! 3. **Nonlinearity**: a small cubic term per channel, `n_i = g_i (1 + k_i (g_i / FS_i)²)`, so
//!    that channel `i` deviates by `k_i` of its full scale `FS_i` at full scale.
//! 4. **Bias**: `+ b(t)`, a first-order Gauss–Markov process per channel around the initial bias
//!    (a random walk when the time constant is infinite), advanced with the sample time.
//! 5. **Noise**: `+ σ_i ξ_i` with independent standard normal `ξ_i` per sample and channel.
//! 6. **Saturation**: each channel is clipped at `±FS_i` and flagged in
//!    [`FtSample::saturated`](ftwire_core::FtSample::saturated).
//!
//! Steps 1–3 are the deterministic part. [`FtSensor::invert_deterministic`] undoes them exactly
//! given a bias: it is the ground-truth calibration that a learnt calibration is compared with.
//! Algorithms must not use it; like a real robot, they must learn the calibration from data.

use std::ops::RangeInclusive;

use ftwire_core::{FtSample, Pose, Wrench, ensure_finite, ensure_rotation_vector};
use nalgebra::{Matrix6, Translation3, UnitQuaternion, Vector3, Vector6};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use super::SensingError;
use super::error::{all_in_range, in_range};

/// Largest magnitude allowed for a cubic nonlinearity coefficient `k_i` (a "mild"
/// nonlinearity: at most 10 % of full scale at full scale).
pub const MAX_CUBIC_NONLINEARITY: f64 = 0.1;

/// Largest hysteresis as a fraction of full scale ([`FtSensorParams::hysteresis`]).
pub const MAX_HYSTERESIS: f64 = 0.01;

/// The allowed range of [`FtSensorParams::rate`] \[Hz\]: a reading a second to 1 MHz (real F/T
/// sensors run at 100 Hz–10 kHz). Bounded so that a run's clock counts its ticks exactly: see
/// `ftwire_sim::rig::SPEED_RANGE` for the run length the rig's bounds allow.
pub const RATE_RANGE: RangeInclusive<f64> = 1.0..=1e6;

/// The allowed range of [`FtSensorParams::clock_offset`] \[s\]: within about 11 days of zero
/// either way, so that the time of a tick (`clock_offset + k / rate`) keeps the clock's
/// resolution over a run.
pub const CLOCK_OFFSET_RANGE: RangeInclusive<f64> = -1e6..=1e6;

/// The largest finite [`FtSensorParams::bias_time_constant`] \[s\] (about 30 years): a longer
/// one is a random walk over any run; `inf` says so exactly.
pub const MAX_BIAS_TIME_CONSTANT: f64 = 1e9;

/// Tolerance, in clock periods, below which a time counts as lying on a clock tick.
const TICK_TOLERANCE: f64 = 1e-9;

/// Parameters of the F/T sensor model. Every distortion can be set or switched off.
///
/// Six-channel arrays are ordered **force first**, `(f1, f2, f3, τ1, τ2, τ3)`, in the sensor
/// frame, as the raw reading is. The defaults have the *character* of a small six-axis sensor of
/// the Bota Systems SensONE class; they are plausible values, not a datasheet (see `SENSING.md`
/// for where each one comes from). [`FtSensorParams::ideal`] switches every distortion off.
///
/// The bundle is serde-(de)serialisable, so it can be read from a TOML file; missing fields take
/// their defaults.
///
/// # Example
/// ```
/// use ftwire_sim::FtSensorParams;
///
/// let config: FtSensorParams = toml::from_str("noise_std = [0.1, 0.1, 0.1, 0.004, 0.004, 0.004]")?;
/// assert_eq!(config.noise_std[0], 0.1);
/// assert_eq!(config.rate, FtSensorParams::default().rate);
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FtSensorParams {
    /// Position of the clamp point in the sensor frame \[m\]: the translation of
    /// `sensor_from_clamp` (default `[0, 0, 0.08]`, the clamp 80 mm out along the sensor's tool
    /// axis z).
    pub clamp_position_in_sensor: [f64; 3],
    /// Orientation of the clamp frame in the sensor frame, as a rotation vector \[rad\] of norm
    /// at most `ftwire_core::MAX_ROTATION_ANGLE`: the rotation of `sensor_from_clamp` (default
    /// `−(2π/3)/√3 · (1, 1, 1)`, which maps the clamp axes x, y, z — x the wire tangent — onto
    /// the sensor axes z, x, y).
    pub clamp_rotation_in_sensor: [f64; 3],
    /// Gain and cross-talk matrix `G`, row-major, force first, acting on the sensor-frame wrench:
    /// force rows and columns in \[N\], torque in \[N·m\], so force-to-torque entries are in
    /// \[m\] and torque-to-force entries in \[1/m\] (default: diagonal 0.987–1.015, cross-talk
    /// up to 1 % within the force and torque blocks, 2 mm force-to-torque coupling).
    pub gain: [[f64; 6]; 6],
    /// Cubic nonlinearity `k_i` per channel \[-\]: the relative deviation, as a fraction of full
    /// scale, at full scale; `|k_i| ≤ 0.1` (default `[0.004, −0.003, 0.005, −0.004, 0.003,
    /// 0.002]`, i.e. at most 0.5 % FS).
    pub cubic_nonlinearity: [f64; 6],
    /// Hysteresis per channel \[N, N, N, N·m, N·m, N·m\]: the half-width `h_i` of a play
    /// (backlash) operator on the channel's deterministic response `r_i`. The reading's
    /// hysteretic part `y_i` stays where it was while `|r_i − y_i| ≤ h_i` and is dragged along
    /// at `r_i ∓ h_i` beyond, so a channel reads up to `h_i` high after unloading and low after
    /// loading, by the load's history, not its value. At most [`MAX_HYSTERESIS`] of full scale
    /// (a small six-axis sensor's data sheet gives a hysteresis of 0.1–1 % FS); default `0`.
    /// [`FtSensor::hysteresis_state`] carries it over from one sensor to the next of a
    /// session.
    pub hysteresis: [f64; 6],
    /// Full scale `FS_i` per channel \[N, N, N, N·m, N·m, N·m\]: the rated range `±FS_i`, where
    /// saturation clips and the nonlinearity is scaled (default `[500, 500, 900, 20, 20, 20]`).
    pub full_scale: [f64; 6],
    /// Clip each channel at `±FS_i` and flag clipped samples (default `true`).
    pub saturation: bool,
    /// Bias at time 0 \[N, N, N, N·m, N·m, N·m\], the offset left after taring
    /// (default `[0.35, −0.22, 0.61, 0.012, −0.008, 0.005]`).
    pub initial_bias: [f64; 6],
    /// Bias drift intensity `q_i` per channel \[N/√s, N·m/√s\]: over a time `dt ≪ T` the bias
    /// moves with standard deviation `q_i √dt` (default `[0.002, 0.002, 0.002, 8e-5, 8e-5,
    /// 8e-5]`: about 0.3 noise σ per minute, and a stationary spread of about 0.7 σ with the
    /// default time constant).
    pub bias_random_walk: [f64; 6],
    /// Time constant `T` of the bias drift \[s\], `> 0` and at most [`MAX_BIAS_TIME_CONSTANT`],
    /// or infinite: the bias is a first-order Gauss–Markov process around the initial bias,
    /// with stationary standard deviation `q_i √(T/2)`; `f64::INFINITY` (TOML `inf`) gives a
    /// pure random walk (default `600`).
    pub bias_time_constant: f64,
    /// Deterministic bias drift `ḃ_i` per channel \[N/s, N·m/s\]: the bias at time `t` is the
    /// Gauss–Markov process above plus `ḃ t`, a slow creep such as a real sensor's warm-up or a
    /// temperature change that the random walk does not model (default all `0`).
    pub bias_drift_rate: [f64; 6],
    /// White-noise standard deviation `σ_i` per channel \[N, N·m\]
    /// (default `[0.05, 0.05, 0.05, 0.002, 0.002, 0.002]`).
    pub noise_std: [f64; 6],
    /// Sample rate of the sensor clock \[Hz\], in [`RATE_RANGE`] (default `1000`).
    pub rate: f64,
    /// Time of the clock tick with index 0 \[s\], in [`CLOCK_OFFSET_RANGE`]; ticks fall at
    /// `clock_offset + k / rate` (default `0`).
    pub clock_offset: f64,
    /// Probability that a read fails with [`SensingError::Dropout`], in `[0, 1)`
    /// (default `1e-4`).
    pub dropout_probability: f64,
}

impl Default for FtSensorParams {
    fn default() -> Self {
        let r = -2.0 * std::f64::consts::FRAC_PI_3 / 3f64.sqrt();
        Self {
            clamp_position_in_sensor: [0.0, 0.0, 0.08],
            clamp_rotation_in_sensor: [r, r, r],
            gain: [
                [1.012, 0.008, -0.005, 0.0, 0.0, 0.0],
                [-0.006, 0.991, 0.007, 0.0, 0.0, 0.0],
                [0.004, -0.009, 1.006, 0.0, 0.0, 0.0],
                [0.0, 0.002, 0.0, 0.987, 0.010, -0.006],
                [-0.002, 0.0, 0.0, -0.008, 1.009, 0.005],
                [0.0, 0.0, 0.0, 0.006, -0.004, 1.015],
            ],
            cubic_nonlinearity: [0.004, -0.003, 0.005, -0.004, 0.003, 0.002],
            hysteresis: [0.0; 6],
            full_scale: [500.0, 500.0, 900.0, 20.0, 20.0, 20.0],
            saturation: true,
            initial_bias: [0.35, -0.22, 0.61, 0.012, -0.008, 0.005],
            bias_random_walk: [0.002, 0.002, 0.002, 8e-5, 8e-5, 8e-5],
            bias_time_constant: 600.0,
            bias_drift_rate: [0.0; 6],
            noise_std: [0.05, 0.05, 0.05, 0.002, 0.002, 0.002],
            rate: 1000.0,
            clock_offset: 0.0,
            dropout_probability: 1e-4,
        }
    }
}

impl FtSensorParams {
    /// A sensor without distortions: identity mounting, identity gain, no nonlinearity, no bias,
    /// drift, noise, saturation or dropout. Its raw reading is the true wrench reordered force
    /// first. The clock keeps the default rate.
    ///
    /// # Example
    /// ```
    /// use ftwire_core::Wrench;
    /// use ftwire_sim::{FtSensor, FtSensorParams};
    /// use nalgebra::{Vector3, Vector6};
    ///
    /// let mut sensor = FtSensor::new(FtSensorParams::ideal(), 7)?;
    /// let w = Wrench::new(Vector3::new(0.1, 0.2, 0.3), Vector3::new(1.0, 2.0, 3.0));
    /// let reading = sensor.read(&w, 0.0)?;
    /// assert_eq!(reading.raw, Vector6::new(1.0, 2.0, 3.0, 0.1, 0.2, 0.3));
    /// # Ok::<(), ftwire_sim::SensingError>(())
    /// ```
    #[must_use]
    pub fn ideal() -> Self {
        let mut gain = [[0.0; 6]; 6];
        for (i, row) in gain.iter_mut().enumerate() {
            if let Some(diagonal) = row.get_mut(i) {
                *diagonal = 1.0;
            }
        }
        Self {
            clamp_position_in_sensor: [0.0; 3],
            clamp_rotation_in_sensor: [0.0; 3],
            gain,
            cubic_nonlinearity: [0.0; 6],
            saturation: false,
            initial_bias: [0.0; 6],
            bias_random_walk: [0.0; 6],
            bias_drift_rate: [0.0; 6],
            noise_std: [0.0; 6],
            dropout_probability: 0.0,
            ..Self::default()
        }
    }

    /// The mounting pose `sensor_from_clamp`, mapping clamp-frame coordinates to sensor-frame
    /// coordinates.
    pub fn sensor_from_clamp(&self) -> Pose {
        Pose::from_parts(
            Translation3::from(Vector3::from(self.clamp_position_in_sensor)),
            UnitQuaternion::from_scaled_axis(Vector3::from(self.clamp_rotation_in_sensor)),
        )
    }

    /// The gain matrix `G` as a nalgebra matrix (force first).
    pub fn gain_matrix(&self) -> Matrix6<f64> {
        Matrix6::from_fn(|i, j| {
            self.gain
                .get(i)
                .and_then(|row| row.get(j))
                .copied()
                .unwrap_or(0.0)
        })
    }

    fn validate(&self) -> Result<(), SensingError> {
        ensure_finite("clamp_position_in_sensor", &self.clamp_position_in_sensor)?;
        ensure_rotation_vector("clamp_rotation_in_sensor", &self.clamp_rotation_in_sensor)?;
        ensure_finite("gain", self.gain.as_flattened())?;
        all_in_range(
            "cubic_nonlinearity",
            &self.cubic_nonlinearity,
            -MAX_CUBIC_NONLINEARITY,
            MAX_CUBIC_NONLINEARITY,
        )?;
        all_in_range("full_scale", &self.full_scale, f64::MIN_POSITIVE, f64::MAX)?;
        for (i, (&h, &fs)) in self.hysteresis.iter().zip(&self.full_scale).enumerate() {
            in_range("hysteresis", i, h, 0.0, MAX_HYSTERESIS * fs)?;
        }
        ensure_finite("initial_bias", &self.initial_bias)?;
        all_in_range("bias_random_walk", &self.bias_random_walk, 0.0, f64::MAX)?;
        ensure_finite("bias_drift_rate", &self.bias_drift_rate)?;
        let t = self.bias_time_constant;
        if !(t == f64::INFINITY || (t > 0.0 && t <= MAX_BIAS_TIME_CONSTANT)) {
            return Err(SensingError::TimeConstant {
                field: "bias_time_constant",
                value: t,
                max: MAX_BIAS_TIME_CONSTANT,
            });
        }
        all_in_range("noise_std", &self.noise_std, 0.0, f64::MAX)?;
        in_range("rate", 0, self.rate, *RATE_RANGE.start(), *RATE_RANGE.end())?;
        in_range(
            "clock_offset",
            0,
            self.clock_offset,
            *CLOCK_OFFSET_RANGE.start(),
            *CLOCK_OFFSET_RANGE.end(),
        )?;
        in_range(
            "dropout_probability",
            0,
            self.dropout_probability,
            0.0,
            1.0 - f64::EPSILON,
        )?;
        Ok(())
    }
}

/// The F/T sensor on the base gripper: a validated [`FtSensorParams`] plus the state of its bias
/// and clock and its own seeded random number generator.
///
/// Same configuration, same seed and same calls give the same readings.
#[derive(Debug, Clone)]
pub struct FtSensor {
    config: FtSensorParams,
    sensor_from_clamp: Pose,
    gain: Matrix6<f64>,
    gain_inverse: Matrix6<f64>,
    bias: Vector6<f64>,
    bias_time: f64,
    last_tick: Option<i64>,
    /// The hysteretic part of the response (`None` before the first reading).
    play: Option<Vector6<f64>>,
    rng: ChaCha8Rng,
}

impl FtSensor {
    /// Builds a sensor from a configuration and a seed for its random number generator.
    ///
    /// # Errors
    /// [`SensingError::Core`] for a non-finite value, [`SensingError::OutOfRange`] naming a
    /// field outside its allowed range, [`SensingError::SingularGain`] for a gain matrix that
    /// cannot be inverted.
    ///
    /// # Example
    /// ```
    /// use ftwire_sim::{FtSensor, FtSensorParams, SensingError};
    ///
    /// let sensor = FtSensor::new(FtSensorParams::default(), 42)?;
    /// assert_eq!(sensor.period(), 1e-3);
    /// let bad = FtSensorParams { rate: 0.0, ..FtSensorParams::default() };
    /// assert!(matches!(FtSensor::new(bad, 42), Err(SensingError::OutOfRange { field: "rate", .. })));
    /// # Ok::<(), SensingError>(())
    /// ```
    pub fn new(config: FtSensorParams, seed: u64) -> Result<Self, SensingError> {
        config.validate()?;
        let gain = config.gain_matrix();
        let singular_values = gain.singular_values();
        let (min, max) = (singular_values.min(), singular_values.max());
        if min.is_nan() || min <= 1e-9 * max {
            return Err(SensingError::SingularGain {
                min_singular_value: min,
            });
        }
        let gain_inverse = gain.try_inverse().ok_or(SensingError::SingularGain {
            min_singular_value: min,
        })?;
        Ok(Self {
            sensor_from_clamp: config.sensor_from_clamp(),
            gain,
            gain_inverse,
            bias: Vector6::from(config.initial_bias),
            bias_time: 0.0,
            last_tick: None,
            play: None,
            rng: ChaCha8Rng::seed_from_u64(seed),
            config,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &FtSensorParams {
        &self.config
    }

    /// The clock period `1 / rate` \[s\].
    pub fn period(&self) -> f64 {
        1.0 / self.config.rate
    }

    /// The time of the last clock tick read \[s\], dropouts included; `None` before the first
    /// read. A rig can advance its clock to it.
    ///
    /// # Example
    /// ```
    /// use ftwire_core::Wrench;
    /// use ftwire_sim::{FtSensor, FtSensorParams};
    ///
    /// let mut sensor = FtSensor::new(FtSensorParams::ideal(), 0)?;
    /// assert_eq!(sensor.last_sample_time(), None);
    /// sensor.read(&Wrench::default(), 0.0101)?;
    /// assert!((sensor.last_sample_time().unwrap_or(0.0) - 0.011).abs() < 1e-12);
    /// # Ok::<(), ftwire_sim::SensingError>(())
    /// ```
    pub fn last_sample_time(&self) -> Option<f64> {
        self.last_tick.map(|tick| self.tick_time(tick))
    }

    /// The true bias \[N, N·m\], force first, at the last sample (or the initial bias before the
    /// first). Ground truth for tests and experiments; algorithms must not use it.
    pub fn bias(&self) -> Vector6<f64> {
        self.bias + self.drift(self.bias_time)
    }

    /// The deterministic part of the bias at `time` \[s\]: `ḃ t`
    /// ([`FtSensorParams::bias_drift_rate`]).
    fn drift(&self, time: f64) -> Vector6<f64> {
        Vector6::from(self.config.bias_drift_rate) * time
    }

    /// The time of the sample that a read at `time` would return: the first clock tick at or
    /// after `time` that is later than the last sample's tick \[s\].
    ///
    /// # Errors
    /// [`SensingError::Core`] if `time` is not finite, [`SensingError::OutOfRange`] if it lies
    /// beyond 2⁵³ clock periods from the clock offset.
    pub fn next_sample_time(&self, time: f64) -> Result<f64, SensingError> {
        Ok(self.tick_time(self.next_tick(time)?))
    }

    /// Reads one sample of the true wrench `wrench` at time `time` \[s\].
    ///
    /// `wrench` is what the wire exerts on the base gripper, in the base clamp frame about the
    /// clamp point, torque first (`a` of `DESIGN.md`); it is taken as constant until the sample
    /// (a quasi-static world). The sample is taken at the next clock tick (see
    /// [`FtSensor::next_sample_time`]); the bias drifts to that tick first.
    ///
    /// # Errors
    /// [`SensingError::Core`] if `time` or the wrench is not finite, or if the wrench is so
    /// large (beyond 1e300 or so) that the reading overflows (field `raw`),
    /// [`SensingError::OutOfRange`] for a time beyond the clock's range (2⁵³ periods), and
    /// [`SensingError::Dropout`] when the sensor misses this tick (with probability
    /// [`FtSensorParams::dropout_probability`]); the tick is consumed either way.
    ///
    /// # Example
    /// ```
    /// use ftwire_core::Wrench;
    /// use ftwire_sim::{FtSensor, FtSensorParams};
    ///
    /// let mut sensor = FtSensor::new(FtSensorParams::default(), 1)?;
    /// let reading = sensor.read(&Wrench::default(), 0.0123)?;
    /// assert!((reading.time - 0.013).abs() < 1e-12); // the next 1 kHz tick
    /// # Ok::<(), ftwire_sim::SensingError>(())
    /// ```
    pub fn read(&mut self, wrench: &Wrench, time: f64) -> Result<FtSample, SensingError> {
        ensure_finite("wrench", wrench.to_vector().as_slice())?;
        let tick = self.next_tick(time)?;
        let tick_time = self.tick_time(tick);
        self.last_tick = Some(tick);
        self.advance_bias(tick_time);

        let dropout = self.rng.random::<f64>() < self.config.dropout_probability;
        let noise = Vector6::from_fn(|i, _| {
            let xi: f64 = self.rng.sample(StandardNormal);
            self.config.noise_std.get(i).copied().unwrap_or(0.0) * xi
        });
        if dropout {
            return Err(SensingError::Dropout { time: tick_time });
        }

        let response = self.hysteretic(self.deterministic_response(wrench));
        let mut raw = response + self.bias + self.drift(tick_time) + noise;
        let mut saturated = [false; 6];
        if self.config.saturation {
            for ((value, flag), &full_scale) in raw
                .iter_mut()
                .zip(saturated.iter_mut())
                .zip(&self.config.full_scale)
            {
                if value.abs() > full_scale {
                    *flag = true;
                    *value = value.clamp(-full_scale, full_scale);
                }
            }
        }
        // Only a wrench far beyond any physical load overflows; refuse it rather than report
        // an infinite or NaN reading.
        ensure_finite("raw", raw.as_slice())?;
        Ok(FtSample {
            time: tick_time,
            raw,
            saturated,
        })
    }

    /// The response through the play operator of [`FtSensorParams::hysteresis`], which
    /// updates its state; the response unchanged without hysteresis.
    fn hysteretic(&mut self, response: Vector6<f64>) -> Vector6<f64> {
        let h = &self.config.hysteresis;
        if h.iter().all(|&h| h == 0.0) {
            return response;
        }
        let last = self.play.unwrap_or(response);
        let out = Vector6::from_fn(|i, _| last[i].clamp(response[i] - h[i], response[i] + h[i]));
        self.play = Some(out);
        out
    }

    /// The state of the play operator of [`FtSensorParams::hysteresis`]: the hysteretic part
    /// of the last reading's response (`None` before the first reading).
    pub fn hysteresis_state(&self) -> Option<Vector6<f64>> {
        self.play
    }

    /// Sets the state of the play operator: a session whose rests are simulated one rig at a
    /// time carries the sensor's load history from one to the next with it.
    ///
    /// # Errors
    /// [`SensingError::Core`] for a state not finite.
    pub fn set_hysteresis_state(
        &mut self,
        state: Option<Vector6<f64>>,
    ) -> Result<(), SensingError> {
        if let Some(s) = &state {
            ensure_finite("hysteresis_state", s.as_slice())?;
        }
        self.play = state;
        Ok(())
    }

    /// The deterministic part of the response (mounting, gain, nonlinearity), without bias,
    /// noise or saturation: a raw 6-vector, force first, in the sensor frame.
    pub fn deterministic_response(&self, wrench: &Wrench) -> Vector6<f64> {
        let in_sensor = wrench.transformed(&self.sensor_from_clamp);
        let linear = self.gain * force_first(&in_sensor);
        Vector6::from_fn(|i, _| {
            let (g, a) = (linear[i], self.cubic(i));
            if a == 0.0 { g } else { g + a * g * g * g }
        })
    }

    /// The exact inverse of [`FtSensor::deterministic_response`] after removing `bias`
    /// \[N, N·m, force first\]: the wrench on the base gripper, in the base clamp frame about
    /// the clamp point, torque first.
    ///
    /// This is the **ground-truth calibration**, for tests and for judging a learnt calibration.
    /// Algorithms must not use it; they must learn the calibration from data, as on a real
    /// robot.
    ///
    /// # Errors
    /// [`SensingError::Core`] if `raw` or `bias` is not finite or the result overflows,
    /// [`SensingError::NotInvertible`]
    /// if a channel lies beyond the monotone range of a softening nonlinearity.
    ///
    /// # Example
    /// ```
    /// use ftwire_core::Wrench;
    /// use ftwire_sim::{FtSensor, FtSensorParams};
    /// use nalgebra::Vector3;
    ///
    /// let sensor = FtSensor::new(FtSensorParams::default(), 3)?;
    /// let w = Wrench::new(Vector3::new(0.05, -0.02, 0.01), Vector3::new(-0.3, 0.1, 0.2));
    /// let raw = sensor.deterministic_response(&w) + sensor.bias();
    /// let back = sensor.invert_deterministic(&raw, &sensor.bias())?;
    /// assert!((back.to_vector() - w.to_vector()).norm() < 1e-12);
    /// # Ok::<(), ftwire_sim::SensingError>(())
    /// ```
    pub fn invert_deterministic(
        &self,
        raw: &Vector6<f64>,
        bias: &Vector6<f64>,
    ) -> Result<Wrench, SensingError> {
        ensure_finite("raw", raw.as_slice())?;
        ensure_finite("bias", bias.as_slice())?;
        let unbiased = raw - bias;
        let mut linear = Vector6::zeros();
        for (channel, (out, &y)) in linear.iter_mut().zip(unbiased.iter()).enumerate() {
            *out = invert_cubic(self.cubic(channel), y)
                .ok_or(SensingError::NotInvertible { channel, value: y })?;
        }
        let s = self.gain_inverse * linear;
        let in_sensor = Wrench::new(
            Vector3::new(s[3], s[4], s[5]),
            Vector3::new(s[0], s[1], s[2]),
        );
        let wrench = in_sensor.transformed(&self.sensor_from_clamp.inverse());
        ensure_finite("wrench", wrench.to_vector().as_slice())?;
        Ok(wrench)
    }

    /// The coefficient `a_i = k_i / FS_i²` of the cubic term of channel `i`.
    fn cubic(&self, i: usize) -> f64 {
        let k = self
            .config
            .cubic_nonlinearity
            .get(i)
            .copied()
            .unwrap_or(0.0);
        let full_scale = self.config.full_scale.get(i).copied().unwrap_or(1.0);
        k / (full_scale * full_scale)
    }

    fn next_tick(&self, time: f64) -> Result<i64, SensingError> {
        ensure_finite("time", &[time])?;
        // Tick indices stay exact integers in f64 up to 2^53.
        const MAX_TICKS: f64 = 9_007_199_254_740_992.0;
        let ticks = ((time - self.config.clock_offset) * self.config.rate - TICK_TOLERANCE).ceil();
        if ticks.abs() >= MAX_TICKS {
            return Err(SensingError::OutOfRange {
                field: "time",
                index: 0,
                value: time,
                min: self.tick_time(-(MAX_TICKS as i64) + 1),
                max: self.tick_time(MAX_TICKS as i64 - 1),
            });
        }
        let at_or_after = ticks as i64;
        Ok(match self.last_tick {
            Some(last) if at_or_after <= last => last.saturating_add(1),
            _ => at_or_after,
        })
    }

    fn tick_time(&self, tick: i64) -> f64 {
        self.config.clock_offset + tick as f64 / self.config.rate
    }

    /// Advances the bias process to `time` with its exact discretisation.
    fn advance_bias(&mut self, time: f64) {
        let dt = (time - self.bias_time).max(0.0);
        self.bias_time = self.bias_time.max(time);
        if dt == 0.0 {
            return;
        }
        let t = self.config.bias_time_constant;
        // Decay factor φ and the variance per unit q² of the increment over dt.
        let (phi, variance) = if t.is_infinite() {
            (1.0, dt)
        } else {
            ((-dt / t).exp(), -0.5 * t * (-2.0 * dt / t).exp_m1())
        };
        let std = variance.sqrt();
        for i in 0..6 {
            let xi: f64 = self.rng.sample(StandardNormal);
            let mean = self.config.initial_bias.get(i).copied().unwrap_or(0.0);
            let q = self.config.bias_random_walk.get(i).copied().unwrap_or(0.0);
            self.bias[i] = mean + (self.bias[i] - mean) * phi + q * std * xi;
        }
    }
}

/// Reorders a wrench force first: `(f1, f2, f3, τ1, τ2, τ3)`.
fn force_first(w: &Wrench) -> Vector6<f64> {
    Vector6::new(
        w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z,
    )
}

/// Solves `x + a x³ = y` by Newton's method from `x = y`; `None` if it does not converge (a
/// softening cubic, `a < 0`, beyond its monotone range).
fn invert_cubic(a: f64, y: f64) -> Option<f64> {
    if a == 0.0 {
        return Some(y);
    }
    let mut x = y;
    for _ in 0..100 {
        let slope = 1.0 + 3.0 * a * x * x;
        if slope.is_nan() || slope <= 0.0 {
            return None;
        }
        let step = (x + a * x * x * x - y) / slope;
        x -= step;
        if !x.is_finite() {
            return None;
        }
        if step.abs() <= 4.0 * f64::EPSILON * x.abs().max(f64::MIN_POSITIVE) {
            return Some(x);
        }
    }
    // Converged to round-off without meeting the step test: accept if the residual is tiny.
    ((x + a * x * x * x - y).abs() <= 1e-12 * y.abs().max(1.0)).then_some(x)
}
