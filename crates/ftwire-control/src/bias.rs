//! An observer of the F/T sensor's bias drift, from the model and the robot's poses.
//!
//! A wrist F/T sensor is tared before the wire is picked up; from then on its bias drifts (the
//! simulated default: a random walk of 2 mN/√s per force channel). Over a run of a hundred
//! moves that is a few hundredths in normalised units, an error of `ã` that the closed loop
//! cannot see and steers into the wire: it is the largest error left in goal reaching once the
//! noise of each rest is averaged out (`docs/drift.md`).
//!
//! **What tells the bias apart.** The model gives a second, bias-free view of the same wire:
//! the pose `Γ(a)` of the second clamp. At every rest the robot reports `b_i`, and
//!
//! ```text
//! Γ(ã_i − β) = b_i · Δ₀
//! ```
//!
//! holds up to noise, with `β` the bias (in `A`, normalised) and `Δ₀` the robot's own
//! calibration error of the second gripper, a constant pose that it does not know (the
//! `offset` execution model; identity for a robot that knows where it is). One rest cannot
//! tell `β` from `Δ₀` (six equations, twelve unknowns), but `J(L)` changes along a motion while
//! `Δ₀` stays put, so a run's rests separate them.
//!
//! **The filter.** An error-state Kalman filter on `x = (β, Δ₀)`: `β` a random walk with the
//! sensor's drift intensity, `Δ₀` constant with the robot's calibration spread as its prior.
//! At a rest, `z = S log((b_i Δ̂₀)⁻¹ Γ(ã_i − β̂))` (rotation first, translation divided by `L`:
//! `S`) is to first order
//!
//! ```text
//! z = J_n e_β + e_Δ + J_n w + r
//! ```
//!
//! with `J_n = S J(L) N⁻¹` (`N` the normalisation of `A`), the rest's own noise `w` (from the
//! pipeline's standard errors), and `r` the robot's repeatability plus a floor for the model's
//! error. An innovation beyond [`BiasObserverParams::gate`] (squared Mahalanobis) is not
//! used: a contact, or a model far off, must not be explained away as drift. The collision
//! detector watches the raw `ã`, not the corrected one.
//!
//! **Fusing each rest** ([`BiasObserverParams::fuse_rest`]). The same equation says more
//! than `β`: the rest's own noise `w` (its standard errors `W`) enters `z` through `J_n`, and a
//! robot that knows its gripper's pose to its repeatability sees it. Adding `w` to the state
//! for this rest only (prior `N(0, W)`, dropped afterwards) changes nothing in `β̂`, `Δ̂₀` and
//! their covariance, and gives
//!
//! ```text
//! ŵ = W J_nᵀ (H P Hᵀ + J_n W J_nᵀ + F)⁻¹ z
//! ```
//!
//! (`F` the floor of `r`). The returned configuration is then `ã − β̂ − ŵ`: where the pose is
//! far more precise than the rest (a light wire, whose wrench is a few mN), it is close to
//! `Γ⁻¹(b_i Δ̂₀)` on the branch of `ã`; where the rest is far more precise, `ŵ` vanishes. The
//! iterations relinearise at `ã − β̂ − ŵ`, and a fused rest is gated there, at its last
//! linearisation (the first, at `ã`, can be far from where a noisy rest of a light wire ends).
//! Under a calibration error that the robot does not know (`Δ₀` still uncertain), `ŵ` is
//! shrunk by it through `H P Hᵀ`.
//!
//! **Another branch.** Where a rest's noise is as large as the wire's wrench (the 920 mm
//! cable: a force scale `c2/L²` of 5 mN against 5 mN of noise a channel), `ã − β̂` can lie
//! where `Γ` folds, and the iterations from it end beyond the gate though the wire never left
//! its branch. Such a rest is tried once more from the branch of the last fused estimate
//! `â`: started at `Γ⁻¹(b_i Δ̂₀)` by Newton from `â` (the wire moves one step between rests),
//! iterated and gated exactly as before ([`BiasObserver::recovered`] counts these). A rest
//! beyond the gate from both (a contact, or no branch near either) is returned as `ã − β̂`,
//! unfused, and counted in [`BiasObserver::rejected`]. The cable's paths need it
//! (`docs/cable.md`).
//!
//! The corrected configuration is `ã − β̂` (`− ŵ` when fusing). It is only as good as the
//! model: the observer trusts `Γ` to the [`BiasObserverParams::model_std`] floor, so on a
//! real rig with a worse model that floor must be raised, or the observer left out.

use ftwire_core::Pose;
use ftwire_estimate::WireModel;
use ftwire_rig::DataSheet;
use ftwire_rod::{from_normalised, se3, to_normalised};
use nalgebra::{Matrix6, SMatrix, SVector, Vector3, Vector6};
use serde::Serialize;

use crate::ControlError;
use crate::collision::{configuration_at, normalised_jacobian};
use crate::noise::{NoiseModel, NoiseParams};

type Matrix12 = SMatrix<f64, 12, 12>;
type Matrix6x12 = SMatrix<f64, 6, 12>;
type Matrix12x6 = SMatrix<f64, 12, 6>;

/// Gauss–Newton iterations of one update.
const UPDATE_ITERATIONS: usize = 3;

/// Gauss–Newton iterations of one update that also fuses the rest
/// ([`BiasObserverParams::fuse_rest`]): the rest's noise can be tenths of a normalised unit,
/// where `Γ` is not linear. They stop early once converged ([`CONVERGED`]).
const FUSED_ITERATIONS: usize = 6;

/// A fused update has converged when an iteration moves `β̂` and `ŵ` by less than this
/// (normalised; a hundredth of the model floor's default).
const CONVERGED: f64 = 2e-6;

/// One rest's iterated update, before it is committed.
struct Iterated {
    bias: Vector6<f64>,
    offset: Pose,
    rest_noise: Vector6<f64>,
    gain: Matrix12x6,
    rest: Linearised,
}

/// One rest, linearised at an estimate.
struct Linearised {
    z: Vector6<f64>,
    h: Matrix6x12,
    r: Matrix6<f64>,
}

/// Settings of the [`BiasObserver`] (public fields + `Default`, the simulated default sensor
/// and the paper's execution spread).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BiasObserverParams {
    /// Drift intensity of each force channel \[N/√s\] (default `0.002`).
    pub force_drift: f64,
    /// Drift intensity of each torque channel \[N·m/√s\] (default `2e-4`: the sensor's own
    /// `8e-5`, plus its force drift acting 8 cm from the clamp).
    pub torque_drift: f64,
    /// Standard deviation of each force channel's bias just after the tare \[N\] (default
    /// `0.005`: a 0.5 s tare of a 0.05 N-noise sensor, with margin).
    pub initial_force_std: f64,
    /// As [`BiasObserverParams::initial_force_std`], torque \[N·m\] (default `2e-4`).
    pub initial_torque_std: f64,
    /// Prior spread of the robot's calibration error `Δ₀` per axis, position \[m\] (default
    /// `0.01`).
    pub offset_position_std: f64,
    /// As [`BiasObserverParams::offset_position_std`], rotation \[rad\] (default 3°).
    pub offset_rotation_std: f64,
    /// The robot's repeatability per move, position \[m\] (default `1e-4`).
    pub repeat_position_std: f64,
    /// As [`BiasObserverParams::repeat_position_std`], rotation \[rad\] (default 0.05°).
    pub repeat_rotation_std: f64,
    /// How far the model's `Γ` is trusted, per component of the scaled twist (rad, and m per
    /// metre of wire) (default `2e-4`).
    pub model_std: f64,
    /// Largest squared Mahalanobis distance of an innovation that is used (default `36`; the
    /// χ² of six degrees of freedom exceeds it with probability 3e-6).
    pub gate: f64,
    /// Also estimate each rest's own noise `w` from the pose, and take it out of the returned
    /// configuration (default `false`: only the drift `β̂` is taken out). See the module docs,
    /// "Fusing each rest". Worth it where the robot knows its gripper's pose better than the
    /// sensor knows the wire's wrench: a light wire, or short rests.
    pub fuse_rest: bool,
}

impl Default for BiasObserverParams {
    fn default() -> Self {
        Self {
            force_drift: 0.002,
            torque_drift: 2e-4,
            initial_force_std: 0.005,
            initial_torque_std: 2e-4,
            offset_position_std: 0.01,
            offset_rotation_std: 3f64.to_radians(),
            repeat_position_std: 1e-4,
            repeat_rotation_std: 0.05f64.to_radians(),
            model_std: 2e-4,
            gate: 36.0,
            fuse_rest: false,
        }
    }
}

impl BiasObserverParams {
    /// The settings for a sensor of data sheet `sheet`, tared over `tare_samples` readings, on
    /// a robot of execution error `noise` with the standard deviations `execution`; `None`
    /// under [`NoiseModel::Absolute`] (the reported pose is off by a new error at every rest,
    /// which the observer would read as drift).
    /// - The drift intensities are the data sheet's largest per kind; a force drift also
    ///   drifts the torque at the clamp, `clamp_position_in_sensor` away:
    ///   `q_τ = hypot(q_τ,sensor, |r| q_f)`.
    /// - The bias just after the tare: `2 σ / √n` per kind (the tare's noise with a margin of
    ///   two).
    /// - The calibration error `Δ₀`: the robot's repeatability where it goes where it is told
    ///   or reports where it went (`none`, `increment`), its calibration spread under
    ///   `offset`; each rest is fused with the pose ([`BiasObserverParams::fuse_rest`]) where
    ///   the robot knows it to its repeatability ([`fuses_rest`]).
    pub fn for_sensor(
        sheet: &DataSheet,
        tare_samples: usize,
        noise: NoiseModel,
        execution: &NoiseParams,
    ) -> Option<Self> {
        let (offset_position_std, offset_rotation_std) = match noise {
            NoiseModel::None | NoiseModel::Increment => (
                execution.repeat_position_std,
                execution.repeat_orientation_std,
            ),
            NoiseModel::Offset => (execution.position_std, execution.orientation_std),
            NoiseModel::Absolute => return None,
        };
        let max = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        let force_drift = max(&sheet.bias_random_walk[..3]);
        let lever = Vector3::from(sheet.clamp_position_in_sensor).norm();
        let torque_drift = max(&sheet.bias_random_walk[3..]).hypot(lever * force_drift);
        #[allow(clippy::cast_precision_loss)] // a tare far below 2⁵² samples
        let tare = 2.0 / (tare_samples.max(1) as f64).sqrt();
        Some(Self {
            force_drift,
            torque_drift,
            initial_force_std: tare * max(&sheet.noise_std[..3]),
            initial_torque_std: tare * max(&sheet.noise_std[3..]),
            offset_position_std,
            offset_rotation_std,
            repeat_position_std: execution.repeat_position_std,
            repeat_rotation_std: execution.repeat_orientation_std,
            fuse_rest: fuses_rest(noise),
            ..Self::default()
        })
    }
}

/// Whether the bias observer fuses each rest with the reported pose under `noise`
/// ([`BiasObserverParams::fuse_rest`]): where the robot knows where its gripper is to its
/// repeatability (no noise; `increment`, whose error the encoders see). Under `offset` the
/// pose is off by the unknown calibration error, which the observer estimates slowly.
pub fn fuses_rest(noise: NoiseModel) -> bool {
    matches!(noise, NoiseModel::None | NoiseModel::Increment)
}

impl BiasObserverParams {
    fn validate(&self) -> Result<(), ControlError> {
        for (name, value) in [
            ("force_drift", self.force_drift),
            ("torque_drift", self.torque_drift),
            ("initial_force_std", self.initial_force_std),
            ("initial_torque_std", self.initial_torque_std),
            ("offset_position_std", self.offset_position_std),
            ("offset_rotation_std", self.offset_rotation_std),
            ("repeat_position_std", self.repeat_position_std),
            ("repeat_rotation_std", self.repeat_rotation_std),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(ControlError::BadSetting {
                    name,
                    value,
                    allowed: "a finite σ ≥ 0",
                });
            }
        }
        if !(self.model_std.is_finite() && self.model_std > 0.0) {
            return Err(ControlError::BadSetting {
                name: "model_std",
                value: self.model_std,
                allowed: "a finite σ > 0 (the model is never exact)",
            });
        }
        if !(self.gate.is_finite() && self.gate > 0.0) {
            return Err(ControlError::BadSetting {
                name: "gate",
                value: self.gate,
                allowed: "a finite squared distance > 0",
            });
        }
        Ok(())
    }
}

/// The bias observer (see the module docs). One observer follows one tare: keep it across the
/// runs of a tracked path, and build a new one after each tare.
///
/// # Example
/// ```
/// use ftwire_control::{BiasObserver, BiasObserverParams};
/// use ftwire_core::WireParams;
/// use ftwire_estimate::{KirchhoffModel, WireModel};
/// use nalgebra::Vector6;
///
/// let model = KirchhoffModel::new(WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015)?);
/// let mut observer = BiasObserver::new(model, BiasObserverParams::default())?;
/// let a = Vector6::new(0.0, 0.2, 0.1, -0.5, 0.3, 0.0);
/// let tip = model.tip(&a)?;
/// // A reading 20 mN off in x, where the robot holds the wire at Γ(a).
/// let biased = a + Vector6::new(0.0, 0.0, 0.0, 0.02, 0.0, 0.0);
/// let corrected = observer.update(&biased, &Vector6::repeat(1e-3), &tip, 0.0);
/// assert!((corrected - a).norm() < (biased - a).norm());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct BiasObserver<M> {
    model: M,
    settings: BiasObserverParams,
    /// `β̂`, normalised.
    bias: Vector6<f64>,
    /// `Δ̂₀`.
    offset: Pose,
    covariance: Matrix12,
    /// `ŵ` of the last rest used, normalised (zero unless `fuse_rest`).
    rest_noise: Vector6<f64>,
    /// The last fused estimate `ã − β̂ − ŵ` (SI units), whose branch a rest beyond the gate is
    /// tried again on.
    last_fused: Option<Vector6<f64>>,
    last_time: Option<f64>,
    updates: usize,
    rejected: usize,
    recovered: usize,
}

impl<M: WireModel> BiasObserver<M> {
    /// An observer for `model` just after a tare.
    ///
    /// # Errors
    /// [`ControlError::BadSetting`] for a setting outside its range.
    pub fn new(model: M, settings: BiasObserverParams) -> Result<Self, ControlError> {
        settings.validate()?;
        let wire = model.wire();
        let (ts, fs, l) = (wire.torque_scale(), wire.force_scale(), wire.length());
        let mut diagonal = [0.0; 12];
        for i in 0..3 {
            diagonal[i] = (settings.initial_torque_std / ts).powi(2);
            diagonal[i + 3] = (settings.initial_force_std / fs).powi(2);
            diagonal[i + 6] = settings.offset_rotation_std.powi(2);
            diagonal[i + 9] = (settings.offset_position_std / l).powi(2);
        }
        Ok(Self {
            model,
            settings,
            bias: Vector6::zeros(),
            offset: Pose::identity(),
            covariance: Matrix12::from_diagonal(&diagonal.into()),
            rest_noise: Vector6::zeros(),
            last_fused: None,
            last_time: None,
            updates: 0,
            rejected: 0,
            recovered: 0,
        })
    }

    /// The estimated bias `β̂` in `A` (torque first, base clamp frame, SI units).
    pub fn bias(&self) -> Vector6<f64> {
        from_normalised(self.model.wire(), &self.bias)
    }

    /// The estimated calibration error `Δ̂₀` of the second gripper (gripper frame).
    pub fn offset(&self) -> &Pose {
        &self.offset
    }

    /// Rests used so far.
    pub fn updates(&self) -> usize {
        self.updates
    }

    /// Rests whose innovation was beyond the gate, and not used.
    pub fn rejected(&self) -> usize {
        self.rejected
    }

    /// Fused rests beyond the gate from `ã` that were used on the branch of the last fused
    /// estimate instead (see the module docs, "Another branch"); counted in
    /// [`BiasObserver::updates`], not in [`BiasObserver::rejected`].
    pub fn recovered(&self) -> usize {
        self.recovered
    }

    /// The covariance of the bias estimate `β̂` (torque first, base clamp frame) \[N²·m²,
    /// N·m·N, N²\] at `time` \[s\]: the filter's own at its last rest, with the drift
    /// `Q·(time − t_last)` of [`BiasObserverParams::torque_drift`] and
    /// [`BiasObserverParams::force_drift`] since (none before the first rest, or for a time
    /// before it). What a shape of `ã − β̂` carries of the bias.
    pub fn bias_covariance(&self, time: f64) -> Matrix6<f64> {
        let wire = self.model.wire();
        let (ts, fs) = (wire.torque_scale(), wire.force_scale());
        let scale = Vector6::new(ts, ts, ts, fs, fs, fs);
        let normalised = self.covariance.fixed_view::<6, 6>(0, 0).into_owned();
        let mut covariance =
            Matrix6::from_diagonal(&scale) * normalised * Matrix6::from_diagonal(&scale);
        let dt = self
            .last_time
            .filter(|_| time.is_finite())
            .map_or(0.0, |t| (time - t).max(0.0));
        for i in 0..3 {
            covariance[(i, i)] += self.settings.torque_drift.powi(2) * dt;
            covariance[(i + 3, i + 3)] += self.settings.force_drift.powi(2) * dt;
        }
        covariance
    }

    /// `a` corrected by the current bias estimate.
    pub fn correct(&self, a: &Vector6<f64>) -> Vector6<f64> {
        a - self.bias()
    }

    /// Takes the rest measured at `time` \[s\] (`a` with per-component standard errors
    /// `a_std`, SI units, with the second gripper reported at `tip` relative to the base clamp)
    /// and returns it corrected by the updated bias estimate.
    ///
    /// A non-finite input, a configuration the model cannot solve, or an innovation beyond
    /// the gate leaves the estimate as it was (the last two are counted in
    /// [`BiasObserver::rejected`]); time that does not advance adds no drift.
    pub fn update(
        &mut self,
        a: &Vector6<f64>,
        a_std: &Vector6<f64>,
        tip: &Pose,
        time: f64,
    ) -> Vector6<f64> {
        let finite = a.iter().chain(a_std.iter()).all(|v| v.is_finite()) && time.is_finite();
        if !finite {
            return self.correct(a);
        }
        self.predict(time);
        let noise = to_normalised(self.model.wire(), a_std);
        let mut update = self.iterate(a, &noise, tip, Vector6::zeros());
        // A fused rest beyond the gate from `ã`: once more from the branch of the last fused
        // estimate (module docs, "Another branch").
        if update.is_none()
            && self.settings.fuse_rest
            && let Some(start) = self.branch_start(a, tip)
        {
            update = self.iterate(a, &noise, tip, start);
            self.recovered += usize::from(update.is_some());
        }
        let Some(update) = update else {
            self.rejected += 1;
            return self.correct(a);
        };
        // Joseph form: stays symmetric and positive definite.
        let keep = Matrix12::identity() - update.gain * update.rest.h;
        self.covariance = keep * self.covariance * keep.transpose()
            + update.gain * update.rest.r * update.gain.transpose();
        self.bias = update.bias;
        self.offset = update.offset;
        self.updates += 1;
        if self.settings.fuse_rest && update.rest_noise.iter().all(|v| v.is_finite()) {
            self.rest_noise = update.rest_noise;
            let fused = self.correct(a) - from_normalised(self.model.wire(), &update.rest_noise);
            self.last_fused = Some(fused);
            fused
        } else {
            self.correct(a)
        }
    }

    /// The iterated update of the rest `a` (normalised standard errors `noise`) at `tip`, its
    /// own noise started at `rest_noise` (normalised; zero: linearised at `ã − β̂` first);
    /// `None` where it is not used (the model cannot be solved, or beyond the gate).
    fn iterate(
        &self,
        a: &Vector6<f64>,
        noise: &Vector6<f64>,
        tip: &Pose,
        mut rest_noise: Vector6<f64>,
    ) -> Option<Iterated> {
        // Iterated update (Gauss–Newton on the prior and this rest): the robot's offset can be
        // degrees, where one linearisation leaves an error above the model's floor.
        let (bias0, offset0) = (self.bias, self.offset);
        let (mut bias, mut offset) = (bias0, offset0);
        // This rest's own noise, the third block of the augmented state (prior `N(0, W)`):
        // iterated with the others, so that the fused rest is linearised where it ends.
        let fuse = self.settings.fuse_rest;
        let w = Matrix6::from_diagonal(&noise.component_mul(noise));
        let iterations = if fuse {
            FUSED_ITERATIONS
        } else {
            UPDATE_ITERATIONS
        };
        let mut last = None;
        let mut distance = f64::NAN;
        for iteration in 0..iterations {
            let at = a - from_normalised(self.model.wire(), &rest_noise);
            let Some(rest) = self.linearise(&at, noise, tip, &bias, &offset) else {
                // A fused rest is gated where it converged: one that cannot be solved on the
                // way is not used.
                if iteration == 0 || fuse {
                    return None;
                }
                break;
            };
            let innovation = rest.h * self.covariance * rest.h.transpose() + rest.r;
            let inverse = innovation.try_inverse()?;
            if iteration == 0 && !fuse {
                let distance = (rest.z.transpose() * inverse * rest.z)[0];
                if !(distance.is_finite() && distance <= self.settings.gate) {
                    return None;
                }
            }
            // How far this iterate already is from the prior, in the error coordinates.
            let mut moved = SVector::<f64, 12>::zeros();
            moved.fixed_rows_mut::<6>(0).copy_from(&(bias - bias0));
            moved
                .fixed_rows_mut::<6>(6)
                .copy_from(&self.scale_twist(se3::log(&(offset0.inverse() * offset))));
            let jn = rest.h.fixed_view::<6, 6>(0, 0).into_owned();
            let gain: Matrix12x6 = self.covariance * rest.h.transpose() * inverse;
            let innovation = rest.z + rest.h * moved + jn * rest_noise;
            distance = (innovation.transpose() * inverse * innovation)[0];
            let step = gain * innovation;
            let previous = (bias, rest_noise);
            bias = bias0 + step.fixed_rows::<6>(0);
            offset = offset0 * se3::exp(&self.unscale_twist(step.fixed_rows::<6>(6).into()));
            offset.rotation.renormalize();
            if fuse {
                // Its gain: `W J_nᵀ S⁻¹`.
                rest_noise = w * jn.transpose() * inverse * innovation;
            }
            last = Some((gain, rest));
            // Converged: the iterate moved less than the model's floor.
            let change = (bias - previous.0)
                .amax()
                .max((rest_noise - previous.1).amax());
            if fuse && change < CONVERGED {
                break;
            }
        }
        // A fused rest is gated at its last linearisation: the first, at `ã`, can be far from
        // where a light wire's noisy rest ends, and `Γ` is not linear over that distance.
        if fuse && !(distance.is_finite() && distance <= self.settings.gate) {
            return None;
        }
        let (gain, rest) = last?;
        Some(Iterated {
            bias,
            offset,
            rest_noise,
            gain,
            rest,
        })
    }

    /// Where a fused rest beyond the gate from `ã` starts again: the configuration on the
    /// branch of the last fused estimate whose `Γ` is `tip Δ̂₀` (Newton from that estimate;
    /// the estimate itself where Newton finds none), as the rest's own noise `ã − β̂ − start`
    /// (normalised). `None` before any rest was fused.
    fn branch_start(&self, a: &Vector6<f64>, tip: &Pose) -> Option<Vector6<f64>> {
        let last = self.last_fused?;
        let start = configuration_at(&self.model, &last, &(tip * self.offset)).unwrap_or(last);
        let rest_noise = to_normalised(self.model.wire(), &(self.correct(a) - start));
        rest_noise
            .iter()
            .all(|v| v.is_finite())
            .then_some(rest_noise)
    }

    /// The last used rest's own noise `ŵ` (SI units, as `a`), taken out of what
    /// [`BiasObserver::update`] returned when [`BiasObserverParams::fuse_rest`] is on; zero
    /// otherwise.
    pub fn rest_noise(&self) -> Vector6<f64> {
        from_normalised(self.model.wire(), &self.rest_noise)
    }

    /// A twist `(ω, v)` as `(ω, v / L)`.
    fn scale_twist(&self, xi: Vector6<f64>) -> Vector6<f64> {
        let l = self.model.wire().length();
        Vector6::new(xi[0], xi[1], xi[2], xi[3] / l, xi[4] / l, xi[5] / l)
    }

    /// A twist `(ω, v / L)` as `(ω, v)`.
    fn unscale_twist(&self, xi: Vector6<f64>) -> Vector6<f64> {
        let l = self.model.wire().length();
        Vector6::new(xi[0], xi[1], xi[2], xi[3] * l, xi[4] * l, xi[5] * l)
    }

    /// The innovation `z`, its Jacobian `H` and noise `R` of the rest `(a, tip)` at the
    /// estimate `(bias, offset)`; `None` where the model cannot be solved.
    fn linearise(
        &self,
        a: &Vector6<f64>,
        noise: &Vector6<f64>,
        tip: &Pose,
        bias: &Vector6<f64>,
        offset: &Pose,
    ) -> Option<Linearised> {
        let wire = self.model.wire();
        let corrected = a - from_normalised(wire, bias);
        let solution = self.model.jacobian(&corrected).ok()?;
        let l = wire.length();
        let z = self.scale_twist(se3::log(&((tip * offset).inverse() * solution.tip)));
        let jn = normalised_jacobian(wire, &solution.jacobian);
        let s = &self.settings;
        let mut floor = [0.0; 6];
        for i in 0..3 {
            floor[i] = s.repeat_rotation_std.powi(2) + s.model_std.powi(2);
            floor[i + 3] = (s.repeat_position_std / l).powi(2) + s.model_std.powi(2);
        }
        let r = jn * Matrix6::from_diagonal(&noise.component_mul(noise)) * jn.transpose()
            + Matrix6::from_diagonal(&floor.into());
        let mut h = Matrix6x12::zeros();
        h.fixed_view_mut::<6, 6>(0, 0).copy_from(&jn);
        h.fixed_view_mut::<6, 6>(0, 6)
            .copy_from(&Matrix6::identity());
        (z.iter().all(|v| v.is_finite()) && h.iter().all(|v| v.is_finite())).then_some(Linearised {
            z,
            h,
            r,
        })
    }

    /// Lets the bias drift until `time`.
    fn predict(&mut self, time: f64) {
        let dt = self.last_time.map_or(0.0, |t| (time - t).max(0.0));
        self.last_time = Some(self.last_time.map_or(time, |t| t.max(time)));
        if dt > 0.0 {
            let wire = self.model.wire();
            let torque = (self.settings.torque_drift / wire.torque_scale()).powi(2) * dt;
            let force = (self.settings.force_drift / wire.force_scale()).powi(2) * dt;
            for i in 0..3 {
                self.covariance[(i, i)] += torque;
                self.covariance[(i + 3, i + 3)] += force;
            }
        }
    }
}
